//! The two buffers a renderer hands over for one camera, and the values each may hold: one rule,
//! applied by the file readers and by the Python package to its arrays alike.

/// What a renderer's per-pixel buffer holds.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum BufferKind {
    /// 1 lit, 0 shadowed (½ or more counts as lit); NaN or negative where the renderer drew
    /// background.
    Visibility,
    /// Distance from the camera's position along each primary ray; 0 or +inf for background.
    Depth,
}

impl BufferKind {
    /// Whether such a buffer may not hold `value`.
    pub fn refuses(self, value: f32) -> bool {
        match self {
            BufferKind::Visibility => value > 1.0,
            BufferKind::Depth => value.is_nan() || value < 0.0,
        }
    }

    /// The rule a refused value breaks.
    pub fn rule(self) -> &'static str {
        match self {
            BufferKind::Visibility => "visibility must be in [0, 1] (NaN or negative for background)",
            BufferKind::Depth => "depth must be ≥ 0 (0 or +inf for background)",
        }
    }

    /// The first value of a `width`-wide image (row 0 at the top) that such a buffer may not
    /// hold, as "pixel (x, y) is v: rule"; None when every value is allowed.
    pub fn first_refused(self, values: &[f32], width: u32) -> Option<String> {
        let i = values.iter().position(|&v| self.refuses(v))?;
        let (x, y) = (i as u64 % width.max(1) as u64, i as u64 / width.max(1) as u64);
        Some(format!("pixel ({x}, {y}) is {}: {}", values[i], self.rule()))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn each_buffer_refuses_only_what_it_cannot_hold() {
        let visibility = [0.0, 1.0, 0.5, -1.0, f32::NAN, f32::NEG_INFINITY];
        assert_eq!(BufferKind::Visibility.first_refused(&visibility, 3), None);
        let e = BufferKind::Visibility.first_refused(&[0.0, 1.0, 0.0, 0.0, 1.5], 3).unwrap();
        assert_eq!(e, "pixel (1, 1) is 1.5: visibility must be in [0, 1] (NaN or negative for background)");
        let depth = [0.0, 3.5, f32::INFINITY];
        assert_eq!(BufferKind::Depth.first_refused(&depth, 2), None);
        for bad in [f32::NAN, -0.5, f32::NEG_INFINITY] {
            let e = BufferKind::Depth.first_refused(&[1.0, 2.0, bad], 2).unwrap();
            assert!(
                e.starts_with("pixel (0, 1) is ")
                    && e.ends_with("depth must be ≥ 0 (0 or +inf for background)"),
                "{e}"
            );
        }
    }
}
