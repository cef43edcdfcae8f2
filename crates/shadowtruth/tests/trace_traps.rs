//! Each obvhs 0.4 trap named in docs/conventions.md ("obvhs traps") and at the top of
//! src/trace/bvh/scene_bvh.rs, pinned: the test fails if our tracer falls into it.
//! Where it is cheap, a control shows that obvhs's own path does fall into it on the same input,
//! so that the test is known to exercise the trap.

use glam::{Vec3, vec3};
use obvhs::BvhBuildParams;
use obvhs::bvh2::reinsertion::ReinsertionOptimizer;
use obvhs::cwbvh::CwBvh;
use obvhs::cwbvh::builder::build_cwbvh_from_tris;
use obvhs::cwbvh::bvh2_to_cwbvh::bvh2_to_cwbvh;
use obvhs::ploc::PlocBuilder;
use obvhs::ray::{Ray, RayHit};
use obvhs::triangle::Triangle;
use shadowtruth::trace::{SceneBvh, ShadowRay, SurfacePoint, WatertightRay};
use std::time::Duration;

fn quad(y: f32, half: f32) -> Vec<[Vec3; 3]> {
    let (a, b, c, d) =
        (vec3(-half, y, -half), vec3(half, y, -half), vec3(half, y, half), vec3(-half, y, half));
    vec![[a, c, b], [a, d, c]]
}

fn obvhs_tris(tris: &[[Vec3; 3]]) -> Vec<Triangle> {
    tris.iter().map(|t| Triangle { v0: t[0].into(), v1: t[1].into(), v2: t[2].into() }).collect()
}

/// A closed cube [-1, 1]³ whose faces are n×n grids of quads split along a diagonal, wound
/// counter-clockwise from outside, with every vertex at an exact binary fraction.
fn closed_grid_cube(n: usize) -> Vec<[Vec3; 3]> {
    let mut tris = Vec::new();
    for axis in 0..3 {
        for sign in [-1.0f32, 1.0] {
            let point = |i: usize, j: usize| {
                let (a, b) = (-1.0 + 2.0 * i as f32 / n as f32, -1.0 + 2.0 * j as f32 / n as f32);
                let mut p = [0.0; 3];
                p[axis] = sign;
                p[(axis + 1) % 3] = a;
                p[(axis + 2) % 3] = b;
                Vec3::from_array(p)
            };
            for i in 0..n {
                for j in 0..n {
                    let (p00, p10, p11, p01) =
                        (point(i, j), point(i + 1, j), point(i + 1, j + 1), point(i, j + 1));
                    if sign > 0.0 {
                        tris.push([p00, p10, p11]);
                        tris.push([p00, p11, p01]);
                    } else {
                        tris.push([p00, p11, p10]);
                        tris.push([p00, p01, p11]);
                    }
                }
            }
        }
    }
    tris
}

#[test]
fn no_crack_in_a_closed_mesh() {
    // Rays from outside through the shared edges and vertices of a closed mesh (grid lines,
    // diagonals, corners) must all hit it: axis-aligned rays and rays along the face diagonals.
    let n = 8;
    let tris = closed_grid_cube(n);
    let bvh = SceneBvh::build_from_triangles(&tris);
    let mut scratch = bvh.scratch();
    let moller = obvhs_tris(&tris);
    let (mut rays, mut misses, mut moller_misses) = (0, 0, 0);
    // Grid lines and diagonals inside each face (not its border, where a ray only grazes).
    let steps: Vec<f32> = (1..2 * n).map(|k| -1.0 + k as f32 / n as f32).collect();
    for axis in 0..3 {
        for sign in [-1.0f32, 1.0] {
            for &a in &steps {
                for &b in &steps {
                    for tilt in [0.0f32, 0.25, -0.5] {
                        let mut dir = [0.0f32; 3];
                        dir[axis] = -sign;
                        dir[(axis + 1) % 3] = tilt;
                        dir[(axis + 2) % 3] = tilt;
                        let dir = Vec3::from_array(dir).normalize();
                        let mut target = [0.0f32; 3];
                        target[axis] = sign;
                        target[(axis + 1) % 3] = a;
                        target[(axis + 2) % 3] = b;
                        // From outside inwards, and from inside outwards (the back side).
                        for (origin, dir) in [
                            (Vec3::from_array(target) - dir * 4.0, dir),
                            (Vec3::from_array(target) + dir * 0.5, -dir),
                        ] {
                            rays += 1;
                            if bvh.closest_hit(&mut scratch, origin, dir, 0.0, f32::INFINITY).is_none() {
                                misses += 1;
                            }
                            let ray = Ray::new_inf(origin.into(), dir.into());
                            if moller.iter().all(|t| t.intersect(&ray) == f32::INFINITY) {
                                moller_misses += 1;
                            }
                        }
                    }
                }
            }
        }
    }
    assert_eq!(misses, 0, "{misses} of {rays} rays through shared edges and vertices leaked through");
    // The control: obvhs's non-watertight test lets some of the same rays through.
    assert!(moller_misses > 0, "control: expected obvhs's triangle test to leak on some of {rays} rays");
}

#[test]
fn watertight_test_hits_exactly_on_a_shared_edge() {
    // Two triangles sharing the diagonal of the unit square; a ray straight through the diagonal.
    let (a, b, c, d) = (vec3(0.0, 0.0, 0.0), vec3(1.0, 0.0, 0.0), vec3(1.0, 0.0, 1.0), vec3(0.0, 0.0, 1.0));
    for s in [0.125f32, 0.3, 0.5, 0.7] {
        let p = vec3(s, 0.0, s);
        let dir = vec3(0.3, -1.0, 0.2).normalize();
        let ray = WatertightRay::new((p - dir * 2.0).into(), dir.into());
        let hits = [ray.intersect(a, b, c, 0.0, 10.0), ray.intersect(a, c, d, 0.0, 10.0)];
        assert!(
            hits.iter().any(Option::is_some),
            "ray through the shared edge at s = {s} missed both triangles"
        );
    }
}

#[test]
fn occluder_5e_5_above_the_surface_is_found() {
    // A ground plane at y = 0 and a small occluder 5e-5 above it. obvhs's node test starts at
    // t = 1e-4 and misses it.
    let mut tris = quad(0.0, 10.0);
    tris.extend(quad(5e-5, 0.5));
    let bvh = SceneBvh::build_from_triangles(&tris);
    let mut scratch = bvh.scratch();
    let up = vec3(0.0, 1.0, 0.0);
    for p in [vec3(0.0, 0.0, 0.0), vec3(0.25, 0.0, -0.3), vec3(-0.4, 0.0, 0.45)] {
        // The ground triangle under p (quad's first triangle covers x ≥ z).
        let triangle = if p.x >= p.z { 0 } else { 1 };
        // p's barycentrics on that triangle ([a, c, b] and [a, d, c] of `quad`, half-size 10).
        let (h2, (x, z)) = (20.0, (p.x, p.z));
        let barycentric =
            if triangle == 0 { [(z + 10.0) / h2, (x - z) / h2] } else { [(z - x) / h2, (x + 10.0) / h2] };
        let point = SurfacePoint {
            position: p,
            normal: up,
            triangle: triangle as u32,
            barycentric,
            vertices: tris[triangle],
        };
        let origin = p;
        let dir = vec3(0.1, 1.0, 0.05).normalize();
        let shadow = ShadowRay::along(&point, dir.as_dvec3());
        assert!(bvh.shadow_occluder(&mut scratch, &shadow).is_some(), "occluder above {p} missed");
        // Control: obvhs's own traversal misses it.
        let obvhs_bvh = build_cwbvh_from_tris(
            &obvhs_tris(&tris),
            BvhBuildParams::medium_build(),
            &mut Duration::default(),
        );
        let t = obvhs_tris(&tris);
        let miss = obvhs_bvh.ray_traverse_miss(Ray::new_inf(origin.into(), dir.into()), |r, id| {
            t[obvhs_bvh.primitive_indices[id] as usize].intersect(r)
        });
        assert!(miss, "control: obvhs's traversal was expected to miss an occluder this close");
    }
}

#[test]
fn occluder_at_exactly_tmax_is_reported() {
    let tris = quad(2.0, 1.0);
    let bvh = SceneBvh::build_from_triangles(&tris);
    let mut scratch = bvh.scratch();
    let (origin, dir) = (vec3(0.1, 0.0, 0.2), vec3(0.0, 1.0, 0.0));
    assert!(bvh.occluded(&mut scratch, origin, dir, 0.0, 2.0));
    let hit = bvh.closest_hit(&mut scratch, origin, dir, 0.0, 2.0).expect("hit at tmax");
    assert_eq!(hit.t, 2.0);
    assert!(!bvh.occluded(&mut scratch, origin, dir, 0.0, 2.0f32.next_down()));
    // Control: obvhs's any-hit loop compares t < tmax and loses it.
    let t = obvhs_tris(&tris);
    let obvhs_bvh = build_cwbvh_from_tris(&t, BvhBuildParams::medium_build(), &mut Duration::default());
    let miss = obvhs_bvh.ray_traverse_miss(Ray::new(origin.into(), dir.into(), 0.0, 2.0), |r, id| {
        t[obvhs_bvh.primitive_indices[id] as usize].intersect(r)
    });
    assert!(miss, "control: obvhs was expected to drop the occluder at exactly tmax");
}

/// Triangles along x, each half the size of the previous and twice as close to the origin: the
/// tree becomes a chain far deeper than obvhs's 32-entry traversal stack.
fn chain(count: usize) -> Vec<[Vec3; 3]> {
    (0..count)
        .map(|k| {
            let x = 2f32.powi(-(k as i32) / 2) * if k % 2 == 0 { 1.0 } else { 0.75 };
            let s = x * 0.05;
            [vec3(x, 0.0, 0.0), vec3(x + s, 0.0, 0.0), vec3(x, s, 0.0)]
        })
        .collect()
}

/// obvhs's CWBVH of `tris` as `build_cwbvh_from_tris` makes it, without the validation it runs
/// in debug builds (which rejects trees deeper than its own stack).
fn obvhs_tree_without_validation(tris: &[[Vec3; 3]]) -> CwBvh {
    let params = BvhBuildParams::medium_build();
    let t = obvhs_tris(tris);
    let mut bvh2 = PlocBuilder::with_capacity(t.len()).build(
        params.ploc_search_distance,
        &t,
        (0..t.len() as u32).collect(),
        params.sort_precision,
        params.search_depth_threshold,
    );
    ReinsertionOptimizer::default().run(&mut bvh2, params.reinsertion_batch_ratio, None);
    bvh2_to_cwbvh(&bvh2, 3, true, false)
}

#[test]
fn deep_tree_finds_every_triangle() {
    let tris = chain(220);
    let bvh = SceneBvh::build_from_triangles(&tris);
    assert!(bvh.depth() > 32, "the test needs a tree deeper than 32 levels, got {}", bvh.depth());
    let mut scratch = bvh.scratch();
    let mut obvhs_lost = 0;
    let tree = obvhs_tree_without_validation(&tris);
    let ordered: Vec<Triangle> = obvhs_tris(&tris);
    for (k, tri) in tris.iter().enumerate() {
        let centroid = (tri[0] + tri[1] + tri[2]) / 3.0;
        let origin = centroid + vec3(0.0, 0.0, 1.0);
        let dir = vec3(0.0, 0.0, -1.0);
        let hit = bvh.closest_hit(&mut scratch, origin, dir, 0.0, f32::INFINITY);
        assert_eq!(hit.map(|h| h.triangle), Some(k as u32), "triangle {k} at depth > 32 was lost");
        let mut h = RayHit::none();
        let ray = Ray::new_inf(origin.into(), dir.into());
        let found =
            tree.ray_traverse(ray, &mut h, |r, id| ordered[tree.primitive_indices[id] as usize].intersect(r));
        obvhs_lost += !found as usize;
    }
    // Control: obvhs's own traversal, with its 32-entry stack, loses triangles of this tree.
    assert!(obvhs_lost > 0, "control: obvhs was expected to lose triangles of a tree {} deep", bvh.depth());
}

#[test]
fn hit_ids_are_scene_triangle_ids() {
    // A grid of separate triangles in scene order; the builder reorders them.
    let mut tris = Vec::new();
    for i in 0..16 {
        for j in 0..16 {
            let o = vec3(i as f32 * 1.5, 0.0, ((j * 7) % 16) as f32 * 1.5);
            tris.push([o, o + vec3(0.0, 0.0, 1.0), o + vec3(1.0, 0.0, 0.0)]);
        }
    }
    let bvh = SceneBvh::build_from_triangles(&tris);
    let t = obvhs_tris(&tris);
    let obvhs_bvh = build_cwbvh_from_tris(&t, BvhBuildParams::medium_build(), &mut Duration::default());
    assert!(
        obvhs_bvh.primitive_indices.iter().enumerate().any(|(i, &p)| i as u32 != p),
        "the test needs a BVH that reorders primitives"
    );
    let mut scratch = bvh.scratch();
    for (k, tri) in tris.iter().enumerate() {
        let c = (tri[0] + tri[1] + tri[2]) / 3.0;
        let hit =
            bvh.closest_hit(&mut scratch, c + vec3(0.0, 1.0, 0.0), vec3(0.0, -1.0, 0.0), 0.0, f32::INFINITY);
        assert_eq!(hit.map(|h| h.triangle), Some(k as u32));
    }
}

#[test]
fn barycentrics_reconstruct_the_hit_point() {
    // A triangle whose doubled area is far from 1: obvhs's Triangle::compute_barycentric divides
    // by the normalized normal and is off by that factor.
    let tri = [vec3(-2.0, 0.5, -1.0), vec3(3.0, 0.2, -1.5), vec3(0.5, 0.1, 4.0)];
    let bvh = SceneBvh::build_from_triangles(&[tri]);
    let mut scratch = bvh.scratch();
    let origin = vec3(0.3, 5.0, 0.4);
    let dir = vec3(0.05, -1.0, 0.02).normalize();
    let hit = bvh.closest_hit(&mut scratch, origin, dir, 0.0, f32::INFINITY).expect("hit");
    let [b0, b1, b2] = hit.barycentric;
    assert!((b0 + b1 + b2 - 1.0).abs() < 1e-6);
    let p = tri[0] * b0 + tri[1] * b1 + tri[2] * b2;
    let on_ray = origin + dir * hit.t;
    assert!((p - on_ray).length() < 1e-5, "barycentric point {p} vs ray point {on_ray}");
    let ob = Triangle { v0: tri[0].into(), v1: tri[1].into(), v2: tri[2].into() }
        .compute_barycentric(&Ray::new_inf(origin.into(), dir.into()));
    assert!(
        (ob.x - b1).abs() > 0.01 || (ob.y - b2).abs() > 0.01,
        "control: obvhs's barycentrics were expected to be off"
    );
}
