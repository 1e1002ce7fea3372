//! Shading layer: sampling a rectangular light uniformly by solid angle (Ureña, Fajardo, King
//! 2013, "An Area-Preserving Parametrization for Spherical Rectangles").
//!
//! A quad light (`light panel = area { mesh panel … }` with `panel = quad { … }`, as cornell's)
//! is today sampled as two spherical triangles (`spherical`): a triangle pick, then Arvo's
//! construction in f64. The spherical rectangle samples the whole rectangle at once, exactly
//! uniform in solid angle (`pdf = 1 / Ω`), in f32, with one `acos` per corner at set-up and
//! one `sincos` plus square roots per sample. Ω is a difference of angles near 2π: in f32 it
//! would be off by ~1e-4 relative for a light of a few millisteradians (a bias
//! `tests/render_light_sampling.rs` sees), so the set-up is f64 and only the per-sample
//! mapping is f32. Below [`spherical::MIN_SOLID_ANGLE`](super::spherical::MIN_SOLID_ANGLE) a
//! caller samples by area (as `area` does for triangles). Not yet wired into [`AreaLight`](super::AreaLight)
//! (it needs the build to recognise a two-triangle rectangle and `sample`/`pdf` to agree on when
//! it is used); this file holds the construction and its tests.

use glam::{DVec3, Vec2, Vec3};

/// A rectangle as seen from a shading point, ready to be sampled: the local frame (x, y along
/// the edges, z towards the point's side flipped away) and the spherical rectangle's angles.
#[derive(Debug, Clone, Copy)]
pub struct SphericalRect {
    origin: Vec3,
    x: Vec3,
    y: Vec3,
    z: Vec3,
    z0: f32,
    x0: f32,
    x1: f32,
    y0: f32,
    y1: f32,
    b0: f32,
    b1: f32,
    k: f32,
    solid_angle: f32,
}

impl SphericalRect {
    /// The rectangle `corner + s·ex + t·ey` (s, t ∈ [0, 1], `ex ⊥ ey`) seen from `p`. `None`
    /// when an edge is degenerate, `p` lies in its plane, or the solid angle is not positive.
    pub fn new(p: Vec3, corner: Vec3, ex: Vec3, ey: Vec3) -> Option<SphericalRect> {
        let (exl, eyl) = (ex.length(), ey.length());
        if !(exl > 0.0 && eyl > 0.0) {
            return None;
        }
        let (x, y) = (ex / exl, ey / eyl);
        let mut z = x.cross(y);
        let d = corner - p;
        let mut z0 = d.dot(z);
        if z0 > 0.0 {
            z = -z;
            z0 = -z0;
        }
        if z0 >= 0.0 || z0.is_nan() {
            return None;
        }
        let (x0, y0) = (d.dot(x), d.dot(y));
        let (x1, y1) = (x0 + exl, y0 + eyl);
        // The set-up in f64: Ω is a small difference of angles near 2π, which f32 keeps only to
        // about 1e-4 relative for a light of a few millisteradians (a bias of that size).
        let v00 = DVec3::new(x0 as f64, y0 as f64, z0 as f64);
        let v01 = DVec3::new(x0 as f64, y1 as f64, z0 as f64);
        let v10 = DVec3::new(x1 as f64, y0 as f64, z0 as f64);
        let v11 = DVec3::new(x1 as f64, y1 as f64, z0 as f64);
        let n0 = v00.cross(v10).normalize_or_zero();
        let n1 = v10.cross(v11).normalize_or_zero();
        let n2 = v11.cross(v01).normalize_or_zero();
        let n3 = v01.cross(v00).normalize_or_zero();
        let angle = |a: DVec3, b: DVec3| (-a.dot(b)).clamp(-1.0, 1.0).acos();
        let (g0, g1, g2, g3) = (angle(n0, n1), angle(n1, n2), angle(n2, n3), angle(n3, n0));
        let k = 2.0 * std::f64::consts::PI - g2 - g3;
        let solid_angle = (g0 + g1 - k) as f32;
        if solid_angle <= 0.0 || solid_angle.is_nan() {
            return None;
        }
        Some(SphericalRect {
            origin: p,
            x,
            y,
            z,
            z0,
            x0,
            x1,
            y0,
            y1,
            b0: n0.z as f32,
            b1: n2.z as f32,
            k: k as f32,
            solid_angle,
        })
    }

    /// The solid angle Ω (sr) the rectangle subtends: the sampling density is `1 / Ω`.
    pub fn solid_angle(&self) -> f32 {
        self.solid_angle
    }

    /// The point of the rectangle for `u` ∈ [0, 1)²; its direction from the shading point is
    /// uniform over the spherical rectangle.
    pub fn sample(&self, u: Vec2) -> Vec3 {
        // The column: the sub-rectangle [x0, xu] subtends u.x · Ω.
        let au = u.x * self.solid_angle + self.k;
        let (sin_au, cos_au) = au.sin_cos();
        let fu = (cos_au * self.b0 - self.b1) / sin_au;
        let cu = ((fu * fu + self.b0 * self.b0).sqrt().recip())
            .copysign(fu)
            .clamp(-1.0, 1.0);
        let xu = -(cu * self.z0) / (1.0 - cu * cu).max(0.0).sqrt();
        let xu = if xu.is_nan() { self.x0 } else { xu }.clamp(self.x0, self.x1);
        // The row: uniform in the sine of the elevation along that column.
        let d = (xu * xu + self.z0 * self.z0).sqrt();
        let h0 = self.y0 / (d * d + self.y0 * self.y0).sqrt();
        let h1 = self.y1 / (d * d + self.y1 * self.y1).sqrt();
        let hv = h0 + u.y * (h1 - h0);
        let hv2 = hv * hv;
        let yv = if hv2 < 1.0 - 1e-6 {
            (hv * d / (1.0 - hv2).sqrt()).clamp(self.y0, self.y1)
        } else {
            self.y1
        };
        self.origin + xu * self.x + yv * self.y + self.z0 * self.z
    }
}

#[cfg(test)]
mod tests {
    use super::super::spherical;
    use super::*;

    /// Solid angle of the sub-rectangle `[s0, s1] × [t0, t1]` from `p`, as two triangles.
    fn rect_omega(p: Vec3, c: Vec3, ex: Vec3, ey: Vec3, s: (f32, f32), t: (f32, f32)) -> f32 {
        let q = |a: f32, b: f32| c + a * ex + b * ey;
        let (a, b, cc, d) = (q(s.0, t.0), q(s.1, t.0), q(s.1, t.1), q(s.0, t.1));
        spherical::solid_angle(p, &[a, b, cc]) + spherical::solid_angle(p, &[a, cc, d])
    }

    fn cases() -> Vec<(Vec3, Vec3, Vec3, Vec3)> {
        let (c, ex, ey) = (
            Vec3::new(-0.3, 1.0, -0.15),
            Vec3::new(0.6, 0.0, 0.0),
            Vec3::new(0.0, 0.0, 0.3),
        );
        vec![
            (Vec3::ZERO, c, ex, ey),
            (Vec3::new(0.7, 0.2, -0.4), c, ex, ey),
            // Close: the light fills most of the hemisphere.
            (Vec3::new(0.05, 0.99, 0.02), c, ex, ey),
            // Grazing: 2 away, 0.05 below the light's plane.
            (Vec3::new(2.0, 0.95, 0.0), c, ex, ey),
            // Tilted, seen from above (z flips).
            (
                Vec3::new(0.2, 3.0, 0.1),
                Vec3::new(0.0, 1.0, 0.0),
                Vec3::new(0.5, 0.2, 0.0),
                Vec3::new(-0.08, 0.2, 0.4),
            ),
        ]
    }

    #[test]
    fn solid_angle_is_that_of_its_two_triangles() {
        for (p, c, ex, ey) in cases() {
            let r = SphericalRect::new(p, c, ex, ey).expect("not degenerate");
            let expected = rect_omega(p, c, ex, ey, (0.0, 1.0), (0.0, 1.0));
            let rel = (r.solid_angle() / expected - 1.0).abs();
            assert!(rel < 1e-3, "from {p}: {} vs {expected}", r.solid_angle());
        }
        // Far and grazing (Ω ≈ 3e-5 sr, under `spherical::MIN_SOLID_ANGLE`, where a caller
        // samples by area as `area` does for triangles): still close.
        let (p, c, ex, ey) = (
            Vec3::new(5.0, 0.98, 0.0),
            cases()[0].1,
            cases()[0].2,
            cases()[0].3,
        );
        let tiny = rect_omega(p, c, ex, ey, (0.0, 1.0), (0.0, 1.0));
        assert!(tiny < spherical::MIN_SOLID_ANGLE);
        let r = SphericalRect::new(p, c, ex, ey).expect("not degenerate");
        assert!((r.solid_angle() / tiny - 1.0).abs() < 0.02);
        let flat = SphericalRect::new(
            Vec3::new(0.0, 1.0, 0.0),
            Vec3::new(-0.3, 1.0, -0.15),
            Vec3::X,
            Vec3::Z,
        );
        assert!(flat.is_none());
    }

    /// Samples on a 64×64 grid of `u` land on the rectangle, and the share falling in each of
    /// 4×4 sub-rectangles is that sub-rectangle's share of the solid angle (uniform density
    /// `1 / Ω`, so it integrates to 1): a quadrature of 4096 points per case, each cell's
    /// share within 0.004 (about a quarter of a row of the grid, 64/4096).
    #[test]
    fn samples_are_uniform_in_solid_angle() {
        let n = 64;
        for (p, c, ex, ey) in cases() {
            let r = SphericalRect::new(p, c, ex, ey).expect("not degenerate");
            let mut cells = [0u32; 16];
            for i in 0..n {
                for j in 0..n {
                    let u = Vec2::new((i as f32 + 0.5) / n as f32, (j as f32 + 0.5) / n as f32);
                    let q = r.sample(u) - c;
                    let (s, t) = (
                        q.dot(ex) / ex.length_squared(),
                        q.dot(ey) / ey.length_squared(),
                    );
                    assert!(
                        (-1e-3..=1.001).contains(&s) && (-1e-3..=1.001).contains(&t),
                        "{s} {t}"
                    );
                    let plane = (q - s * ex - t * ey).length();
                    assert!(
                        plane < 1e-3 * (ex.length() + ey.length()),
                        "off the plane: {plane}"
                    );
                    let (a, b) = (((s * 4.0) as usize).min(3), ((t * 4.0) as usize).min(3));
                    cells[b * 4 + a] += 1;
                }
            }
            for a in 0..4 {
                for b in 0..4 {
                    let (s0, t0) = (a as f32 / 4.0, b as f32 / 4.0);
                    let share = rect_omega(p, c, ex, ey, (s0, s0 + 0.25), (t0, t0 + 0.25))
                        / r.solid_angle();
                    let got = cells[b * 4 + a] as f32 / (n * n) as f32;
                    assert!(
                        (got - share).abs() < 4e-3,
                        "from {p}, cell ({a},{b}): {got} vs {share}"
                    );
                }
            }
        }
    }
}
