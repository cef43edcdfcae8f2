//! The papers' claims as numbers: each claim has an id, its paper, its statement, the set-up that
//! follows the paper, the rule that decides it, the numbers we measured, a verdict, and the same
//! rule over a few other set-ups the paper leaves open (its sensitivity). A claim that does not
//! hold is a finding, reported as such.
//!
//! Rules count the artefact classes the papers name: acne (false shadow away from any true shadow
//! edge), leak and detachment (false lit away from any true shadow edge), as
//! `metrics::attribution` separates them. Outline aliasing (errors within one texel of a true
//! shadow edge, which every shadow map has) is reported beside them, never counted against a
//! technique. Thresholds are fixed here, before measuring, and printed with every claim.

use serde::Serialize;
use serde_json::{Map, Value, json};

#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize)]
#[serde(rename_all = "snake_case")]
pub enum Verdict {
    Holds,
    Partly,
    DoesNotHold,
}

impl Verdict {
    /// Holds when every part holds, partly when some do, does not hold when none does.
    pub fn of_parts(parts: &[bool]) -> Verdict {
        match parts.iter().filter(|&&p| p).count() {
            n if n == parts.len() => Verdict::Holds,
            0 => Verdict::DoesNotHold,
            _ => Verdict::Partly,
        }
    }

    pub fn name(self) -> &'static str {
        match self {
            Verdict::Holds => "holds",
            Verdict::Partly => "partly",
            Verdict::DoesNotHold => "does_not_hold",
        }
    }
}

/// One set-up of a claim: what was chosen, what was measured, and the rule's verdict on it.
#[derive(Clone, Debug, Serialize)]
pub struct SetupResult {
    pub setup: String,
    pub numbers: Map<String, Value>,
    pub verdict: Verdict,
}

impl SetupResult {
    pub fn new(setup: impl Into<String>, numbers: Value, verdict: Verdict) -> Self {
        let numbers = match numbers {
            Value::Object(m) => m,
            other => Map::from_iter([("value".to_string(), other)]),
        };
        SetupResult { setup: setup.into(), numbers, verdict }
    }
}

/// What a claim says, before anything is measured.
pub struct ClaimText {
    pub id: String,
    pub paper: &'static str,
    pub statement: &'static str,
    /// The paper's set-up as we reproduce it, with the sentence of the paper it follows.
    pub setup: &'static str,
    pub rule: &'static str,
}

#[derive(Clone, Debug, Serialize)]
pub struct Claim {
    pub id: String,
    pub paper: String,
    pub statement: String,
    pub setup: String,
    /// How the verdict is decided from the numbers.
    pub rule: String,
    /// The numbers and verdict of the paper's set-up (the first of `sensitivity`).
    pub numbers: Map<String, Value>,
    pub verdict: Verdict,
    /// The same rule over the paper's set-up and the others tried.
    pub sensitivity: Vec<SetupResult>,
    /// "holds in X of Y set-ups; partly in P; does not hold in N".
    pub sensitivity_summary: String,
    /// Figure files (relative to the report folder) that show the claim.
    pub figures: Vec<String>,
}

impl Claim {
    /// The claim judged on `setups`, the paper's set-up first.
    pub fn judged(text: ClaimText, setups: Vec<SetupResult>, figures: Vec<String>) -> Claim {
        let first = setups.first().expect("every claim has the paper's set-up");
        Claim {
            id: text.id,
            paper: text.paper.into(),
            statement: text.statement.into(),
            setup: text.setup.into(),
            rule: text.rule.into(),
            numbers: first.numbers.clone(),
            verdict: first.verdict,
            sensitivity_summary: sensitivity_summary(&setups),
            sensitivity: setups,
            figures,
        }
    }
}

/// "holds in X of Y set-ups; partly in P; does not hold in N".
pub fn sensitivity_summary(setups: &[SetupResult]) -> String {
    let count = |v: Verdict| setups.iter().filter(|s| s.verdict == v).count();
    format!(
        "holds in {} of {} set-ups; partly in {}; does not hold in {}",
        count(Verdict::Holds),
        setups.len(),
        count(Verdict::Partly),
        count(Verdict::DoesNotHold)
    )
}

/// "Few errors": acne + leak at most this fraction of the evaluated pixels.
pub const FEW_ERRORS: f64 = 0.005;
/// "Notable acne": at least this fraction of the evaluated pixels…
pub const NOTABLE_ACNE: f64 = 0.005;
/// …and at least this many times the other camera's.
pub const NOTABLE_RATIO: f64 = 4.0;
/// "Detachment at the tree trunks": at least this many leak pixels at their feet…
pub const DETACHMENT_PIXELS: u64 = 10;
/// …the ground within this distance of a trunk's axis, in metres (trunks are 3.5–5.5 cm in
/// radius; K = 0.01 tolerates 17 cm of depth on the island).
pub const TRUNK_FOOT_RADIUS_M: f32 = 0.25;
/// Two visibilities differ when they differ by more than this (one PCF tap of 121 is 0.008).
pub const DIFFERENT_VISIBILITY: f32 = 1e-6;
/// "No differences": at most this fraction of the cast-shadow pixels differ (holds)…
pub const NO_DIFFERENCE_SHARE: f64 = 1e-4;
/// …at most this fraction (partly).
pub const FEW_DIFFERENCES_SHARE: f64 = 1e-3;
/// Δbias stays "close" to receiver-plane cost: at most this ratio.
pub const DELTA_COST_CAP: f64 = 1.5;
/// "Comparable" edges: mean |v₃ − v₁| along the edge at most two of the 4×4 filter's sixteenths.
pub const COMPARABLE_EDGE_DIFFERENCE: f64 = 0.125;
/// An artefact class "shows" on the L when it covers at least this fraction of the L's
/// evaluated pixels.
pub const ARTEFACT_SHARE: f64 = 0.005;

/// Counts of one run on one view (or region), by class.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Serialize)]
pub struct Artefacts {
    pub evaluated: u64,
    pub acne: u64,
    pub leak: u64,
    /// Reported, not counted against a technique.
    pub aliasing: u64,
}

impl Artefacts {
    fn rate(&self, n: u64) -> f64 {
        n as f64 / self.evaluated.max(1) as f64
    }

    pub fn acne_rate(&self) -> f64 {
        self.rate(self.acne)
    }

    pub fn leak_rate(&self) -> f64 {
        self.rate(self.leak)
    }

    /// Acne and leak together, per evaluated pixel.
    pub fn error_rate(&self) -> f64 {
        self.rate(self.acne + self.leak)
    }

    pub fn json(&self) -> Value {
        json!({
            "evaluated": self.evaluated, "acne": self.acne, "leak": self.leak, "aliasing": self.aliasing,
            "acne_rate": self.acne_rate(), "leak_rate": self.leak_rate(), "error_rate": self.error_rate(),
        })
    }
}

/// One adaptive setting on the island.
#[derive(Clone, Copy, Debug, Default, PartialEq, Serialize)]
pub struct IslandNumbers {
    pub front: Artefacts,
    pub back: Artefacts,
    /// The ground at the feet of every trunk, front camera: its leak is the detachment.
    pub trunk_feet: Artefacts,
    /// The enlarged box around the featured trunk (Figure 12's panel), reported.
    pub featured_trunk_box: Artefacts,
}

impl IslandNumbers {
    pub fn json(&self) -> Value {
        json!({ "front": self.front.json(), "back": self.back.json(), "trunk_feet": self.trunk_feet.json(),
                "featured_trunk_box": self.featured_trunk_box.json() })
    }
}

/// Fig. 12 (a–c): original epsilon, K = 0.0001: few errors on the front (acne + leak ≤
/// [`FEW_ERRORS`]); projective-aliasing acne on the back (≥ [`NOTABLE_ACNE`] and ≥
/// [`NOTABLE_RATIO`] × the front's acne rate).
pub fn fig12_a(n: &IslandNumbers) -> Verdict {
    Verdict::of_parts(&[
        n.front.error_rate() <= FEW_ERRORS,
        n.back.acne_rate() >= NOTABLE_ACNE && n.back.acne_rate() >= NOTABLE_RATIO * n.front.acne_rate(),
    ])
}

/// Fig. 12 (d–f): original epsilon, K = 0.01 against K = 0.0001: at most half the back's acne,
/// and detachment at the tree trunks (≥ [`DETACHMENT_PIXELS`] leak pixels at their feet, more
/// than with K = 0.0001).
pub fn fig12_d(large_k: &IslandNumbers, small_k: &IslandNumbers) -> Verdict {
    let (large, small) = (large_k.trunk_feet.leak, small_k.trunk_feet.leak);
    Verdict::of_parts(&[
        large_k.back.acne_rate() <= 0.5 * small_k.back.acne_rate(),
        large >= DETACHMENT_PIXELS && large > small,
    ])
}

/// Fig. 12 (g–i): enhanced epsilon, K = 0.0001: on each camera, acne + leak at most
/// [`FEW_ERRORS`] or at most the better original setting's.
pub fn fig12_g(enhanced: &IslandNumbers, small_k: &IslandNumbers, large_k: &IslandNumbers) -> Verdict {
    let front_best = small_k.front.error_rate().min(large_k.front.error_rate());
    let back_best = small_k.back.error_rate().min(large_k.back.error_rate());
    Verdict::of_parts(&[
        enhanced.front.error_rate() <= FEW_ERRORS.max(front_best),
        enhanced.back.error_rate() <= FEW_ERRORS.max(back_best),
    ])
}

/// Two filtered techniques compared pixel by pixel, on the plane (cast shadows) and on the
/// casters (self shadows).
#[derive(Clone, Copy, Debug, Default, PartialEq, Serialize)]
pub struct Agreement {
    pub cast_pixels: u64,
    pub cast_differing: u64,
    pub self_pixels: u64,
    pub self_differing: u64,
    pub largest_difference: f32,
}

/// Ehm et al., Fig. 4: per-tap adaptive and Δbias give the same shadows cast on the plane: at
/// most [`NO_DIFFERENCE_SHARE`] of its pixels differ (holds), at most [`FEW_DIFFERENCES_SHARE`]
/// (partly). Self-shadow differences are reported, not judged (the paper allows them).
pub fn ehm_fig4(a: &Agreement) -> Verdict {
    let share = a.cast_differing as f64 / a.cast_pixels.max(1) as f64;
    if share <= NO_DIFFERENCE_SHARE {
        Verdict::Holds
    } else if share <= FEW_DIFFERENCES_SHARE {
        Verdict::Partly
    } else {
        Verdict::DoesNotHold
    }
}

/// Ehm et al., Table 1: at 11×11, Δbias costs less than the per-tap adaptive bias and stays
/// within [`DELTA_COST_CAP`] × receiver-plane bias. Both: holds; only the first: partly.
pub fn ehm_table1(adaptive_over_receiver_plane: f64, delta_over_receiver_plane: f64) -> Verdict {
    match (
        delta_over_receiver_plane < adaptive_over_receiver_plane,
        delta_over_receiver_plane <= DELTA_COST_CAP,
    ) {
        (true, true) => Verdict::Holds,
        (true, false) => Verdict::Partly,
        (false, _) => Verdict::DoesNotHold,
    }
}

/// Pagot et al., Table 1: PCF(k, n) takes at most n·k + 1 distinct values; holds when every
/// configuration (k, n, distinct) stays within its bound and reaches it, partly when within.
pub fn pagot_table1(configs: &[(u32, u32, usize)]) -> Verdict {
    let bound = |k: u32, n: u32| (n * k + 1) as usize;
    if configs.iter().any(|&(k, n, d)| d > bound(k, n)) {
        Verdict::DoesNotHold
    } else if configs.iter().all(|&(k, n, d)| d == bound(k, n)) {
        Verdict::Holds
    } else {
        Verdict::Partly
    }
}

/// The shadow edges of two filters on the plane.
#[derive(Clone, Copy, Debug, Default, PartialEq, Serialize)]
pub struct EdgeNumbers {
    /// Distinct visibility levels strictly between 0 and 1 on the plane.
    pub levels_3sm_3x3: usize,
    pub levels_1sm_4x4: usize,
    /// Plane pixels where either filter is strictly between 0 and 1.
    pub edge_pixels: u64,
    /// Mean |v₃ − v₁| over those pixels.
    pub edge_mean_difference: f64,
}

/// Pagot et al., Fig. 6: the 3-SM with 3×3 PCF gives smoother edges (more distinct levels) than,
/// and comparable to ([`COMPARABLE_EDGE_DIFFERENCE`]), the 1-SM with 4×4 PCF.
pub fn pagot_fig6(e: &EdgeNumbers) -> Verdict {
    Verdict::of_parts(&[
        e.levels_3sm_3x3 > e.levels_1sm_4x4,
        e.edge_pixels > 0 && e.edge_mean_difference <= COMPARABLE_EDGE_DIFFERENCE,
    ])
}

/// One technique's artefacts on the L and on the ground below it.
#[derive(Clone, Copy, Debug, Default, PartialEq, Serialize)]
pub struct LArtefacts {
    /// Acne on the L's lit faces (self-shadowing), leak on them (self-unshadowing), aliasing.
    pub l: Artefacts,
    pub ground: Artefacts,
}

impl LArtefacts {
    fn shows_self_shadowing(&self) -> bool {
        self.l.acne_rate() >= ARTEFACT_SHARE
    }

    fn shows_self_unshadowing(&self) -> bool {
        self.l.leak_rate() >= ARTEFACT_SHARE
    }
}

/// Weiskopf & Ertl, Fig. 5: dual depth layers show neither self-shadowing nor self-unshadowing on
/// the L (each under [`ARTEFACT_SHARE`] of its pixels), while each class shows with at least one
/// of the other techniques. Four parts: holds when all do.
pub fn weiskopf_fig5(dual: &LArtefacts, others: &[LArtefacts]) -> Verdict {
    Verdict::of_parts(&[
        !dual.shows_self_shadowing(),
        !dual.shows_self_unshadowing(),
        others.iter().any(LArtefacts::shows_self_shadowing),
        others.iter().any(LArtefacts::shows_self_unshadowing),
    ])
}

#[cfg(test)]
mod tests {
    use super::*;

    fn cam(evaluated: u64, acne: u64, leak: u64) -> Artefacts {
        Artefacts { evaluated, acne, leak, aliasing: 1000 }
    }

    fn island(front: (u64, u64), back: (u64, u64), trunk: u64) -> IslandNumbers {
        IslandNumbers {
            front: cam(10_000, front.0, front.1),
            back: cam(10_000, back.0, back.1),
            trunk_feet: cam(500, 0, trunk),
            featured_trunk_box: cam(300, 0, 0),
        }
    }

    #[test]
    fn fig12_a_on_both_sides_of_its_thresholds() {
        assert_eq!(fig12_a(&island((10, 40), (50, 0), 0)), Verdict::Holds);
        // Too many errors on the front (51 of 10 000 > 0.5 %).
        assert_eq!(fig12_a(&island((10, 41), (60, 0), 0)), Verdict::Partly);
        // Back acne below the rate, or not 4× the front's.
        assert_eq!(fig12_a(&island((10, 0), (49, 0), 0)), Verdict::Partly);
        assert_eq!(fig12_a(&island((13, 0), (51, 0), 0)), Verdict::Partly);
        assert_eq!(fig12_a(&island((60, 0), (10, 0), 0)), Verdict::DoesNotHold);
        // Aliasing is not counted: the same numbers with any aliasing give the same verdict.
        let mut n = island((10, 40), (50, 0), 0);
        n.front.aliasing = 1_000_000;
        assert_eq!(fig12_a(&n), Verdict::Holds);
    }

    #[test]
    fn fig12_d_on_both_sides_of_its_thresholds() {
        let small_k = island((10, 0), (200, 0), 3);
        assert_eq!(fig12_d(&island((0, 100), (100, 0), 10), &small_k), Verdict::Holds);
        assert_eq!(fig12_d(&island((0, 100), (101, 0), 40), &small_k), Verdict::Partly);
        assert_eq!(fig12_d(&island((0, 100), (100, 0), 9), &small_k), Verdict::Partly);
        assert_eq!(fig12_d(&island((0, 100), (300, 0), 2), &small_k), Verdict::DoesNotHold);
        // More than K = 0.0001's detachment is needed, not only the count.
        let detached = island((10, 0), (200, 0), 20);
        assert_eq!(fig12_d(&island((0, 100), (100, 0), 20), &detached), Verdict::Partly);
    }

    #[test]
    fn fig12_g_on_both_sides_of_its_thresholds() {
        let small_k = island((10, 0), (300, 0), 0);
        let large_k = island((0, 200), (100, 0), 50);
        assert_eq!(fig12_g(&island((50, 0), (100, 0), 0), &small_k, &large_k), Verdict::Holds);
        assert_eq!(fig12_g(&island((50, 0), (101, 0), 0), &small_k, &large_k), Verdict::Partly);
        assert_eq!(fig12_g(&island((51, 0), (101, 0), 0), &small_k, &large_k), Verdict::DoesNotHold);
    }

    #[test]
    fn ehm_fig4_on_both_sides() {
        let a = |cast_differing| Agreement {
            cast_pixels: 100_000,
            cast_differing,
            self_pixels: 1000,
            self_differing: 500,
            largest_difference: 0.1,
        };
        assert_eq!(ehm_fig4(&a(10)), Verdict::Holds);
        assert_eq!(ehm_fig4(&a(11)), Verdict::Partly);
        assert_eq!(ehm_fig4(&a(100)), Verdict::Partly);
        assert_eq!(ehm_fig4(&a(101)), Verdict::DoesNotHold);
    }

    #[test]
    fn ehm_table1_on_both_sides() {
        assert_eq!(ehm_table1(3.0, 1.5), Verdict::Holds);
        assert_eq!(ehm_table1(3.0, 1.51), Verdict::Partly);
        assert_eq!(ehm_table1(1.2, 1.2), Verdict::DoesNotHold);
    }

    #[test]
    fn pagot_rules_on_both_sides() {
        assert_eq!(pagot_table1(&[(9, 3, 28), (16, 1, 17)]), Verdict::Holds);
        assert_eq!(pagot_table1(&[(9, 3, 27), (16, 1, 17)]), Verdict::Partly);
        assert_eq!(pagot_table1(&[(9, 3, 29)]), Verdict::DoesNotHold);
        let e = |l3, l1, d| EdgeNumbers {
            levels_3sm_3x3: l3,
            levels_1sm_4x4: l1,
            edge_pixels: 1000,
            edge_mean_difference: d,
        };
        assert_eq!(pagot_fig6(&e(26, 15, 0.125)), Verdict::Holds);
        assert_eq!(pagot_fig6(&e(15, 15, 0.05)), Verdict::Partly);
        assert_eq!(pagot_fig6(&e(26, 15, 0.126)), Verdict::Partly);
        assert_eq!(pagot_fig6(&e(14, 15, 0.2)), Verdict::DoesNotHold);
        assert_eq!(pagot_fig6(&EdgeNumbers { edge_pixels: 0, ..e(26, 15, 0.0) }), Verdict::Partly);
    }

    #[test]
    fn weiskopf_fig5_on_both_sides() {
        let l = |acne, leak| LArtefacts { l: cam(10_000, acne, leak), ground: cam(10_000, 0, 0) };
        let others = [l(50, 0), l(0, 50), l(0, 0)];
        assert_eq!(weiskopf_fig5(&l(49, 49), &others), Verdict::Holds);
        assert_eq!(weiskopf_fig5(&l(50, 0), &others), Verdict::Partly);
        assert_eq!(weiskopf_fig5(&l(0, 0), &[l(49, 49)]), Verdict::Partly);
        assert_eq!(weiskopf_fig5(&l(50, 50), &[l(0, 0)]), Verdict::DoesNotHold);
    }

    #[test]
    fn the_summary_counts_every_verdict() {
        let s = |v| SetupResult::new("x", json!({}), v);
        let setups = [s(Verdict::Holds), s(Verdict::Partly), s(Verdict::Holds), s(Verdict::DoesNotHold)];
        assert_eq!(sensitivity_summary(&setups), "holds in 2 of 4 set-ups; partly in 1; does not hold in 1");
    }
}
