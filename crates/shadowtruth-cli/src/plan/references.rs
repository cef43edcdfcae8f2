//! The references of one view (scene, camera, light) that a plan's techniques are scored
//! against: the hard mask always, pixel coverage when a filtered technique runs, the area light
//! when PCSS runs; each read from the cache or traced once and shared by every run of the view.

use super::{Plan, PlanError};
use shadowtruth::metrics::thresholded;
use shadowtruth::record::ReferenceUsed;
use shadowtruth::scene::{Camera, Light, Scene};
use shadowtruth::technique::ReferenceKind;
use shadowtruth::trace::{
    GBuffer, HardReference, ReferenceCache, SceneBvh, ShadowOverlap, SoftReference,
    trace_area_light_reference, trace_coverage_reference, trace_hard_reference, trace_shadow_overlap,
};

/// A fractional reference and its ½ threshold (for the hard counts and attribution).
pub struct Fractional {
    pub soft: SoftReference,
    pub hard: HardReference,
}

pub struct ViewReferences {
    pub hard: HardReference,
    /// Where occluders of two objects overlap in the light's view, over the pixels any of the
    /// references shadows: the attribution's light bleeding.
    pub overlap: ShadowOverlap,
    pub coverage: Option<Fractional>,
    pub area_light: Option<Fractional>,
    coverage_grid: u32,
    area_light_grid: u32,
}

impl ViewReferences {
    /// Traces (or reads from `cache`) every reference `plan`'s techniques need for this view.
    /// The pixels the hard reference cannot decide beyond doubt are left out of `gbuffer` first
    /// (`GBuffer::leave_out`), before the soft references are traced over it and before any
    /// technique is scored: no score, attribution or soft reference sees them, and the counts
    /// show them as `uncertain`.
    pub fn new(
        plan: &Plan,
        cache: Option<&ReferenceCache>,
        scene: &Scene,
        bvh: &SceneBvh,
        gbuffer: &mut GBuffer,
        camera: &Camera,
        light: &Light,
    ) -> Result<ViewReferences, PlanError> {
        let io = |source| PlanError::Io {
            path: cache.map_or_else(Default::default, |c| c.dir().to_path_buf()),
            source,
        };
        let needs = |kind| plan.techniques.iter().any(|t| t.reference_kind() == kind);
        let hard = match cache {
            Some(c) => c.hard_reference(scene, bvh, gbuffer, camera, light).map_err(io)?.0,
            None => trace_hard_reference(scene, bvh, gbuffer, light),
        };
        gbuffer.leave_out(&hard.uncertain);
        let gbuffer = &*gbuffer;
        let fractional = |soft: SoftReference| Fractional {
            hard: thresholded(soft.width, soft.height, &soft.visibility),
            soft,
        };
        let coverage = if needs(ReferenceKind::Coverage) {
            let grid = plan.coverage_grid;
            Some(fractional(match cache {
                Some(c) => c.coverage_reference(scene, bvh, gbuffer, camera, light, grid).map_err(io)?.0,
                None => trace_coverage_reference(scene, bvh, gbuffer, camera, light, grid),
            }))
        } else {
            None
        };
        let area_light = if needs(ReferenceKind::AreaLight) {
            let grid = plan.area_light_grid;
            Some(fractional(match cache {
                Some(c) => c.area_light_reference(scene, bvh, gbuffer, camera, light, grid).map_err(io)?.0,
                None => trace_area_light_reference(scene, bvh, gbuffer, light, grid)
                    .map_err(|e| PlanError::Invalid(e.to_string()))?,
            }))
        } else {
            None
        };
        let shadowed = |i: usize| {
            let fractional_shadow = |f: &Option<Fractional>| f.as_ref().is_some_and(|f| f.hard.lit[i] == 0);
            hard.lit[i] == 0 || fractional_shadow(&coverage) || fractional_shadow(&area_light)
        };
        let overlap = trace_shadow_overlap(scene, bvh, gbuffer, light, shadowed);
        Ok(ViewReferences {
            hard,
            overlap,
            coverage,
            area_light,
            coverage_grid: plan.coverage_grid,
            area_light_grid: plan.area_light_grid,
        })
    }

    /// The reference a technique of `kind` is scored against: its (thresholded) hard form, its
    /// fractional values if any, and what the report records.
    pub fn for_kind(&self, kind: ReferenceKind) -> (&HardReference, Option<&SoftReference>, ReferenceUsed) {
        let used = |samples| ReferenceUsed { kind, samples };
        match (kind, &self.coverage, &self.area_light) {
            (ReferenceKind::Coverage, Some(f), _) => {
                (&f.hard, Some(&f.soft), used(self.coverage_grid.pow(2)))
            }
            (ReferenceKind::AreaLight, _, Some(f)) => {
                (&f.hard, Some(&f.soft), used(self.area_light_grid.pow(2)))
            }
            _ => (&self.hard, None, ReferenceUsed::default()),
        }
    }
}
