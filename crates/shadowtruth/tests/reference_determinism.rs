//! The same input gives the same bits for any thread count.

mod common;

use common::bundled;
use shadowtruth::trace::{GBuffer, SceneBvh, trace_hard_reference};

fn with_threads<T: Send>(n: usize, f: impl FnOnce() -> T + Send) -> T {
    rayon::ThreadPoolBuilder::new().num_threads(n).build().unwrap().install(f)
}

#[test]
fn reference_is_identical_on_one_and_two_threads() {
    for name in ["rocks", "spot"] {
        let scene = bundled(name);
        let run = || {
            let bvh = SceneBvh::build(&scene);
            let g = GBuffer::trace(&bvh, &scene.cameras[0], &scene.lights[0]);
            let r = trace_hard_reference(&scene, &bvh, &g, &scene.lights[0]);
            let bits: Vec<u32> = g.position.iter().flat_map(|p| p.to_array().map(f32::to_bits)).collect();
            (r.mask_codes(&g), bits, g.triangle.clone())
        };
        let one = with_threads(1, run);
        let two = with_threads(2, run);
        assert!(one == two, "{name}: results differ between 1 and 2 threads");
    }
}
