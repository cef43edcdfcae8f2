//! Building the depth layers a group of techniques reads, once per (light view, depth format,
//! layer needs), timed as the median of repeats (a multiple-depth map's selection included).

use crate::metrics::{Stopwatch, median_ms};
use crate::raster::{
    DepthFormat, DepthLayer, DepthPairLayer, LightView, MultiDepthLayer, RasterSettings, rasterize_nearest,
    rasterize_two_nearest,
};
use crate::scene::Scene;
use crate::technique::{LayerNeeds, Layers};

/// The depth layers of one group of techniques.
pub enum BuiltLayers {
    Nearest(DepthLayer),
    TwoNearest(DepthPairLayer),
    MultiDepth(MultiDepthLayer),
}

impl BuiltLayers {
    pub fn as_layers(&self) -> Layers<'_> {
        match self {
            BuiltLayers::Nearest(l) => Layers::Nearest(l),
            BuiltLayers::TwoNearest(l) => Layers::TwoNearest(l),
            BuiltLayers::MultiDepth(l) => Layers::MultiDepth(l),
        }
    }

    pub fn memory_bytes(&self) -> usize {
        match self {
            BuiltLayers::Nearest(l) => l.memory_bytes(),
            BuiltLayers::TwoNearest(l) => l.memory_bytes(),
            BuiltLayers::MultiDepth(l) => l.memory_bytes(),
        }
    }
}

/// Rasterizes the layers `needs` asks for, `repeats` times; returns the last build and the
/// median time in milliseconds.
pub fn build_layers(
    scene: &Scene,
    view: &LightView,
    format: DepthFormat,
    needs: &LayerNeeds,
    repeats: usize,
) -> (BuiltLayers, f64) {
    let settings = RasterSettings {
        format,
        culling: needs.culling,
        slope_factor: needs.slope_factor,
        slope_units: needs.slope_units,
    };
    let mut times = Vec::new();
    let mut built = None;
    for _ in 0..repeats.max(1) {
        let sw = Stopwatch::start();
        let layers = match (needs.second_layer, needs.multi_depth) {
            (true, _) => BuiltLayers::TwoNearest(rasterize_two_nearest(scene, view, &settings)),
            (false, Some(m)) => BuiltLayers::MultiDepth(MultiDepthLayer::from_base(
                &rasterize_nearest(scene, view, &settings),
                m.depths,
                m.neighbourhood,
                m.selection,
            )),
            (false, None) => BuiltLayers::Nearest(rasterize_nearest(scene, view, &settings)),
        };
        times.push(sw.ms());
        built = Some(layers);
    }
    (built.expect("at least one build"), median_ms(&times))
}
