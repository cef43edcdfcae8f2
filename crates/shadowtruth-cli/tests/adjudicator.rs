//! The adjudicator's exact test against segments whose answer is known by hand, at f32 points
//! and at anchored points (exactly on their triangle, far from the origin), and the command's
//! verdicts.

use glam::{Vec3, vec3};
use shadowtruth::verify::{AnchoredPoint, Contact, Toward};

/// The triangle (0,1,0), (2,1,0), (0,1,2): horizontal at y = 1, its hypotenuse from (2,1,0) to
/// (0,1,2).
const T: [Vec3; 3] = [vec3(0.0, 1.0, 0.0), vec3(2.0, 1.0, 0.0), vec3(0.0, 1.0, 2.0)];

fn to(l: Vec3) -> Toward {
    Toward::Point(l)
}

/// The exact test from an f32 point.
fn contact(p: Vec3, toward: Toward, triangle: &[Vec3; 3]) -> Contact {
    shadowtruth::verify::contact(&AnchoredPoint::at(p), toward, triangle)
}

#[test]
fn a_segment_through_the_interior_meets_it() {
    assert_eq!(contact(vec3(0.5, 0.0, 0.5), to(vec3(0.5, 2.0, 0.5)), &T), Contact::Meets);
    assert_eq!(contact(vec3(0.5, 0.0, 0.5), Toward::Direction(vec3(0.25, 1.0, 0.25)), &T), Contact::Meets);
    // Stopping short of it, or leaving it behind, does not.
    assert_eq!(contact(vec3(0.5, 0.0, 0.5), to(vec3(0.5, 0.75, 0.5)), &T), Contact::Misses);
    assert_eq!(contact(vec3(0.5, 0.0, 0.5), Toward::Direction(vec3(0.0, -1.0, 0.0)), &T), Contact::Misses);
    // Beside it.
    assert_eq!(contact(vec3(1.5, 0.0, 1.5), to(vec3(1.5, 2.0, 1.5)), &T), Contact::Misses);
}

#[test]
fn through_an_edge_or_a_vertex_meets_it() {
    // The hypotenuse's midpoint (1, 1, 1), exactly.
    assert_eq!(contact(vec3(1.0, 0.0, 1.0), to(vec3(1.0, 2.0, 1.0)), &T), Contact::Meets);
    assert_eq!(contact(vec3(0.0, 0.0, 0.5), to(vec3(0.0, 4.0, 0.5)), &T), Contact::Meets);
    // A vertex, along a slanted segment.
    assert_eq!(contact(vec3(-1.0, 0.0, -1.0), to(vec3(1.0, 2.0, 1.0)), &T), Contact::Meets);
    assert_eq!(contact(vec3(2.0, 0.0, 0.0), Toward::Direction(vec3(0.0, 1.0, 0.0)), &T), Contact::Meets);
    // One ulp outside the hypotenuse misses.
    let x = 1.0f32.next_up();
    assert_eq!(contact(vec3(x, 0.0, 1.0), to(vec3(x, 2.0, 1.0)), &T), Contact::Misses);
}

#[test]
fn a_segment_ending_on_it_meets_it() {
    assert_eq!(contact(vec3(0.5, 0.0, 0.5), to(vec3(0.5, 1.0, 0.5)), &T), Contact::Meets);
    assert_eq!(contact(vec3(0.5, 0.0, 0.5), to(vec3(0.5, 1.0f32.next_down(), 0.5)), &T), Contact::Misses);
}

#[test]
fn a_triangle_that_contains_p_is_not_an_occluder() {
    assert_eq!(contact(vec3(0.5, 1.0, 0.5), to(vec3(0.5, 3.0, 0.5)), &T), Contact::ContainsOrigin);
    // On its edge, and leaving it at any angle.
    assert_eq!(contact(vec3(1.0, 1.0, 0.0), to(vec3(-3.0, 1.0, 4.0)), &T), Contact::ContainsOrigin);
    // p in its plane but outside it, leaving the plane: no meeting.
    assert_eq!(contact(vec3(3.0, 1.0, 3.0), to(vec3(0.5, 3.0, 0.5)), &T), Contact::Misses);
}

#[test]
fn parallel_segments_meet_it_only_in_its_plane() {
    // Parallel above it.
    assert_eq!(contact(vec3(-1.0, 1.5, 0.5), to(vec3(3.0, 1.5, 0.5)), &T), Contact::Misses);
    assert_eq!(contact(vec3(-1.0, 1.5, 0.5), Toward::Direction(vec3(1.0, 0.0, 0.0)), &T), Contact::Misses);
    // In its plane, from outside, across it; stopping short of it; pointing away.
    assert_eq!(contact(vec3(-1.0, 1.0, 0.5), to(vec3(3.0, 1.0, 0.5)), &T), Contact::Meets);
    assert_eq!(contact(vec3(-1.0, 1.0, 0.5), Toward::Direction(vec3(1.0, 0.0, 0.0)), &T), Contact::Meets);
    assert_eq!(contact(vec3(-1.0, 1.0, 0.5), to(vec3(-0.5, 1.0, 0.5)), &T), Contact::Misses);
    assert_eq!(contact(vec3(-1.0, 1.0, 0.5), Toward::Direction(vec3(-1.0, 0.0, 0.0)), &T), Contact::Misses);
    // Along an edge's line, touching its end.
    assert_eq!(contact(vec3(-1.0, 1.0, 0.0), to(vec3(0.0, 1.0, 0.0)), &T), Contact::Meets);
}

/// A flat quad of two triangles at height y around (cx, cz), sharing the edge from (−h, h) to
/// (h, −h): `first` is the half with the corner (−h, −h), `second` the other.
fn quad(cx: f32, y: f32, cz: f32, h: f32) -> ([Vec3; 3], [Vec3; 3]) {
    let v = |dx: f32, dz: f32| vec3(cx + dx, y, cz + dz);
    ([v(-h, -h), v(h, -h), v(-h, h)], [v(h, -h), v(h, h), v(-h, h)])
}

#[test]
fn far_from_the_origin_the_other_half_of_a_flat_quad_is_never_met() {
    // At (2·10⁴, 10⁵) an f32 is a multiple of 2⁻⁹ to 2⁻⁶: the rounded surface point near the
    // shared edge can fall across it. The anchored point is exactly on the plane, on its own
    // half or exactly on the edge, so the other half never occludes it; the f32-rounded point,
    // checked the same way, is "exactly" shadowed by its neighbour somewhere — the wrong point.
    let (first, second) = quad(2e4, 1e5, -2e4, 8.0);
    let tilted = |t: [Vec3; 3]| t.map(|v| vec3(v.x, v.y + 0.5 * (v.x - 2e4) - 0.25 * (v.z + 2e4), v.z));
    let (tfirst, tsecond) = (tilted(first), tilted(second));
    let lights = [
        to(vec3(2e4 + 3.0, 1e5 + 40.0, -2e4 + 5.0)),
        to(vec3(2e4 - 30.0, 1e5 + 2.0, -2e4 - 20.0)),
        Toward::Direction(vec3(0.3, 1.0, -0.2)),
        Toward::Direction(vec3(-0.05, 0.01, 0.07)),
    ];
    let (mut rounded_met, mut on_edge) = (0, 0);
    for k in 0..4000u32 {
        // Barycentrics with b1 + b2 within a few f32 steps of 1: next to the shared edge.
        let b1 = (k as f32 + 0.5) / 4000.0;
        let b2 = (1.0 - b1) - (k % 5) as f32 * f32::EPSILON * 0.5;
        for (own, other) in [(first, second), (tfirst, tsecond)] {
            let p = AnchoredPoint::new(own, [b1, b2]);
            for &light in &lights {
                let exact = shadowtruth::verify::contact(&p, light, &other);
                assert_ne!(exact, Contact::Meets, "k = {k}, {light:?}");
                on_edge += (exact == Contact::ContainsOrigin) as usize;
                rounded_met += (contact(p.approx().as_vec3(), light, &other) == Contact::Meets) as usize;
            }
        }
    }
    assert!(on_edge > 0, "some points lie exactly on the shared edge");
    assert!(rounded_met > 0, "the rounded point is met by the other half somewhere");
}

#[test]
fn a_point_one_rational_step_off_the_edge_is_inside_the_neighbour() {
    // b2 one f32 step past 1 − b1: the anchored point lies just across the shared edge, inside
    // the other half, which then contains it (not an occluder) — and a triangle a step above the
    // plane, over that point, is met.
    let (first, second) = quad(2e4, 1e5, -2e4, 8.0);
    let b1 = 0.25f32;
    let b2 = (1.0 - b1).next_up();
    let p = AnchoredPoint::new(first, [b1, b2]);
    let up = to(vec3(2e4, 1e5 + 50.0, -2e4));
    assert_eq!(shadowtruth::verify::contact(&p, up, &second), Contact::ContainsOrigin);
    let one_step_up = second.map(|v| vec3(v.x, 1e5f32.next_up(), v.z));
    assert_eq!(shadowtruth::verify::contact(&p, up, &one_step_up), Contact::Meets);
    let one_step_down = second.map(|v| vec3(v.x, 1e5f32.next_down(), v.z));
    assert_eq!(shadowtruth::verify::contact(&p, up, &one_step_down), Contact::Misses);
    // On its own half exactly at the edge (b1 + b2 = 1): on both halves.
    let q = AnchoredPoint::new(first, [b1, 1.0 - b1]);
    assert_eq!(shadowtruth::verify::contact(&q, up, &second), Contact::ContainsOrigin);
    assert_eq!(shadowtruth::verify::contact(&q, up, &first), Contact::ContainsOrigin);
}

#[test]
fn verify_command_passes_a_bundled_scene_and_rejects_unknown_names() {
    let repo = std::path::Path::new(concat!(env!("CARGO_MANIFEST_DIR"), "/../.."));
    let dir = tempfile::tempdir().unwrap();
    let json = dir.path().join("verify.json");
    let out = std::process::Command::new(env!("CARGO_BIN_EXE_shadowtruth"))
        .args(["verify", "scenes/plane_box.json", "--pixels", "3000", "--json"])
        .arg(&json)
        .current_dir(repo)
        .output()
        .unwrap();
    let stdout = String::from_utf8_lossy(&out.stdout);
    assert_eq!(out.status.code(), Some(0), "{stdout}{}", String::from_utf8_lossy(&out.stderr));
    assert!(stdout.contains("no disagreement outside the error band"), "{stdout}");
    let report: serde_json::Value = serde_json::from_str(&std::fs::read_to_string(&json).unwrap()).unwrap();
    let view = &report["views"][0];
    assert_eq!(view["disagree_outside_band"], 0);
    assert_eq!(view["primary_disagree_outside_band"], 0);
    assert!(view["checked"].as_u64().unwrap() >= 3000, "{view}");
    assert!(view["primary_checked"].as_u64().unwrap() >= view["checked"].as_u64().unwrap(), "{view}");
    let ratio = view["max_point_error_ratio"].as_f64().unwrap();
    assert!(ratio > 0.0 && ratio <= 1.0, "{view}");
    let out = std::process::Command::new(env!("CARGO_BIN_EXE_shadowtruth"))
        .args(["verify", "scenes/plane_box.json", "--light", "moon"])
        .current_dir(repo)
        .output()
        .unwrap();
    assert_eq!(out.status.code(), Some(2));
    assert!(String::from_utf8_lossy(&out.stderr).contains("no light named 'moon'"));
}
