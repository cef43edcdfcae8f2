//! Tracer benchmarks on the bundled OBJ scene (rocks, 8k triangles, 1024×768): BVH build,
//! G-buffer (primary rays), hard reference (shadow rays) and the area-light reference (4×4 shadow
//! rays per pixel towards a sun of 2° angular diameter; throughput in shadow rays). And primary
//! and shadow rays on an outdoor scene of 200K triangles (`generate forest`: terrain and trees
//! with thin trunks, under the sun), the rays `reference --timing` times (primary and shadow
//! rays prepared before the clock, as it times them), with the G-buffer, the hard reference and
//! the coverage and area-light
//! references per sample beside them; and each way the tracer walks those rays, on one thread:
//! single rays, packets of eight neighbours, and tiles or batches of sixteen, primary and shadow
//! alike.

use criterion::{Criterion, Throughput, criterion_group, criterion_main};
use shadowtruth::scene::{LightKind, load_scene};
use shadowtruth::trace::{
    GBuffer, SceneBvh, ShadowRay, hard_shadow_rays, primary_directions, primary_hits,
    trace_area_light_reference, trace_coverage_reference, trace_hard_reference, trace_shadow_rays,
};
use std::path::Path;
use std::process::Command;

fn trace(c: &mut Criterion) {
    let scene =
        load_scene(&Path::new(env!("CARGO_MANIFEST_DIR")).join("../../scenes/rocks.json")).expect("scene");
    let (camera, light) = (&scene.cameras[0], &scene.lights[0]);
    let bvh = SceneBvh::build(&scene);
    let gbuffer = GBuffer::trace(&bvh, camera, light);

    let mut g = c.benchmark_group("trace/rocks");
    g.sample_size(10);
    g.throughput(Throughput::Elements(scene.flat_triangles.len() as u64));
    g.bench_function("bvh_build", |b| b.iter(|| SceneBvh::build(&scene)));
    g.throughput(Throughput::Elements(gbuffer.pixel_count() as u64));
    g.bench_function("gbuffer", |b| b.iter(|| GBuffer::trace(&bvh, camera, light)));
    g.throughput(Throughput::Elements(gbuffer.evaluated.len() as u64));
    g.bench_function("hard_reference", |b| b.iter(|| trace_hard_reference(&scene, &bvh, &gbuffer, light)));
    let mut sun = light.clone();
    let LightKind::Directional { angular_diameter_deg, .. } = &mut sun.kind else {
        panic!("rocks has a sun")
    };
    *angular_diameter_deg = Some(2.0);
    let grid = 4;
    g.throughput(Throughput::Elements(gbuffer.evaluated.len() as u64 * (grid * grid) as u64));
    g.bench_function("area_light_reference_4x4", |b| {
        b.iter(|| trace_area_light_reference(&scene, &bvh, &gbuffer, &sun, grid).expect("the sun has a size"))
    });
    g.finish();
}

/// The generated 200K-triangle forest, written afresh (the generator is deterministic).
fn forest_scene() -> shadowtruth::Scene {
    let dir = Path::new(env!("CARGO_TARGET_TMPDIR")).join("forest200k");
    let status = Command::new(env!("CARGO_BIN_EXE_shadowtruth"))
        .args(["generate", "forest", "--triangles", "200K", "--image", "1024,768", "-o"])
        .arg(&dir)
        .status()
        .expect("run shadowtruth generate");
    assert!(status.success(), "shadowtruth generate forest failed");
    load_scene(&dir.join("scene.json")).expect("the generated forest loads")
}

fn trace_outdoor(c: &mut Criterion) {
    let scene = forest_scene();
    let camera = &scene.cameras[0];
    let sun = scene.lights.iter().find(|l| l.name == "sun").expect("the forest has a sun");
    let bvh = SceneBvh::build(&scene);
    let gbuffer = GBuffer::trace(&bvh, camera, sun);

    let mut g = c.benchmark_group("trace/forest200k");
    g.sample_size(10);
    g.throughput(Throughput::Elements(gbuffer.pixel_count() as u64));
    let directions = primary_directions(camera);
    g.bench_function("primary_rays", |b| b.iter(|| primary_hits(&bvh, camera, &directions)));
    g.bench_function("gbuffer", |b| b.iter(|| GBuffer::trace(&bvh, camera, sun)));
    g.throughput(Throughput::Elements(gbuffer.evaluated.len() as u64));
    let mut shadow_rays = Vec::new();
    hard_shadow_rays(&scene, &gbuffer, sun, usize::MAX, |rays| shadow_rays = rays.to_vec());
    g.bench_function("shadow_rays", |b| b.iter(|| trace_shadow_rays(&bvh, &shadow_rays)));
    drop(shadow_rays);
    g.bench_function("hard_reference", |b| b.iter(|| trace_hard_reference(&scene, &bvh, &gbuffer, sun)));
    // The soft references per sample, beside the hard rate: 2×2 sub-pixel samples (a primary
    // ray and at most one shadow ray each) and 2×2 shadow rays towards the sun's disk.
    let grid = 2;
    g.throughput(Throughput::Elements(gbuffer.evaluated.len() as u64 * (grid * grid) as u64));
    g.bench_function("coverage_2x2", |b| {
        b.iter(|| trace_coverage_reference(&scene, &bvh, &gbuffer, camera, sun, grid))
    });
    g.bench_function("area_light_2x2", |b| {
        b.iter(|| trace_area_light_reference(&scene, &bvh, &gbuffer, sun, grid).expect("the sun has a size"))
    });
    g.finish();
    trace_modes(c, &scene, &bvh, &gbuffer);
}

/// The forest's rays walked each way the tracer can, on one thread: one ray at a time, eight
/// neighbours at a time (packets where the processor has AVX2), and as `reference` walks them:
/// primary rays in tiles of 4×4 and shadow rays in batches of sixteen, one packet of sixteen
/// where the processor has AVX-512 (two of eight otherwise). The answers are the same; only the
/// walk differs.
fn trace_modes(c: &mut Criterion, scene: &shadowtruth::Scene, bvh: &SceneBvh, gbuffer: &GBuffer) {
    let camera = &scene.cameras[0];
    let sun = scene.lights.iter().find(|l| l.name == "sun").expect("the forest has a sun");
    let directions = primary_directions(camera);
    // In the order the hard reference traces them: tile by tile, band by band.
    let mut bands = Vec::new();
    hard_shadow_rays(scene, gbuffer, sun, usize::MAX, |group| bands = group.to_vec());
    let shadow_rays: Vec<ShadowRay> = bands.concat();
    let mut scratch = bvh.scratch();
    let mut hits = vec![None; 8];
    let one_thread = rayon::ThreadPoolBuilder::new().num_threads(1).build().expect("a pool of one thread");

    let mut g = c.benchmark_group("trace/forest200k/one_thread");
    g.sample_size(10);
    g.throughput(Throughput::Elements(directions.len() as u64));
    g.bench_function("primary_single_rays", |b| {
        b.iter(|| {
            let mut hit = |d| bvh.closest_hit(&mut scratch, camera.position, d, 0.0, f32::INFINITY).is_some();
            directions.iter().filter(|&&d| hit(d)).count()
        })
    });
    g.bench_function("primary_packets_of_8", |b| {
        b.iter(|| {
            let mut count = 0;
            for eight in directions.chunks(8) {
                bvh.closest_hits(&mut scratch, camera.position, eight, &mut hits[..eight.len()]);
                count += hits[..eight.len()].iter().filter(|h| h.is_some()).count();
            }
            count
        })
    });
    g.bench_function("primary_tiles_4x4", |b| {
        b.iter(|| one_thread.install(|| primary_hits(bvh, camera, &directions)))
    });
    g.throughput(Throughput::Elements(shadow_rays.len() as u64));
    g.bench_function("shadow_single_rays", |b| {
        b.iter(|| shadow_rays.iter().filter(|r| bvh.shadow_answer(&mut scratch, r).shadowed()).count())
    });
    g.bench_function("shadow_packets_of_8", |b| {
        b.iter(|| {
            let occluded =
                |eight: &[ShadowRay]| bvh.shadow_occluded(&mut scratch, eight).count_ones() as usize;
            shadow_rays.chunks(8).map(occluded).sum::<usize>()
        })
    });
    g.bench_function("shadow_batches_of_16", |b| {
        b.iter(|| one_thread.install(|| trace_shadow_rays(bvh, &bands)))
    });
    g.finish();
}

criterion_group!(benches, trace, trace_outdoor);
criterion_main!(benches);
