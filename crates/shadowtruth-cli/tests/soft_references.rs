//! The soft references (pixel coverage, area light): analytic penumbrae and shadow-area fractions,
//! standard errors, determinism across thread counts, the cache round trip and bad input.

#[path = "../../shadowtruth/tests/common/mod.rs"]
mod common;

use common::{bundled, near_boundary, scene_from_json};
use shadowtruth::scene::{Camera, Light, LightKind, Scene};
use shadowtruth::trace::{
    AreaLightError, GBuffer, PixelClass, ReferenceCache, SceneBvh, SoftReference, trace_area_light_reference,
    trace_coverage_reference, trace_hard_reference, trace_scored_view,
};

/// Height of the slab's edge above the ground.
const SLAB_HEIGHT: f64 = 3.0;

/// A ground plane and, `SLAB_HEIGHT` above it, a zero-thickness 20×20 slab covering x ≤ 0 whose
/// only nearby edge is the line x = 0; the light shines straight down. The camera sits below the
/// slab, looking obliquely at the ground around the edge's shadow (so the shadow line crosses
/// pixels at every offset), and every pixel shows ground.
fn slab_scene(angular_diameter_deg: Option<f64>) -> Scene {
    let mut light = serde_json::json!({ "name": "sun", "type": "directional", "direction": [0, -1, 0] });
    if let Some(a) = angular_diameter_deg {
        light["angular_diameter_deg"] = serde_json::json!(a);
    }
    scene_from_json(&serde_json::json!({
        "format": "shadowtruth/scene/v1", "name": "slab",
        "objects": [
            { "name": "ground", "shape": { "type": "plane", "size": [40, 40] } },
            { "name": "slab", "shape": { "type": "plane", "size": [20, 20] },
              "transform": { "translate": [-10, SLAB_HEIGHT, 0] } }
        ],
        "cameras": [{ "name": "c", "position": [1.2, 1.0, 0.5], "look_at": [0.1, 0, 0.05], "fov_y_deg": 40,
                      "width": 160, "height": 120 }],
        "lights": [light]
    }))
}

/// The lit fraction of a receiver on the ground at signed horizontal distance `x` from the
/// slab edge's hard shadow line (x > 0 on the lit side), under a sun of angular radius `theta`.
///
/// The plane through the receiver and the straight edge (height h above it) is a great circle
/// whose angular distance from the sun's centre (straight up) is β = atan(x/h): directions on the
/// slab's side of it are blocked. For a small sun the disk of angular radius θ is flat to O(θ²)
/// and the great circle a straight chord at normalized offset s = β/θ. The lit part is the disk
/// minus the circular segment beyond the chord on the slab's side; a segment at distance s from
/// the centre of a unit disk has area acos(s) − s√(1 − s²), so
///
///   lit(s) = 1 − (acos(s) − s·√(1 − s²)) / π   for |s| < 1, 0 below, 1 above
///
/// (lit(0) = ½, lit(±1) = 1 or 0). With θ = 2° the spherical correction is below 1e-3.
fn analytic_lit_fraction(x: f64, theta: f64) -> f64 {
    let s = (x / SLAB_HEIGHT).atan() / theta;
    if s >= 1.0 {
        1.0
    } else if s <= -1.0 {
        0.0
    } else {
        1.0 - (s.acos() - s * (1.0 - s * s).sqrt()) / std::f64::consts::PI
    }
}

fn slab_trace() -> (Scene, SceneBvh, GBuffer) {
    let scene = slab_scene(Some(4.0));
    let bvh = SceneBvh::build(&scene);
    let g = GBuffer::trace(&bvh, &scene.cameras[0], &scene.lights[0]);
    (scene, bvh, g)
}

/// (pixel, analytic lit fraction) of the evaluated pixels whose lit fraction lies in `range`.
fn penumbra_pixels(g: &GBuffer, range: std::ops::RangeInclusive<f64>) -> Vec<(usize, f64)> {
    let theta = 2f64.to_radians();
    g.evaluated
        .iter()
        .map(|&i| (i as usize, analytic_lit_fraction(g.position[i as usize].x as f64, theta)))
        .filter(|(_, f)| range.contains(f))
        .collect()
}

#[test]
fn area_light_penumbra_converges_to_the_circular_segment() {
    let (scene, bvh, g) = slab_trace();
    assert_eq!(g.evaluated.len(), g.pixel_count(), "every pixel shows lit-facing ground");
    // Every pixel strictly inside the penumbra, plus a band of fully lit and fully shadowed ones.
    let theta = 2f64.to_radians();
    let band = SLAB_HEIGHT * (1.5 * theta).tan();
    let pixels: Vec<(usize, f64)> = g
        .evaluated
        .iter()
        .map(|&i| i as usize)
        .filter(|&i| (g.position[i].x as f64).abs() < band)
        .map(|i| (i, analytic_lit_fraction(g.position[i].x as f64, theta)))
        .collect();
    let inside = pixels.iter().filter(|(_, f)| *f > 0.0 && *f < 1.0).count();
    assert!(inside > 1000, "the penumbra covers {inside} pixels");
    let mut errors = Vec::new();
    for grid in [4, 16, 32] {
        let r = trace_area_light_reference(&scene, &bvh, &g, &scene.lights[0], grid).unwrap();
        let mae = pixels.iter().map(|&(i, f)| (r.visibility[i] as f64 - f).abs()).sum::<f64>()
            / pixels.len() as f64;
        println!("area light {grid}×{grid}: mean |error| {mae:.5} over {} pixels", pixels.len());
        errors.push(mae);
    }
    assert!(
        errors[1] < 0.5 * errors[0] && errors[2] < 0.7 * errors[1],
        "errors fall with samples: {errors:?}"
    );
    assert!(errors[2] < 2e-3, "32×32 samples: mean |error| {}", errors[2]);
}

#[test]
fn area_light_standard_error_falls_as_one_over_root_samples() {
    let (scene, bvh, g) = slab_trace();
    let pixels = penumbra_pixels(&g, 0.2..=0.8);
    assert!(pixels.len() > 500, "{} penumbra pixels", pixels.len());
    let median_error = |grid: u32| {
        let r = trace_area_light_reference(&scene, &bvh, &g, &scene.lights[0], grid).unwrap();
        let mut e: Vec<f32> = pixels.iter().map(|&(i, _)| r.std_error[i]).collect();
        e.sort_by(f32::total_cmp);
        e[e.len() / 2] as f64
    };
    let (n, n4) = (median_error(8), median_error(16));
    let ratio = n / n4;
    println!("median standard error: 8×8 {n:.5}, 16×16 {n4:.5}, ratio {ratio:.3}");
    assert!((ratio - 2.0).abs() < 0.3, "4× the samples should halve the standard error: ratio {ratio}");
    // Lit and shadowed pixels far from the penumbra have no spread.
    let r = trace_area_light_reference(&scene, &bvh, &g, &scene.lights[0], 8).unwrap();
    for (i, f) in penumbra_pixels(&g, 0.0..=1.0) {
        if f == 0.0 || f == 1.0 {
            assert_eq!((r.visibility[i] as f64, r.std_error[i]), (f, 0.0), "pixel {i}");
        }
    }
}

/// Image position (pixels from the top-left corner) of world point `p`, inverting the camera's
/// ray formula (docs/conventions.md, "Camera").
fn project(camera: &Camera, p: glam::DVec3) -> (f64, f64) {
    let (r, u, f) = camera.basis();
    let v = p - camera.position.as_dvec3();
    let (w, h) = (camera.width as f64, camera.height as f64);
    let t = (camera.fov_y_deg as f64).to_radians().mul_add(0.5, 0.0).tan();
    let (sx, sy) = (v.dot(r) / v.dot(f), v.dot(u) / v.dot(f));
    ((sx / (t * w / h) + 1.0) * 0.5 * w, (1.0 - sy / t) * 0.5 * h)
}

/// Area of the unit pixel square at (x, y) on the side `a·q ≤ c` of a line (Sutherland–Hodgman
/// clipping of the square by one half-plane, then the shoelace formula).
fn pixel_fraction_below(x: f64, y: f64, a: (f64, f64), c: f64) -> f64 {
    let square = [(x, y), (x + 1.0, y), (x + 1.0, y + 1.0), (x, y + 1.0)];
    let side = |q: (f64, f64)| a.0 * q.0 + a.1 * q.1 - c;
    let mut poly = Vec::new();
    for k in 0..4 {
        let (p, q) = (square[k], square[(k + 1) % 4]);
        let (sp, sq) = (side(p), side(q));
        if sp <= 0.0 {
            poly.push(p);
        }
        if (sp < 0.0) != (sq < 0.0) && sp != sq {
            let t = sp / (sp - sq);
            poly.push((p.0 + t * (q.0 - p.0), p.1 + t * (q.1 - p.1)));
        }
    }
    let n = poly.len();
    (0..n).map(|k| poly[k].0 * poly[(k + 1) % n].1 - poly[(k + 1) % n].0 * poly[k].1).sum::<f64>().abs() * 0.5
}

#[test]
fn coverage_is_hard_away_from_boundaries_and_the_shadow_area_fraction_across_them() {
    let scene = slab_scene(None);
    let (camera, light) = (&scene.cameras[0], &scene.lights[0]);
    let bvh = SceneBvh::build(&scene);
    let g = GBuffer::trace(&bvh, camera, light);
    let hard = trace_hard_reference(&scene, &bvh, &g, light);
    // A 1×1 grid is the pixel-centre ray: the hard reference, bit for bit.
    let one = trace_coverage_reference(&scene, &bvh, &g, camera, light, 1);
    assert!(one.visibility.iter().zip(&hard.lit).all(|(&v, &l)| v.to_bits() == (l as f32).to_bits()));

    let grid = 8;
    let cov = trace_coverage_reference(&scene, &bvh, &g, camera, light, grid);
    assert_eq!(cov.samples, 64);
    let boundary = near_boundary(g.width, g.height, &hard.mask_codes(&g));
    // Away from the shadow edge every sub-pixel agrees with the centre.
    let mut far = 0;
    for (i, &near) in boundary.iter().enumerate() {
        if !near {
            assert_eq!(cov.visibility[i], hard.lit[i] as f32, "pixel {i}");
            assert_eq!(cov.std_error[i], 0.0, "pixel {i}");
            far += 1;
        }
    }
    assert!(far > g.pixel_count() / 2);

    // The shadow edge x = 0 on the ground is a straight line in the image; the exact shadowed
    // fraction of each pixel is the part of its square on the shadow side.
    let (p0, p1) =
        (project(camera, glam::dvec3(0.0, 0.0, -1.0)), project(camera, glam::dvec3(0.0, 0.0, 1.0)));
    let normal = (p1.1 - p0.1, p0.0 - p1.0);
    let mut c = normal.0 * p0.0 + normal.1 * p0.1;
    let mut a = normal;
    let inside = project(camera, glam::dvec3(-1.0, 0.0, 0.0));
    if a.0 * inside.0 + a.1 * inside.1 > c {
        (a, c) = ((-a.0, -a.1), -c);
    }
    let (mut straddling, mut fractional) = (0, 0);
    let (mut sum_exact, mut sum_coverage) = (0.0, 0.0);
    let (mut abs_error, mut max_error, mut hard_abs_error) = (0f64, 0f64, 0.0);
    let (mut image_exact, mut image_coverage) = (0.0, 0.0);
    for y in 0..g.height {
        for x in 0..g.width {
            let i = (y * g.width + x) as usize;
            let shadowed = pixel_fraction_below(x as f64, y as f64, a, c);
            let covered = 1.0 - cov.visibility[i] as f64;
            image_exact += shadowed;
            image_coverage += covered;
            if shadowed > 0.0 && shadowed < 1.0 {
                straddling += 1;
                sum_exact += shadowed;
                sum_coverage += covered;
                abs_error += (covered - shadowed).abs();
                max_error = max_error.max((covered - shadowed).abs());
                hard_abs_error += (1.0 - hard.lit[i] as f64 - shadowed).abs();
                if (0.1..=0.9).contains(&shadowed) {
                    assert!(
                        cov.visibility[i] > 0.0 && cov.visibility[i] < 1.0,
                        "pixel ({x}, {y}) straddles the edge"
                    );
                    assert!(cov.std_error[i] > 0.0);
                    fractional += 1;
                }
            } else {
                assert_eq!(covered, shadowed, "pixel ({x}, {y}) is on one side");
            }
        }
    }
    let (mae, hard_mae) = (abs_error / straddling as f64, hard_abs_error / straddling as f64);
    let n = g.pixel_count() as f64;
    println!(
        "coverage {grid}×{grid}: {straddling} pixels straddle the edge; their shadowed area {sum_coverage:.3} vs \
         exact {sum_exact:.3}; mean |error| {mae:.4} (hard: {hard_mae:.4}), max {max_error:.4}; image shadow \
         fraction {:.5} vs exact {:.5}",
        image_coverage / n,
        image_exact / n
    );
    assert!(straddling > 100 && fractional > straddling / 2);
    // A straight edge across a regular n×n grid: each sub-column's covered height is off by at
    // most half a sub-row, so a pixel is off by at most 1/(2n) (plus where the edge leaves the
    // pixel inside a sub-column); the errors partly cancel over many pixels.
    assert!(max_error <= 1.0 / grid as f64, "worst pixel off by {max_error}");
    assert!(mae < 0.03 && mae < 0.2 * hard_mae, "mean |error| per straddling pixel {mae} (hard {hard_mae})");
    assert!((sum_coverage - sum_exact).abs() < 0.02 * sum_exact, "{sum_coverage} vs {sum_exact}");
    assert!((image_coverage - image_exact).abs() < 1e-3 * n, "{image_coverage} vs {image_exact}");
}

/// A box floating above a lit ground under a light from straight above: its side faces are
/// parallel to the light (facing away), the ground around it is lit.
fn floating_box() -> Scene {
    scene_from_json(&serde_json::json!({
        "format": "shadowtruth/scene/v1", "name": "floating",
        "objects": [
            { "name": "ground", "shape": { "type": "plane", "size": [40, 40] } },
            { "name": "box", "shape": { "type": "box", "size": [1, 1, 1] }, "closed": true,
              "transform": { "translate": [0, 1.5, 0] } }
        ],
        "cameras": [{ "name": "c", "position": [0, 1.8, 6], "look_at": [0, 1.5, 0], "fov_y_deg": 30,
                      "width": 160, "height": 120 }],
        "lights": [{ "name": "sun", "type": "directional", "direction": [0, -1, 0] }]
    }))
}

#[test]
fn coverage_sub_pixel_rays_hit_their_own_surfaces() {
    let scene = floating_box();
    let (camera, light) = (&scene.cameras[0], &scene.lights[0]);
    let bvh = SceneBvh::build(&scene);
    let g = GBuffer::trace(&bvh, camera, light);
    let hard = trace_hard_reference(&scene, &bvh, &g, light);
    let cov = trace_coverage_reference(&scene, &bvh, &g, camera, light, 4);
    let (ground, boxed) = (0, 1);
    let object = |i: usize| g.object(&scene, i);
    let w = g.width as usize;
    // Pixels whose centre sees the lit ground beside a pixel showing the box's side face: the
    // centre's own point is lit, so only sub-rays that hit the box itself can lower the value.
    let (mut candidates, mut mixed) = (0, 0);
    for i in 0..g.pixel_count() {
        let (x, y) = (i % w, i / w);
        if object(i) != ground || hard.lit[i] != 1 || x == 0 || x + 1 == w || y == 0 {
            continue;
        }
        let beside_box =
            [i - 1, i + 1].iter().any(|&j| object(j) == boxed && g.class[j] == PixelClass::FacingAway);
        // Rows where the box's vertical sides stand against the far ground (not its shadow).
        if !beside_box || object(i - w) == ground && object(i - w - 1) != boxed && object(i - w + 1) != boxed
        {
            continue;
        }
        candidates += 1;
        assert!(cov.visibility[i] > 0.0, "pixel ({x}, {y}): its centre is lit");
        mixed += (cov.visibility[i] < 1.0) as u32;
    }
    println!("{candidates} lit ground pixels beside the box's silhouette, {mixed} mix in the box's face");
    assert!(candidates >= 20, "{candidates}");
    assert!(mixed * 4 >= candidates, "{mixed} of {candidates} mix two surfaces");
    // Pixels showing the box's side face are not evaluated: 0, whatever their sub-rays see.
    for i in 0..g.pixel_count() {
        if g.class[i] != PixelClass::Evaluated {
            assert_eq!((cov.visibility[i], cov.std_error[i]), (0.0, 0.0));
        }
    }
}

fn with_threads<T: Send>(n: usize, f: impl FnOnce() -> T + Send) -> T {
    rayon::ThreadPoolBuilder::new().num_threads(n).build().unwrap().install(f)
}

/// A bundled scene with a smaller first camera and a size given to its first light.
fn sized(name: &str) -> (Scene, Camera, Light) {
    let scene = bundled(name);
    let mut camera = scene.cameras[0].clone();
    (camera.width, camera.height) = (256, 192);
    let mut light = scene.lights[0].clone();
    match &mut light.kind {
        LightKind::Directional { angular_diameter_deg, .. } => *angular_diameter_deg = Some(6.0),
        LightKind::Spot { radius, .. } | LightKind::Point { radius, .. } => *radius = Some(0.4),
    }
    (scene, camera, light)
}

fn bits(r: &SoftReference) -> Vec<u32> {
    r.visibility.iter().chain(&r.std_error).map(|x| x.to_bits()).collect()
}

#[test]
fn soft_references_are_identical_on_one_and_two_threads() {
    for name in ["rocks", "spot"] {
        let (scene, camera, light) = sized(name);
        let run = || {
            let bvh = SceneBvh::build(&scene);
            let g = GBuffer::trace(&bvh, &camera, &light);
            let area = trace_area_light_reference(&scene, &bvh, &g, &light, 4).unwrap();
            let coverage = trace_coverage_reference(&scene, &bvh, &g, &camera, &light, 3);
            (bits(&area), bits(&coverage))
        };
        let one = with_threads(1, run);
        let two = with_threads(2, run);
        assert!(one.0 == two.0, "{name}: area-light references differ between 1 and 2 threads");
        assert!(one.1 == two.1, "{name}: coverage references differ between 1 and 2 threads");
        // Not trivially equal: both hold fractional pixels.
        let fractional = |b: &[u32]| {
            b[..b.len() / 2].iter().filter(|&&x| f32::from_bits(x) > 0.0 && f32::from_bits(x) < 1.0).count()
        };
        let (fa, fc) = (fractional(&one.0), fractional(&one.1));
        assert!(fa > 50 && fc > 50, "{name}: {fa} area and {fc} coverage pixels fractional");
    }
}

#[test]
fn cached_soft_references_are_bit_identical_to_fresh_ones() {
    let dir = tempfile::tempdir().unwrap();
    let cache = ReferenceCache::new(dir.path());
    for name in ["plane_box", "spot"] {
        let (scene, camera, mut light) = sized(name);
        let bvh = SceneBvh::build(&scene);
        let g = GBuffer::trace(&bvh, &camera, &light);
        let (_, from_cache) = cache.hard_reference(&scene, &bvh, &g, &camera, &light).unwrap();
        assert!(!from_cache);
        let fresh_area = trace_area_light_reference(&scene, &bvh, &g, &light, 4).unwrap();
        let fresh_coverage = trace_coverage_reference(&scene, &bvh, &g, &camera, &light, 2);
        for round in 0..2 {
            let (area, a_cached) = cache.area_light_reference(&scene, &bvh, &g, &camera, &light, 4).unwrap();
            let (coverage, c_cached) =
                cache.coverage_reference(&scene, &bvh, &g, &camera, &light, 2).unwrap();
            assert_eq!((a_cached, c_cached), (round == 1, round == 1), "{name} round {round}");
            assert!(bits(&area) == bits(&fresh_area) && area.samples == 16, "{name} round {round}: area");
            assert!(bits(&coverage) == bits(&fresh_coverage) && coverage.samples == 4, "{name}: coverage");
        }
        // Hard masks and both soft kinds coexist; another grid is another entry.
        assert!(cache.hard_reference(&scene, &bvh, &g, &camera, &light).unwrap().1);
        assert!(!cache.area_light_reference(&scene, &bvh, &g, &camera, &light, 2).unwrap().1);
        assert!(cache.area_light_reference(&scene, &bvh, &g, &camera, &light, 4).unwrap().1);
        // The light's size is part of the digest.
        match &mut light.kind {
            LightKind::Directional { angular_diameter_deg, .. } => *angular_diameter_deg = Some(1.0),
            LightKind::Spot { radius, .. } | LightKind::Point { radius, .. } => *radius = Some(0.1),
        }
        let (resized, cached) = cache.area_light_reference(&scene, &bvh, &g, &camera, &light, 4).unwrap();
        assert!(!cached && bits(&resized) != bits(&fresh_area), "{name}: a new size is traced again");
    }
    let manifest: serde_json::Value =
        serde_json::from_slice(&std::fs::read(dir.path().join("manifest.json")).unwrap()).unwrap();
    let entries = manifest["entries"].as_object().unwrap();
    let keys: Vec<&str> = entries.keys().map(String::as_str).collect();
    assert_eq!(
        keys,
        [
            "plane_box/main/sun",
            "plane_box/main/sun/area-2x2",
            "plane_box/main/sun/area-4x4",
            "plane_box/main/sun/coverage-2x2",
            "spot/main/lamp",
            "spot/main/lamp/area-2x2",
            "spot/main/lamp/area-4x4",
            "spot/main/lamp/coverage-2x2",
        ]
    );
    let area = &entries["spot/main/lamp/area-4x4"];
    assert_eq!((area["kind"].as_str(), area["samples"].as_u64()), (Some("area"), Some(16)));
    assert!(entries["spot/main/lamp"].get("kind").is_none(), "hard entries are written as before");
}

#[test]
fn a_sizeless_light_is_an_error_naming_the_light_and_the_field() {
    for (name, field) in [("plane_box", "angular_diameter_deg"), ("spot", "radius")] {
        let mut scene = bundled(name);
        // The bundled lights have sizes; take them away.
        match &mut scene.lights[0].kind {
            LightKind::Directional { angular_diameter_deg: size, .. }
            | LightKind::Spot { radius: size, .. }
            | LightKind::Point { radius: size, .. } => *size = None,
        }
        let light = &scene.lights[0];
        let mut camera = scene.cameras[0].clone();
        (camera.width, camera.height) = (32, 24);
        let bvh = SceneBvh::build(&scene);
        let g = GBuffer::trace(&bvh, &camera, light);
        let err = trace_area_light_reference(&scene, &bvh, &g, light, 4).unwrap_err();
        assert_eq!(err, AreaLightError::NoSize { light: light.name.clone(), field });
        let message = err.to_string();
        assert!(message.contains(&format!("'{}'", light.name)) && message.contains(field), "{message}");
        let dir = tempfile::tempdir().unwrap();
        let io = ReferenceCache::new(dir.path())
            .area_light_reference(&scene, &bvh, &g, &camera, light, 4)
            .unwrap_err();
        assert_eq!(io.kind(), std::io::ErrorKind::InvalidInput);
        assert!(io.to_string().contains(field));
        assert!(!dir.path().join("manifest.json").exists(), "nothing is written");
    }
    let (scene, camera, light) = sized("plane_box");
    let bvh = SceneBvh::build(&scene);
    let g = GBuffer::trace(&bvh, &camera, &light);
    assert!(matches!(
        trace_area_light_reference(&scene, &bvh, &g, &light, 0),
        Err(AreaLightError::NoSamples { .. })
    ));
}

fn shadowtruth(args: &[&str], dir: &std::path::Path) -> (i32, String) {
    let out = std::process::Command::new(env!("CARGO_BIN_EXE_shadowtruth"))
        .args(args)
        .current_dir(dir)
        .output()
        .unwrap();
    let stderr = String::from_utf8_lossy(&out.stderr).into_owned();
    assert!(!stderr.contains("panicked"), "panic on {args:?}: {stderr}");
    (out.status.code().unwrap_or(-1), stderr)
}

/// The box-over-plane scene with a small camera and a light given a size (or none).
fn small_scene_file(dir: &std::path::Path, angular_diameter_deg: Option<f64>) -> Scene {
    let mut light =
        serde_json::json!({ "name": "sun", "type": "directional", "direction": [-0.3, -1, -0.2] });
    if let Some(a) = angular_diameter_deg {
        light["angular_diameter_deg"] = serde_json::json!(a);
    }
    let json = serde_json::json!({
        "format": "shadowtruth/scene/v1", "name": "small",
        "objects": [
            { "name": "ground", "shape": { "type": "plane", "size": [10, 10] } },
            { "name": "box", "shape": { "type": "box", "size": [1, 1, 1] }, "closed": true,
              "transform": { "rotate_deg": [0, 30, 0], "translate": [0, 1.5, 0] } }
        ],
        "cameras": [{ "name": "c", "position": [-6, 4, 6.5], "look_at": [0, 0.7, 0], "fov_y_deg": 45,
                      "width": 96, "height": 72 }],
        "lights": [light]
    });
    std::fs::write(dir.join("small.json"), serde_json::to_string(&json).unwrap()).unwrap();
    scene_from_json(&json)
}

#[test]
fn reference_command_writes_soft_references_as_exr() {
    let dir = tempfile::tempdir().unwrap();
    let scene = small_scene_file(dir.path(), Some(5.0));
    let (camera, light) = (&scene.cameras[0], &scene.lights[0]);
    let bvh = SceneBvh::build(&scene);
    // As the command traces them: over the pixels the hard reference decides.
    let (g, _) = trace_scored_view(&scene, &bvh, camera, light);
    let expected = [
        ("coverage", trace_coverage_reference(&scene, &bvh, &g, camera, light, 4)),
        ("area", trace_area_light_reference(&scene, &bvh, &g, light, 8).unwrap()),
    ];
    for (kind, expected) in expected {
        let out = format!("{kind}.exr");
        let (code, stderr) =
            shadowtruth(&["reference", "small.json", "--kind", kind, "-o", &out], dir.path());
        assert_eq!(code, 0, "{stderr}");
        // Any EXR reader sees channels V and E, row 0 at the top.
        let image = exr::prelude::read_first_flat_layer_from_file(dir.path().join(&out)).unwrap();
        let channel = |name: &str| -> Vec<f32> {
            let c = image.layer_data.channel_data.list.iter().find(|c| c.name.eq(name)).unwrap();
            c.sample_data.values_as_f32().collect()
        };
        assert_eq!((image.layer_data.size.width(), image.layer_data.size.height()), (96, 72));
        assert!(
            bits(&SoftReference { visibility: channel("V"), std_error: channel("E"), ..expected.clone() })
                == bits(&expected),
            "{kind}"
        );
        let read = SoftReference::from_exr(&std::fs::read(dir.path().join(&out)).unwrap()).unwrap();
        assert!(read == expected, "{kind}: read back differs");
    }
}

#[test]
fn reference_command_rejects_sizeless_lights_and_bad_sample_counts() {
    let dir = tempfile::tempdir().unwrap();
    small_scene_file(dir.path(), None);
    let cases: [(&[&str], &[&str]); 4] = [
        (&["--kind", "area"], &["small.json", "'sun'", "angular_diameter_deg"]),
        (&["--kind", "coverage", "--samples", "0"], &["--samples", "0"]),
        (&["--kind", "coverage", "--samples", "100000"], &["--samples", "100000"]),
        (&["--samples", "4"], &["--samples"]),
    ];
    for (extra, needles) in cases {
        let mut args = vec!["reference", "small.json", "-o", "out.exr"];
        args.extend_from_slice(extra);
        let (code, stderr) = shadowtruth(&args, dir.path());
        assert_eq!(code, 2, "{args:?}: {stderr}");
        for n in needles {
            assert!(stderr.contains(n), "{args:?}: '{n}' missing from: {stderr}");
        }
        assert!(!dir.path().join("out.exr").exists(), "{args:?}: nothing is written");
    }
}
