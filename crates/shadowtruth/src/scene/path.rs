//! Keyframed paths of cameras and lights (docs/temporal.md): values at key times, sampled at any
//! time by linear or Catmull–Rom interpolation, held at the first and last key outside them.

use glam::DVec3;

#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Interpolation {
    Linear,
    /// The Catmull–Rom spline through the keys: Hermite segments whose tangents are the
    /// central differences (p[i+1] − p[i−1]) / (t[i+1] − t[i−1]), one-sided at the ends.
    CatmullRom,
}

impl Interpolation {
    pub fn parse(name: &str) -> Option<Self> {
        match name {
            "linear" => Some(Interpolation::Linear),
            "catmull_rom" => Some(Interpolation::CatmullRom),
            _ => None,
        }
    }

    /// The name scene files give it (what `parse` reads).
    pub fn name(self) -> &'static str {
        match self {
            Interpolation::Linear => "linear",
            Interpolation::CatmullRom => "catmull_rom",
        }
    }
}

/// One vector-valued track: `times` strictly increasing, one value per time (at least one).
#[derive(Clone, Debug, PartialEq)]
pub struct Keyframes {
    pub interpolation: Interpolation,
    pub times: Vec<f64>,
    pub values: Vec<DVec3>,
}

impl Keyframes {
    /// The first and last key times.
    pub fn span(&self) -> (f64, f64) {
        (self.times[0], self.times[self.times.len() - 1])
    }

    /// The value at time `t`, held constant before the first key and after the last.
    pub fn at(&self, t: f64) -> DVec3 {
        let (times, values) = (&self.times, &self.values);
        let last = times.len() - 1;
        if t <= times[0] {
            return values[0];
        }
        if t >= times[last] {
            return values[last];
        }
        // The segment [times[i], times[i + 1]] that holds t.
        let i = times.partition_point(|&k| k <= t) - 1;
        let (t0, t1) = (times[i], times[i + 1]);
        let s = (t - t0) / (t1 - t0);
        match self.interpolation {
            Interpolation::Linear => values[i].lerp(values[i + 1], s),
            Interpolation::CatmullRom => {
                let (m0, m1) = (self.tangent(i), self.tangent(i + 1));
                hermite(values[i], values[i + 1], m0 * (t1 - t0), m1 * (t1 - t0), s)
            }
        }
    }

    /// The Catmull–Rom tangent (per unit time) at key `i`.
    fn tangent(&self, i: usize) -> DVec3 {
        let (times, values) = (&self.times, &self.values);
        let (a, b) = (i.saturating_sub(1), (i + 1).min(times.len() - 1));
        (values[b] - values[a]) / (times[b] - times[a])
    }
}

/// The cubic Hermite segment from p0 to p1 with end tangents m0, m1 (per unit s), at s ∈ [0, 1].
fn hermite(p0: DVec3, p1: DVec3, m0: DVec3, m1: DVec3, s: f64) -> DVec3 {
    let (s2, s3) = (s * s, s * s * s);
    p0 * (2.0 * s3 - 3.0 * s2 + 1.0) + m0 * (s3 - 2.0 * s2 + s) + p1 * (-2.0 * s3 + 3.0 * s2) + m1 * (s3 - s2)
}

/// A camera's path: where it stands and what it looks at.
#[derive(Clone, Debug, PartialEq)]
pub struct CameraPath {
    pub position: Keyframes,
    pub look_at: Keyframes,
}

/// A light's path: its direction (normalized after interpolation), and a spot light's position.
#[derive(Clone, Debug, PartialEq)]
pub struct LightPath {
    pub direction: Keyframes,
    pub position: Option<Keyframes>,
}

/// The times of `frames` frames spread evenly over `span` (first and last included); one frame
/// is the span's start.
pub fn frame_times(span: (f64, f64), frames: usize) -> Vec<f64> {
    let (t0, t1) = span;
    match frames {
        0 => Vec::new(),
        1 => vec![t0],
        n => {
            (0..n).map(|i| if i == n - 1 { t1 } else { t0 + (t1 - t0) * i as f64 / (n - 1) as f64 }).collect()
        }
    }
}

/// The union of the spans of the paths given (None when there is none).
pub fn union_span(spans: impl IntoIterator<Item = (f64, f64)>) -> Option<(f64, f64)> {
    spans.into_iter().reduce(|a, b| (a.0.min(b.0), a.1.max(b.1)))
}

#[cfg(test)]
mod tests {
    use super::*;

    fn track(interpolation: Interpolation, keys: &[(f64, f64)]) -> Keyframes {
        Keyframes {
            interpolation,
            times: keys.iter().map(|k| k.0).collect(),
            values: keys.iter().map(|k| DVec3::splat(k.1)).collect(),
        }
    }

    #[test]
    fn linear_paths_interpolate_between_keys_and_hold_outside() {
        let k = track(Interpolation::Linear, &[(0.0, 1.0), (2.0, 5.0), (3.0, 5.0)]);
        assert_eq!(k.at(-1.0).x, 1.0);
        assert_eq!(k.at(0.5).x, 2.0);
        assert_eq!(k.at(2.5).x, 5.0);
        assert_eq!(k.at(9.0).x, 5.0);
    }

    #[test]
    fn catmull_rom_passes_through_keys_and_reproduces_a_line() {
        // On keys along a line at uneven times, the spline with central-difference tangents is
        // that line only where the speed is constant: evenly spaced keys of a line.
        let k = track(Interpolation::CatmullRom, &[(0.0, 0.0), (1.0, 2.0), (2.0, 4.0), (3.0, 6.0)]);
        for (t, x) in [(0.0, 0.0), (1.0, 2.0), (1.25, 2.5), (2.5, 5.0), (3.0, 6.0)] {
            assert!((k.at(t).x - x).abs() < 1e-12, "t = {t}: {}", k.at(t).x);
        }
        // A parabola's keys: the spline passes through every key, and between keys bends.
        let p = track(Interpolation::CatmullRom, &[(0.0, 0.0), (1.0, 1.0), (2.0, 4.0), (3.0, 9.0)]);
        assert_eq!(p.at(2.0).x, 4.0);
        assert!((p.at(1.5).x - 2.25).abs() < 0.2 && p.at(1.5).x != 2.5);
    }

    #[test]
    fn frame_times_include_both_ends() {
        assert_eq!(frame_times((1.0, 3.0), 5), vec![1.0, 1.5, 2.0, 2.5, 3.0]);
        assert_eq!(frame_times((1.0, 3.0), 1), vec![1.0]);
        assert_eq!(union_span([(0.0, 1.0), (-1.0, 0.5)]), Some((-1.0, 1.0)));
    }
}
