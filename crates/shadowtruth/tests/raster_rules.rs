//! The rasterizer follows the GPU rules: top-left fill rule (watertight, no double coverage),
//! depth linear in screen space, culling of closed objects only, near-plane clipping, polygon
//! offset, and results independent of the thread count.

use glam::{DMat4, DVec3, Mat4, Vec3, Vec4};
use shadowtruth::raster::*;
use shadowtruth::scene::*;

/// A scene of objects given as (triangles, closed).
fn scene(objects: Vec<(Vec<[Vec3; 3]>, bool)>) -> Scene {
    let mut s = Scene {
        name: "test".into(),
        source: Default::default(),
        objects: vec![],
        flat_triangles: vec![],
        flat_triangle_object: vec![],
        meshes: vec![],
        instances: vec![],
        cameras: vec![],
        lights: vec![],
        dropped_degenerate: 0,
    };
    for (i, (tris, closed)) in objects.into_iter().enumerate() {
        s.objects.push(Object {
            name: format!("o{i}"),
            closed,
            first_triangle: s.flat_triangles.len() as u32,
            triangle_count: tris.len() as u32,
        });
        s.flat_triangle_object.extend(std::iter::repeat_n(i as u32, tris.len()));
        s.flat_triangles.extend(tris);
    }
    s
}

/// A view whose world x, y are raster coordinates in texels (y down, as `DepthLayer` rows) and
/// whose world z is the light depth: the test places vertices directly on the texel grid.
fn texel_view(n: u32) -> LightView {
    let s = 2.0 / n as f32;
    let clip_from_world = Mat4::from_cols(
        Vec4::new(s, 0.0, 0.0, 0.0),
        Vec4::new(0.0, -s, 0.0, 0.0),
        Vec4::new(0.0, 0.0, 1.0, 0.0),
        Vec4::new(-1.0, 1.0, 0.0, 1.0),
    );
    LightView {
        resolution: n,
        projection: Projection::Orthographic { left: 0.0, right: n as f32, bottom: -(n as f32), top: 0.0 },
        light_from_world: Mat4::from_scale(Vec3::new(1.0, 1.0, -1.0)),
        clip_from_world,
        near: 0.0,
        far: 1.0,
        to_light: Some(Vec3::NEG_Z),
        position: None,
        light_size: None,
    }
}

fn p(x: f32, y: f32) -> Vec3 {
    Vec3::new(x, y, 0.5)
}

/// Exact point-in-polygon distance test in f64: the signed distance of (x, y) to the boundary
/// of the simple polygon `poly` (positive inside).
fn inside_distance(poly: &[(f64, f64)], x: f64, y: f64) -> f64 {
    let mut inside = false;
    let mut dist = f64::INFINITY;
    for i in 0..poly.len() {
        let (a, b) = (poly[i], poly[(i + 1) % poly.len()]);
        if (a.1 > y) != (b.1 > y) && x < a.0 + (y - a.1) * (b.0 - a.0) / (b.1 - a.1) {
            inside = !inside;
        }
        let (dx, dy) = (b.0 - a.0, b.1 - a.1);
        let t = (((x - a.0) * dx + (y - a.1) * dy) / (dx * dx + dy * dy)).clamp(0.0, 1.0);
        dist = dist.min((x - a.0 - t * dx).hypot(y - a.1 - t * dy));
    }
    if inside { dist } else { -dist }
}

/// Every texel centre inside `outline` (farther than the snapping error from it) is covered
/// exactly once, every one outside not at all, and none is covered twice.
fn assert_exact_cover(tris: Vec<[Vec3; 3]>, outline: &[(f64, f64)], n: u32) {
    let s = scene(vec![(tris, false)]);
    let count = rasterize_coverage(&s, &texel_view(n), &RasterSettings::default());
    let mut interior = 0;
    for row in 0..n {
        for col in 0..n {
            let c = count[(row * n + col) as usize];
            assert!(c <= 1, "texel ({col}, {row}) covered {c} times");
            let d = inside_distance(outline, col as f64 + 0.5, row as f64 + 0.5);
            // Snapping moves a vertex by at most √2/512 texel.
            if d > 0.01 {
                assert_eq!(c, 1, "gap at texel ({col}, {row})");
                interior += 1;
            } else if d < -0.01 {
                assert_eq!(c, 0, "texel ({col}, {row}) outside covered");
            }
        }
    }
    assert!(interior > 100);
}

#[test]
fn quad_split_along_a_diagonal_covers_each_texel_once() {
    // Awkward corners, a diagonal through texel centres (3.5, 2.5) → (27.5, 26.5), both windings.
    let (a, b, c, d) = (p(3.5, 2.5), p(29.3, 4.1), p(27.5, 26.5), p(1.7, 21.9));
    let outline = [(3.5, 2.5), (29.3, 4.1), (27.5, 26.5), (1.7, 21.9)];
    assert_exact_cover(vec![[a, b, c], [a, c, d]], &outline, 32);
    assert_exact_cover(vec![[a, c, b], [a, c, d]], &outline, 32);
    // The other diagonal.
    assert_exact_cover(vec![[b, c, d], [b, d, a]], &outline, 32);
    // An axis-aligned quad on texel centres: its top and left edges are owned, its bottom and
    // right are not (texel centres on x = 4.5 covered, on x = 20.5 not).
    let (a, b, c, d) = (p(4.5, 3.5), p(20.5, 3.5), p(20.5, 17.5), p(4.5, 17.5));
    let count = rasterize_coverage(
        &scene(vec![(vec![[a, b, c], [a, c, d]], false)]),
        &texel_view(32),
        &RasterSettings::default(),
    );
    let covered: Vec<(u32, u32)> =
        (0..32 * 32).filter(|&i| count[i as usize] == 1).map(|i| (i % 32, i / 32)).collect();
    assert_eq!(covered.len(), 16 * 14);
    assert!(covered.iter().all(|&(x, y)| (4..20).contains(&x) && (3..17).contains(&y)));
}

#[test]
fn fan_around_a_shared_vertex_covers_each_texel_once() {
    let centre = (17.5, 15.5); // on a texel centre
    let ring: Vec<(f64, f64)> = (0..9)
        .map(|k| {
            let a = k as f64 * std::f64::consts::TAU / 9.0 + 0.3;
            let r = 9.0 + 3.7 * ((k * 7 % 5) as f64 / 5.0);
            (centre.0 + r * a.cos(), centre.1 + r * a.sin())
        })
        .collect();
    let v = |q: (f64, f64)| p(q.0 as f32, q.1 as f32);
    let tris: Vec<[Vec3; 3]> = (0..ring.len())
        .map(|k| {
            let (a, b) = (v(ring[k]), v(ring[(k + 1) % ring.len()]));
            // Mixed windings: both are rasterized.
            if k % 2 == 0 { [v(centre), a, b] } else { [b, v(centre), a] }
        })
        .collect();
    let outline: Vec<(f64, f64)> = ring.iter().map(|&q| (q.0 as f32 as f64, q.1 as f32 as f64)).collect();
    assert_exact_cover(tris, &outline, 32);
}

#[test]
fn jittered_grid_mesh_is_watertight() {
    // A 12×12 grid of quads over an awkward rectangle, interior vertices jittered by up to ±0.4
    // cell, alternating diagonals and windings.
    let (x0, y0, x1, y1) = (1.37f32, 2.71f32, 61.13f32, 60.59f32);
    let cells = 12;
    let mut seed = 12345u32;
    let mut jitter = || {
        seed = seed.wrapping_mul(1_664_525).wrapping_add(1_013_904_223);
        (seed >> 8) as f32 / (1u32 << 24) as f32 - 0.5
    };
    let mut grid = vec![Vec3::ZERO; (cells + 1) * (cells + 1)];
    for j in 0..=cells {
        for i in 0..=cells {
            let (fx, fy) = (i as f32 / cells as f32, j as f32 / cells as f32);
            let mut q = p(x0 + fx * (x1 - x0), y0 + fy * (y1 - y0));
            if i > 0 && i < cells && j > 0 && j < cells {
                q.x += 0.8 * jitter() * (x1 - x0) / cells as f32;
                q.y += 0.8 * jitter() * (y1 - y0) / cells as f32;
            }
            grid[j * (cells + 1) + i] = q;
        }
    }
    let mut tris = vec![];
    for j in 0..cells {
        for i in 0..cells {
            let at = |i: usize, j: usize| grid[j * (cells + 1) + i];
            let (a, b, c, d) = (at(i, j), at(i + 1, j), at(i + 1, j + 1), at(i, j + 1));
            let pair = if (i + j) % 2 == 0 { [[a, b, c], [a, c, d]] } else { [[a, b, d], [b, c, d]] };
            for (k, t) in pair.into_iter().enumerate() {
                tris.push(if (i + k) % 3 == 0 { [t[0], t[2], t[1]] } else { t });
            }
        }
    }
    let outline =
        [(x0 as f64, y0 as f64), (x1 as f64, y0 as f64), (x1 as f64, y1 as f64), (x0 as f64, y1 as f64)];
    assert_exact_cover(tris, &outline, 64);
}

fn sun(direction: Vec3) -> Light {
    Light {
        name: "sun".into(),
        path: None,
        cascades: None,
        kind: LightKind::Directional { direction: direction.normalize(), angular_diameter_deg: None },
    }
}

#[test]
fn depth_is_the_triangle_plane_at_texel_centres() {
    let tri = [Vec3::new(-2.1, 0.3, -1.7), Vec3::new(2.6, 1.9, -0.4), Vec3::new(-0.7, -0.2, 2.3)];
    let s = scene(vec![(vec![tri], false)]);
    let n = 256;
    let view = LightView::new(&sun(Vec3::new(-0.3, -1.0, -0.2)), (Vec3::splat(-3.0), Vec3::splat(3.0)), n);
    let layer = rasterize_nearest(&s, &view, &RasterSettings::default());

    // Exact projection of the f32 vertices: raster (x, y) in texels and depth d, in f64.
    let m: DMat4 = view.clip_from_world.as_dmat4();
    let raster = tri.map(|v| {
        let c = m * v.as_dvec3().extend(1.0);
        let (u, vv) = (0.5 * c.x / c.w + 0.5, 0.5 * c.y / c.w + 0.5);
        DVec3::new(u * n as f64, (1.0 - vv) * n as f64, c.z / c.w)
    });
    let (e1, e2) = (raster[1] - raster[0], raster[2] - raster[0]);
    let det = e1.x * e2.y - e2.x * e1.y;
    // Exact depth gradient (depth units per texel).
    let gx = (e1.z * e2.y - e2.z * e1.y) / det;
    let gy = (e1.x * e2.z - e2.x * e1.z) / det;
    let extent = (e1.x.abs().max(e2.x.abs()), e1.y.abs().max(e2.y.abs()));
    // Error bound, derived:
    // 1. Snapping moves each vertex by ≤ 2^−9 texel per axis (round to 1/256), plus the f32
    //    rounding of the raster coordinate (< 2^−24·N ≤ 2^−16 texel here). The snapped plane
    //    differs from the exact one by a linear function whose value at a snapped vertex is
    //    ≤ (|gx| + |gy|)·δ; inside the (snapped) triangle it is a convex combination of those.
    // 2. The f32 vertex depth z/w: a 4-term f32 dot product and a divide by w = 1, error ≤
    //    5·2^−24·Σ|terms|, again carried to the inside by a convex combination.
    // 3. The f32 plane set-up and evaluation: the slopes are computed from depth differences
    //    (≤ 1) and snapped offsets with a few roundings each, their relative error times the
    //    depth change across the triangle (≤ |g|·extent) plus the 2 roundings of the sum:
    //    ≤ 16·2^−24·(1 + |gx|·W + |gy|·H).
    let u = 2f64.powi(-24);
    let delta = 2f64.powi(-9) + 2f64.powi(-16);
    let vertex_err = tri
        .iter()
        .map(|v| {
            let row = m.row(2);
            5.0 * u
                * (row.x.abs() * (v.x as f64).abs()
                    + row.y.abs() * (v.y as f64).abs()
                    + row.z.abs() * (v.z as f64).abs()
                    + row.w.abs())
        })
        .fold(0.0, f64::max);
    let tolerance = (gx.abs() + gy.abs()) * delta
        + vertex_err
        + 16.0 * u * (1.0 + gx.abs() * extent.0 + gy.abs() * extent.1);

    let mut covered = 0;
    let mut worst = 0.0f64;
    for row in 0..n {
        for col in 0..n {
            let d = layer.at(col, row);
            if d == 1.0 {
                continue;
            }
            covered += 1;
            let (x, y) = (col as f64 + 0.5, row as f64 + 0.5);
            let exact = raster[0].z + gx * (x - raster[0].x) + gy * (y - raster[0].y);
            worst = worst.max((d as f64 - exact).abs());
        }
    }
    assert!(covered > 1000, "{covered}");
    assert!(worst <= tolerance, "worst {worst:e} > tolerance {tolerance:e}");
}

/// 12 triangles of the box [lo, hi], counter-clockwise seen from outside.
fn box_triangles(lo: Vec3, hi: Vec3) -> Vec<[Vec3; 3]> {
    let centre = 0.5 * (lo + hi);
    let corner =
        |i: usize| Vec3::new([lo.x, hi.x][i & 1], [lo.y, hi.y][(i >> 1) & 1], [lo.z, hi.z][(i >> 2) & 1]);
    let faces = [[0, 1, 3, 2], [4, 5, 7, 6], [0, 1, 5, 4], [2, 3, 7, 6], [0, 2, 6, 4], [1, 3, 7, 5]];
    let mut out = vec![];
    for f in faces {
        let q = f.map(corner);
        for t in [[q[0], q[1], q[2]], [q[0], q[2], q[3]]] {
            let outward = (t[0] + t[1] + t[2]) / 3.0 - centre;
            let normal = (t[1] - t[0]).cross(t[2] - t[0]);
            out.push(if normal.dot(outward) > 0.0 { t } else { [t[0], t[2], t[1]] });
        }
    }
    out
}

#[test]
fn culling_applies_to_closed_objects_only() {
    let cube = box_triangles(Vec3::new(-1.0, 0.5, -1.0), Vec3::new(1.0, 2.0, 1.0));
    // An open ground quad wound clockwise from above (its normal points down, away from the
    // light): open objects are two-sided, never culled.
    let ground = vec![
        [Vec3::new(-4.0, 0.0, -4.0), Vec3::new(4.0, 0.0, -4.0), Vec3::new(4.0, 0.0, 4.0)],
        [Vec3::new(-4.0, 0.0, -4.0), Vec3::new(4.0, 0.0, 4.0), Vec3::new(-4.0, 0.0, 4.0)],
    ];
    let s = scene(vec![(cube, true), (ground, false)]);
    // Straight down from above: the box's top and bottom and the ground are each at one depth.
    let lamp = Light {
        name: "lamp".into(),
        path: None,
        cascades: None,
        kind: LightKind::Spot {
            position: Vec3::new(0.1, 6.0, 0.1),
            direction: Vec3::NEG_Y,
            cone_deg: 90.0,
            near: 0.5,
            far: 20.0,
            radius: None,
        },
    };
    for light in [sun(Vec3::new(0.0, -1.0, 0.0)), lamp] {
        assert_culling(&s, &LightView::new(&light, s.bounds(), 64));
    }
}

fn assert_culling(s: &Scene, view: &LightView) {
    let depth_at = |culling: Culling, p: Vec3| {
        let layer = rasterize_nearest(s, view, &RasterSettings { culling, ..Default::default() });
        let q = view.project(p).unwrap();
        let (x, row) = layer.texel_of(q.x, q.y).unwrap();
        layer.at(x, row)
    };
    let depth_of = |p: Vec3| view.project(p).unwrap().z;
    let (top, bottom, floor) = (Vec3::new(0.1, 2.0, 0.1), Vec3::new(0.1, 0.5, 0.1), Vec3::new(3.1, 0.0, 3.1));
    let close = |a: f32, b: f32| (a - b).abs() < 1e-5;

    assert!(close(depth_at(Culling::None, top), depth_of(top)));
    assert!(close(depth_at(Culling::BackFacesOfClosed, top), depth_of(top)), "the nearest face stays");
    assert!(close(depth_at(Culling::FrontFacesOfClosed, top), depth_of(bottom)), "the far face remains");
    for culling in [Culling::None, Culling::BackFacesOfClosed, Culling::FrontFacesOfClosed] {
        assert!(close(depth_at(culling, floor), depth_of(floor)), "open ground under {culling:?}");
    }
}

#[test]
fn spot_light_clips_a_triangle_crossing_the_near_plane() {
    let lamp = Light {
        name: "lamp".into(),
        path: None,
        cascades: None,
        kind: LightKind::Spot {
            position: Vec3::ZERO,
            direction: Vec3::NEG_Y,
            cone_deg: 90.0,
            near: 0.5,
            far: 20.0,
            radius: None,
        },
    };
    // Two vertices below the light, one above it (behind the light's plane): unclipped, that
    // vertex would project through w < 0 and wrap onto the wrong side of the map.
    let tri = [Vec3::new(-3.0, -2.0, -1.0), Vec3::new(3.0, -2.5, -1.5), Vec3::new(0.5, 3.0, 2.5)];
    let s = scene(vec![(vec![tri], false)]);
    let n = 64;
    let view = LightView::new(&lamp, s.bounds(), n);
    let layer = rasterize_nearest(&s, &view, &RasterSettings::default());

    let world_from_light = view.light_from_world.as_dmat4().inverse();
    let eye = DVec3::ZERO;
    let t = 1.0f64; // tan(45°)
    let v = tri.map(|p| p.as_dvec3());
    let normal = (v[1] - v[0]).cross(v[2] - v[0]);
    let (mut inside, mut outside) = (0, 0);
    for row in 0..n {
        for col in 0..n {
            let (x, y) =
                (2.0 * (col as f64 + 0.5) / n as f64 - 1.0, 1.0 - 2.0 * (row as f64 + 0.5) / n as f64);
            // Ray through the texel centre; it hits the plane at view depth D (the ray's view z
            // component is −1 per unit of D).
            let dir = world_from_light.transform_vector3(DVec3::new(x * t, y * t, -1.0));
            let depth = normal.dot(v[0] - eye) / normal.dot(dir);
            let hit = eye + dir * depth;
            let bary = |a: DVec3, b: DVec3| (b - a).cross(hit - a).dot(normal) / normal.length_squared();
            let margin = [bary(v[0], v[1]), bary(v[1], v[2]), bary(v[2], v[0])]
                .into_iter()
                .fold(f64::INFINITY, f64::min);
            let stored = layer.at(col, row);
            let (near, far) = (view.near as f64, view.far as f64);
            if depth.is_finite() && margin > 0.02 && depth > near * 1.05 && depth < far * 0.95 {
                inside += 1;
                let expected = view.depth_of_view_depth(depth);
                assert!((stored as f64 - expected).abs() < 1e-4, "({col}, {row}) {stored} vs {expected}");
            } else if depth.is_nan() || depth <= near * 0.95 || margin < -0.02 {
                outside += 1;
                assert_eq!(stored, 1.0, "({col}, {row}) must be empty (D = {depth})");
            }
        }
    }
    assert!(inside > 200 && outside > 200, "{inside} {outside}");
}

#[test]
fn polygon_offset_adds_factor_times_slope_plus_units_times_r() {
    // Depth plane z = 0.25 + gx·x + gy·y with gx = 3/1024, gy = 4/1024 per texel: m = 5/1024.
    // All values are dyadic with few bits, so the f32 plane evaluation is exact.
    let (gx, gy) = (3.0 / 1024.0, 4.0 / 1024.0);
    let at = |x: f64, y: f64| Vec3::new(x as f32, y as f32, (0.25 + gx * x + gy * y) as f32);
    let tri = [at(2.0, 2.0), at(40.0, 3.0), at(10.0, 50.0)];
    let s = scene(vec![(vec![tri], false)]);
    let view = texel_view(64);
    let (factor, units) = (2.0f32, 4.0f32);
    let m = 5.0 / 1024.0;
    // Max vertex depth 0.25 + 230/1024 ∈ [0.25, 0.5): e = −2, r = 2^(−2−23) for f32.
    for (format, r) in [(DepthFormat::F32, 2f64.powi(-25)), (DepthFormat::Unorm16, 1.0 / 65535.0)] {
        let offset = factor as f64 * m + units as f64 * r;
        let settings =
            RasterSettings { format, slope_factor: factor, slope_units: units, ..Default::default() };
        let layer = rasterize_nearest(&s, &view, &settings);
        let mut covered = 0;
        for row in 0..64 {
            for col in 0..64 {
                let d = layer.at(col, row);
                if d == 1.0 {
                    continue;
                }
                covered += 1;
                let plane = 0.25 + gx * (col as f64 + 0.5) + gy * (row as f64 + 0.5);
                let expected = format.store((plane as f32) + (offset as f32));
                if format == DepthFormat::F32 {
                    assert_eq!(d, (plane + offset) as f32, "({col}, {row})");
                }
                assert_eq!(d, expected, "{format:?} ({col}, {row})");
            }
        }
        assert!(covered > 500);
    }
    // Worked numbers: o = 2·5/1024 + 4·2^−25 = 0.009765625 + 1.1920929e−7.
    assert_eq!(2.0 * m + 4.0 * 2f64.powi(-25), 0.009_765_625 + 1.192_092_895_507_812_5e-7);
}

/// A UV sphere of `rings × segments` quads, counter-clockwise from outside.
fn sphere(centre: Vec3, radius: f32, rings: usize, segments: usize) -> Vec<[Vec3; 3]> {
    let point = |i: usize, j: usize| {
        let (theta, phi) = (
            std::f32::consts::PI * i as f32 / rings as f32,
            std::f32::consts::TAU * j as f32 / segments as f32,
        );
        centre + radius * Vec3::new(theta.sin() * phi.cos(), theta.cos(), theta.sin() * phi.sin())
    };
    let mut out = vec![];
    for i in 0..rings {
        for j in 0..segments {
            let (a, b, c, d) = (point(i, j), point(i + 1, j), point(i + 1, j + 1), point(i, j + 1));
            for t in [[a, c, b], [a, d, c]] {
                if (t[1] - t[0]).cross(t[2] - t[0]).length_squared() > 0.0 {
                    out.push(t);
                }
            }
        }
    }
    out
}

#[test]
fn thread_count_does_not_change_a_bit() {
    let ground = vec![
        [Vec3::new(-5.0, 0.0, -5.0), Vec3::new(5.0, 0.0, 5.0), Vec3::new(5.0, 0.0, -5.0)],
        [Vec3::new(-5.0, 0.0, -5.0), Vec3::new(-5.0, 0.0, 5.0), Vec3::new(5.0, 0.0, 5.0)],
    ];
    let s = scene(vec![(sphere(Vec3::new(0.3, 1.5, -0.2), 1.2, 24, 48), true), (ground, false)]);
    let view = LightView::new(&sun(Vec3::new(-0.3, -1.0, -0.2)), s.bounds(), 300);
    let settings = RasterSettings {
        format: DepthFormat::Unorm24,
        culling: Culling::BackFacesOfClosed,
        slope_factor: 1.5,
        slope_units: 2.0,
        ..Default::default()
    };
    let run = |threads: usize| {
        let pool = rayon::ThreadPoolBuilder::new().num_threads(threads).build().unwrap();
        pool.install(|| rasterize_nearest(&s, &view, &settings))
            .depth
            .iter()
            .map(|d| d.to_bits())
            .collect::<Vec<u32>>()
    };
    let one = run(1);
    assert_eq!(one, run(2));
    assert_eq!(one, run(3));
    assert!(one.iter().any(|&b| b != 1f32.to_bits()));
}

#[test]
fn hostile_input_does_not_panic() {
    let nan = Vec3::splat(f32::NAN);
    let huge = Vec3::new(1e30, -1e30, 1e30);
    let tris = vec![
        [nan, Vec3::ZERO, Vec3::X],
        [huge, Vec3::ZERO, Vec3::Y],
        [Vec3::new(-1e6, 0.0, -1e6), Vec3::new(1e6, 0.0, -1e6), Vec3::new(0.0, 0.0, 1e6)],
        [Vec3::ZERO, Vec3::X, Vec3::X * 2.0],
    ];
    let mut s = scene(vec![(tris, true)]);
    s.flat_triangle_object[0] = 99; // an out-of-range object index is treated as open
    let lamp = Light {
        name: "lamp".into(),
        path: None,
        cascades: None,
        kind: LightKind::Spot {
            position: Vec3::new(0.0, 1.0, 0.0),
            direction: Vec3::NEG_Y,
            cone_deg: 170.0,
            near: 1e-4,
            far: 1e4,
            radius: None,
        },
    };
    for light in [sun(Vec3::new(0.1, -1.0, 0.2)), lamp] {
        for n in [0, 1, 2, 33] {
            let bounds = (Vec3::splat(-2.0), Vec3::splat(2.0));
            let view = LightView::new(&light, bounds, n);
            let settings = RasterSettings { slope_factor: 1.0, slope_units: 1.0, ..Default::default() };
            let layer = rasterize_nearest(&s, &view, &settings);
            assert_eq!(layer.depth.len(), (n * n) as usize);
            assert!(layer.depth.iter().all(|d| (0.0..=1.0).contains(d)));
        }
    }
    let empty = scene(vec![]);
    let view = LightView::new(&sun(Vec3::NEG_Y), empty.bounds(), 8);
    assert!(rasterize_nearest(&empty, &view, &RasterSettings::default()).depth.iter().all(|&d| d == 1.0));
}
