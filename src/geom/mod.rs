//! Geometry primitives shared by the acceleration structures and the renderer: rays, bounds and
//! ray–triangle intersection. No scene or file knowledge lives here.

mod aabb;
pub mod avx2;
mod ray;
pub mod triangle;
pub mod triangle4;
pub mod triangle8;

pub use aabb::Aabb;
pub use ray::Ray;
