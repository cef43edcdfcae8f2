//! Flicker between two frames of the same surface points (docs/temporal.md): a point flickers
//! when the technique decides it differently in the two frames while the reference decides it
//! the same. Decisions are per camera pixel of the later frame: `NOT_SCORED`, `SHADOWED` or
//! `LIT` (the ½ threshold of `classify.rs`).

use crate::trace::{GBuffer, HardReference};

pub const NOT_SCORED: u8 = 0;
pub const SHADOWED: u8 = 1;
pub const LIT: u8 = 2;

/// The technique's decision at every pixel, from its visibility per evaluated pixel (NaN, a
/// surface mismatch, is not scored).
pub fn technique_decisions(gbuffer: &GBuffer, visibility: &[f32]) -> Vec<u8> {
    let mut out = vec![NOT_SCORED; gbuffer.pixel_count()];
    for (&i, &v) in gbuffer.evaluated.iter().zip(visibility) {
        if !v.is_nan() {
            out[i as usize] = if v >= 0.5 { LIT } else { SHADOWED };
        }
    }
    out
}

/// The reference's decision at every evaluated pixel.
pub fn reference_decisions(gbuffer: &GBuffer, reference: &HardReference) -> Vec<u8> {
    let mut out = vec![NOT_SCORED; gbuffer.pixel_count()];
    for &i in &gbuffer.evaluated {
        out[i as usize] = if reference.lit[i as usize] != 0 { LIT } else { SHADOWED };
    }
    out
}

/// The two frames' decisions of the same points, one per pixel of the later frame.
pub struct FrameDecisions<'a> {
    pub technique: &'a [u8],
    pub reference: &'a [u8],
}

/// Flickering points between `before` and `after` (each pixel's count in `heat` goes up by one),
/// and the points compared: those both frames score.
pub fn count_flicker(before: &FrameDecisions, after: &FrameDecisions, heat: &mut [u16]) -> (u64, u64) {
    let (mut flicker, mut compared) = (0u64, 0u64);
    let technique = before.technique.iter().zip(after.technique);
    let reference = before.reference.iter().zip(after.reference);
    for ((count, (&t0, &t1)), (&r0, &r1)) in heat.iter_mut().zip(technique).zip(reference) {
        if t0 == NOT_SCORED || t1 == NOT_SCORED || r0 == NOT_SCORED || r1 == NOT_SCORED {
            continue;
        }
        compared += 1;
        if t0 != t1 && r0 == r1 {
            flicker += 1;
            *count = count.saturating_add(1);
        }
    }
    (flicker, compared)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn only_technique_changes_the_reference_does_not_share_are_flicker() {
        // Pixels: steady; technique flips alone; both flip (a moving shadow); not scored before.
        let before =
            FrameDecisions { technique: &[LIT, LIT, LIT, NOT_SCORED], reference: &[LIT, LIT, LIT, LIT] };
        let after = FrameDecisions {
            technique: &[LIT, SHADOWED, SHADOWED, SHADOWED],
            reference: &[LIT, LIT, SHADOWED, LIT],
        };
        let mut heat = vec![0u16; 4];
        assert_eq!(count_flicker(&before, &after, &mut heat), (1, 3));
        assert_eq!(heat, vec![0, 1, 0, 0]);
    }
}
