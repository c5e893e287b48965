//! pixelproc's bit-exact golden model and the renderer around it.
//!
//! Data flows one way: scene ([`scene`]) → float front end ([`frontend`]) → one snapping
//! step → span setup ([`setup`]) → the pixel-processor array ([`pixel_array`]) → image
//! ([`pipeline`]). The planner ([`plan`]) decides which stages run. See
//! `docs/architecture.md` for the whole map and `docs/formats.md` for every bit layout.

#![warn(missing_docs)]

pub mod aa;
pub mod abuffer;
pub mod builtin;
pub mod core_model;
pub mod frontend;
pub mod hwcost;
pub mod input;
pub mod mask;
pub mod mask_search;
pub mod obj;
pub mod pipeline;
pub mod pixel_array;
pub mod plan;
pub mod raster;
pub mod reference;
pub mod render;
pub mod rng;
pub mod scene;
pub mod setup;
pub mod shadow;
pub mod stream;
pub mod strict_json;
