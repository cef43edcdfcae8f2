//! `shadowtruth view-export`: everything an engine needs to render the same pixels under the
//! same light (docs/conventions.md, "Exported views"): `view.json` (the camera's and the shadow
//! map's matrices in OpenGL, Vulkan and D3D form), the G-buffer as EXRs and the scene as glTF
//! binary.

mod gbuffer_exr;
mod glb;
pub(crate) use glb::glb_container;
mod json_number;
mod map_json;
mod matrices;
mod point_map;
mod shadow_eye;

use anyhow::{Context, Result};
use gbuffer_exr::{IDS_FILE, NORMAL_FILE, POSITION_FILE};
use glam::Vec3;
use glb::{GlbCamera, GlbLight};
use json_number::{num, nums};
use map_json::{map_json, matrices_json};
use matrices::{ViewMatrices, camera_depth_range, camera_matrices};
use point_map::{point_map_json, point_views};
use serde_json::{Value, json};
use shadowtruth::atomic_file::write_atomic;
use shadowtruth::raster::LightView;
use shadowtruth::scene::{Camera, Light, LightKind, LightSize, Scene};
use shadowtruth::trace::{GBuffer, SceneBvh};
use std::path::{Path, PathBuf};

/// The format tag of view.json.
pub(crate) const VIEW_FORMAT: &str = "shadowtruth/view/v1";
pub(crate) const VIEW_FILE: &str = "view.json";
pub(crate) const GLB_FILE: &str = "scene.glb";

const PIXEL_CENTRES: &str = "Pixel (x, y) has x from the left and row y = 0 at the top of the image; it covers \
[x, x + 1) × [y, y + 1) and its centre is (x + 0.5, y + 0.5). The G-buffer holds the closest hit of the ray from \
the camera's position through that centre, with direction normalize(forward + sx·right + sy·up), sx = (2·px/width \
− 1)·tan(fov_y/2)·width/height, sy = (1 − 2·py/height)·tan(fov_y/2) at (px, py) = (x + 0.5, y + 0.5), computed in \
f64 and rounded once to f32. With ndc = clip.xyz / clip.w of a camera matrix, the point lands at px = (ndc.x + \
1)/2·width and py = (1 − ndc.y)/2·height for opengl and d3d (opengl's window row counts from the bottom: height − \
py), py = (ndc.y + 1)/2·height for vulkan.";

const MATRICES: &str = "Every matrix maps column vectors, clip = M · (x, y, z, 1); `_row_major` lists the 16 \
entries row by row, `_column_major` column by column (OpenGL/glTF order). View space is right-handed, looking down \
−z with +y up. opengl: clip z/w ∈ [−1, 1], y up in NDC, window row 0 at the bottom, texture t up. vulkan: z/w ∈ \
[0, 1], y down in NDC and in the framebuffer, texture t down. d3d: z/w ∈ [0, 1], y up in NDC, framebuffer row 0 \
at the top, texture v down. clip_from_world = clip_from_view · view_from_world, rounded once.";

const SHADOW_MAP: &str = "The shadow map is resolution × resolution texels. d3d's clip_from_world is the CPU \
rasterizer's clip_from_world bit for bit (src/raster/projection.rs); u = clip.x/clip.w·½ + ½ runs left to right, \
v = clip.y/clip.w·½ + ½ upwards and depth d = clip.z/clip.w ∈ [0, 1], smaller is closer. Texel (x, row) covers u ∈ \
[x/N, (x + 1)/N) and v ∈ [1 − (row + 1)/N, 1 − row/N): row 0 holds the largest v. texture_from_world gives (s·w, \
t·w, depth·w, w) for a map rendered with that API: s = u; t = v for opengl (window row 0 at the bottom), t = 1 − v \
for vulkan and d3d (framebuffer row 0 at the top); depth = d in every form (opengl's window depth ½·z/w + ½). \
eye (position, target, up; world space) is the map's camera for engines that place one by lookAt: lookAt(position, \
target, up) gives view_from_world; left/right/bottom/top/near/far are an orthographic camera's box, fov_y_deg and \
aspect (1) a perspective one's.";

/// Exports the view of `camera` under `light` into `dir` (created if missing); returns the
/// files written.
pub(crate) fn write_view_export(
    scene: &Scene,
    camera: &Camera,
    light: &Light,
    resolution: u32,
    dir: &Path,
    mut progress: impl FnMut(&str),
) -> Result<Vec<PathBuf>> {
    std::fs::create_dir_all(dir)
        .with_context(|| format!("--out {}: cannot create the output folder", dir.display()))?;
    progress("tracing the G-buffer");
    let bvh = SceneBvh::build(scene);
    // The bounds the BVH was built from: the scene's triangles walked once.
    let bounds = bvh.scene_bounds();
    let gbuffer = GBuffer::trace(&bvh, camera, light);
    let views = light_views(light, bounds, resolution);

    progress("tracing the other cameras' depth ranges");
    let cameras: Vec<GlbCamera> = scene
        .cameras
        .iter()
        .map(|c| {
            // The exported camera itself (by identity: names need not be unique).
            let (near, far) = if std::ptr::eq(c, camera) {
                camera_depth_range(c, &gbuffer, bounds)
            } else {
                camera_depth_range(c, &GBuffer::trace(&bvh, c, light), bounds)
            };
            GlbCamera { camera: c, near, far }
        })
        .collect();
    let lights: Vec<GlbLight> = scene
        .lights
        .iter()
        .map(|l| GlbLight { light: l, view: light_views(l, bounds, resolution).swap_remove(0) })
        .collect();

    progress("writing");
    let mut files = Vec::new();
    let mut write = |name: &str, bytes: &[u8]| -> Result<()> {
        let path = dir.join(name);
        write_atomic(&path, bytes).with_context(|| format!("writing {}", path.display()))?;
        files.push(path);
        Ok(())
    };
    let camera_index = scene.cameras.iter().position(|c| c.name == camera.name).unwrap_or(0);
    let light_index = scene.lights.iter().position(|l| l.name == light.name).unwrap_or(0);
    let (near, far) = (cameras[camera_index].near, cameras[camera_index].far);
    let document = json!({
        "format": VIEW_FORMAT,
        "scene": scene.name,
        "conventions": { "matrices": MATRICES, "pixel_centres": PIXEL_CENTRES, "shadow_map": SHADOW_MAP },
        "camera": camera_json(camera, &camera_matrices(camera, near, far), glb::camera_node(scene, camera_index)),
        "light": light_json(light, &views, resolution, glb::light_node(scene, light_index)),
        "gbuffer": gbuffer_json(),
        "scene_glb": GLB_FILE,
    });
    let mut text = serde_json::to_string_pretty(&document)?;
    text.push('\n');
    write(VIEW_FILE, text.as_bytes())?;
    let exrs = gbuffer_exr::gbuffer_exrs(scene, &gbuffer)
        .with_context(|| format!("encoding the G-buffer EXRs for {}", dir.display()))?;
    for (name, bytes) in exrs {
        write(name, &bytes)?;
    }
    write(GLB_FILE, &glb::scene_glb(scene, &cameras, &lights))?;
    Ok(files)
}

fn camera_json(camera: &Camera, m: &ViewMatrices, node: usize) -> Value {
    let (r, u, f) = camera.basis();
    let mut object = json!({
        "name": camera.name,
        "glb_node": node,
        "position": nums(&camera.position.to_array()),
        "look_at": nums(&camera.look_at.to_array()),
        "up": nums(&camera.up.to_array()),
        "right_unit": nums(&r.as_vec3().to_array()),
        "up_unit": nums(&u.as_vec3().to_array()),
        "forward_unit": nums(&f.as_vec3().to_array()),
        "fov_y_deg": num(camera.fov_y_deg),
        "fov_y_rad": num((camera.fov_y_deg as f64).to_radians() as f32),
        "width": camera.width,
        "height": camera.height,
        "aspect_ratio": num((camera.width as f64 / camera.height as f64) as f32),
        "near": num(m.near),
        "far": num(m.far),
        "depth_range": "near = ½ the smallest view depth of the G-buffer's hits, far = the largest view depth of the \
                        scene bounds' corners plus 1 %",
    });
    object.as_object_mut().expect("an object").extend(matrices_json(m));
    object
}

/// The views `light`'s map is drawn from at `resolution`: one, or a point light's faces or
/// hemispheres.
fn light_views(light: &Light, bounds: (Vec3, Vec3), resolution: u32) -> Vec<LightView> {
    if light.is_point() {
        point_views(light, resolution)
    } else {
        vec![LightView::new(light, bounds, resolution)]
    }
}

fn light_json(light: &Light, views: &[LightView], resolution: u32, node: usize) -> Value {
    let mut object = json!({ "name": light.name, "glb_node": node });
    match &light.kind {
        LightKind::Directional { direction, .. } => {
            object["type"] = json!("directional");
            object["direction"] = nums(&direction.to_array());
        }
        LightKind::Spot { position, direction, cone_deg, near, far, .. } => {
            object["type"] = json!("spot");
            object["position"] = nums(&position.to_array());
            object["direction"] = nums(&direction.to_array());
            object["cone_deg"] = num(*cone_deg);
            object["near"] = num(*near);
            object["far"] = num(*far);
        }
        LightKind::Point { position, near, far, .. } => {
            object["type"] = json!("point");
            object["position"] = nums(&position.to_array());
            object["near"] = num(*near);
            object["far"] = num(*far);
        }
    }
    if let Ok(size) = light.size() {
        let field = match size {
            LightSize::AngularDiameterDeg(_) => LightSize::ANGULAR_DIAMETER_FIELD,
            LightSize::Radius(_) => LightSize::RADIUS_FIELD,
        };
        object[field] = num(size.value());
    }
    object["shadow_map"] =
        if light.is_point() { point_map_json(light, views, resolution) } else { map_json(light, &views[0]) };
    object
}

fn gbuffer_json() -> Value {
    json!({
        "rows": "row 0 at the top, x from the left; every file is width × height",
        "position": { "file": POSITION_FILE, "channels": "R, G, B (f32) = world x, y, z of the surface point; 0 on background" },
        "normal": {
            "file": NORMAL_FILE,
            "channels": "R, G, B (f32) = the unit geometric normal, turned towards the camera; 0 on background",
        },
        "ids": {
            "file": IDS_FILE,
            "channels": "triangle, object (u32) = the scene's triangle and object index (the glb's object nodes \
                         in order; the triangle's position in its object's mesh is triangle − the object's first \
                         triangle), 4294967295 on background; class (u32)",
            "class": { "0": "background", "1": "facing_away", "2": "outside_light", "3": "evaluated" },
        },
    })
}
