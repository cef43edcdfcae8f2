//! The hard cases of the reference, generated here, each checked pixel by pixel against the
//! exact adjudicator (`shadowtruth::verify`): shadow answers and primary hits alike, no
//! disagreement may lie on a pixel the tracer did not flag as uncertain, on one thread and on
//! two. Each case also checks that it is not vacuous (it has lit and, where it has an occluder,
//! shadowed pixels) and that the tracer's band stays a sliver of the image.

mod common;

use common::scene_from_json;
use glam::{DVec3, Vec3, vec3};
use serde_json::{Value, json};
use shadowtruth::scene::{Object, Scene};
use shadowtruth::trace::{
    GBuffer, PixelClass, SceneBvh, trace_area_light_reference, trace_coverage_reference, trace_hard_reference,
};
use shadowtruth::verify::{Adjudicator, PixelSelection, ViewVerification, verify_view};

fn with_threads<T: Send>(n: usize, f: impl FnOnce() -> T + Send) -> T {
    rayon::ThreadPoolBuilder::new().num_threads(n).build().unwrap().install(f)
}

/// Checks every pixel of every (camera, light) of `scene` on 1 and 2 threads; returns the
/// one-thread results.
fn check(case: &str, scene: &Scene, occluded: bool, max_band_fraction: f64) -> Vec<ViewVerification> {
    let bvh = SceneBvh::build(scene);
    let adjudicator = Adjudicator::new(scene);
    let mut first = Vec::new();
    for threads in [1, 2] {
        for camera in &scene.cameras {
            for light in &scene.lights {
                let v = with_threads(threads, || {
                    verify_view(scene, &bvh, &adjudicator, camera, light, PixelSelection::All)
                });
                let what =
                    format!("{case}, camera {}, light {}, {threads} thread(s)", camera.name, light.name);
                assert_eq!(
                    (v.disagree_outside_band, v.primary_disagree_outside_band),
                    (0, 0),
                    "{what}: disagreements on pixels the tracer did not flag: {:#?}",
                    v.cases
                );
                assert!(v.passed(), "{what}");
                assert!(v.evaluated > 500, "{what}: only {} evaluated pixels", v.evaluated);
                let g = GBuffer::trace(&bvh, camera, light);
                assert_eq!(
                    v.checked,
                    v.evaluated + g.count(PixelClass::Uncertain),
                    "{what}: every evaluated and every flagged pixel is checked"
                );
                assert_eq!(v.primary_checked, g.pixel_count(), "{what}: every primary ray is checked");
                assert!(v.max_point_error_ratio <= 1.0, "{what}");
                let band = v.in_band as f64 / v.primary_checked as f64;
                println!(
                    "{what}: band {:.4} %, {} shadow and {} primary disagreements inside it, \
                     point error ratio at most {:.3}",
                    100.0 * band,
                    v.disagree_in_band,
                    v.primary_disagree_in_band,
                    v.max_point_error_ratio
                );
                assert!(
                    band <= max_band_fraction,
                    "{what}: {:.4} % of the pixels lie in the band",
                    100.0 * band
                );
                if threads == 1 {
                    first.push(v);
                }
            }
        }
    }
    let g_and_r = |camera: usize, light: usize| {
        let bvh = SceneBvh::build(scene);
        let g = GBuffer::trace(&bvh, &scene.cameras[camera], &scene.lights[light]);
        let r = trace_hard_reference(scene, &bvh, &g, &scene.lights[light]);
        let lit = g.evaluated.iter().filter(|&&i| r.lit[i as usize] != 0).count();
        (lit, g.evaluated.len() - lit)
    };
    for c in 0..scene.cameras.len() {
        for l in 0..scene.lights.len() {
            let (lit, shadowed) = g_and_r(c, l);
            assert!(lit > 0, "{case}: camera {c} light {l} has no lit pixel");
            if occluded {
                assert!(shadowed > 0, "{case}: camera {c} light {l} has no shadowed pixel");
            }
        }
    }
    first
}

/// Appends an object made of `triangles` to a scene.
fn append(scene: &mut Scene, name: &str, triangles: Vec<[Vec3; 3]>, closed: bool) {
    let first = scene.flat_triangles.len() as u32;
    let object = scene.objects.len() as u32;
    scene.objects.push(Object {
        name: name.into(),
        closed,
        first_triangle: first,
        triangle_count: triangles.len() as u32,
    });
    scene.flat_triangle_object.extend(std::iter::repeat_n(object, triangles.len()));
    scene.flat_triangles.extend(triangles);
}

fn camera(name: &str, position: DVec3, look_at: DVec3, width: u32, height: u32) -> Value {
    json!({ "name": name, "position": position.to_array(), "look_at": look_at.to_array(),
            "fov_y_deg": 50, "width": width, "height": height })
}

/// A spot light `distance` from `target` at `elevation_deg`, aimed at it.
fn spot(
    name: &str,
    target: DVec3,
    distance: f64,
    elevation_deg: f64,
    azimuth_deg: f64,
    near: f64,
    far: f64,
) -> Value {
    let (e, a) = (elevation_deg.to_radians(), azimuth_deg.to_radians());
    let position = target + distance * DVec3::new(e.cos() * a.cos(), e.sin(), e.cos() * a.sin());
    json!({ "name": name, "type": "spot", "position": position.to_array(), "direction": (target - position).to_array(),
            "cone_deg": 90, "near": near, "far": far })
}

fn directional(name: &str, elevation_deg: f64, azimuth_deg: f64) -> Value {
    let (e, a) = (elevation_deg.to_radians(), azimuth_deg.to_radians());
    let towards_light = DVec3::new(e.cos() * a.cos(), e.sin(), e.cos() * a.sin());
    json!({ "name": name, "type": "directional", "direction": (-towards_light).to_array() })
}

fn scene(name: &str, objects: Value, cameras: Vec<Value>, lights: Vec<Value>) -> Scene {
    scene_from_json(&json!({ "format": "shadowtruth/scene/v1", "name": name, "objects": objects,
                             "cameras": cameras, "lights": lights }))
}

/// The heightfield island in its sea: 161 × 161 vertices over 140 × 140 units, from about −6
/// under the water to about +30, its shore crossing y = 0, inside a two-triangle sea 800 units
/// across at y = 0.
fn sea_and_island(lights: Vec<Value>) -> Scene {
    let cameras = vec![
        camera("shore", DVec3::new(-60.0, 40.0, 140.0), DVec3::ZERO, 160, 120),
        camera("open_sea", DVec3::new(100.0, 30.0, -110.0), DVec3::ZERO, 160, 120),
    ];
    let mut s = scene(
        "sea_and_island",
        json!([{ "name": "sea", "shape": { "type": "plane", "size": [800, 800] } }]),
        cameras,
        lights,
    );
    let n = 161;
    let height = |x: f64, z: f64| {
        let r2 = (x * x + z * z) / (70.0 * 70.0);
        let falloff = (1.0 - r2).max(0.0);
        36.0 * falloff - 6.0
            + falloff * (2.0 * (0.31 * x + 1.3).sin() * (0.27 * z - 0.4).cos() + (0.69 * x + 0.5 * z).sin())
    };
    let vertex = |i: usize, j: usize| {
        let (x, z) = (-70.0 + 140.0 * i as f64 / (n - 1) as f64, -70.0 + 140.0 * j as f64 / (n - 1) as f64);
        DVec3::new(x, height(x, z), z).as_vec3()
    };
    let mut tris = Vec::new();
    for j in 0..n - 1 {
        for i in 0..n - 1 {
            let (a, b, c, d) = (vertex(i, j), vertex(i + 1, j), vertex(i, j + 1), vertex(i + 1, j + 1));
            tris.push([a, c, d]);
            tris.push([a, d, b]);
        }
    }
    append(&mut s, "terrain", tris, false);
    s
}

#[test]
fn sea_and_island_under_a_spot_light_has_no_self_shadow_speckle() {
    // The regression: a fixed Wächter–Binder offset let the sea hit itself at 0 < t < 2e-5 on
    // about 0.3 % of its pixels, wherever the terrain made the tracer test the sea's triangles.
    let light = spot("spot", DVec3::ZERO, 150.0, 14.0, 0.0, 20.0, 400.0);
    let s = sea_and_island(vec![light]);
    let views = check("sea and island, spot 150 away", &s, true, 0.002);
    assert!(views.iter().all(|v| v.agree + v.disagree_in_band == v.checked));
    assert!(views.iter().all(|v| v.max_point_error_ratio > 0.0), "the point check compares something");
}

#[test]
fn sea_and_island_under_near_and_far_spot_lights_and_the_sun() {
    let lights = vec![
        spot("near", DVec3::ZERO, 75.0, 20.0, 30.0, 5.0, 400.0),
        spot("far", DVec3::ZERO, 380.0, 8.0, -20.0, 100.0, 900.0),
        directional("sun", 14.0, 0.0),
    ];
    check("sea and island", &sea_and_island(lights), true, 0.002);
}

/// A two-triangle ground `size` across with a box floating over it, lit at each elevation.
fn ground_with_box(size: f64, translate: DVec3, lights: Vec<Value>) -> Scene {
    let b = size / 10.0;
    let objects = json!([
        { "name": "ground", "shape": { "type": "plane", "size": [size, size] }, "transform": { "translate": translate.to_array() } },
        { "name": "box", "shape": { "type": "box", "size": [b, b, b] }, "closed": true,
          "transform": { "rotate_deg": [0, 25, 0], "translate": (translate + DVec3::new(0.0, size / 12.0, 0.0)).to_array() } }
    ]);
    let cameras = vec![camera("main", translate + DVec3::new(-0.45, 0.35, 0.5) * size, translate, 64, 48)];
    scene("ground", objects, cameras, lights)
}

#[test]
fn ground_planes_from_10_to_1e5_units_under_lights_from_5_to_85_degrees() {
    for size in [10.0, 1e3, 1e5] {
        for elevation in [5.0, 30.0, 60.0, 85.0] {
            let lights = vec![
                directional("sun", elevation, 40.0),
                spot("near", DVec3::ZERO, 0.4 * size, elevation, 40.0, 0.01 * size, 2.0 * size),
                spot("far", DVec3::ZERO, 4.0 * size, elevation, 40.0, 0.5 * size, 8.0 * size),
            ];
            // A light at 5° has the box's shadow run off the ground: only then may it be absent.
            let s = ground_with_box(size, DVec3::ZERO, lights);
            check(&format!("ground {size} across, light at {elevation}°"), &s, elevation > 20.0, 0.002);
        }
    }
}

#[test]
fn ground_planes_far_from_the_origin_and_scaled() {
    let lights = |size: f64, at: DVec3| {
        vec![
            directional("sun", 35.0, 40.0),
            spot("spot", at, 0.6 * size, 35.0, 40.0, 0.01 * size, 3.0 * size),
        ]
    };
    // f32 points there are known to 2⁻²⁴ of their magnitude (0.03 units at 1e6): the tracer's
    // band may widen with the distance from the origin, never the disagreements outside it.
    for (offset, max_band) in [(1e4, 0.005), (1e5, 0.05), (1e6, 0.4)] {
        let at = DVec3::new(offset, 0.25 * offset, -0.5 * offset);
        check(
            &format!("ground 10 across at {at}"),
            &ground_with_box(10.0, at, lights(10.0, at)),
            true,
            max_band,
        );
    }
    for scale in [1e-3, 1e3] {
        let size = 10.0 * scale;
        check(
            &format!("ground {size} across"),
            &ground_with_box(size, DVec3::ZERO, lights(size, DVec3::ZERO)),
            true,
            0.002,
        );
    }
}

#[test]
fn a_plane_lit_at_89_99_degrees() {
    let lights = vec![
        directional("grazing", 0.01, 10.0),
        spot("grazing_spot", DVec3::ZERO, 20.0, 0.01, 10.0, 0.1, 60.0),
    ];
    let objects = json!([
        { "name": "ground", "shape": { "type": "plane", "size": [20, 20] } },
        { "name": "wall", "shape": { "type": "box", "size": [0.2, 0.5, 3] }, "closed": true, "transform": { "translate": [2, 0.25, 0] } }
    ]);
    let s = scene(
        "grazing",
        objects,
        vec![camera("main", DVec3::new(-6.0, 5.0, 7.0), DVec3::ZERO, 96, 72)],
        lights,
    );
    check("plane lit at 89.99°", &s, true, 0.01);
}

#[test]
fn sliver_triangles_of_aspect_ratio_1e4() {
    // A 10 × 10 ground cut into strips 1e-3 wide, each two triangles 1e4 times longer than wide,
    // and a box of slivers over it.
    let mut s = scene(
        "slivers",
        json!([{ "name": "placeholder", "shape": { "type": "box", "size": [1, 1, 1] } }]),
        vec![camera("main", DVec3::new(-4.0, 6.0, 7.0), DVec3::ZERO, 96, 72)],
        vec![directional("sun", 50.0, 30.0), spot("spot", DVec3::ZERO, 8.0, 40.0, -60.0, 0.5, 30.0)],
    );
    s.objects.clear();
    s.flat_triangles.clear();
    s.flat_triangle_object.clear();
    let w = 1e-3f32;
    let strips = 1000;
    let mut ground = Vec::new();
    for k in 0..strips {
        let x0 = -0.5 + k as f32 * w;
        let (a, b, c, d) =
            (vec3(x0, 0.0, -5.0), vec3(x0 + w, 0.0, -5.0), vec3(x0, 0.0, 5.0), vec3(x0 + w, 0.0, 5.0));
        ground.push([a, c, d]);
        ground.push([a, d, b]);
    }
    // The rest of the ground, plain, either side of the strips.
    for (x0, x1) in [(-5.0f32, -0.5f32), (0.5, 5.0)] {
        let (a, b, c, d) = (vec3(x0, 0.0, -5.0), vec3(x1, 0.0, -5.0), vec3(x0, 0.0, 5.0), vec3(x1, 0.0, 5.0));
        ground.push([a, c, d]);
        ground.push([a, d, b]);
    }
    append(&mut s, "ground", ground, false);
    // A horizontal sliver fan 1 above the ground: a 2 × 2 square cut into 1e4:1 triangles.
    let mut roof = Vec::new();
    for k in 0..2000 {
        let z0 = -1.0 + k as f32 * w;
        let (a, b, c, d) =
            (vec3(-1.0, 1.0, z0), vec3(1.0, 1.0, z0), vec3(-1.0, 1.0, z0 + w), vec3(1.0, 1.0, z0 + w));
        roof.push([a, c, d]);
        roof.push([a, d, b]);
    }
    append(&mut s, "roof", roof, false);
    check("sliver triangles", &s, true, 0.015);
}

#[test]
fn closed_meshes_with_shared_edges_have_no_cracks() {
    // Rays through a tessellated sphere's shared edges and vertices must hit it: every pixel
    // whose segment passes inside the sphere's inscribed ball is shadowed (an analytic check
    // the band cannot excuse), and the adjudicator finds no other disagreement.
    let (centre, radius) = (DVec3::new(0.0, 1.5, 0.0), 1.0);
    let objects = json!([
        { "name": "ground", "shape": { "type": "plane", "size": [12, 12] } },
        { "name": "ball", "shape": { "type": "sphere", "radius": radius, "segments": 24, "rings": 12 }, "closed": true,
          "transform": { "translate": centre.to_array() } }
    ]);
    let lights = vec![directional("sun", 70.0, 20.0), spot("spot", DVec3::ZERO, 6.0, 75.0, 20.0, 0.5, 20.0)];
    let s = scene(
        "ball",
        objects,
        vec![camera("main", DVec3::new(-3.0, 6.0, 5.0), DVec3::new(0.3, 0.0, 0.0), 128, 96)],
        lights,
    );
    check("closed sphere", &s, true, 0.002);
    let ball = &s.objects[1];
    let inscribed = s.flat_triangles
        [ball.first_triangle as usize..(ball.first_triangle + ball.triangle_count) as usize]
        .iter()
        .map(|t| {
            let (a, b, c) = (t[0].as_dvec3(), t[1].as_dvec3(), t[2].as_dvec3());
            (centre - a).dot((b - a).cross(c - a).normalize()).abs()
        })
        .fold(f64::INFINITY, f64::min);
    assert!(inscribed > 0.9 * radius);
    let bvh = SceneBvh::build(&s);
    let mut through_ball = 0;
    for light in &s.lights {
        let g = GBuffer::trace(&bvh, &s.cameras[0], light);
        let r = trace_hard_reference(&s, &bvh, &g, light);
        for &i in &g.evaluated {
            let i = i as usize;
            if g.object(&s, i) != 0 {
                continue;
            }
            let p = g.position[i].as_dvec3();
            let (dir, length) = match &light.kind {
                shadowtruth::scene::LightKind::Directional { direction, .. } => {
                    (-direction.as_dvec3().normalize(), f64::INFINITY)
                }
                shadowtruth::scene::LightKind::Spot { position, .. }
                | shadowtruth::scene::LightKind::Point { position, .. } => {
                    let d = position.as_dvec3() - p;
                    (d.normalize(), d.length())
                }
            };
            let along = (centre - p).dot(dir).clamp(0.0, length);
            if (p + dir * along - centre).length() < 0.999 * inscribed {
                through_ball += 1;
                assert_eq!(
                    r.lit[i], 0,
                    "light {}: pixel {i}'s segment passes through the ball but is lit",
                    light.name
                );
            }
        }
    }
    assert!(through_ball > 500, "only {through_ball} segments pass through the ball");
}

#[test]
fn coplanar_overlapping_surfaces_do_not_shadow_each_other() {
    // A ground plane and a rotated decal in exactly the same plane, and a second pair of
    // coplanar quads on a tilted wall: each surface is seen through the other's triangles.
    let objects = json!([
        { "name": "ground", "shape": { "type": "plane", "size": [10, 10], "subdivisions": 3 } },
        { "name": "decal", "shape": { "type": "plane", "size": [4, 4], "subdivisions": 2 }, "transform": { "rotate_deg": [0, 30, 0] } },
        { "name": "ramp", "shape": { "type": "plane", "size": [3, 3] }, "transform": { "rotate_deg": [20, 0, 0], "translate": [2, 1, -2] } },
        { "name": "ramp_decal", "shape": { "type": "plane", "size": [2, 2] }, "transform": { "rotate_deg": [20, 45, 0], "translate": [2, 1, -2] } },
        { "name": "post", "shape": { "type": "box", "size": [0.3, 2, 0.3] }, "closed": true, "transform": { "translate": [-1, 1, 1] } }
    ]);
    let lights = vec![directional("sun", 40.0, 30.0), spot("spot", DVec3::ZERO, 7.0, 45.0, 60.0, 0.5, 25.0)];
    let s = scene(
        "coplanar",
        objects,
        vec![camera("main", DVec3::new(-4.0, 5.0, 6.0), DVec3::ZERO, 128, 96)],
        lights,
    );
    check("coplanar overlapping surfaces", &s, true, 0.002);
}

#[test]
fn a_thin_occluder_just_above_its_receiver() {
    // A slab 1e-4 thick whose underside lies 1e-4 above the ground, seen from 7 mm away at its
    // edge: under a light 10° up, its shadow is a strip about 6e-4 wide beside the edge.
    let objects = json!([
        { "name": "ground", "shape": { "type": "plane", "size": [6, 6] } },
        { "name": "slab", "shape": { "type": "box", "size": [1, 0.0001, 1] }, "closed": true,
          "transform": { "translate": [0, 0.00015, 0] } }
    ]);
    let lights =
        vec![directional("sun", 10.0, -80.0), spot("spot", DVec3::ZERO, 3.0, 10.0, -100.0, 0.2, 10.0)];
    let edge = DVec3::new(0.1, 0.0, 0.5006);
    let eye = edge + DVec3::new(0.0, 0.004, 0.006);
    let s = scene("thin", objects, vec![camera("main", eye, edge, 128, 96)], lights);
    check("thin occluder 1e-4 above its receiver", &s, true, 0.03);
}

#[test]
fn a_spot_light_just_above_a_surface() {
    let objects = json!([
        { "name": "ground", "shape": { "type": "plane", "size": [10, 10] } },
        { "name": "stone", "shape": { "type": "box", "size": [0.5, 0.3, 0.5] }, "closed": true, "transform": { "translate": [1.5, 0.15, 0.5] } }
    ]);
    let lights =
        vec![json!({ "name": "low", "type": "spot", "position": [0, 0.001, 0], "direction": [1, -0.05, 0.2],
                               "cone_deg": 150, "near": 0.0001, "far": 20 })];
    let s = scene(
        "low_spot",
        objects,
        vec![camera("main", DVec3::new(-2.0, 3.0, 3.0), DVec3::new(2.0, 0.0, 0.0), 128, 96)],
        lights,
    );
    check("spot light 1e-3 above the ground", &s, true, 0.002);
}

#[test]
fn soft_references_show_no_self_shadow_speckle_on_a_large_plane() {
    // The sea alone, 800 across, under an area spot light and a sun with an angular size: every
    // light sample of every pixel is unoccluded, so every pixel must be exactly 1.
    let lights = vec![
        {
            let mut l = spot("spot", DVec3::ZERO, 150.0, 14.0, 0.0, 20.0, 400.0);
            l["radius"] = json!(2.0);
            l
        },
        {
            let mut l = directional("sun", 14.0, 0.0);
            l["angular_diameter_deg"] = json!(2.0);
            l
        },
    ];
    let cameras = vec![camera("main", DVec3::new(-60.0, 40.0, 140.0), DVec3::ZERO, 96, 72)];
    let s = scene(
        "sea",
        json!([{ "name": "sea", "shape": { "type": "plane", "size": [800, 800] } }]),
        cameras,
        lights,
    );
    // A second, coplanar sea with other triangles: the case where the tracer tests the sea.
    let mut s = s;
    let h = 400.0f32;
    append(&mut s, "sea_overlay", vec![[vec3(-h, 0.0, -h), vec3(-h, 0.0, h), vec3(h, 0.0, 0.0)]], false);
    let bvh = SceneBvh::build(&s);
    for light in &s.lights {
        let g = GBuffer::trace(&bvh, &s.cameras[0], light);
        assert!(g.evaluated.len() > 3000);
        let area = trace_area_light_reference(&s, &bvh, &g, light, 4).unwrap();
        // Sub-pixel samples past a spot light's cone count as shadowed: coverage under the sun.
        let coverage =
            light.is_directional().then(|| trace_coverage_reference(&s, &bvh, &g, &s.cameras[0], light, 3));
        for &i in &g.evaluated {
            let i = i as usize;
            assert_eq!(g.class[i], PixelClass::Evaluated);
            assert_eq!(area.visibility[i], 1.0, "light {}: area-light speckle at pixel {i}", light.name);
            if let Some(c) = &coverage {
                assert_eq!(c.visibility[i], 1.0, "light {}: coverage speckle at pixel {i}", light.name);
            }
        }
    }
}
