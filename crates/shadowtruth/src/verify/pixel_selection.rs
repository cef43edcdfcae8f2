//! Which evaluated pixels `verify` checks, as the command's `--pixels` and the Python package's
//! `pixels` name them: `all`, or a positive count.

use std::fmt;
use std::str::FromStr;

/// Pixels sampled per view unless told: enough that a wrong reference shows up on every bundled
/// view, few enough that the exact predicates finish in seconds.
pub const DEFAULT_SAMPLE_PIXELS: usize = 100_000;

/// Which evaluated pixels to check.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum PixelSelection {
    All,
    /// About this many pixels spread uniformly over the evaluated ones, plus every pixel next
    /// to a shadow boundary.
    Sample(usize),
}

impl Default for PixelSelection {
    fn default() -> Self {
        PixelSelection::Sample(DEFAULT_SAMPLE_PIXELS)
    }
}

impl FromStr for PixelSelection {
    type Err = String;

    fn from_str(text: &str) -> Result<Self, Self::Err> {
        if text == "all" {
            return Ok(PixelSelection::All);
        }
        text.parse::<usize>()
            .ok()
            .filter(|&n| n > 0)
            .map(PixelSelection::Sample)
            .ok_or_else(|| format!("'{text}' is neither `all` nor a positive number of pixels"))
    }
}

impl fmt::Display for PixelSelection {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            PixelSelection::All => f.write_str("all"),
            PixelSelection::Sample(n) => write!(f, "{n}"),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn names_round_trip_and_bad_ones_are_refused() {
        for selection in [PixelSelection::All, PixelSelection::Sample(1), PixelSelection::default()] {
            assert_eq!(selection.to_string().parse::<PixelSelection>(), Ok(selection));
        }
        assert_eq!(PixelSelection::default().to_string(), "100000");
        for bad in ["0", "-3", "ALL", "", "1.5", "1e5", "99999999999999999999999999999999999999999"] {
            let e = bad.parse::<PixelSelection>().unwrap_err();
            assert!(e.contains(&format!("'{bad}'")), "{bad}: {e}");
        }
    }
}
