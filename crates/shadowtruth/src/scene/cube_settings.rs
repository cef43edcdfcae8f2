//! A point light's cube shadow map, as a scene file sets it (docs/point-lights.md). The six faces
//! themselves are built per resolution in src/raster/cube_map.rs.

use crate::json_input::{Reader, count};

/// How a point light's six-face cube map is drawn.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct CubeSettings {
    /// Texels drawn beyond each edge of every face, at the face's own texel size: a filter tap
    /// up to this far past an edge reads the scene in its direction, as a seamless cube lookup
    /// reads the neighbouring face; farther taps clamp to the face's edge. 0 is a cube whose
    /// filters clamp at every seam.
    pub guard_texels: u32,
}

/// The largest guard band, in texels.
pub const MAX_GUARD_TEXELS: u32 = 64;

impl Default for CubeSettings {
    /// A guard of 8 texels: wider than the 5×5 PCF kernel and its bilinear taps, and than the
    /// filterable maps' default blur.
    fn default() -> Self {
        CubeSettings { guard_texels: 8 }
    }
}

/// Reads a point light's `cube_map` object: `{"guard_texels"}`.
pub(super) fn read_cube_settings(r: &mut Reader) -> Option<CubeSettings> {
    let guard = CubeSettings::default().guard_texels;
    let guard_texels = r.optional_or("guard_texels", count(0, MAX_GUARD_TEXELS as u64), guard)?;
    Some(CubeSettings { guard_texels })
}
