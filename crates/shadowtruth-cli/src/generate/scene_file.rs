//! The scene file of a generated scene: its objects, a camera over the ground from one corner,
//! a low sun and a spot light above the centre, placed from the ground's size and the tallest
//! caster so that long shadows fall across the camera's view.

use super::generated::GeneratedScene;
use super::request::{GenerateOptions, SceneKind};
use glam::DVec3;
use std::fmt::Write as _;

/// The sun's direction (towards the ground): about 30° above the horizon.
const SUN_DIRECTION: [f64; 3] = [0.6, -0.45, -0.35];
const SUN_ANGULAR_DIAMETER_DEG: f64 = 0.5;
const SPOT_CONE_DEG: f64 = 70.0;
const CAMERA_FOV_DEG: f64 = 50.0;

/// The text of `scene.json`; `files[i]` is the mesh file of object `i`.
pub(super) fn scene_json(options: &GenerateOptions, scene: &GeneratedScene, files: &[String]) -> String {
    let name = match options.kind {
        SceneKind::City => "city",
        SceneKind::Forest => "forest",
    };
    let s = scene.ground_size_m;
    let top = scene.top_m;
    let mut out =
        format!("{{\n  \"format\": \"shadowtruth/scene/v1\",\n  \"name\": \"{name}\",\n  \"objects\": [\n");
    for (k, (object, file)) in scene.objects.iter().zip(files).enumerate() {
        let comma = if k + 1 == files.len() { "" } else { "," };
        let _ = writeln!(
            out,
            "    {{ \"name\": \"{}\", \"mesh\": \"{file}\", \"closed\": {}{} }}{comma}",
            object.name,
            object.closed,
            instances_json(&object.instances)
        );
    }
    let camera = DVec3::new(-0.55 * s, 0.3 * s + top, 0.55 * s);
    let look_at = DVec3::new(0.05 * s, 0.0, -0.05 * s);
    let _ = writeln!(
        out,
        "  ],\n  \"cameras\": [\n    {{ \"name\": \"main\", \"position\": {}, \"look_at\": {}, \"up\": [0, 1, 0],\n      \
         \"fov_y_deg\": {CAMERA_FOV_DEG}, \"width\": {}, \"height\": {} }}\n  ],",
        v3(camera),
        v3(look_at),
        options.width_px,
        options.height_px
    );
    let spot = DVec3::new(-0.15 * s, top + 0.35 * s, 0.1 * s);
    let target = DVec3::new(0.1 * s, 0.0, -0.1 * s);
    let reach = (spot - DVec3::new(0.5 * s, 0.0, -0.5 * s)).length() * 1.5;
    let _ = write!(
        out,
        "  \"lights\": [\n    {{ \"name\": \"sun\", \"type\": \"directional\", \"direction\": {}, \
         \"angular_diameter_deg\": {SUN_ANGULAR_DIAMETER_DEG} }},\n    \
         {{ \"name\": \"lamp\", \"type\": \"spot\", \"position\": {}, \"direction\": {},\n      \
         \"cone_deg\": {SPOT_CONE_DEG}, \"near\": 1, \"far\": {}, \"radius\": 0.5 }}\n  ]\n}}\n",
        v3(DVec3::from_array(SUN_DIRECTION)),
        v3(spot),
        v3(target - spot),
        number(reach.ceil())
    );
    out
}

/// `, "instances": [...]` for an instanced object, one transform a line; nothing otherwise.
fn instances_json(instances: &[shadowtruth::scene::Transform]) -> String {
    let mut out = String::new();
    for (k, t) in instances.iter().enumerate() {
        let _ = write!(
            out,
            "{}\n      {{ \"scale\": {}, \"rotate_deg\": {}, \"translate\": {} }}",
            if k == 0 { ", \"instances\": [" } else { "," },
            v3(t.scale.as_dvec3()),
            v3(t.rotate_deg.as_dvec3()),
            v3(t.translate.as_dvec3())
        );
    }
    if !instances.is_empty() {
        out.push_str("\n    ]");
    }
    out
}

/// A vector in the scene file: each component rounded to millimetres.
fn v3(v: DVec3) -> String {
    format!("[{}, {}, {}]", number(v.x), number(v.y), number(v.z))
}

/// `x` to three decimals without trailing zeros (and never "-0").
fn number(x: f64) -> String {
    let s = format!("{:.3}", x + 0.0);
    let s = s.trim_end_matches('0').trim_end_matches('.');
    if s == "-0" { "0".into() } else { s.into() }
}
