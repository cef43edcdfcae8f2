//! The adjudicator's exact test against segments whose answer is known by hand (anchored
//! points far from the origin are tested beside the test itself, in verify/segment.rs), and the
//! command's verdicts.

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
