//! pixelproc's bit-exact golden model and the renderer around it.
//!
//! Data flows one way: scene (float front end) → one snapping step → span setup
//! ([`setup`]) → the pixel-processor array ([`pixel_array`]) → image. See
//! `docs/architecture.md` for the whole map and `docs/formats.md` for every bit layout.

#![warn(missing_docs)]

pub mod abuffer;
pub mod mask;
pub mod mask_search;
pub mod pixel_array;
pub mod render;
pub mod setup;
