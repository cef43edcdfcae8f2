//! The reference does not depend on where the scene sits or on its scale: no scene-dependent
//! epsilon. The same scene moved far from the origin, or scaled by 1e-3 or 1e3 (camera and
//! light with it), gives the same mask except within one pixel of a boundary.

mod common;

use common::{near_boundary, repo, scene_from_json, trace_first};
use serde_json::Value;

fn plane_box_transformed(scale: f64, offset: [f64; 3]) -> Value {
    let mut v: Value =
        serde_json::from_str(&std::fs::read_to_string(repo().join("scenes/plane_box.json")).unwrap())
            .unwrap();
    let map = |p: &Value, k: usize| p[k].as_f64().unwrap() * scale + offset[k];
    for object in v["objects"].as_array_mut().unwrap() {
        let t = object.get("transform").cloned().unwrap_or(Value::Null);
        let s: Vec<f64> =
            (0..3).map(|k| t.get("scale").map_or(1.0, |s| s[k].as_f64().unwrap()) * scale).collect();
        let tr: Vec<f64> = (0..3)
            .map(|k| t.get("translate").map_or(0.0, |s| s[k].as_f64().unwrap()) * scale + offset[k])
            .collect();
        let rot = t.get("rotate_deg").cloned().unwrap_or(serde_json::json!([0, 0, 0]));
        object["transform"] = serde_json::json!({ "scale": s, "rotate_deg": rot, "translate": tr });
    }
    for camera in v["cameras"].as_array_mut().unwrap() {
        for key in ["position", "look_at"] {
            let p = camera[key].clone();
            camera[key] = serde_json::json!([map(&p, 0), map(&p, 1), map(&p, 2)]);
        }
    }
    v
}

fn compare(scale: f64, offset: [f64; 3]) {
    let base = scene_from_json(&plane_box_transformed(1.0, [0.0; 3]));
    let moved = scene_from_json(&plane_box_transformed(scale, offset));
    let (g0, r0) = trace_first(&base);
    let (g1, r1) = trace_first(&moved);
    let (a, b) = (r0.mask_codes(&g0), r1.mask_codes(&g1));
    let edge = near_boundary(g0.width, g0.height, &a);
    let away: Vec<usize> = (0..a.len()).filter(|&i| a[i] != b[i] && !edge[i]).collect();
    let shadowed = a.iter().filter(|&&c| c == 0).count();
    assert!(shadowed > 5_000, "the scene must cast a shadow");
    assert!(
        away.is_empty(),
        "scale {scale}, offset {offset:?}: {} pixels differ away from boundaries, e.g. {:?}",
        away.len(),
        &away[..away.len().min(5)]
    );
}

#[test]
fn translated_far_from_the_origin() {
    compare(1.0, [1e4, 0.0, 1e4]);
}

#[test]
fn scaled_down_1e_3() {
    compare(1e-3, [0.0; 3]);
}

#[test]
fn scaled_up_1e3() {
    compare(1e3, [0.0; 3]);
}
