//! The papers' claims as numbers: each claim has an id, its paper, its statement, the numbers we
//! measured and a verdict computed by a rule written next to it. A claim that does not hold on our
//! scenes is a finding, reported as such.
//!
//! Thresholds (what "few", "less" or "close" mean) are fixed here, before measuring, and printed
//! with every claim.

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

#[derive(Clone, Debug, Serialize)]
pub struct Claim {
    pub id: String,
    pub paper: String,
    pub statement: String,
    /// How the verdict is decided from the numbers.
    pub rule: String,
    pub numbers: Map<String, Value>,
    pub verdict: Verdict,
    /// Figure files (relative to the report folder) that show the claim.
    pub figures: Vec<String>,
}

/// "Few errors": an error rate at most this (fraction of evaluated pixels).
pub const FEW_ERRORS: f64 = 0.005;
/// "Notable false shadow": at least this rate…
pub const NOTABLE_FALSE_SHADOW: f64 = 0.005;
/// …and at least this many times the other camera's.
pub const NOTABLE_RATIO: f64 = 4.0;
/// "Detachment at the trunk": at least this many false-lit pixels in the trunk's box…
pub const DETACHMENT_PIXELS: u64 = 10;

/// Per-camera numbers of one adaptive setting on the island.
#[derive(Clone, Copy, Debug, Default, PartialEq, Serialize)]
pub struct IslandNumbers {
    pub front_false_shadow: f64,
    pub front_false_lit: f64,
    pub back_false_shadow: f64,
    pub back_false_lit: f64,
    /// False-lit pixels inside the box around the featured trunk (front camera).
    pub trunk_false_lit: u64,
}

impl IslandNumbers {
    pub fn front_error(&self) -> f64 {
        self.front_false_shadow + self.front_false_lit
    }

    pub fn back_error(&self) -> f64 {
        self.back_false_shadow + self.back_false_lit
    }
}

/// Fig. 12 (a): original epsilon, K = 0.0001: few errors on the front (error ≤ [`FEW_ERRORS`]),
/// projective-aliasing false shadow on the back (false-shadow rate ≥ [`NOTABLE_FALSE_SHADOW`] and
/// ≥ [`NOTABLE_RATIO`] × the front's).
pub fn fig12_a(n: &IslandNumbers) -> Verdict {
    Verdict::of_parts(&[
        n.front_error() <= FEW_ERRORS,
        n.back_false_shadow >= NOTABLE_FALSE_SHADOW
            && n.back_false_shadow >= NOTABLE_RATIO * n.front_false_shadow,
    ])
}

/// Fig. 12 (d–f): original epsilon, K = 0.01 against K = 0.0001: less false shadow on the back (at
/// most half), and false lit at the trunk (≥ [`DETACHMENT_PIXELS`] and more than with K = 0.0001).
pub fn fig12_d(large_k: &IslandNumbers, small_k: &IslandNumbers) -> Verdict {
    Verdict::of_parts(&[
        large_k.back_false_shadow <= 0.5 * small_k.back_false_shadow,
        large_k.trunk_false_lit >= DETACHMENT_PIXELS && large_k.trunk_false_lit > small_k.trunk_false_lit,
    ])
}

/// Fig. 12 (g–i): enhanced epsilon, K = 0.0001: low on both sides: on each camera its error rate
/// is at most [`FEW_ERRORS`] or at most that of the better original setting.
pub fn fig12_g(enhanced: &IslandNumbers, small_k: &IslandNumbers, large_k: &IslandNumbers) -> Verdict {
    let front_best = small_k.front_error().min(large_k.front_error());
    let back_best = small_k.back_error().min(large_k.back_error());
    Verdict::of_parts(&[
        enhanced.front_error() <= FEW_ERRORS.max(front_best),
        enhanced.back_error() <= FEW_ERRORS.max(back_best),
    ])
}

/// Weiskopf & Ertl, Fig. 5: dual depth layers (with back-face culling) have the fewest errors of
/// the six techniques on the undersampled L-shape. Strictly fewest: holds; tied for fewest: partly.
pub fn weiskopf_fig5(dual_errors: u64, others: &[u64]) -> Verdict {
    let best_other = others.iter().copied().min().unwrap_or(u64::MAX);
    if dual_errors < best_other {
        Verdict::Holds
    } else if dual_errors == best_other {
        Verdict::Partly
    } else {
        Verdict::DoesNotHold
    }
}

/// Pagot et al., Table 1: PCF(k, n) takes at most n·k + 1 distinct values; holds when every
/// configuration stays within its bound and reaches it, partly when within but not reached.
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

/// Pagot et al., Fig. 6: 3-SM with 3×3 PCF is at least as close to the coverage reference as
/// 1-SM with 4×4 PCF (mean absolute error); within 10 %: partly.
pub fn pagot_fig6(mae_3sm_3x3: f64, mae_1sm_4x4: f64) -> Verdict {
    if mae_3sm_3x3 <= mae_1sm_4x4 {
        Verdict::Holds
    } else if mae_3sm_3x3 <= 1.1 * mae_1sm_4x4 {
        Verdict::Partly
    } else {
        Verdict::DoesNotHold
    }
}

/// Ehm et al., Fig. 4: adaptive and adaptive_delta PCF 11×11 give the same cast shadows: no pixel
/// differs by more than 1e-6 (holds); at most 0.1 % of the pixels (partly).
pub fn ehm_fig4(differing: u64, evaluated: u64) -> Verdict {
    if differing == 0 {
        Verdict::Holds
    } else if differing as f64 <= 0.001 * evaluated as f64 {
        Verdict::Partly
    } else {
        Verdict::DoesNotHold
    }
}

/// Ehm et al., Table 1: at 11×11, Δbias costs less than the per-tap adaptive bias and stays close
/// to receiver-plane bias (at most 1.5× its cost). Both: holds; only the first: partly.
pub fn ehm_table1(adaptive_over_receiver_plane: f64, delta_over_receiver_plane: f64) -> Verdict {
    match (delta_over_receiver_plane < adaptive_over_receiver_plane, delta_over_receiver_plane <= 1.5) {
        (true, true) => Verdict::Holds,
        (true, false) => Verdict::Partly,
        (false, _) => Verdict::DoesNotHold,
    }
}

/// The numbers of an island setting as a JSON object.
pub fn island_numbers_json(n: &IslandNumbers) -> Value {
    json!({
        "front": { "false_shadow": n.front_false_shadow, "false_lit": n.front_false_lit, "error": n.front_error() },
        "back": { "false_shadow": n.back_false_shadow, "false_lit": n.back_false_lit, "error": n.back_error() },
        "trunk_false_lit_pixels": n.trunk_false_lit,
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    fn island(front: (f64, f64), back: (f64, f64), trunk: u64) -> IslandNumbers {
        IslandNumbers {
            front_false_shadow: front.0,
            front_false_lit: front.1,
            back_false_shadow: back.0,
            back_false_lit: back.1,
            trunk_false_lit: trunk,
        }
    }

    #[test]
    fn fig12_a_on_both_sides_of_its_thresholds() {
        assert_eq!(fig12_a(&island((0.001, 0.001), (0.02, 0.0), 0)), Verdict::Holds);
        // Too many errors on the front.
        assert_eq!(fig12_a(&island((0.004, 0.002), (0.05, 0.0), 0)), Verdict::Partly);
        // Back false shadow below the rate, or not 4× the front's.
        assert_eq!(fig12_a(&island((0.001, 0.0), (0.004, 0.0), 0)), Verdict::Partly);
        assert_eq!(fig12_a(&island((0.002, 0.0), (0.006, 0.0), 0)), Verdict::Partly);
        assert_eq!(fig12_a(&island((0.01, 0.0), (0.001, 0.0), 0)), Verdict::DoesNotHold);
    }

    #[test]
    fn fig12_d_on_both_sides_of_its_thresholds() {
        let small_k = island((0.001, 0.0), (0.02, 0.0), 3);
        assert_eq!(fig12_d(&island((0.0, 0.01), (0.01, 0.0), 40), &small_k), Verdict::Holds);
        assert_eq!(fig12_d(&island((0.0, 0.01), (0.0101, 0.0), 40), &small_k), Verdict::Partly);
        assert_eq!(fig12_d(&island((0.0, 0.01), (0.01, 0.0), 9), &small_k), Verdict::Partly);
        assert_eq!(fig12_d(&island((0.0, 0.01), (0.03, 0.0), 2), &small_k), Verdict::DoesNotHold);
    }

    #[test]
    fn fig12_g_on_both_sides_of_its_thresholds() {
        let small_k = island((0.001, 0.0), (0.03, 0.0), 0);
        let large_k = island((0.0, 0.02), (0.01, 0.0), 50);
        assert_eq!(fig12_g(&island((0.004, 0.0), (0.008, 0.0), 0), &small_k, &large_k), Verdict::Holds);
        assert_eq!(fig12_g(&island((0.004, 0.0), (0.011, 0.0), 0), &small_k, &large_k), Verdict::Partly);
        assert_eq!(fig12_g(&island((0.006, 0.0), (0.011, 0.0), 0), &small_k, &large_k), Verdict::DoesNotHold);
    }

    #[test]
    fn the_other_papers_rules_on_both_sides() {
        assert_eq!(weiskopf_fig5(10, &[11, 50]), Verdict::Holds);
        assert_eq!(weiskopf_fig5(11, &[11, 50]), Verdict::Partly);
        assert_eq!(weiskopf_fig5(12, &[11, 50]), Verdict::DoesNotHold);
        assert_eq!(pagot_table1(&[(9, 3, 28), (16, 1, 17)]), Verdict::Holds);
        assert_eq!(pagot_table1(&[(9, 3, 27), (16, 1, 17)]), Verdict::Partly);
        assert_eq!(pagot_table1(&[(9, 3, 29)]), Verdict::DoesNotHold);
        assert_eq!(pagot_fig6(0.010, 0.010), Verdict::Holds);
        assert_eq!(pagot_fig6(0.0109, 0.010), Verdict::Partly);
        assert_eq!(pagot_fig6(0.0111, 0.010), Verdict::DoesNotHold);
        assert_eq!(ehm_fig4(0, 1000), Verdict::Holds);
        assert_eq!(ehm_fig4(1, 1000), Verdict::Partly);
        assert_eq!(ehm_fig4(2, 1000), Verdict::DoesNotHold);
        assert_eq!(ehm_table1(3.0, 1.2), Verdict::Holds);
        assert_eq!(ehm_table1(3.0, 1.6), Verdict::Partly);
        assert_eq!(ehm_table1(1.2, 1.3), Verdict::DoesNotHold);
    }
}
