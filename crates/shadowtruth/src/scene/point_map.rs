//! A point light's shadow map, as a scene file sets it (docs/point-lights.md): a cube of six
//! faces or two paraboloids. The maps themselves are built per resolution in
//! src/raster/cube_map.rs and src/raster/dual_paraboloid.rs.

use crate::json_input::{Reader, count};

/// How a point light's shadow map covers every direction.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum PointMap {
    /// Six 90° perspective faces.
    Cube(CubeSettings),
    /// Two paraboloid hemispheres (Brabec, Annen and Seidel 2002), looking down and up.
    DualParaboloid,
}

impl Default for PointMap {
    fn default() -> Self {
        PointMap::Cube(CubeSettings::default())
    }
}

impl PointMap {
    /// The layout's name, as scene files and reports write it.
    pub fn name(&self) -> &'static str {
        match self {
            PointMap::Cube(_) => "cube",
            PointMap::DualParaboloid => "dual_paraboloid",
        }
    }
}

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

/// A point light's `shadow_map` value: "cube" or "dual_paraboloid".
pub(super) fn as_layout(v: &serde_json::Value) -> Result<&'static str, String> {
    match crate::json_input::as_string(v)?.as_str() {
        "cube" => Ok("cube"),
        "dual_paraboloid" => Ok("dual_paraboloid"),
        other => Err(format!("unknown shadow map \"{other}\"; expected cube or dual_paraboloid")),
    }
}
