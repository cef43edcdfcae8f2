//! One shadow map's part of view.json: its size, depth range and projection, the eye an engine
//! places its camera at, and its matrices in the three APIs' forms.

use super::json_number::{num, nums};
use super::matrices::{ViewMatrices, light_matrices};
use super::shadow_eye::ShadowEye;
use glam::Mat4;
use serde_json::{Map, Value, json};
use shadowtruth::raster::{LightView, Projection};
use shadowtruth::scene::Light;

/// The `shadow_map` object of `light`'s map `view` (a directional or spot light's, or one face of
/// a point light's cube).
pub(super) fn map_json(light: &Light, view: &LightView) -> Value {
    let mut map = json!({ "resolution": view.resolution, "near": num(view.near), "far": num(view.far) });
    match view.projection {
        Projection::Orthographic { left, right, bottom, top } => {
            map["projection"] = json!("orthographic");
            map["left"] = num(left);
            map["right"] = num(right);
            map["bottom"] = num(bottom);
            map["top"] = num(top);
        }
        Projection::Perspective { tan_half_fov } => {
            map["projection"] = json!("perspective");
            map["tan_half_fov"] = num(tan_half_fov);
            // The square map's full field of view, as engines' perspective cameras take it.
            map["fov_y_deg"] = num((2.0 * (tan_half_fov as f64).atan()).to_degrees() as f32);
            map["aspect"] = json!(1);
        }
        Projection::Paraboloid => unreachable!("a paraboloid is exported as a hemisphere"),
    }
    map["eye"] = eye_json(light, view);
    map.as_object_mut().expect("an object").extend(matrices_json(&light_matrices(view)));
    map
}

/// The map's camera as engines place one: `lookAt(position, target, up)`.
pub(super) fn eye_json(light: &Light, view: &LightView) -> Value {
    let eye = ShadowEye::of(light, view);
    json!({
        "position": nums(&eye.position.to_array()),
        "target": nums(&eye.target(view).to_array()),
        "up": nums(&eye.up.as_vec3().to_array()),
        "rule": "lookAt(position, target, up) (f = normalize(target − position), s = normalize(f × up), u = s × f, \
                 rows s, u, −f) gives view_from_world to f32 rounding; up is the view's unit y axis",
    })
}

/// `{name}_row_major` and `{name}_column_major` of `m`.
pub(super) fn insert_matrix(object: &mut Map<String, Value>, name: &str, m: &Mat4) {
    object.insert(format!("{name}_row_major"), nums(&m.transpose().to_cols_array()));
    object.insert(format!("{name}_column_major"), nums(&m.to_cols_array()));
}

/// The view matrix, then one object per API with its projections.
pub(super) fn matrices_json(m: &ViewMatrices) -> Map<String, Value> {
    let mut object = Map::new();
    insert_matrix(&mut object, "view_from_world", &m.view_from_world);
    for a in &m.apis {
        let mut api = Map::new();
        insert_matrix(&mut api, "clip_from_view", &a.clip_from_view);
        insert_matrix(&mut api, "clip_from_world", &a.clip_from_world);
        if let Some(t) = &a.texture_from_world {
            insert_matrix(&mut api, "texture_from_world", t);
        }
        object.insert(a.api.key().to_string(), Value::Object(api));
    }
    object
}
