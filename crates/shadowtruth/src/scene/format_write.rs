//! Writing the `shadowtruth/scene/v1` format from the reader's own types (`Camera`, `Light`,
//! `Transform`, `Shape`), serialised by serde through small structs shaped like the file.
//!
//! Every field written is one that `format.rs` reads, and the reader reports any field it does not
//! know, so a name that drifted fails the round-trip tests at once. Values are written as they are
//! held: `f32` fields in the shortest text that reads back to the same `f32`, so a written scene
//! loads with the very values it was written from.

use super::cascade_settings::{CascadeFit, CascadeSettings, SplitScheme};
use super::format::Geometry;
use super::path::Keyframes;
use super::{Camera, Light, LightKind, SCENE_FORMAT, Transform};
use glam::DVec3;
use serde::Serialize;

/// The content of a scene file, written by [`SceneFile::to_json`] and read back by
/// [`load_scene`](super::load_scene) to the same objects, cameras and lights.
#[derive(Clone, Debug, PartialEq)]
pub struct SceneFile {
    pub name: String,
    pub objects: Vec<SceneFileObject>,
    pub cameras: Vec<Camera>,
    pub lights: Vec<Light>,
}

/// One object of a scene file: where its triangles come from, whether it is a closed solid, and
/// where it is placed.
#[derive(Clone, Debug, PartialEq)]
pub struct SceneFileObject {
    pub name: String,
    pub geometry: Geometry,
    /// A solid whose back faces may be culled from the light's view.
    pub closed: bool,
    pub placement: ObjectPlacement,
}

/// Where an object stands: one transform, or the transforms of its instances (the geometry
/// stored once, src/scene/instance.rs).
#[derive(Clone, Debug, PartialEq)]
pub enum ObjectPlacement {
    /// Written as `transform`, left out when it is the identity.
    Single(Transform),
    /// Written as `instances`: at least one transform.
    Instanced(Vec<Transform>),
}

/// What the file cannot say: `path` is the JSON path of the value, as the reader's problems name
/// them (e.g. `cameras[0].path`).
#[derive(Clone, Debug, PartialEq, Eq, thiserror::Error)]
#[error("{path}: {message}")]
pub struct UnwritableScene {
    pub path: String,
    pub message: String,
}

impl SceneFile {
    /// The scene file's JSON text, pretty-printed, ending with a newline.
    ///
    /// Non-finite numbers are written as `null`, which the reader refuses; a camera or light
    /// path's tracks must share their key times and interpolation, as every path read from a
    /// file does.
    pub fn to_json(&self) -> Result<String, UnwritableScene> {
        let root = FileRoot {
            format: SCENE_FORMAT,
            name: &self.name,
            objects: self
                .objects
                .iter()
                .enumerate()
                .map(|(i, o)| file_object(i, o))
                .collect::<Result<_, _>>()?,
            cameras: self
                .cameras
                .iter()
                .enumerate()
                .map(|(i, c)| file_camera(i, c))
                .collect::<Result<_, _>>()?,
            lights: self
                .lights
                .iter()
                .enumerate()
                .map(|(i, l)| file_light(i, l))
                .collect::<Result<_, _>>()?,
        };
        let mut text = serde_json::to_string_pretty(&root).expect("scene files have string keys only");
        text.push('\n');
        Ok(text)
    }
}

#[derive(Serialize)]
struct FileRoot<'a> {
    format: &'static str,
    name: &'a str,
    objects: Vec<FileObject<'a>>,
    cameras: Vec<FileCamera<'a>>,
    lights: Vec<FileLight<'a>>,
}

#[derive(Serialize)]
struct FileObject<'a> {
    name: &'a str,
    #[serde(skip_serializing_if = "Option::is_none")]
    mesh: Option<&'a str>,
    #[serde(skip_serializing_if = "Option::is_none")]
    gltf: Option<&'a str>,
    #[serde(skip_serializing_if = "Option::is_none")]
    shape: Option<&'a super::Shape>,
    closed: bool,
    #[serde(skip_serializing_if = "Option::is_none")]
    transform: Option<FileTransform>,
    #[serde(skip_serializing_if = "Option::is_none")]
    instances: Option<Vec<FileTransform>>,
}

#[derive(Serialize)]
struct FileTransform {
    scale: [f32; 3],
    rotate_deg: [f32; 3],
    translate: [f32; 3],
}

/// A camera; `position` and `look_at` are left out when a path gives them.
#[derive(Serialize)]
struct FileCamera<'a> {
    name: &'a str,
    #[serde(skip_serializing_if = "Option::is_none")]
    position: Option<[f32; 3]>,
    #[serde(skip_serializing_if = "Option::is_none")]
    look_at: Option<[f32; 3]>,
    up: [f32; 3],
    fov_y_deg: f32,
    width: u32,
    height: u32,
    #[serde(skip_serializing_if = "Option::is_none")]
    path: Option<FilePath>,
}

/// A light of either kind: the fields of the other kind are left out, and so are `direction` and
/// `position` when a path gives them.
#[derive(Serialize)]
struct FileLight<'a> {
    name: &'a str,
    #[serde(rename = "type")]
    light_type: &'static str,
    #[serde(skip_serializing_if = "Option::is_none")]
    position: Option<[f32; 3]>,
    #[serde(skip_serializing_if = "Option::is_none")]
    direction: Option<[f32; 3]>,
    #[serde(skip_serializing_if = "Option::is_none")]
    angular_diameter_deg: Option<f32>,
    #[serde(skip_serializing_if = "Option::is_none")]
    cone_deg: Option<f32>,
    #[serde(skip_serializing_if = "Option::is_none")]
    near: Option<f32>,
    #[serde(skip_serializing_if = "Option::is_none")]
    far: Option<f32>,
    #[serde(skip_serializing_if = "Option::is_none")]
    radius: Option<f32>,
    #[serde(skip_serializing_if = "Option::is_none")]
    path: Option<FilePath>,
    #[serde(skip_serializing_if = "Option::is_none")]
    cascades: Option<FileCascades>,
    #[serde(skip_serializing_if = "Option::is_none")]
    shadow_map: Option<&'static str>,
    #[serde(skip_serializing_if = "Option::is_none")]
    cube_map: Option<FileCube>,
}

#[derive(Serialize)]
struct FileCube {
    guard_texels: u32,
}

#[derive(Serialize)]
struct FilePath {
    interpolation: &'static str,
    keys: Vec<FileKey>,
}

/// One key of a path: its time and the vectors its owner moves.
#[derive(Serialize)]
struct FileKey {
    time: f64,
    #[serde(skip_serializing_if = "Option::is_none")]
    position: Option<[f32; 3]>,
    #[serde(skip_serializing_if = "Option::is_none")]
    look_at: Option<[f32; 3]>,
    #[serde(skip_serializing_if = "Option::is_none")]
    direction: Option<[f32; 3]>,
}

#[derive(Serialize)]
struct FileCascades {
    count: u32,
    split: &'static str,
    #[serde(skip_serializing_if = "Option::is_none")]
    lambda: Option<f64>,
    fit: &'static str,
    stabilize: bool,
    blend_band: f64,
    #[serde(skip_serializing_if = "Option::is_none")]
    near_distance: Option<f64>,
    #[serde(skip_serializing_if = "Option::is_none")]
    max_distance: Option<f64>,
}

fn file_object(index: usize, object: &SceneFileObject) -> Result<FileObject<'_>, UnwritableScene> {
    let (mesh, gltf, shape) = match &object.geometry {
        Geometry::Mesh(path) => (Some(path.as_str()), None, None),
        Geometry::Gltf(path) => (None, Some(path.as_str()), None),
        Geometry::Shape(shape) => (None, None, Some(shape)),
    };
    let (transform, instances) = match &object.placement {
        ObjectPlacement::Single(t) if *t == Transform::default() => (None, None),
        ObjectPlacement::Single(t) => (Some(file_transform(t)), None),
        ObjectPlacement::Instanced(list) if list.is_empty() => {
            let message = "an instanced object needs at least one transform".into();
            return Err(UnwritableScene { path: format!("objects[{index}].instances"), message });
        }
        ObjectPlacement::Instanced(list) => (None, Some(list.iter().map(file_transform).collect())),
    };
    Ok(FileObject { name: &object.name, mesh, gltf, shape, closed: object.closed, transform, instances })
}

fn file_transform(t: &Transform) -> FileTransform {
    FileTransform {
        scale: t.scale.to_array(),
        rotate_deg: t.rotate_deg.to_array(),
        translate: t.translate.to_array(),
    }
}

fn file_camera(index: usize, camera: &Camera) -> Result<FileCamera<'_>, UnwritableScene> {
    let at = || format!("cameras[{index}].path");
    let path = match &camera.path {
        None => None,
        Some(p) => Some(file_path(&[("position", &p.position), ("look_at", &p.look_at)], at)?),
    };
    let given = camera.path.is_none();
    Ok(FileCamera {
        name: &camera.name,
        position: given.then(|| camera.position.to_array()),
        look_at: given.then(|| camera.look_at.to_array()),
        up: camera.up.to_array(),
        fov_y_deg: camera.fov_y_deg,
        width: camera.width,
        height: camera.height,
        path,
    })
}

fn file_light(index: usize, light: &Light) -> Result<FileLight<'_>, UnwritableScene> {
    let at = || format!("lights[{index}].path");
    let path = match &light.path {
        None => None,
        Some(p) => {
            let mut tracks = vec![("direction", &p.direction)];
            tracks.extend(p.position.as_ref().map(|k| ("position", k)));
            Some(file_path(&tracks, at)?)
        }
    };
    let given = light.path.is_none();
    let mut file = FileLight {
        name: &light.name,
        light_type: "",
        position: None,
        direction: None,
        angular_diameter_deg: None,
        cone_deg: None,
        near: None,
        far: None,
        radius: None,
        path,
        cascades: light.cascades.as_ref().map(file_cascades),
        shadow_map: None,
        cube_map: None,
    };
    match light.kind {
        LightKind::Directional { direction, angular_diameter_deg } => {
            file.light_type = "directional";
            file.direction = given.then(|| direction.to_array());
            file.angular_diameter_deg = angular_diameter_deg;
        }
        LightKind::Spot { position, direction, cone_deg, near, far, radius } => {
            file.light_type = "spot";
            file.position = given.then(|| position.to_array());
            file.direction = given.then(|| direction.to_array());
            (file.cone_deg, file.near, file.far, file.radius) =
                (Some(cone_deg), Some(near), Some(far), radius);
        }
        LightKind::Point { position, near, far, radius, map } => {
            file.light_type = "point";
            file.position = Some(position.to_array());
            (file.near, file.far, file.radius) = (Some(near), Some(far), radius);
            file.shadow_map = Some(map.name());
            if let crate::scene::PointMap::Cube(cube) = map {
                file.cube_map = Some(FileCube { guard_texels: cube.guard_texels });
            }
        }
    }
    Ok(file)
}

/// The keys of a path from its named tracks, which must share times and interpolation.
fn file_path(
    tracks: &[(&'static str, &Keyframes)],
    at: impl Fn() -> String,
) -> Result<FilePath, UnwritableScene> {
    let first = tracks[0].1;
    for (name, track) in tracks {
        let message = if track.interpolation != first.interpolation || track.times != first.times {
            format!("the `{name}` track's times or interpolation differ from the `{}` track's", tracks[0].0)
        } else if track.values.len() != track.times.len() {
            format!("the `{name}` track has {} values for {} times", track.values.len(), track.times.len())
        } else {
            continue;
        };
        return Err(UnwritableScene { path: at(), message });
    }
    // Path values are read through f32, as every scene vector is; writing them so keeps the text
    // short and loses nothing the reader would keep.
    let vector = |v: DVec3| v.as_vec3().to_array();
    let value = |name: &str, i: usize| tracks.iter().find(|t| t.0 == name).map(|t| vector(t.1.values[i]));
    let keys = (0..first.times.len())
        .map(|i| FileKey {
            time: first.times[i],
            position: value("position", i),
            look_at: value("look_at", i),
            direction: value("direction", i),
        })
        .collect();
    Ok(FilePath { interpolation: first.interpolation.name(), keys })
}

fn file_cascades(c: &CascadeSettings) -> FileCascades {
    let (split, lambda) = match c.split {
        SplitScheme::Uniform => ("uniform", None),
        SplitScheme::Logarithmic => ("logarithmic", None),
        SplitScheme::Practical { lambda } => ("practical", Some(lambda)),
    };
    let fit = match c.fit {
        CascadeFit::Sphere => "sphere",
        CascadeFit::Frustum => "frustum",
    };
    FileCascades {
        count: c.count,
        split,
        lambda,
        fit,
        stabilize: c.stabilize,
        blend_band: c.blend_band,
        near_distance: c.near_distance,
        max_distance: c.max_distance,
    }
}

#[cfg(test)]
mod tests {
    use super::super::Shape;
    use super::super::format::{SceneDesc, read_scene};
    use super::super::path::{CameraPath, Interpolation, LightPath};
    use super::*;
    use crate::json_input::Problems;
    use glam::Vec3;

    /// Writes `file`, reads the text back with the scene reader and checks it has no problems.
    fn written_and_read(file: &SceneFile) -> (String, SceneDesc) {
        let text = file.to_json().unwrap();
        let mut problems = Problems::new(std::path::Path::new("scene.json"));
        let desc = read_scene(&serde_json::from_str(&text).unwrap(), &mut problems);
        assert!(problems.list.is_empty(), "{:?}\n{text}", problems.list);
        (text, desc)
    }

    /// What the reader makes of each object: (name, geometry, closed, placement).
    fn read_objects(desc: &SceneDesc) -> Vec<SceneFileObject> {
        let object = |o: &super::super::format::ObjectDesc| SceneFileObject {
            name: o.name.clone(),
            geometry: o.geometry.clone().unwrap(),
            closed: o.closed,
            placement: match o.instances.is_empty() {
                true => ObjectPlacement::Single(o.transform.clone().unwrap()),
                false => ObjectPlacement::Instanced(o.instances.clone()),
            },
        };
        desc.objects.iter().map(object).collect()
    }

    fn assert_round_trip(file: &SceneFile) -> String {
        let (text, desc) = written_and_read(file);
        let read = SceneFile {
            name: desc.name.clone(),
            objects: read_objects(&desc),
            cameras: desc.cameras.clone(),
            lights: desc.lights.clone(),
        };
        assert_eq!(&read, file, "{text}");
        text
    }

    fn transform(scale: [f32; 3], rotate_deg: [f32; 3], translate: [f32; 3]) -> Transform {
        Transform { scale: scale.into(), rotate_deg: rotate_deg.into(), translate: translate.into() }
    }

    fn object(name: &str, geometry: Geometry, closed: bool, placement: ObjectPlacement) -> SceneFileObject {
        SceneFileObject { name: name.into(), geometry, closed, placement }
    }

    fn camera(path: Option<CameraPath>) -> Camera {
        Camera {
            name: "main".into(),
            position: Vec3::new(-66.0, 147.23, 66.0),
            look_at: Vec3::new(6.0, 0.0, -6.125),
            up: Vec3::Y,
            fov_y_deg: 47.5,
            width: 640,
            height: 360,
            path,
        }
    }

    fn track(interpolation: Interpolation, values: &[[f64; 3]]) -> Keyframes {
        Keyframes {
            interpolation,
            times: (0..values.len()).map(|i| i as f64 * 0.75).collect(),
            // Through f32, as the reader holds them.
            values: values.iter().map(|v| DVec3::from(*v).as_vec3().as_dvec3()).collect(),
        }
    }

    /// Unit directions whose f32 components the reader's normalisation keeps as they are.
    const DOWN: Vec3 = Vec3::new(0.0, -1.0, 0.0);
    const SLANT: Vec3 = Vec3::new(0.6, -0.8, 0.0);

    fn sun(angular_diameter_deg: Option<f32>) -> Light {
        let kind = LightKind::Directional { direction: SLANT, angular_diameter_deg };
        Light { name: "sun".into(), kind, path: None, cascades: None }
    }

    fn spot(radius: Option<f32>) -> Light {
        let kind = LightKind::Spot {
            position: Vec3::new(-18.0, 153.23, 12.0),
            direction: DOWN,
            cone_deg: 70.0,
            near: 0.25,
            far: 280.0,
            radius,
        };
        Light { name: "lamp".into(), kind, path: None, cascades: None }
    }

    /// A point light with a cube of `guard_texels`, or dual paraboloids (None).
    fn point(radius: Option<f32>, guard_texels: Option<u32>) -> Light {
        let map = match guard_texels {
            Some(guard_texels) => crate::scene::PointMap::Cube(crate::scene::CubeSettings { guard_texels }),
            None => crate::scene::PointMap::DualParaboloid,
        };
        let kind =
            LightKind::Point { position: Vec3::new(2.5, 3.75, -1.0), near: 0.05, far: 40.0, radius, map };
        Light { name: "lamp_point".into(), kind, path: None, cascades: None }
    }

    #[test]
    fn scene_file_meshes_shapes_and_lights_of_every_kind_read_back_as_written() {
        let shapes = [
            Shape::Plane { size: [40.0, 12.5], subdivisions: 3 },
            Shape::Box { size: [1.0, 2.0, 0.125] },
            Shape::Sphere { radius: 0.75, segments: 12, rings: 5 },
            Shape::Cylinder { radius: 0.5, height: 3.0, segments: 7 },
            Shape::Cone { radius: 2.0, height: 1.5, segments: 9 },
        ];
        let mut objects = vec![
            object(
                "ground",
                Geometry::Mesh("meshes/ground.obj".into()),
                false,
                ObjectPlacement::Single(Transform::default()),
            ),
            object(
                "statue",
                Geometry::Gltf("statue.glb".into()),
                true,
                ObjectPlacement::Single(transform(
                    [2.0, -1.0, 0.5],
                    [10.0, 264.096, -5.0],
                    [-68.981, 7.288, 0.0],
                )),
            ),
        ];
        for (i, shape) in shapes.into_iter().enumerate() {
            let t = transform([1.0; 3], [0.0; 3], [i as f32, 0.0, -0.001]);
            objects.push(object(
                &format!("shape{i}"),
                Geometry::Shape(shape),
                i % 2 == 0,
                ObjectPlacement::Single(t),
            ));
        }
        let file = SceneFile {
            name: "mixed".into(),
            objects,
            cameras: vec![camera(None)],
            lights: vec![
                sun(Some(0.5)),
                spot(Some(0.5)),
                Light { name: "bare".into(), ..sun(None) },
                Light { name: "small".into(), ..spot(None) },
                point(Some(0.125), Some(0)),
                Light { name: "bulb".into(), ..point(None, Some(12)) },
                Light { name: "paraboloids".into(), ..point(None, None) },
            ],
        };
        let text = assert_round_trip(&file);
        // An identity transform is left out, as a hand-written file would.
        let value: serde_json::Value = serde_json::from_str(&text).unwrap();
        assert!(value["objects"][0].get("transform").is_none(), "{text}");
        assert_eq!(value["objects"][1]["transform"]["rotate_deg"][1].as_f64(), Some(264.096));
        assert_eq!(value["format"], SCENE_FORMAT);
    }

    #[test]
    fn scene_file_instances_read_back_as_written() {
        let instances = vec![
            transform([1.073; 3], [0.0, 264.096, 0.0], [-68.981, 7.288, -68.659]),
            transform([0.8; 3], [0.0, 288.145, 0.0], [-33.671, 6.623, -71.292]),
        ];
        let file = SceneFile {
            name: "forest".into(),
            objects: vec![object(
                "tree",
                Geometry::Mesh("tree.obj".into()),
                true,
                ObjectPlacement::Instanced(instances),
            )],
            cameras: vec![],
            lights: vec![sun(Some(0.5))],
        };
        let text = assert_round_trip(&file);
        let value: serde_json::Value = serde_json::from_str(&text).unwrap();
        // f32 values are written in their shortest form, not widened to f64's digits.
        assert_eq!(value["objects"][0]["instances"][0]["scale"][0].to_string(), "1.073");
    }

    #[test]
    fn scene_file_paths_and_cascades_read_back_as_written() {
        let position = track(Interpolation::Linear, &[[0.0, 2.0, 5.0], [1.5, 2.0, 4.0], [3.0, 2.5, 3.0]]);
        let look_at = track(Interpolation::Linear, &[[0.0, 0.0, 0.0], [0.1, 0.0, 0.0], [0.2, 0.0, -0.1]]);
        let mut moving = camera(Some(CameraPath { position: position.clone(), look_at }));
        (moving.position, moving.look_at) = (Vec3::new(0.0, 2.0, 5.0), Vec3::ZERO);
        let cascades = |split| CascadeSettings {
            count: 3,
            split,
            fit: CascadeFit::Frustum,
            stabilize: false,
            blend_band: 0.125,
            near_distance: Some(0.5),
            max_distance: Some(80.0),
        };
        let mut swept = sun(None);
        swept.path = Some(LightPath {
            direction: track(Interpolation::CatmullRom, &[[0.6, -0.8, 0.0], [0.0, -1.0, 0.0]]),
            position: None,
        });
        swept.cascades = Some(cascades(SplitScheme::Practical { lambda: 0.75 }));
        let mut moving_spot = spot(Some(0.25));
        moving_spot.path = Some(LightPath {
            direction: track(Interpolation::Linear, &[[0.0, -1.0, 0.0], [0.6, -0.8, 0.0], [0.0, -1.0, 0.0]]),
            position: Some(position),
        });
        moving_spot.kind = match moving_spot.kind {
            LightKind::Spot { cone_deg, near, far, radius, .. } => LightKind::Spot {
                position: Vec3::new(0.0, 2.0, 5.0),
                direction: DOWN,
                cone_deg,
                near,
                far,
                radius,
            },
            directional => directional,
        };
        let uniform = Light {
            name: "uniform".into(),
            cascades: Some(cascades(SplitScheme::Uniform)),
            ..sun(Some(1.0))
        };
        let log = Light {
            name: "log".into(),
            cascades: Some(cascades(SplitScheme::Logarithmic)),
            ..sun(Some(1.0))
        };
        let file = SceneFile {
            name: "moving".into(),
            objects: vec![object(
                "floor",
                Geometry::Shape(Shape::Box { size: [4.0, 0.1, 4.0] }),
                true,
                ObjectPlacement::Single(Transform::default()),
            )],
            cameras: vec![moving],
            lights: vec![swept, moving_spot, uniform, log],
        };
        let text = assert_round_trip(&file);
        // The first key gives the camera's position: the reader refuses it beside a path.
        let value: serde_json::Value = serde_json::from_str(&text).unwrap();
        assert!(value["cameras"][0].get("position").is_none(), "{text}");
    }

    #[test]
    fn scene_file_refuses_what_the_format_cannot_hold() {
        let mut file = SceneFile {
            name: "s".into(),
            objects: vec![object(
                "o",
                Geometry::Mesh("o.obj".into()),
                false,
                ObjectPlacement::Instanced(vec![]),
            )],
            cameras: vec![],
            lights: vec![],
        };
        assert_eq!(file.to_json().unwrap_err().path, "objects[0].instances");
        file.objects[0].placement = ObjectPlacement::Single(Transform::default());
        let mut direction = track(Interpolation::Linear, &[[0.0, -1.0, 0.0], [0.6, -0.8, 0.0]]);
        let mut position = direction.clone();
        position.times[1] = 2.0;
        let mut lamp = spot(None);
        lamp.path = Some(LightPath { direction: direction.clone(), position: Some(position) });
        file.lights = vec![sun(None), lamp];
        assert_eq!(file.to_json().unwrap_err().path, "lights[1].path");
        direction.values.pop();
        file.lights[1].path = Some(LightPath { direction, position: None });
        assert!(file.to_json().unwrap_err().message.contains("1 values for 2 times"));
    }
}
