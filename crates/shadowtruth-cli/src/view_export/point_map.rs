//! A point light's part of view.json (docs/point-lights.md): its cube's six faces, each a
//! perspective map with its matrices, or its two paraboloid hemispheres, each a view frame and
//! the mapping in words (a paraboloid is not a matrix).

use super::json_number::num;
use super::map_json::{eye_json, insert_matrix, map_json};
use serde_json::{Map, Value, json};
use shadowtruth::raster::{CUBE_FACE_NAMES, CubeMap, DualParaboloid, LightView, PARABOLOID_NAMES};
use shadowtruth::scene::{Light, LightKind, PointMap};

const FACE_SELECTION: &str = "A point p is shaded through the face of the major axis of d = p − position, in f32: \
|d.x| ≥ |d.y| and |d.x| ≥ |d.z| picks ±x, else |d.y| ≥ |d.z| picks ±y, else ±z, by the sign of that component \
(ties go to x, then y). Faces are OpenGL's (table 8.19): +x, −x, +y, −y, +z, −z. Each face is resolution + \
2·guard_texels texels square: its frustum is widened so that the guard band holds the neighbouring faces' \
texels at this face's own texel size (guard 0: the hardware's clamped seam).";

const PARABOLOID_MAPPING: &str = "q = view_from_world · p (view space, looking down −z), L = |q|, h = L − q.z; the \
map position is (u, v) = (q.x/h·½ + ½, q.y/h·½ + ½), v upwards, and the depth d = (L − near)/(far − near). A point \
is shaded through the first hemisphere (looking down −y) when p.y ≤ position.y in f32, else the second. \
Triangles are clipped to their hemisphere (q.z ≤ 0) and their vertices mapped, edges drawn straight in the map.";

/// The views a point light's map is drawn from at `resolution`: the cube's faces or the
/// paraboloids' hemispheres, in their names' order.
pub(super) fn point_views(light: &Light, resolution: u32) -> Vec<LightView> {
    match light.kind {
        LightKind::Point { map: PointMap::DualParaboloid, .. } => {
            DualParaboloid::new(light, resolution).hemispheres
        }
        _ => CubeMap::new(light, resolution).faces,
    }
}

/// The `shadow_map` object of point `light` at `resolution`, its views from [`point_views`].
pub(super) fn point_map_json(light: &Light, views: &[LightView], resolution: u32) -> Value {
    let LightKind::Point { near, far, map, .. } = light.kind else {
        unreachable!("point maps are exported for point lights only")
    };
    let mut object = json!({ "resolution": resolution, "near": num(near), "far": num(far) });
    match map {
        PointMap::Cube(cube) => {
            object["projection"] = json!("cube");
            object["guard_texels"] = json!(cube.guard_texels);
            object["face_resolution"] = json!(resolution + 2 * cube.guard_texels);
            object["face_selection"] = json!(FACE_SELECTION);
            let faces = views.iter().zip(CUBE_FACE_NAMES).map(|(face, name)| {
                let mut face_json = map_json(light, face);
                face_json["name"] = json!(name);
                face_json
            });
            object["faces"] = Value::Array(faces.collect());
        }
        PointMap::DualParaboloid => {
            object["projection"] = json!("dual_paraboloid");
            object["mapping"] = json!(PARABOLOID_MAPPING);
            let hemispheres =
                views.iter().zip(PARABOLOID_NAMES).map(|(h, name)| hemisphere_json(light, h, name));
            object["hemispheres"] = Value::Array(hemispheres.collect());
        }
    }
    object
}

/// One paraboloid hemisphere: its name, depth range, eye and view matrix.
fn hemisphere_json(light: &Light, view: &LightView, name: &str) -> Value {
    let mut object = Map::new();
    object.insert("name".into(), json!(name));
    object.insert("resolution".into(), json!(view.resolution));
    object.insert("near".into(), num(view.near));
    object.insert("far".into(), num(view.far));
    object.insert("eye".into(), eye_json(light, view));
    insert_matrix(&mut object, "view_from_world", &view.light_from_world);
    Value::Object(object)
}
