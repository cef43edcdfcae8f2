//! A layer group's rasterization (binning once, then the nearest layer) on the two kinds of large
//! scene: a generated instanced forest (10 M triangles placed from one tree mesh, nearly all of
//! them smaller than a texel at 2048²) and a generated city (1 M flat triangles, most of them
//! covering texels, at 4096²), each under its sun; the same `Rasterizer` calls that `run`'s
//! layer groups make. Throughput is the scene's triangles.

use criterion::{Criterion, Throughput, criterion_group, criterion_main};
use shadowtruth::raster::{LightView, RasterSettings, Rasterizer};
use shadowtruth::scene::{Scene, load_scene};
use std::hint::black_box;
use std::path::Path;
use std::process::Command;

/// A generated scene, written afresh (the generators are deterministic).
fn generated(kind: &str, triangles: &str, instanced: bool) -> Scene {
    let dir = Path::new(env!("CARGO_TARGET_TMPDIR")).join(format!("layers-{kind}-{triangles}"));
    let mut command = Command::new(env!("CARGO_BIN_EXE_shadowtruth"));
    command.args(["generate", kind, "--triangles", triangles, "-o"]).arg(&dir);
    if instanced {
        command.arg("--instanced");
    }
    let status = command.status().expect("run shadowtruth generate");
    assert!(status.success(), "shadowtruth generate {kind} failed");
    load_scene(&dir.join("scene.json")).expect("the generated scene loads")
}

fn layer_group(c: &mut Criterion, name: &str, scene: &Scene, resolution: u32) {
    let sun = scene.lights.iter().find(|l| l.name == "sun").expect("a sun");
    let view = LightView::new(sun, scene.bounds(), resolution);
    let settings = RasterSettings::default();
    let mut g = c.benchmark_group(format!("layers/{name}"));
    g.sample_size(10);
    g.throughput(Throughput::Elements(scene.triangle_count() as u64));
    g.bench_function(format!("{resolution}_nearest"), |b| {
        b.iter(|| black_box(Rasterizer::new(black_box(scene), &view).nearest(&settings)))
    });
    g.finish();
}

fn layers(c: &mut Criterion) {
    layer_group(c, "forest_instanced_10M", &generated("forest", "10M", true), 2048);
    layer_group(c, "city_1M", &generated("city", "1M", false), 4096);
}

criterion_group!(benches, layers);
criterion_main!(benches);
