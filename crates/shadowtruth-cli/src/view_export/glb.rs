//! The scene as glTF 2.0 binary (docs/conventions.md, "Exported views"): one indexed mesh per
//! object in world space, the cameras, the lights as `KHR_lights_punctual`; a hand-built GLB
//! container (12-byte header, a JSON chunk padded with spaces, a BIN chunk padded with zeros).

use super::json_number::{num, nums};
use super::shadow_eye::ShadowEye;
use glam::{DMat3, DQuat, DVec3, Vec3};
use serde_json::{Value, json};
use shadowtruth::raster::LightView;
use shadowtruth::scene::{Camera, Light, LightKind, LightSize, PointMap, Scene};

const GLB_MAGIC: u32 = 0x4654_6C67; // "glTF"
const CHUNK_JSON: u32 = 0x4E4F_534A; // "JSON"
const CHUNK_BIN: u32 = 0x004E_4942; // "BIN\0"
const ARRAY_BUFFER: u32 = 34962;
const ELEMENT_ARRAY_BUFFER: u32 = 34963;
const FLOAT: u32 = 5126;
const UNSIGNED_INT: u32 = 5125;
/// Material indices: closed objects are one-sided (their back faces may be culled), open ones
/// two-sided.
const CLOSED_MATERIAL: usize = 0;
const OPEN_MATERIAL: usize = 1;

/// A camera with the depth range its exported projection uses.
pub(crate) struct GlbCamera<'a> {
    pub camera: &'a Camera,
    pub near: f32,
    pub far: f32,
}

/// A light with its shadow map's view (the node's frame is the light's view space).
pub(crate) struct GlbLight<'a> {
    pub light: &'a Light,
    pub view: LightView,
}

/// The node index of camera `i` and of light `i` (object `i` is node `i`).
pub(crate) fn camera_node(scene: &Scene, i: usize) -> usize {
    scene.objects.len() + i
}
pub(crate) fn light_node(scene: &Scene, i: usize) -> usize {
    scene.objects.len() + scene.cameras.len() + i
}

/// The .glb bytes of `scene`.
pub(crate) fn scene_glb(scene: &Scene, cameras: &[GlbCamera], lights: &[GlbLight]) -> Vec<u8> {
    let mut bin = Vec::new();
    let (mut buffer_views, mut accessors, mut meshes, mut nodes) = (vec![], vec![], vec![], vec![]);
    for (index, object) in scene.objects.iter().enumerate() {
        let mut node = json!({ "name": object.name, "extras": { "closed": object.closed } });
        if object.triangle_count > 0 {
            let primitive = write_mesh(scene, index, &mut bin, &mut buffer_views, &mut accessors);
            node["mesh"] = json!(meshes.len());
            meshes.push(json!({ "name": object.name, "primitives": [primitive] }));
        }
        nodes.push(node);
    }
    let mut gltf_cameras = Vec::new();
    for (i, c) in cameras.iter().enumerate() {
        let cam = c.camera;
        let (r, u, f) = cam.basis();
        let mut node = frame_node(&cam.name, cam.position, r, u, f);
        node["camera"] = json!(i);
        nodes.push(node);
        gltf_cameras.push(json!({
            "name": cam.name,
            "type": "perspective",
            "perspective": {
                "yfov": num((cam.fov_y_deg as f64).to_radians() as f32),
                "aspectRatio": num((cam.width as f64 / cam.height as f64) as f32),
                "znear": num(c.near),
                "zfar": num(c.far),
            },
            "extras": { "width": cam.width, "height": cam.height },
        }));
    }
    let mut gltf_lights = Vec::new();
    for (i, l) in lights.iter().enumerate() {
        let (light, node) = light_json(l);
        let mut node = node;
        node["extensions"] = json!({ "KHR_lights_punctual": { "light": i } });
        nodes.push(node);
        gltf_lights.push(light);
    }
    let document = json!({
        "asset": { "version": "2.0", "generator": concat!("shadowtruth ", env!("CARGO_PKG_VERSION")) },
        "extensionsUsed": ["KHR_lights_punctual"],
        "extensions": { "KHR_lights_punctual": { "lights": gltf_lights } },
        "scene": 0,
        "scenes": [{ "name": scene.name, "nodes": (0..nodes.len()).collect::<Vec<_>>() }],
        "nodes": nodes,
        "meshes": meshes,
        "cameras": gltf_cameras,
        "materials": [
            { "name": "closed", "doubleSided": false },
            { "name": "open", "doubleSided": true },
        ],
        "accessors": accessors,
        "bufferViews": buffer_views,
        "buffers": [{ "byteLength": bin.len() }],
    });
    glb_container(&serde_json::to_vec(&document).expect("JSON of plain values"), &bin)
}

/// Writes one object's vertices and indices into `bin`; returns its primitive. Every triangle
/// has its own three vertices, each with the triangle's geometric normal: the reference shades
/// with that flat normal (docs/conventions.md, "The surface point"), and an engine's normal-offset
/// bias does nothing without a NORMAL attribute, while smoothed normals would push points along
/// directions the reference never uses.
fn write_mesh(
    scene: &Scene,
    object: usize,
    bin: &mut Vec<u8>,
    buffer_views: &mut Vec<Value>,
    accessors: &mut Vec<Value>,
) -> Value {
    let triangles: Vec<[Vec3; 3]> = scene.object_triangles(object).collect();
    let vertices: Vec<Vec3> = triangles.iter().flatten().copied().collect();
    let normals: Vec<Vec3> = triangles.iter().flat_map(|t| [face_normal(t); 3]).collect();
    let indices: Vec<u32> = (0..vertices.len() as u32).collect();
    let bounds = |points: &[Vec3]| {
        points.iter().fold((Vec3::INFINITY, Vec3::NEG_INFINITY), |(lo, hi), v| (lo.min(*v), hi.max(*v)))
    };
    let as_bytes = |points: &[Vec3]| -> Vec<u8> {
        points.iter().flat_map(|v| v.to_array()).flat_map(f32::to_le_bytes).collect()
    };
    let mut vec3_accessor = |points: &[Vec3]| {
        let (lo, hi) = bounds(points);
        push_view(bin, buffer_views, &as_bytes(points), ARRAY_BUFFER);
        accessors.push(json!({
            "bufferView": buffer_views.len() - 1, "componentType": FLOAT, "count": points.len(),
            "type": "VEC3", "min": nums(&lo.to_array()), "max": nums(&hi.to_array()),
        }));
        accessors.len() - 1
    };
    let position_accessor = vec3_accessor(&vertices);
    let normal_accessor = vec3_accessor(&normals);
    let index_bytes: Vec<u8> = indices.iter().flat_map(|i| i.to_le_bytes()).collect();
    push_view(bin, buffer_views, &index_bytes, ELEMENT_ARRAY_BUFFER);
    accessors.push(json!({
        "bufferView": buffer_views.len() - 1, "componentType": UNSIGNED_INT, "count": indices.len(),
        "type": "SCALAR",
    }));
    let material = if scene.objects[object].closed { CLOSED_MATERIAL } else { OPEN_MATERIAL };
    json!({
        "attributes": { "POSITION": position_accessor, "NORMAL": normal_accessor },
        "indices": accessors.len() - 1,
        "material": material,
        "mode": 4,
    })
}

/// The unit geometric normal `normalize((v1 − v0) × (v2 − v0))`, in f64 rounded once to f32, as
/// the G-buffer computes it (before it is turned towards the camera). glTF requires unit normals,
/// so a degenerate triangle (which covers no pixel) gets +z.
pub(crate) fn face_normal([v0, v1, v2]: &[Vec3; 3]) -> Vec3 {
    let (v0, v1, v2) = (v0.as_dvec3(), v1.as_dvec3(), v2.as_dvec3());
    let n = (v1 - v0).cross(v2 - v0).normalize_or_zero();
    if n == DVec3::ZERO || !n.is_finite() { Vec3::Z } else { n.as_vec3() }
}

/// Appends `bytes` (a multiple of 4 long, so every view stays 4-byte aligned) as a buffer view.
fn push_view(bin: &mut Vec<u8>, buffer_views: &mut Vec<Value>, bytes: &[u8], target: u32) {
    buffer_views
        .push(json!({ "buffer": 0, "byteOffset": bin.len(), "byteLength": bytes.len(), "target": target }));
    bin.extend_from_slice(bytes);
}

/// A node whose local frame has x = `right`, y = `up` and looks down −z = `forward` (glTF's
/// camera and light convention), at `position`.
fn frame_node(name: &str, position: Vec3, right: DVec3, up: DVec3, forward: DVec3) -> Value {
    let rotation = DQuat::from_mat3(&DMat3::from_cols(right, up, -forward)).normalize();
    json!({
        "name": name,
        "translation": nums(&position.to_array()),
        "rotation": nums(&rotation.as_quat().to_array()),
    })
}

/// The light's `KHR_lights_punctual` entry and its node (rotation: the shadow map's view basis;
/// translation: the spot light's position, or the directional map's eye).
fn light_json(l: &GlbLight) -> (Value, Value) {
    let ShadowEye { position: eye, right, up, forward } = ShadowEye::of(l.light, &l.view);
    let mut extras = json!({ "near": num(l.view.near), "far": num(l.view.far) });
    if let Ok(size) = l.light.size() {
        extras[match size {
            LightSize::AngularDiameterDeg(_) => LightSize::ANGULAR_DIAMETER_FIELD,
            LightSize::Radius(_) => LightSize::RADIUS_FIELD,
        }] = num(size.value());
    }
    let (light, position) = match l.light.kind {
        LightKind::Directional { .. } => (
            json!({ "name": l.light.name, "type": "directional", "color": [1.0, 1.0, 1.0], "intensity": 1.0 }),
            eye,
        ),
        LightKind::Spot { position, cone_deg, far, .. } => {
            extras["cone_deg"] = num(cone_deg);
            let (inner, outer) = cone_angles(cone_deg);
            let light = json!({
                "name": l.light.name, "type": "spot", "color": [1.0, 1.0, 1.0], "intensity": 1.0,
                "range": num(far), "spot": { "innerConeAngle": num(inner), "outerConeAngle": num(outer) },
            });
            (light, position)
        }
        LightKind::Point { position, near, far, map, .. } => {
            // The light's own near and far (a face's may be adjusted), and its map, as the glTF
            // reader takes them back.
            extras["near"] = num(near);
            extras["far"] = num(far);
            extras["shadow_map"] = json!(map.name());
            if let PointMap::Cube(cube) = map {
                extras["guard_texels"] = json!(cube.guard_texels);
            }
            let light = json!({
                "name": l.light.name, "type": "point", "color": [1.0, 1.0, 1.0], "intensity": 1.0, "range": num(far),
            });
            (light, position)
        }
    };
    let mut node = frame_node(&l.light.name, position, right, up, forward);
    node["extras"] = extras;
    (light, node)
}

/// The largest f32 not above π/2 (π/2 itself rounds up in f32).
const HALF_PI_BELOW: f32 = f32::from_bits(0x3FC9_0FDA);

/// (innerConeAngle, outerConeAngle) of a hard-edged cone of full angle `cone_deg`: the outer
/// angle is the half-angle; glTF needs inner < outer, so inner is the next f32 below it.
pub(crate) fn cone_angles(cone_deg: f32) -> (f32, f32) {
    // Within glTF's 0 ≤ inner < outer ≤ π/2, also for a cone that f32 rounds to 0° or 180°.
    let outer = ((0.5 * cone_deg as f64).to_radians() as f32).clamp(f32::from_bits(1), HALF_PI_BELOW);
    (f32::from_bits(outer.to_bits() - 1), outer)
}

/// The GLB container: header (magic, version 2, total length), the JSON chunk padded with spaces
/// and the BIN chunk padded with zeros, each to a multiple of 4 bytes.
pub(crate) fn glb_container(json: &[u8], bin: &[u8]) -> Vec<u8> {
    let padded = |len: usize| len.div_ceil(4) * 4;
    let (json_len, bin_len) = (padded(json.len()), padded(bin.len()));
    let total = 12 + 8 + json_len + 8 + bin_len;
    let mut out = Vec::with_capacity(total);
    for word in [GLB_MAGIC, 2, total as u32, json_len as u32, CHUNK_JSON] {
        out.extend_from_slice(&word.to_le_bytes());
    }
    out.extend_from_slice(json);
    out.resize(20 + json_len, b' ');
    out.extend_from_slice(&(bin_len as u32).to_le_bytes());
    out.extend_from_slice(&CHUNK_BIN.to_le_bytes());
    out.extend_from_slice(bin);
    out.resize(total, 0);
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn container_layout_and_padding() {
        let glb = glb_container(b"{\"a\":1}", &[1, 2, 3, 4, 5]);
        // 12 header + 8 + 8 (7 padded) + 8 + 8 (5 padded).
        assert_eq!(glb.len(), 44);
        assert_eq!(&glb[0..4], b"glTF");
        assert_eq!(u32::from_le_bytes(glb[4..8].try_into().unwrap()), 2);
        assert_eq!(u32::from_le_bytes(glb[8..12].try_into().unwrap()), 44);
        assert_eq!(u32::from_le_bytes(glb[12..16].try_into().unwrap()), 8);
        assert_eq!(&glb[16..20], b"JSON");
        assert_eq!(&glb[20..28], b"{\"a\":1} ");
        assert_eq!(u32::from_le_bytes(glb[28..32].try_into().unwrap()), 8);
        assert_eq!(&glb[32..36], b"BIN\0");
        assert_eq!(&glb[36..44], &[1, 2, 3, 4, 5, 0, 0, 0]);
    }

    #[test]
    fn hard_cone_angles() {
        let (inner, outer) = cone_angles(90.0);
        assert_eq!(outer, std::f32::consts::FRAC_PI_4);
        assert!(inner < outer && inner == f32::from_bits(outer.to_bits() - 1));
    }
}
