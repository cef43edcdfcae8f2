//! The references of a point light against exact answers: the hard reference of a square
//! occluder against the square's central projection from the light, decided in f64; the light's
//! range (`far`) against the distance of each pixel's point; and the sphere light's area
//! reference against the fraction of the sphere's visible cone on the open side of a straight
//! occluder edge, integrated here in f64.

mod common;

use common::scene_from_json;
use glam::DVec3;
use shadowtruth::scene::Scene;
use shadowtruth::trace::{GBuffer, PixelClass, SceneBvh, trace_area_light_reference, trace_hard_reference};

// ---------------------------------------------------------------------------------------------
// The hard reference and the light's range.

const LAMP: [f32; 3] = [0.1, 3.0, 0.05];
const RANGE: f32 = 5.0;

/// A 12×12 floor at y = 0 and, 1.6 above it, a horizontal 1.2×1.2 square (two triangles) off to
/// one side of a point light 3 above the floor, whose range (5) ends on the floor 4 from the
/// point below it. The camera sees the square's shadow and the floor beyond the range.
fn square_scene() -> Scene {
    scene_from_json(&serde_json::json!({
        "format": "shadowtruth/scene/v1", "name": "square",
        "objects": [
            { "name": "floor", "shape": { "type": "plane", "size": [12, 12] } },
            { "name": "square", "shape": { "type": "plane", "size": [1.2, 1.2] },
              "transform": { "translate": [0.35, 1.6, -0.2] } }
        ],
        "cameras": [{ "name": "c", "position": [0.5, 7, 6], "look_at": [0, 0, -0.5], "fov_y_deg": 60,
                      "width": 160, "height": 120 }],
        "lights": [{ "name": "lamp", "type": "point", "position": LAMP, "near": 0.05, "far": RANGE }]
    }))
}

/// The square's corners as the scene holds them (f32, exactly): (x range, z range, height).
fn square_bounds(scene: &Scene) -> ((f64, f64), (f64, f64), f64) {
    let vertices: Vec<DVec3> = scene.object_triangles(1).flat_map(|t| t.map(|p| p.as_dvec3())).collect();
    assert_eq!(vertices.len(), 6, "two triangles");
    let height = vertices[0].y;
    assert!(vertices.iter().all(|p| p.y == height), "the square is horizontal");
    let range = |c: fn(&DVec3) -> f64| {
        vertices.iter().map(c).fold((f64::INFINITY, f64::NEG_INFINITY), |(lo, hi), x| (lo.min(x), hi.max(x)))
    };
    (range(|p| p.x), range(|p| p.z), height)
}

#[test]
fn a_point_lights_hard_shadow_is_the_central_projection_of_its_occluder() {
    let scene = square_scene();
    let light = &scene.lights[0];
    let bvh = SceneBvh::build(&scene);
    let g = GBuffer::trace(&bvh, &scene.cameras[0], light);
    let reference = trace_hard_reference(&scene, &bvh, &g, light);
    let l = light.position().unwrap().as_dvec3();
    let ((x0, x1), (z0, z1), height) = square_bounds(&scene);
    let (centre, half) = (DVec3::new(x0 + x1, 0.0, z0 + z1) * 0.5, DVec3::new(x1 - x0, 0.0, z1 - z0) * 0.5);
    // A floor point's segment to the light crosses the square's plane at a fraction h/l.y of the
    // way: the shadow is the square enlarged l.y/(l.y − h) times about the point below the light.
    let magnification = l.y / (l.y - height);
    // The reference decides for the exact surface point of the pixel, of which `position` is the
    // f32 rounding: within half an ulp of each coordinate, 2⁻²² < 2.5e-7 below 8 (the floor
    // spans ±6). Every other quantity here is an f32 input converted exactly and a few f64
    // operations. A pixel farther than 1e-5 (under a millionth of the floor's size, 40 times
    // that rounding) from the shadow's outline has the same answer at both points.
    let band = 1e-5;
    let (mut lit, mut shadowed, mut skipped) = (0, 0, 0);
    for &i in &g.evaluated {
        let i = i as usize;
        if g.object(&scene, i) != 0 {
            continue;
        }
        let p = g.position[i].as_dvec3();
        assert_eq!(p.y, 0.0, "pixel {i} lies on the floor");
        let q = p + (l - p) * (height / l.y);
        // Signed distance to the square's outline (the larger of the two axes' distances: no
        // more than the Euclidean distance outside, equal to it inside), in floor units.
        let d = ((q.x - centre.x).abs() - half.x).max((q.z - centre.z).abs() - half.z) * magnification;
        if d.abs() < band {
            skipped += 1;
            continue;
        }
        let exact_lit = d > 0.0;
        assert_eq!(reference.lit[i] != 0, exact_lit, "pixel {i} at {p}: {d:e} from the shadow's outline");
        if exact_lit { lit += 1 } else { shadowed += 1 }
    }
    for &i in &reference.uncertain {
        let p = g.position[i as usize].as_dvec3();
        let q = p + (l - p) * (height / l.y);
        let d = ((q.x - centre.x).abs() - half.x).max((q.z - centre.z).abs() - half.z) * magnification;
        assert!(d.abs() < band, "uncertain pixel {i} at {p} is {d:e} from the shadow's outline");
    }
    println!(
        "{lit} lit, {shadowed} shadowed, {skipped} within {band:e} of the outline, {} uncertain",
        reference.uncertain.len()
    );
    assert!(lit > 3000 && shadowed > 400, "{lit} lit, {shadowed} shadowed");
    assert!(skipped <= 2, "{skipped} pixels on the outline");
}

#[test]
fn a_point_light_reaches_exactly_the_points_within_its_range() {
    let scene = square_scene();
    let light = &scene.lights[0];
    let bvh = SceneBvh::build(&scene);
    let g = GBuffer::trace(&bvh, &scene.cameras[0], light);
    let l = light.position().unwrap().as_dvec3();
    let range2 = (RANGE as f64).powi(2);
    let (mut outside, mut inside) = (0, 0);
    for i in 0..g.pixel_count() {
        if g.class[i] == PixelClass::Background {
            continue;
        }
        assert!(
            g.class[i] != PixelClass::FacingAway,
            "pixel {i}: the floor and the square's top face the light"
        );
        // Exact but for the last rounding of a sum of three squares of differences of f32s.
        let d2 = (g.position[i].as_dvec3() - l).length_squared();
        if (d2 - range2).abs() < 1e-9 * range2 {
            continue;
        }
        if d2 > range2 {
            assert_eq!(
                g.class[i],
                PixelClass::OutsideLight,
                "pixel {i} at {}, {} from the light",
                g.position[i],
                d2.sqrt()
            );
            outside += 1;
        } else {
            assert!(
                matches!(g.class[i], PixelClass::Evaluated | PixelClass::Uncertain),
                "pixel {i} at {}, {} from the light: {:?}",
                g.position[i],
                d2.sqrt(),
                g.class[i]
            );
            inside += 1;
        }
    }
    println!("{inside} pixels within the range, {outside} beyond it");
    assert!(outside > 2000 && inside > 5000, "{inside} within, {outside} beyond");
}

// ---------------------------------------------------------------------------------------------
// The sphere light's area reference.

/// The sphere's centre and radius.
const SPHERE: [f32; 3] = [0.0, 4.0, 0.0];
const RADIUS: f64 = 0.8;
/// The height of the occluder: a horizontal plane between the floor and the sphere's bottom.
const SLAB: f64 = 2.0;
const GRID: u32 = 16;

/// A 40×40 floor at y = 0 under a sphere light of radius 0.8 centred 4 above it, and at height 2:
/// `Edge`, a 40×40 slab over x ≤ 0, whose one nearby edge is the line x = 0, y = 2 under the
/// sphere's centre; `Cover`, a 40×40 slab centred under the sphere; `Open`, nothing. The camera,
/// below the slab at x = 0 with an odd width, looks along −z at the floor under the edge, its
/// centre column at x = 0.
#[derive(Clone, Copy, Debug, PartialEq)]
enum Occluder {
    Edge,
    Cover,
    Open,
}

fn sphere_scene(occluder: Occluder) -> Scene {
    let mut objects =
        vec![serde_json::json!({ "name": "floor", "shape": { "type": "plane", "size": [40, 40] } })];
    let slab = |x: f64| {
        serde_json::json!({ "name": "slab", "shape": { "type": "plane", "size": [40, 40] },
                            "transform": { "translate": [x, SLAB, 0] } })
    };
    match occluder {
        Occluder::Edge => objects.push(slab(-20.0)),
        Occluder::Cover => objects.push(slab(0.0)),
        Occluder::Open => {}
    }
    scene_from_json(&serde_json::json!({
        "format": "shadowtruth/scene/v1", "name": "sphere", "objects": objects,
        "cameras": [{ "name": "c", "position": [0, 1.2, 1.5], "look_at": [0, 0, -0.5], "fov_y_deg": 40,
                      "width": 41, "height": 31 }],
        "lights": [{ "name": "bulb", "type": "point", "position": SPHERE, "near": 0.05, "far": 30, "radius": RADIUS }]
    }))
}

/// The fraction of the directions uniform in solid angle over the cone of half-angle `theta_max`
/// around the unit `axis` that lie strictly on the positive side of the plane through the apex
/// with unit normal `m`.
///
/// With β the axis's angle above the plane (sin β = axis·m), a direction at angle θ from the
/// axis and azimuth φ from m's side has ω·m = cos θ sin β + sin θ cos β cos φ, positive for
/// cos φ > −tan β / tan θ: a fraction acos(−tan β / tan θ)/π of the circle (0 or 1 beyond ±1).
/// Uniform in solid angle, u = 1 − cos θ is uniform on [0, 1 − cos θmax]: the fraction is the
/// mean over u, taken here by the midpoint rule on 20 000 steps (the integrand is monotone in u
/// and within [0, 1], so the rule errs by less than 1/20 000). Beyond |β| ≥ θmax the cone lies
/// wholly on one side.
fn open_fraction(axis: DVec3, m: DVec3, theta_max: f64) -> f64 {
    let beta = axis.dot(m).clamp(-1.0, 1.0).asin();
    if beta.abs() >= theta_max {
        return if beta > 0.0 { 1.0 } else { 0.0 };
    }
    let steps = 20_000;
    let u_max = 1.0 - theta_max.cos();
    let sum: f64 = (0..steps)
        .map(|k| {
            let theta = (1.0 - u_max * (k as f64 + 0.5) / steps as f64).acos();
            let c = -beta.tan() / theta.tan();
            if c <= -1.0 {
                1.0
            } else if c >= 1.0 {
                0.0
            } else {
                c.acos() / std::f64::consts::PI
            }
        })
        .sum();
    sum / steps as f64
}

/// (evaluated floor pixel, the analytic open fraction) of the `Edge` scene.
///
/// A direction ω from floor point p = (x, 0, z) (upwards: the sphere lies wholly above the slab)
/// crosses the slab's plane at x + ω.x·2/ω.y, blocked where that is ≤ 0: it is open where
/// ω·(2, x, 0) > 0, a plane through p. Its line through the edge holds the sphere's centre when
/// x = 0: there the plane splits the cone in half.
fn analytic(g: &GBuffer) -> Vec<(usize, f64)> {
    let centre = DVec3::from(SPHERE.map(f64::from));
    g.evaluated
        .iter()
        .map(|&i| {
            let p = g.position[i as usize].as_dvec3();
            let to_centre = centre - p;
            let theta_max = (RADIUS / to_centre.length()).asin();
            let m = DVec3::new(SLAB, p.x, 0.0).normalize();
            (i as usize, open_fraction(to_centre.normalize(), m, theta_max))
        })
        .collect()
}

#[test]
fn a_sphere_light_half_hidden_by_an_edge_through_its_centre_is_half_visible() {
    let grid_samples = (GRID * GRID) as f64;
    let scene = sphere_scene(Occluder::Edge);
    let light = &scene.lights[0];
    let bvh = SceneBvh::build(&scene);
    let g = GBuffer::trace(&bvh, &scene.cameras[0], light);
    assert_eq!(g.evaluated.len(), g.pixel_count(), "every pixel shows the lit floor");
    let soft = trace_area_light_reference(&scene, &bvh, &g, light, GRID).unwrap();
    assert_eq!(soft.samples, GRID * GRID);
    // The standard error of N independent samples at the true fraction F, √(F(1 − F)/(N − 1)),
    // and the reference's own (at its estimate): stratified samples err by less.
    let sigma =
        |f: f64, i: usize| ((f * (1.0 - f) / (grid_samples - 1.0)).sqrt()).max(soft.std_error[i] as f64);
    let (mut on_the_line, mut penumbra, mut bias, mut variance) = (0, 0, 0.0, 0.0);
    let mut worst = 0.0f64;
    for (i, f) in analytic(&g) {
        let v = soft.visibility[i] as f64;
        let x = g.position[i].x;
        if x.abs() < 1e-6 {
            // The edge's line meets the segment to the sphere's centre: half the cone is open.
            assert!((f - 0.5).abs() < 1e-5, "pixel {i}: the analytic fraction {f}");
            on_the_line += 1;
        }
        if f == 0.0 || f == 1.0 {
            // Wholly under the slab or clear of it: every sample agrees.
            assert_eq!(v, f, "pixel {i} at x = {x}");
            continue;
        }
        penumbra += 1;
        let s = sigma(f, i);
        worst = worst.max((v - f).abs() / s);
        assert!((v - f).abs() <= 3.0 * s, "pixel {i} at x = {x}: {v}, the exact fraction {f} (σ {s:.4})");
        bias += v - f;
        variance += s * s;
    }
    // Summed over the penumbra, the errors of independent pixels (each with its own jitter)
    // would stay within 3σ of zero; a systematic error of the sampling would not.
    let sum_sigma = variance.sqrt();
    println!(
        "{penumbra} penumbra pixels ({on_the_line} on the edge's line): worst |v − F| = {worst:.2} σ, summed \
         error {bias:.4} against σ {sum_sigma:.4}"
    );
    assert!(on_the_line >= 20, "{on_the_line} pixels on the line x = 0");
    assert!(penumbra > 200, "{penumbra} penumbra pixels");
    assert!(bias.abs() <= 3.0 * sum_sigma, "summed error {bias} beyond 3σ = {}", 3.0 * sum_sigma);
}

#[test]
fn a_sphere_light_open_to_the_sky_is_wholly_visible_and_covered_wholly_hidden() {
    for (occluder, expected) in [(Occluder::Open, 1.0), (Occluder::Cover, 0.0)] {
        let scene = sphere_scene(occluder);
        let light = &scene.lights[0];
        let bvh = SceneBvh::build(&scene);
        let g = GBuffer::trace(&bvh, &scene.cameras[0], light);
        assert_eq!(g.evaluated.len(), g.pixel_count(), "{occluder:?}: every pixel shows the floor");
        let soft = trace_area_light_reference(&scene, &bvh, &g, light, GRID).unwrap();
        for &i in &g.evaluated {
            let i = i as usize;
            assert_eq!((soft.visibility[i], soft.std_error[i]), (expected, 0.0), "{occluder:?}: pixel {i}");
        }
    }
}
