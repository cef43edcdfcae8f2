//! Pagot, Comba & Oliveira, "Multiple-depth shadow maps" (SIBGRAPI 2004), Fig. 7: shadows on
//! curved receivers, where the 2-SM's transition is thinner than the 3-SM's, on
//! `scenes/papers/curved.json` (a box and a ball casting onto a large sphere).
//!
//! Both maps keep the base depth and the maximum over 3×3 texels; the 3-SM also keeps the
//! minimum (`raster::multi_depth`), so its n-shadow test grades the edge on both sides of the
//! base map's edge, the 2-SM's on one side. Each is read with the paper's single n-shadow test
//! (one tap, no PCF), with a constant bias of three texels' depth at a slope of 60° from the
//! light (the extra depths on the receiver wherever it faces the light by less). The transition
//! is the receiver's pixels strictly between lit and shadowed where it faces the light within
//! those 60° (beyond, its own terminator grades too). Acne and leak on the receiver are reported
//! beside.

use super::claims::{self, Claim, ClaimText, SetupResult};
use super::measure::{LightMap, View, artefacts_in, light_of, shade, spec};
use super::names::PAGOT;
use super::pagot::{PagotSetup, setups_with};
use super::suite::{Suite, plan_of};
use crate::plan::PlanError;
use serde_json::json;
use shadowtruth::raster::LightView;
use shadowtruth::scene::{Scene, load_scene};
use shadowtruth::technique::TechniqueSpec;
use shadowtruth::trace::SceneBvh;

const RESOLUTION: u32 = 512;
const RECEIVER: &str = "receiver";

fn setups() -> Vec<PagotSetup> {
    setups_with(("lower light", "low_sun"))
}

/// The bias's reach: texels of depth at [`BIAS_SLOPE_DEG`] from the light.
const BIAS_TEXELS: f64 = 3.0;
const BIAS_SLOPE_DEG: f64 = 60.0;

/// The 2-SM and the 3-SM, one n-shadow test per pixel, biased for `view`'s texels.
fn n_sms(scene: &Scene, view: &LightView) -> [TechniqueSpec; 2] {
    let (lo, hi) = scene.bounds();
    let texel_world = view.texel_world_size((lo + hi) * 0.5) as f64;
    let bias = BIAS_TEXELS * texel_world * BIAS_SLOPE_DEG.to_radians().tan() / (view.far - view.near) as f64;
    [2, 3].map(|depths| {
        spec(&format!(
            r#"{{ "technique": "mdsm", "depths": {depths}, "neighbourhood": 3, "select": "min_max",
                 "bias": "constant", "bias_depth": {bias:e} }}"#
        ))
    })
}

/// The 2-SM's and the 3-SM's transitions on the receiver, on one set-up.
fn measure(scene: &Scene, bvh: &SceneBvh, setup: &PagotSetup) -> Result<SetupResult, PlanError> {
    let view = View::trace(scene, bvh, "main", light_of(scene, setup.light)?)?;
    let map = LightMap::new(&view, setup.resolution);
    let on_receiver = view.on_objects(|name| name == RECEIVER);
    let to_light = map.view.to_light.expect("the set-ups' lights are directional");
    let facing = BIAS_SLOPE_DEG.to_radians().cos() as f32;
    // The receiver where it faces the light within the bias's 60°: beyond, its own terminator
    // grades too, which is not a cast shadow's transition.
    let judged: Vec<bool> = view
        .gbuffer
        .evaluated
        .iter()
        .zip(&on_receiver)
        .map(|(&i, &r)| r && view.gbuffer.normal[i as usize].dot(to_light) >= facing)
        .collect();
    let mut numbers = json!({ "light": setup.light, "resolution": setup.resolution });
    let mut transitions = [0u64; 2];
    for ((transition, depths), t) in transitions.iter_mut().zip([2, 3]).zip(n_sms(scene, &map.view)) {
        let v = shade(&view, &map, &t, None, 1).visibility;
        *transition = v.iter().zip(&judged).filter(|&(&x, &r)| r && x > 0.0 && x < 1.0).count() as u64;
        let a = artefacts_in(&view, &map, &v, &on_receiver);
        numbers[format!("{depths}_sm")] = json!({ "transition_pixels": *transition, "receiver": a.json() });
    }
    Ok(SetupResult::new(setup.name, numbers, claims::pagot_fig7(transitions[0], transitions[1])))
}

/// Fig. 7.
pub(super) fn claims(suite: &mut Suite) -> Result<Vec<Claim>, PlanError> {
    let path = suite.scene("curved.json");
    let scene = load_scene(&path)?;
    let paper = &setups()[0];
    let view = LightView::new(&light_of(&scene, paper.light)?, scene.bounds(), paper.resolution);
    let techniques = n_sms(&scene, &view);
    let runs = suite.report(&plan_of(&path, &["main"], paper.light, techniques.to_vec(), &[RESOLUTION]))?;
    suite.stage("Pagot et al. Fig. 7 set-ups")?;
    let bvh = SceneBvh::build(&scene);
    let results = suite.grid(setups()).iter().map(|s| measure(&scene, &bvh, s)).collect::<Result<_, _>>()?;
    Ok(vec![Claim::judged(
        ClaimText {
            id: "pagot2004-fig7-curved".into(),
            paper: PAGOT,
            statement: "Fig. 7: on curved receivers, the 2-SM's shadow transition is thinner than the 3-SM's.",
            setup: "scenes/papers/curved.json: a box and a ball over a sphere of radius 1.6 under a directional \
                    light, 512² orthographic map; both maps keep the base depth and the maximum over 3×3 texels, \
                    the 3-SM also the minimum; one n-shadow test a pixel (no PCF); a constant bias of three \
                    texels' depth at 60° from the light (the paper gives none). Acne and leak on the receiver reported.",
            rule: "on the sphere where it faces the light within 60° (the bias's reach): the 2-SM's transition \
                   pixels (strictly between 0 and 1) < the 3-SM's, and at least one (the shadows fall on the sphere)",
        },
        results,
        techniques.iter().filter_map(|t| runs.error_map("main", t, RESOLUTION)).collect(),
    )])
}
