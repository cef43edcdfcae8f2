//! The read-back pixels as the two buffers `shadowtruth score` reads, and their EXR files: one
//! f32 channel, uncompressed scanlines, row 0 at the top (as the three.js and Babylon.js
//! harnesses write them).

use crate::render::Pixels;
use exr::prelude::{
    AnyChannel, AnyChannels, Encoding, FlatSamples, Image, Layer, LayerAttributes, WritableImage,
};
use std::path::Path;

/// wgpu's `COPY_BYTES_PER_ROW_ALIGNMENT`: each read-back row is padded to it.
const ROW_ALIGNMENT_BYTES: usize = 256;
const RGBA32F_BYTES: usize = 16;

/// Per pixel, row 0 at the top: the shadow factor (NaN on background) and the camera distance
/// (+inf on background).
pub struct Buffers {
    pub visibility: Vec<f32>,
    pub depth_world: Vec<f32>,
    pub covered_pixels: usize,
}

pub fn decode(pixels: &Pixels) -> Result<Buffers, String> {
    let (w, h) = (pixels.width as usize, pixels.height as usize);
    let row_bytes = (w * RGBA32F_BYTES).div_ceil(ROW_ALIGNMENT_BYTES) * ROW_ALIGNMENT_BYTES;
    if pixels.bytes.len() < row_bytes * h {
        return Err(format!(
            "the read-back holds {} bytes, {w} × {h} RGBA f32 pixels need {}",
            pixels.bytes.len(),
            row_bytes * h
        ));
    }
    let mut out = Buffers {
        visibility: Vec::with_capacity(w * h),
        depth_world: Vec::with_capacity(w * h),
        covered_pixels: 0,
    };
    for y in 0..h {
        let row = &pixels.bytes[y * row_bytes..][..w * RGBA32F_BYTES];
        for px in row.chunks_exact(RGBA32F_BYTES) {
            let [r, g, b, a] = std::array::from_fn(|i| {
                f32::from_le_bytes(px[4 * i..4 * i + 4].try_into().expect("4 bytes"))
            });
            // The target is cleared to alpha 0; every surface writes alpha 1.
            if a > 0.5 {
                out.visibility.push(r);
                out.depth_world.push(g + b);
                out.covered_pixels += 1;
            } else {
                out.visibility.push(f32::NAN);
                out.depth_world.push(f32::INFINITY);
            }
        }
    }
    Ok(out)
}

/// Writes `values` (width × height, row 0 at the top) as a one-channel f32 EXR named `Y`.
pub fn write_exr(path: &Path, values: Vec<f32>, width: u32, height: u32) -> Result<(), String> {
    let channel = AnyChannel::new("Y", FlatSamples::F32(values));
    let layer = Layer::new(
        (width as usize, height as usize),
        LayerAttributes::default(),
        Encoding::UNCOMPRESSED,
        AnyChannels::sort(vec![channel].into()),
    );
    Image::from_layer(layer)
        .write()
        .non_parallel()
        .to_file(path)
        .map_err(|e| format!("cannot write {}: {e}", path.display()))
}
