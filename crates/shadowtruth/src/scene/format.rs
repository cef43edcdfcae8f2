//! The `shadowtruth/scene/v1` file format, read field by field so that every problem is reported.
//!
//! The JSON is parsed into a `serde_json::Value` and walked by hand rather than derived with
//! serde: a derive stops at the first error, while users fixing a scene want all of them at once,
//! each with its JSON path.

use super::cascade_settings::read_cascades;
use super::path::{CameraPath, Keyframes};
use super::path_format::{read_camera_path, read_light_path};
use super::point_map::{as_layout, read_cube_settings};
use super::shapes::Shape;
use super::{Camera, CubeSettings, Light, LightKind, LightSize, PointMap, SCENE_FORMAT, Transform};
use crate::json_input::{
    Problems, Reader, as_array_of, as_bool, as_name, as_positive, as_positive_array, as_string, count,
    open_range, show,
};
use glam::{DVec3, Vec3};
use serde_json::Value;

/// Largest camera image side, and largest image (64 megapixels).
pub const MAX_IMAGE_SIDE: u64 = 16384;
pub const MAX_IMAGE_PIXELS: u64 = 1 << 26;
/// Segment, ring and subdivision counts accepted for procedural shapes.
const MAX_SEGMENTS: u64 = 4096;
/// Most triangles that the procedural shapes of one scene make, each alone and all together
/// (4 194 304, e.g. a plane of 1448 subdivisions). A few bytes of JSON ask for them, so they are
/// bounded well below what a machine holds: loading this many takes about 400 MB.
pub(crate) const MAX_SHAPE_TRIANGLES: u64 = 1 << 22;
/// Most triangles of one scene, meshes and shapes together (16 777 216; about 1.5 GB to load).
/// A mesh file may be named by many objects, each adding its triangles again.
pub const MAX_SCENE_TRIANGLES: u64 = 1 << 24;
/// Most triangles of a scene counting every instance's placement (2 147 483 648): triangle ids
/// are u32, and memory grows with unique triangles only, so the bound is the id range.
pub const MAX_INSTANCED_TRIANGLES: u64 = 1 << 31;
/// Most instances of one object.
pub const MAX_INSTANCES: u64 = 1 << 20;

/// Where an object's triangles come from.
#[derive(Clone, Debug, PartialEq)]
pub enum Geometry {
    /// An OBJ path, relative to the scene file's folder.
    Mesh(String),
    Shape(Shape),
    /// A glTF path (`.gltf` or `.glb`), relative to the scene file's folder: its meshes, each
    /// node an object; its cameras and lights are not read (docs/gltf.md).
    Gltf(String),
}

/// One object as written in the file; fields that failed to read are `None`.
#[derive(Clone, Debug)]
pub(crate) struct ObjectDesc {
    /// JSON path of the object, e.g. `objects[2]`.
    pub path: String,
    pub name: String,
    pub geometry: Option<Geometry>,
    pub closed: bool,
    pub transform: Option<Transform>,
    /// `instances`: one transform per placement of the geometry, stored once and traced
    /// through a two-level BVH (src/trace/bvh/instances.rs). Empty when the field is absent;
    /// `transform` is then the one placement.
    pub instances: Vec<Transform>,
}

/// A scene file's content, before meshes are loaded.
#[derive(Clone, Debug, Default)]
pub(crate) struct SceneDesc {
    pub name: String,
    pub objects: Vec<ObjectDesc>,
    pub cameras: Vec<Camera>,
    pub lights: Vec<Light>,
}

/// Reads the top level of a scene file.
pub(crate) fn read_scene(root: &Value, problems: &mut Problems) -> SceneDesc {
    let mut desc = SceneDesc::default();
    let Some(mut top) = Reader::new(root, String::new(), problems) else {
        return desc;
    };
    // Another program's JSON (a folder of scenes may hold some): one problem, not one for
    // each field it lacks and each it has.
    if ["format", "objects", "cameras", "lights"].iter().all(|k| top.get(k).is_none()) {
        top.problem(
            "",
            format!(
                "not a shadowtruth scene: it has no \"format\": \"{SCENE_FORMAT}\", objects, cameras \
                 or lights. Name the scene files, or keep other JSON files out of a folder of scenes"
            ),
        );
        return desc;
    }
    if let Some(format) = top.required("format", as_string)
        && format != SCENE_FORMAT
    {
        let message = format!("unsupported format \"{format}\"; expected \"{SCENE_FORMAT}\"");
        top.problem("format", message);
    }
    desc.name = top.required("name", as_name).unwrap_or_default();
    if let Some(items) = top.array("objects") {
        if items.is_empty() {
            top.problem("objects", "must contain at least one object");
        }
        desc.objects = top.each("objects", items, read_object);
    }
    if let Some(items) = top.array("cameras") {
        desc.cameras = top.each("cameras", items, read_camera).into_iter().flatten().collect();
    }
    if let Some(items) = top.array("lights") {
        desc.lights = top.each("lights", items, read_light).into_iter().flatten().collect();
    }
    top.finish();
    desc
}

fn read_object(r: &mut Reader) -> ObjectDesc {
    let name = r.required("name", as_name).unwrap_or_default();
    let mesh = r.optional("mesh", as_string).map(Geometry::Mesh);
    let gltf = r.optional("gltf", as_string).map(Geometry::Gltf);
    let shape = r.optional_object("shape", read_shape);
    let given: Vec<&str> = ["mesh", "gltf", "shape"].into_iter().filter(|k| r.has(k)).collect();
    let geometry = match given.as_slice() {
        [] => {
            r.problem("", "needs a `mesh` (OBJ path), a `gltf` (glTF path) or a `shape`");
            None
        }
        [_] => mesh.or(gltf).or(shape.flatten().map(Geometry::Shape)),
        [a, b] => {
            r.problem("", format!("has both `{a}` and `{b}`; give exactly one"));
            None
        }
        _ => {
            r.problem("", "has `mesh`, `gltf` and `shape`; give exactly one");
            None
        }
    };
    let closed = r.optional("closed", as_bool).unwrap_or(false);
    let transform = match r.optional_object("transform", read_transform) {
        None => Some(Transform::default()),
        Some(t) => t,
    };
    let (transform, instances) = read_instances(r, transform);
    ObjectDesc { path: r.path.clone(), name, geometry, closed, transform, instances }
}

/// The `instances` list, which replaces `transform`: (`None` when either is invalid, the
/// instance transforms).
fn read_instances(r: &mut Reader, transform: Option<Transform>) -> (Option<Transform>, Vec<Transform>) {
    if !r.has("instances") {
        return (transform, Vec::new());
    }
    if r.has("transform") {
        r.problem(
            "instances",
            "has both `transform` and `instances`; give one transform per instance instead",
        );
    }
    let Some(items) = r.array("instances") else {
        return (None, Vec::new());
    };
    if items.is_empty() {
        r.problem("instances", "must contain at least one transform");
        return (None, Vec::new());
    }
    if items.len() as u64 > MAX_INSTANCES {
        r.problem(
            "instances",
            format!("{} instances; an object may have at most {MAX_INSTANCES}", items.len()),
        );
        return (None, Vec::new());
    }
    let read: Vec<Option<Transform>> = r.each("instances", items, read_transform);
    let valid = read.len() == items.len() && read.iter().all(Option::is_some) && !r.has("transform");
    match valid {
        true => (Some(Transform::default()), read.into_iter().flatten().collect()),
        false => (None, Vec::new()),
    }
}

fn read_transform(r: &mut Reader) -> Option<Transform> {
    let nonzero = |v: &Value| {
        let s = as_vec3(v)?;
        match s.to_array().iter().position(|&c| c == 0.0) {
            Some(i) => Err(format!("component {i} is zero; a scale must not flatten the object")),
            None => Ok(s),
        }
    };
    let scale = r.optional_or("scale", nonzero, Vec3::ONE);
    let rotate_deg = r.optional_or("rotate_deg", as_vec3, Vec3::ZERO);
    let translate = r.optional_or("translate", as_vec3, Vec3::ZERO);
    Some(Transform { scale: scale?, rotate_deg: rotate_deg?, translate: translate? })
}

fn read_shape(r: &mut Reader) -> Option<Shape> {
    let Some(kind) = r.required("type", as_string) else {
        r.ignore_unknown = true;
        return None;
    };
    let segments = |r: &mut Reader| r.optional_or("segments", count(3, MAX_SEGMENTS), 32);
    let shape = match kind.as_str() {
        "plane" => {
            let size = r.required("size", as_positive_array::<2>);
            let subdivisions = r.optional_or("subdivisions", count(1, MAX_SEGMENTS), 1);
            Shape::Plane { size: size?, subdivisions: subdivisions? }
        }
        "box" => Shape::Box { size: r.required("size", as_positive_array::<3>)? },
        "sphere" => {
            let radius = r.required("radius", as_positive);
            let segments = segments(r);
            let rings = r.optional_or("rings", count(2, MAX_SEGMENTS), 16);
            Shape::Sphere { radius: radius?, segments: segments?, rings: rings? }
        }
        "cylinder" | "cone" => {
            let radius = r.required("radius", as_positive);
            let height = r.required("height", as_positive);
            let segments = segments(r);
            let (radius, height, segments) = (radius?, height?, segments?);
            if kind == "cone" {
                Shape::Cone { radius, height, segments }
            } else {
                Shape::Cylinder { radius, height, segments }
            }
        }
        other => {
            let message =
                format!("unknown shape type \"{other}\"; expected plane, box, sphere, cylinder or cone");
            r.problem("type", message);
            r.ignore_unknown = true;
            return None;
        }
    };
    if shape.triangle_count() > MAX_SHAPE_TRIANGLES {
        let message = format!(
            "would have {} triangles; procedural shapes may have at most {MAX_SHAPE_TRIANGLES}",
            shape.triangle_count()
        );
        r.problem("", message);
        return None;
    }
    Some(shape)
}

fn read_camera(r: &mut Reader) -> Option<Camera> {
    let name = r.required("name", as_name);
    let path = r.optional_object("path", read_camera_path);
    // A camera on a path starts at its first key.
    let first =
        |track: fn(&CameraPath) -> &Keyframes| path.clone().flatten().map(|p| track(&p).values[0].as_vec3());
    let (position, look_at) = if path.is_some() {
        refuse_beside_path(r, &["position", "look_at"]);
        (first(|p| &p.position), first(|p| &p.look_at))
    } else {
        (r.required("position", as_vec3), r.required("look_at", as_vec3))
    };
    let up = r.optional_or("up", as_vec3, Vec3::Y);
    let fov_y_deg = r.required("fov_y_deg", open_range(0.0, 180.0));
    let width = r.required("width", count(1, MAX_IMAGE_SIDE));
    let height = r.required("height", count(1, MAX_IMAGE_SIDE));
    let mut valid = true;
    if let (Some(w), Some(h)) = (width, height)
        && w as u64 * h as u64 > MAX_IMAGE_PIXELS
    {
        r.problem("", format!("image {w}×{h} has more than 64 megapixels"));
        valid = false;
    }
    match (&path, position, look_at, up) {
        // Every key of a path must give the camera a frame.
        (Some(Some(path)), _, _, Some(up)) => {
            for (i, (p, l)) in path.position.values.iter().zip(&path.look_at.values).enumerate() {
                valid &= camera_frame_problem(r, Some(i), *p, *l, up.as_dvec3());
            }
        }
        (None, Some(position), Some(look_at), Some(up)) => {
            valid &= camera_frame_problem(r, None, position.as_dvec3(), look_at.as_dvec3(), up.as_dvec3());
        }
        _ => {}
    }
    let camera = Camera {
        name: name?,
        position: position?,
        look_at: look_at?,
        up: up?,
        fov_y_deg: fov_y_deg? as f32,
        width: width?,
        height: height?,
        path: path.flatten(),
    };
    valid.then_some(camera)
}

fn read_light(r: &mut Reader) -> Option<Light> {
    let name = r.required("name", as_name);
    let light_type = r.required("type", as_string);
    if light_type.as_deref() == Some("point") {
        return read_point_light(r, name);
    }
    let spot = light_type.as_deref() == Some("spot");
    let path = r.optional_object("path", |p| read_light_path(p, spot));
    let direction = match path.clone() {
        None => r.required("direction", as_direction),
        Some(path) => {
            refuse_beside_path(r, &["direction", "position"]);
            path.map(|p| p.direction.values[0].normalize().as_vec3())
        }
    };
    let mut light = match light_type.as_deref() {
        Some("directional") => {
            let angular = r.optional(LightSize::ANGULAR_DIAMETER_FIELD, open_range(0.0, 90.0));
            let kind = LightKind::Directional {
                direction: direction?,
                angular_diameter_deg: angular.map(|a| a as f32),
            };
            Light { name: name?, kind, path: None, cascades: None }
        }
        Some("spot") => {
            let position = match &path {
                None => r.required("position", as_vec3),
                Some(p) => p.as_ref().and_then(|p| p.position.as_ref()).map(|k| k.values[0].as_vec3()),
            };
            let cone_deg = r.required("cone_deg", open_range(0.0, 180.0));
            let (near, far) = read_near_far(r)?;
            let radius = r.optional(LightSize::RADIUS_FIELD, as_positive);
            let kind = LightKind::Spot {
                position: position?,
                direction: direction?,
                cone_deg: cone_deg? as f32,
                near,
                far,
                radius: radius.map(|x| x as f32),
            };
            Light { name: name?, kind, path: None, cascades: None }
        }
        Some(other) => {
            let message = format!("unknown light type \"{other}\"; expected directional, spot or point");
            r.problem("type", message);
            r.ignore_unknown = true;
            return None;
        }
        None => {
            r.ignore_unknown = true;
            return None;
        }
    };
    let cascades = r.optional_object("cascades", read_cascades);
    if cascades.is_some() && spot {
        r.problem("cascades", "cascaded shadow maps are for directional lights only");
        return None;
    }
    if r.get("cube_map").is_some() {
        r.problem("cube_map", "cube shadow maps are for point lights only");
        return None;
    }
    // Present and invalid (reported): the light is not made.
    light.path = match path {
        Some(read) => Some(read?),
        None => None,
    };
    light.cascades = match cascades {
        Some(read) => Some(read?),
        None => None,
    };
    Some(light)
}

/// A point light: `position`, `near`, `far`, an optional sphere `radius`, its `shadow_map`
/// ("cube" or "dual_paraboloid") and a cube's `cube_map`.
fn read_point_light(r: &mut Reader, name: Option<String>) -> Option<Light> {
    let mut refused = false;
    for (field, why) in [
        ("path", "point lights do not move along paths"),
        ("direction", "a point light shines every way: it has no direction"),
        ("cascades", "cascaded shadow maps are for directional lights only"),
    ] {
        // Asked for, so that the problem is this one rather than an unknown field.
        if r.get(field).is_some() {
            r.problem(field, why);
            refused = true;
        }
    }
    let position = r.required("position", as_vec3);
    let near_far = read_near_far(r);
    let radius = r.optional(LightSize::RADIUS_FIELD, as_positive);
    let layout = r.optional_or("shadow_map", as_layout, "cube");
    let cube = r.optional_object("cube_map", read_cube_settings);
    let map = match (layout?, cube) {
        ("cube", Some(read)) => PointMap::Cube(read?),
        ("cube", None) => PointMap::Cube(CubeSettings::default()),
        (_, Some(_)) => {
            r.problem("cube_map", "sets a cube map, but `shadow_map` is dual_paraboloid");
            return None;
        }
        (_, None) => PointMap::DualParaboloid,
    };
    let (near, far) = near_far?;
    if refused {
        return None;
    }
    let kind = LightKind::Point { position: position?, near, far, radius: radius.map(|x| x as f32), map };
    Some(Light { name: name?, kind, path: None, cascades: None })
}

/// A spot or point light's `near` and `far`, with far beyond near.
fn read_near_far(r: &mut Reader) -> Option<(f32, f32)> {
    let near = r.required("near", as_positive);
    let far = r.required("far", as_positive);
    let (near, far) = (near?, far?);
    // Compared as the f32 the light keeps, so that rounding cannot make them equal.
    if far as f32 <= near as f32 {
        r.problem("far", format!("must be greater than `near` ({}) as f32 numbers", show(near)));
        return None;
    }
    Some((near as f32, far as f32))
}

/// Whether `position`, `look_at` and `up` give a camera frame; if not, the problem is reported
/// at the field at fault (`look_at` of path key `key`, when the values are a key's).
fn camera_frame_problem(
    r: &mut Reader,
    key: Option<usize>,
    position: DVec3,
    look_at: DVec3,
    up: DVec3,
) -> bool {
    let forward = look_at - position;
    let of_key = key.map_or_else(String::new, |i| format!(" (path key {i})"));
    if forward == DVec3::ZERO {
        let field = key.map_or_else(|| "look_at".to_string(), |i| format!("path.keys[{i}].look_at"));
        r.problem(&field, "equals `position`: the camera has no viewing direction");
        return false;
    }
    if !is_unit_safe(up) || forward.normalize().cross(up.normalize()).length() < 1e-6 {
        r.problem("up", format!("is zero or parallel to the viewing direction (look_at − position){of_key}"));
        return false;
    }
    true
}

/// Fields a path's first key gives, reported where they are given too (and then not read).
fn refuse_beside_path(r: &mut Reader, fields: &[&'static str]) {
    for &key in fields {
        if r.has(key) {
            r.get(key);
            r.problem(key, "is given by the first key of `path`: leave it out");
        }
    }
}

fn as_vec3(v: &Value) -> Result<Vec3, String> {
    Ok(DVec3::from(as_array_of::<3>(v)?).as_vec3())
}

fn is_unit_safe(d: DVec3) -> bool {
    let n = d.length();
    n.is_finite() && n > 0.0 && d.normalize().is_finite()
}

/// A non-zero direction, normalized (in f64, rounded once).
fn as_direction(v: &Value) -> Result<Vec3, String> {
    let d = DVec3::from(as_array_of::<3>(v)?);
    if !is_unit_safe(d) {
        return Err("must have a non-zero length".into());
    }
    Ok(d.normalize().as_vec3())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn scene_format_non_object_root_is_one_problem() {
        let mut problems = Problems::new(std::path::Path::new("s.json"));
        let desc = read_scene(&Value::Array(vec![]), &mut problems);
        assert!(desc.objects.is_empty());
        assert_eq!(problems.list.len(), 1);
        assert_eq!(problems.list[0].message, "expected an object, found an array of 0 items");
    }
}
