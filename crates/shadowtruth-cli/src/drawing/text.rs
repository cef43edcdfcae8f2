//! Text of captions and legends, drawn into indexed figures with the bundled DejaVu Sans
//! (`bundled_font.rs`), antialiased and proportionally spaced, at an integer `scale`.
//!
//! A line of text sits in a box [`TEXT_HEIGHT`]·scale pixels tall whose bottom is the baseline
//! (capitals fill most of it, descenders hang below it) and lines are [`LINE_PITCH`]·scale
//! apart. Characters the font lacks draw as `?`.

use super::bundled_font::dejavu_sans;
use super::palette::is_grey;
use ab_glyph::{Font, GlyphId, PxScale, ScaleFont, point};

/// Height of a line's box in pixels per unit of scale: from its top to the baseline.
pub const TEXT_HEIGHT: u32 = 7;
/// Distance between the baselines of consecutive lines in pixels per unit of scale.
pub const LINE_PITCH: u32 = 9;
/// The font's pixel size (ascent minus descent, as ab_glyph measures it) per unit of scale:
/// capitals about 6.3 and ascender-to-descender ink about 8.6 pixels, so that lines
/// [`LINE_PITCH`] apart never touch.
const PX_PER_SCALE: f32 = 10.0;

fn px_scale(scale: u32) -> PxScale {
    PxScale::from(PX_PER_SCALE * scale.max(1) as f32)
}

/// The glyph of `c`, or of `?` when the font has none.
fn glyph_id(c: char) -> GlyphId {
    let font = dejavu_sans();
    match font.glyph_id(c) {
        GlyphId(0) => font.glyph_id('?'),
        id => id,
    }
}

/// Calls `place` with each character's glyph and its pen position (pixels from the start of the
/// line, advances and kerning summed); returns the pen position after the last character.
fn lay_out(text: &str, scale: u32, mut place: impl FnMut(GlyphId, f32)) -> f32 {
    let font = dejavu_sans().as_scaled(px_scale(scale));
    let mut pen = 0.0;
    let mut previous = None;
    for c in text.chars() {
        let id = glyph_id(c);
        if let Some(previous) = previous {
            pen += font.kern(previous, id);
        }
        place(id, pen);
        pen += font.h_advance(id);
        previous = Some(id);
    }
    pen
}

/// Width in pixels of one line of `text`: its advances and kerning summed, rounded up.
pub fn text_width(text: &str, scale: u32) -> u32 {
    lay_out(text, scale, |_, _| {}).ceil() as u32
}

/// Height in pixels of a line's box (its top to the baseline).
pub fn text_height(scale: u32) -> u32 {
    TEXT_HEIGHT * scale.max(1)
}

/// Distance in pixels between consecutive lines.
pub fn line_pitch(scale: u32) -> u32 {
    LINE_PITCH * scale.max(1)
}

/// The palette index of a pixel of `background` covered to `coverage` (0–1) by `ink`: the grey
/// between them when both are greys, so the result stays in the palette; otherwise (text over an
/// error colour) whichever of the two covers at least half the pixel.
fn blend(background: u8, ink: u8, coverage: f32) -> u8 {
    let coverage = coverage.clamp(0.0, 1.0);
    if is_grey(background) && is_grey(ink) {
        (background as f32 + (ink as f32 - background as f32) * coverage).round() as u8
    } else if coverage >= 0.5 {
        ink
    } else {
        background
    }
}

/// Draws one line of `text` into a one-index-per-pixel image of `width`×`height`, its box's
/// top-left corner at (`x`, `y`), in palette index `ink` blended over what is there (see
/// [`blend`]); clipped to the image. Returns how many pixels it changed.
#[allow(clippy::too_many_arguments)]
pub fn draw_text(
    pixels: &mut [u8],
    width: u32,
    height: u32,
    x: i64,
    y: i64,
    text: &str,
    scale: u32,
    ink: u8,
) -> usize {
    let font = dejavu_sans();
    let size = px_scale(scale);
    let (w, h) = (width as i64, height as i64);
    let baseline = (y + text_height(scale) as i64) as f32;
    let mut changed = 0;
    lay_out(text, scale, |id, pen| {
        let glyph = id.with_scale_and_position(size, point(x as f32 + pen, baseline));
        // Spaces have no outline.
        let Some(outlined) = font.outline_glyph(glyph) else { return };
        let bounds = outlined.px_bounds();
        let (left, top) = (bounds.min.x as i64, bounds.min.y as i64);
        if left >= w || top >= h || bounds.max.x < 0.0 || bounds.max.y < 0.0 {
            return;
        }
        outlined.draw(|gx, gy, coverage| {
            let (px, py) = (left + gx as i64, top + gy as i64);
            if coverage <= 0.0 || px < 0 || py < 0 || px >= w || py >= h {
                return;
            }
            let pixel = &mut pixels[(py * w + px) as usize];
            let blended = blend(*pixel, ink, coverage);
            changed += (blended != *pixel) as usize;
            *pixel = blended;
        });
    });
    changed
}

/// Splits `text` into lines at most `max_width` pixels wide at `scale`, breaking at spaces where
/// it can and inside words where it must (a line holds at least one character).
pub fn wrap(text: &str, max_width: u32, scale: u32) -> Vec<String> {
    let fits = |line: &str| text_width(line, scale) <= max_width;
    let mut lines = Vec::new();
    let mut line = String::new();
    for word in text.split(' ') {
        let joined = if line.is_empty() { word.to_string() } else { format!("{line} {word}") };
        if fits(&joined) {
            line = joined;
            continue;
        }
        if !line.is_empty() {
            lines.push(std::mem::take(&mut line));
        }
        // The word alone is too wide: as many characters per line as fit.
        for c in word.chars() {
            line.push(c);
            if !fits(&line) && line.chars().count() > 1 {
                line.pop();
                lines.push(std::mem::replace(&mut line, c.to_string()));
            }
        }
    }
    if !line.is_empty() || lines.is_empty() {
        lines.push(line);
    }
    lines
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::drawing::palette::{FALSE_LIT_INDEX, GREY_MAX};

    fn drawn(width: u32, height: u32, background: u8, x: i64, y: i64, text: &str, ink: u8) -> Vec<u8> {
        let mut pixels = vec![background; (width * height) as usize];
        draw_text(&mut pixels, width, height, x, y, text, 1, ink);
        pixels
    }

    #[test]
    fn width_grows_with_the_text_and_is_the_sum_of_its_advances() {
        let font = dejavu_sans().as_scaled(px_scale(2));
        let text = "AVery wide caption: err 1.23% ×2";
        let ids: Vec<GlyphId> = text.chars().map(|c| font.glyph_id(c)).collect();
        let advances: f32 = ids.iter().map(|&id| font.h_advance(id)).sum::<f32>()
            + ids.windows(2).map(|p| font.kern(p[0], p[1])).sum::<f32>();
        assert_eq!(text_width(text, 2), advances.ceil() as u32);
        let mut previous = 0;
        for end in 1..=text.chars().count() {
            let prefix: String = text.chars().take(end).collect();
            let width = text_width(&prefix, 1);
            assert!(width > previous || prefix.ends_with(' ') && width >= previous, "{prefix:?}");
            previous = width;
        }
        assert_eq!(text_width("", 3), 0);
        assert!(text_width("iiii", 1) < text_width("WWWW", 1), "spacing is proportional");
        assert!(text_width("WWWW", 2).abs_diff(2 * text_width("WWWW", 1)) <= 1);
    }

    #[test]
    fn wrapping_respects_the_pixel_width() {
        let caption = "constant(bias_depth=0.001) err 1.23% slope_scaled_with_a_very_long_name";
        for max_width in [30, 60, 100, 160, 400] {
            let lines = wrap(caption, max_width, 1);
            for line in &lines {
                assert!(text_width(line, 1) <= max_width, "{line:?} is wider than {max_width}");
            }
            // Nothing is lost: the lines are the caption cut at spaces or inside words.
            assert_eq!(lines.concat().replace(' ', ""), caption.replace(' ', ""));
        }
        let lines = wrap(caption, 160, 1);
        assert_eq!(lines[0], "constant(bias_depth=0.001) err");
        assert_eq!(wrap("short", 200, 1), ["short"]);
        assert_eq!(wrap("", 5, 1), [""]);
        // A width narrower than any character still gives one character per line.
        assert_eq!(wrap("ab", 1, 1), ["a", "b"]);
    }

    #[test]
    fn drawing_writes_ink_only_inside_the_clip() {
        let text = "Hello, world² ×";
        let (ox, oy) = (20i64, 10i64);
        let whole = drawn(160, 40, 0, ox - 5, oy - 3, text, 200);
        assert!(whole.iter().filter(|&&p| p != 0).count() > 50);
        // The same text 5 pixels left and 3 up in a 60×20 image is the whole drawing's window.
        let clipped = drawn(60, 20, 0, -5, -3, text, 200);
        for y in 0..20 {
            for x in 0..60 {
                let window = whole[((y + oy) * 160 + x + ox) as usize];
                assert_eq!(clipped[(y * 60 + x) as usize], window, "({x}, {y})");
            }
        }
        // The ink stays near the line's box: the advance across, a line pitch down.
        let width = text_width(text, 1) as i64;
        for (i, &p) in whole.iter().enumerate() {
            let (x, y) = (i as i64 % 160, i as i64 / 160);
            if p != 0 {
                assert!((ox - 6..=ox - 5 + width + 1).contains(&x), "ink at column {x}");
                assert!((oy - 4..oy - 3 + LINE_PITCH as i64).contains(&y), "ink at row {y}");
            }
        }
        // Entirely outside: nothing is written.
        let mut pixels = vec![0u8; 100];
        assert_eq!(draw_text(&mut pixels, 10, 10, 50, 0, text, 1, 200), 0);
        assert_eq!(draw_text(&mut pixels, 10, 10, -500, 0, text, 1, 200), 0);
        assert_eq!(draw_text(&mut pixels, 10, 10, 0, 30, text, 1, 200), 0);
        assert!(pixels.iter().all(|&p| p == 0));
    }

    #[test]
    fn antialiased_edges_are_intermediate_greys() {
        let (background, ink) = (20u8, 230u8);
        let pixels = drawn(40, 20, background, 2, 2, "Ox/", ink);
        let between = pixels.iter().filter(|&&p| p > background && p < ink).count();
        assert!(between > 10, "only {between} intermediate greys");
        assert!(pixels.iter().all(|&p| (background..=ink).contains(&p) && p <= GREY_MAX));
        // Over an error colour there is no grey between: a pixel is the ink or the colour.
        let over_colour = drawn(40, 20, FALSE_LIT_INDEX, 2, 2, "Ox/", ink);
        assert!(over_colour.iter().all(|&p| p == FALSE_LIT_INDEX || p == ink));
        assert!(over_colour.contains(&ink));
    }

    #[test]
    fn the_same_text_draws_byte_identically_twice() {
        let text = "false shadow 1234 (0.56%) ≤ ·";
        assert_eq!(drawn(200, 20, 24, 3, 4, text, 235), drawn(200, 20, 24, 3, 4, text, 235));
        assert_ne!(drawn(200, 20, 24, 3, 4, text, 235), drawn(200, 20, 24, 4, 4, text, 235));
    }

    #[test]
    fn missing_characters_draw_as_question_marks() {
        let question = drawn(20, 12, 0, 1, 1, "?", 200);
        assert_eq!(drawn(20, 12, 0, 1, 1, "中", 200), question);
        assert_eq!(text_width("中", 1), text_width("?", 1));
        for c in ['²', '×', '·', '%', '≤'] {
            assert_ne!(drawn(20, 12, 0, 1, 1, &c.to_string(), 200), question, "{c:?} has its own glyph");
        }
    }
}
