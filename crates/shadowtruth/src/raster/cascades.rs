//! Cascaded shadow maps of a directional light (docs/cascades.md): the camera's depth range split
//! into cascades (uniform, logarithmic, or Zhang et al.'s practical blend of the two, "Parallel-
//! split shadow maps for large-scale virtual environments", VRCIA 2006), each an orthographic map
//! of its slice of the camera frustum, fitted to the slice's bounding sphere or tight to its
//! corners, and optionally snapped to whole texels so that it does not shimmer as the camera
//! moves (Valient, "Stable rendering of cascaded shadow maps", ShaderX6, 2008).
//!
//! Every cascade shares the light's space and depth range with the single map
//! (`DirectionalFrame`): only its x and y extent differ, so a cascade whose extent is the scene's
//! is the single map, bit for bit.

use super::projection::{DirectionalFrame, LightView, Projection};
use crate::scene::{Camera, CascadeFit, CascadeSettings, Light, LightKind, SplitScheme};
use glam::{DVec3, Vec3};

/// The cascades of one light for one camera and resolution.
#[derive(Clone, Debug, PartialEq)]
pub struct Cascades {
    /// Cascade i serves view depths `[splits[i], splits[i + 1])`; `splits[0]` is the near distance
    /// (cascade 0 also serves everything nearer) and the last is the maximum distance.
    pub splits: Vec<f64>,
    pub views: Vec<LightView>,
    /// Fraction of each cascade's depth range, at its far end, blended into the next.
    pub blend_band: f64,
    camera_position: DVec3,
    camera_forward: DVec3,
}

/// Which cascade shades a point.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum CascadeChoice {
    /// Cascade `index` alone.
    One(usize),
    /// Cascade `index` blended with the next by `weight` ∈ (0, 1) (the next's share).
    Blend { index: usize, weight: f32 },
    /// Beyond the last cascade: lit, as engines draw it.
    Beyond,
}

/// The split distances of `scheme` between `near` and `far` for `count` cascades: count + 1
/// values from near to far. Uniform: n + (f − n)·i/N; logarithmic: n·(f/n)^(i/N); practical:
/// λ·logarithmic + (1 − λ)·uniform (Zhang et al. 2006, eq. 7).
pub fn split_distances(scheme: SplitScheme, near: f64, far: f64, count: u32) -> Vec<f64> {
    let n = count as f64;
    let uniform = |i: f64| near + (far - near) * i / n;
    let logarithmic = |i: f64| near * (far / near).powf(i / n);
    (0..=count)
        .map(|i| match (i, scheme) {
            (0, _) => near,
            (i, _) if i == count => far,
            (i, SplitScheme::Uniform) => uniform(i as f64),
            (i, SplitScheme::Logarithmic) => logarithmic(i as f64),
            (i, SplitScheme::Practical { lambda }) => {
                lambda * logarithmic(i as f64) + (1.0 - lambda) * uniform(i as f64)
            }
        })
        .collect()
}

/// The default last split: from `camera` to the farthest corner of `scene_bounds`.
pub fn default_max_distance(camera: &Camera, scene_bounds: (Vec3, Vec3)) -> f64 {
    let (lo, hi) = (scene_bounds.0.as_dvec3(), scene_bounds.1.as_dvec3());
    let eye = camera.position.as_dvec3();
    let farthest = (eye - lo).abs().max((eye - hi).abs());
    farthest.length().max(1e-3)
}

impl Cascades {
    /// The cascades of the directional `light` for `camera` at `resolution`, with `settings`
    /// and the last split at `max_distance` (resolved by the caller: `settings.max_distance` or
    /// `default_max_distance`).
    pub fn new(
        settings: &CascadeSettings,
        light: &Light,
        camera: &Camera,
        scene_bounds: (Vec3, Vec3),
        resolution: u32,
        max_distance: f64,
    ) -> Self {
        let near = settings.near_distance.unwrap_or(max_distance / 1000.0).min(max_distance * 0.999);
        let splits = split_distances(settings.split, near, max_distance, settings.count);
        let LightKind::Directional { direction, .. } = light.kind else {
            unreachable!("scene files give cascades to directional lights only")
        };
        let frame = DirectionalFrame::new(direction, scene_bounds);
        let slice = FrustumSlices::new(camera);
        let views = (0..settings.count as usize)
            .map(|i| {
                // Cascade i also serves the blend band at the end of the one before it, and
                // cascade 0 everything nearer than the first split.
                let start = match i {
                    0 => 0.0,
                    _ => splits[i] - settings.blend_band * (splits[i] - splits[i - 1]),
                };
                let (x, y) = match settings.fit {
                    CascadeFit::Sphere => {
                        slice.sphere_box(&frame, start, splits[i + 1], resolution, settings.stabilize)
                    }
                    CascadeFit::Frustum => {
                        slice.corner_box(&frame, start, splits[i + 1], resolution, settings.stabilize)
                    }
                };
                LightView { light_size: light.size().ok(), ..frame.orthographic(x, y, resolution) }
            })
            .collect();
        Cascades {
            splits,
            views,
            blend_band: settings.blend_band,
            camera_position: camera.position.as_dvec3(),
            camera_forward: camera.forward(),
        }
    }

    /// Depth of `p` along the camera's viewing direction.
    pub fn view_depth(&self, p: Vec3) -> f64 {
        (p.as_dvec3() - self.camera_position).dot(self.camera_forward)
    }

    /// The cascade (or two, blended) that shades `p`.
    pub fn choose(&self, p: Vec3) -> CascadeChoice {
        let d = self.view_depth(p);
        let last = self.views.len() - 1;
        if d >= self.splits[last + 1] {
            return CascadeChoice::Beyond;
        }
        // The first cascade whose far split lies beyond d.
        let index = self.splits[1..].partition_point(|&s| s <= d).min(last);
        let (start, end) = (self.splits[index], self.splits[index + 1]);
        let band = self.blend_band * (end - start);
        if index < last && band > 0.0 && d > end - band {
            return CascadeChoice::Blend { index, weight: ((d - (end - band)) / band) as f32 };
        }
        CascadeChoice::One(index)
    }

    /// World size of one texel of cascade `i`.
    pub fn texel_world(&self, i: usize) -> f64 {
        match self.views[i].projection {
            Projection::Orthographic { left, right, bottom, top } => {
                (right - left).max(top - bottom) as f64 / self.views[i].resolution as f64
            }
            Projection::Perspective { .. } | Projection::Paraboloid => {
                unreachable!("cascades are orthographic")
            }
        }
    }
}

/// The camera frustum, for its slices between two view depths.
struct FrustumSlices {
    position: DVec3,
    /// right, up, forward.
    basis: (DVec3, DVec3, DVec3),
    /// tan of half the horizontal and vertical fields of view.
    tan_half: (f64, f64),
}

impl FrustumSlices {
    fn new(camera: &Camera) -> Self {
        let ty = (0.5 * (camera.fov_y_deg as f64).to_radians()).tan();
        let tx = ty * camera.width as f64 / camera.height as f64;
        FrustumSlices { position: camera.position.as_dvec3(), basis: camera.basis(), tan_half: (tx, ty) }
    }

    /// The x and y ranges of the box around the bounding sphere of the slice [a, b] (the same
    /// size whichever way the camera turns), its centre snapped to whole texels when `stabilize`.
    fn sphere_box(
        &self,
        frame: &DirectionalFrame,
        a: f64,
        b: f64,
        resolution: u32,
        stabilize: bool,
    ) -> ((f64, f64), (f64, f64)) {
        let (tx, ty) = self.tan_half;
        let k2 = tx * tx + ty * ty;
        // The centre on the axis equidistant from the near and far corners, or the far plane's
        // centre when that is nearer the far corners than the near ones.
        let z = (0.5 * (a + b) * (1.0 + k2)).min(b);
        let radius = ((z - a).powi(2) + a * a * k2).max((b - z).powi(2) + b * b * k2).sqrt();
        let centre = frame.light_from_world.transform_point3(self.position + self.basis.2 * z);
        let (mut cx, mut cy) = (centre.x, centre.y);
        if !stabilize {
            return ((cx - radius, cx + radius), (cy - radius, cy + radius));
        }
        // Snapping moves the centre by up to a texel: the box is wider than the sphere by one
        // texel on each side (half = r + texel with texel = 2·half/N), so it still holds the
        // whole slice, and its size stays independent of the camera.
        let n = resolution.max(3) as f64;
        let half = radius * n / (n - 2.0);
        let texel = 2.0 * half / n;
        cx = (cx / texel).floor() * texel;
        cy = (cy / texel).floor() * texel;
        ((cx - half, cx + half), (cy - half, cy + half))
    }

    /// The light-space x and y ranges of the slice's eight corners, clipped to the scene's box;
    /// with `stabilize`, widened outward to whole texels of the clipped width.
    fn corner_box(
        &self,
        frame: &DirectionalFrame,
        a: f64,
        b: f64,
        resolution: u32,
        stabilize: bool,
    ) -> ((f64, f64), (f64, f64)) {
        let (right, up, forward) = self.basis;
        let (tx, ty) = self.tan_half;
        let (mut min, mut max) = (DVec3::splat(f64::INFINITY), DVec3::splat(f64::NEG_INFINITY));
        for corner in 0..8 {
            let d = if corner & 4 == 0 { a } else { b };
            let sx = if corner & 1 == 0 { -tx } else { tx };
            let sy = if corner & 2 == 0 { -ty } else { ty };
            let p = self.position + forward * d + right * (d * sx) + up * (d * sy);
            let q = frame.light_from_world.transform_point3(p);
            (min, max) = (min.min(q), max.max(q));
        }
        let (scene_x, scene_y) = frame.scene_xy();
        let clip = |lo: f64, hi: f64, (s_lo, s_hi): (f64, f64)| {
            let (lo, hi) = (lo.max(s_lo), hi.min(s_hi));
            if lo < hi { (lo, hi) } else { (s_lo, s_hi) }
        };
        let (x, y) = (clip(min.x, max.x, scene_x), clip(min.y, max.y, scene_y));
        if !stabilize {
            return (x, y);
        }
        let texel = (x.1 - x.0).max(y.1 - y.0) / resolution as f64;
        let snap = |(lo, hi): (f64, f64)| ((lo / texel).floor() * texel, (hi / texel).ceil() * texel);
        (snap(x), snap(y))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn practical_splits_follow_their_formula_for_lambda_0_half_and_1() {
        let (n, f, count) = (0.5, 200.0, 4);
        let uniform: Vec<f64> = (0..=4).map(|i| n + (f - n) * i as f64 / 4.0).collect();
        let log: Vec<f64> = (0..=4).map(|i| n * (f / n).powf(i as f64 / 4.0)).collect();
        assert_eq!(split_distances(SplitScheme::Practical { lambda: 0.0 }, n, f, count), uniform);
        assert_eq!(split_distances(SplitScheme::Uniform, n, f, count), uniform);
        let practical_log = split_distances(SplitScheme::Practical { lambda: 1.0 }, n, f, count);
        for (a, b) in practical_log.iter().zip(&log) {
            assert!((a - b).abs() <= 1e-12 * b, "{a} against {b}");
        }
        // λ = ½ by hand: split 2 of 4 is ½·n·(f/n)^½ + ½·(n + (f − n)/2) = 5 + 50.125.
        let half = split_distances(SplitScheme::Practical { lambda: 0.5 }, n, f, count);
        assert!((half[2] - (0.5 * 10.0 + 0.5 * 100.25)).abs() < 1e-12, "{}", half[2]);
        assert_eq!((half[0], half[4]), (n, f));
        assert!(half.windows(2).all(|w| w[0] < w[1]));
    }
}
