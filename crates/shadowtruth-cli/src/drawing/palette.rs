//! The one fixed palette every figure is drawn in: indices 0–[`GREY_MAX`] are greys of that
//! level, [`FALSE_SHADOW_INDEX`] and [`FALSE_LIT_INDEX`] the two error colours and
//! [`UNCERTAIN_INDEX`] the colour of the pixels the reference cannot decide.

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
}
