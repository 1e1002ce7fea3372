//! Shading layer: the pixel's footprint on a surface, an ellipse in UV space, for choosing mip
//! levels and anisotropic taps (`filter trilinear | anisotropic`).
//!
//! Ray cones, GPU-style (Akenine-Möller et al., "Texture Level of Detail Strategies for
//! Real-Time Ray Tracing", Ray Tracing Gems, 2019): a camera ray is a cone whose spread angle is
//! one pixel's, `α = atan(2·tan(fov_y/2) / height_px)`; at distance `t` its width is `W = α·t`
//! (the small-angle form of `2·t·tan(α/2)`). Where it meets a surface at cosine `|n·d|` the
//! cone's cross-section becomes an ellipse on the tangent plane: `W / |n·d|` along the ray's
//! direction projected onto the plane (the major axis), `W` across it (the minor axis). Both
//! axes are mapped to UV space through the triangle's UV gradients (`∇u`, `∇v`, exact for the
//! affine map a triangle's UVs define), giving two conjugate axes of the ellipse in UV units
//! ([`Footprint`]). A texture of `w × h` texels then sees them as `(w·Δu, h·Δv)` texels.
//!
//! Trilinear filtering uses level `λ = log2(longest axis in texels)` (the GPU convention:
//! level 0 when one texel spans one pixel); anisotropic filtering (see `anisotropic`) uses the
//! ellipse itself. Meshes without UVs use the barycentric parameterisation.
//!
//! **The footprint shrinks with the sample count** (pbrt-v4 scales its ray differentials by
//! `max(1/8, 1/√spp)` for the same reason): `W` is multiplied by [`footprint_scale`] of the
//! samples the pixel ends with (or, sampling adaptively, of the samples taken so far by the end
//! of the current batch), so prefiltering only removes what the pixel's samples cannot resolve
//! and the filtered image converges to the point-sampled one. Only camera hits look textures
//! up (the integrator does direct lighting), so the cone never has to be propagated through
//! reflections.

use glam::{Vec2, Vec3};

use crate::scene::Scene;
use crate::shade::surface::SurfaceHit;

/// The pixel's footprint in UV space: two conjugate axes (full widths) of an ellipse centred on
/// the lookup's UV. `Footprint::default()` is a point (no prefiltering).
#[derive(Debug, Clone, Copy, Default, PartialEq)]
pub struct Footprint {
    /// The axis along the ray's direction projected onto the surface (the long one at grazing
    /// angles), UV units.
    pub major: Vec2,
    /// The axis across it, UV units.
    pub minor: Vec2,
}

impl Footprint {
    /// A circle of diameter `width` UV units.
    pub fn isotropic(width: f32) -> Footprint {
        Footprint {
            major: Vec2::new(width, 0.0),
            minor: Vec2::new(0.0, width),
        }
    }

    /// The longer axis's length in UV units: trilinear filtering's isotropic width.
    pub fn width(&self) -> f32 {
        self.major.length().max(self.minor.length())
    }

    /// Both axes in texels of a `size` (width, height) image.
    pub fn in_texels(&self, size: Vec2) -> (Vec2, Vec2) {
        (self.major * size, self.minor * size)
    }
}

/// The spread angle of one pixel of a camera with vertical field of view `fov_y_rad` rendering
/// `height_px` rows.
pub fn pixel_spread_angle(fov_y_rad: f32, height_px: u32) -> f32 {
    (2.0 * (fov_y_rad / 2.0).tan() / height_px.max(1) as f32).atan()
}

/// How much of the pixel's cone the texture filter covers when the pixel ends with `spp`
/// samples: `max(1/8, 1/√spp)` (pbrt-v4). More samples resolve more of the pixel themselves;
/// the floor keeps minification aliasing away where even many samples would alias.
pub fn footprint_scale(spp: u32) -> f32 {
    (1.0 / (spp.max(1) as f32).sqrt()).max(0.125)
}

/// The footprint at `hit` of the pixel's ray cone, scaled by `scale` (see [`footprint_scale`]),
/// for a camera ray of unit direction `dir`. Degenerate triangles give a point.
pub fn uv_footprint(scene: &Scene, hit: &SurfaceHit, dir: Vec3, scale: f32) -> Footprint {
    let spread = pixel_spread_angle(scene.camera.fov_y_rad, scene.settings.height);
    let width = spread * hit.hit.t * scale;
    let Some((n, grad_u, grad_v)) = uv_gradients(scene, hit) else {
        return Footprint::default();
    };
    let cos = n.dot(dir).abs().max(1e-6);
    let along = dir - n * n.dot(dir);
    // At normal incidence the ellipse is a circle: any in-plane direction will do.
    let along = along
        .try_normalize()
        .unwrap_or_else(|| n.any_orthonormal_vector());
    let across = n.cross(along);
    let to_uv = |w: Vec3| Vec2::new(w.dot(grad_u), w.dot(grad_v));
    let footprint = Footprint {
        major: to_uv(along * (width / cos)),
        minor: to_uv(across * width),
    };
    if footprint.major.is_finite() && footprint.minor.is_finite() {
        footprint
    } else {
        Footprint::default()
    }
}

/// The hit triangle's unit world normal and the world-space gradients of its u and v (of its
/// barycentric coordinates `(b₁, b₂)` when the mesh has no UVs); `None` for a degenerate
/// triangle or indices that are not the scene's (which cannot happen for a hit it rebuilt).
fn uv_gradients(scene: &Scene, hit: &SurfaceHit) -> Option<(Vec3, Vec3, Vec3)> {
    let inst = scene.instances.get(hit.hit.instance as usize)?;
    let mesh = scene.meshes.get(inst.mesh as usize)?;
    let tri = mesh.triangles.get(hit.hit.prim as usize)?;
    let p = tri.map(|i| {
        let at = mesh
            .positions
            .get(i as usize)
            .copied()
            .unwrap_or(Vec3::ZERO);
        inst.world_from_object.transform_point3(at)
    });
    let (e1, e2) = (p[1] - p[0], p[2] - p[0]);
    let n = e1.cross(e2);
    let nn = n.length_squared();
    if nn <= 0.0 || !nn.is_finite() {
        return None;
    }
    // Gradients of the barycentrics b₁, b₂ within the plane (∇b₁·e₁ = 1, ∇b₁·e₂ = 0, …).
    let grad_b1 = e2.cross(n) / nn;
    let grad_b2 = n.cross(e1) / nn;
    let (d1, d2) = if mesh.uvs.is_empty() {
        (Vec2::X, Vec2::Y)
    } else {
        let t = tri.map(|i| mesh.uvs.get(i as usize).copied().unwrap_or(Vec2::ZERO));
        (t[1] - t[0], t[2] - t[0])
    };
    let grad_u = grad_b1 * d1.x + grad_b2 * d2.x;
    let grad_v = grad_b1 * d1.y + grad_b2 * d2.y;
    Some((n / nn.sqrt(), grad_u, grad_v))
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

    #[test]
    fn scale_is_one_over_root_spp_floored_at_an_eighth() {
        assert_eq!(footprint_scale(1), 1.0);
        assert_eq!(footprint_scale(0), 1.0);
        assert_eq!(footprint_scale(4), 0.5);
        assert_eq!(footprint_scale(16), 0.25);
        assert_eq!(footprint_scale(64), 0.125);
        assert_eq!(footprint_scale(1024), 0.125);
    }

    #[test]
    fn isotropic_footprint_has_equal_axes() {
        let f = Footprint::isotropic(0.25);
        assert_eq!(f.width(), 0.25);
        let (a, b) = f.in_texels(Vec2::new(8.0, 4.0));
        assert_eq!((a, b), (Vec2::new(2.0, 0.0), Vec2::new(0.0, 1.0)));
    }
}
