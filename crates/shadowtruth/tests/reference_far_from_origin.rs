//! The hard cases far from the origin: the island's terrain and thin trees, exactly coplanar quads
//! (two triangles sharing an edge, and a decal overlapping them), a sun a few degrees above the
//! ground, spot lights, and a fold with a spot light exactly in one face's plane, each moved 10³,
//! 10⁴, 10⁵ and 10⁶ units along a fixed direction that is no axis. Every pixel of every view is checked against the exact adjudicator
//! (`shadowtruth::verify`), on one thread and on two: no disagreement may lie on a pixel the
//! tracer did not flag, the two references must be identical, and the flagged pixels may be at
//! most 0.01 % of the evaluated ones. A flat quad with nothing above it must be lit everywhere.
//!
//! Far out, an f32 coordinate is coarse (2⁻²⁴ of 10⁶ is 0.06 units), and a surface point
//! rounded to f32 lies off its own tilted triangle: the neighbour across a shared edge, or a
//! coplanar decal, is then "above" it. The scenes are moved the way `scripts/move_scene.py`
//! moves them, by whole units added to each object's translation in f64, so the quads' lattice
//! vertices stay exact and every other vertex is rounded to f32 once.

mod common;

use common::repo;
use glam::DVec3;
use serde_json::{Value, json};
use shadowtruth::scene::{Scene, load_scene_str};
use shadowtruth::trace::{GBuffer, PixelClass, SceneBvh, trace_hard_reference};
use shadowtruth::verify::{Adjudicator, PixelSelection, verify_view};
use std::path::{Path, PathBuf};

/// How far out each case is placed.
const DISTANCES: [f64; 4] = [1e3, 1e4, 1e5, 1e6];

/// The direction the scenes move along (normalized), as in `scripts/move_scene.py`.
const DIRECTION: DVec3 = DVec3::new(0.6, 0.3, -0.74);

/// The offset `distance` along `DIRECTION`, in whole units.
fn offset(distance: f64) -> DVec3 {
    (DIRECTION.normalize() * distance).round()
}

fn shifted(v: &Value, o: DVec3) -> Value {
    let a: Vec<f64> = v.as_array().expect("a vector").iter().map(|c| c.as_f64().expect("a number")).collect();
    json!([a[0] + o.x, a[1] + o.y, a[2] + o.z])
}

/// The scene moved by `o`: each object's translation (or each instance's), the cameras'
/// positions and targets and the spot lights' positions; directions unchanged.
fn moved(scene: &Value, o: DVec3) -> Value {
    let mut s = scene.clone();
    for object in s["objects"].as_array_mut().unwrap() {
        let transforms: Vec<&mut Value> = match object.get_mut("instances") {
            Some(instances) => instances.as_array_mut().unwrap().iter_mut().collect(),
            None => vec![object.as_object_mut().unwrap().entry("transform").or_insert(json!({}))],
        };
        for t in transforms {
            let translate = t.get("translate").cloned().unwrap_or(json!([0.0, 0.0, 0.0]));
            t["translate"] = shifted(&translate, o);
        }
    }
    for camera in s["cameras"].as_array_mut().unwrap() {
        for field in ["position", "look_at"] {
            camera[field] = shifted(&camera[field], o);
        }
    }
    for light in s["lights"].as_array_mut().unwrap() {
        if light.get("position").is_some() {
            light["position"] = shifted(&light["position"], o);
        }
    }
    s
}

fn scene_file(path: &Path) -> Value {
    serde_json::from_str(&std::fs::read_to_string(path).unwrap()).unwrap()
}

/// Loads `json` (edited near the origin) moved by `o`, its meshes read from `folder`.
fn load(json: &Value, o: DVec3, folder: &Path) -> Scene {
    let text = serde_json::to_string(&moved(json, o)).unwrap();
    load_scene_str(&text, &folder.join("moved.json"), folder).unwrap_or_else(|e| panic!("{e}"))
}

fn island_folder() -> PathBuf {
    repo().join("scenes/papers")
}

fn far_folder() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/far")
}

/// The island (scenes/papers/island.json): a heightfield terrain of 18 432 triangles, 32 trunks
/// about 0.05 units thick under cone and sphere crowns, in a flat sea; both cameras at 96 × 72.
fn island(lights: Option<Value>) -> Value {
    let mut s = scene_file(&island_folder().join("island.json"));
    for camera in s["cameras"].as_array_mut().unwrap() {
        camera["width"] = json!(96);
        camera["height"] = json!(72);
    }
    if let Some(lights) = lights {
        s["lights"] = lights;
    }
    s
}

/// tests/far/coplanar_quad.json: a flat 20 × 10 quad of two triangles in the tilted plane
/// y = x/8 + z/16, a decal of two triangles exactly in that plane across the quad's shared
/// edge, and a box floating over them; only the lights named in `lights` are kept.
fn coplanar_quad(with_box: bool, lights: &[&str]) -> Value {
    let mut s = scene_file(&far_folder().join("coplanar_quad.json"));
    if !with_box {
        s["objects"].as_array_mut().unwrap().retain(|o| o["name"] != "box");
    }
    s["lights"].as_array_mut().unwrap().retain(|l| lights.contains(&l["name"].as_str().unwrap()));
    s
}

fn directional(name: &str, elevation_deg: f64, azimuth_deg: f64) -> Value {
    let (e, a) = (elevation_deg.to_radians(), azimuth_deg.to_radians());
    let towards_light = DVec3::new(e.cos() * a.cos(), e.sin(), e.cos() * a.sin());
    json!({ "name": name, "type": "directional", "direction": (-towards_light).to_array() })
}

fn with_threads<T: Send>(n: usize, f: impl FnOnce() -> T + Send) -> T {
    rayon::ThreadPoolBuilder::new().num_threads(n).build().unwrap().install(f)
}

/// What one (camera, light) of one case traced: compared between thread counts.
#[derive(PartialEq, Debug)]
struct Traced {
    class: Vec<PixelClass>,
    triangle: Vec<u32>,
    barycentric: Vec<[u32; 2]>,
    lit: Vec<u8>,
    uncertain: Vec<u32>,
}

/// The counts of one case at one distance, over its views.
#[derive(Default, Debug)]
struct Tally {
    /// Pixels with a surface point the reference is about: evaluated, or flagged at the primary.
    evaluated: usize,
    /// Flagged pixels: shadow answers (`HardReference::uncertain`) and primary hits
    /// (`PixelClass::Uncertain`).
    flagged: usize,
    /// Of those, the primary hits.
    primary_flagged: usize,
    /// Unflagged evaluated pixels lit and shadowed.
    lit: usize,
    shadowed: usize,
    /// Disagreements with the exact answer on flagged pixels (allowed).
    in_band: usize,
    /// The first few of them, for the failure message.
    in_band_cases: Vec<String>,
}

/// The flagged pixels allowed, as a fraction of the evaluated ones: 0.01 % up to 10⁵ units out,
/// 0.1 % at 10⁶ (docs/reference.md, "Far from the origin").
fn allowed_fraction(distance: f64) -> f64 {
    if distance <= 1e5 { 1e-4 } else { 1e-3 }
}

impl Tally {
    /// `allowed_fraction` of the evaluated pixels, and at least one.
    fn band_bound(&self, distance: f64) -> usize {
        ((self.evaluated as f64 * allowed_fraction(distance)) as usize).max(1)
    }
}

/// Checks every pixel of every (camera, light) of `scene` on one and on two threads.
fn check(case: &str, scene: &Scene, distance: f64) -> Tally {
    let bvh = SceneBvh::build(scene);
    let adjudicator = Adjudicator::new(scene);
    let mut tally = Tally::default();
    for camera in &scene.cameras {
        for light in &scene.lights {
            let what = format!("{case}, camera {}, light {}", camera.name, light.name);
            let trace = || {
                let g = GBuffer::trace(&bvh, camera, light);
                let r = trace_hard_reference(scene, &bvh, &g, light);
                let traced = Traced {
                    class: g.class.clone(),
                    triangle: g.triangle.clone(),
                    barycentric: g.barycentric.iter().map(|b| b.map(f32::to_bits)).collect(),
                    lit: r.lit.clone(),
                    uncertain: r.uncertain.clone(),
                };
                (g, traced)
            };
            let (g, one) = with_threads(1, trace);
            let (_, two) = with_threads(2, trace);
            assert!(one == two, "{what}: the references on one and on two threads differ");
            for threads in [1, 2] {
                let v = with_threads(threads, || {
                    verify_view(scene, &bvh, &adjudicator, camera, light, PixelSelection::All)
                });
                assert_eq!(
                    (v.disagree_outside_band, v.primary_disagree_outside_band),
                    (0, 0),
                    "{what}, {threads} thread(s): {} shadow and {} primary disagreements with the exact \
                     answer on pixels the tracer did not flag ({} evaluated, {} flagged): {:#?}",
                    v.disagree_outside_band,
                    v.primary_disagree_outside_band,
                    v.evaluated,
                    v.uncertain,
                    v.cases
                );
                assert_eq!(v.primary_checked, g.pixel_count(), "{what}: every primary ray is checked");
                let with_point = g
                    .class
                    .iter()
                    .zip(&g.triangle)
                    .filter(|&(&c, &t)| c == PixelClass::Uncertain && t != u32::MAX)
                    .count();
                assert_eq!(
                    v.checked,
                    v.evaluated + with_point,
                    "{what}: every pixel with a point is checked"
                );
                if threads == 1 {
                    tally.in_band += v.disagree_in_band + v.primary_disagree_in_band;
                    for c in v.cases.iter().filter(|c| c.in_band).take(4) {
                        tally.in_band_cases.push(format!(
                            "{}/{} ({}, {}): {:?}",
                            camera.name, light.name, c.x, c.y, c.disagreement
                        ));
                    }
                }
            }
            let primary_flagged = g.count(PixelClass::Uncertain);
            let mut flagged = vec![false; g.pixel_count()];
            for &i in &one.uncertain {
                flagged[i as usize] = true;
            }
            tally.evaluated += g.evaluated.len() + primary_flagged;
            tally.flagged += one.uncertain.len() + primary_flagged;
            tally.primary_flagged += primary_flagged;
            for &i in &g.evaluated {
                match (flagged[i as usize], one.lit[i as usize] != 0) {
                    (true, _) => {}
                    (false, true) => tally.lit += 1,
                    (false, false) => tally.shadowed += 1,
                }
            }
        }
    }
    println!(
        "{case}: {} evaluated, {} flagged ({} at the primary hit; at most {} allowed), {} lit, {} shadowed, \
         {} disagreements inside the band",
        tally.evaluated,
        tally.flagged,
        tally.primary_flagged,
        tally.band_bound(distance),
        tally.lit,
        tally.shadowed,
        tally.in_band
    );
    assert!(tally.evaluated > 2000, "{case}: only {} evaluated pixels", tally.evaluated);
    assert!(tally.lit > 0, "{case}: no lit pixel");
    assert!(
        tally.flagged <= tally.band_bound(distance),
        "{case}: {} of {} evaluated pixels flagged uncertain ({} at the primary hit), more than {} % (at most {}); the disagreements among them: {:#?}",
        tally.flagged,
        tally.evaluated,
        tally.primary_flagged,
        100.0 * allowed_fraction(distance),
        tally.band_bound(distance),
        tally.in_band_cases
    );
    tally
}

#[test]
fn terrain_with_thin_trees_far_from_the_origin() {
    let json = island(Some(json!([directional("sun", 35.0, -30.0)])));
    for distance in DISTANCES {
        let s = load(&json, offset(distance), &island_folder());
        let t = check(&format!("island under a sun at 35°, {distance:e} out"), &s, distance);
        assert!(t.shadowed > 100, "the terrain and trees cast shadows ({} shadowed pixels)", t.shadowed);
    }
}

#[test]
fn coplanar_quads_far_from_the_origin() {
    let with_box = coplanar_quad(true, &["sun"]);
    let without_box = coplanar_quad(false, &["sun", "grazing_sun", "spot"]);
    for distance in DISTANCES {
        let o = offset(distance);
        let t = check(
            &format!("coplanar quads and a box, sun at 40°, {distance:e} out"),
            &load(&with_box, o, &far_folder()),
            distance,
        );
        assert!(t.shadowed > 100, "the box casts a shadow ({} shadowed pixels)", t.shadowed);
        // Nothing above the quad and its decal: no surface may be shadowed by its neighbour
        // across the shared edge, nor by the coplanar surface over it, flagged pixels included.
        let s = load(&without_box, o, &far_folder());
        let case = format!("coplanar quads alone, {distance:e} out");
        check(&case, &s, distance);
        let bvh = SceneBvh::build(&s);
        for camera in &s.cameras {
            for light in &s.lights {
                let g = GBuffer::trace(&bvh, camera, light);
                let r = trace_hard_reference(&s, &bvh, &g, light);
                let shadowed: Vec<u32> =
                    g.evaluated.iter().copied().filter(|&i| r.lit[i as usize] == 0).collect();
                let flagged = shadowed.iter().filter(|i| r.uncertain.binary_search(i).is_ok()).count();
                assert!(
                    shadowed.is_empty(),
                    "{case}, camera {}, light {}: {} of {} evaluated pixels shadowed ({flagged} of them flagged), \
                     the first {:?}",
                    camera.name,
                    light.name,
                    shadowed.len(),
                    g.evaluated.len(),
                    &shadowed[..shadowed.len().min(8)]
                );
            }
        }
    }
}

#[test]
fn a_grazing_sun_far_from_the_origin() {
    // 3° above the sea and the terrain's foot, and 3° above the tilted quad's plane.
    let island_json = island(Some(json!([directional("grazing_sun", 3.0, 160.0)])));
    let quad_json = coplanar_quad(true, &["grazing_sun"]);
    for distance in DISTANCES {
        let o = offset(distance);
        let t = check(
            &format!("island under a sun at 3°, {distance:e} out"),
            &load(&island_json, o, &island_folder()),
            distance,
        );
        assert!(t.shadowed > 100, "the hills' long shadows ({} shadowed pixels)", t.shadowed);
        check(
            &format!("coplanar quads under a sun 3° above them, {distance:e} out"),
            &load(&quad_json, o, &far_folder()),
            distance,
        );
    }
}

#[test]
fn spot_lights_far_from_the_origin() {
    // The island's own spot light, 13 units from the island, and a spot 9 above the quad.
    let island_json = island(None);
    let quad_json = coplanar_quad(true, &["spot"]);
    for distance in DISTANCES {
        let o = offset(distance);
        let t = check(
            &format!("island under its spot light, {distance:e} out"),
            &load(&island_json, o, &island_folder()),
            distance,
        );
        assert!(t.shadowed > 100, "the trees' shadows ({} shadowed pixels)", t.shadowed);
        let t = check(
            &format!("coplanar quads under a spot light, {distance:e} out"),
            &load(&quad_json, o, &far_folder()),
            distance,
        );
        assert!(t.shadowed > 100, "the box casts a shadow ({} shadowed pixels)", t.shadowed);
    }
}

#[test]
fn a_light_exactly_in_a_surface_plane_far_from_the_origin() {
    // The island 10⁵ out had a terrain triangle whose plane held its spot light exactly. The
    // segment from any of its points then runs inside the plane to the neighbour's edge, which
    // no precision can decide; the definition makes such a surface face away (N·L = 0).
    let json = json!({
        "format": "shadowtruth/scene/v1",
        "name": "fold",
        "objects": [{ "name": "fold", "mesh": "fold.obj", "closed": false }],
        "cameras": [{ "name": "above", "position": [-6, 8, -6], "look_at": [4, 0.8, 4], "fov_y_deg": 50,
                      "width": 96, "height": 72 }],
        "lights": [{ "name": "in_plane", "type": "spot", "position": [16, 3, 16], "direction": [-1, -0.15, -1],
                     "cone_deg": 120, "near": 0.5, "far": 60 }]
    });
    for distance in [0.0].into_iter().chain(DISTANCES) {
        let s = load(&json, offset(distance), &far_folder());
        let (camera, light) = (&s.cameras[0], &s.lights[0]);
        let bvh = SceneBvh::build(&s);
        let g = GBuffer::trace(&bvh, camera, light);
        let r = trace_hard_reference(&s, &bvh, &g, light);
        let on_plane: Vec<PixelClass> =
            (0..g.pixel_count()).filter(|&i| g.triangle[i] == 0).map(|i| g.class[i]).collect();
        let facing = on_plane.iter().filter(|&&c| c != PixelClass::FacingAway).count();
        assert!(
            on_plane.len() > 500,
            "{distance:e} out: only {} pixels see the first triangle",
            on_plane.len()
        );
        assert_eq!(
            facing,
            0,
            "{distance:e} out: {facing} of {} pixels in the light's plane face it",
            on_plane.len()
        );
        assert!(g.evaluated.len() > 100, "{distance:e} out: {} pixels face the light", g.evaluated.len());
        assert_eq!(
            (r.uncertain.len(), g.count(PixelClass::Uncertain)),
            (0, 0),
            "{distance:e} out: flagged pixels"
        );
        let v = verify_view(&s, &bvh, &Adjudicator::new(&s), camera, light, PixelSelection::All);
        assert_eq!(v.cases, vec![], "{distance:e} out");
    }
}
