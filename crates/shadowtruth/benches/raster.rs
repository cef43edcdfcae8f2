//! Depth rasterization speed: a tessellated sphere (~10k triangles) over a ground plane, seen
//! from a directional light, at 1024² and 4096², into a fresh and into a reused layer, and the
//! two nearest surfaces.

use criterion::{Criterion, criterion_group, criterion_main};
use glam::Vec3;
use shadowtruth::raster::{
    DepthLayer, LightView, RasterSettings, rasterize_nearest, rasterize_nearest_into, rasterize_two_nearest,
};
use shadowtruth::scene::{Light, LightKind, Object, Scene};
use std::hint::black_box;

/// A UV sphere (counter-clockwise from outside) and a 2-triangle ground, as two objects.
fn sphere_over_plane(rings: usize, segments: usize) -> Scene {
    let (centre, radius) = (Vec3::new(0.0, 1.5, 0.0), 1.0f32);
    let point = |i: usize, j: usize| {
        let theta = std::f32::consts::PI * i as f32 / rings as f32;
        let phi = std::f32::consts::TAU * j as f32 / segments as f32;
        centre + radius * Vec3::new(theta.sin() * phi.cos(), theta.cos(), theta.sin() * phi.sin())
    };
    let mut triangles = vec![];
    for i in 0..rings {
        for j in 0..segments {
            let (a, b, c, d) = (point(i, j), point(i + 1, j), point(i + 1, j + 1), point(i, j + 1));
            for t in [[a, c, b], [a, d, c]] {
                if (t[1] - t[0]).cross(t[2] - t[0]).length_squared() > 0.0 {
                    triangles.push(t);
                }
            }
        }
    }
    let sphere_count = triangles.len() as u32;
    triangles.push([Vec3::new(-4.0, 0.0, -4.0), Vec3::new(4.0, 0.0, 4.0), Vec3::new(4.0, 0.0, -4.0)]);
    triangles.push([Vec3::new(-4.0, 0.0, -4.0), Vec3::new(-4.0, 0.0, 4.0), Vec3::new(4.0, 0.0, 4.0)]);
    let mut triangle_object = vec![0u32; sphere_count as usize];
    triangle_object.extend([1, 1]);
    Scene {
        name: "sphere_over_plane".into(),
        source: Default::default(),
        objects: vec![
            Object { name: "sphere".into(), closed: true, first_triangle: 0, triangle_count: sphere_count },
            Object { name: "ground".into(), closed: false, first_triangle: sphere_count, triangle_count: 2 },
        ],
        flat_triangles: triangles,
        flat_triangle_object: triangle_object,
        meshes: vec![],
        instances: vec![],
        cameras: vec![],
        lights: vec![],
        dropped_degenerate: 0,
    }
}

fn bench_raster(c: &mut Criterion) {
    let scene = sphere_over_plane(72, 72);
    let sun = Light {
        name: "sun".into(),
        path: None,
        cascades: None,
        kind: LightKind::Directional {
            direction: Vec3::new(-0.3, -1.0, -0.2).normalize(),
            angular_diameter_deg: None,
        },
    };
    let mut group = c.benchmark_group(format!("rasterize_nearest_{}_triangles", scene.flat_triangles.len()));
    group.sample_size(10);
    for resolution in [1024, 4096] {
        let view = LightView::new(&sun, scene.bounds(), resolution);
        let settings = RasterSettings::default();
        group.bench_function(format!("{resolution}"), |b| {
            b.iter(|| black_box(rasterize_nearest(black_box(&scene), &view, &settings)))
        });
        // The same into a reused layer: without the page faults of a fresh allocation.
        let mut layer = DepthLayer::new_empty(resolution);
        group.bench_function(format!("{resolution}_reused_layer"), |b| {
            b.iter(|| rasterize_nearest_into(black_box(&scene), &view, &settings, &mut layer))
        });
        // The two nearest surfaces (z1, z2) in one pass, for the depth-layer techniques.
        group.bench_function(format!("{resolution}_two_nearest"), |b| {
            b.iter(|| black_box(rasterize_two_nearest(black_box(&scene), &view, &settings)))
        });
    }
    group.finish();
}

criterion_group!(benches, bench_raster);
criterion_main!(benches);
