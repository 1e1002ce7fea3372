//! Shading layer: the pixel's footprint on a surface, for choosing mip levels (`filter trilinear`).
//!
//! Ray cones, GPU-style (Akenine-Möller et al., "Texture Level of Detail Strategies for
//! Real-Time Ray Tracing", Ray Tracing Gems, 2019): a camera ray is a cone whose spread angle is
//! one pixel's, `α = atan(2·tan(fov_y/2) / height_px)`; at distance `t` its width is `W = α·t`
//! (the small-angle form of `2·t·tan(α/2)`). On a triangle of world area `P` and UV area `T`
//! (both as parallelograms, `|e₁ × e₂|`), seen at cosine `|n·d|`, the pixel covers
//! `W / |n·d| · √(T/P)` UV units. A texture of `w × h` texels then uses level
//!
//! ```text
//! λ = log2(W / |n·d|) + ½·log2(w·h·T / P)
//! ```
//!
//! (the paper's `Δ₀ + log2(W) − log2|n·d|`, with `Δ₀ = ½·log2(t_a/p_a)`, `t_a = w·h·T`):
//! level 0 when one texel spans one pixel, level k when 2^k texels do (per side). This is the
//! "GPU" convention: λ = log2 of the footprint's width in texels, the same as a rasteriser's
//! `log2(max |∂(s,t)/∂(x,y)|)` for an isotropic footprint. Only camera hits look textures up
//! (the integrator does direct lighting), so the cone never has to be propagated through
//! reflections.

use glam::Vec3;

use crate::scene::Scene;
use crate::shade::surface::SurfaceHit;

/// The spread angle of one pixel of a camera with vertical field of view `fov_y_rad` rendering
/// `height_px` rows.
pub fn pixel_spread_angle(fov_y_rad: f32, height_px: u32) -> f32 {
    (2.0 * (fov_y_rad / 2.0).tan() / height_px.max(1) as f32).atan()
}

/// The width of the pixel's ray cone at `hit` in UV units (`W / |n·d| · √(T/P)`), for a camera
/// ray of unit direction `dir`. Meshes without UVs use the barycentric parameterisation
/// (`T = 1`).
pub fn uv_footprint(scene: &Scene, hit: &SurfaceHit, dir: Vec3) -> f32 {
    let spread = pixel_spread_angle(scene.camera.fov_y_rad, scene.settings.height);
    let width = spread * hit.hit.t;
    let cos = hit.ng.dot(dir).abs().max(1e-6);
    width / cos * uv_per_world(scene, hit)
}

/// `√(T/P)`: UV units per world unit on the hit triangle (0 if the accel's indices are not the
/// scene's, which cannot happen for a hit the scene rebuilt).
fn uv_per_world(scene: &Scene, hit: &SurfaceHit) -> f32 {
    let Some(inst) = scene.instances.get(hit.hit.instance as usize) else {
        return 0.0;
    };
    let Some(mesh) = scene.meshes.get(inst.mesh as usize) else {
        return 0.0;
    };
    let Some(tri) = mesh.triangles.get(hit.hit.prim as usize) else {
        return 0.0;
    };
    let p = tri.map(|i| {
        inst.world_from_object
            .transform_point3(mesh.positions[i as usize])
    });
    let world_area = (p[1] - p[0]).cross(p[2] - p[0]).length();
    let uv_area = if mesh.uvs.is_empty() {
        1.0
    } else {
        let t = tri.map(|i| mesh.uvs[i as usize]);
        (t[1] - t[0]).perp_dot(t[2] - t[0]).abs()
    };
    if world_area > 0.0 {
        (uv_area / world_area).sqrt()
    } else {
        0.0
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn spread_is_one_pixel_of_the_field_of_view() {
        let a = pixel_spread_angle(90f32.to_radians(), 2);
        assert!((a - std::f32::consts::FRAC_PI_4).abs() < 1e-6);
        let small = pixel_spread_angle(40f32.to_radians(), 1000);
        assert!((small - 2.0 * 20f32.to_radians().tan() / 1000.0).abs() < 1e-8);
    }
}
