//! Sample patterns of the soft references: stratified grids over the unit square, jittered by a
//! hash of (pixel, sample) rather than by a random generator's state, so that every pixel's
//! samples are the same bits whatever thread traces it; the concentric square-to-disk map; an
//! orthonormal frame around a direction.

use crate::trace::splitmix::{mix64, unit_f64};
use glam::DVec3;

/// The centre of stratum `k` (row-major) of a `grid`×`grid` split of the unit square.
#[inline]
pub fn stratum_centre(k: u32, grid: u32) -> (f64, f64) {
    stratum_point(k, grid, 0.5, 0.5)
}

/// A point uniformly distributed in stratum `k` of a `grid`×`grid` split of the unit square; the
/// jitter is a hash of (`pixel`, `k`, `salt`) and nothing else. Always inlined, with the hash,
/// so that the area-light reference's blocks compile it for their instruction set (`cap_block`).
#[inline(always)]
pub fn jittered_stratum(pixel: u64, k: u32, grid: u32, salt: u64) -> (f64, f64) {
    let h1 = mix64(mix64(pixel ^ salt.rotate_left(32)) ^ k as u64);
    let h2 = mix64(h1);
    stratum_point(k, grid, unit_f64(h1), unit_f64(h2))
}

/// The point at (`u`, `v`) ∈ [0, 1)² within stratum `k` (row-major) of a `grid`×`grid` split:
/// ((k mod grid + u)/grid, (⌊k/grid⌋ + v)/grid). A grid of 2ⁿ (the usual 2×2, 4×4, 8×8) needs
/// no division: a mask and a shift split k, and dividing by 2ⁿ is multiplying by 2⁻ⁿ exactly
/// (the sums lie in [0, 2ⁿ]), so the points are the same bits. The divisions had taken a tenth
/// of the area-light reference's time (docs/scale.md).
#[inline(always)]
fn stratum_point(k: u32, grid: u32, u: f64, v: f64) -> (f64, f64) {
    if grid.is_power_of_two() {
        let scale = 1.0 / grid as f64;
        let (i, j) = (k & (grid - 1), k >> grid.trailing_zeros());
        return ((i as f64 + u) * scale, (j as f64 + v) * scale);
    }
    let (i, j) = (k % grid, k / grid);
    ((i as f64 + u) / grid as f64, (j as f64 + v) / grid as f64)
}

/// Shirley & Chiu, "A Low Distortion Map Between Disk and Square" (JGT 1997), in the
/// single-branch-per-half form: maps the unit square onto the unit disk preserving area
/// fractions (uniform in, uniform out) and keeping strata compact, so stratification survives.
#[inline(always)]
pub fn concentric_disk(u: f64, v: f64) -> (f64, f64) {
    disk_point(concentric_polar(u, v))
}

/// `concentric_disk`'s point in polar form (r, t, by_a): the angle φ is π/4·t where `by_a`,
/// else π/2 − π/4·t, with t ∈ [−1, 1] (the map's ratio b/a, or a/b), and the point is
/// (r·cos φ, r·sin φ). The division's operands are chosen, not its result, so that a block of
/// samples is computed a vector at a time with one division each (area_light.rs); the centre
/// (a = b = 0) gives r = 0 and t = 0, so the point (0, 0).
#[inline(always)]
pub fn concentric_polar(u: f64, v: f64) -> (f64, f64, bool) {
    let (a, b) = (2.0 * u - 1.0, 2.0 * v - 1.0);
    let centre = a == 0.0 && b == 0.0;
    let by_a = a.abs() > b.abs();
    let (r, other) = if by_a { (a, b) } else { (b, a) };
    (r, if centre { 0.0 } else { other / r }, by_a)
}

/// The point (r·cos φ, r·sin φ) of `concentric_polar`'s (r, t, by_a): with (s, c) the sine and
/// cosine of π/4·t, (r·c, r·s) where φ = π/4·t, and (r·s, r·c) where φ = π/2 − π/4·t.
#[inline(always)]
pub fn disk_point((r, t, by_a): (f64, f64, bool)) -> (f64, f64) {
    let (s, c) = sin_cos_quarter_pi(t);
    if by_a { (r * c, r * s) } else { (r * s, r * c) }
}

/// sin(π/4·t) and cos(π/4·t) for t ∈ [−1, 1]: the concentric map's angles are no wider, so
/// no range reduction is needed. Taylor series in x = π/4·t up to x¹⁷ and x¹⁶ (the first term
/// left out is below 10⁻¹⁷ at |x| = π/4), by Horner's rule in t² with plain products and sums:
/// within an ulp of the true values, and the same bits on every platform, where the C
/// library's `sin` and `cos` differ from one library to the next. Called one sample at a time,
/// those had taken a tenth of the area-light reference's time; this form is taken a vector of
/// samples at a time (`cap_block` in area_light.rs).
#[inline(always)]
pub fn sin_cos_quarter_pi(t: f64) -> (f64, f64) {
    let t2 = t * t;
    let (mut sin, mut cos) = (SIN_QUARTER_PI[8], COS_QUARTER_PI[8]);
    for k in (0..8).rev() {
        sin = sin * t2 + SIN_QUARTER_PI[k];
        cos = cos * t2 + COS_QUARTER_PI[k];
    }
    (sin * t, cos)
}

/// The Taylor coefficients of sin(π/4·t) in t: (−1)ᵏ(π/4)²ᵏ⁺¹/(2k + 1)!.
const SIN_QUARTER_PI: [f64; 9] = taylor_quarter_pi(1);
/// The Taylor coefficients of cos(π/4·t) in t: (−1)ᵏ(π/4)²ᵏ/(2k)!.
const COS_QUARTER_PI: [f64; 9] = taylor_quarter_pi(0);

/// (−1)ᵏ(π/4)²ᵏ⁺ᵖ/(2k + p)! for k = 0..9, each term from the one before.
const fn taylor_quarter_pi(p: u32) -> [f64; 9] {
    let x = std::f64::consts::FRAC_PI_4;
    let mut terms = [0.0; 9];
    let mut term = if p == 1 { x } else { 1.0 };
    let mut k = 0;
    while k < 9 {
        terms[k] = term;
        let n = (2 * k as u32 + p) as f64;
        term = -term * x * x / ((n + 1.0) * (n + 2.0));
        k += 1;
    }
    terms
}

/// Two unit vectors completing unit `n` to a right-handed orthonormal frame, without a branch
/// on a near-parallel helper axis (Duff et al., "Building an Orthonormal Basis, Revisited",
/// JCGT 2017).
#[inline]
pub fn orthonormal_frame(n: DVec3) -> (DVec3, DVec3) {
    let sign = 1f64.copysign(n.z);
    let a = -1.0 / (sign + n.z);
    let b = n.x * n.y * a;
    (DVec3::new(1.0 + sign * n.x * n.x * a, sign * b, -sign * n.x), DVec3::new(b, sign + n.y * n.y * a, -n.y))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn concentric_map_stays_on_the_disk_and_keeps_area() {
        // Uniform square in, uniform disk out: the fraction of strata centres inside radius ½
        // is the area fraction ¼.
        let n = 200;
        let mut inside = 0;
        for k in 0..n * n {
            let (u, v) = stratum_centre(k, n);
            let (x, y) = concentric_disk(u, v);
            let r2 = x * x + y * y;
            assert!(r2 <= 1.0 + 1e-12);
            inside += (r2 < 0.25) as u32;
        }
        let frac = inside as f64 / (n * n) as f64;
        assert!((frac - 0.25).abs() < 2e-3, "{frac}");
    }

    /// The branch-free polar form gives the bits of the map as Shirley & Chiu write it, one
    /// branch per half (each with its angle's sine and cosine): at the centre, on the diagonals
    /// |a| = |b|, on the axes and in between.
    #[test]
    fn concentric_polar_gives_the_branching_maps_bits() {
        let branching = |u: f64, v: f64| {
            let (a, b) = (2.0 * u - 1.0, 2.0 * v - 1.0);
            if a == 0.0 && b == 0.0 {
                return (0.0, 0.0);
            }
            if a.abs() > b.abs() {
                let (s, c) = sin_cos_quarter_pi(b / a);
                (a * c, a * s)
            } else {
                // φ = π/2 − π/4·(a/b): cos φ = sin(π/4·a/b), sin φ = cos(π/4·a/b).
                let (s, c) = sin_cos_quarter_pi(a / b);
                (b * s, b * c)
            }
        };
        let mut points =
            vec![(0.5, 0.5), (0.0, 0.0), (1.0, 1.0), (0.0, 1.0), (0.25, 0.75), (0.5, 0.0), (0.5, 1.0)];
        let mut h = 1u64;
        for _ in 0..20_000 {
            h = mix64(h);
            points.push((unit_f64(h), unit_f64(mix64(h ^ 7))));
        }
        for k in 0..=64 {
            let t = k as f64 / 64.0;
            points.extend([(t, t), (t, 1.0 - t), (t, 0.5), (0.5, t)]);
        }
        let bits = |(x, y): (f64, f64)| (x.to_bits(), y.to_bits());
        for (u, v) in points {
            assert_eq!(bits(concentric_disk(u, v)), bits(branching(u, v)), "({u}, {v})");
        }
    }

    /// The series give sine and cosine within 1.5·2⁻⁵³ of the platform's across [−π/4, π/4]
    /// (the worst here is 2⁻⁵³, an ulp of values below 1; the platform's are within half an
    /// ulp), odd and even exactly, and the very values at 0. Leaving out the last term of the
    /// sine (2⁻⁵² off) or making a coefficient 10⁻¹⁵ wrong fails it.
    #[test]
    fn quarter_pi_sine_and_cosine_are_within_an_ulp() {
        let q = std::f64::consts::FRAC_PI_4;
        let mut worst: f64 = 0.0;
        let mut h = 3u64;
        let mut ts: Vec<f64> = (0..=4096).map(|k| k as f64 / 2048.0 - 1.0).collect();
        for _ in 0..100_000 {
            h = mix64(h);
            ts.push(2.0 * unit_f64(h) - 1.0);
        }
        ts.extend([1.0, -1.0, 1e-300, f64::MIN_POSITIVE, 0.5f64.next_up()]);
        for t in ts {
            let (s, c) = sin_cos_quarter_pi(t);
            let x = q * t;
            worst = worst.max((s - x.sin()).abs()).max((c - x.cos()).abs());
            let (ns, nc) = sin_cos_quarter_pi(-t);
            assert_eq!((ns.to_bits(), nc.to_bits()), ((-s).to_bits(), c.to_bits()), "t = {t}");
        }
        assert!(worst <= 1.5 * 2f64.powi(-53), "worst |error| {worst:e}");
        assert_eq!(sin_cos_quarter_pi(0.0), (0.0, 1.0));
    }

    /// The division-free path for grids of 2ⁿ gives the very bits of the definition.
    #[test]
    fn power_of_two_grids_give_the_divisions_bits() {
        for grid in [1u32, 2, 4, 8, 16, 64, 1024] {
            for k in (0..grid * grid).step_by(((grid * grid) / 97).max(1) as usize) {
                for pixel in [0u64, 1, 12345, u64::MAX] {
                    let h1 = mix64(mix64(pixel ^ 9u64.rotate_left(32)) ^ k as u64);
                    let (u, v) = (unit_f64(h1), unit_f64(mix64(h1)));
                    let by_division =
                        (((k % grid) as f64 + u) / grid as f64, ((k / grid) as f64 + v) / grid as f64);
                    let bits = |(x, y): (f64, f64)| (x.to_bits(), y.to_bits());
                    assert_eq!(
                        bits(jittered_stratum(pixel, k, grid, 9)),
                        bits(by_division),
                        "grid {grid}, k {k}"
                    );
                    let centre =
                        (((k % grid) as f64 + 0.5) / grid as f64, ((k / grid) as f64 + 0.5) / grid as f64);
                    assert_eq!(bits(stratum_centre(k, grid)), bits(centre), "grid {grid}, k {k}");
                }
            }
        }
    }

    #[test]
    fn jitter_stays_in_its_stratum_and_depends_on_the_pixel() {
        for k in 0..16 {
            let (u, v) = jittered_stratum(7, k, 4, 1);
            assert!((u * 4.0).floor() as u32 == k % 4 && (v * 4.0).floor() as u32 == k / 4);
        }
        assert_ne!(jittered_stratum(7, 3, 4, 1), jittered_stratum(8, 3, 4, 1));
        assert_ne!(jittered_stratum(7, 3, 4, 1), jittered_stratum(7, 3, 4, 2));
    }

    #[test]
    fn frame_is_orthonormal() {
        for n in [DVec3::X, DVec3::NEG_Z, DVec3::new(0.3, -1.0, 0.2).normalize(), DVec3::Z] {
            let (t, b) = orthonormal_frame(n);
            for (x, y) in [(t, b), (t, n), (b, n)] {
                assert!(x.dot(y).abs() < 1e-12);
            }
            assert!((t.length() - 1.0).abs() < 1e-12 && (b.length() - 1.0).abs() < 1e-12);
        }
    }
}
