//! The bundled DejaVu Sans (`assets/fonts/DejaVuSans.ttf`), the one typeface of every figure and
//! plot, so that no system font is needed and text draws the same on every machine.

use ab_glyph::FontRef;
use std::sync::LazyLock;

/// The TTF file's bytes, compiled into the binary.
pub const DEJAVU_SANS_TTF: &[u8] = include_bytes!("../../assets/fonts/DejaVuSans.ttf");

/// The parsed font, parsed once on first use.
pub fn dejavu_sans() -> &'static FontRef<'static> {
    static FONT: LazyLock<FontRef<'static>> =
        LazyLock::new(|| FontRef::try_from_slice(DEJAVU_SANS_TTF).expect("the bundled DejaVu Sans parses"));
    &FONT
}
