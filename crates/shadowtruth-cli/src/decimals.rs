//! Numbers rounded to a count of decimals as printing them does, for generated scene files whose
//! values are meant to be the short text they are written as.

use glam::{DVec3, Vec3};

/// `x` rounded to `decimals` decimals as `format!("{x:.decimals$}")` prints it (the exact binary
/// value, ties to even), as the f64 that text reads back as, and never -0.
pub(crate) fn rounded(x: f64, decimals: usize) -> f64 {
    let value: f64 = format!("{x:.decimals$}").parse().expect("a formatted number parses");
    // Adding +0 turns -0 into +0 and changes nothing else.
    value + 0.0
}

/// [`rounded`], held as the f32 the scene types use. While the value has at most six
/// significant digits (below 16384 with three decimals, below 100 with four), its f32 prints
/// back as the same decimal text.
pub(crate) fn rounded_f32(x: f64, decimals: usize) -> f32 {
    rounded(x, decimals) as f32
}

/// [`rounded_f32`] of each component.
pub(crate) fn rounded_vec3(v: DVec3, decimals: usize) -> Vec3 {
    Vec3::new(rounded_f32(v.x, decimals), rounded_f32(v.y, decimals), rounded_f32(v.z, decimals))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn decimals_round_as_printing_does_and_never_give_negative_zero() {
        assert_eq!(rounded(0.123456, 5), 0.12346);
        assert_eq!(rounded(2.5, 0), 2.0);
        assert!(rounded(-0.000001, 5).is_sign_positive());
        assert!(rounded_f32(-0.0004, 3).is_sign_positive());
        assert_eq!(rounded(-1.23456, 4), -1.2346);
        assert_eq!(rounded_vec3(DVec3::new(1.00049, -2.0, 16383.9996), 3), Vec3::new(1.0, -2.0, 16384.0));
        assert_eq!(rounded_f32(12.34567, 4).to_string(), "12.3457");
    }
}
