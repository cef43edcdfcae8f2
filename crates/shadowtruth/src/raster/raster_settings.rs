//! What a depth layer depends on besides the scene and the light view: depth format, culling,
//! polygon offset and the vertices of the depth plane.

use super::DepthFormat;

/// Which faces of closed objects are not rasterized (open objects are never culled).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub enum Culling {
    None,
    BackFacesOfClosed,
    FrontFacesOfClosed,
}

/// Which vertices the depth plane of a triangle goes through (docs/conventions.md, "Rasterizer").
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
pub enum DepthPlane {
    /// The vertices snapped to 1/256 texel, as coverage uses them (the default).
    #[default]
    Snapped,
    /// The unsnapped vertices (after the divide and viewport), as llvmpipe sets the plane up.
    Exact,
}

/// Everything a depth layer depends on besides the scene and the light view.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct RasterSettings {
    pub format: DepthFormat,
    pub culling: Culling,
    /// glPolygonOffset `factor` (multiplies the depth slope m, in depth units per texel).
    pub slope_factor: f32,
    /// glPolygonOffset `units` (multiplies the format's minimum resolvable difference r).
    pub slope_units: f32,
    /// The vertices the depth plane goes through; coverage always uses the snapped ones.
    pub depth_plane: DepthPlane,
}

impl Default for RasterSettings {
    fn default() -> Self {
        RasterSettings {
            format: DepthFormat::F32,
            culling: Culling::None,
            slope_factor: 0.0,
            slope_units: 0.0,
            depth_plane: DepthPlane::Snapped,
        }
    }
}
