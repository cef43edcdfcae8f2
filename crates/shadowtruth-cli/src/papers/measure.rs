//! What every paper's experiment shares: a view traced once (G-buffer and hard reference, under a
//! light that a set-up may have moved), one technique shaded at one resolution with the plan
//! executor's own steps (`plan::execute`), and the artefact classes of a run over a region of the
//! image. Every set-up, the paper's included, is measured by these functions.

use super::claims::Artefacts;
use crate::plan::PlanError;
use shadowtruth::metrics::{Counts, LightUv, attribute, timed_median};
use shadowtruth::raster::{DepthFormat, LightView};
use shadowtruth::scene::{Light, Scene};
use shadowtruth::technique::{ShadeContext, ShadeOrder, TechniqueSpec, shade_evaluated};
use shadowtruth::trace::{GBuffer, HardReference, SceneBvh, trace_scored_view};

/// A pixel rectangle (x, y, width, height).
pub(super) type Rect = (u32, u32, u32, u32);

pub(super) fn spec(json: &str) -> TechniqueSpec {
    serde_json::from_str(json).expect("the suite's technique specs are valid")
}

/// The light of `scene` named `name`.
pub(super) fn light_of(scene: &Scene, name: &str) -> Result<Light, PlanError> {
    scene
        .light(name)
        .cloned()
        .ok_or_else(|| PlanError::Invalid(format!("{}: no light {name}", scene.source.display())))
}

/// One camera of a scene under one light, traced once.
pub(super) struct View<'a> {
    pub scene: &'a Scene,
    pub light: Light,
    pub gbuffer: GBuffer,
    pub reference: HardReference,
}

impl<'a> View<'a> {
    pub fn trace(scene: &'a Scene, bvh: &SceneBvh, camera: &str, light: Light) -> Result<Self, PlanError> {
        let camera = scene
            .camera(camera)
            .ok_or_else(|| PlanError::Invalid(format!("{}: no camera '{camera}'", scene.source.display())))?;
        let (gbuffer, reference) = trace_scored_view(scene, bvh, camera, &light);
        Ok(View { scene, light, gbuffer, reference })
    }

    /// Per evaluated pixel (in `gbuffer.evaluated` order): whether it shows an object `keep`
    /// accepts by name.
    pub fn on_objects(&self, keep: impl Fn(&str) -> bool) -> Vec<bool> {
        let kept: Vec<bool> = self.scene.objects.iter().map(|o| keep(&o.name)).collect();
        let object = |i: u32| self.gbuffer.object(self.scene, i as usize) as usize;
        self.gbuffer.evaluated.iter().map(|&i| kept[object(i)]).collect()
    }

    /// Per evaluated pixel: whether it lies inside `rect`.
    pub fn in_rect(&self, (x0, y0, w, h): Rect) -> Vec<bool> {
        let width = self.gbuffer.width;
        let inside = |i: u32| {
            let (x, y) = (i % width, i / width);
            x >= x0 && x < x0 + w && y >= y0 && y < y0 + h
        };
        self.gbuffer.evaluated.iter().map(|&i| inside(i)).collect()
    }

    /// A square pixel box around the object named `name`: centred on its pixels' bounds, as wide
    /// as their longer side and a half (so a trunk's box holds the ground around its foot); None
    /// when the object is not in view.
    pub fn object_box(&self, name: &str) -> Option<Rect> {
        let index = self.scene.objects.iter().position(|o| o.name == name)? as u32;
        let (w, h) = (self.gbuffer.width, self.gbuffer.height);
        let (mut x0, mut y0, mut x1, mut y1) = (u32::MAX, u32::MAX, 0, 0);
        let pixels = 0..self.gbuffer.pixel_count();
        for i in pixels.filter(|&i| self.gbuffer.object(self.scene, i) == index) {
            let (x, y) = (i as u32 % w, i as u32 / w);
            (x0, y0, x1, y1) = (x0.min(x), y0.min(y), x1.max(x), y1.max(y));
        }
        if x0 > x1 {
            return None;
        }
        let half = (3 * (x1 - x0).max(y1 - y0) / 4).max(8);
        let (cx, cy) = ((x0 + x1) / 2, (y0 + y1) / 2);
        let (bx, by) = (cx.saturating_sub(half), cy.saturating_sub(half));
        Some((bx, by, (cx + half + 1).min(w) - bx, (cy + half + 1).min(h) - by))
    }
}

/// A view's light map at one resolution, with what every technique on it shares.
pub(super) struct LightMap {
    pub view: LightView,
    uv: LightUv,
    order: ShadeOrder,
}

impl LightMap {
    pub fn new(v: &View, resolution: u32) -> Self {
        let view = LightView::new(&v.light, v.scene.bounds(), resolution);
        let uv = LightUv::new(&v.gbuffer, &view);
        let order = ShadeOrder::new(&v.gbuffer, &view);
        LightMap { view, uv, order }
    }
}

/// One technique shaded on one view.
pub(super) struct Shaded {
    /// Per evaluated pixel.
    pub visibility: Vec<f32>,
    /// Against the hard reference, with the attribution filled in.
    pub counts: Counts,
    /// Median shading time per evaluated pixel (nanoseconds).
    pub ns_per_pixel: f64,
}

/// Shades `spec` on `v` through `map` (f32 depths), `repeats` times (the time is the median);
/// `scene_scale` replaces the shading context's sceneScale (Dou et al.'s bounding-box diagonal)
/// when given.
pub(super) fn shade(
    v: &View,
    map: &LightMap,
    spec: &TechniqueSpec,
    scene_scale: Option<f32>,
    repeats: usize,
) -> Shaded {
    let technique = spec.build().expect("the papers' techniques are all shaded");
    let layers = shadowtruth::technique::BuiltLayers::build(
        v.scene,
        &map.view,
        DepthFormat::F32,
        &technique.layer_needs(),
    );
    let mut ctx = ShadeContext::new(v.scene, v.gbuffer.footprint, &map.view, layers.as_layers());
    ctx.scene_scale = scene_scale.unwrap_or(ctx.scene_scale);
    let (visibility, shade_ms) =
        timed_median(repeats, || shade_evaluated(technique.as_ref(), &map.order, &ctx));
    // The papers' leaks are every false lit away from a boundary: no light-bleeding class.
    let counts = crate::plan::score_against(v.scene, &v.gbuffer, &v.reference, &visibility, &map.uv, None);
    let ns_per_pixel = shade_ms * 1e6 / visibility.len().max(1) as f64;
    Shaded { visibility, counts, ns_per_pixel }
}

/// [`shade`] on one thread: per-pixel costs then compare across techniques whatever else the
/// machine runs.
pub(super) fn shade_on_one_thread(v: &View, map: &LightMap, spec: &TechniqueSpec, repeats: usize) -> Shaded {
    match rayon::ThreadPoolBuilder::new().num_threads(1).build() {
        Ok(pool) => pool.install(|| shade(v, map, spec, None, repeats)),
        Err(_) => shade(v, map, spec, None, repeats),
    }
}

/// The artefact classes of a whole run.
pub(super) fn artefacts(c: &Counts) -> Artefacts {
    Artefacts { evaluated: c.evaluated, acne: c.acne, leak: c.leak, aliasing: c.aliasing }
}

/// The artefact classes of `visibility` on the evaluated pixels `region` selects: the others are
/// set to the reference, so that they are never false, and the attribution runs as for a run.
pub(super) fn artefacts_in(v: &View, map: &LightMap, visibility: &[f32], region: &[bool]) -> Artefacts {
    let masked: Vec<f32> = v
        .gbuffer
        .evaluated
        .iter()
        .zip(visibility.iter().zip(region))
        .map(|(&i, (&value, &inside))| if inside { value } else { v.reference.lit[i as usize] as f32 })
        .collect();
    let a = attribute(v.scene, &v.gbuffer, &v.reference, &masked, &map.uv, None);
    let evaluated = region.iter().filter(|&&r| r).count() as u64;
    Artefacts { evaluated, acne: a.acne, leak: a.leak, aliasing: a.aliasing }
}

/// Two filtered values closer than this are one level. PCF's values are multiples of 1/(n·k),
/// at least 1/401 apart for the papers' filters (k ≤ 100 taps, n ≤ 4 depths), summed in f32
/// with an error under k·2⁻²⁴ < 1e-5: a gap of 1e-4 lies between the two. (Rounding to a fixed
/// grid instead would split a level that straddles a grid line: 1e-5 steps did for k ≥ 36.)
const LEVEL_GAP: f64 = 1e-4;

/// Distinct values: the sorted values, a new level wherever one lies more than [`LEVEL_GAP`]
/// above the one before.
pub(super) fn distinct_levels<'v>(values: impl Iterator<Item = &'v f32>) -> usize {
    let mut sorted: Vec<f64> = values.map(|&x| x as f64).collect();
    sorted.sort_unstable_by(f64::total_cmp);
    let gaps = sorted.windows(2).filter(|w| w[1] - w[0] > LEVEL_GAP).count();
    if sorted.is_empty() { 0 } else { gaps + 1 }
}

/// Distinct values strictly between 0 and 1.
pub(super) fn interior_levels<'v>(values: impl Iterator<Item = &'v f32>) -> usize {
    distinct_levels(values.filter(|&&x| x > 0.0 && x < 1.0))
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Sums of 81 taps of 1/81 · (0 or ½) in f32, in two orders, are one level per count of
    /// halves, however the rounding of each falls; levels 1/162 apart stay apart.
    #[test]
    fn levels_merge_summation_rounding_and_keep_the_fractions() {
        let sum = |j: usize, reversed: bool| {
            let mut taps: Vec<f32> = (0..81).map(|t| if t < j { 0.5 } else { 0.0 }).collect();
            if reversed {
                taps.reverse();
            }
            taps.iter().fold(0.0f32, |a, &p| a + p / 81.0)
        };
        let values: Vec<f32> = (0..=81).flat_map(|j| [sum(j, false), sum(j, true)]).collect();
        assert_eq!(distinct_levels(values.iter()), 82);
        assert_eq!(distinct_levels([0.0f32, 1.0 / 162.0, 2.0 / 162.0].iter()), 3);
        // Two roundings of one level either side of a line of a 1e-5 grid are one level.
        assert_eq!(distinct_levels([0.123_454_9f32, 0.123_455_1].iter()), 1);
        assert_eq!(distinct_levels([].iter()), 0);
        assert_eq!(interior_levels([0.0f32, 0.5, 0.5, 1.0].iter()), 1);
    }
}
