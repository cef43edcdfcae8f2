//! Reading visibility and depth images (EXR through the `exr` crate, PNG through `png`) into
//! one f32 per pixel, row 0 at the top; from a file or from memory, through the same checks.
//! Every header is checked before any pixel is decoded (`ExpectedSize`).

use super::buffer_kind::BufferKind;
use super::error::{ImportError, Result};
use super::expected_size::ExpectedSize;
use super::exr_image::{ChannelChoice, read_exr_channel};
use super::png_image::read_png_first_channel;
use super::{ImportedImage, ReadOptions};
use std::io::{BufReader, Cursor};
use std::path::Path;

fn import_error(path: &Path, message: impl Into<String>) -> ImportError {
    ImportError::File { path: path.to_path_buf(), message: message.into() }
}

/// Where an image's bytes are: a file, or memory (with the name its messages show, whose
/// extension says the format).
#[derive(Clone, Copy, Debug)]
pub enum ImageSource<'a> {
    File(&'a Path),
    Bytes { name: &'a Path, bytes: &'a [u8] },
}

impl ImageSource<'_> {
    fn path(&self) -> &Path {
        match self {
            ImageSource::File(path) | ImageSource::Bytes { name: path, .. } => path,
        }
    }
}

/// Reads a visibility file (see the module documentation) of any camera's size: values in
/// [0, 1], or NaN or negative for background; any other value is an error naming the pixel.
pub fn read_visibility(path: impl AsRef<Path>, options: &ReadOptions) -> Result<ImportedImage> {
    read_visibility_from(ImageSource::File(path.as_ref()), options, ExpectedSize::ANY_CAMERA)
}

/// [`read_visibility`] of a file or bytes whose header must declare `expected` (the camera's
/// size, when it is known) before any pixel is decoded.
pub fn read_visibility_from(
    source: ImageSource,
    options: &ReadOptions,
    expected: ExpectedSize,
) -> Result<ImportedImage> {
    let image = read_image(source, options, None, expected)?;
    refuse_values(image, BufferKind::Visibility)
}

/// Reads a depth file of any camera's size (EXR; the only channel or `Z`, unless `options`
/// names one): distances ≥ 0 or `+inf`; a NaN or negative depth is an error naming the pixel.
pub fn read_depth(path: impl AsRef<Path>, options: &ReadOptions) -> Result<ImportedImage> {
    read_depth_from(ImageSource::File(path.as_ref()), options, ExpectedSize::ANY_CAMERA)
}

/// [`read_depth`] of a file or bytes whose header must declare `expected`.
pub fn read_depth_from(
    source: ImageSource,
    options: &ReadOptions,
    expected: ExpectedSize,
) -> Result<ImportedImage> {
    let image = read_image(source, options, Some("Z"), expected)?;
    refuse_values(image, BufferKind::Depth)
}

/// `image`, or the error naming its first value that a `kind` buffer may not hold.
fn refuse_values(image: ImportedImage, kind: BufferKind) -> Result<ImportedImage> {
    match kind.first_refused(&image.values, image.width) {
        Some(message) => Err(import_error(&image.path, message)),
        None => Ok(image),
    }
}

/// The two formats, by extension.
#[derive(Clone, Copy, PartialEq)]
enum Format {
    Exr,
    Png,
}

/// One channel of an EXR or PNG image, by extension; `fallback` is the channel taken from a
/// many-channel EXR when none is named (and says a depth file is read, which must be EXR).
pub(super) fn read_image(
    source: ImageSource,
    options: &ReadOptions,
    fallback: Option<&str>,
    expected: ExpectedSize,
) -> Result<ImportedImage> {
    let path = source.path();
    let extension = path.extension().and_then(|e| e.to_str()).map(str::to_ascii_lowercase);
    let format = match extension.as_deref() {
        Some("exr") => Format::Exr,
        Some("png") if options.channel.is_some() => {
            return Err(import_error(path, "a channel name applies to EXR files only"));
        }
        Some("png") if fallback.is_some() => return Err(import_error(path, "depth files must be EXR")),
        Some("png") => Format::Png,
        _ => return Err(import_error(path, "unknown image type: expected a .exr or .png file")),
    };
    let choice = ChannelChoice { named: options.channel.as_deref(), fallback };
    let decoded = match source {
        ImageSource::File(path) => {
            let (file, file_bytes) = open_regular_file(path)?;
            decode(format, BufReader::new(file), file_bytes, &choice, expected)
        }
        ImageSource::Bytes { bytes, .. } => {
            decode(format, Cursor::new(bytes), bytes.len() as u64, &choice, expected)
        }
    };
    let (width, height, mut values) = decoded.map_err(|message| import_error(path, message))?;
    if options.flip_y {
        flip_rows(&mut values, width as usize);
    }
    Ok(ImportedImage { path: path.to_path_buf(), width, height, values })
}

fn decode<R: std::io::BufRead + std::io::Seek + Send>(
    format: Format,
    reader: R,
    file_bytes: u64,
    choice: &ChannelChoice,
    expected: ExpectedSize,
) -> std::result::Result<(u32, u32, Vec<f32>), String> {
    match format {
        Format::Exr => read_exr_channel(reader, file_bytes, choice, expected),
        Format::Png => read_png_first_channel(reader, file_bytes, expected),
    }
}

/// The file at `path` opened, when it is a regular file (no FIFO or device), with its length.
fn open_regular_file(path: &Path) -> Result<(std::fs::File, u64)> {
    // An image's length is checked against its header, so it must be a regular file.
    let missing = || match std::fs::metadata(path) {
        Ok(_) => {
            import_error(path, "not a regular file (a FIFO, device or folder): images are read from files")
        }
        Err(_) => import_error(path, "no such file"),
    };
    if !path.is_file() {
        return Err(missing());
    }
    let file = std::fs::File::open(path).map_err(|e| import_error(path, format!("cannot open: {e}")))?;
    let metadata = file.metadata().map_err(|e| import_error(path, format!("cannot read: {e}")))?;
    // Checked again as opened: the path may have been replaced since.
    if !metadata.is_file() {
        return Err(missing());
    }
    Ok((file, metadata.len()))
}

fn flip_rows(values: &mut [f32], width: usize) {
    let rows = values.len() / width;
    for y in 0..rows / 2 {
        let (top, bottom) = values.split_at_mut((rows - 1 - y) * width);
        top[y * width..(y + 1) * width].swap_with_slice(&mut bottom[..width]);
    }
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

    fn seed(name: &str) -> Vec<u8> {
        let path = Path::new(env!("CARGO_MANIFEST_DIR")).join("../../fuzz/corpus/image_reader").join(name);
        std::fs::read(path).unwrap()
    }

    fn from_bytes(
        name: &str,
        channel: Option<&str>,
        depth: bool,
        expected: ExpectedSize,
    ) -> Result<ImportedImage> {
        let bytes = seed(name);
        let source = ImageSource::Bytes { name: Path::new(name), bytes: &bytes };
        let options = ReadOptions { channel: channel.map(String::from), flip_y: false };
        if depth {
            read_depth_from(source, &options, expected)
        } else {
            read_visibility_from(source, &options, expected)
        }
    }

    /// The seeds, written byte by byte to the formats' specifications, read back as written.
    #[test]
    fn every_seed_format_reads_its_values() {
        let any = ExpectedSize::ANY_CAMERA;
        let view = ExpectedSize::View { width: 4, height: 3 };
        let lit: Vec<f32> = (0..12).map(|i| if (i % 4 + i / 4) % 3 != 0 { 1.0 } else { 0.0 }).collect();
        let checker: Vec<f32> = (0..12).map(|i| ((i % 4 + i / 4) % 2) as f32).collect();
        for name in ["f32_one_channel.exr", "f16_one_channel.exr"] {
            assert_eq!(from_bytes(name, None, false, view).unwrap().values, lit, "{name}");
        }
        for name in ["grey8.png", "grey16.png"] {
            assert_eq!(from_bytes(name, None, false, view).unwrap().values, checker, "{name}");
        }
        for name in ["rgba8.png", "rgba16.png"] {
            assert_eq!(from_bytes(name, None, false, any).unwrap().values, vec![1.0; 6], "{name}");
        }
        let interlaced = from_bytes("grey8_interlaced.png", None, false, any).unwrap();
        assert_eq!(interlaced.values, (0..81).map(|i| (i % 9 % 2) as f32).collect::<Vec<_>>());
        let three = "f32_three_channels.exr";
        assert_eq!(from_bytes(three, Some("V"), false, any).unwrap().values, vec![1.0; 6]);
        assert_eq!(from_bytes(three, None, true, any).unwrap().values, vec![2.5; 6], "depth falls back to Z");
        assert!(from_bytes(three, None, false, any).unwrap_err().to_string().contains("A, V, Z: name one"));
        assert_eq!(from_bytes("f16_depth_z.exr", None, true, any).unwrap().values, vec![3.0; 4]);
    }

    #[test]
    fn png_alpha_zero_marks_background_and_any_other_alpha_keeps_the_value() {
        let read = |color: png::ColorType, depth: png::BitDepth, raw: &[u8]| {
            let mut bytes = Vec::new();
            let mut encoder = png::Encoder::new(&mut bytes, 3, 1);
            encoder.set_color(color);
            encoder.set_depth(depth);
            encoder.write_header().unwrap().write_image_data(raw).unwrap();
            let source = ImageSource::Bytes { name: Path::new("alpha.png"), bytes: &bytes };
            read_visibility_from(source, &ReadOptions::default(), ExpectedSize::ANY_CAMERA).unwrap().values
        };
        let rgba8 = [255, 0, 0, 0, 255, 9, 9, 1, 0, 0, 0, 255];
        let v = read(png::ColorType::Rgba, png::BitDepth::Eight, &rgba8);
        assert!(v[0].is_nan() && v[1] == 1.0 && v[2] == 0.0, "{v:?}");
        // 16-bit grey and alpha: only both alpha bytes 0 is transparent.
        let ga16 = [0x80, 0x00, 0x00, 0x00, 0xFF, 0xFF, 0x00, 0x01, 0x00, 0x00, 0xFF, 0xFF];
        let v = read(png::ColorType::GrayscaleAlpha, png::BitDepth::Sixteen, &ga16);
        assert!(v[0].is_nan() && v[1] == 1.0 && v[2] == 0.0, "{v:?}");
    }

    #[test]
    fn hostile_headers_are_refused_before_decoding() {
        let any = ExpectedSize::ANY_CAMERA;
        let e = from_bytes("huge_header.exr", None, false, any).unwrap_err().to_string();
        assert_eq!(
            e,
            "huge_header.exr: declares 100000×100000, expected at most 16384×16384 and 67108864 pixels (the largest \
             camera image)"
        );
        let e = from_bytes("huge_header.png", None, false, ExpectedSize::View { width: 32, height: 24 });
        assert!(e.unwrap_err().to_string().contains("declares 20000×20000, expected the camera's 32×24"));
        let e = from_bytes("truncated_offsets.exr", None, false, any).unwrap_err().to_string();
        assert!(
            e.contains("declares 64 chunks, whose offset table alone is more than the file's 293 bytes"),
            "{e}"
        );
        let e =
            from_bytes("wide.exr", None, false, ExpectedSize::View { width: 32, height: 24 }).unwrap_err();
        assert!(e.to_string().contains("declares 40×24, expected the camera's 32×24"));
    }

    /// A PNG of 64 MB of zeros, compressed at deflate's best, is read; cut to 1000 bytes, its
    /// header's size is more than those bytes can hold, and it is refused before decoding.
    #[test]
    fn a_png_shorter_than_its_header_allows_is_refused_and_the_best_compression_read() {
        let (width, height) = (16384u32, 4096u32);
        let mut bytes = Vec::new();
        let mut encoder = png::Encoder::new(&mut bytes, width, height);
        encoder.set_color(png::ColorType::Grayscale);
        encoder.set_compression(png::Compression::High);
        let raw = vec![0u8; width as usize * height as usize];
        encoder.write_header().unwrap().write_image_data(&raw).unwrap();
        let name = Path::new("zeros.png");
        let read = |bytes: &[u8]| {
            read_visibility_from(
                ImageSource::Bytes { name, bytes },
                &ReadOptions::default(),
                ExpectedSize::ANY_CAMERA,
            )
        };
        assert_eq!(read(&bytes).unwrap().values.len(), raw.len(), "{} bytes", bytes.len());
        let e = read(&bytes[..1000]).unwrap_err().to_string();
        assert!(
            e.contains("more than a file of 1000 bytes holds (deflate compresses at most 1032:1)"),
            "{e}"
        );
    }

    #[test]
    fn flipping_reverses_the_rows_only() {
        let mut v = vec![0.0, 1.0, 2.0, 3.0, 4.0, 5.0];
        flip_rows(&mut v, 2);
        assert_eq!(v, vec![4.0, 5.0, 2.0, 3.0, 0.0, 1.0]);
    }
}
