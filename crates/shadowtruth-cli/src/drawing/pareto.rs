//! The Pareto front of shading cost against error, with the cost's noise.
//!
//! A cost is the median of a few timed shading passes on a shared machine: two medians a few
//! per cent apart say nothing. So a setting beats another only where it is measurably so: its
//! error is no greater, its cost range (least to greatest of the repeats) does not lie wholly
//! above the other's, and it is either strictly better in error or wholly cheaper. A setting
//! joins the front when no setting beats it; one whose cost was not measured here (another
//! renderer's buffer) is drawn but never on the front, and never beats one.

/// One setting: its cost (ns per evaluated pixel, the median and the range of the repeats),
/// its error, and whether the cost was measured at all.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct CostPoint {
    pub cost: f64,
    pub cost_range: [f64; 2],
    pub error: f64,
    pub measured: bool,
}

impl CostPoint {
    /// A measured setting with a cost known exactly (a range of one value).
    #[cfg(test)]
    pub fn exact(cost: f64, error: f64) -> Self {
        CostPoint { cost, cost_range: [cost, cost], error, measured: true }
    }

    /// Whether `self` beats `other` beyond the noise of their costs.
    fn beats(&self, other: &CostPoint) -> bool {
        let not_costlier = self.cost_range[0] <= other.cost_range[1];
        let cheaper = self.cost_range[1] < other.cost_range[0];
        self.measured && self.error <= other.error && not_costlier && (self.error < other.error || cheaper)
    }
}

/// The indices of the points on the front, by cost (then error): the measured points no point
/// beats.
pub fn pareto_front(points: &[CostPoint]) -> Vec<usize> {
    let mut front: Vec<usize> = (0..points.len())
        .filter(|&i| points[i].measured && !points.iter().any(|p| p.beats(&points[i])))
        .collect();
    front.sort_by(|&a, &b| {
        let (a, b) = (&points[a], &points[b]);
        a.cost.total_cmp(&b.cost).then(a.error.total_cmp(&b.error))
    });
    front
}

#[cfg(test)]
pub(crate) mod tests {
    use super::*;

    /// Fifty sets of thirty points with exact costs and errors on a coarse grid (so that ties
    /// happen), the same every time.
    pub(crate) fn random_point_sets() -> Vec<Vec<CostPoint>> {
        let mut state = 7u64;
        let mut next = || {
            state = state.wrapping_mul(6364136223846793005).wrapping_add(1442695040888963407);
            ((state >> 40) % 50) as f64
        };
        (0..50).map(|_| (0..30).map(|_| CostPoint::exact(next(), next())).collect()).collect()
    }

    /// With exact costs the front is the classic one: exactly the points no other point is at
    /// least as good as on both axes and better on one.
    #[test]
    fn with_exact_costs_the_front_holds_exactly_the_non_dominated_points() {
        for points in random_point_sets() {
            let front = pareto_front(&points);
            let dominates = |a: &CostPoint, b: &CostPoint| {
                a.cost <= b.cost && a.error <= b.error && (a.cost, a.error) != (b.cost, b.error)
            };
            for (i, p) in points.iter().enumerate() {
                let dominated = points.iter().any(|q| dominates(q, p));
                assert_eq!(front.contains(&i), !dominated, "{p:?}");
            }
            assert!(front.windows(2).all(|w| points[w[0]].cost <= points[w[1]].cost));
        }
    }

    /// The case of a cheap setting with a huge error (no bias at all) whose cost is within the
    /// noise of a good setting's: the good one beats it. Measurably cheaper, it stays.
    #[test]
    fn a_point_joins_the_front_only_beyond_the_noise() {
        let ranged = |cost: f64, lo: f64, hi: f64, error: f64| CostPoint {
            cost,
            cost_range: [lo, hi],
            error,
            measured: true,
        };
        let none = ranged(9.0, 8.5, 10.5, 48.0);
        let constant = ranged(9.6, 9.0, 11.0, 0.5);
        assert_eq!(pareto_front(&[none, constant]), [1], "none is within the noise of constant");
        let cheaper_none = ranged(5.0, 4.5, 5.5, 48.0);
        assert_eq!(pareto_front(&[cheaper_none, constant]), [0, 1], "measurably cheaper: both on the front");
        // Equal errors within the noise: neither beats the other.
        assert_eq!(pareto_front(&[ranged(9.0, 8.0, 10.0, 1.0), ranged(9.5, 9.0, 11.0, 1.0)]), [0, 1]);
    }

    #[test]
    fn an_unmeasured_cost_is_never_on_the_front_and_beats_nothing() {
        let external = CostPoint { cost: 0.0, cost_range: [0.0, 0.0], error: 0.1, measured: false };
        let constant = CostPoint::exact(9.6, 0.5);
        assert_eq!(pareto_front(&[external, constant]), [1]);
    }
}
