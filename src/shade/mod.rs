//! The shading layer: what a hit point needs to be shaded, between scene build and the
//! integrator.
//!
//! ```text
//! scene::build ─▶ Scene { lights: Lights, textures: Textures, … }   stores shade types
//! render::integrator ─▶ shade::{surface, texture, normal_map, brdf, light, sampling}
//!                                                                    calls them per hit
//! ```
//!
//! The scene *stores* these types (built once from the IR and the assets); the integrator
//! *calls* them at every hit. Nothing here traces a ray, reads a file or draws a random number:
//! each routine is a function of the hit and of the numbers `u ∈ [0, 1)²` it is given, so it can
//! be tested against mathematics alone (pdfs that integrate to 1, samples whose density is the
//! pdf).
//!
//! - [`surface`]: the hit point itself (position with its error bound, normals, UV) and how a
//!   ray leaves it without hitting it again.
//! - [`texture`]: `texture … = image | checker | constant` evaluated at a UV and a footprint
//!   ([`texture::footprint`], the pixel's ray cone on the surface as an ellipse in UV space,
//!   shrunk as the pixel's samples grow); [`texture::image`] holds decoded texels and their mip
//!   pyramid, [`texture::anisotropic`] filters along the ellipse's major axis.
//! - [`normal_map`]: `normal_map` in tangent space, and the bend that keeps it plausible.
//! - [`color`]: the luminance of linear RGB, one weighting for every stage.
//! - [`brdf`]: the energy-normalised Phong BRDF: `eval`, `sample` and `pdf` side by side.
//! - [`light`]: the closed set of lights, each with `sample` beside `pdf` (pbrt's `SampleLi`
//!   beside `PDF_Li`), so that multiple importance sampling weighs a BRDF ray with exactly the
//!   density the light sampler had; the environment map and its importance table.
//! - [`sampling`]: warps from the unit square (cosine hemisphere, Phong lobe, sphere) and the
//!   power heuristic; [`distribution`] and [`distribution2d`]: tables sampled by inverting a
//!   CDF (lights by power, triangles by area, environment texels by luminance).
//!
//! The random numbers themselves (`render::rng`, hashed from pixel, sample and seed, and
//! stratified over the pixel) and the sub-pixel positions (`render::pattern`) stay in `render/`:
//! they are the render loop's sample sequence, decided by pixel and sample index, which this
//! layer never sees.

pub mod brdf;
pub mod color;
pub mod distribution;
pub mod distribution2d;
pub mod light;
pub mod normal_map;
pub mod sampling;
pub mod surface;
pub mod texture;

pub use light::{AreaLight, EnvMap, EnvSample, Environment, Light, Lights, Picked, PointLight};
pub use texture::{Texture, Textures};
