//! The first channel of a PNG file as f32 in [0, 1], its IHDR checked before any pixel is
//! decoded (the expected size, and a file long enough for it), decoded a row at a time into the
//! final image. A pixel whose alpha is 0 is background (NaN): a PNG has no other way to say so.

use super::expected_size::{ExpectedSize, check_plausible_length};
use png::{BitDepth, Decoder, Limits, Transformations};
use std::io::{BufRead, Seek};

/// What the PNG decoder may allocate for itself (a few rows, the chunks it keeps): 16 MiB, over
/// a hundred rows of the widest camera image in RGBA16.
const DECODER_BYTES: usize = 16 << 20;

/// The most deflate shrinks data: a 258-byte match in 2 bits.
const DEFLATE_MAX_RATIO: u64 = 1032;

/// The first channel of every pixel of the PNG `reader` holds (`file_bytes` long), scaled so that
/// the largest code is 1, row 0 at the top; NaN where alpha is 0. Errors are messages about the
/// file.
pub(super) fn read_png_first_channel(
    reader: impl BufRead + Seek,
    file_bytes: u64,
    expected: ExpectedSize,
) -> Result<(u32, u32, Vec<f32>), String> {
    let unreadable = |e: png::DecodingError| format!("not a readable PNG file: {e}");
    let mut decoder = Decoder::new_with_limits(reader, Limits { bytes: DECODER_BYTES });
    let info = decoder.read_header_info().map_err(unreadable)?;
    let (width, height) = (info.width, info.height);
    expected.check(width as u64, height as u64)?;
    let raw_bytes = height as u64 * info.raw_row_length() as u64;
    check_plausible_length(raw_bytes, Some(DEFLATE_MAX_RATIO), file_bytes, "deflate")?;
    // Palettes become RGB(A) and grey below 8 bits 8 bits, scaled to the full range.
    decoder.set_transformations(Transformations::EXPAND);
    decoder.set_ignore_text_chunk(true);
    decoder.set_ignore_iccp_chunk(true);
    let mut reader = decoder.read_info().map_err(unreadable)?;
    let (color, depth) = reader.output_color_type();
    let first = FirstChannel {
        bytes_per_pixel: color.samples() * depth_bytes(depth),
        sixteen: depth == BitDepth::Sixteen,
        alpha_at: matches!(color, png::ColorType::Rgba | png::ColorType::GrayscaleAlpha)
            .then(|| (color.samples() - 1) * depth_bytes(depth)),
    };
    let mut values = Vec::with_capacity(width as usize * height as usize);
    if reader.info().interlaced {
        // Adam7 rows arrive pass by pass: the whole frame, then its rows in order.
        let size = reader.output_buffer_size().ok_or("an image too large to address")?;
        let mut frame = vec![0u8; size];
        let line = reader.next_frame(&mut frame).map_err(unreadable)?.line_size;
        frame.chunks_exact(line).for_each(|row| first.push_row(row, &mut values));
    } else {
        while let Some(row) = reader.next_row().map_err(unreadable)? {
            first.push_row(row.data(), &mut values);
        }
    }
    if values.len() != width as usize * height as usize {
        return Err(format!("holds {} pixels, but its header declares {width}×{height}", values.len()));
    }
    Ok((width, height, values))
}

fn depth_bytes(depth: BitDepth) -> usize {
    if depth == BitDepth::Sixteen { 2 } else { 1 }
}

/// Takes the first sample of each pixel of a decoded row.
struct FirstChannel {
    bytes_per_pixel: usize,
    sixteen: bool,
    /// The byte offset of the alpha sample in a pixel, when the image has one.
    alpha_at: Option<usize>,
}

impl FirstChannel {
    fn push_row(&self, row: &[u8], values: &mut Vec<f32>) {
        let sample = |px: &[u8], at: usize| {
            if self.sixteen {
                u16::from_be_bytes([px[at], px[at + 1]]) as f32 / 65535.0
            } else {
                px[at] as f32 / 255.0
            }
        };
        let pixels = row.chunks_exact(self.bytes_per_pixel);
        match self.alpha_at {
            Some(alpha) => values.extend(pixels.map(|px| {
                let transparent = px[alpha] == 0 && (!self.sixteen || px[alpha + 1] == 0);
                if transparent { f32::NAN } else { sample(px, 0) }
            })),
            None => values.extend(pixels.map(|px| sample(px, 0))),
        }
    }
}
