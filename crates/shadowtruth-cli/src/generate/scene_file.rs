//! The scene file of a generated scene: its objects, a camera over the ground from one corner,
//! a low sun and a spot light above the centre, placed from the ground's size and the tallest
//! caster so that long shadows fall across the camera's view.

use super::generated::GeneratedScene;
use super::request::{GenerateOptions, SceneKind};
use crate::decimals::rounded_vec3;
use glam::{DVec3, Vec3};
use shadowtruth::scene::{
    Camera, Geometry, Light, LightKind, ObjectPlacement, SceneFile, SceneFileObject, Transform,
};

/// The sun's direction (towards the ground): about 30° above the horizon.
const SUN_DIRECTION: [f64; 3] = [0.6, -0.45, -0.35];
const SUN_ANGULAR_DIAMETER_DEG: f32 = 0.5;
const SPOT_CONE_DEG: f32 = 70.0;
const SPOT_NEAR_M: f32 = 1.0;
const SPOT_RADIUS_M: f32 = 0.5;
const CAMERA_FOV_DEG: f32 = 50.0;

/// The text of `scene.json`; `files[i]` is the mesh file of object `i`.
pub(super) fn scene_json(options: &GenerateOptions, scene: &GeneratedScene, files: &[String]) -> String {
    let name = match options.kind {
        SceneKind::City => "city",
        SceneKind::Forest => "forest",
    };
    let s = scene.ground_size_m;
    let top = scene.top_m;
    let objects = scene.objects.iter().zip(files).map(|(object, file)| SceneFileObject {
        name: object.name.into(),
        geometry: Geometry::Mesh(file.clone()),
        closed: object.closed,
        placement: match object.instances.is_empty() {
            true => ObjectPlacement::Single(Transform::default()),
            false => ObjectPlacement::Instanced(object.instances.iter().map(millimetre_transform).collect()),
        },
    });
    let camera = Camera {
        name: "main".into(),
        position: millimetres(DVec3::new(-0.55 * s, 0.3 * s + top, 0.55 * s)),
        look_at: millimetres(DVec3::new(0.05 * s, 0.0, -0.05 * s)),
        up: Vec3::Y,
        fov_y_deg: CAMERA_FOV_DEG,
        width: options.width_px,
        height: options.height_px,
        path: None,
    };
    let spot = DVec3::new(-0.15 * s, top + 0.35 * s, 0.1 * s);
    let target = DVec3::new(0.1 * s, 0.0, -0.1 * s);
    let reach = (spot - DVec3::new(0.5 * s, 0.0, -0.5 * s)).length() * 1.5;
    let sun = LightKind::Directional {
        direction: millimetres(DVec3::from_array(SUN_DIRECTION)),
        angular_diameter_deg: Some(SUN_ANGULAR_DIAMETER_DEG),
    };
    // The spot's axis is written unnormalised, from the lamp to its target; the reader normalises.
    let lamp = LightKind::Spot {
        position: millimetres(spot),
        direction: millimetres(target - spot),
        cone_deg: SPOT_CONE_DEG,
        near: SPOT_NEAR_M,
        far: reach.ceil() as f32,
        radius: Some(SPOT_RADIUS_M),
    };
    let light = |name: &str, kind| Light { name: name.into(), kind, path: None, cascades: None };
    let file = SceneFile {
        name: name.into(),
        objects: objects.collect(),
        cameras: vec![camera],
        lights: vec![light("sun", sun), light("lamp", lamp)],
    };
    file.to_json().expect("a generated scene has no paths and every instanced object has instances")
}

/// A transform with each component rounded to millimetres.
fn millimetre_transform(t: &Transform) -> Transform {
    Transform {
        scale: millimetres(t.scale.as_dvec3()),
        rotate_deg: millimetres(t.rotate_deg.as_dvec3()),
        translate: millimetres(t.translate.as_dvec3()),
    }
}

/// `v` rounded to millimetres; below 16384 every component prints with at most three decimals.
fn millimetres(v: DVec3) -> Vec3 {
    rounded_vec3(v, 3)
}
