//! Figures (PNG, RGB8, row 0 at the top, camera-sized): a shaded base image of the scene, the
//! reference and a technique's output drawn over it, an error map with false shadow and false lit
//! in two colour-blind-safe colours, enlarged crops, and captioned grids in the style of the
//! papers' figures.
//!
//! The base image depends only on the G-buffer and the light: build it once per (scene, camera,
//! light) and pass it to every run's figures. Images are encoded with fast PNG compression so that
//! figures stay a small fraction of a batch's time.
//!
//! The error map keeps the image area exact: every pixel coloured exactly [`FALSE_SHADOW`] or
//! [`FALSE_LIT`] is a false-shadow or false-lit pixel of the run, and every such pixel is coloured.
//! Its legend (swatches in the same two colours, with the counts) is drawn on a strip added *below*
//! the camera image, never over it.

use super::font;
use super::record::RunRecord;
use crate::scene::{Light, LightKind};
use crate::trace::{GBuffer, HardReference, PixelClass};
use glam::Vec3;
use image::ImageEncoder;
use image::codecs::png::{CompressionType, FilterType, PngEncoder};
use rayon::prelude::*;
use sha2::{Digest, Sha256};
use std::path::Path;

/// False shadow (lit in truth, shadowed by the technique): Okabe–Ito vermillion.
pub const FALSE_SHADOW: [u8; 3] = [0xD5, 0x5E, 0x00];
/// False lit (shadowed in truth, lit by the technique): Okabe–Ito blue.
pub const FALSE_LIT: [u8; 3] = [0x00, 0x72, 0xB2];
/// Background pixels of the base image (no hit).
pub const BACKGROUND_GREY: u8 = 46;
/// Visibility 0 multiplies the base by this; visibility 1 leaves it unchanged.
pub const SHADOW_FACTOR: f32 = 0.35;
/// The error map's base: the shaded image desaturated and multiplied by this…
pub const ERROR_DIM: f32 = 0.6;
/// …and, where the reference is shadowed, by this as well (so that the true shadows show).
pub const ERROR_REFERENCE_SHADOW: f32 = 0.6;
/// Background of the error map's legend strip.
pub const LEGEND_BACKGROUND: [u8; 3] = [24, 24, 24];
/// Text of the error map's legend strip.
pub const LEGEND_TEXT: [u8; 3] = [235, 235, 235];
/// Frame around enlarged crops.
pub const ZOOM_FRAME: [u8; 3] = [255, 255, 255];
/// Space between grid cells, in pixels.
pub const GRID_GAP: u32 = 4;
/// Background of grids (the papers' white page).
pub const GRID_BACKGROUND: [u8; 3] = [255, 255, 255];
/// Caption text of grids.
pub const GRID_TEXT: [u8; 3] = [20, 20, 20];

fn grey(level: f32) -> u8 {
    (level.clamp(0.0, 1.0) * 255.0 + 0.5) as u8
}

fn scale_u8(v: u8, f: f32) -> u8 {
    (v as f32 * f + 0.5).min(255.0) as u8
}

/// `scale_u8(·, f)` for every byte.
fn lut(f: f32) -> [u8; 256] {
    std::array::from_fn(|v| scale_u8(v as u8, f))
}

/// Rec. 601 luma in integers, exact for greys.
fn luma(p: &[u8]) -> u8 {
    if p[0] == p[1] && p[1] == p[2] {
        return p[0];
    }
    ((77 * p[0] as u32 + 150 * p[1] as u32 + 29 * p[2] as u32 + 128) >> 8) as u8
}

/// A grey, shadow-free rendering of the G-buffer (RGB8, camera-sized): a Lambert term for the
/// light plus a sky term `½ + ½·N·y` for shape, on a dark neutral background. Evaluated pixels are
/// light (grey 102–255), pixels outside a spot light's cone mid grey, pixels facing away from the
/// light dark (they are in attached shadow whatever a technique says). Every pixel is grey
/// (R = G = B).
pub fn shaded_base(gbuffer: &GBuffer, light: &Light) -> Vec<u8> {
    let w = gbuffer.width as usize;
    let mut out = vec![0u8; gbuffer.pixel_count() * 3];
    out.par_chunks_mut(w * 3).enumerate().for_each(|(y, row)| {
        for x in 0..w {
            let i = y * w + x;
            let n = gbuffer.normal[i];
            let sky = 0.5 + 0.5 * n.y;
            let level = match gbuffer.class[i] {
                PixelClass::Background => BACKGROUND_GREY as f32 / 255.0,
                PixelClass::FacingAway => 0.22 + 0.18 * sky,
                cls => {
                    let l = match &light.kind {
                        LightKind::Directional { direction } => -direction.normalize(),
                        LightKind::Spot { position, .. } => {
                            (*position - gbuffer.position[i]).normalize_or(Vec3::Y)
                        }
                    };
                    let lambert = n.dot(l).max(0.0);
                    if cls == PixelClass::Evaluated {
                        0.40 + 0.45 * lambert + 0.15 * sky
                    } else {
                        0.30 + 0.15 * lambert + 0.15 * sky
                    }
                }
            };
            let g = grey(level);
            row[x * 3..x * 3 + 3].copy_from_slice(&[g, g, g]);
        }
    });
    out
}

/// The range of `gbuffer.evaluated` indices that fall in row `y`.
fn evaluated_in_row(gbuffer: &GBuffer, y: usize) -> std::ops::Range<usize> {
    let w = gbuffer.width as u64;
    let (lo, hi) = (y as u64 * w, (y as u64 + 1) * w);
    let start = gbuffer.evaluated.partition_point(|&i| (i as u64) < lo);
    let end = start + gbuffer.evaluated[start..].partition_point(|&i| (i as u64) < hi);
    start..end
}

/// The reference as one visibility per evaluated pixel (1 lit, 0 shadowed), for
/// [`visibility_image`].
pub fn reference_visibility(gbuffer: &GBuffer, reference: &HardReference) -> Vec<f32> {
    gbuffer.evaluated.iter().map(|&i| reference.lit[i as usize] as f32).collect()
}

/// `base` darkened by visibility: each evaluated pixel is multiplied by
/// `SHADOW_FACTOR + (1 − SHADOW_FACTOR)·v` (×0.35 shadowed, ×1 lit, linear in between); the other
/// pixels are `base` unchanged. `values` holds one visibility per evaluated pixel, in
/// `gbuffer.evaluated` order.
pub fn visibility_image(gbuffer: &GBuffer, base: &[u8], values: &[f32]) -> Vec<u8> {
    assert_eq!(values.len(), gbuffer.evaluated.len(), "one visibility per evaluated pixel");
    assert_eq!(base.len(), gbuffer.pixel_count() * 3, "base is an RGB8 image of the camera");
    let w = gbuffer.width as usize;
    let shadowed = lut(SHADOW_FACTOR);
    let mut out = base.to_vec();
    out.par_chunks_mut(w * 3).enumerate().for_each(|(y, row)| {
        for k in evaluated_in_row(gbuffer, y) {
            let x = gbuffer.evaluated[k] as usize - y * w;
            let v = values[k];
            let px = &mut row[x * 3..x * 3 + 3];
            if v >= 1.0 {
                continue;
            } else if v <= 0.0 {
                px.iter_mut().for_each(|c| *c = shadowed[*c as usize]);
            } else {
                let f = SHADOW_FACTOR + (1.0 - SHADOW_FACTOR) * v;
                px.iter_mut().for_each(|c| *c = scale_u8(*c, f));
            }
        }
    });
    out
}

/// Height of the legend strip below an error map of the given width.
pub fn legend_strip_height(width: u32) -> u32 {
    let s = legend_scale(width);
    font::text_height(s) + 8 * s
}

fn legend_scale(width: u32) -> u32 {
    (width / 512).clamp(1, 4)
}

/// The error map of a run: `base` desaturated and dimmed (×[`ERROR_DIM`], and
/// ×[`ERROR_REFERENCE_SHADOW`] more where the reference is shadowed, so the true shadows show),
/// false-shadow pixels exactly [`FALSE_SHADOW`], false-lit pixels exactly [`FALSE_LIT`] (the
/// thresholds of `metrics::score_hard`), and a legend strip of [`legend_strip_height`] rows added
/// below the image. Returns (pixels, width, height); the image area is the top
/// `gbuffer.height` rows.
pub fn error_map(
    gbuffer: &GBuffer,
    reference: &HardReference,
    visibility: &[f32],
    base: &[u8],
) -> (Vec<u8>, u32, u32) {
    assert_eq!(visibility.len(), gbuffer.evaluated.len(), "one visibility per evaluated pixel");
    assert_eq!(base.len(), gbuffer.pixel_count() * 3, "base is an RGB8 image of the camera");
    let (w, h) = (gbuffer.width as usize, gbuffer.height as usize);
    let strip = legend_strip_height(gbuffer.width) as usize;
    let (dim, dim_shadowed) = (lut(ERROR_DIM), lut(ERROR_DIM * ERROR_REFERENCE_SHADOW));
    let mut out = vec![0u8; w * (h + strip) * 3];
    let (image, legend) = out.split_at_mut(w * h * 3);
    let (false_shadow, false_lit) = image
        .par_chunks_mut(w * 3)
        .zip(base.par_chunks(w * 3))
        .enumerate()
        .map(|(y, (row, base_row))| {
            for (o, b) in row.chunks_exact_mut(3).zip(base_row.chunks_exact(3)) {
                let g = dim[luma(b) as usize];
                o.copy_from_slice(&[g, g, g]);
            }
            let (mut fs, mut fl) = (0u64, 0u64);
            for k in evaluated_in_row(gbuffer, y) {
                let i = gbuffer.evaluated[k] as usize;
                let x = i - y * w;
                let px = &mut row[x * 3..x * 3 + 3];
                let r_lit = reference.lit[i] != 0;
                let v_lit = visibility[k] >= 0.5;
                match (r_lit, v_lit) {
                    (true, false) => {
                        px.copy_from_slice(&FALSE_SHADOW);
                        fs += 1;
                    }
                    (false, true) => {
                        px.copy_from_slice(&FALSE_LIT);
                        fl += 1;
                    }
                    (false, false) => {
                        let g = dim_shadowed[luma(&base_row[x * 3..x * 3 + 3]) as usize];
                        px.copy_from_slice(&[g, g, g]);
                    }
                    (true, true) => {}
                }
            }
            (fs, fl)
        })
        .reduce(|| (0, 0), |a, b| (a.0 + b.0, a.1 + b.1));
    let evaluated = gbuffer.evaluated.len();
    draw_legend(legend, gbuffer.width, strip as u32, false_shadow, false_lit, evaluated);
    (out, gbuffer.width, (h + strip) as u32)
}

fn draw_legend(strip: &mut [u8], width: u32, height: u32, fs: u64, fl: u64, evaluated: usize) {
    for px in strip.chunks_exact_mut(3) {
        px.copy_from_slice(&LEGEND_BACKGROUND);
    }
    let s = legend_scale(width);
    let pct = |n: u64| 100.0 * n as f64 / evaluated.max(1) as f64;
    let entries = [
        (FALSE_SHADOW, format!("false shadow {fs} ({:.2}%)", pct(fs))),
        (FALSE_LIT, format!("false lit {fl} ({:.2}%)", pct(fl))),
    ];
    let side = font::text_height(s);
    let y = (4 * s) as i64;
    let mut x = (4 * s) as i64;
    for (color, text) in entries {
        fill_rect(strip, width, height, x, y, side, side, color);
        x += (side + 3 * s) as i64;
        font::draw_text(strip, width, height, x, y, &text, s, LEGEND_TEXT);
        x += (font::text_width(&text, s) + 12 * s) as i64;
    }
}

#[allow(clippy::too_many_arguments)]
fn fill_rect(rgb: &mut [u8], width: u32, height: u32, x: i64, y: i64, w: u32, h: u32, color: [u8; 3]) {
    let (iw, ih) = (width as i64, height as i64);
    for py in y.max(0)..(y + h as i64).min(ih) {
        for px in x.max(0)..(x + w as i64).min(iw) {
            let o = ((py * iw + px) * 3) as usize;
            rgb[o..o + 3].copy_from_slice(&color);
        }
    }
}

/// Draws the 1-pixel outline of `rect` = (x, y, w, h) on an RGB8 image (clipped), to mark where
/// a [`zoom`] panel comes from.
pub fn outline_rect(rgb: &mut [u8], width: u32, height: u32, rect: (u32, u32, u32, u32), color: [u8; 3]) {
    let (x, y, w, h) = (rect.0 as i64, rect.1 as i64, rect.2, rect.3);
    if w == 0 || h == 0 {
        return;
    }
    fill_rect(rgb, width, height, x, y, w, 1, color);
    fill_rect(rgb, width, height, x, y + h as i64 - 1, w, 1, color);
    fill_rect(rgb, width, height, x, y, 1, h, color);
    fill_rect(rgb, width, height, x + w as i64 - 1, y, 1, h, color);
}

/// An enlarged panel: `rect` = (x, y, w, h) of an RGB8 image (clipped to it), each pixel repeated
/// `scale`×`scale` times (nearest neighbour), inside a 1-pixel [`ZOOM_FRAME`]. Returns (pixels,
/// width, height) with width = 2 + w·scale and height = 2 + h·scale for the clipped w, h.
pub fn zoom(
    rgb: &[u8],
    width: u32,
    height: u32,
    rect: (u32, u32, u32, u32),
    scale: u32,
) -> (Vec<u8>, u32, u32) {
    assert_eq!(rgb.len(), (width * height * 3) as usize, "an RGB8 image of width × height");
    let scale = scale.max(1) as usize;
    let x0 = rect.0.min(width) as usize;
    let y0 = rect.1.min(height) as usize;
    let cw = (rect.2 as usize).min(width as usize - x0);
    let ch = (rect.3 as usize).min(height as usize - y0);
    let (ow, oh) = (cw * scale + 2, ch * scale + 2);
    let mut out = vec![0u8; ow * oh * 3];
    for px in out.chunks_exact_mut(3) {
        px.copy_from_slice(&ZOOM_FRAME);
    }
    let src_w = width as usize;
    for (oy, row) in out.chunks_exact_mut(ow * 3).enumerate().skip(1).take(ch * scale) {
        let sy = y0 + (oy - 1) / scale;
        let src = &rgb[(sy * src_w + x0) * 3..(sy * src_w + x0 + cw) * 3];
        let mut o = 3;
        for p in src.chunks_exact(3) {
            for _ in 0..scale {
                row[o..o + 3].copy_from_slice(p);
                o += 3;
            }
        }
    }
    (out, ow as u32, oh as u32)
}

/// One cell of a [`grid`]: an RGB8 image and the caption printed below it.
#[derive(Clone, Debug)]
pub struct GridCell<'a> {
    pub image: &'a [u8],
    pub width: u32,
    pub height: u32,
    pub caption: String,
}

/// How a grid is laid out: every cell occupies `cell_width` × (`cell_height` + `caption_height`)
/// pixels, cells are [`GRID_GAP`] apart and from the border.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct GridLayout {
    /// Cells are shrunk by this integer factor (box filter).
    pub downscale: u32,
    pub cell_width: u32,
    pub cell_height: u32,
    pub caption_scale: u32,
    pub caption_lines: u32,
    pub caption_height: u32,
    pub columns: u32,
    pub rows: u32,
    pub width: u32,
    pub height: u32,
}

impl GridLayout {
    /// The layout of `cells` in `columns` columns, shrunk by the smallest integer factor that
    /// makes the widest cell at most `max_cell_width` pixels wide.
    pub fn new(cells: &[GridCell], columns: u32, max_cell_width: u32) -> GridLayout {
        let columns = columns.clamp(1, cells.len().max(1) as u32);
        let rows = cells.len().div_ceil(columns as usize) as u32;
        let widest = cells.iter().map(|c| c.width).max().unwrap_or(0);
        let downscale = widest.div_ceil(max_cell_width.max(1)).max(1);
        let cell_width = cells.iter().map(|c| c.width / downscale).max().unwrap_or(0);
        let cell_height = cells.iter().map(|c| c.height / downscale).max().unwrap_or(0);
        let caption_scale = (cell_width / 256).clamp(1, 3);
        let per_line = font::chars_per_line(cell_width, caption_scale);
        let caption_lines =
            cells.iter().map(|c| font::wrap(&c.caption, per_line).len() as u32).max().unwrap_or(1).max(1);
        let caption_height = caption_block_height(caption_lines, caption_scale);
        let width = columns * cell_width + (columns + 1) * GRID_GAP;
        let height = rows * (cell_height + caption_height) + (rows + 1) * GRID_GAP;
        GridLayout {
            downscale,
            cell_width,
            cell_height,
            caption_scale,
            caption_lines,
            caption_height,
            columns,
            rows,
            width,
            height,
        }
    }

    /// Top-left corner of cell `index`'s image; its caption starts `cell_height` rows lower.
    pub fn cell_origin(&self, index: usize) -> (u32, u32) {
        let (c, r) = (index as u32 % self.columns, index as u32 / self.columns);
        (
            GRID_GAP + c * (self.cell_width + GRID_GAP),
            GRID_GAP + r * (self.cell_height + self.caption_height + GRID_GAP),
        )
    }
}

/// Height of a caption block of `lines` lines at font scale `scale`.
pub fn caption_block_height(lines: u32, scale: u32) -> u32 {
    scale * (3 + font::LINE_HEIGHT * lines)
}

/// Shrinks an RGB8 image by an integer factor, each output pixel the mean of a `f`×`f` block
/// (the incomplete blocks at the right and bottom edges are dropped).
pub fn box_downscale(rgb: &[u8], width: u32, height: u32, f: u32) -> (Vec<u8>, u32, u32) {
    let f = f.max(1) as usize;
    let (w, h) = (width as usize, height as usize);
    let (ow, oh) = (w / f, h / f);
    if f == 1 {
        return (rgb[..w * h * 3].to_vec(), width, height);
    }
    let mut out = vec![0u8; ow * oh * 3];
    let area = (f * f) as u32;
    out.par_chunks_mut((ow * 3).max(1)).enumerate().for_each(|(oy, row)| {
        for ox in 0..ow {
            let mut sum = [0u32; 3];
            for sy in oy * f..oy * f + f {
                let line = &rgb[(sy * w + ox * f) * 3..(sy * w + ox * f + f) * 3];
                for p in line.chunks_exact(3) {
                    sum[0] += p[0] as u32;
                    sum[1] += p[1] as u32;
                    sum[2] += p[2] as u32;
                }
            }
            for c in 0..3 {
                row[ox * 3 + c] = ((sum[c] + area / 2) / area) as u8;
            }
        }
    });
    (out, ow as u32, oh as u32)
}

/// A captioned grid (techniques × settings, in the style of the papers' figures): cells in
/// row-major order, `columns` per row, shrunk by an integer box filter so that none is wider than
/// `max_cell_width`, each with its caption (wrapped, centred) below it, [`GRID_GAP`] pixels apart
/// on a white page. Returns (pixels, width, height); see [`GridLayout`] for the geometry.
pub fn grid(cells: &[GridCell], columns: u32, max_cell_width: u32) -> (Vec<u8>, u32, u32) {
    let layout = GridLayout::new(cells, columns, max_cell_width);
    let (gw, gh) = (layout.width, layout.height);
    let mut out = vec![0u8; (gw * gh * 3) as usize];
    for px in out.chunks_exact_mut(3) {
        px.copy_from_slice(&GRID_BACKGROUND);
    }
    let shrunk: Vec<(Vec<u8>, u32, u32)> = cells
        .par_iter()
        .map(|c| {
            assert_eq!(c.image.len(), (c.width * c.height * 3) as usize, "cell {:?} size", c.caption);
            box_downscale(c.image, c.width, c.height, layout.downscale)
        })
        .collect();
    let s = layout.caption_scale;
    let per_line = font::chars_per_line(layout.cell_width, s);
    for (index, (cell, (pixels, w, h))) in cells.iter().zip(&shrunk).enumerate() {
        let (x0, y0) = layout.cell_origin(index);
        for y in 0..*h {
            let dst = (((y0 + y) * gw + x0) * 3) as usize;
            let src = (y * w * 3) as usize;
            out[dst..dst + (*w * 3) as usize].copy_from_slice(&pixels[src..src + (*w * 3) as usize]);
        }
        let text_top = y0 + layout.cell_height + 2 * s;
        for (line_no, line) in font::wrap(&cell.caption, per_line).iter().enumerate() {
            let tw = font::text_width(line, s);
            let x = x0 as i64 + (layout.cell_width.saturating_sub(tw) / 2) as i64;
            let y = text_top as i64 + (line_no as u32 * font::LINE_HEIGHT * s) as i64;
            font::draw_text(&mut out, gw, gh, x, y, line, s, GRID_TEXT);
        }
    }
    (out, gw, gh)
}

/// PNG bytes of an RGB8 image with fast compression: zlib level 1 with the `Sub` filter, and a
/// one-channel (grey) PNG when every pixel is grey, as the base, reference and technique images
/// are; decoders return the same RGB values. On the bundled scenes at 1024×768 level 1 + `Sub`
/// encodes as fast as `CompressionType::Fast` (fdeflate, whose files stay near 1 MB per figure)
/// and writes files 5–10 times smaller; the grey encoding is 2–4 times faster and smaller again.
pub fn encode_png_fast(width: u32, height: u32, rgb: &[u8]) -> std::io::Result<Vec<u8>> {
    assert_eq!(rgb.len(), width as usize * height as usize * 3, "an RGB8 image of width × height");
    let grey = rgb.chunks_exact(3).all(|p| p[0] == p[1] && p[1] == p[2]);
    let mut out = Vec::with_capacity(rgb.len() / 16);
    if grey {
        let levels: Vec<u8> = rgb.chunks_exact(3).map(|p| p[0]).collect();
        PngEncoder::new_with_quality(&mut out, CompressionType::Level(1), FilterType::Sub)
            .write_image(&levels, width, height, image::ExtendedColorType::L8)
            .map_err(std::io::Error::other)?;
    } else {
        // Error maps hold a few hundred colours at most: one byte per pixel deflates about three
        // times faster than three.
        let mut encoder = png::Encoder::new(&mut out, width, height);
        encoder.set_depth(png::BitDepth::Eight);
        encoder.set_compression(png::Compression::Fast);
        encoder.set_filter(png::Filter::Sub);
        let data = match palette_of(rgb) {
            Some((palette, indices)) => {
                encoder.set_color(png::ColorType::Indexed);
                encoder.set_palette(palette);
                indices
            }
            // Larger palettes (grids) stay RGB.
            None => {
                encoder.set_color(png::ColorType::Rgb);
                rgb.to_vec()
            }
        };
        let mut writer = encoder.write_header().map_err(std::io::Error::other)?;
        writer.write_image_data(&data).map_err(std::io::Error::other)?;
        writer.finish().map_err(std::io::Error::other)?;
    }
    Ok(out)
}

/// The palette (RGB triples) and per-pixel indices of an image with at most 256 colours. Greys
/// are looked up directly by level, the few other colours by a short scan.
fn palette_of(rgb: &[u8]) -> Option<(Vec<u8>, Vec<u8>)> {
    let mut grey_slot = [u16::MAX; 256];
    let mut others: Vec<([u8; 3], u8)> = Vec::new();
    let mut palette: Vec<u8> = Vec::new();
    let mut indices = Vec::with_capacity(rgb.len() / 3);
    for p in rgb.chunks_exact(3) {
        let c = [p[0], p[1], p[2]];
        let known = if c[0] == c[1] && c[1] == c[2] {
            (grey_slot[c[0] as usize] != u16::MAX).then(|| grey_slot[c[0] as usize] as u8)
        } else {
            others.iter().find(|(o, _)| *o == c).map(|&(_, i)| i)
        };
        let index = match known {
            Some(i) => i,
            None => {
                let next = palette.len() / 3;
                if next == 256 {
                    return None;
                }
                palette.extend_from_slice(&c);
                if c[0] == c[1] && c[1] == c[2] {
                    grey_slot[c[0] as usize] = next as u16;
                } else {
                    others.push((c, next as u8));
                }
                next as u8
            }
        };
        indices.push(index);
    }
    Some((palette, indices))
}

/// Writes an RGB8 image as a PNG (fast compression) through a temporary file renamed over
/// `path`, so that a killed run never leaves a half-written figure. Unlike
/// `atomic_file::write_atomic` it does not fsync: figures are derived data that a rerun
/// regenerates, and two fsyncs per run cost as much as building and encoding both figures
/// (10–15 ms on ext4).
pub fn write_png(path: &Path, width: u32, height: u32, rgb: &[u8]) -> std::io::Result<()> {
    write_renamed(path, &encode_png_fast(width, height, rgb)?)
}

fn write_renamed(path: &Path, bytes: &[u8]) -> std::io::Result<()> {
    let dir = path.parent().filter(|d| !d.as_os_str().is_empty()).unwrap_or(Path::new("."));
    std::fs::create_dir_all(dir)?;
    let name = path.file_name().map(|n| n.to_string_lossy().into_owned()).unwrap_or_default();
    let tmp = dir.join(format!(".{name}.tmp{}", std::process::id()));
    let result = std::fs::write(&tmp, bytes).and_then(|()| std::fs::rename(&tmp, path));
    if result.is_err() {
        let _ = std::fs::remove_file(&tmp);
    }
    result
}

/// The files of one run, relative to the directory they were written to (file names).
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct RunFigures {
    /// `<stem>.technique.png`: the technique's visibility over the base image.
    pub technique: String,
    /// `<stem>.error.png`: the error map with its legend strip.
    pub error: String,
    /// The error map as drawn (RGB8, legend strip included), for grids and zooms.
    pub error_image: Vec<u8>,
    pub error_size: (u32, u32),
}

/// Writes `dir/<stem>.technique.png` and `dir/<stem>.error.png` for one run. `base` is the
/// view's [`shaded_base`], built once and shared by its runs.
pub fn write_run_figures(
    dir: &Path,
    stem: &str,
    gbuffer: &GBuffer,
    reference: &HardReference,
    visibility: &[f32],
    base: &[u8],
) -> std::io::Result<RunFigures> {
    let (technique, error) = (format!("{stem}.technique.png"), format!("{stem}.error.png"));
    let (written, (error_image, w, h)) = rayon::join(
        || {
            let img = visibility_image(gbuffer, base, visibility);
            write_png(&dir.join(&technique), gbuffer.width, gbuffer.height, &img)
        },
        || error_map(gbuffer, reference, visibility, base),
    );
    written?;
    write_png(&dir.join(&error), w, h, &error_image)?;
    Ok(RunFigures { technique, error, error_image, error_size: (w, h) })
}

/// Writes `dir/<stem>.reference.png`, the reference's shadows over the base image, and returns
/// its file name. `stem` is usually [`view_stem`].
pub fn write_reference_figure(
    dir: &Path,
    stem: &str,
    gbuffer: &GBuffer,
    reference: &HardReference,
    base: &[u8],
) -> std::io::Result<String> {
    let name = format!("{stem}.reference.png");
    let img = visibility_image(gbuffer, base, &reference_visibility(gbuffer, reference));
    write_png(&dir.join(&name), gbuffer.width, gbuffer.height, &img)?;
    Ok(name)
}

/// Writes a [`grid`] of `cells` to `path`.
pub fn write_grid(path: &Path, cells: &[GridCell], columns: u32, max_cell_width: u32) -> std::io::Result<()> {
    let (img, w, h) = grid(cells, columns, max_cell_width);
    write_png(path, w, h, &img)
}

/// A file-name-safe rendering of `s`: ASCII letters, digits, `_`, `-` and `.` are kept, `=`
/// becomes `-`, `)` is dropped, anything else (`(`, `,`, `/`, spaces, non-ASCII…) becomes `_`;
/// a leading `.` or `-` becomes `_` and an empty name `_`.
fn file_safe(s: &str) -> String {
    let mut out: String = s
        .chars()
        .filter(|&c| c != ')')
        .map(|c| match c {
            c if c.is_ascii_alphanumeric() || c == '_' || c == '-' || c == '.' => c,
            '=' => '-',
            _ => '_',
        })
        .collect();
    if out.starts_with(['.', '-']) {
        out.replace_range(0..1, "_");
    }
    if out.is_empty() {
        out.push('_');
    }
    out
}

const MAX_READABLE: usize = 160;

fn view_readable(scene: &str, camera: &str, light: &str) -> String {
    format!("{}.{}.{}", file_safe(scene), file_safe(camera), file_safe(light))
}

/// The first 8 hex digits of the SHA-256 of `parts` (each prefixed with its length, so that
/// part boundaries count).
fn short_hash(parts: &[&str]) -> String {
    let mut hasher = Sha256::new();
    for part in parts {
        hasher.update((part.len() as u64).to_le_bytes());
        hasher.update(part.as_bytes());
    }
    hasher.finalize()[..4].iter().map(|b| format!("{b:02x}")).collect()
}

/// A readable, file-name-safe and unique stem for a view's files (its reference figure):
/// `<scene>.<camera>.<light>.<hash>`, each name passed through a character filter (only ASCII
/// letters, digits, `_`, `-`, `.`) and `<hash>` the first 8 hex digits of the SHA-256 of the
/// exact names, so that views whose filtered names coincide still get distinct stems.
pub fn view_stem(scene: &str, camera: &str, light: &str) -> String {
    let mut readable = view_readable(scene, camera, light);
    readable.truncate(MAX_READABLE);
    format!("{readable}.{}", short_hash(&[scene, camera, light]))
}

/// A readable, file-name-safe and unique stem for a run's files:
/// `<scene>.<camera>.<light>.<label>.r<resolution>.<depth format>.<hash>`, each part passed
/// through the filter of [`view_stem`], the readable part capped at 160 characters, and `<hash>`
/// the first 8 hex digits of the SHA-256 of the exact key (scene, camera, light, technique,
/// label, parameters, resolution, depth format).
pub fn run_stem(record: &RunRecord) -> String {
    let mut readable = format!(
        "{}.{}.r{}.{}",
        view_readable(&record.scene, &record.camera, &record.light),
        file_safe(&record.label),
        record.resolution,
        file_safe(&record.depth_format)
    );
    readable.truncate(MAX_READABLE);
    let hash = short_hash(&[
        &record.scene,
        &record.camera,
        &record.light,
        &record.technique,
        &record.label,
        &serde_json::Value::Object(record.parameters.clone()).to_string(),
        &record.resolution.to_string(),
        &record.depth_format,
    ]);
    format!("{readable}.{hash}")
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn file_safe_keeps_names_readable() {
        assert_eq!(file_safe("constant(bias_depth=0.001)"), "constant_bias_depth-0.001");
        assert_eq!(
            file_safe("slope_scaled(factor=1.5,units=2,cull=none)"),
            "slope_scaled_factor-1.5_units-2_cull-none"
        );
        assert_eq!(file_safe("../a b/c"), "_._a_b_c");
        assert_eq!(file_safe(""), "_");
        assert_eq!(file_safe("-x"), "_x");
    }

    #[test]
    fn box_downscale_averages_blocks() {
        // 4×2 image, factor 2: two output pixels, the means of two 2×2 blocks.
        let px = |v: u8| [v, v / 2, 255 - v];
        let rows = [[0u8, 10, 100, 200], [20, 30, 50, 50]];
        let rgb: Vec<u8> = rows.iter().flat_map(|r| r.iter().flat_map(|&v| px(v))).collect();
        let (out, w, h) = box_downscale(&rgb, 4, 2, 2);
        assert_eq!((w, h), (2, 1));
        assert_eq!(out[0], 15);
        assert_eq!(out[3], 100);
        assert_eq!(out[5], ((255 * 4 - 400 + 2) / 4) as u8);
    }

    #[test]
    fn zoom_clips_to_the_image() {
        let rgb = vec![7u8; 4 * 4 * 3];
        let (out, w, h) = zoom(&rgb, 4, 4, (2, 3, 10, 10), 3);
        assert_eq!((w, h), (2 + 2 * 3, 2 + 3));
        assert_eq!(out.len(), (w * h * 3) as usize);
        assert_eq!(&out[((w + 1) * 3) as usize..((w + 1) * 3 + 3) as usize], &[7, 7, 7]);
    }

    #[test]
    fn legend_strip_scales_with_width() {
        assert!(legend_strip_height(1024) > legend_strip_height(256));
        assert_eq!(legend_strip_height(256), legend_strip_height(512));
    }
}
