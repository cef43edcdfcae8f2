//! Shading speed of every technique on one thread: the bundled rocks scene (1024×768 camera,
//! the sun) at a 2048² map, each technique's layers built once before the clock, the shading
//! pass over the G-buffer's evaluated pixels timed (criterion's throughput is pixels, so its
//! time per element is the technique's ns/pixel). PCF is timed with each tap bias at the same
//! 3×3 box, so that a bias's cost reads against the constant one's.

use criterion::{Criterion, Throughput, criterion_group, criterion_main};
use shadowtruth::raster::{DepthFormat, LightView};
use shadowtruth::scene::load_scene;
use shadowtruth::technique::{BuiltLayers, ShadeContext, ShadeOrder, TechniqueSpec, shade_evaluated};
use shadowtruth::trace::{GBuffer, SceneBvh};
use std::hint::black_box;
use std::path::Path;

/// One setting of each technique (the default plan's where it has one).
const TECHNIQUES: &[&str] = &[
    r#"{ "technique": "none" }"#,
    r#"{ "technique": "constant", "bias_depth": 0.001 }"#,
    r#"{ "technique": "slope_scaled", "factor": 2.0, "units": 4.0 }"#,
    r#"{ "technique": "normal_offset", "scale_texels": 1.0 }"#,
    r#"{ "technique": "receiver_plane", "bias_depth": 0.00001 }"#,
    r#"{ "technique": "second_depth" }"#,
    r#"{ "technique": "midpoint", "cull_back_faces": true }"#,
    r#"{ "technique": "dual", "z_offset": 0.005, "cull_back_faces": true }"#,
    r#"{ "technique": "adaptive", "k": 0.0001, "epsilon": "original" }"#,
    r#"{ "technique": "adaptive", "k": 0.0001, "epsilon": "ehm" }"#,
    r#"{ "technique": "pcf", "kernel": "box", "size": 3, "bias": "constant", "bias_depth": 0.001 }"#,
    r#"{ "technique": "pcf", "kernel": "box", "size": 3, "bias": "receiver_plane", "bias_depth": 0.00001 }"#,
    r#"{ "technique": "pcf", "kernel": "box", "size": 3, "bias": "adaptive_delta" }"#,
    r#"{ "technique": "mdsm", "depths": 1, "kernel": "box", "size": 4, "bias": "receiver_plane", "bias_depth": 0.00001 }"#,
    r#"{ "technique": "pcss", "search_taps": 25, "filter_taps": 25, "bias": "receiver_plane" }"#,
    r#"{ "technique": "vsm" }"#,
    r#"{ "technique": "esm", "exponent": 40 }"#,
    r#"{ "technique": "evsm2" }"#,
    r#"{ "technique": "evsm4" }"#,
    r#"{ "technique": "msm" }"#,
];

fn shading(c: &mut Criterion) {
    let scene =
        load_scene(&Path::new(env!("CARGO_MANIFEST_DIR")).join("../../scenes/rocks.json")).expect("scene");
    let (camera, sun) = (&scene.cameras[0], &scene.lights[0]);
    let bvh = SceneBvh::build(&scene);
    let gbuffer = GBuffer::trace(&bvh, camera, sun);
    let view = LightView::new(sun, scene.bounds(), 2048);
    let order = ShadeOrder::new(&gbuffer, &view);
    let one_thread = rayon::ThreadPoolBuilder::new().num_threads(1).build().expect("a thread pool");

    let mut g = c.benchmark_group("shading/rocks_2048");
    g.sample_size(10);
    g.throughput(Throughput::Elements(gbuffer.evaluated.len() as u64));
    for json in TECHNIQUES {
        let spec: TechniqueSpec = serde_json::from_str(json).expect("a technique");
        let technique = spec.build().expect("a shaded technique");
        let layers = BuiltLayers::build(&scene, &view, DepthFormat::F32, &technique.layer_needs());
        let ctx = ShadeContext::new(&scene, gbuffer.footprint, &view, layers.as_layers());
        g.bench_function(spec.canonical(), |b| {
            b.iter(|| one_thread.install(|| black_box(shade_evaluated(technique.as_ref(), &order, &ctx))))
        });
    }
    g.finish();
}

criterion_group!(benches, shading);
criterion_main!(benches);
