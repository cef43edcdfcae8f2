//! The hard reference against shadows computed by hand.

mod common;

use common::{bundled, scene_from_json, trace_first};
use glam::{DVec2, DVec3};
use serde_json::json;
use shadowtruth::scene::LightKind;
use shadowtruth::trace::PixelClass;

/// Convex hull (counter-clockwise) of points in the plane, by Andrew's monotone chain.
fn convex_hull(mut pts: Vec<DVec2>) -> Vec<DVec2> {
    pts.sort_by(|a, b| a.x.total_cmp(&b.x).then(a.y.total_cmp(&b.y)));
    let cross = |o: DVec2, a: DVec2, b: DVec2| (a - o).perp_dot(b - o);
    let mut hull: Vec<DVec2> = Vec::new();
    for pass in 0..2 {
        let start = hull.len();
        let iter: Box<dyn Iterator<Item = &DVec2>> =
            if pass == 0 { Box::new(pts.iter()) } else { Box::new(pts.iter().rev()) };
        for &p in iter {
            while hull.len() >= start + 2 && cross(hull[hull.len() - 2], hull[hull.len() - 1], p) <= 0.0 {
                hull.pop();
            }
            hull.push(p);
        }
        hull.pop();
    }
    hull
}

/// Signed distance from `p` to a counter-clockwise convex polygon: negative inside.
fn signed_distance(poly: &[DVec2], p: DVec2) -> f64 {
    let mut outside = f64::NEG_INFINITY;
    let mut edge_dist = f64::INFINITY;
    for i in 0..poly.len() {
        let (a, b) = (poly[i], poly[(i + 1) % poly.len()]);
        let e = b - a;
        outside = outside.max(-e.perp_dot(p - a) / e.length());
        let t = ((p - a).dot(e) / e.length_squared()).clamp(0.0, 1.0);
        edge_dist = edge_dist.min((a + e * t - p).length());
    }
    if outside > 0.0 { edge_dist } else { -edge_dist }
}

#[test]
fn box_over_plane_matches_the_shadow_polygon() {
    let scene = bundled("plane_box");
    let LightKind::Directional { direction, .. } = scene.lights[0].kind else {
        panic!("directional light expected")
    };
    let d = direction.as_dvec3();
    // The box's shadow on y = 0: its corners slid along the light direction, then their hull.
    let box_object = &scene.objects[1];
    let first = box_object.first_triangle as usize;
    let corners: Vec<DVec2> = scene.flat_triangles[first..first + box_object.triangle_count as usize]
        .iter()
        .flatten()
        .map(|v| {
            let v = v.as_dvec3();
            let q = v + d * (v.y / -d.y);
            DVec2::new(q.x, q.z)
        })
        .collect();
    let polygon = convex_hull(corners);
    assert!(polygon.len() >= 4);
    let (g, r) = trace_first(&scene);
    let (mut compared, mut shadowed, mut box_lit) = (0, 0, 0);
    for &i in &g.evaluated {
        let i = i as usize;
        let lit = r.lit[i] != 0;
        if g.object(&scene, i) == 1 {
            // A lit-facing face of a convex box with nothing above it is lit.
            assert!(lit, "box pixel {i} is shadowed");
            box_lit += 1;
            continue;
        }
        let p = g.position[i].as_dvec3();
        assert_eq!(p.y, 0.0, "ground points lie on y = 0");
        let sd = signed_distance(&polygon, DVec2::new(p.x, p.z));
        if sd.abs() <= 1e-4 {
            continue;
        }
        compared += 1;
        let expect_lit = sd > 0.0;
        shadowed += !expect_lit as usize;
        assert_eq!(
            lit,
            expect_lit,
            "pixel {} ({}, {}) at distance {sd} from the shadow edge",
            i,
            i % 1024,
            i / 1024
        );
    }
    assert!(compared > 300_000 && shadowed > 5_000 && box_lit > 3_000, "{compared} {shadowed} {box_lit}");
}

fn camera_above(width: u32) -> serde_json::Value {
    json!({ "name": "cam", "position": [0.5, 9.0, 7.0], "look_at": [0, 0, 0], "fov_y_deg": 50,
            "width": width, "height": width * 3 / 4 })
}

#[test]
fn a_plane_lit_at_89_9_degrees_is_fully_lit() {
    for azimuth_deg in [0.0f64, 37.0, 90.0, 211.0] {
        let (theta, phi) = (89.9f64.to_radians(), azimuth_deg.to_radians());
        let to_light = DVec3::new(theta.sin() * phi.cos(), theta.cos(), theta.sin() * phi.sin());
        let scene = scene_from_json(&json!({
            "format": "shadowtruth/scene/v1", "name": "grazing",
            "objects": [{ "name": "ground", "shape": { "type": "plane", "size": [20, 20], "subdivisions": 16 } }],
            "cameras": [camera_above(512)],
            "lights": [{ "name": "l", "type": "directional", "direction": (-to_light).to_array() }]
        }));
        let (g, r) = trace_first(&scene);
        assert!(g.evaluated.len() > 100_000);
        let dark = g.evaluated.iter().filter(|&&i| r.lit[i as usize] == 0).count();
        assert_eq!(dark, 0, "azimuth {azimuth_deg}: {dark} pixels of a lone plane are shadowed");
    }
}

/// Light directions all around, including axis-aligned and near-grazing ones.
fn directions() -> Vec<[f64; 3]> {
    let mut out =
        vec![[0.0, -1.0, 0.0], [1.0, 0.0, 0.0], [0.0, 0.0, -1.0], [-1.0, -1.0, -1.0], [0.3, 1.0, -0.2]];
    for k in 0..12 {
        let (theta, phi) = (0.2 + 2.7 * k as f64 / 11.0, 2.399963 * k as f64);
        out.push([theta.sin() * phi.cos(), -theta.cos(), theta.sin() * phi.sin()]);
    }
    out
}

#[test]
fn convex_closed_objects_never_shadow_themselves() {
    let shapes = [
        json!({ "type": "sphere", "radius": 1.5, "segments": 64, "rings": 32 }),
        json!({ "type": "box", "size": [2.0, 1.5, 2.5] }),
    ];
    for shape in shapes {
        for dir in directions() {
            let scene = scene_from_json(&json!({
                "format": "shadowtruth/scene/v1", "name": "convex",
                "objects": [{ "name": "solid", "shape": shape, "closed": true,
                              "transform": { "rotate_deg": [10, 25, 0], "translate": [0.1, 0.2, 0.3] } }],
                "cameras": [{ "name": "cam", "position": [3.0, 2.5, 4.0], "look_at": [0, 0, 0], "fov_y_deg": 45,
                              "width": 320, "height": 240 }],
                "lights": [{ "name": "l", "type": "directional", "direction": dir }]
            }));
            let (g, r) = trace_first(&scene);
            let dark = g.evaluated.iter().filter(|&&i| r.lit[i as usize] == 0).count();
            assert!(g.evaluated.len() > 1000 || g.count(PixelClass::FacingAway) > 1000);
            assert_eq!(dark, 0, "{shape} lit from {dir:?}: {dark} lit-facing pixels are shadowed");
        }
    }
}
