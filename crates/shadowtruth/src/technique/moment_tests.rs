//! The visibility formulas of the filterable shadow maps, on filtered moments (docs/formulas.md,
//! "Filterable shadow maps"):
//!
//! - Chebyshev's one-tailed bound, the test of variance shadow maps (Donnelly & Lauritzen,
//!   "Variance Shadow Maps", I3D 2006, eq. 5) and of exponential variance shadow maps on each
//!   warp (Lauritzen & McCool, "Layered Variance Shadow Maps", GI 2008, §4);
//! - light-bleeding reduction, the bound's low tail cut off and rescaled (Lauritzen, "Summed-Area
//!   Variance Shadow Maps", GPU Gems 3, ch. 8, 2007, §8.4.3);
//! - the four-moment Hamburger reconstruction of moment shadow mapping (Peters & Klein, "Moment
//!   Shadow Mapping", I3D 2015, Algorithm 2), written after the paper's own HLSL.

/// Chebyshev's bound P(z ≥ t) ≤ σ²/(σ² + (t − μ)²) for t > μ (1 for t ≤ μ), with
/// σ² = max(m₂ − μ², `min_variance`): the largest fraction of the filter region lit at depth t.
#[inline]
pub fn chebyshev_upper_bound(mean: f32, second: f32, t: f32, min_variance: f32) -> f32 {
    if t <= mean {
        return 1.0;
    }
    let variance = (second - mean * mean).max(min_variance);
    let d = t - mean;
    variance / (variance + d * d)
}

/// Light-bleeding reduction: visibilities below `amount` become 0 and the rest are stretched back
/// over [0, 1], `linstep(amount, 1, p)`.
#[inline]
pub fn reduce_bleeding(p: f32, amount: f32) -> f32 {
    saturate((p - amount) / (1.0 - amount))
}

/// HLSL's saturate: clamped to [0, 1], NaN to 0.
#[inline]
pub fn saturate(x: f32) -> f32 {
    if x.is_nan() { 0.0 } else { x.clamp(0.0, 1.0) }
}

/// The fraction of the filter region that shadows depth `depth`, reconstructed from the four
/// moments `b = (E z, E z², E z³, E z⁴)` after biasing them towards (½, ½, ½, ½) by
/// `moment_bias` (Peters & Klein 2015, Algorithm 2: the three-point distribution that matches the
/// moments and has a point at `depth`, its weight below `depth` summed).
pub fn hamburger_shadow_intensity(moments: [f32; 4], depth: f32, moment_bias: f32) -> f32 {
    let b: [f32; 4] = std::array::from_fn(|i| moments[i] + moment_bias * (0.5 - moments[i]));
    // The Cholesky factorisation of the Hankel matrix B = [[1, b0, b1], [b0, b1, b2], [b1, b2, b3]].
    let l32_d22 = -b[0] * b[1] + b[2];
    let d22 = -b[0] * b[0] + b[1];
    let squared_depth_variance = -b[1] * b[1] + b[3];
    let d33_d22 = squared_depth_variance * d22 - l32_d22 * l32_d22;
    let inv_d22 = 1.0 / d22;
    let l32 = l32_d22 * inv_d22;
    // Solve B c = (1, z, z²) by forward substitution, scaling and back substitution.
    let z0 = depth;
    let mut c = [1.0, z0, z0 * z0];
    c[1] -= b[0];
    c[2] -= b[1] + l32 * c[1];
    c[1] *= inv_d22;
    c[2] *= d22 / d33_d22;
    c[1] -= l32 * c[2];
    c[0] -= c[1] * b[0] + c[2] * b[1];
    // The other two support points: the roots of c0 + c1 z + c2 z².
    let p = c[1] / c[2];
    let q = c[0] / c[2];
    let r = (p * p * 0.25 - q).sqrt();
    let (z1, z2) = (-p * 0.5 - r, -p * 0.5 + r);
    let switch = if z2 < z0 {
        [z1, z0, 1.0, 1.0]
    } else if z1 < z0 {
        [z0, z1, 0.0, 1.0]
    } else {
        [0.0, 0.0, 0.0, 0.0]
    };
    let quotient = (switch[0] * z2 - b[0] * (switch[0] + z2) + b[1]) / ((z2 - switch[1]) * (z0 - z1));
    saturate(switch[2] + switch[3] * quotient)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Moments of a distribution of (depth, weight) points.
    fn moments(points: &[(f32, f32)]) -> [f32; 4] {
        std::array::from_fn(|k| points.iter().map(|&(z, w)| w * z.powi(k as i32 + 1)).sum())
    }

    #[test]
    fn chebyshev_worked_by_hand() {
        // Half the region at 0.2, half at 0.6: μ = 0.4, σ² = 0.04. At t = 0.7: 0.04/(0.04 + 0.09).
        let [m1, m2, ..] = moments(&[(0.2, 0.5), (0.6, 0.5)]);
        assert!((chebyshev_upper_bound(m1, m2, 0.7, 0.0) - 0.04 / 0.13).abs() < 1e-6);
        assert_eq!(chebyshev_upper_bound(m1, m2, 0.4, 0.0), 1.0);
        // One depth only: σ² = 0 and the test is the plain depth test, exact.
        assert_eq!(chebyshev_upper_bound(0.3, 0.09, 0.31, 0.0), 0.0);
        assert_eq!(chebyshev_upper_bound(0.3, 0.09, 0.3, 0.0), 1.0);
        // The minimum variance rounds a near-zero variance up.
        assert!((chebyshev_upper_bound(0.3, 0.09, 0.31, 1e-4) - 1e-4 / (1e-4 + 1e-4)).abs() < 1e-3);
    }

    #[test]
    fn bleeding_reduction_is_a_linstep() {
        assert_eq!(reduce_bleeding(0.2, 0.3), 0.0);
        assert!((reduce_bleeding(0.65, 0.3) - 0.5).abs() < 1e-6);
        assert_eq!(reduce_bleeding(1.0, 0.3), 1.0);
        assert_eq!(reduce_bleeding(0.4, 0.0), 0.4);
        assert_eq!(saturate(f32::NAN), 0.0);
    }

    #[test]
    fn hamburger_recovers_a_three_point_distribution_at_its_support() {
        // Occluders at 0.2, 0.5, 0.8 with weights 0.3, 0.3, 0.4. Four moments determine the
        // three-point distribution with a point at the receiver, so at each support point the
        // reconstruction is the true one and the shadow is the weight strictly in front (worked
        // by hand: 0, 0.3, 0.6; in f32 within 1e-4 without a moment bias).
        let b = moments(&[(0.2, 0.3), (0.5, 0.3), (0.8, 0.4)]);
        for (depth, shadow) in [(0.2, 0.0), (0.5, 0.3), (0.8, 0.6), (0.1, 0.0)] {
            let got = hamburger_shadow_intensity(b, depth, 0.0);
            assert!((got - shadow).abs() < 1e-4, "at {depth}: {got}, not {shadow}");
        }
        // The default moment bias moves it by less than 1e-4 here.
        assert!((hamburger_shadow_intensity(b, 0.5, 3e-5) - 0.3).abs() < 1e-4);
    }
}
