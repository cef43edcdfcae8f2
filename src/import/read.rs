//! Reading visibility and depth images (EXR through the `exr` crate, PNG through `image`) into
//! one f32 per pixel, row 0 at the top.

use super::{ImportedImage, ReadOptions};
use crate::error::{Error, Result};
use exr::prelude::*;
use image::DynamicImage;
use std::path::Path;

fn import_error(path: &Path, message: impl Into<String>) -> Error {
    Error::Import { path: path.to_path_buf(), message: message.into() }
}

/// Reads a visibility file (see the module documentation): values in [0, 1], or NaN or negative
/// for background; any other value is an error naming the pixel.
pub fn read_visibility(path: impl AsRef<Path>, options: &ReadOptions) -> Result<ImportedImage> {
    let image = read_image(path.as_ref(), options, None)?;
    if let Some(i) = image.values.iter().position(|&v| v > 1.0) {
        let (x, y) = (i as u32 % image.width, i as u32 / image.width);
        return Err(import_error(
            &image.path,
            format!(
                "pixel ({x}, {y}) is {}: visibility must be in [0, 1] (NaN or negative for background)",
                image.values[i]
            ),
        ));
    }
    Ok(image)
}

/// Reads a depth file (EXR; the only channel or `Z`, unless `options` names one): distances ≥ 0
/// or `+inf`; a NaN or negative depth is an error naming the pixel.
pub fn read_depth(path: impl AsRef<Path>, options: &ReadOptions) -> Result<ImportedImage> {
    let image = read_image(path.as_ref(), options, Some("Z"))?;
    if let Some(i) = image.values.iter().position(|&d| d.is_nan() || d < 0.0) {
        let (x, y) = (i as u32 % image.width, i as u32 / image.width);
        return Err(import_error(
            &image.path,
            format!("pixel ({x}, {y}) is {}: depth must be ≥ 0 (0 or +inf for background)", image.values[i]),
        ));
    }
    Ok(image)
}

/// One channel of an EXR or PNG file, by extension; `fallback` is the channel taken from a
/// many-channel EXR when none is named.
pub(super) fn read_image(
    path: &Path,
    options: &ReadOptions,
    fallback: Option<&str>,
) -> Result<ImportedImage> {
    if !path.is_file() {
        return Err(import_error(path, "no such file"));
    }
    let extension = path.extension().and_then(|e| e.to_str()).map(str::to_ascii_lowercase);
    let (width, height, mut values) = match extension.as_deref() {
        Some("exr") => read_exr(path, options.channel.as_deref(), fallback)?,
        Some("png") if options.channel.is_some() => {
            return Err(import_error(path, "a channel name applies to EXR files only"));
        }
        Some("png") if fallback.is_some() => return Err(import_error(path, "depth files must be EXR")),
        Some("png") => read_png(path)?,
        _ => return Err(import_error(path, "unknown image type: expected a .exr or .png file")),
    };
    if width == 0 || height == 0 {
        return Err(import_error(path, "an empty image"));
    }
    if options.flip_y {
        flip_rows(&mut values, width as usize);
    }
    Ok(ImportedImage { path: path.to_path_buf(), width, height, values })
}

fn flip_rows(values: &mut [f32], width: usize) {
    let rows = values.len() / width;
    for y in 0..rows / 2 {
        let (top, bottom) = values.split_at_mut((rows - 1 - y) * width);
        top[y * width..(y + 1) * width].swap_with_slice(&mut bottom[..width]);
    }
}

fn read_exr(path: &Path, channel: Option<&str>, fallback: Option<&str>) -> Result<(u32, u32, Vec<f32>)> {
    let image = read()
        .no_deep_data()
        .largest_resolution_level()
        .all_channels()
        .first_valid_layer()
        .all_attributes()
        .from_file(path)
        .map_err(|e| import_error(path, format!("not a readable EXR file: {e}")))?;
    let layer = &image.layer_data;
    let list = &layer.channel_data.list;
    let names: Vec<String> = list.iter().map(|c| c.name.to_string()).collect();
    let chosen = match (channel, fallback) {
        (Some(name), _) => list.iter().find(|c| c.name.eq(name)),
        (None, _) if list.len() == 1 => list.first(),
        (None, Some(name)) => list.iter().find(|c| c.name.eq(name)),
        (None, None) => None,
    };
    let Some(chosen) = chosen else {
        let wanted = channel.or(fallback).map_or("one channel".to_string(), |c| format!("channel \"{c}\""));
        return Err(import_error(
            path,
            format!("no {wanted} among the channels {}: name one", names.join(", ")),
        ));
    };
    let values = match &chosen.sample_data {
        FlatSamples::F32(v) => v.clone(),
        FlatSamples::F16(v) => v.iter().map(|h| h.to_f32()).collect(),
        FlatSamples::U32(_) => {
            return Err(import_error(
                path,
                format!("channel {} holds u32 samples: expected f16 or f32", chosen.name),
            ));
        }
    };
    let (width, height) = (layer.size.width() as u32, layer.size.height() as u32);
    if values.len() != width as usize * height as usize {
        let message = format!("channel {} is subsampled: expected one sample per pixel", chosen.name);
        return Err(import_error(path, message));
    }
    Ok((width, height, values))
}

fn read_png(path: &Path) -> Result<(u32, u32, Vec<f32>)> {
    let decoded = image::ImageReader::open(path)
        .map_err(|e| import_error(path, format!("cannot open: {e}")))?
        .with_guessed_format()
        .map_err(|e| import_error(path, format!("cannot read: {e}")))?
        .decode()
        .map_err(|e| import_error(path, format!("not a readable PNG file: {e}")))?;
    let (width, height) = (decoded.width(), decoded.height());
    // The first channel of every pixel, scaled so that the largest code is 1.
    fn first<T: Copy + Into<f32>>(raw: &[T], channels: usize, max: f32) -> Vec<f32> {
        raw.chunks_exact(channels).map(|px| px[0].into() / max).collect()
    }
    let values = match &decoded {
        DynamicImage::ImageLuma8(b) => first(b.as_raw(), 1, 255.0),
        DynamicImage::ImageLumaA8(b) => first(b.as_raw(), 2, 255.0),
        DynamicImage::ImageRgb8(b) => first(b.as_raw(), 3, 255.0),
        DynamicImage::ImageRgba8(b) => first(b.as_raw(), 4, 255.0),
        DynamicImage::ImageLuma16(b) => first(b.as_raw(), 1, 65535.0),
        DynamicImage::ImageLumaA16(b) => first(b.as_raw(), 2, 65535.0),
        DynamicImage::ImageRgb16(b) => first(b.as_raw(), 3, 65535.0),
        DynamicImage::ImageRgba16(b) => first(b.as_raw(), 4, 65535.0),
        other => return Err(import_error(path, format!("unsupported PNG pixel type {:?}", other.color()))),
    };
    Ok((width, height, values))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn an_rgb_png_gives_its_first_channel_over_255() {
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join("v.png");
        // Red carries the visibility; green and blue must be ignored.
        let pixels = [0u8, 255, 255, 255, 0, 0, 51, 7, 9];
        image::save_buffer(&path, &pixels, 3, 1, image::ExtendedColorType::Rgb8).unwrap();
        let image = read_visibility(&path, &ReadOptions::default()).unwrap();
        assert_eq!((image.width, image.height), (3, 1));
        assert_eq!(image.values, vec![0.0, 1.0, 0.2]);
        let named = ReadOptions { channel: Some("R".into()), flip_y: false };
        assert!(read_visibility(&path, &named).unwrap_err().to_string().contains("EXR files only"));
    }

    #[test]
    fn flipping_reverses_the_rows_only() {
        let mut v = vec![0.0, 1.0, 2.0, 3.0, 4.0, 5.0];
        flip_rows(&mut v, 2);
        assert_eq!(v, vec![4.0, 5.0, 2.0, 3.0, 0.0, 1.0]);
    }
}
