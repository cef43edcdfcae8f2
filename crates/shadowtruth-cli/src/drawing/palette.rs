//! The one colour code of every output, and the fixed palette every figure is drawn in.
//!
//! The colour code (Okabe & Ito, "Color Universal Design", 2008: told apart by colour-blind
//! readers): false shadow is vermillion, false lit blue and their total (the error) black, in
//! error maps, sweep and resolution plots, the `tune` plot and the page alike; pixels the
//! reference cannot decide are reddish purple. Series that are not an error rate (techniques,
//! settings) take the colours the code leaves free ([`SERIES`]).
//!
//! The palette of the error maps: indices 0–[`GREY_MAX`] are greys of that level,
//! [`FALSE_SHADOW_INDEX`] and [`FALSE_LIT_INDEX`] the two error colours and [`UNCERTAIN_INDEX`]
//! the colour of the pixels the reference cannot decide.

/// The lightest grey (and the page white of grids and zoom frames): levels above it are drawn as it.
pub const GREY_MAX: u8 = 252;
/// Palette index of the pixels the reference cannot decide beyond doubt (left out of the score).
pub const UNCERTAIN_INDEX: u8 = 253;
/// Palette index of false shadow.
pub const FALSE_SHADOW_INDEX: u8 = 254;
/// Palette index of false lit.
pub const FALSE_LIT_INDEX: u8 = 255;
/// False shadow (lit in truth, shadowed by the technique): Okabe–Ito vermillion.
pub const FALSE_SHADOW: [u8; 3] = [0xD5, 0x5E, 0x00];
/// False lit (shadowed in truth, lit by the technique): Okabe–Ito blue.
pub const FALSE_LIT: [u8; 3] = [0x00, 0x72, 0xB2];
/// Uncertain (the reference cannot decide the pixel, scored neither way): Okabe–Ito reddish purple.
pub const UNCERTAIN: [u8; 3] = [0xCC, 0x79, 0xA7];
/// The error, false shadow and false lit together: Okabe–Ito black.
pub const TOTAL_ERROR: [u8; 3] = [0x00, 0x00, 0x00];
/// The colours of series that are not an error rate: the Okabe–Ito colours the code leaves
/// free, the nearest to the error colours last.
pub const SERIES: [[u8; 3]; 6] = [
    [0x00, 0x9E, 0x73], // bluish green
    [0xE6, 0x9F, 0x00], // orange
    [0x56, 0xB4, 0xE9], // sky blue
    [0x66, 0x66, 0x66], // dark grey
    [0xF0, 0xE4, 0x42], // yellow
    [0xCC, 0x79, 0xA7], // reddish purple
];
/// A sweep's best value and the band of values near it: bluish green, as no rate is drawn.
pub const BEST: [u8; 3] = [0x00, 0x9E, 0x73];

/// The error map's colours in words and swatches, for the page (HTML).
pub(super) fn colour_code_legend() -> String {
    let swatch = |[r, g, b]: [u8; 3], what: &str| {
        format!("<span style=\"color:#{r:02X}{g:02X}{b:02X}\">&#9632;</span> {what}")
    };
    format!(
        "The error map shows {}, {} and {} (pixels the reference cannot decide)",
        swatch(FALSE_SHADOW, "false shadow"),
        swatch(FALSE_LIT, "false lit"),
        swatch(UNCERTAIN, "uncertain")
    )
}

/// The nearest colour of the xterm 256-colour cube (indices 16–231), which terminals without
/// 24-bit colour show too. By hand: six levels a channel, too small for a crate.
pub fn terminal_colour(rgb: [u8; 3]) -> u8 {
    const LEVELS: [u8; 6] = [0, 95, 135, 175, 215, 255];
    let level = |c: u8| (0..6).min_by_key(|&k| LEVELS[k].abs_diff(c)).expect("six levels") as u8;
    let [r, g, b] = rgb.map(level);
    16 + 36 * r + 6 * g + b
}

/// The colour of a series named for an error rate ("false shadow", "false lit", or "error",
/// alone or followed by a space and more words), or `None` for any other series.
pub fn rate_colour(series: &str) -> Option<[u8; 3]> {
    match series {
        "false shadow" => Some(FALSE_SHADOW),
        "false lit" => Some(FALSE_LIT),
        _ if series == "error" || series.starts_with("error ") => Some(TOTAL_ERROR),
        _ => None,
    }
}

/// The RGB colour of palette index `index`.
pub const fn palette_rgb(index: u8) -> [u8; 3] {
    match index {
        FALSE_SHADOW_INDEX => FALSE_SHADOW,
        FALSE_LIT_INDEX => FALSE_LIT,
        UNCERTAIN_INDEX => UNCERTAIN,
        g => [g, g, g],
    }
}

/// The whole palette as a PNG `PLTE` chunk holds it: 256 RGB triples in index order.
pub fn palette_bytes() -> Vec<u8> {
    (0..=255u8).flat_map(palette_rgb).collect()
}

/// Whether `index` is one of the greys (not an error colour nor the uncertain one).
pub const fn is_grey(index: u8) -> bool {
    index <= GREY_MAX
}

/// A grey index for a level in [0, 1] (clamped; levels above [`GREY_MAX`]/255 draw as it).
pub fn grey(level: f32) -> u8 {
    ((level.clamp(0.0, 1.0) * 255.0 + 0.5) as u8).min(GREY_MAX)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// xterm's cube: vermillion #D55E00 is nearest #D75F00 (166), blue #0072B2 nearest #005FAF (25).
    #[test]
    fn the_error_colours_keep_their_hue_in_a_256_colour_terminal() {
        assert_eq!(terminal_colour(FALSE_SHADOW), 166);
        assert_eq!(terminal_colour(FALSE_LIT), 25);
        assert_eq!(terminal_colour([0, 0, 0]), 16);
        assert_eq!(terminal_colour([255, 255, 255]), 231);
    }

    #[test]
    fn palette_holds_the_greys_and_three_colours() {
        assert_eq!(palette_rgb(0), [0, 0, 0]);
        assert_eq!(palette_rgb(GREY_MAX), [GREY_MAX; 3]);
        assert_eq!(palette_rgb(FALSE_SHADOW_INDEX), FALSE_SHADOW);
        assert_eq!(palette_rgb(FALSE_LIT_INDEX), FALSE_LIT);
        assert_eq!(palette_rgb(UNCERTAIN_INDEX), UNCERTAIN);
        assert!(is_grey(GREY_MAX) && !is_grey(FALSE_SHADOW_INDEX) && !is_grey(FALSE_LIT_INDEX));
        assert!(!is_grey(UNCERTAIN_INDEX));
        assert_eq!(grey(1.0), GREY_MAX);
        assert_eq!(grey(0.5), 128);
    }

    #[test]
    fn rates_have_their_colours_and_other_series_never_take_them() {
        assert_eq!(rate_colour("false shadow"), Some(FALSE_SHADOW));
        assert_eq!(rate_colour("false lit"), Some(FALSE_LIT));
        assert_eq!(rate_colour("error"), Some(TOTAL_ERROR));
        assert_eq!(rate_colour("error (the objective)"), Some(TOTAL_ERROR));
        assert_eq!(rate_colour("false shadow + 2·false lit"), None);
        assert_eq!(rate_colour("constant bias_depth=0.001"), None);
        for code in [FALSE_SHADOW, FALSE_LIT, TOTAL_ERROR] {
            assert!(!SERIES.contains(&code) && BEST != code);
        }
    }
}
