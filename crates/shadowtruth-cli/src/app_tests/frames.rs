//! Cascades and frames through the schedule: one cascade over the whole view is the single map,
//! still views never flicker, a moving camera compares the same surface points, and a moving
//! light's flicker is what independent single-frame runs of each frame give.

use crate::plan::{Event, Plan, Watch, execute};
use serde_json::{Value, json};
use shadowtruth::metrics::{FrameDecisions, count_flicker, reference_decisions};
use shadowtruth::record::RunRecord;
use std::path::{Path, PathBuf};

/// The plane-and-box scene seen from far enough that its whole box is in view, under `lights`,
/// with `camera` fields added to its camera.
fn write_scene(dir: &Path, name: &str, camera: Value, lights: Value) -> PathBuf {
    let mut cam = json!({ "name": "main", "up": [0, 1, 0], "fov_y_deg": 45, "width": 160, "height": 120 });
    cam.as_object_mut().unwrap().extend(camera.as_object().unwrap().clone());
    let scene = json!({
        "format": "shadowtruth/scene/v1", "name": name,
        "objects": [
            { "name": "ground", "shape": { "type": "plane", "size": [20, 20] } },
            { "name": "box", "shape": { "type": "box", "size": [1, 1, 1] }, "closed": true,
              "transform": { "rotate_deg": [0, 30, 0], "translate": [0, 1.5, 0] } },
            { "name": "pole", "shape": { "type": "cylinder", "radius": 0.05, "height": 2.0 }, "closed": true,
              "transform": { "translate": [2, 0, 1] } }
        ],
        "cameras": [cam],
        "lights": lights,
    });
    let path = dir.join(format!("{name}.json"));
    std::fs::write(&path, serde_json::to_string_pretty(&scene).unwrap()).unwrap();
    path
}

fn sun(name: &str, extra: Value) -> Value {
    let mut light = json!({ "name": name, "type": "directional", "direction": [-0.3, -1, -0.2],
                            "angular_diameter_deg": 1 });
    light.as_object_mut().unwrap().extend(extra.as_object().unwrap().clone());
    light
}

fn far_camera() -> Value {
    json!({ "position": [-30, 20, 32], "look_at": [0, 0.7, 0] })
}

/// Every shaded technique of the default plan, PCF and PCSS, at 256², over `frames` frames.
fn plan(scene: PathBuf, frames: usize) -> Plan {
    let mut plan = Plan::default_for(vec![scene]);
    let extra = r#"{"format": "shadowtruth/plan/v1", "resolutions": [256], "techniques": [
        {"technique": "pcf", "kernel": "box", "size": 3, "bias": "constant", "bias_depth": 0.002},
        {"technique": "pcss", "bias": "constant", "bias_depth": 0.002}]}"#;
    let extra = crate::plan::parse_plan(extra, Path::new("extra.json")).unwrap();
    plan.techniques.extend(extra.techniques);
    plan.resolutions = vec![256];
    plan.repeats = 1;
    plan.figures = false;
    plan.frames = frames;
    plan
}

/// Every run's record and visibility, and each view's evaluated pixels and reference
/// decisions (per pixel), in order.
struct Seen {
    runs: Vec<(RunRecord, Vec<f32>)>,
    views: Vec<(Vec<u32>, Vec<u8>)>,
}

fn run(plan: &Plan) -> Seen {
    let mut seen = Seen { runs: Vec::new(), views: Vec::new() };
    let mut watch = Watch(|e: &Event| match e {
        Event::RunDone { record, visibility } => seen.runs.push(((*record).clone(), visibility.to_vec())),
        Event::ViewTraced(v) => {
            seen.views.push((v.gbuffer.evaluated.clone(), reference_decisions(v.gbuffer, &v.references.hard)))
        }
        _ => {}
    });
    execute(plan, None, &mut [&mut watch]).unwrap();
    seen
}

#[test]
fn one_cascade_covering_the_whole_view_is_the_single_map_bit_for_bit() {
    let dir = tempfile::tempdir().unwrap();
    let one =
        json!({ "cascades": { "count": 1, "fit": "frustum", "stabilize": false, "max_distance": 1000 } });
    let lights = json!([sun("single", json!({})), sun("one", one)]);
    let scene = write_scene(dir.path(), "whole", far_camera(), lights);
    let seen = run(&plan(scene, 1));
    let (single, cascaded): (Vec<_>, Vec<_>) = seen.runs.iter().partition(|(r, _)| r.light == "single");
    assert_eq!(single.len(), cascaded.len());
    assert!(single.len() > 15);
    for ((a, va), (b, vb)) in single.iter().zip(&cascaded) {
        assert_eq!(a.label, b.label);
        let differing = va.iter().zip(vb).filter(|(x, y)| x.to_bits() != y.to_bits()).count();
        assert_eq!((va.len(), differing), (vb.len(), 0), "{}", a.label);
        assert_eq!(a.counts, b.counts, "{}", a.label);
        let cascades = b.cascades.as_ref().expect("a cascaded run records its cascades");
        let only = cascades.cascades[0].counts;
        assert_eq!(
            (only.evaluated, only.false_shadow, only.false_lit),
            (b.counts.evaluated, b.counts.false_shadow, b.counts.false_lit)
        );
        assert!(a.cascades.is_none());
    }
}

#[test]
fn a_still_light_and_camera_give_zero_flicker_for_every_technique() {
    let dir = tempfile::tempdir().unwrap();
    let csm = json!({ "cascades": { "count": 3, "blend_band": 0.2 } });
    let lights = json!([sun("sun", json!({})), sun("csm", csm)]);
    let scene =
        write_scene(dir.path(), "still", json!({ "position": [-6, 4, 6.5], "look_at": [0, 0.7, 0] }), lights);
    let seen = run(&plan(scene, 3));
    assert!(seen.runs.len() > 30);
    for (record, _) in &seen.runs {
        let t = record.temporal.as_ref().expect("a run over frames has its temporal record");
        assert_eq!(t.frames, 3);
        assert_eq!(t.flicker_pixels, 0, "{} {}", record.light, record.label);
        assert!(t.compared_pixels > 2 * 10_000, "{}", t.compared_pixels);
        assert!(t.frame_errors.iter().all(|&e| e == t.frame_errors[0]), "{}", record.label);
        assert_eq!(record.counts.evaluated, 3 * (record.counts.evaluated / 3));
    }
}

/// A camera path over the plane and box: a dolly along x.
fn dolly() -> Value {
    json!({ "path": { "interpolation": "catmull_rom", "keys": [
        { "time": 0, "position": [-6, 4, 6.5], "look_at": [0, 0.7, 0] },
        { "time": 1, "position": [-4, 3.8, 6.6], "look_at": [1, 0.7, 0] },
        { "time": 2, "position": [-2, 3.6, 6.7], "look_at": [2, 0.7, 0] } ] } })
}

#[test]
fn a_moving_camera_compares_the_same_surface_points_so_one_still_map_never_flickers() {
    let dir = tempfile::tempdir().unwrap();
    let unstable =
        json!({ "cascades": { "count": 3, "fit": "frustum", "stabilize": false, "max_distance": 30 } });
    let lights = json!([sun("sun", json!({})), sun("loose", unstable)]);
    let scene = write_scene(dir.path(), "dolly", dolly(), lights);
    let seen = run(&plan(scene, 4));
    let mut loose_flicker = 0;
    for (record, _) in &seen.runs {
        let t = record.temporal.as_ref().unwrap();
        assert_eq!(t.moving, "camera");
        // The frames see different pixels: the same still map, another image.
        assert!(t.frame_errors.windows(2).any(|w| w[0] != w[1]) || t.mean_error == 0.0, "{}", record.label);
        match record.light.as_str() {
            "sun" => assert_eq!(t.flicker_pixels, 0, "{}", record.label),
            _ => loose_flicker += t.flicker_pixels,
        }
    }
    // Cascades that follow the camera unsnapped do move under the same points.
    assert!(loose_flicker > 0);
}

#[test]
fn a_moving_lights_flicker_is_what_single_frame_runs_of_each_frame_give() {
    let dir = tempfile::tempdir().unwrap();
    // Keys at the frames' times: each frame's light is exactly a key, which a scene of its own
    // can hold as its light's only key.
    let keys = [[-0.3, -1.0, -0.2], [-0.2, -1.0, -0.3], [-0.1, -1.0, -0.35]];
    let light = |keys: Value| {
        json!({ "name": "sun", "type": "directional", "angular_diameter_deg": 1,
                "path": { "interpolation": "linear", "keys": keys } })
    };
    let camera = json!({ "position": [-6, 4, 6.5], "look_at": [0, 0.7, 0] });
    let all_keys = json!([{ "time": 0, "direction": keys[0] }, { "time": 0.5, "direction": keys[1] },
                          { "time": 1, "direction": keys[2] }]);
    let frames = keys.len();
    let over_path =
        run(&plan(write_scene(dir.path(), "sweep", camera.clone(), json!([light(all_keys)])), frames));
    let alone: Vec<Seen> = keys
        .iter()
        .enumerate()
        .map(|(f, key)| {
            let fixed = light(json!([{ "time": 0, "direction": key }]));
            run(&plan(write_scene(dir.path(), &format!("frame{f}"), camera.clone(), json!([fixed])), 1))
        })
        .collect();
    let mut total = 0;
    for (r, (record, _)) in over_path.runs.iter().enumerate() {
        let t = record.temporal.as_ref().unwrap();
        for f in 1..frames {
            let decisions = |seen: &Seen| {
                let (evaluated, reference) = &seen.views[0];
                let mut technique = vec![0u8; reference.len()];
                for (&i, &v) in evaluated.iter().zip(&seen.runs[r].1) {
                    technique[i as usize] = if v >= 0.5 { 2 } else { 1 };
                }
                (technique, reference.clone())
            };
            let (t0, r0) = decisions(&alone[f - 1]);
            let (t1, r1) = decisions(&alone[f]);
            let mut heat = vec![0u16; t0.len()];
            let before = FrameDecisions { technique: &t0, reference: &r0 };
            let after = FrameDecisions { technique: &t1, reference: &r1 };
            let (flicker, _) = count_flicker(&before, &after, &mut heat);
            assert_eq!(alone[f].runs[r].0.label, record.label);
            assert_eq!(t.frame_flicker[f], flicker, "{} frame {f}", record.label);
            let alone_error = alone[f].runs[r].0.rates.error;
            assert_eq!(t.frame_errors[f], alone_error, "{} frame {f}", record.label);
            total += flicker;
        }
    }
    assert!(total > 0, "the sweep moves shadows and acne under some technique");
}
