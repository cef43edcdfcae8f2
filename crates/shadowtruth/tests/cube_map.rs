//! A point light's cube map (raster/cube_map.rs) on analytic scenes: the depth of every texel of
//! a face, guard band included, against the perspective depth of the floor seen through its
//! centre; a receiver plane seen across a cube corner, where PCF with a receiver-plane bias is
//! exact with the default guard band and wrong only next to the seams without one; and the face
//! each pixel is shaded through against the major axis of its direction from the light.

mod common;

use common::scene_from_json;
use glam::DVec3;
use shadowtruth::CubeMap;
use shadowtruth::metrics::falseness;
use shadowtruth::raster::{CascadeChoice, DepthFormat, RasterSettings, SEAM_TEXELS, rasterize_nearest};
use shadowtruth::scene::Scene;
use shadowtruth::technique::{BuiltLayers, CascadeOrders, ShadeContext, TechniqueSpec};
use shadowtruth::trace::{GBuffer, SceneBvh};

/// The f32 spacing just above `x` (x ≥ 0).
fn ulp(x: f32) -> f64 {
    (f32::from_bits(x.to_bits() + 1) - x) as f64
}

/// A point light at `position` with the given near, far and guard band.
fn point_light(position: [f32; 3], near: f32, far: f32, guard_texels: u32) -> serde_json::Value {
    serde_json::json!({ "name": "lamp", "type": "point", "position": position, "near": near, "far": far,
                        "cube_map": { "guard_texels": guard_texels } })
}

// ---------------------------------------------------------------------------------------------
// a. Every texel's depth against the floor's analytic depth.

/// The light's height above the floor: a power of two, so that 1/w is exact on the −y face.
const FLOOR_H: f32 = 2.0;
const FLOOR_LIGHT: [f32; 3] = [0.25, FLOOR_H, -0.5];
const FLOOR_NEAR: f32 = 0.05;
const FLOOR_FAR: f32 = 100.0;

/// A 400×400 floor at y = 0 centred under a point light `FLOOR_H` above it, whose cube has a
/// guard band of `guard` texels.
fn floor_scene(guard: u32) -> Scene {
    scene_from_json(&serde_json::json!({
        "format": "shadowtruth/scene/v1", "name": "floor",
        "objects": [{ "name": "floor", "shape": { "type": "plane", "size": [400, 400] },
                      "transform": { "translate": [FLOOR_LIGHT[0], 0, FLOOR_LIGHT[2]] } }],
        "cameras": [{ "name": "c", "position": [3, 5, 4], "look_at": [0, 0, 0], "fov_y_deg": 50, "width": 8, "height": 8 }],
        "lights": [point_light(FLOOR_LIGHT, FLOOR_NEAR, FLOOR_FAR, guard)]
    }))
}

/// The perspective depth of view depth `d` for the face's own near and far (what its matrix
/// was built from, exactly).
fn perspective_depth(n: f64, f: f64, d: f64) -> f64 {
    f * (d - n) / (d * (f - n))
}

#[test]
fn every_texel_of_the_down_face_guard_band_included_holds_the_floors_one_depth() {
    for (n, guard) in [(32, 8), (24, 4), (16, 0)] {
        let scene = floor_scene(guard);
        let cube = shadowtruth::cube_map(&scene.lights[0], n).unwrap();
        let face = &cube.faces[3];
        assert_eq!(face.resolution, n + 2 * guard);
        let layer = rasterize_nearest(&scene, face, &RasterSettings::default());
        // From the −y face the floor lies at view depth h in every direction: the face's frustum,
        // widened by its guard band to a half-angle of atan((N + 2g)/N), sees the floor through
        // every texel centre (it reaches 200 either way, the frustum h·(N + 2g)/N ≤ 3).
        let d = perspective_depth(face.near as f64, face.far as f64, FLOOR_H as f64);
        // The floor's four vertices have w = h and the same clip z, the f32 rounding of one f64
        // matrix entry (the other terms are products with exact zeros), and 1/w = ½ is exact: the
        // depth plane is that constant, so every texel holds it to half an ulp. One ulp allows it.
        let tolerance = ulp(d as f32);
        let mut worst = 0.0f64;
        for (k, &stored) in layer.depth.iter().enumerate() {
            let error = (stored as f64 - d).abs();
            worst = worst.max(error / ulp(d as f32));
            assert!(
                error <= tolerance,
                "N = {n}, guard {guard}: texel ({}, {}) holds {stored}, the floor's depth is {d}",
                k as u32 % face.resolution,
                k as u32 / face.resolution
            );
        }
        println!("−y face, N = {n}, guard {guard}: every texel within {worst:.2} ulp of the floor's depth");
    }
}

#[test]
fn every_texel_of_a_side_face_guard_band_included_holds_the_floor_depth_through_its_centre() {
    for (n, guard) in [(32, 8), (24, 4), (16, 0)] {
        let scene = floor_scene(guard);
        let cube = shadowtruth::cube_map(&scene.lights[0], n).unwrap();
        let face = &cube.faces[0];
        let side = face.resolution;
        let layer = rasterize_nearest(&scene, face, &RasterSettings::default());
        let (near, far) = (face.near as f64, face.far as f64);
        let tan_half = side as f64 / n as f64;
        // The +x face looks down +x with up +y, so its right (view x) is +x × +y = +z. The ray
        // through the centre (u, v) of a texel is x' + a·z' + b·y' with a = (2u − 1)·tan,
        // b = (2v − 1)·tan in the face's (right, up): it meets the floor, h below the light, where
        // b·D = −h, at x-distance (the face's view depth) D = −h/b, when b < 0. The texel row just
        // below the horizon has b = −1/N, D = N·h ≤ 64 < far, and the floor reaches 96 = tan·N·h
        // sideways with room to spare, so every texel below the horizon sees the floor, every
        // texel above it nothing.
        let depth_of_row = |row: u32| {
            let v = 1.0 - (row as f64 + 0.5) / side as f64;
            let b = (2.0 * v - 1.0) * tan_half;
            (b < 0.0).then(|| perspective_depth(near, far, -(FLOOR_H as f64) / b))
        };
        let (mut floor, mut worst) = (0, 0.0f64);
        for row in 0..side {
            for x in 0..side {
                let stored = layer.at(x, row);
                let Some(d) = depth_of_row(row) else {
                    assert_eq!(stored, 1.0, "N = {n}, guard {guard}: texel ({x}, {row}) above the horizon");
                    continue;
                };
                floor += 1;
                // The rasterizer evaluates the plane through the vertices snapped to 1/256 texel
                // (each coordinate moved by at most 1/512): that plane differs from the floor's
                // by at most its slope times 1/512 texel in each of x and y. Along a row the
                // floor's depth does not change; across rows it changes by `step` a texel. Twice
                // that, plus four ulps for the f32 set-up and evaluation of the plane, bounds
                // the stored depth; a texel shifted by a tenth of a texel would be 25 times
                // outside it.
                let step = depth_of_row(row + 1).map_or(0.0, |next| (next - d).abs());
                let step = step.max(depth_of_row(row.wrapping_sub(1)).map_or(0.0, |prev| (prev - d).abs()));
                let tolerance = step / 256.0 + 4.0 * ulp(d as f32);
                let error = (stored as f64 - d).abs();
                worst = worst.max(error / tolerance);
                assert!(
                    error <= tolerance,
                    "N = {n}, guard {guard}: texel ({x}, {row}) holds {stored}, the floor through its centre is \
                     at {d} (tolerance {tolerance:e})"
                );
            }
        }
        assert_eq!(floor, side * side / 2, "the lower half of the face sees the floor");
        println!("+x face, N = {n}, guard {guard}: every floor texel within {worst:.3} of its tolerance");
    }
}

// ---------------------------------------------------------------------------------------------
// b. A receiver plane seen across a cube corner.

const SEAM_LIGHT: [f32; 3] = [0.0, 3.0, 0.0];
/// The face resolution of the seam test: large texels, so that the corner spans many pixels.
const SEAM_N: u32 = 32;

/// A 4×4 plane with no occluder, turned by 20° about x and then 45° about y: it descends away
/// from the light towards +x and +z alike, y' = −1 − k·(x' + z') with k = tan 20°/√2 relative to
/// the light, and passes through the direction (1, −1, 1) from it, where the −y, +x and +z faces
/// meet, at distance D = 1/(1 − 2k) ≈ 2.06 along each axis. The camera looks at that corner
/// point along the plane's normal.
///
/// Why a corner, and why this tilt. Without a guard band a tap past a face's edge reads the edge
/// texel (clamp to edge), while the receiver-plane bias compares the plane's depth at the tap's
/// own centre: the tap fails exactly where the plane's depth in that face grows outwards across
/// the edge. A flat floor never does (its depth is constant in the −y face and falls outwards
/// across the side faces' lower edges), nor does a wall; a plane descending away from the light
/// does in the face looking down on it. And across one edge a 5×5 kernel has at most 2 of its 5
/// columns past the edge, 10 of 25 taps: visibility 0.6, lit by the ½ threshold. Only at a
/// corner, where the depth grows outwards across both edges of the −y face, do 16 of 25 taps
/// fail (visibility 0.36): a false shadow.
fn corner_scene(guard: u32) -> (Scene, DVec3) {
    let k = 20f64.to_radians().tan() / 2f64.sqrt();
    let d = 1.0 / (1.0 - 2.0 * k);
    let light = DVec3::from(SEAM_LIGHT.map(f64::from));
    let corner = light + DVec3::new(d, -d, d);
    let normal = DVec3::new(k, 1.0, k).normalize();
    let camera = corner + 3.0 * normal;
    let scene = scene_from_json(&serde_json::json!({
        "format": "shadowtruth/scene/v1", "name": "corner",
        "objects": [{ "name": "slope", "shape": { "type": "plane", "size": [4, 4] },
                      "transform": { "rotate_deg": [20, 45, 0], "translate": corner.to_array() } }],
        "cameras": [{ "name": "c", "position": camera.to_array(), "look_at": corner.to_array(),
                      "fov_y_deg": 25, "width": 128, "height": 128 }],
        "lights": [point_light(SEAM_LIGHT, 0.1, 20.0, guard)]
    }));
    (scene, corner)
}

/// The cube of the scene's point light at `resolution` and `spec`'s visibility of every
/// evaluated pixel of `g`, each shaded through its own face.
fn shade_cube(scene: &Scene, g: &GBuffer, spec: &TechniqueSpec, resolution: u32) -> (CubeMap, Vec<f32>) {
    let cube = shadowtruth::cube_map(&scene.lights[0], resolution).unwrap();
    let technique = spec.build().expect("a shaded technique");
    let needs = technique.layer_needs();
    let layers: Vec<BuiltLayers> =
        cube.faces.iter().map(|face| BuiltLayers::build(scene, face, DepthFormat::F32, &needs)).collect();
    let contexts: Vec<ShadeContext> = cube
        .faces
        .iter()
        .zip(&layers)
        .map(|(face, l)| ShadeContext::new(scene, g.footprint, face, l.as_layers()))
        .collect();
    let visibility =
        CascadeOrders::of_faces(g, &cube.faces, &faces_of(g, &cube)).shade(technique.as_ref(), &contexts);
    (cube, visibility)
}

/// A 5×5 box PCF with the receiver-plane bias and `bias_depth`.
fn pcf5_receiver_plane(bias_depth: f64) -> TechniqueSpec {
    let spec: TechniqueSpec = serde_json::from_value(serde_json::json!(
        { "technique": "pcf", "kernel": "box", "size": 5, "bias": "receiver_plane", "bias_depth": bias_depth }
    ))
    .unwrap();
    spec.validate().unwrap();
    spec
}

/// Per evaluated pixel of the corner scene with `guard` texels: its texels from its face's edge
/// and its visibility under each of `specs`; and the pixels per face.
fn corner_pixels(guard: u32, specs: &[TechniqueSpec]) -> (Vec<(f32, Vec<f32>)>, [usize; 6]) {
    let (scene, corner) = corner_scene(guard);
    let (g, reference) = common::trace_first(&scene);
    assert!(reference.uncertain.is_empty(), "{} pixels uncertain", reference.uncertain.len());
    assert!(g.evaluated.len() > 12000, "the plane fills the image: {} pixels", g.evaluated.len());
    assert!(g.evaluated.iter().all(|&i| reference.lit[i as usize] != 0), "nothing occludes the plane");
    let shaded: Vec<(CubeMap, Vec<f32>)> =
        specs.iter().map(|spec| shade_cube(&scene, &g, spec, SEAM_N)).collect();
    let cube = &shaded[0].0;
    // The corner is where the three faces meet.
    let c = corner.as_vec3();
    assert!(cube.texels_from_edge(cube.face_of(c), c).is_some_and(|t| t.abs() < 1e-3));
    let mut faces = [0usize; 6];
    let pixels = g
        .evaluated
        .iter()
        .enumerate()
        .map(|(k, &i)| {
            let p = g.position[i as usize];
            let face = cube.face_of(p);
            faces[face] += 1;
            let from_edge = cube.texels_from_edge(face, p).expect("a point projects into its own face");
            (from_edge, shaded.iter().map(|(_, v)| v[k]).collect())
        })
        .collect();
    (pixels, faces)
}

/// The seam test: every pixel of the corner scene is lit in truth. With the default guard band
/// of 8 texels every tap of a 5×5 kernel (2 texels either way) past a face's edge reads the
/// plane drawn in its direction, and PCF is as exact there as anywhere; without one, the taps
/// past an edge read the clamped edge texel, and the plane's depth growing outwards makes them
/// fail.
///
/// Two biases. plans/soft.json's `bias_depth` of 1e-5 lies within the rasterizer's own error
/// on this slope (its vertices snapped to 1/256 texel move the depth plane by up to its slope,
/// about 0.006 a texel across rows here and less along them, times 1/512 texel in each
/// direction: ~1.5e-5; 1e-5 is measured): a few taps fail anywhere on the plane, a few in 25,
/// never half; the ½ threshold's false shadows are counted with it. With a `bias_depth` of
/// 1e-4, several times that error and a sixtieth of the depth the plane gains in a texel, no tap
/// may fail unless it reads a clamped texel: every pixel short of visibility 1 is then a seam
/// error. (At faces of 16² texels the receivers' planes also come within the 5×5 kernel of
/// their horizon, past which a plane's extrapolated depth exceeds 1 and fails against the empty
/// map: hence faces of 32².)
#[test]
fn pcf_across_a_cube_corner_is_exact_with_a_guard_band_and_wrong_only_at_the_seams_without() {
    let specs = [pcf5_receiver_plane(1e-5), pcf5_receiver_plane(1e-4)];
    for guard in [8, 0] {
        let (pixels, faces) = corner_pixels(guard, &specs);
        // The visible plane spans the three faces around the corner, and only those.
        for (face, &count) in faces.iter().enumerate() {
            assert_eq!(count > 1000, matches!(face, 0 | 3 | 4), "face {face}: {count} pixels");
        }
        let (mut false_shadow, mut darkened, mut farthest) = (0, 0, 0.0f32);
        for (k, (from_edge, v)) in pixels.iter().enumerate() {
            let (soft_json, wide_bias) = (v[0], v[1]);
            if falseness(true, soft_json).0 {
                false_shadow += 1;
                farthest = farthest.max(*from_edge);
                assert!(
                    guard == 0 && *from_edge < SEAM_TEXELS,
                    "guard {guard}: a false shadow {from_edge} texels inside its face (pixel {k}, visibility {soft_json})"
                );
            }
            if wide_bias < 1.0 {
                darkened += 1;
                farthest = farthest.max(*from_edge);
                assert!(
                    guard == 0 && *from_edge < SEAM_TEXELS,
                    "guard {guard}: visibility {wide_bias} {from_edge} texels inside its face (pixel {k})"
                );
            }
        }
        println!(
            "guard {guard}: {} pixels {faces:?} per face; {false_shadow} false shadows (bias 1e-5), {darkened} \
             below 1 (bias 1e-4), the farthest {farthest:.3} texels from its face's edge",
            pixels.len()
        );
        if guard == 0 {
            assert!(
                false_shadow > 20,
                "without a guard band the clamped corner shadows the plane: {false_shadow}"
            );
            assert!(darkened > 2 * false_shadow, "and the clamped edges darken it: {darkened}");
        }
    }
}

// ---------------------------------------------------------------------------------------------
// c. Face selection.

/// A closed 8×6×7 room around a point light, seen by two cameras inside it, each looking into
/// a corner: between them every face of the cube shades a large share of the pixels.
fn room() -> Scene {
    scene_from_json(&serde_json::json!({
        "format": "shadowtruth/scene/v1", "name": "box_room",
        "objects": [{ "name": "room", "shape": { "type": "box", "size": [8, 6, 7] } }],
        "cameras": [
            { "name": "a", "position": [-2.5, -1.5, -2], "look_at": [4, 3, 3.5], "fov_y_deg": 100, "width": 64, "height": 48 },
            { "name": "b", "position": [2.5, 1.5, 2], "look_at": [-4, -3, -3.5], "fov_y_deg": 100, "width": 64, "height": 48 }
        ],
        "lights": [point_light([0.3, 0.2, -0.1], 0.05, 30.0, 8)]
    }))
}

#[test]
fn every_pixel_is_shaded_through_the_face_of_its_directions_major_axis() {
    let scene = room();
    let bvh = SceneBvh::build(&scene);
    let light = &scene.lights[0];
    let cube = shadowtruth::cube_map(light, 64).unwrap();
    let position = light.position().unwrap().as_dvec3();
    let (mut per_face, mut ties) = ([0usize; 6], 0);
    for camera in &scene.cameras {
        let g = GBuffer::trace(&bvh, camera, light);
        let orders = CascadeOrders::of_faces(&g, &cube.faces, &faces_of(&g, &cube));
        for (k, &i) in g.evaluated.iter().enumerate() {
            let p = g.position[i as usize];
            // Exact: the difference of two f32 numbers this close is exact in f64.
            let d = p.as_dvec3() - position;
            let a = d.abs();
            // Rounding is monotone, so the f32 components the light's lookup compares keep the
            // exact order unless they round to the same value.
            let f32_abs = (p - light.position().unwrap()).abs();
            if f32_abs.x == f32_abs.y || f32_abs.y == f32_abs.z || f32_abs.x == f32_abs.z {
                ties += 1;
                continue;
            }
            let (axis, sign) = if a.x > a.y && a.x > a.z {
                (0, d.x)
            } else if a.y > a.z {
                (1, d.y)
            } else {
                (2, d.z)
            };
            let expected = 2 * axis + usize::from(sign < 0.0);
            assert_eq!(cube.face_of(p), expected, "camera {}, pixel {i} at {p}", camera.name);
            assert_eq!(orders.choices[k], CascadeChoice::One(expected), "camera {}, pixel {i}", camera.name);
            per_face[expected] += 1;
        }
    }
    println!("pixels per face {per_face:?}, {ties} ties");
    assert!(per_face.iter().all(|&count| count > 300), "every face shades part of the room: {per_face:?}");
}

/// The face of every evaluated pixel of `g`, as the command's point-light maps choose it.
fn faces_of(g: &GBuffer, cube: &CubeMap) -> Vec<u8> {
    g.evaluated.iter().map(|&i| cube.face_of(g.position[i as usize]) as u8).collect()
}
