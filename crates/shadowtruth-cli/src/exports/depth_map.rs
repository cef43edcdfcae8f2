//! `shadowtruth depth-map`: one depth layer as a one-channel f32 EXR (row 0 at the top, the
//! largest v; empty texels 1.0) and a JSON sidecar with the matrix the rasterizer used, so that
//! the map can be checked against any other rasterizer.

use exr::prelude::*;
use shadowtruth::atomic_file::write_atomic;
use shadowtruth::raster::{DepthLayer, LightView};
use shadowtruth::trace::EXR_ENCODING;
use std::path::Path;

/// Writes `path` (EXR, channel `Z`) and `path` with extension `.json` (the sidecar).
pub fn write_depth_map(
    path: &Path,
    layer: &DepthLayer,
    view: &LightView,
    description: serde_json::Value,
) -> std::io::Result<()> {
    let n = layer.resolution as usize;
    let channel = AnyChannel::new("Z", FlatSamples::F32(layer.depth.clone()));
    let image = Image::from_layer(Layer::new(
        (n, n),
        LayerAttributes::named("depth"),
        EXR_ENCODING,
        AnyChannels::sort(SmallVec::from_vec(vec![channel])),
    ));
    let mut bytes = std::io::Cursor::new(Vec::new());
    image.write().to_buffered(&mut bytes).map_err(std::io::Error::other)?;
    write_atomic(path, bytes.get_ref())?;
    let m = view.clip_from_world.transpose().to_cols_array_2d(); // rows of the matrix
    let sidecar = serde_json::json!({
        "clip_from_world": m,
        "near": view.near,
        "far": view.far,
        "resolution": layer.resolution,
        "layer": description,
        "conventions": "clip = clip_from_world · (x, y, z, 1); u = x/w·½ + ½, v = y/w·½ + ½ (v up, row 0 of the EXR is the largest v), depth = z/w in [0, 1], smaller is closer; empty texels 1.0",
    });
    let mut text = serde_json::to_string_pretty(&sidecar).map_err(std::io::Error::other)?;
    text.push('\n');
    write_atomic(&path.with_extension("json"), text.as_bytes())
}
