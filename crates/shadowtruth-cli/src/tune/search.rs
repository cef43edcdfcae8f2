//! The search for the parameter values that minimise an objective, each parameter on a log
//! scale over a positive range (docs/tune.md):
//!
//! - one parameter: a grid of `GRID_1D` points brackets the best value between its two
//!   neighbours, then golden-section search narrows the bracket to `TOLERANCE_LOG10`;
//! - two or three: a coarse grid, then rounds of golden-section search along one coordinate at
//!   a time, the others held at the best point so far.
//!
//! Error counts are piecewise constant in a bias, so the search may stop anywhere on a plateau:
//! the best point is the best of every point evaluated, never worse than any grid point.
//!
//! Every stage has a hard cap on its steps, whatever the ranges and the objective (docs/tune.md,
//! Bounds): `MAX_EVALUATIONS` bounds the calls of a whole search with its safe ranges. An
//! objective value that is NaN counts as the worst (+∞), so that no comparison silently fails.

/// An interval searched on a log scale: positive here; one below zero (`tune`'s options allow
/// it) is searched on its magnitude.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct LogRange {
    pub lo: f64,
    pub hi: f64,
}

impl LogRange {
    /// Whether the range lies below zero.
    pub fn is_negative(&self) -> bool {
        self.hi < 0.0
    }

    /// The range of the values' magnitudes (itself when positive).
    pub fn magnitude(&self) -> LogRange {
        if self.is_negative() { LogRange { lo: -self.hi, hi: -self.lo } } else { *self }
    }

    /// `count` points from `lo` to `hi`, evenly spaced in log (the ends exactly `lo` and `hi`).
    pub fn grid(&self, count: usize) -> Vec<f64> {
        let (a, b) = (self.lo.ln(), self.hi.ln());
        let step = (b - a) / count.saturating_sub(1).max(1) as f64;
        (0..count).map(|i| (a + step * i as f64).exp().clamp(self.lo, self.hi)).collect()
    }
}

/// One evaluated setting: a value per parameter and the objective there.
#[derive(Clone, Debug, PartialEq)]
pub struct Point {
    pub params: Vec<f64>,
    pub value: f64,
}

/// Points of the one-parameter grid.
pub const GRID_1D: usize = 12;
/// Points per parameter of the coarse grid with two parameters, and with three.
const GRID_2D: usize = 7;
const GRID_3D: usize = 5;
/// The search stops when the bracket spans less than this in log10 (about 2.3 %).
pub const TOLERANCE_LOG10: f64 = 0.01;
/// The ends of a safe range are placed to this, in log10 (about 4.7 %).
const SAFE_RANGE_TOLERANCE_LOG10: f64 = 0.02;
/// Rounds of coordinate refinement with several parameters.
const ROUNDS: usize = 2;
/// Golden-section steps per bracket at most: 0.618^30 narrows a bracket of 10⁴ decades to the
/// tolerance, and a valid range's bracket needs about 10.
pub const MAX_GOLDEN_STEPS: usize = 30;
/// Bisection steps per end of a safe range at most (2^30 narrows 10⁷ decades to its tolerance).
pub const MAX_BISECTIONS: usize = 30;
/// Calls of the objective by `minimise` and the safe ranges of every parameter, at most: the
/// largest grid (5³), then per round and parameter a bracket (its four first points and the
/// golden-section steps), then per parameter and end a walk over the grid and every point
/// already evaluated, and the bisection.
pub const MAX_EVALUATIONS: usize = {
    let grid = GRID_3D * GRID_3D * GRID_3D;
    let search = grid + ROUNDS * 3 * (4 + MAX_GOLDEN_STEPS);
    search + 3 * 2 * (GRID_1D + search + MAX_BISECTIONS)
};
/// 1/φ.
const INV_PHI: f64 = 0.618_033_988_749_894_9;

/// Minimises `f` over the box of `ranges` (one to three parameters) and returns the best point;
/// `f` sees every point the search evaluates (the caller keeps them).
pub fn minimise(ranges: &[LogRange], f: &mut dyn FnMut(&[f64]) -> f64) -> Point {
    assert!((1..=3).contains(&ranges.len()), "one to three parameters");
    let grid_points = match ranges.len() {
        1 => GRID_1D,
        2 => GRID_2D,
        _ => GRID_3D,
    };
    let grids: Vec<Vec<f64>> = ranges.iter().map(|r| r.grid(grid_points)).collect();
    let mut best = grid_minimum(&grids, f);
    let rounds = if ranges.len() == 1 { 1 } else { ROUNDS };
    for _ in 0..rounds {
        for axis in 0..ranges.len() {
            let bracket = neighbours(&grids[axis], best.params[axis]);
            let found = golden_section(bracket, |x| {
                let mut p = best.params.clone();
                p[axis] = x;
                f(&p)
            });
            if found.1 < best.value {
                best.params[axis] = found.0;
                best.value = found.1;
            }
        }
    }
    best
}

/// The best point of the full grid; among equal values, the middle of the first run of them
/// in grid order (the centre of a plateau is the setting farthest from its edges).
fn grid_minimum(grids: &[Vec<f64>], f: &mut dyn FnMut(&[f64]) -> f64) -> Point {
    let mut points = vec![Vec::new()];
    for grid in grids {
        points = points
            .iter()
            .flat_map(|p: &Vec<f64>| grid.iter().map(move |&x| [&p[..], &[x]].concat()))
            .collect();
    }
    let values: Vec<f64> = points.iter().map(|p| worst_if_nan(f(p))).collect();
    let least = values.iter().copied().fold(f64::INFINITY, f64::min);
    // `least` is one of the values (+∞ when all are): the run holds at least that one.
    let first = values.iter().position(|&v| v == least).unwrap_or(0);
    let run = values[first..].iter().take_while(|&&v| v == least).count().max(1);
    let middle = first + (run - 1) / 2;
    Point { params: points[middle].clone(), value: values[middle] }
}

/// The grid points on either side of `x` (the ends of the grid at its ends), in log.
fn neighbours(grid: &[f64], x: f64) -> (f64, f64) {
    let i = grid.iter().position(|&g| g >= x).unwrap_or(grid.len() - 1);
    let lo = grid[i.saturating_sub(1)];
    let hi = grid[(i + 1).min(grid.len() - 1)];
    (lo.ln(), hi.ln())
}

/// Golden-section search of `g` over the log bracket (a, b): the best point found, as
/// (value of the parameter, objective). A bracket whose ends and first two inner points all
/// score the same is flat (the function is taken to be unimodal, as golden section does), and
/// is not searched further.
fn golden_section(bracket: (f64, f64), mut g_raw: impl FnMut(f64) -> f64) -> (f64, f64) {
    let mut g = |x: f64| worst_if_nan(g_raw(x));
    let (mut a, mut b) = bracket;
    let mut c = b - (b - a) * INV_PHI;
    let mut d = a + (b - a) * INV_PHI;
    let (mut gc, mut gd) = (g(c.exp()), g(d.exp()));
    let mut best = if gc <= gd { (c, gc) } else { (d, gd) };
    if gc == gd && g(a.exp()) == gc && g(b.exp()) == gc {
        return (best.0.exp(), best.1);
    }
    for _ in 0..MAX_GOLDEN_STEPS {
        if (b - a) / std::f64::consts::LN_10 <= TOLERANCE_LOG10 {
            break;
        }
        if gc <= gd {
            (b, d, gd) = (d, c, gc);
            c = b - (b - a) * INV_PHI;
            gc = g(c.exp());
            if gc < best.1 {
                best = (c, gc);
            }
        } else {
            (a, c, gc) = (c, d, gd);
            d = a + (b - a) * INV_PHI;
            gd = g(d.exp());
            if gd < best.1 {
                best = (d, gd);
            }
        }
    }
    (best.0.exp(), best.1)
}

/// NaN compares false with everything: as +∞ it loses to every number instead.
fn worst_if_nan(value: f64) -> f64 {
    if value.is_nan() { f64::INFINITY } else { value }
}

/// Where the objective along one parameter stays within a bound around the best point.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct SafeRange {
    pub lo: f64,
    pub hi: f64,
    /// Whether the range stops at the searched range's end rather than at a worse value.
    pub lo_at_range_end: bool,
    pub hi_at_range_end: bool,
}

impl SafeRange {
    /// The same range of the negated parameter: its ends swapped.
    pub fn negated(self) -> SafeRange {
        SafeRange {
            lo: -self.hi,
            hi: -self.lo,
            lo_at_range_end: self.hi_at_range_end,
            hi_at_range_end: self.lo_at_range_end,
        }
    }
}

/// The contiguous interval of parameter `axis` around `best` (the others held) where `f` stays
/// at most `bound`. Each end is found by walking outward from the optimum over the points
/// already evaluated on this axis (`known`: the value of the parameter there) and the grid,
/// to the first value beyond the bound, then bisecting in log between it and the last value
/// within until they are `SAFE_RANGE_TOLERANCE_LOG10` apart.
pub fn safe_range(
    best: &Point,
    axis: usize,
    range: LogRange,
    known: &[f64],
    bound: f64,
    f: &mut dyn FnMut(&[f64]) -> f64,
) -> SafeRange {
    let mut along = |x: f64| {
        let mut p = best.params.clone();
        p[axis] = x;
        worst_if_nan(f(&p))
    };
    let x0 = best.params[axis];
    let mut steps: Vec<f64> = range.grid(GRID_1D).into_iter().chain(known.iter().copied()).collect();
    steps.sort_by(f64::total_cmp);
    steps.dedup();
    let below: Vec<f64> = steps.iter().rev().copied().filter(|&g| g < x0).collect();
    let above: Vec<f64> = steps.iter().copied().filter(|&g| g > x0).collect();
    let (lo, lo_at_range_end) = edge(x0, &below, bound, &mut along);
    let (hi, hi_at_range_end) = edge(x0, &above, bound, &mut along);
    SafeRange { lo, hi, lo_at_range_end, hi_at_range_end }
}

/// Walks `steps` outward from `x0` to the first value beyond `bound`, then bisects between it
/// and the last value within. Returns the last value within, and whether the walk ran out.
fn edge(x0: f64, steps: &[f64], bound: f64, along: &mut impl FnMut(f64) -> f64) -> (f64, bool) {
    let mut good = x0;
    for &x in steps {
        if along(x) > bound {
            let mut bad = x;
            for _ in 0..MAX_BISECTIONS {
                if (good.ln() - bad.ln()).abs() / std::f64::consts::LN_10 <= SAFE_RANGE_TOLERANCE_LOG10 {
                    break;
                }
                let mid = (good.ln() * 0.5 + bad.ln() * 0.5).exp();
                if along(mid) > bound {
                    bad = mid;
                } else {
                    good = mid;
                }
            }
            return (good, false);
        }
        good = x;
    }
    (good, true)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn log_distance(a: f64, b: f64) -> f64 {
        (a.log10() - b.log10()).abs()
    }

    #[test]
    fn one_parameter_finds_a_smooth_minimum_within_the_tolerance() {
        let range = LogRange { lo: 1e-6, hi: 1e-1 };
        let mut calls = 0;
        let mut f = |p: &[f64]| {
            calls += 1;
            (p[0].log10() + 3.3).powi(2)
        };
        let best = minimise(&[range], &mut f);
        assert!(log_distance(best.params[0], 10f64.powf(-3.3)) < TOLERANCE_LOG10, "{best:?}");
        assert!(calls < GRID_1D + 20, "{calls} evaluations");
    }

    #[test]
    fn one_parameter_never_ends_worse_than_a_grid_point() {
        // Two wells: golden section refines the deeper one the grid found.
        let range = LogRange { lo: 1e-4, hi: 1.0 };
        let well = |x: f64, at: f64, depth: f64| depth - (-(x.log10() - at).powi(2) * 40.0).exp();
        let mut f = |p: &[f64]| well(p[0], -3.0, 1.0).min(well(p[0], -1.0, 0.8));
        let best = minimise(&[range], &mut f);
        assert!(log_distance(best.params[0], 0.1) < TOLERANCE_LOG10, "{best:?}");
        for x in range.grid(50) {
            assert!(best.value <= f(&[x]) + 1e-12, "{x} beats {best:?}");
        }
    }

    #[test]
    fn a_plateau_gives_its_middle() {
        let range = LogRange { lo: 1e-6, hi: 1e-1 };
        let mut f = |p: &[f64]| {
            if p[0] < 1e-5 {
                10.0 - p[0].log10()
            } else if p[0] > 1e-2 {
                p[0].log10() + 10.0
            } else {
                0.0
            }
        };
        let best = minimise(&[range], &mut f);
        assert_eq!(best.value, 0.0);
        assert!(log_distance(best.params[0], 10f64.powf(-3.5)) < 0.4, "{best:?}");
        let safe = safe_range(&best, 0, range, &[], 0.0, &mut f);
        let close = |a, b| log_distance(a, b) < SAFE_RANGE_TOLERANCE_LOG10;
        assert!(close(safe.lo, 1e-5) && close(safe.hi, 1e-2), "{safe:?}");
        assert!(!safe.lo_at_range_end && !safe.hi_at_range_end);
    }

    #[test]
    fn two_parameters_find_a_tilted_valley() {
        let ranges = [LogRange { lo: 0.01, hi: 100.0 }, LogRange { lo: 0.01, hi: 100.0 }];
        let mut f = |p: &[f64]| {
            let (u, v) = (p[0].log10(), p[1].log10());
            (u - 0.4).powi(2) + 2.0 * (v + 0.7).powi(2) + 0.5 * (u - 0.4) * (v + 0.7)
        };
        let best = minimise(&ranges, &mut f);
        assert!(log_distance(best.params[0], 10f64.powf(0.4)) < 0.05, "{best:?}");
        assert!(log_distance(best.params[1], 10f64.powf(-0.7)) < 0.05, "{best:?}");
    }

    /// `minimise`, then the safe range of every parameter over the points already evaluated on
    /// its axis, as `tune` runs them; the number of calls of `f` and the best point.
    fn search_with_safe_ranges(ranges: &[LogRange], f: &mut dyn FnMut(&[f64]) -> f64) -> (usize, Point) {
        let seen: std::cell::RefCell<Vec<Vec<f64>>> = Default::default();
        let mut counted = |p: &[f64]| {
            seen.borrow_mut().push(p.to_vec());
            f(p)
        };
        let best = minimise(ranges, &mut counted);
        for (axis, &range) in ranges.iter().enumerate() {
            let others_at_best = |p: &&Vec<f64>| (0..p.len()).all(|k| k == axis || p[k] == best.params[k]);
            let known: Vec<f64> = seen.borrow().iter().filter(others_at_best).map(|p| p[axis]).collect();
            let bound = best.value * 1.1;
            let safe = safe_range(&best, axis, range, &known, bound, &mut counted);
            assert!(safe.lo <= best.params[axis] && best.params[axis] <= safe.hi, "{safe:?} {best:?}");
        }
        (seen.borrow().len(), best)
    }

    type Objective = Box<dyn FnMut(&[f64]) -> f64>;

    /// Objectives that break comparisons or never settle: NaN everywhere, NaN on every other
    /// call, ±∞, and noise that no bracket narrows on.
    fn hostile_objectives() -> Vec<(&'static str, Objective)> {
        let mut call = 0u64;
        let mut state = 0x9e37_79b9_7f4a_7c15_u64;
        vec![
            ("NaN everywhere", Box::new(|_: &[f64]| f64::NAN)),
            (
                "NaN on every other call",
                Box::new(move |p: &[f64]| {
                    call += 1;
                    if call.is_multiple_of(2) { f64::NAN } else { p[0].log10().abs() }
                }),
            ),
            ("+inf everywhere", Box::new(|_: &[f64]| f64::INFINITY)),
            ("-inf at large values", Box::new(|p: &[f64]| if p[0] > 1.0 { f64::NEG_INFINITY } else { 0.0 })),
            (
                "noise",
                Box::new(move |_: &[f64]| {
                    state ^= state << 13;
                    state ^= state >> 7;
                    state ^= state << 17;
                    (state % 1000) as f64
                }),
            ),
        ]
    }

    #[test]
    fn every_search_ends_within_its_step_cap_whatever_the_objective_and_range() {
        let huge = LogRange { lo: f64::MIN_POSITIVE, hi: f64::MAX };
        let usual = LogRange { lo: 1e-6, hi: 0.1 };
        for dims in 1..=3 {
            for range in [usual, huge] {
                for (name, mut f) in hostile_objectives() {
                    let ranges = vec![range; dims];
                    let (calls, best) = search_with_safe_ranges(&ranges, &mut f);
                    assert!(
                        calls <= MAX_EVALUATIONS,
                        "{name}, {dims} parameters over {range:?}: {calls} calls"
                    );
                    // exp(ln(x)) may miss x by a few ulps.
                    let inside = best.params.iter().all(|&x| range.lo * 0.999 <= x && x <= range.hi * 1.001);
                    assert!(inside && !best.value.is_nan(), "{name}: {best:?}");
                }
            }
        }
    }

    #[test]
    fn nan_is_the_worst_value_and_the_best_point_avoids_it() {
        // NaN below 1e-3, a smooth well at 1e-2 above: the grid sees both sides.
        let range = LogRange { lo: 1e-6, hi: 1.0 };
        let mut f = |p: &[f64]| if p[0] < 1e-3 { f64::NAN } else { (p[0].log10() + 2.0).powi(2) };
        let best = minimise(&[range], &mut f);
        assert!(log_distance(best.params[0], 1e-2) < TOLERANCE_LOG10, "{best:?}");
        // Only NaN: no panic, the middle of the grid, scored as the worst.
        let best = minimise(&[range], &mut |_: &[f64]| f64::NAN);
        assert_eq!(best.value, f64::INFINITY);
        assert_eq!(best.params[0], range.grid(GRID_1D)[(GRID_1D - 1) / 2]);
        // NaN beyond 0.1 ends the safe range there, as a worse value would.
        let mut g = |p: &[f64]| if p[0] > 0.1 { f64::NAN } else { 0.0 };
        let best = Point { params: vec![1e-3], value: 0.0 };
        let safe = safe_range(&best, 0, range, &[], 0.0, &mut g);
        assert!(log_distance(safe.hi, 0.1) < SAFE_RANGE_TOLERANCE_LOG10 && !safe.hi_at_range_end, "{safe:?}");
        assert!(safe.lo_at_range_end, "{safe:?}");
    }

    #[test]
    fn the_evaluation_cap_is_the_one_docs_tune_md_states() {
        assert_eq!(MAX_EVALUATIONS, 2555);
    }

    #[test]
    fn a_safe_range_open_at_the_end_of_the_range_says_so() {
        let range = LogRange { lo: 1.0, hi: 100.0 };
        let mut f = |p: &[f64]| p[0].log10();
        let best = minimise(&[range], &mut f);
        assert_eq!(best.params[0], 1.0);
        let safe = safe_range(&best, 0, range, &[], 0.5, &mut f);
        assert!(safe.lo_at_range_end && !safe.hi_at_range_end, "{safe:?}");
        assert!(log_distance(safe.hi, 10f64.powf(0.5)) < SAFE_RANGE_TOLERANCE_LOG10, "{safe:?}");
    }
}
