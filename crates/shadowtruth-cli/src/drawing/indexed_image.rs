//! Figures as 8-bit images over one fixed palette (`palette.rs`: greys and the two error
//! colours). Every figure (the
//! shaded base, reference, technique, error map, zoom, grid) is drawn in it, so a figure costs one
//! byte per pixel to draw and to compress and is written as an indexed PNG without a colour scan;
//! decoders return the palette's RGB.

use super::palette::palette_bytes;
use super::text;
use std::path::Path;

/// An image of palette indices, row 0 at the top.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct IndexedImage {
    pub width: u32,
    pub height: u32,
    pub pixels: Vec<u8>,
}

impl IndexedImage {
    /// A `width`×`height` image of one index.
    pub fn filled(width: u32, height: u32, index: u8) -> IndexedImage {
        IndexedImage { width, height, pixels: vec![index; width as usize * height as usize] }
    }

    #[cfg(test)]
    /// The index at (`x`, `y`).
    pub fn at(&self, x: u32, y: u32) -> u8 {
        self.pixels[y as usize * self.width as usize + x as usize]
    }

    #[cfg(test)]
    /// RGB8 pixels, as a PNG decoder returns them.
    pub fn to_rgb(&self) -> Vec<u8> {
        self.pixels.iter().flat_map(|&i| super::palette::palette_rgb(i)).collect()
    }

    /// Fills the rectangle at (`x`, `y`) of `w`×`h` pixels (clipped to the image).
    pub fn fill_rect(&mut self, x: i64, y: i64, w: u32, h: u32, index: u8) {
        let (iw, ih) = (self.width as i64, self.height as i64);
        let (x0, x1) = (x.max(0), (x + w as i64).min(iw));
        if x0 >= x1 {
            return;
        }
        for py in y.max(0)..(y + h as i64).min(ih) {
            let row = (py * iw) as usize;
            self.pixels[row + x0 as usize..row + x1 as usize].fill(index);
        }
    }

    #[cfg(test)]
    /// Draws the 1-pixel outline of `rect` = (x, y, w, h) (clipped).
    pub fn outline_rect(&mut self, rect: (u32, u32, u32, u32), index: u8) {
        let (x, y, w, h) = (rect.0 as i64, rect.1 as i64, rect.2, rect.3);
        if w == 0 || h == 0 {
            return;
        }
        self.fill_rect(x, y, w, 1, index);
        self.fill_rect(x, y + h as i64 - 1, w, 1, index);
        self.fill_rect(x, y, 1, h, index);
        self.fill_rect(x + w as i64 - 1, y, 1, h, index);
    }

    /// Draws one line of `line` with its box's top-left corner at (`x`, `y`), antialiased over
    /// what is there; see [`text::draw_text`].
    pub fn draw_text(&mut self, x: i64, y: i64, line: &str, scale: u32, index: u8) -> usize {
        text::draw_text(&mut self.pixels, self.width, self.height, x, y, line, scale, index)
    }

    /// PNG bytes: an indexed PNG with the fixed palette, the `Sub` filter (runs of one index become
    /// runs of zeros) and fast deflate.
    pub fn encode_png(&self) -> std::io::Result<Vec<u8>> {
        assert_eq!(self.pixels.len(), self.width as usize * self.height as usize, "width × height indices");
        let mut out = Vec::with_capacity(self.pixels.len() / 8);
        let mut encoder = png::Encoder::new(&mut out, self.width, self.height);
        encoder.set_color(png::ColorType::Indexed);
        encoder.set_depth(png::BitDepth::Eight);
        encoder.set_palette(palette_bytes());
        // zlib level 1 (zlib-rs's quick deflate): on the bundled scenes at 1024×768, 1–1.5 ms and
        // 30 KiB per figure; fdeflate is no faster on indexed data and writes 15 times more bytes.
        encoder.set_deflate_compression(png::DeflateCompression::Level(1));
        encoder.set_filter(png::Filter::Sub);
        let mut writer = encoder.write_header().map_err(std::io::Error::other)?;
        writer.write_image_data(&self.pixels).map_err(std::io::Error::other)?;
        writer.finish().map_err(std::io::Error::other)?;
        Ok(out)
    }

    /// Writes the PNG through a temporary file renamed over `path`, so that a killed run never
    /// leaves a half-written figure. It does not fsync (`write_atomic_unsynced`): figures are
    /// derived data that a rerun regenerates, and an fsync per figure costs more than drawing and
    /// encoding it.
    pub fn write_png(&self, path: &Path) -> std::io::Result<()> {
        shadowtruth::atomic_file::write_atomic_unsynced(path, &self.encode_png()?)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::drawing::palette::{FALSE_LIT_INDEX, FALSE_SHADOW_INDEX, GREY_MAX};

    #[test]
    fn png_decodes_to_the_palette_colours() {
        let mut img = IndexedImage::filled(13, 7, 40);
        img.fill_rect(2, 1, 3, 2, FALSE_SHADOW_INDEX);
        img.fill_rect(-4, 5, 6, 9, FALSE_LIT_INDEX);
        img.outline_rect((8, 0, 5, 7), GREY_MAX);
        let decoded = image::load_from_memory(&img.encode_png().unwrap()).unwrap().to_rgb8();
        assert_eq!(decoded.dimensions(), (13, 7));
        assert_eq!(decoded.as_raw(), &img.to_rgb());
        assert_eq!(img.at(3, 2), FALSE_SHADOW_INDEX);
        assert_eq!(img.at(0, 6), FALSE_LIT_INDEX);
        assert_eq!(img.at(12, 3), GREY_MAX);
        assert_eq!(img.at(10, 3), 40);
    }
}
