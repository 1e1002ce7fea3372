//! Asset access: the only place (with `cli/`) that touches the file system.
//!
//! Every stage that needs a file (the parser for `include`, `scene::build` for OBJ files and
//! images) asks a [`Loader`]. [`FsLoader`] reads the disk and records each path it was asked
//! for, found or not: that record is exactly the set of files `scnc watch` must watch.
//! [`MemLoader`] serves files from memory so that every stage is testable without a disk.
//! [`obj`] decodes OBJ bytes (read through a `Loader`) into triangles; [`hdr_image`] decodes
//! environment maps (HDR, EXR, PFM) into linear float RGB; [`texture_image`] decodes material
//! textures (PNG, JPEG, HDR, EXR) into linear RGBA texels.

pub mod hdr_image;
mod loader;
pub mod obj;
pub mod texture_image;

pub use loader::{FsLoader, Loader, MemLoader};
