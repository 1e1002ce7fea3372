//! Shading layer: tangent-space normal mapping, `material m = phong { normal_map bumps
//! normal_strength 0.8  normal_green opengl|directx }`.
//!
//! The map stores `n·½ + ½` in a data texture. Its (x, y, z) is expressed in the frame
//! (t, b, n): `n` the interpolated shading normal, `t` the interpolated per-vertex tangent
//! (`scene::tangents`, MikkTSpace convention) made orthogonal to `n`, `b = w·(n × t)` (w the
//! stored handedness, times the sign of the instance transform's determinant, since a mirrored
//! instance flips `n × t`). `normal_green directx` negates y. `strength` scales x and y before
//! normalising (0: no effect, 1: as authored).
//!
//! The mapped normal only shades. The geometric normal decides which side light comes from
//! (the integrator drops light below the geometric surface, so no light leaks through), and the
//! mapped normal is bent towards the geometric one just enough that the viewer's mirror
//! direction stays above the surface: Cycles' `ensure_valid_reflection`, after Keller et al.,
//! "The Iray Light Transport Simulation and Rendering System" (2017), appendix A.3. Without it
//! a mapped normal facing away from the viewer gives black pixels (every light direction is
//! "behind" it) and a specular lobe reflecting into the surface.

use glam::{Vec2, Vec3};

use super::surface::SurfaceHit;
use super::texture::{FilterStats, Footprint};
use crate::ir::{ColorInput, GreenConvention, NormalMap};
use crate::scene::Scene;

/// The mapped shading normal at `hit` in world space (on the same side as `hit.ns`), or `None`
/// when the mesh has no tangents (no UVs: the build warned).
pub fn mapped_normal(
    scene: &Scene,
    hit: &SurfaceHit,
    map: &NormalMap,
    footprint: Footprint,
    stats: &mut FilterStats,
) -> Option<Vec3> {
    let inst = scene.instances.get(hit.hit.instance as usize)?;
    let tangents = scene.tangents.get(inst.mesh as usize)?;
    let mesh = scene.meshes.get(inst.mesh as usize)?;
    let tri = mesh.triangles.get(hit.hit.prim as usize)?;
    let t = tri.map(|i| tangents.get(i as usize).copied());
    let [Some(t0), Some(t1), Some(t2)] = t else {
        return None;
    };
    let (u, v) = (hit.hit.u, hit.hit.v);
    let t_obj = t0 * (1.0 - u - v) + t1 * u + t2 * v;
    let linear = glam::Mat3::from(inst.world_from_object.matrix3);
    let handedness = if (t_obj.w < 0.0) != (linear.determinant() < 0.0) {
        -1.0
    } else {
        1.0
    };
    let n = hit.ns;
    let t_world = linear * t_obj.truncate();
    let tangent = (t_world - n * n.dot(t_world)).normalize_or_zero();
    if tangent == Vec3::ZERO {
        return Some(n);
    }
    let bitangent = handedness * n.cross(tangent);
    let c = scene
        .textures
        .color(ColorInput::Texture(map.texture), hit.uv, footprint, stats);
    let local = decode(c, map.green, map.strength);
    let mapped = (tangent * local.x + bitangent * local.y + n * local.z).normalize_or_zero();
    Some(if mapped.is_finite() && mapped != Vec3::ZERO {
        mapped
    } else {
        n
    })
}

/// A texel `n·½ + ½` → the unit tangent-space normal, green convention and strength applied.
/// A texel pointing into the surface (z ≤ 0, a broken map) is lifted to the tangent plane.
pub fn decode(texel: Vec3, green: GreenConvention, strength: f32) -> Vec3 {
    let mut xy = Vec2::new(2.0 * texel.x - 1.0, 2.0 * texel.y - 1.0) * strength;
    if green == GreenConvention::DirectX {
        xy.y = -xy.y;
    }
    let z = (2.0 * texel.z - 1.0).max(0.0);
    let n = Vec3::new(xy.x, xy.y, z).normalize_or_zero();
    if n == Vec3::ZERO || !n.is_finite() {
        Vec3::Z
    } else {
        n
    }
}

/// Bends `n` (unit, on the viewer's side) towards `ng` (unit, viewer's side) so that the mirror
/// direction of `wo` about it is above the geometric surface by a small margin (Cycles'
/// `ensure_valid_reflection`, Keller et al. 2017 A.3). Returns `n` unchanged when it is valid.
pub fn ensure_valid_reflection(ng: Vec3, wo: Vec3, n: Vec3) -> Vec3 {
    let r = 2.0 * n.dot(wo) * n - wo;
    let threshold = (0.9 * ng.dot(wo)).min(0.01);
    if ng.dot(r) >= threshold {
        return n;
    }
    // Work in the plane of ng and n: X the part of n along the surface.
    let x = (n - n.dot(ng) * ng).normalize_or_zero();
    if x == Vec3::ZERO {
        return ng;
    }
    let (ix, iz) = (wo.dot(x), wo.dot(ng));
    let (ix2, iz2) = (ix * ix, iz * iz);
    let a = ix2 + iz2;
    if a <= 0.0 {
        return ng;
    }
    let b = (ix2 * (a - threshold * threshold)).max(0.0).sqrt();
    let c = iz * threshold + a;
    let fac = 0.5 / a;
    let (n1_z2, n2_z2) = (fac * (b + c), fac * (c - b));
    let valid = |z2: f32| z2 > 1e-5 && z2 <= 1.0 + 1e-5;
    let to_2d = |z2: f32| Vec2::new((1.0 - z2).max(0.0).sqrt(), z2.max(0.0).sqrt());
    let reflected_z = |m: Vec2| 2.0 * (m.x * ix + m.y * iz) * m.y - iz;
    let chosen = match (valid(n1_z2), valid(n2_z2)) {
        (true, true) => {
            let (m1, m2) = (to_2d(n1_z2), to_2d(n2_z2));
            let (r1, r2) = (reflected_z(m1), reflected_z(m2));
            let (ok1, ok2) = (r1 >= 1e-5, r2 >= 1e-5);
            if ok1 && ok2 {
                if r1 < r2 {
                    m1
                } else {
                    m2
                }
            } else if r1 > r2 {
                m1
            } else {
                m2
            }
        }
        (true, false) => to_2d(n1_z2),
        (false, true) => to_2d(n2_z2),
        (false, false) => return ng,
    };
    (chosen.x * x + chosen.y * ng).normalize_or_zero()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn flat_texel_decodes_to_z_and_green_flips() {
        assert_eq!(
            decode(Vec3::new(0.5, 0.5, 1.0), GreenConvention::OpenGl, 1.0),
            Vec3::Z
        );
        let up = decode(Vec3::new(0.5, 1.0, 0.5), GreenConvention::OpenGl, 1.0);
        let down = decode(Vec3::new(0.5, 1.0, 0.5), GreenConvention::DirectX, 1.0);
        assert!((up - Vec3::Y).length() < 1e-6 && (down + Vec3::Y).length() < 1e-6);
        let none = decode(Vec3::new(1.0, 0.0, 0.7), GreenConvention::OpenGl, 0.0);
        assert_eq!(none, Vec3::Z);
        assert!(decode(Vec3::ZERO, GreenConvention::OpenGl, 1.0).is_finite());
    }

    #[test]
    fn valid_normals_are_kept_and_invalid_ones_bent_just_enough() {
        let ng = Vec3::Z;
        let wo = Vec3::new(0.6, 0.0, 0.8);
        let n = Vec3::new(-0.2, 0.0, 1.0).normalize();
        assert_eq!(ensure_valid_reflection(ng, wo, n), n);
        // Grazing view, normal tilted away from the viewer: the reflection would go below.
        for (view, tilt) in [(0.1f32, 0.8f32), (0.02, 0.3), (0.5, 1.4), (1.0, 1.5)] {
            let wo = Vec3::new(view.cos(), 0.0, view.sin());
            let n = Vec3::new(-tilt.sin(), 0.0, tilt.cos());
            let bent = ensure_valid_reflection(ng, wo, n);
            assert!(bent.is_finite() && (bent.length() - 1.0).abs() < 1e-4);
            let r = 2.0 * bent.dot(wo) * bent - wo;
            assert!(r.dot(ng) > 0.0, "view {view} tilt {tilt}: {bent}");
            assert!(
                bent.dot(wo) > 0.0,
                "the viewer sees the front of the bent normal"
            );
        }
    }
}
