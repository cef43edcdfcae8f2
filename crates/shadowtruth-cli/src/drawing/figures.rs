//! Figures (PNG, row 0 at the top, camera-sized): a shaded base image of the scene, the reference
//! and a technique's output drawn over it, an error map with false shadow and false lit in two
//! colour-blind-safe colours, enlarged crops, and captioned grids in the style of the papers'
//! figures. All are [`IndexedImage`]s over one palette of greys, the two error colours and the uncertain colour.
//!
//! What depends only on the view (the base image, the error map's background): build a
//! [`ViewCanvas`] once per (scene, camera, light) and pass it to every run's figures.
//!
//! The error map keeps the image area exact: every pixel coloured exactly [`FALSE_SHADOW`](super::palette::FALSE_SHADOW) or
//! [`FALSE_LIT`](super::palette::FALSE_LIT) is a false-shadow or false-lit pixel of the run, and every such pixel is coloured.
//! Its legend (swatches in the same two colours, with the counts) is drawn on a strip added *below*
//! the camera image, never over it. The pixels the reference cannot decide beyond doubt
//! (`PixelClass::Uncertain`, scored neither way) are drawn exactly [`UNCERTAIN`](super::palette::UNCERTAIN),
//! with their count in the legend.

pub use super::indexed_image::IndexedImage;
pub use super::palette::{FALSE_LIT_INDEX, FALSE_SHADOW_INDEX, GREY_MAX, UNCERTAIN_INDEX, grey, is_grey};
use super::text;
use glam::Vec3;
use rayon::prelude::*;
use shadowtruth::file_name;
use shadowtruth::record::RunRecord;
use shadowtruth::scene::{Light, LightKind, ViewKey};
use shadowtruth::trace::{GBuffer, HardReference, PixelClass};
use std::path::Path;

/// Background pixels of the base image (no hit).
pub const BACKGROUND_GREY: u8 = 46;
/// Visibility 0 multiplies the base by this; visibility 1 leaves it unchanged.
pub const SHADOW_FACTOR: f32 = 0.35;
/// The error map's base: the shaded image multiplied by this…
pub const ERROR_DIM: f32 = 0.6;
/// …and, where the reference is shadowed, by this as well (so that the true shadows show).
pub const ERROR_REFERENCE_SHADOW: f32 = 0.6;
/// Background of the error map's legend strip.
pub const LEGEND_BACKGROUND: u8 = 24;
/// Text of the error map's legend strip.
pub const LEGEND_TEXT: u8 = 235;
/// Frame around enlarged crops.
pub const ZOOM_FRAME: u8 = GREY_MAX;
/// Space between grid cells, in pixels.
pub const GRID_GAP: u32 = 4;
/// Background of grids (the papers' white page).
pub const GRID_BACKGROUND: u8 = GREY_MAX;
/// Caption text of grids.
pub const GRID_TEXT: u8 = 20;

/// A grey level times `f` in 8-bit fixed point (integer arithmetic, so whole images scale in
/// vector instructions), capped at [`GREY_MAX`].
fn scale_level(v: u8, f: f32) -> u8 {
    let q = (f.max(0.0) * 256.0).round() as u32;
    ((v as u32 * q + 128) >> 8).min(GREY_MAX as u32) as u8
}

/// `scale_level(·, f)` for every grey.
pub(super) fn lut(f: f32) -> [u8; 256] {
    std::array::from_fn(|v| scale_level(v as u8, f))
}

/// A grey, shadow-free rendering of the G-buffer (camera-sized): a Lambert term for the light plus
/// a sky term `½ + ½·N·y` for shape, on a dark neutral background. Evaluated pixels are light
/// (grey 102–252), pixels outside a spot light's cone mid grey, pixels facing away from the light
/// dark (they are in attached shadow whatever a technique says).
pub fn shaded_base(gbuffer: &GBuffer, light: &Light) -> IndexedImage {
    let w = gbuffer.width as usize;
    let mut out = IndexedImage::filled(gbuffer.width, gbuffer.height, 0);
    out.pixels.par_chunks_mut(w).enumerate().for_each(|(y, row)| {
        for (x, px) in row.iter_mut().enumerate() {
            let i = y * w + x;
            let n = gbuffer.normal[i];
            let sky = 0.5 + 0.5 * n.y;
            let level = match gbuffer.class[i] {
                PixelClass::Background => BACKGROUND_GREY as f32 / 255.0,
                PixelClass::FacingAway => 0.22 + 0.18 * sky,
                cls => {
                    let l = match (&light.kind, light.position()) {
                        (LightKind::Directional { direction, .. }, _) => -direction.normalize(),
                        (_, Some(position)) => (position - gbuffer.position[i]).normalize_or(Vec3::Y),
                        (_, None) => unreachable!("lights other than directional ones have a position"),
                    };
                    let lambert = n.dot(l).max(0.0);
                    if cls == PixelClass::Evaluated {
                        0.40 + 0.45 * lambert + 0.15 * sky
                    } else {
                        0.30 + 0.15 * lambert + 0.15 * sky
                    }
                }
            };
            *px = grey(level);
        }
    });
    out
}

/// Where each row's pixels start in `gbuffer.evaluated` (`height + 1` entries): row `y` is
/// `starts[y]..starts[y + 1]`. A row holds at most `width` of them, so each boundary is searched
/// within one row's span of the previous one (a search over the whole list per row costs
/// more than drawing the image).
fn evaluated_row_starts(gbuffer: &GBuffer) -> Vec<usize> {
    let (w, n) = (gbuffer.width as usize, gbuffer.evaluated.len());
    let mut starts = Vec::with_capacity(gbuffer.height as usize + 1);
    let mut k = 0;
    starts.push(0);
    for y in 1..=gbuffer.height as usize {
        let bound = (y * w) as u64;
        let span = &gbuffer.evaluated[k..(k + w).min(n)];
        k += span.partition_point(|&i| (i as u64) < bound);
        starts.push(k);
    }
    starts
}

/// The reference as one visibility per evaluated pixel (1 lit, 0 shadowed), for
/// [`visibility_image`].
pub fn reference_visibility(gbuffer: &GBuffer, reference: &HardReference) -> Vec<f32> {
    gbuffer.evaluated.iter().map(|&i| reference.lit[i as usize] as f32).collect()
}

/// What every figure of one view (scene, camera, light) starts from, built once and shared by its
/// runs: the [`shaded_base`], the error map's background (the base dimmed, the reference's shadows
/// dimmed more, the legend strip blank) and where each row starts among the evaluated pixels.
pub struct ViewCanvas {
    pub base: IndexedImage,
    error_background: IndexedImage,
    /// The pixels drawn [`UNCERTAIN_INDEX`] on the error map: the G-buffer's `Uncertain` ones.
    uncertain: u64,
    /// `gbuffer.evaluated[row_starts[y]..row_starts[y + 1]]` are the evaluated pixels of row `y`.
    row_starts: Vec<usize>,
}

impl ViewCanvas {
    pub fn new(gbuffer: &GBuffer, reference: &HardReference, light: &Light) -> ViewCanvas {
        let base = shaded_base(gbuffer, light);
        let (w, h) = (gbuffer.width as usize, gbuffer.height as usize);
        let strip = legend_strip_height(gbuffer.width);
        let (dim, dim_shadowed) = (lut(ERROR_DIM), lut(ERROR_DIM * ERROR_REFERENCE_SHADOW));
        let mut error_background = IndexedImage::filled(gbuffer.width, h as u32 + strip, LEGEND_BACKGROUND);
        let mut uncertain = 0;
        for (i, (o, &b)) in error_background.pixels[..w * h].iter_mut().zip(&base.pixels).enumerate() {
            let class = gbuffer.class[i];
            let shadowed = class == PixelClass::Evaluated && reference.lit[i] == 0;
            *o = if class == PixelClass::Uncertain {
                uncertain += 1;
                UNCERTAIN_INDEX
            } else if shadowed {
                dim_shadowed[b as usize]
            } else {
                dim[b as usize]
            };
        }
        ViewCanvas { base, error_background, uncertain, row_starts: evaluated_row_starts(gbuffer) }
    }

    /// The pixels the error map draws [`UNCERTAIN_INDEX`]: the reference cannot decide them.
    pub fn uncertain(&self) -> u64 {
        self.uncertain
    }

    fn row(&self, y: usize) -> std::ops::Range<usize> {
        self.row_starts[y]..self.row_starts[y + 1]
    }

    fn assert_fits(&self, gbuffer: &GBuffer, values: &[f32]) {
        assert_eq!(values.len(), gbuffer.evaluated.len(), "one visibility per evaluated pixel");
        assert_eq!((self.base.width, self.base.height), (gbuffer.width, gbuffer.height), "camera-sized");
    }
}

/// `base` darkened by visibility: each evaluated pixel is multiplied by
/// `SHADOW_FACTOR + (1 − SHADOW_FACTOR)·v` (×0.35 shadowed, ×1 lit, linear in between); the other
/// pixels are `base` unchanged. `values` holds one visibility per evaluated pixel, in
/// `gbuffer.evaluated` order.
pub fn visibility_image(gbuffer: &GBuffer, canvas: &ViewCanvas, values: &[f32]) -> IndexedImage {
    canvas.assert_fits(gbuffer, values);
    let w = gbuffer.width as usize;
    let shadowed = lut(SHADOW_FACTOR);
    let mut out = canvas.base.clone();
    out.pixels.par_chunks_mut(w).enumerate().for_each(|(y, row)| {
        let range = canvas.row(y);
        for (&i, &v) in gbuffer.evaluated[range.clone()].iter().zip(&values[range]) {
            let px = &mut row[i as usize - y * w];
            *px = darkened(*px, v, &shadowed);
        }
    });
    out
}

/// A base grey darkened by visibility `v`; `shadowed` is `lut(SHADOW_FACTOR)`.
#[inline]
fn darkened(level: u8, v: f32, shadowed: &[u8; 256]) -> u8 {
    // Hard techniques return exactly 0 or 1: the branches predict well. NaN (an imported
    // buffer's surface mismatch) leaves the base as it is.
    if v >= 1.0 || v.is_nan() {
        level
    } else if v <= 0.0 {
        shadowed[level as usize]
    } else {
        scale_level(level, SHADOW_FACTOR + (1.0 - SHADOW_FACTOR) * v)
    }
}

/// The error colour of an evaluated pixel (the thresholds of `metrics::score_hard`), if any.
#[inline]
fn error_index(reference_lit: u8, v: f32) -> Option<u8> {
    if v.is_nan() {
        return None; // a surface mismatch: neither error
    }
    match (reference_lit != 0, v >= 0.5) {
        (true, false) => Some(FALSE_SHADOW_INDEX),
        (false, true) => Some(FALSE_LIT_INDEX),
        _ => None,
    }
}

/// [`visibility_image`] and `error_map` of one run, drawn in one pass over the evaluated pixels
/// (the pass is bound by memory traffic, so sharing it halves the cost).
pub fn run_images(
    gbuffer: &GBuffer,
    reference: &HardReference,
    values: &[f32],
    canvas: &ViewCanvas,
) -> (IndexedImage, IndexedImage) {
    canvas.assert_fits(gbuffer, values);
    let (w, h) = (gbuffer.width as usize, gbuffer.height as usize);
    let shadowed = lut(SHADOW_FACTOR);
    let mut technique = canvas.base.clone();
    let mut error = canvas.error_background.clone();
    let (false_shadow, false_lit) = technique
        .pixels
        .par_chunks_mut(w)
        .zip(error.pixels[..w * h].par_chunks_mut(w))
        .enumerate()
        .map(|(y, (t_row, e_row))| {
            let (mut fs, mut fl) = (0u64, 0u64);
            let range = canvas.row(y);
            for (&i, &v) in gbuffer.evaluated[range.clone()].iter().zip(&values[range]) {
                let (i, x) = (i as usize, i as usize - y * w);
                t_row[x] = darkened(t_row[x], v, &shadowed);
                if let Some(e) = error_index(reference.lit[i], v) {
                    e_row[x] = e;
                    fs += (e == FALSE_SHADOW_INDEX) as u64;
                    fl += (e == FALSE_LIT_INDEX) as u64;
                }
            }
            (fs, fl)
        })
        .reduce(|| (0, 0), |a, b| (a.0 + b.0, a.1 + b.1));
    draw_legend(&mut error, h as u32, (false_shadow, false_lit, canvas.uncertain), gbuffer.evaluated.len());
    (technique, error)
}

/// Height of the legend strip below an error map of the given width.
pub fn legend_strip_height(width: u32) -> u32 {
    let s = legend_scale(width);
    text::text_height(s) + 8 * s
}

/// Font scale of the legend strip below an image of the given width.
pub(super) fn legend_scale(width: u32) -> u32 {
    (width / 512).clamp(1, 4)
}

#[cfg(test)]
/// The error map of a run: `base` dimmed (×[`ERROR_DIM`], and ×[`ERROR_REFERENCE_SHADOW`] more
/// where the reference is shadowed, so the true shadows show), false-shadow pixels exactly
/// [`FALSE_SHADOW`](super::palette::FALSE_SHADOW), false-lit pixels exactly
/// [`FALSE_LIT`](super::palette::FALSE_LIT) (the thresholds of `metrics::score_hard`), and a
/// legend strip of [`legend_strip_height`] rows added below the image; the image area is the top
/// `gbuffer.height` rows.
pub fn error_map(
    gbuffer: &GBuffer,
    reference: &HardReference,
    visibility: &[f32],
    canvas: &ViewCanvas,
) -> IndexedImage {
    let (mut out, false_shadow, false_lit) = error_map_unlabelled(gbuffer, reference, visibility, canvas);
    draw_legend(
        &mut out,
        gbuffer.height,
        (false_shadow, false_lit, canvas.uncertain),
        gbuffer.evaluated.len(),
    );
    out
}

/// The error map of a run (`error_map`) with its legend strip left blank, and the false-shadow
/// and false-lit pixels it coloured: for maps whose legend is drawn at another size (the frames
/// of `frame_movie.rs`).
pub fn error_map_unlabelled(
    gbuffer: &GBuffer,
    reference: &HardReference,
    visibility: &[f32],
    canvas: &ViewCanvas,
) -> (IndexedImage, u64, u64) {
    canvas.assert_fits(gbuffer, visibility);
    let (w, h) = (gbuffer.width as usize, gbuffer.height as usize);
    let mut out = canvas.error_background.clone();
    let (false_shadow, false_lit) = out.pixels[..w * h]
        .par_chunks_mut(w)
        .enumerate()
        .map(|(y, row)| {
            let (mut fs, mut fl) = (0u64, 0u64);
            let range = canvas.row(y);
            for (&i, &v) in gbuffer.evaluated[range.clone()].iter().zip(&visibility[range]) {
                if let Some(e) = error_index(reference.lit[i as usize], v) {
                    row[i as usize - y * w] = e;
                    fs += (e == FALSE_SHADOW_INDEX) as u64;
                    fl += (e == FALSE_LIT_INDEX) as u64;
                }
            }
            (fs, fl)
        })
        .reduce(|| (0, 0), |a, b| (a.0 + b.0, a.1 + b.1));
    (out, false_shadow, false_lit)
}

/// The legend on the strip that starts at row `top`: the false shadows and false lits (with
/// their share of the evaluated pixels) and the uncertain pixels, left out of that share.
fn draw_legend(img: &mut IndexedImage, top: u32, (fs, fl, uncertain): (u64, u64, u64), evaluated: usize) {
    let s = legend_scale(img.width);
    let pct = |n: u64| 100.0 * n as f64 / evaluated.max(1) as f64;
    let entries = [
        (FALSE_SHADOW_INDEX, format!("false shadow {fs} ({:.2}%)", pct(fs))),
        (FALSE_LIT_INDEX, format!("false lit {fl} ({:.2}%)", pct(fl))),
        (UNCERTAIN_INDEX, format!("uncertain {uncertain} (not scored)")),
    ];
    let side = text::text_height(s);
    let y = (top + 4 * s) as i64;
    let mut x = (4 * s) as i64;
    for (index, label) in entries {
        img.fill_rect(x, y, side, side, index);
        x += (side + 3 * s) as i64;
        img.draw_text(x, y, &label, s, LEGEND_TEXT);
        x += (text::text_width(&label, s) + 12 * s) as i64;
    }
}

/// An enlarged panel: `rect` = (x, y, w, h) of an image (clipped to it), each pixel repeated
/// `scale`×`scale` times (nearest neighbour), inside a 1-pixel [`ZOOM_FRAME`]. Its size is
/// (2 + w·scale) × (2 + h·scale) for the clipped w, h.
pub fn zoom(img: &IndexedImage, rect: (u32, u32, u32, u32), scale: u32) -> IndexedImage {
    let scale = scale.max(1) as usize;
    let x0 = rect.0.min(img.width) as usize;
    let y0 = rect.1.min(img.height) as usize;
    let cw = (rect.2 as usize).min(img.width as usize - x0);
    let ch = (rect.3 as usize).min(img.height as usize - y0);
    let (ow, oh) = (cw * scale + 2, ch * scale + 2);
    let mut out = IndexedImage::filled(ow as u32, oh as u32, ZOOM_FRAME);
    let src_w = img.width as usize;
    for (oy, row) in out.pixels.chunks_exact_mut(ow).enumerate().skip(1).take(ch * scale) {
        let sy = y0 + (oy - 1) / scale;
        let src = &img.pixels[sy * src_w + x0..sy * src_w + x0 + cw];
        for (block, &p) in row[1..1 + cw * scale].chunks_exact_mut(scale).zip(src) {
            block.fill(p);
        }
    }
    out
}

/// One cell of a [`grid`]: an image and the caption printed below it.
#[derive(Clone, Debug)]
pub struct GridCell<'a> {
    pub image: &'a IndexedImage,
    pub caption: String,
}

/// How a grid is laid out: every cell occupies `cell_width` × (`cell_height` + `caption_height`)
/// pixels, cells are [`GRID_GAP`] apart and from the border.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct GridLayout {
    /// Cells are shrunk by this integer factor (see [`downscale`]).
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
        let widest = cells.iter().map(|c| c.image.width).max().unwrap_or(0);
        let downscale = widest.div_ceil(max_cell_width.max(1)).max(1);
        let cell_width = cells.iter().map(|c| c.image.width / downscale).max().unwrap_or(0);
        let cell_height = cells.iter().map(|c| c.image.height / downscale).max().unwrap_or(0);
        let caption_scale = (cell_width / 256).clamp(1, 3);
        let caption_lines = cells
            .iter()
            .map(|c| text::wrap(&c.caption, cell_width, caption_scale).len() as u32)
            .max()
            .unwrap_or(1)
            .max(1);
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
    3 * scale + text::line_pitch(scale) * lines
}

/// Shrinks an image by an integer factor `f` (the incomplete blocks at the right and bottom edges
/// are dropped). Errors stay visible: a block holding error pixels shows the error colour it holds
/// most of (false shadow on a tie), a block holding no error pixel but an uncertain one shows
/// the uncertain colour; a block of greys shows their mean.
pub fn downscale(img: &IndexedImage, f: u32) -> IndexedImage {
    let f = f.max(1) as usize;
    let (w, h) = (img.width as usize, img.height as usize);
    if f == 1 {
        return img.clone();
    }
    let (ow, oh) = (w / f, h / f);
    let mut out = IndexedImage::filled(ow as u32, oh as u32, 0);
    let area = (f * f) as u32;
    let block_colour = |oy: usize, ox: usize| {
        let (mut fs, mut fl) = (0u32, 0u32);
        for sy in oy * f..oy * f + f {
            for &p in &img.pixels[sy * w + ox * f..sy * w + ox * f + f] {
                fs += (p == FALSE_SHADOW_INDEX) as u32;
                fl += (p == FALSE_LIT_INDEX) as u32;
            }
        }
        if fs + fl == 0 {
            UNCERTAIN_INDEX
        } else if fs >= fl {
            FALSE_SHADOW_INDEX
        } else {
            FALSE_LIT_INDEX
        }
    };
    if f == 2 {
        // The usual case (1024-pixel cameras in 512-pixel cells), in one vectorisable pass.
        out.pixels.par_chunks_mut(ow.max(1)).enumerate().for_each(|(oy, row)| {
            let a = img.pixels[2 * oy * w..2 * oy * w + 2 * ow].chunks_exact(2);
            let b = img.pixels[(2 * oy + 1) * w..(2 * oy + 1) * w + 2 * ow].chunks_exact(2);
            for (ox, (o, (a, b))) in row.iter_mut().zip(a.zip(b)).enumerate() {
                let sum = a[0] as u32 + a[1] as u32 + b[0] as u32 + b[1] as u32;
                let grey = a[0].max(a[1]).max(b[0]).max(b[1]) <= GREY_MAX;
                *o = if grey { ((sum + 2) / 4) as u8 } else { block_colour(oy, ox) };
            }
        });
        return out;
    }
    // Column sums and maxima over the block's rows first (loops the compiler vectorises), then
    // one pass over the blocks; the rare blocks holding an error are counted again.
    out.pixels.par_chunks_mut(ow.max(1)).enumerate().for_each_init(
        || (vec![0u32; ow * f], vec![0u8; ow * f]),
        |(sum, max), (oy, row)| {
            sum.fill(0);
            max.fill(0);
            for sy in oy * f..oy * f + f {
                let src = &img.pixels[sy * w..sy * w + ow * f];
                for ((s, m), &p) in sum.iter_mut().zip(max.iter_mut()).zip(src) {
                    *s += p as u32;
                    *m = (*m).max(p);
                }
            }
            for (ox, o) in row.iter_mut().enumerate() {
                let block = ox * f..ox * f + f;
                *o = if max[block.clone()].iter().any(|&m| !is_grey(m)) {
                    block_colour(oy, ox)
                } else {
                    ((sum[block].iter().sum::<u32>() + area / 2) / area) as u8
                };
            }
        },
    );
    out
}

/// A captioned grid (techniques × settings, in the style of the papers' figures): cells in
/// row-major order, `columns` per row, shrunk by an integer factor ([`downscale`]) so that none is
/// wider than `max_cell_width`, each with its caption (wrapped, centred) below it, [`GRID_GAP`]
/// pixels apart on a white page. See [`GridLayout`] for the geometry.
pub fn grid(cells: &[GridCell], columns: u32, max_cell_width: u32) -> IndexedImage {
    let layout = GridLayout::new(cells, columns, max_cell_width);
    let mut out = IndexedImage::filled(layout.width, layout.height, GRID_BACKGROUND);
    let shrunk: Vec<std::borrow::Cow<IndexedImage>> = cells
        .par_iter()
        .map(|c| match layout.downscale {
            1 => std::borrow::Cow::Borrowed(c.image),
            f => std::borrow::Cow::Owned(downscale(c.image, f)),
        })
        .collect();
    let s = layout.caption_scale;
    let gw = layout.width as usize;
    for (index, (cell, small)) in cells.iter().zip(&shrunk).enumerate() {
        let (x0, y0) = layout.cell_origin(index);
        let sw = small.width as usize;
        for (y, src) in small.pixels.chunks_exact(sw.max(1)).enumerate() {
            let dst = (y0 as usize + y) * gw + x0 as usize;
            out.pixels[dst..dst + sw].copy_from_slice(src);
        }
        let text_top = y0 + layout.cell_height + 2 * s;
        for (line_no, line) in text::wrap(&cell.caption, layout.cell_width, s).iter().enumerate() {
            let tw = text::text_width(line, s);
            let x = x0 as i64 + (layout.cell_width.saturating_sub(tw) / 2) as i64;
            let y = text_top as i64 + (line_no as u32 * text::line_pitch(s)) as i64;
            out.draw_text(x, y, line, s, GRID_TEXT);
        }
    }
    out
}

/// The files of one run, relative to the directory they were written to (file names).
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct RunFigures {
    /// `<stem>.technique.png`: the technique's visibility over the base image.
    pub technique: String,
    /// `<stem>.error.png`: the error map with its legend strip.
    pub error: String,
    /// The error map as drawn (legend strip included), for grids and zooms.
    pub error_image: IndexedImage,
}

/// Writes `dir/<stem>.technique.png` and `dir/<stem>.error.png` for one run.
pub fn write_run_figures(
    dir: &Path,
    stem: &str,
    gbuffer: &GBuffer,
    reference: &HardReference,
    visibility: &[f32],
    canvas: &ViewCanvas,
) -> std::io::Result<RunFigures> {
    let (technique, error) = (format!("{stem}.technique.png"), format!("{stem}.error.png"));
    let (technique_image, error_image) = run_images(gbuffer, reference, visibility, canvas);
    let (written, error_written) = rayon::join(
        || technique_image.write_png(&dir.join(&technique)),
        || error_image.write_png(&dir.join(&error)),
    );
    written?;
    error_written?;
    Ok(RunFigures { technique, error, error_image })
}

/// Writes `dir/<stem>.reference.png`, the reference's shadows over the base image, and returns
/// its file name. `stem` is usually [`view_stem`].
pub fn write_reference_figure(
    dir: &Path,
    stem: &str,
    gbuffer: &GBuffer,
    reference: &HardReference,
    canvas: &ViewCanvas,
) -> std::io::Result<String> {
    let name = format!("{stem}.reference.png");
    visibility_image(gbuffer, canvas, &reference_visibility(gbuffer, reference))
        .write_png(&dir.join(&name))?;
    Ok(name)
}

/// The stem of a view's files (its reference figure): the view's own
/// (`ViewKey::file_stem`), `<scene>.<camera>.<light>.<digest>`, the names filtered and capped
/// and the digest that of the exact names (`src/file_name.rs`), the stem its cached references
/// have too.
pub fn view_stem(view: ViewKey) -> String {
    view.file_stem()
}

/// The stem of a run's files: `<scene>.<camera>.<light>.<label>.r<resolution>.<depth format>`
/// filtered and capped, then the digest of the exact key (scene, camera, light, technique,
/// label, parameters, resolution, depth format; `src/file_name.rs`).
pub fn run_stem(record: &RunRecord) -> String {
    let resolution = format!("r{}", record.resolution);
    let readable =
        [&record.scene, &record.camera, &record.light, &record.label, &resolution, &record.depth_format]
            .map(|part| file_name::readable(part))
            .join(".");
    let parameters = serde_json::Value::Object(record.parameters.clone()).to_string();
    file_name::stem_with(
        &readable,
        &[
            &record.scene,
            &record.camera,
            &record.light,
            &record.technique,
            &record.label,
            &parameters,
            &record.resolution.to_string(),
            &record.depth_format,
        ],
    )
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn downscale_averages_greys_and_keeps_errors() {
        // 8×2 image, factor 2: four output pixels from four 2×2 blocks.
        let (s, l) = (FALSE_SHADOW_INDEX, FALSE_LIT_INDEX);
        let rows = [[0u8, 10, 100, 200, 9, s, l, s], [20, 30, 50, 50, 9, 9, l, 9]];
        let img = IndexedImage { width: 8, height: 2, pixels: rows.concat() };
        let out = downscale(&img, 2);
        assert_eq!((out.width, out.height), (4, 1));
        assert_eq!(out.pixels, [15, 100, s, l], "means of greys; one error pixel colours its block");
        // Other factors take the general path: 3×3 blocks of a 6×3 image.
        let img = IndexedImage { width: 6, height: 3, pixels: [[9u8, 9, 9, 0, 0, 9]; 3].concat() };
        assert_eq!(downscale(&img, 3).pixels, [9, 3]);
        let mut with_error = img.clone();
        with_error.pixels[3 * 6 - 1] = l;
        assert_eq!(downscale(&with_error, 3).pixels, [9, l]);
        // A tie between the two errors shows false shadow.
        let tie = IndexedImage { width: 2, height: 2, pixels: vec![l, s, 9, 9] };
        assert_eq!(downscale(&tie, 2).pixels, [s]);
    }

    #[test]
    fn zoom_clips_to_the_image() {
        let img = IndexedImage::filled(4, 4, 7);
        let out = zoom(&img, (2, 3, 10, 10), 3);
        assert_eq!((out.width, out.height), (2 + 2 * 3, 2 + 3));
        assert_eq!(out.pixels.len(), (out.width * out.height) as usize);
        assert_eq!(out.at(1, 1), 7);
        assert_eq!(out.at(0, 0), ZOOM_FRAME);
    }

    #[test]
    fn legend_strip_scales_with_width() {
        assert!(legend_strip_height(1024) > legend_strip_height(256));
        assert_eq!(legend_strip_height(256), legend_strip_height(512));
    }
}
