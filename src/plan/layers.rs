//! Building the depth layers a group of techniques reads, once per (light view, depth format,
//! layer needs), timed as the median of repeats (a multiple-depth map's selection included).

use crate::metrics::{Stopwatch, median_ms};
use crate::raster::{DepthFormat, LightView};
use crate::scene::Scene;
use crate::technique::{BuiltLayers, LayerNeeds};

/// Rasterizes the layers `needs` asks for, `repeats` times; returns the last build and the
/// median time in milliseconds.
pub fn build_layers_timed(
    scene: &Scene,
    view: &LightView,
    format: DepthFormat,
    needs: &LayerNeeds,
    repeats: usize,
) -> (BuiltLayers, f64) {
    let mut times = Vec::new();
    let mut built = None;
    for _ in 0..repeats.max(1) {
        let sw = Stopwatch::start();
        built = Some(BuiltLayers::build(scene, view, format, needs));
        times.push(sw.ms());
    }
    (built.expect("at least one build"), median_ms(&times))
}
