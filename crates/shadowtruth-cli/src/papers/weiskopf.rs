//! Weiskopf & Ertl, "Shadow mapping based on dual depth layers" (Eurographics 2003), Fig. 5, on
//! `scenes/papers/l_above.json`: the L-shape above the ground, lit from its upper left so that
//! the upright arm shadows the lower arm's top from the crease on, seen by a camera that faces its
//! lit faces, their silhouettes and the crease. (The bundled `scenes/l_shape.json` stands the L
//! on the ground and shows only faces turned away from the light.)
//!
//! The paper's artefacts are self-shadowing at silhouettes and self-unshadowing at the crease; its
//! constant bias is "chosen too large" and its z_offset "well above" it. So the single map gets a
//! constant bias of half the L's arm thickness and dual a z_offset of twice that, and each
//! technique is judged on each class on the L (acne: self-shadowing; leak: self-unshadowing),
//! with the ground's acne and leak and every outline aliasing reported beside. The sensitivity
//! grid halves and doubles both (keeping z_offset twice the bias) and steepens the light.

use super::claims::{self, Claim, ClaimText, LArtefacts, SetupResult};
use super::measure::{LightMap, View, artefacts_in, light_of, shade, spec};
use super::suite::{Suite, plan_of};
use crate::plan::PlanError;
use serde_json::{Map, json};
use shadowtruth::raster::LightView;
use shadowtruth::scene::load_scene;
use shadowtruth::technique::TechniqueSpec;
use shadowtruth::trace::SceneBvh;

/// The heavily undersampled resolutions of Fig. 5, one claim each.
pub const L_RESOLUTIONS: [u32; 2] = [64, 128];
/// The constant bias "chosen too large": half the L's arm thickness (1), in scene units, more
/// than twice what its top faces need at 64² (a texel of about 0.2 at 35° from the light).
const CONSTANT_BIAS_WORLD: f64 = 0.5;
/// z_offset "well above" it: twice, in scene units along the light's axis.
const Z_OFFSET_WORLD: f64 = 1.0;
const L_OBJECT: &str = "l_solid";
const WEISKOPF: &str = "Weiskopf & Ertl, Shadow mapping based on dual depth layers (Eurographics 2003)";

struct LSetup {
    name: &'static str,
    light: &'static str,
    bias_world: f64,
    z_offset_world: f64,
}

fn setups() -> Vec<LSetup> {
    let s = |name, light, bias_world, z_offset_world| LSetup { name, light, bias_world, z_offset_world };
    vec![
        s("paper: bias 0.5 (too large), z_offset 1.0", "above", CONSTANT_BIAS_WORLD, Z_OFFSET_WORLD),
        s("bias 0.25, z_offset 0.5", "above", 0.5 * CONSTANT_BIAS_WORLD, 0.5 * Z_OFFSET_WORLD),
        s("bias 1.0, z_offset 2.0", "above", 2.0 * CONSTANT_BIAS_WORLD, 2.0 * Z_OFFSET_WORLD),
        s("steeper light", "steep", CONSTANT_BIAS_WORLD, Z_OFFSET_WORLD),
    ]
}

/// The six techniques: the biased single map, second depth, midpoint and dual (the last two
/// without and with back-face culling). The last is the paper's dual depth layers.
fn six(setup: &LSetup, view: &LightView) -> [TechniqueSpec; 6] {
    let z = setup.z_offset_world / (view.far - view.near) as f64;
    [
        spec(&format!(r#"{{ "technique": "constant", "bias_world": {} }}"#, setup.bias_world)),
        spec(r#"{ "technique": "second_depth" }"#),
        spec(r#"{ "technique": "midpoint", "cull_back_faces": false }"#),
        spec(r#"{ "technique": "midpoint", "cull_back_faces": true }"#),
        spec(&format!(r#"{{ "technique": "dual", "z_offset": {z:e}, "cull_back_faces": false }}"#)),
        spec(&format!(r#"{{ "technique": "dual", "z_offset": {z:e}, "cull_back_faces": true }}"#)),
    ]
}

/// Fig. 5's numbers on one set-up at one resolution, and each technique's artefacts on the L
/// and the ground (in `six`'s order).
fn measure(view: &View, setup: &LSetup, resolution: u32) -> Measured {
    let map = LightMap::new(view, resolution);
    let (on_l, on_ground) = (view.on_objects(|n| n == L_OBJECT), view.on_objects(|n| n != L_OBJECT));
    let mut techniques = Map::new();
    let mut classes = Vec::new();
    for t in six(setup, &map.view) {
        let v = shade(view, &map, &t, None, 1).visibility;
        let c = LArtefacts {
            l: artefacts_in(view, &map, &v, &on_l),
            ground: artefacts_in(view, &map, &v, &on_ground),
        };
        techniques.insert(t.label(), json!({ "l": c.l.json(), "ground": c.ground.json() }));
        classes.push(c);
    }
    let numbers = json!({ "light": setup.light, "resolution": resolution, "bias_world": setup.bias_world,
                          "z_offset_world": setup.z_offset_world, "techniques": techniques });
    Measured { setup: setup.name, numbers, classes }
}

/// One set-up's measurements at one resolution.
#[derive(Clone)]
struct Measured {
    setup: &'static str,
    numbers: serde_json::Value,
    classes: Vec<LArtefacts>,
}

const SETUP: &str = "scenes/papers/l_above.json: the L above the ground, lit from its upper left, a camera facing \
                     its lit faces, silhouettes and crease; constant bias \"chosen too large\" (0.5, half the \
                     arm's thickness), z_offset \"well above\" it (1.0). Every technique's acne and leak on the L \
                     and the ground are in the numbers (second depth too, which Fig. 5 does not show).";

/// Fig. 5's panels as claims at one resolution, from each set-up's measurements (the paper's
/// first): dual depth layers with back-face culling (the paper's), midpoint without culling
/// (b) and the constant bias (d).
fn panels(resolution: u32, measured: &[Measured], error_map: impl Fn(usize) -> Vec<String>) -> [Claim; 3] {
    let judged = |rule: &dyn Fn(&[LArtefacts]) -> claims::Judgement| {
        measured.iter().map(|m| SetupResult::new(m.setup, m.numbers.clone(), rule(&m.classes))).collect()
    };
    let text = |id: &str, statement, rule| ClaimText {
        id: format!("weiskopf2003-fig5-{id}-r{resolution}"),
        paper: WEISKOPF,
        statement,
        setup: SETUP,
        rule,
    };
    [
        Claim::judged(
            text(
                "dual",
                "With a heavily undersampled map, dual depth layers show neither self-shadowing at silhouettes nor \
                 self-unshadowing at the crease.",
                "dual (with back-face culling): acne and leak on the L each < 0.5 % of its pixels (the ground and \
                 outline aliasing reported)",
            ),
            judged(&|c| claims::weiskopf_fig5_dual(&c[5])),
            error_map(5),
        ),
        Claim::judged(
            text(
                "b-midpoint",
                "Fig. 5 (b): midpoint shadow maps without back-face culling show self-unshadowing at the crease.",
                "midpoint without culling: leak on the L ≥ 0.5 % of its pixels",
            ),
            judged(&|c| claims::weiskopf_fig5_unshadows("midpoint", &c[2])),
            error_map(2),
        ),
        Claim::judged(
            text(
                "d-constant",
                "Fig. 5 (d): a constant bias chosen too large lets light leak onto the L.",
                "constant bias: leak on the L ≥ 0.5 % of its pixels",
            ),
            judged(&|c| claims::weiskopf_fig5_unshadows("constant bias", &c[0])),
            error_map(0),
        ),
    ]
}

/// Fig. 5, its panels as claims at each resolution.
pub(super) fn claims(suite: &mut Suite) -> Result<Vec<Claim>, PlanError> {
    let path = suite.scene("l_above.json");
    let scene = load_scene(&path)?;
    let paper = &setups()[0];
    let view = LightView::new(&light_of(&scene, paper.light)?, scene.bounds(), L_RESOLUTIONS[0]);
    let paper_techniques = six(paper, &view);
    let runs =
        suite.report(&plan_of(&path, &["main"], paper.light, paper_techniques.to_vec(), &L_RESOLUTIONS))?;
    suite.stage("Weiskopf & Ertl Fig. 5 set-ups")?;
    let bvh = SceneBvh::build(&scene);
    let setups = suite.grid(setups());
    let mut per_resolution = vec![Vec::new(); L_RESOLUTIONS.len()];
    for setup in &setups {
        let view = View::trace(&scene, &bvh, "main", light_of(&scene, setup.light)?)?;
        for (results, &resolution) in per_resolution.iter_mut().zip(&L_RESOLUTIONS) {
            results.push(measure(&view, setup, resolution));
        }
    }
    let error_map =
        |k: usize, resolution| runs.error_map("main", &paper_techniques[k], resolution).into_iter().collect();
    Ok(per_resolution
        .iter()
        .zip(L_RESOLUTIONS)
        .flat_map(|(measured, resolution)| panels(resolution, measured, |k| error_map(k, resolution)))
        .collect())
}
