//! Classification of every pixel: the classes of the G-buffer, and on evaluated pixels the false
//! shadow (reference lit, technique shadowed: acne, self-shadowing) and false lit (reference
//! shadowed, technique lit: leaks, peter-panning) with the ½ threshold of docs/conventions.md,
//! "False shadow and false lit".

use crate::trace::{GBuffer, HardReference, PixelClass};
use serde::{Deserialize, Serialize};

#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Serialize, Deserialize)]
pub struct Counts {
    pub pixels: u64,
    pub background: u64,
    pub facing_away: u64,
    pub outside_light: u64,
    pub evaluated: u64,
    /// Pixels the reference cannot decide beyond doubt (`PixelClass::Uncertain`): left out of
    /// every score, not part of `evaluated`, counted here so that a report shows them.
    #[serde(default)]
    pub uncertain: u64,
    pub false_shadow: u64,
    pub false_lit: u64,
    /// False pixels within one texel footprint of a reference shadow boundary (see
    /// `attribution`); 0 until `Counts::with_attribution` fills them in.
    #[serde(default)]
    pub aliasing: u64,
    /// Other false pixels that a point light's map shades near a seam of its faces (see
    /// `attribution`); 0 under other lights.
    #[serde(default)]
    pub seam: u64,
    /// Other false shadows.
    #[serde(default)]
    pub acne: u64,
    /// Other false lits, where one occluder shadows the pixel.
    #[serde(default)]
    pub leak: u64,
    /// Other false lits, where occluders of two objects overlap in the light's view
    /// (`trace::ShadowOverlap`): a filterable map's light bleeding. 0 when the run's attribution
    /// was not told where occluders overlap (they are then leaks).
    #[serde(default)]
    pub light_bleeding: u64,
    /// Evaluated pixels where an imported buffer shows another surface than the reference (its
    /// background, or a depth beyond the tolerance): left out of every other score. Always 0
    /// for the built-in techniques, and then not written.
    #[serde(default, skip_serializing_if = "is_zero")]
    pub surface_mismatch: u64,
}

fn is_zero(n: &u64) -> bool {
    *n == 0
}

#[derive(Clone, Copy, Debug, Default, PartialEq, Serialize, Deserialize)]
pub struct Rates {
    pub false_shadow: f64,
    pub false_lit: f64,
    pub error: f64,
}

impl Counts {
    /// Rates as fractions of the scored pixels: evaluated less surface mismatches (0 when none
    /// is scored).
    pub fn rates(&self) -> Rates {
        let n = self.scored().max(1) as f64;
        Rates {
            false_shadow: self.false_shadow as f64 / n,
            false_lit: self.false_lit as f64 / n,
            error: (self.false_shadow + self.false_lit) as f64 / n,
        }
    }
}

impl Counts {
    /// Adds every count of `other` (the frames of a path).
    pub fn add(&mut self, other: &Counts) {
        // Destructured so that a new field cannot be left out.
        let Counts {
            pixels,
            background,
            facing_away,
            outside_light,
            evaluated,
            uncertain,
            false_shadow,
            false_lit,
            aliasing,
            seam,
            acne,
            leak,
            light_bleeding,
            surface_mismatch,
        } = *other;
        self.pixels += pixels;
        self.background += background;
        self.facing_away += facing_away;
        self.outside_light += outside_light;
        self.evaluated += evaluated;
        self.uncertain += uncertain;
        self.false_shadow += false_shadow;
        self.false_lit += false_lit;
        self.aliasing += aliasing;
        self.seam += seam;
        self.acne += acne;
        self.leak += leak;
        self.light_bleeding += light_bleeding;
        self.surface_mismatch += surface_mismatch;
    }

    /// The pixels the rates are over: evaluated, less the surface mismatches.
    pub fn scored(&self) -> u64 {
        self.evaluated.saturating_sub(self.surface_mismatch)
    }
}

/// Scores `visibility` (one value per evaluated pixel, in `gbuffer.evaluated` order) against the
/// hard reference. A NaN marks a surface mismatch (an imported buffer showing another surface,
/// `crate::import`): counted as such and scored neither way. The attribution fields stay 0 (see
/// `attribution::attribute`). Panics if `gbuffer` still evaluates a pixel the reference lists
/// as uncertain: `GBuffer::leave_out` (or `trace_scored_view`) takes them out first.
pub fn score_hard(gbuffer: &GBuffer, reference: &HardReference, visibility: &[f32]) -> Counts {
    assert_eq!(visibility.len(), gbuffer.evaluated.len(), "one visibility per evaluated pixel");
    if let Some(i) = reference.uncertain_still_evaluated(gbuffer) {
        panic!("pixel {i} is uncertain in the reference but still evaluated: leave it out first");
    }
    let mut c = Counts { pixels: gbuffer.pixel_count() as u64, ..Counts::default() };
    for class in &gbuffer.class {
        match class {
            PixelClass::Background => c.background += 1,
            PixelClass::FacingAway => c.facing_away += 1,
            PixelClass::OutsideLight => c.outside_light += 1,
            PixelClass::Evaluated => c.evaluated += 1,
            PixelClass::Uncertain => c.uncertain += 1,
        }
    }
    add_false_counts(&mut c, gbuffer, reference, visibility);
    c
}

/// Adds the false shadows, false lits and surface mismatches of `visibility` to `c`: what
/// changes from one technique to the next on the same view.
pub fn add_false_counts(c: &mut Counts, gbuffer: &GBuffer, reference: &HardReference, visibility: &[f32]) {
    for (&i, &v) in gbuffer.evaluated.iter().zip(visibility) {
        if v.is_nan() {
            c.surface_mismatch += 1;
            continue;
        }
        let (false_shadow, false_lit) = falseness(reference.lit[i as usize] != 0, v);
        c.false_shadow += false_shadow as u64;
        c.false_lit += false_lit as u64;
    }
}

/// Whether visibility `v` of a pixel the reference sees lit (`reference_lit`) or not is a false
/// shadow, and whether it is a false lit: the ½ threshold.
#[inline]
pub fn falseness(reference_lit: bool, v: f32) -> (bool, bool) {
    let v_lit = v >= 0.5;
    (reference_lit && !v_lit, !reference_lit && v_lit)
}
