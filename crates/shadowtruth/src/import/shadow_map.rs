//! Another renderer's shadow map: one depth layer as an EXR (row 0 at the top, the largest v;
//! depth d in [0, 1], smaller closer; empty texels 1) with a JSON sidecar holding the row-major
//! `clip_from_world`, the `near` and `far` planes and optionally the map's `resolution` — the
//! files `shadowtruth depth-map` writes (docs/conventions.md, "Imported buffers").

use super::ReadOptions;
use super::error::{ImportError, Result};
use super::expected_size::ExpectedSize;
use super::map_light::check_map_light;
use super::read::{ImageSource, read_image};
use crate::raster::{DepthLayer, LightView, MAX_SHADOW_MAP_RESOLUTION};
use crate::scene::Light;
use glam::{Mat4, Vec3};
use serde_json::Value;
use std::path::{Path, PathBuf};

/// The most bytes of a sidecar read: 1 MiB, far above its 16 numbers and two planes.
const MAX_SIDECAR_BYTES: u64 = 1 << 20;

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
    /// The light view of `light` this map was rendered with (`LightView::from_clip_from_world`),
    /// once its matrix is checked to be a map of `light` in a scene of `scene_bounds`
    /// (src/import/map_light.rs): a map of another light is an error naming the sidecar's
    /// `clip_from_world`.
    pub fn light_view(&self, light: &Light, scene_bounds: (Vec3, Vec3)) -> Result<LightView> {
        let sidecar_error = |message: String| ImportError::File {
            path: self.files.1.clone(),
            message: format!("clip_from_world: {message}"),
        };
        check_map_light(self.clip_from_world, light, scene_bounds).map_err(sidecar_error)?;
        LightView::from_clip_from_world(
            light,
            self.clip_from_world,
            self.near,
            self.far,
            self.layer.resolution,
        )
        .map_err(sidecar_error)
    }
}

/// Reads a square depth map (EXR: the only channel or `Z`; every depth in [0, 1]) and its
/// sidecar (JSON: `clip_from_world` as 4 rows of 4 numbers, `near`, `far`, and optionally the
/// map's `resolution`, which the EXR's header must then declare).
pub fn read_shadow_map(map: impl AsRef<Path>, sidecar: impl AsRef<Path>) -> Result<ImportedShadowMap> {
    let (map, sidecar) = (map.as_ref(), sidecar.as_ref());
    let error = |path: &Path, message: String| ImportError::File { path: path.to_path_buf(), message };
    // The sidecar is read first for the size it declares, but its errors come after the map's.
    let json = read_sidecar(sidecar);
    let declared = json.as_ref().ok().and_then(|j| resolution(j).ok().flatten());
    let expected =
        declared.map_or(ExpectedSize::ANY_SHADOW_MAP, |resolution| ExpectedSize::Map { resolution });
    let image = read_image(ImageSource::File(map), &ReadOptions::default(), Some("Z"), expected)?;
    if image.width != image.height {
        return Err(error(map, format!("{}×{} texels: a shadow map is square", image.width, image.height)));
    }
    if let Some(i) = image.values.iter().position(|d| !(0.0..=1.0).contains(d)) {
        let (x, y) = (i as u32 % image.width, i as u32 / image.width);
        return Err(error(map, format!("texel ({x}, {y}) is {}: depth must be in [0, 1]", image.values[i])));
    }
    let json = json.map_err(|message| error(sidecar, message))?;
    resolution(&json).map_err(|message| error(sidecar, message))?;
    // Matrices are f32: a number that f32 cannot hold (it would become ±inf, or 0) is refused,
    // never changed silently.
    let number = |v: &Value, at: &str| {
        v.as_f64()
            .filter(|x| x.is_finite())
            .filter(|&x| (x as f32).is_finite() && ((x as f32) != 0.0 || x == 0.0))
            .map(|x| x as f32)
            .ok_or_else(|| error(sidecar, format!("{at}: expected a finite number that f32 can hold")))
    };
    let mut rows = [[0f32; 4]; 4];
    for (r, row) in rows.iter_mut().enumerate() {
        for (c, cell) in row.iter_mut().enumerate() {
            let at = format!("clip_from_world[{r}][{c}]");
            *cell = number(&json["clip_from_world"][r][c], &at)?;
        }
    }
    let clip_from_world = Mat4::from_cols_array_2d(&rows).transpose();
    let (near, far) = (number(&json["near"], "near")?, number(&json["far"], "far")?);
    let layer = DepthLayer { resolution: image.width, depth: image.values };
    Ok(ImportedShadowMap {
        layer,
        clip_from_world,
        near,
        far,
        files: (map.to_path_buf(), sidecar.to_path_buf()),
    })
}

/// The sidecar's JSON, read up to `MAX_SIDECAR_BYTES`.
fn read_sidecar(sidecar: &Path) -> std::result::Result<Value, String> {
    let text = crate::input_file::read_named_text(sidecar, MAX_SIDECAR_BYTES)?;
    serde_json::from_str(&text).map_err(|e| format!("not JSON: {e}"))
}

/// The sidecar's `resolution`, when it has one: an integer from 1 to the largest map.
fn resolution(json: &Value) -> std::result::Result<Option<u32>, String> {
    let Some(value) = json.get("resolution") else { return Ok(None) };
    match value.as_u64() {
        Some(r) if (1..=MAX_SHADOW_MAP_RESOLUTION as u64).contains(&r) => Ok(Some(r as u32)),
        _ => Err(format!("resolution: {value}: expected an integer from 1 to {MAX_SHADOW_MAP_RESOLUTION}")),
    }
}
