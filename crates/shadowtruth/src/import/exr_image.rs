//! One channel of an EXR file as f32, its header checked before any pixel is decoded: one flat
//! layer, the chosen channel f16 or f32 with one sample per pixel, the declared size the
//! expected one, a file long enough for what the header declares, and blocks small enough that
//! decoding holds little beside the final image.

use super::expected_size::{ExpectedSize, check_plausible_length};
use exr::meta::MetaData;
use exr::meta::header::Header;
use exr::prelude::*;
use std::io::{Read, Seek, SeekFrom};
use std::result::Result;

/// The largest uncompressed block (all channels of one chunk) decoded: 64 MiB, above a
/// 16384-wide block of 32 lines of 32 f32 channels (PIZ), far below what a forged header
/// could ask for one chunk.
const MAX_BLOCK_BYTES: usize = 64 << 20;

/// Which channel to read: `named`, or the only one, or `fallback` among several.
pub(super) struct ChannelChoice<'a> {
    pub named: Option<&'a str>,
    pub fallback: Option<&'a str>,
}

/// The chosen channel of the EXR `reader` holds (`file_bytes` long), row 0 at the top, after
/// the header checks of the module documentation. Errors are messages about the file.
pub(super) fn read_exr_channel(
    mut reader: impl Read + Seek + Send,
    file_bytes: u64,
    choice: &ChannelChoice,
    expected: ExpectedSize,
) -> Result<(u32, u32, Vec<f32>), String> {
    let unreadable = |e: exr::error::Error| format!("not a readable EXR file: {e}");
    let meta = MetaData::read_from_buffered(&mut reader, false).map_err(unreadable)?;
    let header = single_flat_layer(&meta)?;
    let (width, height) = (header.layer_size.width(), header.layer_size.height());
    expected.check(width as u64, height as u64)?;
    MetaData::validate(&meta.headers, false).map_err(unreadable)?;
    let channel = choose_channel(header, choice)?;
    check_sizes(header, file_bytes)?;
    reader.seek(SeekFrom::Start(0)).map_err(|e| format!("cannot read: {e}"))?;
    let values = decode_channel(reader, channel.name.clone(), header)?;
    Ok((width as u32, height as u32, values))
}

/// The one header of a flat (not deep) image.
fn single_flat_layer(meta: &MetaData) -> Result<&Header, String> {
    let [header] = meta.headers.as_slice() else {
        return Err(format!("holds {} layers: expected one", meta.headers.len()));
    };
    if header.deep {
        return Err("holds deep data: expected one flat sample per pixel".into());
    }
    Ok(header)
}

/// The channel `choice` picks, when it is f16 or f32 with one sample per pixel.
fn choose_channel<'h>(
    header: &'h Header,
    choice: &ChannelChoice,
) -> Result<&'h exr::meta::attribute::ChannelDescription, String> {
    let list = &header.channels.list;
    let chosen = match (choice.named, choice.fallback) {
        (Some(name), _) => list.iter().find(|c| c.name.eq(name)),
        (None, _) if list.len() == 1 => list.first(),
        (None, Some(name)) => list.iter().find(|c| c.name.eq(name)),
        (None, None) => None,
    };
    let Some(chosen) = chosen else {
        let names: Vec<String> = list.iter().map(|c| c.name.to_string()).collect();
        let wanted = choice
            .named
            .or(choice.fallback)
            .map_or("one channel".to_string(), |c| format!("channel \"{c}\""));
        return Err(format!("no {wanted} among the channels {}: name one", names.join(", ")));
    };
    if chosen.sample_type == SampleType::U32 {
        return Err(format!("channel {} holds u32 samples: expected f16 or f32", chosen.name));
    }
    if chosen.sampling != Vec2(1, 1) {
        return Err(format!("channel {} is subsampled: expected one sample per pixel", chosen.name));
    }
    Ok(chosen)
}

/// The most an EXR compression can shrink pixel data (None: no cheap bound), so that a file
/// shorter than its header's pixels over this ratio is refused. Each is the format's limit,
/// not a typical ratio: RLE codes at most 128 equal bytes in 2; deflate at most 258 bytes in 2
/// bits (1032:1), after PXR24's 4-to-3 byte f32 rounding (1376:1); PIZ's Huffman code repeats
/// a 16-bit symbol at most 255 times per 9 bits (453:1, rounded up); B44A stores 16 flat f16
/// samples in 3 bytes. DWA's lossy coefficients have no such bound.
fn max_compression_ratio(compression: Compression) -> Option<u64> {
    match compression {
        Compression::Uncompressed => Some(1),
        Compression::RLE => Some(64),
        Compression::ZIP1 | Compression::ZIP16 => Some(1032),
        Compression::PXR24 => Some(1376),
        Compression::PIZ => Some(512),
        Compression::B44 | Compression::B44A => Some(11),
        _ => None,
    }
}

/// The file can hold what the header declares (its offset table, and its pixels at the
/// compression's best ratio), and no block is larger than `MAX_BLOCK_BYTES`.
fn check_sizes(header: &Header, file_bytes: u64) -> Result<(), String> {
    let compression = header.compression;
    if matches!(compression, Compression::HTJ2K32 | Compression::HTJ2K256) {
        return Err(format!("{compression} compression is not supported"));
    }
    let offset_table_bytes = header.chunk_count as u64 * 8;
    if offset_table_bytes > file_bytes {
        return Err(format!(
            "its header declares {} chunks, whose offset table alone is more than the file's {file_bytes} bytes: \
             a truncated or forged file",
            header.chunk_count
        ));
    }
    let pixel_bytes = header.total_pixel_bytes() as u64;
    let ratio = max_compression_ratio(compression);
    check_plausible_length(pixel_bytes, ratio, file_bytes, &compression.to_string())?;
    let block_bytes = header.max_block_byte_size();
    if block_bytes > MAX_BLOCK_BYTES {
        return Err(format!(
            "one block holds {block_bytes} bytes, more than the {MAX_BLOCK_BYTES} read at once: write fewer \
             channels, smaller tiles or fewer lines a block"
        ));
    }
    Ok(())
}

/// The pixels of `channel`, converted to f32, into one buffer of the image's size; blocks are
/// decompressed in parallel only when the blocks in flight (about one per thread) stay below
/// the image itself.
fn decode_channel(
    reader: impl Read + Seek + Send,
    channel: Text,
    header: &Header,
) -> Result<Vec<f32>, String> {
    let width = header.layer_size.width();
    let in_flight = (rayon::current_num_threads() + 2) * header.max_block_byte_size();
    let parallel = in_flight <= header.layer_size.area() * std::mem::size_of::<f32>();
    let read = read()
        .no_deep_data()
        .largest_resolution_level()
        .specific_channels()
        .required(channel)
        .collect_pixels(
            |size: Vec2<usize>, _| vec![0f32; size.area()],
            move |values: &mut Vec<f32>, at: Vec2<usize>, (v,): (f32,)| values[at.y() * width + at.x()] = v,
        )
        .first_valid_layer()
        .all_attributes();
    let read = if parallel { read } else { read.non_parallel() };
    let image = read.from_buffered(reader).map_err(|e| format!("not a readable EXR file: {e}"))?;
    Ok(image.layer_data.channel_data.pixels)
}
