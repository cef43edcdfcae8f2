//! How the gate prints a metric's value: in rule descriptions (`rules.rs`) and in the outcome
//! (`render.rs`).

/// Six significant digits, no trailing zeros: `0.00123457`, `0`, `1.5e-9`.
pub fn fmt_value(v: f64) -> String {
    if v == 0.0 || !v.is_finite() {
        return format!("{v}");
    }
    let exp = v.abs().log10().floor() as i32;
    if (-6..=6).contains(&exp) {
        let decimals = (5 - exp).max(0) as usize;
        let s = format!("{v:.decimals$}");
        if s.contains('.') { s.trim_end_matches('0').trim_end_matches('.').to_string() } else { s }
    } else {
        format!("{v:.5e}")
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn values_print_with_six_significant_digits() {
        assert_eq!(fmt_value(0.0), "0");
        assert_eq!(fmt_value(0.001), "0.001");
        assert_eq!(fmt_value(1.0 / 3.0), "0.333333");
        assert_eq!(fmt_value(0.0012715657552083333), "0.00127157");
        assert_eq!(fmt_value(2.0), "2");
        assert_eq!(fmt_value(1.5e-9), "1.50000e-9");
    }
}
