//! Errors of fractional visibility against a fractional reference (docs/conventions.md, "Soft
//! errors"): the mean absolute error, the false-shadow mass Σ max(0, r − v) and the false-lit
//! mass Σ max(0, v − r), each per evaluated pixel. The hard counts of such a run threshold both
//! at ½ ([`thresholded`] then `score_hard`).

use crate::trace::{GBuffer, HardReference};
use serde::{Deserialize, Serialize};

#[derive(Clone, Copy, Debug, Default, PartialEq, Serialize, Deserialize)]
pub struct SoftErrors {
    /// Mean |v − r| over the evaluated pixels.
    pub mae: f64,
    /// Σ max(0, r − v) / evaluated: light the technique removed.
    pub false_shadow_mass: f64,
    /// Σ max(0, v − r) / evaluated: light the technique added.
    pub false_lit_mass: f64,
}

/// The soft errors of `visibility` (one value per evaluated pixel, in `gbuffer.evaluated` order)
/// against `reference` (one value per pixel). Summed in f64 in pixel order, so the result does
/// not depend on the thread count.
pub fn score_soft(gbuffer: &GBuffer, reference: &[f32], visibility: &[f32]) -> SoftErrors {
    assert_eq!(visibility.len(), gbuffer.evaluated.len(), "one visibility per evaluated pixel");
    assert_eq!(reference.len(), gbuffer.pixel_count(), "one reference value per pixel");
    let (mut shadow, mut lit) = (0.0f64, 0.0f64);
    for (&i, &v) in gbuffer.evaluated.iter().zip(visibility) {
        let d = v as f64 - reference[i as usize] as f64;
        if d > 0.0 {
            lit += d;
        } else {
            shadow -= d;
        }
    }
    let n = gbuffer.evaluated.len().max(1) as f64;
    SoftErrors { mae: (shadow + lit) / n, false_shadow_mass: shadow / n, false_lit_mass: lit / n }
}

/// A fractional reference thresholded at ½ (lit when r ≥ ½), for the hard counts and attribution.
pub fn thresholded(width: u32, height: u32, reference: &[f32]) -> HardReference {
    HardReference {
        width,
        height,
        lit: reference.iter().map(|&r| (r >= 0.5) as u8).collect(),
        uncertain: Vec::new(),
    }
}
