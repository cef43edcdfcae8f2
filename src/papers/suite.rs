//! The papers suite: the runs behind every claim (through the ordinary plan executor, so they land
//! in the usual report with their figures), the measurements a report does not hold (false lit
//! around the featured trunk, distinct PCF values, per-pixel agreement of two techniques), the
//! claims with their verdicts, and the Figure 12 grid.

use super::claims::{self, Claim, IslandNumbers, Verdict, island_numbers_json};
use super::island::FEATURED_TRUNK;
use crate::plan::{Event, Plan, PlanError, execute, parse_plan};
use crate::report::figures::{GridCell, ViewCanvas, grid, run_images, visibility_image, zoom};
use crate::report::{ReportWriter, RunRecord};
use crate::scene::{Scene, load_scene};
use crate::technique::TechniqueSpec;
use crate::trace::{GBuffer, HardReference, ReferenceCache, SceneBvh};
use serde_json::{Map, Value, json};
use std::collections::HashMap;
use std::path::Path;

/// The shadow-map resolution of the island runs.
pub const ISLAND_RESOLUTION: u32 = 2048;
/// The heavily undersampled resolutions of Weiskopf & Ertl's Fig. 5.
pub const L_SHAPE_RESOLUTIONS: [u32; 2] = [64, 128];

const ADAPTIVE_SMALL_K: &str = r#"{ "technique": "adaptive", "k": 0.0001, "epsilon": "original" }"#;
const ADAPTIVE_LARGE_K: &str = r#"{ "technique": "adaptive", "k": 0.01, "epsilon": "original" }"#;
const ADAPTIVE_ENHANCED: &str = r#"{ "technique": "adaptive", "k": 0.0001, "epsilon": "ehm" }"#;
const PCF11_RECEIVER_PLANE: &str =
    r#"{ "technique": "pcf", "kernel": "box", "size": 11, "bias": "receiver_plane", "bias_depth": 0.00001 }"#;
const PCF11_ADAPTIVE: &str =
    r#"{ "technique": "pcf", "kernel": "box", "size": 11, "bias": "adaptive", "k": 0.0001 }"#;
const PCF11_DELTA: &str =
    r#"{ "technique": "pcf", "kernel": "box", "size": 11, "bias": "adaptive_delta", "k": 0.0001 }"#;
const MDSM3_PCF3: &str = r#"{ "technique": "mdsm", "depths": 3, "neighbourhood": 3, "select": "min_max",
    "kernel": "box", "size": 3, "bias": "receiver_plane", "bias_depth": 0.00001 }"#;
const MDSM1_PCF4: &str = r#"{ "technique": "mdsm", "depths": 1, "kernel": "box", "size": 4,
    "bias": "receiver_plane", "bias_depth": 0.00001 }"#;
/// Weiskopf & Ertl's six: the biased single map, second depth, midpoint and dual, the last two
/// with and without back-face culling.
const L_SHAPE_SIX: [&str; 6] = [
    r#"{ "technique": "constant", "bias_depth": 0.005 }"#,
    r#"{ "technique": "second_depth" }"#,
    r#"{ "technique": "midpoint", "cull_back_faces": false }"#,
    r#"{ "technique": "midpoint", "cull_back_faces": true }"#,
    r#"{ "technique": "dual", "z_offset": 0.005, "cull_back_faces": false }"#,
    r#"{ "technique": "dual", "z_offset": 0.005, "cull_back_faces": true }"#,
];

fn spec(json: &str) -> TechniqueSpec {
    serde_json::from_str(json).expect("the suite's technique specs are valid")
}

fn plan_of(
    scene: &Path,
    techniques: &[&str],
    resolutions: &[u32],
    repeats: usize,
) -> Result<Plan, PlanError> {
    let text = json!({
        "format": crate::plan::PLAN_FORMAT,
        "techniques": techniques.iter().map(|t| serde_json::from_str::<Value>(t).expect("valid JSON")).collect::<Vec<_>>(),
        "resolutions": resolutions,
        "repeats": repeats,
    })
    .to_string();
    let mut plan = parse_plan(&text, Path::new("papers"))?;
    plan.scenes = vec![scene.to_path_buf()];
    Ok(plan)
}

/// One camera of a scene with everything traced once: G-buffer, hard reference, BVH.
struct View<'a> {
    scene: &'a Scene,
    gbuffer: GBuffer,
    reference: HardReference,
}

impl<'a> View<'a> {
    fn new(scene: &'a Scene, bvh: &'a SceneBvh, camera_name: &str) -> Result<Self, PlanError> {
        let camera = scene.cameras.iter().position(|c| c.name == camera_name).ok_or_else(|| {
            PlanError::Invalid(format!("{}: no camera '{camera_name}'", scene.source.display()))
        })?;
        let light = &scene.lights[0];
        let gbuffer = GBuffer::trace(scene, bvh, &scene.cameras[camera], light);
        let reference = crate::trace::trace_hard_reference(bvh, &gbuffer, light);
        Ok(View { scene, gbuffer, reference })
    }

    /// The pixel box (x, y, w, h) around the object named `name`, padded by half its size (at
    /// least 8 pixels) on every side; None when the object is not in view.
    fn object_box(&self, name: &str) -> Option<(u32, u32, u32, u32)> {
        let index = self.scene.objects.iter().position(|o| o.name == name)? as u32;
        let w = self.gbuffer.width;
        let (mut x0, mut y0, mut x1, mut y1) = (u32::MAX, u32::MAX, 0, 0);
        for (i, &o) in self.gbuffer.object.iter().enumerate() {
            if o == index {
                let (x, y) = (i as u32 % w, i as u32 / w);
                (x0, y0, x1, y1) = (x0.min(x), y0.min(y), x1.max(x), y1.max(y));
            }
        }
        if x0 > x1 {
            return None;
        }
        let pad_x = ((x1 - x0) / 2).max(8);
        let pad_y = ((y1 - y0) / 2).max(8);
        let (bx, by) = (x0.saturating_sub(pad_x), y0.saturating_sub(pad_y));
        let bw = (x1 + pad_x + 1).min(w) - bx;
        let bh = (y1 + pad_y + 1).min(self.gbuffer.height) - by;
        Some((bx, by, bw, bh))
    }

    /// False-lit pixels (reference shadowed, visibility ≥ ½) inside `rect`.
    fn false_lit_in(&self, visibility: &[f32], rect: (u32, u32, u32, u32)) -> u64 {
        let w = self.gbuffer.width;
        self.gbuffer
            .evaluated
            .iter()
            .zip(visibility)
            .filter(|&(&i, &v)| {
                let (x, y) = (i % w, i / w);
                let inside = x >= rect.0 && x < rect.0 + rect.2 && y >= rect.1 && y < rect.1 + rect.3;
                inside && self.reference.lit[i as usize] == 0 && v >= 0.5
            })
            .count() as u64
    }
}

/// The run of `report` for (scene, camera, technique label, resolution).
fn find<'r>(
    runs: &'r [RunRecord],
    scene: &str,
    camera: &str,
    label: &str,
    resolution: u32,
) -> Option<&'r RunRecord> {
    runs.iter()
        .find(|r| r.scene == scene && r.camera == camera && r.label == label && r.resolution == resolution)
}

fn missing(what: &str) -> PlanError {
    PlanError::Invalid(format!("papers: the run of {what} is missing from the report"))
}

/// Runs the whole suite into `writer`'s folder and returns the claims (also written by the
/// caller as `claims.json`). `scenes_dir` holds `papers/island.json` and `l_shape.json`.
pub fn run_papers(
    scenes_dir: &Path,
    writer: &mut ReportWriter,
    cache: Option<&ReferenceCache>,
    on_event: &mut dyn FnMut(Event),
) -> Result<Vec<Claim>, PlanError> {
    let island_path = scenes_dir.join("papers/island.json");
    let l_shape_path = scenes_dir.join("l_shape.json");
    let mut island_techniques = vec![ADAPTIVE_SMALL_K, ADAPTIVE_LARGE_K, ADAPTIVE_ENHANCED];
    island_techniques.extend([PCF11_RECEIVER_PLANE, PCF11_ADAPTIVE, PCF11_DELTA, MDSM3_PCF3, MDSM1_PCF4]);
    // The island runs' visibilities, kept for the measurements a report does not hold.
    let mut island_visibility: HashMap<(String, String), Vec<f32>> = HashMap::new();
    let mut keep = |event: Event| {
        if let Event::RunDone { record, visibility } = &event {
            island_visibility.insert((record.camera.clone(), record.label.clone()), visibility.to_vec());
        }
        on_event(event)
    };
    let island_plan = plan_of(&island_path, &island_techniques, &[ISLAND_RESOLUTION], 3)?;
    execute(&island_plan, writer, cache, &mut keep)?;
    execute(&plan_of(&l_shape_path, &L_SHAPE_SIX, &L_SHAPE_RESOLUTIONS, 1)?, writer, cache, on_event)?;
    on_event(Event::Stage("papers: measuring the claims".into()));
    let visibility = |camera: &str, json: &str| {
        let label = spec(json).label();
        island_visibility
            .get(&(camera.to_string(), label.clone()))
            .ok_or_else(|| missing(&format!("{label} on {camera}")))
    };

    let island = load_scene(&island_path)?;
    let bvh = SceneBvh::build(&island);
    let front = View::new(&island, &bvh, "front")?;
    let back = View::new(&island, &bvh, "back")?;
    let trunk_box = front.object_box(FEATURED_TRUNK).ok_or_else(|| {
        PlanError::Invalid(format!("{}: {FEATURED_TRUNK} is not in the front view", island_path.display()))
    })?;
    let runs = writer.report().runs.clone();
    let name = island.name.clone();
    let rates = |camera: &str, json: &str| {
        let s = spec(json);
        find(&runs, &name, camera, &s.label(), ISLAND_RESOLUTION)
            .map(|r| (r.rates.false_shadow, r.rates.false_lit))
            .ok_or_else(|| missing(&format!("{} on {camera}", s.label())))
    };
    let mut settings = Vec::new();
    let mut visibilities = Vec::new();
    for json in [ADAPTIVE_SMALL_K, ADAPTIVE_LARGE_K, ADAPTIVE_ENHANCED] {
        let (front_false_shadow, front_false_lit) = rates("front", json)?;
        let (back_false_shadow, back_false_lit) = rates("back", json)?;
        let (v_front, v_back) = (visibility("front", json)?, visibility("back", json)?);
        settings.push(IslandNumbers {
            front_false_shadow,
            front_false_lit,
            back_false_shadow,
            back_false_lit,
            trunk_false_lit: front.false_lit_in(v_front, trunk_box),
        });
        visibilities.push((v_front, v_back));
    }
    let (small_k, large_k, enhanced) = (settings[0], settings[1], settings[2]);
    let figure12 = "figures/papers.figure12.png".to_string();
    write_figure12(writer.dir(), &figure12, &front, &back, &visibilities, trunk_box)
        .map_err(|source| PlanError::Io { path: writer.dir().join(&figure12), source })?;

    let mut out = Vec::new();
    let claim = |id: &str,
                 paper: &str,
                 statement: &str,
                 rule: &str,
                 numbers: Value,
                 verdict: Verdict,
                 figures: Vec<String>| Claim {
        id: id.into(),
        paper: paper.into(),
        statement: statement.into(),
        rule: rule.into(),
        numbers: match numbers {
            Value::Object(m) => m,
            other => Map::from_iter([("value".to_string(), other)]),
        },
        verdict,
        figures,
    };
    const EHM: &str = "Ehm, Ederer, Klein & Nischwitz, Adaptive depth bias for soft shadows (WSCG 2015)";
    out.push(claim(
        "ehm2015-fig12-a",
        EHM,
        "Original adaptive epsilon, K = 0.0001: few errors on the front; projective-aliasing false shadow on the back.",
        "front error ≤ 0.5 %; back false shadow ≥ 0.5 % and ≥ 4× the front's",
        json!({ "original_k_0.0001": island_numbers_json(&small_k) }),
        claims::fig12_a(&small_k),
        vec![figure12.clone()],
    ));
    out.push(claim(
        "ehm2015-fig12-d",
        EHM,
        "Original adaptive epsilon, K = 0.01: less false shadow on the back, but false lit (detachment) at the tree trunks on the front.",
        "back false shadow ≤ ½ of K = 0.0001's; ≥ 10 false-lit pixels in the trunk box, more than with K = 0.0001",
        json!({ "original_k_0.01": island_numbers_json(&large_k), "original_k_0.0001": island_numbers_json(&small_k) }),
        claims::fig12_d(&large_k, &small_k),
        vec![figure12.clone()],
    ));
    out.push(claim(
        "ehm2015-fig12-g",
        EHM,
        "Enhanced epsilon, K = 0.0001: low errors on both sides.",
        "on each camera, error ≤ max(0.5 %, the better original setting's error)",
        json!({ "enhanced_k_0.0001": island_numbers_json(&enhanced) }),
        claims::fig12_g(&enhanced, &small_k, &large_k),
        vec![figure12.clone()],
    ));

    // Ehm et al. Fig. 4 and Table 1: per-tap adaptive against Δbias, 11×11.
    let (a, d) = (visibility("front", PCF11_ADAPTIVE)?, visibility("front", PCF11_DELTA)?);
    let differing = a.iter().zip(d.iter()).filter(|(x, y)| (*x - *y).abs() > 1e-6).count() as u64;
    let largest = a.iter().zip(d.iter()).map(|(x, y)| (x - y).abs()).fold(0.0f32, f32::max);
    let mean = a.iter().zip(d.iter()).map(|(x, y)| (x - y).abs() as f64).sum::<f64>() / a.len().max(1) as f64;
    let evaluated = a.len() as u64;
    out.push(claim(
        "ehm2015-fig4",
        EHM,
        "Adaptive bias per tap and with the Δbias optimisation give identical 11×11 PCF shadows.",
        "no pixel differs by more than 1e-6: holds; at most 0.1 % of pixels: partly",
        json!({ "differing_pixels": differing, "evaluated_pixels": evaluated, "largest_difference": largest,
                "mean_abs_difference": mean, "camera": "front", "light": "spot (perspective map)" }),
        claims::ehm_fig4(differing, evaluated),
        vec![],
    ));
    let ns = |json: &str| {
        let s = spec(json);
        find(&runs, &name, "front", &s.label(), ISLAND_RESOLUTION)
            .map(|r| r.timings.ns_per_pixel)
            .ok_or_else(|| missing(&s.label()))
    };
    let (rp, ad, de) = (ns(PCF11_RECEIVER_PLANE)?, ns(PCF11_ADAPTIVE)?, ns(PCF11_DELTA)?);
    out.push(claim(
        "ehm2015-table1",
        EHM,
        "At 11×11 PCF, the Δbias optimisation costs far less than the per-tap adaptive bias (GPU: 2.27 ms receiver plane, 5.75 ms adaptive, 3.01 ms Δbias).",
        "Δbias/receiver-plane < adaptive/receiver-plane, and ≤ 1.5",
        json!({
            "ns_per_pixel": { "receiver_plane": rp, "adaptive": ad, "adaptive_delta": de },
            "ours": { "adaptive_over_receiver_plane": ad / rp, "adaptive_delta_over_receiver_plane": de / rp },
            "theirs": { "adaptive_over_receiver_plane": 5.75 / 2.27, "adaptive_delta_over_receiver_plane": 3.01 / 2.27 },
        }),
        claims::ehm_table1(ad / rp, de / rp),
        vec![],
    ));

    // Pagot et al.: distinct values and soft error against pixel coverage.
    const PAGOT: &str = "Pagot, Comba & Oliveira, Multiple-depth shadow maps (SIBGRAPI 2004)";
    // Distinct values up to summation rounding (the values are multiples of 1/(n·k), far
    // coarser than 1e-5).
    let distinct = |json: &str| -> Result<usize, PlanError> {
        let v = visibility("front", json)?;
        let mut keys: Vec<i64> = v.iter().map(|x| (*x as f64 * 1e5).round() as i64).collect();
        keys.sort_unstable();
        keys.dedup();
        Ok(keys.len())
    };
    let configs = [(9u32, 3u32, distinct(MDSM3_PCF3)?), (16, 1, distinct(MDSM1_PCF4)?)];
    out.push(claim(
        "pagot2004-table1",
        PAGOT,
        "PCF(k, n) over k taps of an n-depth map takes at most n·k + 1 distinct values.",
        "every configuration within n·k + 1 and reaching it: holds; within but not reaching: partly",
        json!({ "configurations": configs.iter().map(|&(k, n, d)| json!({ "k": k, "n": n, "bound": n * k + 1, "distinct": d })).collect::<Vec<_>>() }),
        claims::pagot_table1(&configs),
        vec![],
    ));
    let mae = |json: &str| {
        let s = spec(json);
        find(&runs, &name, "front", &s.label(), ISLAND_RESOLUTION)
            .and_then(|r| r.soft.map(|soft| soft.mae))
            .ok_or_else(|| missing(&s.label()))
    };
    let (mae3, mae1) = (mae(MDSM3_PCF3)?, mae(MDSM1_PCF4)?);
    out.push(claim(
        "pagot2004-fig6",
        PAGOT,
        "A 3-SM with 3×3 PCF looks at least as good as a 1-SM with 4×4 PCF.",
        "mean absolute error against pixel coverage: 3-SM 3×3 ≤ 1-SM 4×4: holds; within 10 %: partly",
        json!({ "mae_3sm_pcf3x3": mae3, "mae_1sm_pcf4x4": mae1, "camera": "front" }),
        claims::pagot_fig6(mae3, mae1),
        vec![],
    ));

    // Weiskopf & Ertl Fig. 5 on the L-shape.
    let l_name = load_scene(&l_shape_path)?.name;
    for &resolution in &L_SHAPE_RESOLUTIONS {
        let errors: Vec<(String, u64)> = L_SHAPE_SIX
            .iter()
            .map(|json| {
                let s = spec(json);
                find(&runs, &l_name, "main", &s.label(), resolution)
                    .or_else(|| {
                        runs.iter()
                            .find(|r| r.scene == l_name && r.label == s.label() && r.resolution == resolution)
                    })
                    .map(|r| (s.label(), r.counts.false_shadow + r.counts.false_lit))
                    .ok_or_else(|| missing(&s.label()))
            })
            .collect::<Result<_, _>>()?;
        let dual = errors[5].1;
        let others: Vec<u64> = errors[..5].iter().map(|e| e.1).collect();
        out.push(claim(
            &format!("weiskopf2003-fig5-r{resolution}"),
            "Weiskopf & Ertl, Shadow mapping based on dual depth layers (Eurographics 2003)",
            "On the L-shape with a heavily undersampled map, dual depth layers with back-face culling have the fewest errors of the six techniques.",
            "dual+culling strictly fewest false pixels: holds; tied for fewest: partly",
            json!({ "resolution": resolution, "false_pixels": errors.iter().map(|(l, e)| (l.clone(), json!(e))).collect::<Map<_, _>>() }),
            claims::weiskopf_fig5(dual, &others),
            vec![],
        ));
    }
    Ok(out)
}

/// The Figure 12 grid: the references of both cameras, then per setting the front error map,
/// the trunk enlarged and the back error map.
fn write_figure12(
    dir: &Path,
    file: &str,
    front: &View,
    back: &View,
    visibilities: &[(&Vec<f32>, &Vec<f32>)],
    trunk_box: (u32, u32, u32, u32),
) -> std::io::Result<()> {
    let light = &front.scene.lights[0];
    let (front_canvas, back_canvas) = (
        ViewCanvas::new(&front.gbuffer, &front.reference, light),
        ViewCanvas::new(&back.gbuffer, &back.reference, light),
    );
    let reference = |v: &View, c: &ViewCanvas| {
        visibility_image(
            &v.gbuffer,
            c,
            &crate::report::figures::reference_visibility(&v.gbuffer, &v.reference),
        )
    };
    let mut images = vec![
        ("(a) reference, front".to_string(), reference(front, &front_canvas)),
        ("(b) reference, front, trunk".to_string(), zoom(&reference(front, &front_canvas), trunk_box, 4)),
        ("(c) reference, back".to_string(), reference(back, &back_canvas)),
    ];
    let names = ["original K=0.0001", "original K=0.01", "enhanced K=0.0001"];
    let letters = [["(d)", "(e)", "(f)"], ["(g)", "(h)", "(i)"], ["(j)", "(k)", "(l)"]];
    for ((name, (v_front, v_back)), l) in names.iter().zip(visibilities).zip(letters) {
        let (_, e_front) = run_images(&front.gbuffer, &front.reference, v_front, &front_canvas);
        let (_, e_back) = run_images(&back.gbuffer, &back.reference, v_back, &back_canvas);
        images.push((format!("{} {name}, front", l[0]), e_front.clone()));
        images.push((format!("{} {name}, trunk", l[1]), zoom(&e_front, trunk_box, 4)));
        images.push((format!("{} {name}, back", l[2]), e_back));
    }
    let cells: Vec<GridCell> =
        images.iter().map(|(caption, image)| GridCell { image, caption: caption.clone() }).collect();
    grid(&cells, 3, 512).write_png(&dir.join(file))
}
