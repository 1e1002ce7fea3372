//! Shading layer: what a hit is (position, normals, UV) and how rays leave it without hitting the same
//! surface again.
//!
//! The hit point is rebuilt from the world-space triangle and the barycentrics the accel found,
//! with a conservative bound on its rounding error (pbrt's method: `γ(7)·Σ|bᵢ pᵢ|`, plus the
//! error of transforming the vertices to world space). A ray leaving the surface starts at the
//! point pushed along the geometric normal by that bound (towards the side it leaves on) and
//! rounded one more ulp away. The bound scales with the magnitude of the coordinates, so a scene
//! at 1e5 gets offsets around 1e-2 and one at 1e-4 around 1e-11: no self-intersection (acne) in
//! the first, no leaking through thin contacts in the second (tests in `tests/render_robust.rs`).

use glam::{Affine3A, Vec2, Vec3, Vec3A};

use crate::bvh::Hit;
use crate::scene::{Scene, SceneInstance, Surface, TriMesh};

/// γ(n) = n·ε / (1 − n·ε) with ε = 2⁻²⁴: the classic bound on n rounded f32 operations.
pub fn gamma(n: u32) -> f32 {
    let e = f32::EPSILON * 0.5 * n as f32;
    e / (1.0 - e)
}

/// A hit on a scene surface, in world space.
#[derive(Debug, Clone, Copy)]
pub struct SurfaceHit {
    /// The hit point, rebuilt from the world-space triangle and the barycentrics.
    pub p: Vec3,
    /// Per-axis bound on the error of `p`.
    pub p_error: Vec3,
    /// Unit face normal `(p1 − p0) × (p2 − p0)` (front side by counter-clockwise winding).
    pub ng: Vec3,
    /// Unit interpolated vertex normal, or `ng` when the mesh has none (not yet flipped).
    pub ns: Vec3,
    /// Texture coordinates: interpolated, or the barycentrics (u, v) when the mesh has none.
    pub uv: Vec2,
    /// What the hit triangle is: a material to shade or an emitter.
    pub surface: Surface,
    /// The accel's record (distance, barycentrics, instance, triangle), for the texture
    /// footprint and normal mapping.
    pub hit: Hit,
    /// Shadow-terminator offsets (world space) for rays leaving on the front (`ng` side) and
    /// the back; zero without vertex normals. See [`terminator_offsets`].
    pub bulge: [Vec3; 2],
}

impl SurfaceHit {
    /// Where a ray leaving in direction `w` starts: the hit point moved onto the smooth surface
    /// the vertex normals describe (on `w`'s side), then offset by the rounding bound along
    /// `n` (the geometric normal, possibly flipped to face the viewer).
    #[inline]
    pub fn ray_origin(&self, n: Vec3, w: Vec3) -> Vec3 {
        leaving_origin(self.p, self.p_error, self.ng, self.bulge, n, w)
    }
}

/// [`SurfaceHit::ray_origin`] from the hit's parts: its point `p`, error bound `p_error`, face
/// normal `ng` (as rebuilt, not flipped) and shadow-terminator offsets `bulge`.
#[inline(always)]
pub fn leaving_origin(
    p: Vec3,
    p_error: Vec3,
    ng: Vec3,
    bulge: [Vec3; 2],
    n: Vec3,
    w: Vec3,
) -> Vec3 {
    let bulge = if w.dot(ng) >= 0.0 { bulge[0] } else { bulge[1] };
    let p = p + bulge;
    offset_origin(p, p_error + gamma(4) * p.abs(), n, w)
}

/// Hanika, "Hacking the Shadow Terminator" (Ray Tracing Gems II, 2021, ch. 4): a low-poly mesh
/// with interpolated normals is shaded as if smooth, but shadow rays leave the flat triangle,
/// so points near the terminator are shadowed by the neighbouring faces (the blocky
/// terminator). Moving the ray origin to the barycentric mean of the hit projected onto each
/// vertex's tangent plane (only where it lies below that plane) puts it on the smooth surface
/// the normals describe: `p' = p − Σ bᵢ·min(0, (p − pᵢ)·nᵢ)·nᵢ`. Flat meshes (all `nᵢ = ng`)
/// get zero. Returns the offsets for the front (normals as given) and the back (negated).
pub fn terminator_offsets(
    p: Vec3,
    b: [f32; 3],
    corners: [Vec3; 3],
    normals: [Vec3; 3],
) -> [Vec3; 2] {
    let side = |sign: f32| {
        let mut off = Vec3::ZERO;
        for i in 0..3 {
            let n = sign * normals[i];
            let d = (p - corners[i]).dot(n).min(0.0);
            off -= b[i] * d * n;
        }
        if off.is_finite() {
            off
        } else {
            Vec3::ZERO
        }
    };
    [side(1.0), side(-1.0)]
}

/// What a camera ray found, from one look-up of its instance, mesh and triangle: an emitter
/// (the light's index and the triangle's unit face normal, all a camera ray that sees a light
/// needs; the same bits as [`SurfaceHit::ng`]) or a surface to shade, rebuilt in full.
#[derive(Debug, Clone, Copy)]
pub enum SeenHit {
    /// A hit on an area light's triangle.
    Emitter {
        /// Index of the light in the scene's lights.
        light: u32,
        /// Unit face normal of the hit triangle.
        ng: Vec3,
    },
    /// A hit on a surface with a material.
    Surface(SurfaceHit),
}

/// Rebuilds the hit from the scene's own data. `None` only if the accel returned an index the
/// scene does not have (an internal bug; the ray then counts as a miss).
pub fn surface_hit(scene: &Scene, hit: &Hit) -> Option<SurfaceHit> {
    let inst = scene.instances.get(hit.instance as usize)?;
    let mesh = scene.meshes.get(inst.mesh as usize)?;
    let tri = *mesh.triangles.get(hit.prim as usize)?;
    let surface = scene.surface_of(inst, mesh, hit.prim);
    let unmoved = unmoved_normals(scene, inst);
    Some(rebuild(inst, mesh, unmoved, tri, surface, hit))
}

/// [`surface_hit`], except that a hit on an emitter reconstructs only its face normal (a tenth
/// of cornell's camera samples: the light's pixels take 16× the samples), from the same
/// look-up of instance, mesh and triangle.
pub fn seen_hit(scene: &Scene, hit: &Hit) -> Option<SeenHit> {
    let inst = scene.instances.get(hit.instance as usize)?;
    let mesh = scene.meshes.get(inst.mesh as usize)?;
    let tri = *mesh.triangles.get(hit.prim as usize)?;
    let surface = scene.surface_of(inst, mesh, hit.prim);
    let unmoved = unmoved_normals(scene, inst);
    if let Surface::Emitter(light) = surface {
        let m = inst.world_from_object;
        if let Some(&ng) = unmoved.get(hit.prim as usize) {
            return Some(SeenHit::Emitter { light, ng });
        }
        let world = tri.map(|i| {
            let q = mesh.positions[i as usize];
            // `rebuild`'s corners, the same bits.
            if m == Affine3A::IDENTITY {
                q + Vec3::ZERO
            } else {
                m.transform_point3(q)
            }
        });
        let ng = face_normal(world);
        return Some(SeenHit::Emitter { light, ng });
    }
    Some(SeenHit::Surface(rebuild(
        inst, mesh, unmoved, tri, surface, hit,
    )))
}

/// The face normals the build computed for `inst`'s mesh (`scene::face_normals`) when `inst`
/// places it unmoved; empty otherwise (the caller then computes the normal).
#[inline]
fn unmoved_normals<'a>(scene: &'a Scene, inst: &SceneInstance) -> &'a [Vec3] {
    if inst.world_from_object == Affine3A::IDENTITY {
        scene
            .face_normals
            .get(inst.mesh as usize)
            .map_or(&[], Vec::as_slice)
    } else {
        &[]
    }
}

/// The [`SurfaceHit`] of triangle `tri` (vertex indices) of `mesh` placed by `inst`;
/// `unmoved` holds the mesh's face normals if the build computed them for this placement
/// (the same bits as computing them here), else it is empty.
#[inline(always)] // reason: one body for `surface_hit` and `seen_hit`, each as fast as when it was its own
fn rebuild(
    inst: &SceneInstance,
    mesh: &TriMesh,
    unmoved: &[Vec3],
    tri: [u32; 3],
    surface: Surface,
    hit: &Hit,
) -> SurfaceHit {
    let obj = tri.map(|i| mesh.positions[i as usize]);
    let m = inst.world_from_object;
    let (world, transform_error) = if m == Affine3A::IDENTITY {
        unmoved_corners(obj)
    } else {
        let abs_m = glam::Mat3A::from_cols(
            m.matrix3.x_axis.abs(),
            m.matrix3.y_axis.abs(),
            m.matrix3.z_axis.abs(),
        );
        let error = obj
            .iter()
            .map(|&q| Vec3::from(abs_m * Vec3A::from(q).abs() + m.translation.abs()))
            .fold(Vec3::ZERO, Vec3::max);
        (obj.map(|p| m.transform_point3(p)), error)
    };
    let b = [1.0 - hit.u - hit.v, hit.u, hit.v];
    let (p, p_error) = point_and_error(world, transform_error, hit.u, hit.v);
    let ng = match unmoved.get(hit.prim as usize) {
        Some(&n) => n,
        None => face_normal(world),
    };
    let mut bulge = [Vec3::ZERO; 2];
    let ns = if mesh.normals.is_empty() {
        ng
    } else {
        let n = tri.map(|i| mesh.normals[i as usize]);
        let n_obj = b[0] * n[0] + b[1] * n[1] + b[2] * n[2];
        let n_world = (inst.normal_from_object * n_obj).normalize_or_zero();
        let corner_normals = n.map(|v| (inst.normal_from_object * v).normalize_or_zero());
        bulge = terminator_offsets(p, b, world, corner_normals);
        if n_world == Vec3::ZERO {
            ng
        } else {
            n_world
        }
    };
    let uv = if mesh.uvs.is_empty() {
        Vec2::new(hit.u, hit.v)
    } else {
        let t = tri.map(|i| mesh.uvs[i as usize]);
        b[0] * t[0] + b[1] * t[1] + b[2] * t[2]
    };
    SurfaceHit {
        p,
        p_error,
        ng,
        ns,
        uv,
        surface,
        bulge,
        hit: *hit,
    }
}

/// The world corners of a triangle of an unmoved placement (object corners `obj`) and their
/// error bound: what the general transform computes, without its products (`1·x + 0·y + 0·z +
/// 0` is `x + 0` for finite coordinates, a −0 becoming +0 either way, and `|M|·|q| + |t|` is
/// `|q|`). Unplaced meshes (all of cornell's) are the common case.
#[inline(always)]
pub fn unmoved_corners(obj: [Vec3; 3]) -> ([Vec3; 3], Vec3) {
    let world = obj.map(|q| q + Vec3::ZERO);
    (
        world,
        obj.iter().map(|q| q.abs()).fold(Vec3::ZERO, Vec3::max),
    )
}

/// The point at barycentrics (`u`, `v`) of the triangle with world corners `world`, and the
/// bound on its rounding error (`γ(7)·Σ|bᵢ pᵢ|`, plus `γ(3)` of the corners' own bound
/// `transform_error`).
#[inline(always)]
pub fn point_and_error(world: [Vec3; 3], transform_error: Vec3, u: f32, v: f32) -> (Vec3, Vec3) {
    let b = [1.0 - u - v, u, v];
    let p = b[0] * world[0] + b[1] * world[1] + b[2] * world[2];
    let abs_sum = (b[0] * world[0]).abs() + (b[1] * world[1]).abs() + (b[2] * world[2]).abs();
    (p, gamma(7) * abs_sum + gamma(3) * transform_error)
}

/// The geometric and shading normals of a hit (`ng`, `ns` as rebuilt) turned to the side of
/// the viewer looking along unit direction `dir`: `ng` faces the viewer, `ns` lies on `ng`'s
/// side; and whether `ns` was flipped.
#[inline(always)]
pub fn facing_viewer(ng: Vec3, ns: Vec3, dir: Vec3) -> (Vec3, Vec3, bool) {
    let wo = -dir;
    let ng = if ng.dot(wo) < 0.0 { -ng } else { ng };
    let flip = ns.dot(ng) < 0.0;
    (ng, if flip { -ns } else { ns }, flip)
}

/// The unit face normal `(p1 − p0) × (p2 − p0)` of a world-space triangle (zero if degenerate).
#[inline]
pub fn face_normal(world: [Vec3; 3]) -> Vec3 {
    (world[1] - world[0])
        .cross(world[2] - world[0])
        .normalize_or_zero()
}

/// A point off the surface at `p` (error bound `p_error`, unit normal `n`), on the side that
/// direction `w` points to, safe to start a ray from.
#[inline(always)] // reason: on every shadow ray's chain; as a call (the hint alone was declined) it cost 2.6% of cornell's CPU (docs/speed.md, fifth session)
pub fn offset_origin(p: Vec3, p_error: Vec3, n: Vec3, w: Vec3) -> Vec3 {
    // Twice the bound, since the accel's own intersection test rounds too; and never less than
    // a few ulps of the point, for surfaces whose error bound is zero along the normal (an
    // axis-aligned plane) but that an accel transforming rays could still see a rounding off.
    let d = (2.0 * n.abs().dot(p_error)).max(gamma(3) * p.abs().max_element());
    let offset = if w.dot(n) < 0.0 { -d * n } else { d * n };
    let po = p + offset;
    Vec3::new(
        one_ulp_towards(po.x, offset.x),
        one_ulp_towards(po.y, offset.y),
        one_ulp_towards(po.z, offset.z),
    )
}

/// `x` moved one ulp in the direction of `towards`'s sign: [`next_up`] for a positive
/// `towards`, [`next_down`] for a negative one, `x` itself for zero (the same values),
/// computed on the bits without branches the sign of a normal's component would mispredict.
#[inline]
fn one_ulp_towards(x: f32, towards: f32) -> f32 {
    let bits = x.to_bits();
    let magnitude = bits & 0x7fff_ffff;
    let x_negative = bits >> 31;
    let down = u32::from(towards < 0.0);
    // Away from zero (the magnitude grows) when x's sign is the direction's; from ±0 the
    // smallest subnormal of the direction's sign.
    let grows = x_negative == down;
    let stepped = if magnitude == 0 {
        (down << 31) | 1
    } else if grows {
        bits.wrapping_add(1)
    } else {
        bits - 1
    };
    // Unchanged: no direction, NaN, or an infinity that cannot grow.
    let keep = towards == 0.0
        || towards.is_nan()
        || magnitude > 0x7f80_0000
        || (magnitude == 0x7f80_0000 && grows);
    f32::from_bits(if keep { bits } else { stepped })
}

#[cfg(test)]
fn next_up(x: f32) -> f32 {
    if x.is_infinite() && x > 0.0 || x.is_nan() {
        return x;
    }
    let x = if x == -0.0 { 0.0 } else { x };
    let bits = x.to_bits();
    f32::from_bits(if x >= 0.0 { bits + 1 } else { bits - 1 })
}

#[cfg(test)]
fn next_down(x: f32) -> f32 {
    -next_up(-x)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn one_ulp_towards_is_next_up_and_next_down() {
        let values = [
            0.0,
            -0.0,
            1.0,
            -1.0,
            1e-40,
            -1e-40,
            f32::MIN_POSITIVE,
            f32::MAX,
            -f32::MAX,
            f32::INFINITY,
            f32::NEG_INFINITY,
            3.5e7,
            -2.25e-3,
        ];
        for x in values {
            assert_eq!(
                one_ulp_towards(x, 1e-3).to_bits(),
                next_up(x).to_bits(),
                "{x}"
            );
            assert_eq!(
                one_ulp_towards(x, -2.0).to_bits(),
                next_down(x).to_bits(),
                "{x}"
            );
            assert_eq!(one_ulp_towards(x, 0.0).to_bits(), x.to_bits(), "{x}");
        }
        assert!(one_ulp_towards(f32::NAN, 1.0).is_nan());
    }

    #[test]
    fn next_float_steps_one_ulp() {
        assert!(next_up(1.0) > 1.0 && next_up(1.0) - 1.0 == f32::EPSILON);
        assert!(next_down(1.0) < 1.0);
        assert!(next_up(0.0) > 0.0 && next_up(-0.0) > 0.0);
        assert!(next_up(-1.0) > -1.0);
    }

    #[test]
    fn terminator_offset_is_zero_when_flat_and_lifts_onto_the_smooth_surface() {
        let c = [Vec3::ZERO, Vec3::X, Vec3::Y];
        let b = [1.0 / 3.0; 3];
        let p = (c[0] + c[1] + c[2]) / 3.0;
        assert_eq!(terminator_offsets(p, b, c, [Vec3::Z; 3]), [Vec3::ZERO; 2]);
        // Normals splayed outwards, as on a coarse sphere: the point moves out, mostly along +z.
        let n = c.map(|q| (q - p + Vec3::Z).normalize());
        let [front, back] = terminator_offsets(p, b, c, n);
        assert!(
            front.z > 0.01 && front.z > 2.0 * front.truncate().length(),
            "{front}"
        );
        assert_eq!(back, Vec3::ZERO);
    }

    #[test]
    fn offset_goes_to_the_side_of_w_and_scales_with_magnitude() {
        for s in [1e-4f32, 1.0, 1e5] {
            let p = Vec3::new(s, 0.0, s);
            let err = gamma(7) * p.abs();
            let up = offset_origin(p, err, Vec3::Y, Vec3::new(0.3, 1.0, 0.0));
            let down = offset_origin(p, err, Vec3::Y, -Vec3::Y);
            assert!(up.y > 0.0 && down.y < 0.0);
            assert!(up.y < 1e-5 * s && up.y > 0.0);
        }
    }
}
