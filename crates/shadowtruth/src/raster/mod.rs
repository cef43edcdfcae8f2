//! The light's view: projection and frustum fitting, the CPU depth rasterizer (GPU rules),
//! depth layers and depth formats.

mod bands;
mod cascades;
mod clip;
mod cube_map;
mod depth_format;
mod dual_paraboloid;
mod imported_view;
mod layer;
mod moment_level;
mod moment_map;
mod multi_depth;
mod projection;
mod raster_settings;
mod rasterize;
mod setup;

pub use cascades::{CascadeChoice, Cascades, default_max_distance, split_distances};
pub use cube_map::{CUBE_FACE_NAMES, CubeMap, SEAM_TEXELS};
pub use depth_format::DepthFormat;
pub use dual_paraboloid::{DualParaboloid, PARABOLOID_NAMES};

/// Largest shadow-map side accepted, in texels.
pub const MAX_SHADOW_MAP_RESOLUTION: u32 = 16384;
/// What `LightView::light_size` holds; PCSS reads it from here.
pub use crate::scene::LightSize;
pub use layer::{DepthLayer, DepthPairLayer};
pub use moment_level::MomentLevel;
pub use moment_map::{
    MAX_BLUR_RADIUS_TEXELS, MapBlur, MomentLayer, MomentWarp, evsm_negative, evsm_positive, level_of_detail,
};
pub use multi_depth::{DepthSelection, MAX_DEPTHS_PER_TEXEL, MultiDepthLayer};
pub use projection::{LightView, Projection};
pub use raster_settings::{Culling, DepthPlane, RasterSettings};
pub use rasterize::{
    Rasterizer, rasterize_coverage, rasterize_nearest, rasterize_nearest_into, rasterize_two_nearest,
};
