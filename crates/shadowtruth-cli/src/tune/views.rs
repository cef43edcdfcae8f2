//! What `tune` builds once and what each evaluation shades: per view (scene, camera, light) the
//! G-buffer and the references; per resolution the light view or the light's cascades and the
//! shading order (`plan`'s `MapSetup`); per
//! layer needs the depth layers, kept while the tuned setting does not change them. An
//! evaluation of a setting on one scene is then one shading pass and one scoring per view and
//! resolution.

use crate::plan::{
    BinnedView, ExportedViews, MapSetup, Plan, PlanError, TracedView, ViewReferences, build_layers_timed,
    check_multi_map_lights, load_selected, run_setting,
};
use glam::Vec3;
use shadowtruth::metrics::{Counts, add_false_counts};
use shadowtruth::raster::{DepthFormat, LightView};
use shadowtruth::scene::Scene;
use shadowtruth::technique::{BuiltLayers, CommandParams, LayerNeeds, TechniqueSpec};
use shadowtruth::trace::{GBuffer, ReferenceCache, SceneBvh};

/// Layer sets kept per map: the tuned setting's and one more, so that a parameter that changes
/// the layers (a raster bias) does not keep every set it tried.
const KEPT_LAYER_SETS: usize = 2;

/// Every view of every scene of a plan, traced, with its maps set up.
pub struct TuneViews {
    pub scenes: Vec<SceneViews>,
    format: DepthFormat,
    /// The views exported for a renderer's command, when the tuned technique is one.
    exports: ExportedViews,
}

pub struct SceneViews {
    pub name: String,
    scene: Scene,
    bounds: (Vec3, Vec3),
    views: Vec<View>,
}

struct View {
    /// The camera's and the light's index in the scene.
    camera: usize,
    light: usize,
    gbuffer: GBuffer,
    references: ViewReferences,
    maps: Vec<Map>,
}

/// One shadow-map resolution of a view: its map or cascades, and the layers kept for them (one
/// per map of the set-up).
struct Map {
    setup: MapSetup,
    layers: Vec<(LayerNeeds, Vec<BuiltLayers>)>,
}

impl TuneViews {
    /// Traces every view of `plan` (its references from `cache` when given), calling `stage`
    /// with what is under way. Each scene's BVH is dropped once its views are traced.
    pub fn build(
        plan: &Plan,
        cache: Option<&ReferenceCache>,
        stage: &mut dyn FnMut(&str),
    ) -> Result<Self, PlanError> {
        let format = *plan.depth_formats.first().unwrap_or(&DepthFormat::F32);
        let mut scenes = Vec::new();
        let selected = load_selected(plan)?;
        check_multi_map_lights(plan, &selected)?;
        for selected in selected {
            let scene = selected.scene;
            stage(&format!("{}: building the BVH", scene.name));
            let bvh = SceneBvh::build(&scene);
            let bounds = scene.bounds();
            let mut views = Vec::new();
            for (ci, li) in selected.pairs {
                let (camera, light) = (&scene.cameras[ci], &scene.lights[li]);
                stage(&format!("{}/{}/{}: G-buffer and reference", scene.name, camera.name, light.name));
                let (gbuffer, references) =
                    crate::plan::trace_view(plan, cache, &scene, &bvh, (camera, light), &mut |_| Ok(()))?;
                let maps = plan
                    .resolutions
                    .iter()
                    .map(|&resolution| {
                        let setup =
                            MapSetup::new(plan, (&gbuffer, camera, camera), light, bounds, resolution)?;
                        Ok(Map { setup, layers: Vec::new() })
                    })
                    .collect::<Result<_, PlanError>>()?;
                views.push(View { camera: ci, light: li, gbuffer, references, maps });
            }
            scenes.push(SceneViews { name: scene.name.clone(), scene, bounds, views });
        }
        Ok(TuneViews { scenes, format, exports: ExportedViews::new() })
    }

    /// The counts of `spec` on every view and resolution of scene `index`, summed: shaded here,
    /// or rendered by the renderer's command (which may fail).
    pub fn counts(&mut self, index: usize, spec: &TechniqueSpec) -> Result<Counts, PlanError> {
        if let TechniqueSpec::Command(params) = spec {
            return self.rendered_counts(index, spec, params);
        }
        let technique = spec.build().expect("tune shades built-in techniques or runs commands");
        let needs = technique.layer_needs();
        let format = self.format;
        let s = &mut self.scenes[index];
        let mut total = Counts::default();
        for view in &mut s.views {
            let (reference, _, _) = view.references.for_kind(spec.reference_kind());
            for map in &mut view.maps {
                let setting = map.setup.setting(format, s.bounds);
                let layers = layers_for(&s.scene, &setting.views(), &mut map.layers, format, &needs);
                let visibility = crate::plan::shade_through(technique.as_ref(), &s.scene, &setting, layers);
                total.evaluated += view.gbuffer.evaluated.len() as u64;
                add_false_counts(&mut total, &view.gbuffer, reference, &visibility);
            }
        }
        Ok(total)
    }

    /// [`Self::counts`] of a renderer's command: one run per view and resolution.
    fn rendered_counts(
        &mut self,
        index: usize,
        spec: &TechniqueSpec,
        params: &CommandParams,
    ) -> Result<Counts, PlanError> {
        let s = &self.scenes[index];
        let mut total = Counts::default();
        for view in &s.views {
            let (camera, light) = (&s.scene.cameras[view.camera], &s.scene.lights[view.light]);
            let traced = TracedView {
                scene: &s.scene,
                camera,
                light,
                gbuffer: &view.gbuffer,
                references: &view.references,
            };
            let (reference, _, _) = view.references.for_kind(spec.reference_kind());
            for map in &view.maps {
                let resolution = map.setup.resolution();
                let visibility = run_setting(&mut self.exports, params, &traced, resolution, 0, spec)?;
                total.evaluated += view.gbuffer.evaluated.len() as u64;
                add_false_counts(&mut total, &view.gbuffer, reference, &visibility);
            }
        }
        Ok(total)
    }
}

/// The layers for `needs` of each of `views`: kept from an earlier evaluation, or rasterized now.
fn layers_for<'m>(
    scene: &Scene,
    views: &[&LightView],
    kept: &'m mut Vec<(LayerNeeds, Vec<BuiltLayers>)>,
    format: DepthFormat,
    needs: &LayerNeeds,
) -> &'m [BuiltLayers] {
    match kept.iter().position(|(n, _)| n == needs) {
        Some(i) => &kept[i].1,
        None => {
            let build = |view: &&LightView| {
                build_layers_timed(&BinnedView::new(scene, view), format, needs, 1, None).0
            };
            let built = views.iter().map(build).collect();
            if kept.len() == KEPT_LAYER_SETS {
                kept.remove(0);
            }
            kept.push((*needs, built));
            &kept.last().expect("just pushed").1
        }
    }
}
