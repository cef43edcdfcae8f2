//! The flicker heat map of a run over a path (`figures/<run stem>.flicker.png`): per camera
//! pixel, how many times the technique's answer flipped between consecutive frames
//! (`Event::FlickerDone`, src/plan/events.rs). Pixels that never flickered are grey — the shaded
//! base dimmed as under an error map (`figures.rs`) when the camera stood still, plain dark grey
//! when it moved and no single image lies under every frame — and flickering pixels are coloured
//! on a sequential yellow-to-red scale by their count, so that no flickering pixel is grey. A
//! legend strip below the image gives the scale, the largest count and how many pixels
//! flickered.

use super::figures::{ERROR_DIM, LEGEND_BACKGROUND, LEGEND_TEXT, legend_scale, legend_strip_height, lut};
use super::indexed_image::IndexedImage;
use super::palette::palette_rgb;
use super::text;
use shadowtruth::atomic_file::{encode_rgb_png, write_atomic_unsynced};
use std::path::Path;

/// The scale's colours, fewest flickers first: ColorBrewer's YlOrRd (its five darker classes,
/// so that the lightest still stands out against the grey base), a sequential scale that stays
/// ordered for colour-blind readers and in greyscale.
pub const HEAT_COLOURS: [[u8; 3]; 5] =
    [[0xFE, 0xD9, 0x76], [0xFE, 0xB2, 0x4C], [0xFD, 0x8D, 0x3C], [0xF0, 0x3B, 0x20], [0xBD, 0x00, 0x26]];

/// The pixels that never flickered when the camera moved.
pub const STILL_GREY: u8 = 60;

/// The file under `figures/` of a run's flicker heat map.
pub fn flicker_file_name(run_stem: &str) -> String {
    format!("{run_stem}.flicker.png")
}

/// The colour step of a pixel that flickered `count` times (≥ 1) when the most was `max`: on a
/// log scale, since a few pixels flicker often and most rarely, so that both show; `max` always
/// takes the darkest step.
pub fn heat_step(count: u16, max: u16) -> usize {
    let steps = HEAT_COLOURS.len() as f64;
    let t = (1.0 + count as f64).ln() / (1.0 + max.max(1) as f64).ln();
    ((t * steps).ceil() as usize).clamp(1, HEAT_COLOURS.len()) - 1
}

/// An RGB image, row 0 at the top.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct RgbImage {
    pub width: u32,
    pub height: u32,
    pub pixels: Vec<u8>,
}

impl RgbImage {
    /// Fills the rectangle at (`x`, `y`) of `w`×`h` pixels (clipped to the image).
    fn fill_rect(&mut self, (x, y): (i64, i64), (w, h): (u32, u32), colour: [u8; 3]) {
        let (iw, ih) = (self.width as i64, self.height as i64);
        for py in y.max(0)..(y + h as i64).min(ih) {
            for px in x.max(0)..(x + w as i64).min(iw) {
                let i = 3 * (py * iw + px) as usize;
                self.pixels[i..i + 3].copy_from_slice(&colour);
            }
        }
    }
}

/// The heat map of `heat` (row-major, `width`×`height`) with its legend strip below. `base` is
/// the camera image the grey pixels show (dimmed), when there is one of that size.
pub fn flicker_image(heat: &[u16], (width, height): (u32, u32), base: Option<&IndexedImage>) -> RgbImage {
    assert_eq!(heat.len(), width as usize * height as usize, "one count per camera pixel");
    let area = heat.len();
    let mut grey = IndexedImage::filled(width, height + legend_strip_height(width), LEGEND_BACKGROUND);
    match base.filter(|b| (b.width, b.height) == (width, height)) {
        Some(base) => {
            let dim = lut(ERROR_DIM);
            grey.pixels[..area].iter_mut().zip(&base.pixels).for_each(|(o, &b)| *o = dim[b as usize]);
        }
        None => grey.pixels[..area].fill(STILL_GREY),
    }
    let max = heat.iter().copied().max().unwrap_or(0);
    let flickered = heat.iter().filter(|&&n| n > 0).count();
    let ramp_at = draw_legend_text(&mut grey, height, max, flickered);
    let mut out = RgbImage {
        width: grey.width,
        height: grey.height,
        pixels: grey.pixels.iter().flat_map(|&i| palette_rgb(i)).collect(),
    };
    for (px, &n) in out.pixels[..3 * area].chunks_exact_mut(3).zip(heat) {
        if n > 0 {
            px.copy_from_slice(&HEAT_COLOURS[heat_step(n, max)]);
        }
    }
    if let Some((x, y, side)) = ramp_at {
        for (k, &colour) in HEAT_COLOURS.iter().enumerate() {
            out.fill_rect((x + (k as u32 * side) as i64, y), (side, side), colour);
        }
    }
    out
}

/// The legend's text on the strip that starts at row `top`: `1 [scale] max flickers (log
/// scale)   N pixels flickered`, or that none did. Returns where the colour scale goes (x, y and
/// the side of each of its squares), drawn in colour by the caller.
fn draw_legend_text(img: &mut IndexedImage, top: u32, max: u16, flickered: usize) -> Option<(i64, i64, u32)> {
    let s = legend_scale(img.width);
    let side = text::text_height(s);
    let (y, mut x) = ((top + 4 * s) as i64, (4 * s) as i64);
    if max == 0 {
        img.draw_text(x, y, "no pixel flickered", s, LEGEND_TEXT);
        return None;
    }
    img.draw_text(x, y, "1", s, LEGEND_TEXT);
    x += (text::text_width("1", s) + 3 * s) as i64;
    let ramp = (x, y, side);
    x += (HEAT_COLOURS.len() as u32 * side + 3 * s) as i64;
    let times = if max == 1 { "time" } else { "times" };
    let scale = format!("{max} {times} (log scale)");
    img.draw_text(x, y, &scale, s, LEGEND_TEXT);
    x += (text::text_width(&scale, s) + 12 * s) as i64;
    let pixels = if flickered == 1 { "pixel" } else { "pixels" };
    img.draw_text(x, y, &format!("{flickered} {pixels} flickered"), s, LEGEND_TEXT);
    Some(ramp)
}

/// Writes `dir/<stem>.flicker.png` (see [`flicker_image`]) and returns its file name. A `heat`
/// that is not `width`×`height` counts is an error naming the file.
pub fn write_flicker_map(
    dir: &Path,
    stem: &str,
    heat: &[u16],
    size: (u32, u32),
    base: Option<&IndexedImage>,
) -> std::io::Result<String> {
    let name = flicker_file_name(stem);
    if heat.len() != size.0 as usize * size.1 as usize {
        return Err(std::io::Error::new(
            std::io::ErrorKind::InvalidInput,
            format!("{name}: {} flicker counts for a {}×{} camera", heat.len(), size.0, size.1),
        ));
    }
    let image = flicker_image(heat, size, base);
    write_atomic_unsynced(&dir.join(&name), &encode_rgb_png(image.width, image.height, &image.pixels)?)?;
    Ok(name)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn rgb_at(image: &image::RgbImage, x: u32, y: u32) -> [u8; 3] {
        image.get_pixel(x, y).0
    }

    #[test]
    fn flickering_pixels_are_coloured_and_the_others_grey() {
        let dir = tempfile::tempdir().unwrap();
        let (w, h) = (64, 8);
        let mut heat = vec![0u16; (w * h) as usize];
        heat[3] = 1; // (3, 0): once
        heat[(5 * w + 10) as usize] = 12; // (10, 5): the most
        let base = IndexedImage::filled(w, h, 200);
        let name = write_flicker_map(dir.path(), "run", &heat, (w, h), Some(&base)).unwrap();
        assert_eq!(name, "run.flicker.png");
        let png = image::open(dir.path().join(&name)).unwrap().to_rgb8();
        assert_eq!(png.dimensions(), (w, h + legend_strip_height(w)));
        assert_eq!(rgb_at(&png, 10, 5), HEAT_COLOURS[4], "the largest count is the darkest");
        assert_eq!(rgb_at(&png, 3, 0), HEAT_COLOURS[heat_step(1, 12)]);
        assert_ne!(heat_step(1, 12), 4);
        let still = lut(ERROR_DIM)[200];
        assert_eq!(rgb_at(&png, 4, 0), [still; 3], "a pixel that never flickered shows the dimmed base");
        // Without a base (a moving camera) it is plain dark grey; the legend shows the scale.
        let plain = flicker_image(&heat, (w, h), None);
        assert_eq!(plain.pixels[3 * 4..3 * 5], [STILL_GREY; 3]);
        let legend = &plain.pixels[3 * (w * h) as usize..];
        assert!(HEAT_COLOURS.iter().all(|c| legend.chunks_exact(3).any(|p| p == c)));
    }

    #[test]
    fn heat_steps_grow_with_the_count() {
        let steps: Vec<usize> = (1..=100).map(|n| heat_step(n, 100)).collect();
        assert!(steps.windows(2).all(|w| w[0] <= w[1]));
        assert_eq!((steps[0], steps[99]), (0, 4));
        assert_eq!(heat_step(1, 1), 4);
        let e = write_flicker_map(Path::new("."), "run", &[0; 5], (2, 2), None).unwrap_err();
        assert!(e.to_string().contains("run.flicker.png"), "{e}");
    }
}
