//! A hand-drawn 5×7 bitmap font for captions and legends: printable ASCII 32–126 plus `²`, drawn
//! into RGB8 images with an integer scale. No font files, no system fonts.
//!
//! Each glyph is seven rows of five bits, top row first, bit 4 the leftmost column. Glyphs sit in
//! a 6×9 cell (one column and two rows of spacing); characters outside the table draw as `?`.

/// Glyph width in font pixels.
pub const GLYPH_WIDTH: u32 = 5;
/// Glyph height in font pixels.
pub const GLYPH_HEIGHT: u32 = 7;
/// Horizontal advance per character in font pixels (glyph and one column of spacing).
pub const ADVANCE: u32 = 6;
/// Line pitch in font pixels (glyph and two rows of spacing).
pub const LINE_HEIGHT: u32 = 9;

#[rustfmt::skip]
const ASCII: [[u8; 7]; 95] = [
    [0b00000, 0b00000, 0b00000, 0b00000, 0b00000, 0b00000, 0b00000], // ' '
    [0b00100, 0b00100, 0b00100, 0b00100, 0b00100, 0b00000, 0b00100], // !
    [0b01010, 0b01010, 0b01010, 0b00000, 0b00000, 0b00000, 0b00000], // "
    [0b01010, 0b01010, 0b11111, 0b01010, 0b11111, 0b01010, 0b01010], // #
    [0b00100, 0b01111, 0b10100, 0b01110, 0b00101, 0b11110, 0b00100], // $
    [0b11000, 0b11001, 0b00010, 0b00100, 0b01000, 0b10011, 0b00011], // %
    [0b01100, 0b10010, 0b10100, 0b01000, 0b10101, 0b10010, 0b01101], // &
    [0b00100, 0b00100, 0b01000, 0b00000, 0b00000, 0b00000, 0b00000], // '
    [0b00010, 0b00100, 0b01000, 0b01000, 0b01000, 0b00100, 0b00010], // (
    [0b01000, 0b00100, 0b00010, 0b00010, 0b00010, 0b00100, 0b01000], // )
    [0b00000, 0b00100, 0b10101, 0b01110, 0b10101, 0b00100, 0b00000], // *
    [0b00000, 0b00100, 0b00100, 0b11111, 0b00100, 0b00100, 0b00000], // +
    [0b00000, 0b00000, 0b00000, 0b00000, 0b01100, 0b00100, 0b01000], // ,
    [0b00000, 0b00000, 0b00000, 0b11111, 0b00000, 0b00000, 0b00000], // -
    [0b00000, 0b00000, 0b00000, 0b00000, 0b00000, 0b01100, 0b01100], // .
    [0b00000, 0b00001, 0b00010, 0b00100, 0b01000, 0b10000, 0b00000], // /
    [0b01110, 0b10001, 0b10011, 0b10101, 0b11001, 0b10001, 0b01110], // 0
    [0b00100, 0b01100, 0b00100, 0b00100, 0b00100, 0b00100, 0b01110], // 1
    [0b01110, 0b10001, 0b00001, 0b00010, 0b00100, 0b01000, 0b11111], // 2
    [0b11111, 0b00010, 0b00100, 0b00010, 0b00001, 0b10001, 0b01110], // 3
    [0b00010, 0b00110, 0b01010, 0b10010, 0b11111, 0b00010, 0b00010], // 4
    [0b11111, 0b10000, 0b11110, 0b00001, 0b00001, 0b10001, 0b01110], // 5
    [0b00110, 0b01000, 0b10000, 0b11110, 0b10001, 0b10001, 0b01110], // 6
    [0b11111, 0b00001, 0b00010, 0b00100, 0b01000, 0b01000, 0b01000], // 7
    [0b01110, 0b10001, 0b10001, 0b01110, 0b10001, 0b10001, 0b01110], // 8
    [0b01110, 0b10001, 0b10001, 0b01111, 0b00001, 0b00010, 0b01100], // 9
    [0b00000, 0b01100, 0b01100, 0b00000, 0b01100, 0b01100, 0b00000], // :
    [0b00000, 0b01100, 0b01100, 0b00000, 0b01100, 0b00100, 0b01000], // ;
    [0b00010, 0b00100, 0b01000, 0b10000, 0b01000, 0b00100, 0b00010], // <
    [0b00000, 0b00000, 0b11111, 0b00000, 0b11111, 0b00000, 0b00000], // =
    [0b01000, 0b00100, 0b00010, 0b00001, 0b00010, 0b00100, 0b01000], // >
    [0b01110, 0b10001, 0b00001, 0b00010, 0b00100, 0b00000, 0b00100], // ?
    [0b01110, 0b10001, 0b00001, 0b01101, 0b10101, 0b10101, 0b01110], // @
    [0b01110, 0b10001, 0b10001, 0b11111, 0b10001, 0b10001, 0b10001], // A
    [0b11110, 0b10001, 0b10001, 0b11110, 0b10001, 0b10001, 0b11110], // B
    [0b01110, 0b10001, 0b10000, 0b10000, 0b10000, 0b10001, 0b01110], // C
    [0b11100, 0b10010, 0b10001, 0b10001, 0b10001, 0b10010, 0b11100], // D
    [0b11111, 0b10000, 0b10000, 0b11110, 0b10000, 0b10000, 0b11111], // E
    [0b11111, 0b10000, 0b10000, 0b11110, 0b10000, 0b10000, 0b10000], // F
    [0b01110, 0b10001, 0b10000, 0b10111, 0b10001, 0b10001, 0b01111], // G
    [0b10001, 0b10001, 0b10001, 0b11111, 0b10001, 0b10001, 0b10001], // H
    [0b01110, 0b00100, 0b00100, 0b00100, 0b00100, 0b00100, 0b01110], // I
    [0b00111, 0b00010, 0b00010, 0b00010, 0b00010, 0b10010, 0b01100], // J
    [0b10001, 0b10010, 0b10100, 0b11000, 0b10100, 0b10010, 0b10001], // K
    [0b10000, 0b10000, 0b10000, 0b10000, 0b10000, 0b10000, 0b11111], // L
    [0b10001, 0b11011, 0b10101, 0b10101, 0b10001, 0b10001, 0b10001], // M
    [0b10001, 0b10001, 0b11001, 0b10101, 0b10011, 0b10001, 0b10001], // N
    [0b01110, 0b10001, 0b10001, 0b10001, 0b10001, 0b10001, 0b01110], // O
    [0b11110, 0b10001, 0b10001, 0b11110, 0b10000, 0b10000, 0b10000], // P
    [0b01110, 0b10001, 0b10001, 0b10001, 0b10101, 0b10010, 0b01101], // Q
    [0b11110, 0b10001, 0b10001, 0b11110, 0b10100, 0b10010, 0b10001], // R
    [0b01111, 0b10000, 0b10000, 0b01110, 0b00001, 0b00001, 0b11110], // S
    [0b11111, 0b00100, 0b00100, 0b00100, 0b00100, 0b00100, 0b00100], // T
    [0b10001, 0b10001, 0b10001, 0b10001, 0b10001, 0b10001, 0b01110], // U
    [0b10001, 0b10001, 0b10001, 0b10001, 0b10001, 0b01010, 0b00100], // V
    [0b10001, 0b10001, 0b10001, 0b10101, 0b10101, 0b10101, 0b01010], // W
    [0b10001, 0b10001, 0b01010, 0b00100, 0b01010, 0b10001, 0b10001], // X
    [0b10001, 0b10001, 0b10001, 0b01010, 0b00100, 0b00100, 0b00100], // Y
    [0b11111, 0b00001, 0b00010, 0b00100, 0b01000, 0b10000, 0b11111], // Z
    [0b01110, 0b01000, 0b01000, 0b01000, 0b01000, 0b01000, 0b01110], // [
    [0b00000, 0b10000, 0b01000, 0b00100, 0b00010, 0b00001, 0b00000], // backslash
    [0b01110, 0b00010, 0b00010, 0b00010, 0b00010, 0b00010, 0b01110], // ]
    [0b00100, 0b01010, 0b10001, 0b00000, 0b00000, 0b00000, 0b00000], // ^
    [0b00000, 0b00000, 0b00000, 0b00000, 0b00000, 0b00000, 0b11111], // _
    [0b01000, 0b00100, 0b00010, 0b00000, 0b00000, 0b00000, 0b00000], // `
    [0b00000, 0b00000, 0b01110, 0b00001, 0b01111, 0b10001, 0b01111], // a
    [0b10000, 0b10000, 0b10110, 0b11001, 0b10001, 0b10001, 0b11110], // b
    [0b00000, 0b00000, 0b01110, 0b10000, 0b10000, 0b10001, 0b01110], // c
    [0b00001, 0b00001, 0b01101, 0b10011, 0b10001, 0b10001, 0b01111], // d
    [0b00000, 0b00000, 0b01110, 0b10001, 0b11111, 0b10000, 0b01110], // e
    [0b00110, 0b01001, 0b01000, 0b11100, 0b01000, 0b01000, 0b01000], // f
    [0b00000, 0b01111, 0b10001, 0b10001, 0b01111, 0b00001, 0b01110], // g
    [0b10000, 0b10000, 0b10110, 0b11001, 0b10001, 0b10001, 0b10001], // h
    [0b00100, 0b00000, 0b01100, 0b00100, 0b00100, 0b00100, 0b01110], // i
    [0b00010, 0b00000, 0b00110, 0b00010, 0b00010, 0b10010, 0b01100], // j
    [0b10000, 0b10000, 0b10010, 0b10100, 0b11000, 0b10100, 0b10010], // k
    [0b01100, 0b00100, 0b00100, 0b00100, 0b00100, 0b00100, 0b01110], // l
    [0b00000, 0b00000, 0b11010, 0b10101, 0b10101, 0b10001, 0b10001], // m
    [0b00000, 0b00000, 0b10110, 0b11001, 0b10001, 0b10001, 0b10001], // n
    [0b00000, 0b00000, 0b01110, 0b10001, 0b10001, 0b10001, 0b01110], // o
    [0b00000, 0b00000, 0b11110, 0b10001, 0b11110, 0b10000, 0b10000], // p
    [0b00000, 0b00000, 0b01101, 0b10011, 0b01111, 0b00001, 0b00001], // q
    [0b00000, 0b00000, 0b10110, 0b11001, 0b10000, 0b10000, 0b10000], // r
    [0b00000, 0b00000, 0b01110, 0b10000, 0b01110, 0b00001, 0b11110], // s
    [0b01000, 0b01000, 0b11100, 0b01000, 0b01000, 0b01001, 0b00110], // t
    [0b00000, 0b00000, 0b10001, 0b10001, 0b10001, 0b10011, 0b01101], // u
    [0b00000, 0b00000, 0b10001, 0b10001, 0b10001, 0b01010, 0b00100], // v
    [0b00000, 0b00000, 0b10001, 0b10001, 0b10101, 0b10101, 0b01010], // w
    [0b00000, 0b00000, 0b10001, 0b01010, 0b00100, 0b01010, 0b10001], // x
    [0b00000, 0b00000, 0b10001, 0b10001, 0b01111, 0b00001, 0b01110], // y
    [0b00000, 0b00000, 0b11111, 0b00010, 0b00100, 0b01000, 0b11111], // z
    [0b00010, 0b00100, 0b00100, 0b01000, 0b00100, 0b00100, 0b00010], // {
    [0b00100, 0b00100, 0b00100, 0b00100, 0b00100, 0b00100, 0b00100], // |
    [0b01000, 0b00100, 0b00100, 0b00010, 0b00100, 0b00100, 0b01000], // }
    [0b00000, 0b00000, 0b01000, 0b10101, 0b00010, 0b00000, 0b00000], // ~
];

#[rustfmt::skip]
const SUPERSCRIPT_TWO: [u8; 7] = [0b01100, 0b00010, 0b00100, 0b01110, 0b00000, 0b00000, 0b00000];

/// The rows of `c`'s glyph (`?` for characters the font lacks).
pub fn glyph(c: char) -> &'static [u8; 7] {
    match c {
        ' '..='~' => &ASCII[c as usize - 32],
        '²' => &SUPERSCRIPT_TWO,
        _ => &ASCII['?' as usize - 32],
    }
}

/// Width in image pixels of one line of `text` (no trailing spacing column).
pub fn text_width(text: &str, scale: u32) -> u32 {
    let n = text.chars().count() as u32;
    (n * ADVANCE).saturating_sub(1) * scale
}

/// Height in image pixels of one line of text (the glyph, without line spacing).
pub fn text_height(scale: u32) -> u32 {
    GLYPH_HEIGHT * scale
}

/// How many characters fit on a line `width` image pixels wide.
pub fn chars_per_line(width: u32, scale: u32) -> usize {
    ((width / scale.max(1) + 1) / ADVANCE) as usize
}

/// Draws one line of `text` into a one-byte-per-pixel image of `width`×`height` with its
/// top-left corner at (`x`, `y`), each font pixel a `scale`×`scale` square of `value`; clipped to
/// the image. Returns the number of image pixels written.
#[allow(clippy::too_many_arguments)]
pub fn draw_text(
    pixels: &mut [u8],
    width: u32,
    height: u32,
    x: i64,
    y: i64,
    text: &str,
    scale: u32,
    value: u8,
) -> usize {
    let scale = scale.max(1) as i64;
    let (w, h) = (width as i64, height as i64);
    let mut written = 0;
    for (k, c) in text.chars().enumerate() {
        let gx = x + k as i64 * ADVANCE as i64 * scale;
        if gx >= w {
            break;
        }
        let rows = glyph(c);
        for (row, &bits) in rows.iter().enumerate() {
            if bits == 0 {
                continue;
            }
            for col in 0..GLYPH_WIDTH as i64 {
                if bits >> (GLYPH_WIDTH as i64 - 1 - col) & 1 == 0 {
                    continue;
                }
                let (x0, y0) = (gx + col * scale, y + row as i64 * scale);
                for py in y0.max(0)..(y0 + scale).min(h) {
                    let (a, b) = (x0.max(0), (x0 + scale).min(w));
                    if a < b {
                        pixels[(py * w + a) as usize..(py * w + b) as usize].fill(value);
                        written += (b - a) as usize;
                    }
                }
            }
        }
    }
    written
}

/// Splits `text` into lines of at most `max_chars` characters, breaking at spaces where it can
/// and inside words where it must.
pub fn wrap(text: &str, max_chars: usize) -> Vec<String> {
    let max_chars = max_chars.max(1);
    let mut lines = Vec::new();
    let mut line = String::new();
    let mut line_len = 0usize;
    for word in text.split(' ') {
        let word_len = word.chars().count();
        let needed = if line_len == 0 { word_len } else { line_len + 1 + word_len };
        if needed <= max_chars {
            if line_len > 0 {
                line.push(' ');
            }
            line.push_str(word);
            line_len = needed;
            continue;
        }
        if line_len > 0 {
            lines.push(std::mem::take(&mut line));
            line_len = 0;
        }
        let chars: Vec<char> = word.chars().collect();
        let mut pieces = chars.chunks(max_chars).peekable();
        while let Some(piece) = pieces.next() {
            if pieces.peek().is_some() {
                lines.push(piece.iter().collect());
            } else {
                line = piece.iter().collect();
                line_len = piece.len();
            }
        }
    }
    if line_len > 0 || lines.is_empty() {
        lines.push(line);
    }
    lines
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn every_printable_character_but_space_has_ink_and_fits_the_cell() {
        for c in (33u8..=126).map(char::from).chain(['²']) {
            let g = glyph(c);
            assert!(g.iter().any(|&r| r != 0), "{c:?} is blank");
            assert!(g.iter().all(|&r| r < 1 << GLYPH_WIDTH), "{c:?} is wider than the cell");
        }
        assert!(glyph(' ').iter().all(|&r| r == 0));
    }

    #[test]
    fn glyphs_are_distinct() {
        let all: Vec<char> = (32u8..=126).map(char::from).chain(['²']).collect();
        for (i, a) in all.iter().enumerate() {
            for b in &all[i + 1..] {
                assert_ne!(glyph(*a), glyph(*b), "{a:?} and {b:?} draw the same");
            }
        }
    }

    #[test]
    fn unknown_characters_draw_as_question_marks() {
        assert_eq!(glyph('é'), glyph('?'));
    }

    #[test]
    fn drawing_is_scaled_and_clipped() {
        let (w, h) = (40u32, 20u32);
        let mut img = vec![0u8; (w * h) as usize];
        let n = draw_text(&mut img, w, h, 0, 0, "I", 2, 9);
        let ink: u32 = glyph('I').iter().map(|r| r.count_ones()).sum();
        assert_eq!(n as u32, ink * 4);
        assert_eq!(img.iter().filter(|&&p| p == 9).count(), n);
        // The top bar of `I` covers columns 1..4 of the glyph, i.e. pixels 2..8 at scale 2.
        assert_eq!(img[..2], [0, 0]);
        assert_eq!(img[2..8], [9; 6]);
        assert_eq!(img[8], 0);
        // Drawing off the edges writes only what is inside.
        let mut img = vec![0u8; (w * h) as usize];
        let clipped = draw_text(&mut img, w, h, -3, -3, "Hello, world", 1, 7);
        assert!(clipped > 0);
        assert_eq!(img.iter().filter(|&&p| p == 7).count(), clipped);
    }

    #[test]
    fn width_and_wrapping() {
        assert_eq!(text_width("abc", 1), 17);
        assert_eq!(text_width("abc", 2), 34);
        assert_eq!(text_width("", 3), 0);
        assert_eq!(chars_per_line(17, 1), 3);
        assert_eq!(chars_per_line(16, 1), 2);
        assert_eq!(wrap("constant(bias_depth=0.001)  err 1.23%", 20).len(), 2);
        for line in wrap("constant(bias_depth=0.001)  err 1.23%", 20) {
            assert!(line.chars().count() <= 20, "{line:?}");
        }
        assert_eq!(wrap("short", 20), vec!["short".to_string()]);
        assert_eq!(wrap("", 5), vec![String::new()]);
    }
}
