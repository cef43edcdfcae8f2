//! Instanced geometry (`instances` in a scene object) gives the same answers as the same scene
//! flattened, one object per placement: the same world triangles, G-buffer, hard reference,
//! shadow maps and verdicts, and the same closest hits and occlusion for rays aimed at the
//! instances' vertices and edges, where a culling margin too small would lose a hit.

mod common;

use common::scene_from_json;
use glam::Vec3;
use serde_json::{Value, json};
use shadowtruth::scene::Scene;
use shadowtruth::trace::{GBuffer, PixelClass, SceneBvh, trace_hard_reference};
use shadowtruth::verify::{Adjudicator, PixelSelection, verify_view};
use shadowtruth::{DepthFormat, TechniqueSpec};

/// Placements with arbitrary rotations, non-uniform and mirroring scales, and one far away.
fn placements() -> Vec<Value> {
    let mut out = Vec::new();
    for i in 0..12 {
        let (x, z) = ((i % 4) as f64 * 2.6 - 4.0, (i / 4) as f64 * 2.9 - 3.0);
        let scale = match i % 3 {
            0 => json!([1.0, 1.3, 1.0]),
            1 => json!([0.7, 1.9, 0.9]),
            _ => json!([-0.8, 1.1, 0.8]),
        };
        out.push(
            json!({ "scale": scale, "rotate_deg": [7.0 * i as f64, 33.0 * i as f64 + 11.0, -5.0 * i as f64],
                         "translate": [x, 0.4 + 0.1 * i as f64, z] }),
        );
    }
    out.push(json!({ "scale": [3e-3, 3e-3, 3e-3], "translate": [0.3, 2.2, 0.1] }));
    out
}

fn scene_json(objects: Vec<Value>) -> Value {
    json!({
        "format": "shadowtruth/scene/v1", "name": "forest",
        "objects": objects,
        "cameras": [{ "name": "cam", "position": [-7, 6, 8], "look_at": [0, 0.5, 0], "up": [0, 1, 0],
                      "fov_y_deg": 50, "width": 320, "height": 240 }],
        "lights": [
            { "name": "sun", "type": "directional", "direction": [-0.35, -1, -0.25] },
            { "name": "lamp", "type": "spot", "position": [2, 7, 3], "direction": [-0.3, -1, -0.4],
              "cone_deg": 80, "near": 0.5, "far": 30 }
        ]
    })
}

fn tree() -> Value {
    json!({ "type": "sphere", "radius": 0.6, "segments": 24, "rings": 12 })
}

fn ground() -> Value {
    json!({ "name": "ground", "shape": { "type": "plane", "size": [14, 14], "subdivisions": 4 } })
}

/// The forest with its trees instanced, and the same forest with one object per tree.
fn forests() -> (Scene, Scene) {
    let instanced = scene_json(vec![
        ground(),
        json!({ "name": "tree", "shape": tree(), "closed": true, "instances": placements() }),
        json!({ "name": "rock", "shape": { "type": "box", "size": [0.5, 0.3, 0.4] }, "closed": true,
                "instances": [{ "translate": [1.1, 0.15, 1.2] }, { "rotate_deg": [0, 45, 0], "translate": [-1.5, 0.15, 0.5] }] }),
    ]);
    let mut flat = vec![ground()];
    for (k, p) in placements().into_iter().enumerate() {
        flat.push(json!({ "name": format!("tree#{k}"), "shape": tree(), "closed": true, "transform": p }));
    }
    flat.push(json!({ "name": "rock#0", "shape": { "type": "box", "size": [0.5, 0.3, 0.4] }, "closed": true,
                      "transform": { "translate": [1.1, 0.15, 1.2] } }));
    flat.push(json!({ "name": "rock#1", "shape": { "type": "box", "size": [0.5, 0.3, 0.4] }, "closed": true,
                      "transform": { "rotate_deg": [0, 45, 0], "translate": [-1.5, 0.15, 0.5] } }));
    (scene_from_json(&instanced), scene_from_json(&scene_json(flat)))
}

#[test]
fn instancing_stores_each_mesh_once_and_numbers_its_triangles_after_the_flat_ones() {
    let (instanced, flat) = forests();
    assert_eq!(instanced.meshes.len(), 2);
    assert_eq!(instanced.instances.len(), 15);
    assert_eq!(instanced.flat_triangles.len(), 2 * 16);
    assert_eq!(instanced.triangle_count(), flat.triangle_count());
    assert_eq!(instanced.bounds(), flat.bounds());
    // Object by object, the same world triangles in the same order.
    assert_eq!(instanced.objects.len(), flat.objects.len());
    for (i, (a, b)) in instanced.objects.iter().zip(&flat.objects).enumerate() {
        assert_eq!((&a.name, a.closed, a.triangle_count), (&b.name, b.closed, b.triangle_count));
        let (ta, tb): (Vec<_>, Vec<_>) =
            (instanced.object_triangles(i).collect(), flat.object_triangles(i).collect());
        assert_eq!(ta, tb, "object {}", a.name);
        let ids = a.first_triangle..a.first_triangle + a.triangle_count;
        assert!(ids.clone().all(|id| instanced.object_of(id) == i as u32));
        assert_eq!(ids.map(|id| instanced.triangle(id)).collect::<Vec<_>>(), tb);
    }
}

#[test]
fn instancing_gives_the_flattened_scenes_gbuffer_reference_and_verdicts() {
    let (instanced, flat) = forests();
    let (bvh_i, bvh_f) = (SceneBvh::build(&instanced), SceneBvh::build(&flat));
    let camera = &flat.cameras[0];
    for light in &flat.lights {
        let gi = GBuffer::trace(&bvh_i, camera, light);
        let gf = GBuffer::trace(&bvh_f, camera, light);
        assert_eq!(gi.class, gf.class, "{}", light.name);
        assert_eq!(bits(&gi.position), bits(&gf.position), "{}", light.name);
        assert_eq!(bits(&gi.normal), bits(&gf.normal), "{}", light.name);
        let same_triangles = gi.evaluated.iter().all(|&p| {
            let p = p as usize;
            instanced.triangle(gi.triangle[p]) == flat.triangle(gf.triangle[p])
        });
        assert!(same_triangles, "{}", light.name);
        let ri = trace_hard_reference(&instanced, &bvh_i, &gi, light);
        let rf = trace_hard_reference(&flat, &bvh_f, &gf, light);
        assert_eq!(ri.lit, rf.lit, "{}", light.name);
        let shadowed = gi.evaluated.iter().filter(|&&p| ri.lit[p as usize] == 0).count();
        assert!(shadowed > 1000 && shadowed < gi.evaluated.len() - 1000, "{}: {shadowed}", light.name);

        let verdict = verify_view(
            &instanced,
            &bvh_i,
            &Adjudicator::new(&instanced),
            camera,
            light,
            PixelSelection::All,
        );
        assert!(verdict.passed(), "{}: {:#?}", light.name, verdict.cases);
        assert_eq!(verdict.checked, gi.evaluated.len() + gi.count(PixelClass::Uncertain));
        assert_eq!(verdict.primary_checked, gi.pixel_count());
    }
}

#[test]
fn instancing_gives_the_flattened_scenes_shadow_maps() {
    let (instanced, flat) = forests();
    let technique: TechniqueSpec = serde_json::from_str(r#"{"technique": "midpoint"}"#).unwrap();
    for light in &flat.lights {
        let view = shadowtruth::light_view(&flat, light, 512).unwrap();
        assert_eq!(shadowtruth::light_view(&instanced, light, 512).unwrap(), view);
        let li = shadowtruth::rasterize_layers(&instanced, &view, DepthFormat::F32, &technique).unwrap();
        let lf = shadowtruth::rasterize_layers(&flat, &view, DepthFormat::F32, &technique).unwrap();
        assert!(li == lf, "{}", light.name);
    }
}

/// Rays from scattered origins aimed exactly at each instanced triangle's vertices and edge
/// midpoints: closest hits on the same world triangle at the same distance (unbounded, and
/// within half the distance to the target), and the same occlusion, in both scenes.
#[test]
fn instancing_keeps_every_hit_at_vertices_and_edges() {
    let (instanced, flat) = forests();
    let (bvh_i, bvh_f) = (SceneBvh::build(&instanced), SceneBvh::build(&flat));
    let (mut si, mut sf) = (bvh_i.scratch(), bvh_f.scratch());
    let origins = [
        Vec3::new(-7.0, 6.0, 8.0),
        Vec3::new(5.0, 9.0, -2.0),
        Vec3::new(0.1, 0.05, 0.2),
        Vec3::new(9.0, 0.3, 9.0),
    ];
    let mut rays = 0;
    for id in instanced.flat_triangles.len() as u32..instanced.triangle_count() as u32 {
        let [a, b, c] = instanced.triangle(id);
        for target in [a, b, c, (a + b) * 0.5, (b + c) * 0.5, (c + a) * 0.5] {
            for &origin in &origins {
                let Some(direction) = (target - origin).try_normalize() else { continue };
                let hi = bvh_i.closest_hit(&mut si, origin, direction, 0.0, f32::INFINITY);
                let hf = bvh_f.closest_hit(&mut sf, origin, direction, 0.0, f32::INFINITY);
                assert_eq!(hi.map(|h| h.t), hf.map(|h| h.t), "ray {origin} → {target}");
                if let (Some(hi), Some(hf)) = (hi, hf) {
                    assert_eq!(instanced.triangle(hi.triangle), flat.triangle(hf.triangle));
                }
                let tmax = (target - origin).length();
                // A bounded search: nothing beyond tmax, in either scene.
                let bounded = |bvh: &SceneBvh, s: &mut _, scene: &Scene| {
                    bvh.closest_hit(s, origin, direction, 0.0, 0.5 * tmax)
                        .map(|h| (h.t, scene.triangle(h.triangle)))
                };
                assert_eq!(bounded(&bvh_i, &mut si, &instanced), bounded(&bvh_f, &mut sf, &flat));
                assert_eq!(
                    bvh_i.occluded(&mut si, origin, direction, 0.0, tmax),
                    bvh_f.occluded(&mut sf, origin, direction, 0.0, tmax),
                    "ray {origin} → {target}"
                );
                rays += 1;
            }
        }
    }
    assert!(rays > 50_000, "{rays}");
}

fn bits(v: &[Vec3]) -> Vec<[u32; 3]> {
    v.iter().map(|p| p.to_array().map(f32::to_bits)).collect()
}
