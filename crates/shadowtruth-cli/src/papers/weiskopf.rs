//! Weiskopf & Ertl, "Shadow mapping based on dual depth layers" (Eurographics 2003), Fig. 5 to 7
//! and the offset's dependence, on `scenes/papers/l_above.json`: the L-shape above the ground, lit from its upper left so that
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
//!
//! Fig. 6 and 7 filter the dual layers' shadow test (bilinear; a jittered 4×4): the same rule
//! as Fig. 5's dual, on the filtered visibility. "Much less dependent on this value": the
//! constant bias and dual's z_offset are each swept over two octaves either way, and the spreads
//! of the L's errors compared.

use super::claims::{self, Claim, ClaimText, LArtefacts, OffsetSweep, SetupResult};
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

/// The techniques, in this order: the biased single map, second depth, midpoint and dual (each
/// without and with back-face culling); then dual with culling (the paper's dual depth layers)
/// filtered as in Fig. 6 (bilinear) and Fig. 7 (jittered 4×4).
fn techniques(setup: &LSetup, view: &LightView) -> [TechniqueSpec; 8] {
    let z = setup.z_offset_world / (view.far - view.near) as f64;
    let filtered = |kernel: &str| {
        spec(&format!(
            r#"{{ "technique": "pcf", "kernel": "{kernel}", "layers": "dual", "z_offset": {z:e}, "cull_back_faces": true }}"#
        ))
    };
    [
        constant(setup.bias_world),
        spec(r#"{ "technique": "second_depth" }"#),
        spec(r#"{ "technique": "midpoint", "cull_back_faces": false }"#),
        spec(r#"{ "technique": "midpoint", "cull_back_faces": true }"#),
        spec(&format!(r#"{{ "technique": "dual", "z_offset": {z:e}, "cull_back_faces": false }}"#)),
        dual(z),
        filtered("bilinear"),
        filtered("jitter4x4"),
    ]
}

/// Indices into [`techniques`].
const CONSTANT: usize = 0;
const MIDPOINT: usize = 2;
const DUAL: usize = 5;
const DUAL_BILINEAR: usize = 6;
const DUAL_JITTERED: usize = 7;

fn constant(bias_world: f64) -> TechniqueSpec {
    spec(&format!(r#"{{ "technique": "constant", "bias_world": {bias_world} }}"#))
}

/// Dual depth layers with back-face culling, `z_offset` in depth units.
fn dual(z_offset: f64) -> TechniqueSpec {
    spec(&format!(r#"{{ "technique": "dual", "z_offset": {z_offset:e}, "cull_back_faces": true }}"#))
}

/// "Much less dependent on this value": the constant bias and dual's z_offset each scaled by
/// these factors around the set-up's values, two octaves either way.
const OFFSET_FACTORS: [f64; 5] = [0.25, 0.5, 1.0, 2.0, 4.0];

/// The L's acne + leak rate of the constant bias and of dual at each of [`OFFSET_FACTORS`];
/// at factor 1 they are `at_one`'s (the set-up's own techniques, already shaded).
fn offset_sweep(view: &View, map: &LightMap, setup: &LSetup, on_l: &[bool], at_one: [f64; 2]) -> OffsetSweep {
    let z = setup.z_offset_world / (map.view.far - map.view.near) as f64;
    let rate = |t: TechniqueSpec| {
        let v = shade(view, map, &t, None, 1).visibility;
        artefacts_in(view, map, &v, on_l).error_rate()
    };
    let sweep = |one: f64, at: &dyn Fn(f64) -> TechniqueSpec| {
        OFFSET_FACTORS.iter().map(|&f| if f == 1.0 { one } else { rate(at(f)) }).collect()
    };
    OffsetSweep {
        factors: OFFSET_FACTORS.to_vec(),
        constant: sweep(at_one[0], &|f| constant(f * setup.bias_world)),
        dual: sweep(at_one[1], &|f| dual(f * z)),
    }
}

/// Fig. 5's numbers on one set-up at one resolution, and each technique's artefacts on the L
/// and the ground (in [`techniques`]' order), and the offset sweep.
fn measure(view: &View, setup: &LSetup, resolution: u32) -> Measured {
    let map = LightMap::new(view, resolution);
    let (on_l, on_ground) = (view.on_objects(|n| n == L_OBJECT), view.on_objects(|n| n != L_OBJECT));
    let mut techniques = Map::new();
    let mut classes = Vec::new();
    for t in self::techniques(setup, &map.view) {
        let v = shade(view, &map, &t, None, 1).visibility;
        let c = LArtefacts {
            l: artefacts_in(view, &map, &v, &on_l),
            ground: artefacts_in(view, &map, &v, &on_ground),
        };
        techniques.insert(t.label(), json!({ "l": c.l.json(), "ground": c.ground.json() }));
        classes.push(c);
    }
    let at_one = [classes[CONSTANT].l.error_rate(), classes[DUAL].l.error_rate()];
    let sweep = offset_sweep(view, &map, setup, &on_l, at_one);
    let numbers = json!({ "light": setup.light, "resolution": resolution, "bias_world": setup.bias_world,
                          "z_offset_world": setup.z_offset_world, "techniques": techniques,
                          "offset_sweep_l_error_rate": sweep });
    Measured { setup: setup.name, numbers, classes, sweep }
}

/// One set-up's measurements at one resolution.
#[derive(Clone)]
struct Measured {
    setup: &'static str,
    numbers: serde_json::Value,
    classes: Vec<LArtefacts>,
    sweep: OffsetSweep,
}

const SETUP: &str = "scenes/papers/l_above.json: the L above the ground, lit from its upper left, a camera facing \
                     its lit faces, silhouettes and crease; constant bias \"chosen too large\" (0.5, half the \
                     arm's thickness), z_offset \"well above\" it (1.0). Every technique's acne and leak on the L \
                     and the ground are in the numbers (second depth too, which Fig. 5 does not show).";

/// The panels as claims at one resolution, from each set-up's measurements (the paper's first):
/// Fig. 5's dual depth layers with back-face culling (the paper's), midpoint without culling (b)
/// and the constant bias (d); dual filtered as in Fig. 6 and Fig. 7; and the dependence on the
/// offset's value.
fn panels(resolution: u32, measured: &[Measured], error_map: impl Fn(&[usize]) -> Vec<String>) -> [Claim; 6] {
    let judged = |rule: &dyn Fn(&Measured) -> claims::Judgement| {
        measured.iter().map(|m| SetupResult::new(m.setup, m.numbers.clone(), rule(m))).collect()
    };
    let text = |id: &str, statement, rule| ClaimText {
        id: format!("weiskopf2003-{id}-r{resolution}"),
        paper: WEISKOPF,
        statement,
        setup: SETUP,
        rule,
    };
    let clean =
        |t: usize, name: &'static str| move |m: &Measured| claims::weiskopf_clean(name, &m.classes[t]);
    [
        Claim::judged(
            text(
                "fig5-dual",
                "With a heavily undersampled map, dual depth layers show neither self-shadowing at silhouettes nor \
                 self-unshadowing at the crease.",
                "dual (with back-face culling): acne and leak on the L each < 0.5 % of its pixels (the ground and \
                 outline aliasing reported)",
            ),
            judged(&clean(DUAL, "dual")),
            error_map(&[DUAL]),
        ),
        Claim::judged(
            text(
                "fig5-b-midpoint",
                "Fig. 5 (b): midpoint shadow maps without back-face culling show self-unshadowing at the crease.",
                "midpoint without culling: leak on the L ≥ 0.5 % of its pixels",
            ),
            judged(&|m| claims::weiskopf_fig5_unshadows("midpoint", &m.classes[MIDPOINT])),
            error_map(&[MIDPOINT]),
        ),
        Claim::judged(
            text(
                "fig5-d-constant",
                "Fig. 5 (d): a constant bias chosen too large lets light leak onto the L.",
                "constant bias: leak on the L ≥ 0.5 % of its pixels",
            ),
            judged(&|m| claims::weiskopf_fig5_unshadows("constant bias", &m.classes[CONSTANT])),
            error_map(&[CONSTANT]),
        ),
        Claim::judged(
            text(
                "fig6-bilinear",
                "Fig. 6, and the abstract: \"Dual depth mapping only modifies the construction of the shadow map and \
                 can therefore be combined with other extensions such as filtering\": with bilinear filtering of the \
                 shadow test, still neither self-shadowing nor self-unshadowing.",
                "dual (with back-face culling), bilinear PCF over its layers: acne and leak on the L each < 0.5 % of \
                 its pixels, the filtered visibility against the hard reference at ½ (the ground and outline \
                 aliasing reported)",
            ),
            judged(&clean(DUAL_BILINEAR, "dual, bilinear")),
            error_map(&[DUAL_BILINEAR]),
        ),
        Claim::judged(
            text(
                "fig7-jittered",
                "Fig. 7: dual depth layers with a jittered 4×4 filter of the shadow test, still neither \
                 self-shadowing nor self-unshadowing.",
                "dual (with back-face culling), PCF over its layers with one jittered tap in each cell of a 4×4 \
                 grid (radius 2 texels, the tool's jitter4x4): acne and leak on the L each < 0.5 % of its pixels, \
                 the filtered visibility against the hard reference at ½",
            ),
            judged(&clean(DUAL_JITTERED, "dual, jittered 4×4")),
            error_map(&[DUAL_JITTERED]),
        ),
        Claim::judged(
            text(
                "offset-dependence",
                "Dual depth layers are \"much less dependent on this value\" (the offset) than a single map is on \
                 its constant bias.",
                "the constant bias and dual's z_offset each scaled by ¼, ½, 1, 2 and 4 around the set-up's values: \
                 the spread (largest − smallest) of the L's acne + leak rate across them is, for dual, at most ½ \
                 of the constant bias's (\"much less\": at least a factor of two), and the constant bias's spread \
                 is more than 0 (a value that matters)",
            ),
            judged(&|m| claims::weiskopf_offset_dependence(&m.sweep)),
            error_map(&[CONSTANT, DUAL]),
        ),
    ]
}

/// Fig. 5's panels, Fig. 6 and 7 and the offset's dependence as claims at each resolution.
pub(super) fn claims(suite: &mut Suite) -> Result<Vec<Claim>, PlanError> {
    let path = suite.scene("l_above.json");
    let scene = load_scene(&path)?;
    let paper = &setups()[0];
    let view = LightView::new(&light_of(&scene, paper.light)?, scene.bounds(), L_RESOLUTIONS[0]);
    let paper_techniques = techniques(paper, &view);
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
    let error_map = |k: &[usize], resolution| {
        k.iter().filter_map(|&k| runs.error_map("main", &paper_techniques[k], resolution)).collect()
    };
    Ok(per_resolution
        .iter()
        .zip(L_RESOLUTIONS)
        .flat_map(|(measured, resolution)| panels(resolution, measured, |k| error_map(k, resolution)))
        .collect())
}
