//! The shading layer: what a hit point needs to be shaded.

pub mod brdf;
pub mod distribution;
pub mod distribution2d;
pub mod light;
pub mod normal_map;
pub mod sampling;
pub mod surface;
pub mod texture;

pub use light::{AreaLight, EnvMap, EnvSample, Environment, Light, Lights, Picked, PointLight};
pub use texture::{Texture, Textures};
