//! The parts of `view.json` (`shadowtruth/view/v1`, written by `shadowtruth view-export`) that the
//! render needs: the camera, the light and its shadow map's box.

use serde::Deserialize;
use std::path::{Path, PathBuf};

#[derive(Debug, Deserialize)]
pub struct View {
    pub format: String,
    pub scene_glb: String,
    pub camera: Camera,
    pub light: Light,
}

#[derive(Debug, Deserialize)]
pub struct Camera {
    pub position: [f32; 3],
    pub look_at: [f32; 3],
    pub up: [f32; 3],
    pub fov_y_rad: f32,
    pub width: u32,
    pub height: u32,
    pub near: f32,
    pub far: f32,
}

#[derive(Debug, Deserialize)]
#[serde(tag = "type", rename_all = "lowercase")]
pub enum Light {
    Directional {
        direction: [f32; 3],
        shadow_map: ShadowMap,
    },
    Spot {
        position: [f32; 3],
        direction: [f32; 3],
        cone_deg: f32,
        near: f32,
        far: f32,
        shadow_map: ShadowMap,
    },
}

impl Light {
    pub fn shadow_map(&self) -> &ShadowMap {
        match self {
            Light::Directional { shadow_map, .. } | Light::Spot { shadow_map, .. } => shadow_map,
        }
    }
}

/// The exported map: its resolution, and for a directional light the orthographic box in the
/// light's view space (`view_from_world` looks down −z).
#[derive(Debug, Deserialize)]
pub struct ShadowMap {
    pub resolution: u32,
    pub near: f32,
    pub far: f32,
    pub left: Option<f32>,
    pub right: Option<f32>,
    pub bottom: Option<f32>,
    pub top: Option<f32>,
    pub view_from_world_column_major: [f32; 16],
    pub eye: Eye,
}

/// The map's eye: `lookAt(position → target, up)` is its `view_from_world`.
#[derive(Debug, Deserialize)]
pub struct Eye {
    pub up: [f32; 3],
}

/// The orthographic box of a directional light's map, light view space.
#[derive(Clone, Copy, Debug)]
pub struct OrthoBox {
    pub left: f32,
    pub right: f32,
    pub bottom: f32,
    pub top: f32,
    pub near: f32,
    pub far: f32,
}

impl ShadowMap {
    pub fn eye_up(&self) -> [f32; 3] {
        self.eye.up
    }

    pub fn ortho_box(&self) -> Option<OrthoBox> {
        Some(OrthoBox {
            left: self.left?,
            right: self.right?,
            bottom: self.bottom?,
            top: self.top?,
            near: self.near,
            far: self.far,
        })
    }
}

pub const FORMAT: &str = "shadowtruth/view/v1";

/// Reads `DIR/view.json`; the error names the file.
pub fn read(dir: &Path) -> Result<(View, PathBuf), String> {
    let path = dir.join("view.json");
    let text = std::fs::read_to_string(&path).map_err(|e| format!("cannot read {}: {e}", path.display()))?;
    let view: View =
        serde_json::from_str(&text).map_err(|e| format!("{}: not a view export: {e}", path.display()))?;
    if view.format != FORMAT {
        return Err(format!("{}: format {:?}, expected {FORMAT:?}", path.display(), view.format));
    }
    if view.camera.width == 0 || view.camera.height == 0 {
        return Err(format!("{}: the camera has no pixels", path.display()));
    }
    let glb = dir.join(&view.scene_glb);
    Ok((view, glb))
}
