//! The G-buffer as three EXRs, row 0 at the top, lossless and with tiles in increasing order (so
//! the same G-buffer gives the same bytes): `position.exr` and `normal.exr` (f32 channels R, G,
//! B = world x, y, z) and `ids.exr` (u32 channels `triangle`, `object`, `class`).

use exr::prelude::*;
use glam::Vec3;
use shadowtruth::Scene;
use shadowtruth::trace::{EXR_ENCODING, GBuffer, PixelClass};
use std::io::Cursor;

pub(crate) const POSITION_FILE: &str = "position.exr";
pub(crate) const NORMAL_FILE: &str = "normal.exr";
pub(crate) const IDS_FILE: &str = "ids.exr";

/// The `class` channel's value of each pixel class (docs/conventions.md, "Exported views").
pub(crate) fn class_code(class: PixelClass) -> u32 {
    match class {
        PixelClass::Background => 0,
        PixelClass::FacingAway => 1,
        PixelClass::OutsideLight => 2,
        PixelClass::Evaluated => 3,
        PixelClass::Uncertain => 4,
    }
}

/// (file name, EXR bytes) of the three files.
pub(crate) fn gbuffer_exrs(
    scene: &Scene,
    gbuffer: &GBuffer,
) -> std::io::Result<Vec<(&'static str, Vec<u8>)>> {
    let object = (0..gbuffer.pixel_count()).map(|i| gbuffer.object(scene, i)).collect();
    let ids = vec![
        AnyChannel::new("triangle", FlatSamples::U32(gbuffer.triangle.clone())),
        AnyChannel::new("object", FlatSamples::U32(object)),
        AnyChannel::new("class", FlatSamples::U32(gbuffer.class.iter().map(|&c| class_code(c)).collect())),
    ];
    Ok(vec![
        (POSITION_FILE, encode(gbuffer, "position", vector_channels(&gbuffer.position))?),
        (NORMAL_FILE, encode(gbuffer, "normal", vector_channels(&gbuffer.normal))?),
        (IDS_FILE, encode(gbuffer, "ids", ids)?),
    ])
}

fn vector_channels(values: &[Vec3]) -> Vec<AnyChannel<FlatSamples>> {
    let component = |name: &'static str, i: usize| {
        AnyChannel::new(name, FlatSamples::F32(values.iter().map(|v| v[i]).collect()))
    };
    vec![component("R", 0), component("G", 1), component("B", 2)]
}

fn encode(gbuffer: &GBuffer, name: &str, channels: Vec<AnyChannel<FlatSamples>>) -> std::io::Result<Vec<u8>> {
    let image = Image::from_layer(Layer::new(
        (gbuffer.width as usize, gbuffer.height as usize),
        LayerAttributes::named(name),
        EXR_ENCODING,
        AnyChannels::sort(SmallVec::from_vec(channels)),
    ));
    let mut bytes = Cursor::new(Vec::new());
    image.write().to_buffered(&mut bytes).map_err(std::io::Error::other)?;
    Ok(bytes.into_inner())
}
