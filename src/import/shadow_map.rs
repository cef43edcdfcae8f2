//! Another renderer's shadow map: one depth layer as an EXR (row 0 at the top, the largest v;
//! depth d in [0, 1], smaller closer; empty texels 1) with a JSON sidecar holding the row-major
//! `clip_from_world` and the `near` and `far` planes — the files `shadowtruth depth-map`
//! writes (docs/conventions.md, "Imported buffers").

use super::{ReadOptions, read::read_image};
use crate::error::{Error, Result};
use crate::raster::{DepthLayer, LightView};
use crate::scene::Light;
use glam::Mat4;
use std::path::{Path, PathBuf};

/// A shadow map read from its files.
#[derive(Clone, Debug, PartialEq)]
pub struct ImportedShadowMap {
    pub layer: DepthLayer,
    pub clip_from_world: Mat4,
    pub near: f32,
    pub far: f32,
    /// The EXR and the sidecar, named in errors.
    pub files: (PathBuf, PathBuf),
}

impl ImportedShadowMap {
    /// The light view of `light` this map was rendered with (`LightView::from_clip_from_world`).
    pub fn light_view(&self, light: &Light) -> Result<LightView> {
        LightView::from_clip_from_world(
            light,
            self.clip_from_world,
            self.near,
            self.far,
            self.layer.resolution,
        )
        .map_err(|message| Error::Import {
            path: self.files.1.clone(),
            message: format!("clip_from_world: {message}"),
        })
    }
}

/// Reads a square depth map (EXR: the only channel or `Z`; every depth in [0, 1]) and its
/// sidecar (JSON: `clip_from_world` as 4 rows of 4 numbers, `near`, `far`).
pub fn read_shadow_map(map: impl AsRef<Path>, sidecar: impl AsRef<Path>) -> Result<ImportedShadowMap> {
    let (map, sidecar) = (map.as_ref(), sidecar.as_ref());
    let image = read_image(map, &ReadOptions::default(), Some("Z"))?;
    let error = |path: &Path, message: String| Error::Import { path: path.to_path_buf(), message };
    if image.width != image.height {
        return Err(error(map, format!("{}×{} texels: a shadow map is square", image.width, image.height)));
    }
    if let Some(i) = image.values.iter().position(|d| !(0.0..=1.0).contains(d)) {
        let (x, y) = (i as u32 % image.width, i as u32 / image.width);
        return Err(error(map, format!("texel ({x}, {y}) is {}: depth must be in [0, 1]", image.values[i])));
    }
    let text = std::fs::read_to_string(sidecar).map_err(|e| error(sidecar, format!("cannot read: {e}")))?;
    let json: serde_json::Value =
        serde_json::from_str(&text).map_err(|e| error(sidecar, format!("not JSON: {e}")))?;
    let number = |v: &serde_json::Value, at: &str| {
        v.as_f64()
            .filter(|x| x.is_finite())
            .ok_or_else(|| error(sidecar, format!("{at}: expected a finite number")))
    };
    let mut rows = [[0f32; 4]; 4];
    for (r, row) in rows.iter_mut().enumerate() {
        for (c, cell) in row.iter_mut().enumerate() {
            let at = format!("clip_from_world[{r}][{c}]");
            *cell = number(&json["clip_from_world"][r][c], &at)? as f32;
        }
    }
    let clip_from_world = Mat4::from_cols_array_2d(&rows).transpose();
    let (near, far) = (number(&json["near"], "near")? as f32, number(&json["far"], "far")? as f32);
    let layer = DepthLayer { resolution: image.width, depth: image.values };
    Ok(ImportedShadowMap {
        layer,
        clip_from_world,
        near,
        far,
        files: (map.to_path_buf(), sidecar.to_path_buf()),
    })
}
