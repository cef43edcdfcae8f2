//! Buffers another renderer wrote, read so that they can be scored like a technique's output
//! (docs/conventions.md, "Imported buffers").
//!
//! - A **visibility** file holds one value per camera pixel, row 0 at the top (or at the bottom
//!   with `flip_y`), 1 lit and 0 shadowed; a value of ½ or more counts as lit. EXR (f16 or f32,
//!   the only channel or the one named) or PNG (8 or 16 bit grey, or the first channel of RGB(A),
//!   scaled to [0, 1]). A NaN or negative value marks a pixel where the renderer drew background.
//! - A **depth** file (optional) holds, per camera pixel, the distance from the camera's position
//!   to the surface the renderer saw, along the pixel's primary ray, in world units; `+inf` or
//!   `0` where it drew background. EXR only (f16 or f32; the only channel, or `Z`).
//!
//! - A **shadow map** (`read_shadow_map`) is one depth layer with its `clip_from_world`, as
//!   `shadowtruth depth-map` writes it: a built-in technique shades the reference's G-buffer
//!   with it instead of our own map, once its matrix is checked to be the light's.
//!
//! Every image header is checked before a pixel is decoded (`ExpectedSize`): its size must be
//! the camera's (or the map's) where that is known, and within the largest camera image (or
//! map) where it is not; the file must be long enough for what the header declares.
//!
//! A pixel the reference evaluates is a *surface mismatch*, left out of every score and counted
//! in `Counts::surface_mismatch`, when the renderer drew background there, or when its depth `d`
//! differs from the reference's distance `t` by more than `tolerance · t + DEPTH_FLOOR_WORLD`.

mod buffer_kind;
mod error;
mod expected_size;
mod exr_image;
mod map_light;
mod png_image;
mod read;
mod shadow_map;
mod surface;

pub use buffer_kind::BufferKind;
pub use error::ImportError;
pub use expected_size::ExpectedSize;
pub use read::{ImageSource, read_depth, read_depth_from, read_visibility, read_visibility_from};
pub use shadow_map::{ImportedShadowMap, read_shadow_map};
pub use surface::evaluated_visibility;

use std::path::PathBuf;

/// Relative tolerance of the depth comparison unless one is given: 1e-3, above the rounding of
/// an f16 depth (2⁻¹¹ relative) so that an exact depth stored as f16 still matches.
pub const DEFAULT_DEPTH_TOLERANCE: f64 = 1e-3;

/// Absolute floor of the depth tolerance, in world units, for surfaces very near the camera.
pub const DEPTH_FLOOR_WORLD: f64 = 1e-4;

/// How an image file is read.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct ReadOptions {
    /// The EXR channel to read (needed when the file has more than one).
    pub channel: Option<String>,
    /// Row 0 of the file is the bottom row of the image.
    pub flip_y: bool,
}

/// One channel of an image file, row 0 at the top, with the file it came from (named in every
/// error about it).
#[derive(Clone, Debug, PartialEq)]
pub struct ImportedImage {
    pub path: PathBuf,
    pub width: u32,
    pub height: u32,
    pub values: Vec<f32>,
}
