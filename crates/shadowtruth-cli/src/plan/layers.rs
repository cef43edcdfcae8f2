//! Building the depth layers a group of techniques reads, once per (light view, depth format,
//! layer needs), timed as the median of repeats (a multiple-depth map's selection included).
//! The view's triangles are binned once for every group (`Rasterizer`); the binning's time is
//! added to each group's, as a build of that group alone would pay it.

use shadowtruth::metrics::{Stopwatch, timed_median};
use shadowtruth::raster::{DepthFormat, LightView, Rasterizer};
use shadowtruth::scene::Scene;
use shadowtruth::technique::{BuiltLayers, LayerNeeds};

/// A view's binned triangles and the time binning them took (ms).
pub struct BinnedView<'a> {
    pub rasterizer: Rasterizer<'a>,
    pub bin_ms: f64,
}

impl<'a> BinnedView<'a> {
    pub fn new(scene: &'a Scene, view: &'a LightView) -> Self {
        let sw = Stopwatch::start();
        let rasterizer = Rasterizer::new(scene, view);
        BinnedView { rasterizer, bin_ms: sw.ms() }
    }
}

/// Rasterizes the layers `needs` asks for, `repeats` times; returns the last build and its
/// time in milliseconds: the median of the repeats plus the binning's.
pub fn build_layers_timed(
    binned: &BinnedView,
    format: DepthFormat,
    needs: &LayerNeeds,
    repeats: usize,
) -> (BuiltLayers, f64) {
    let (built, build_ms) =
        timed_median(repeats, || BuiltLayers::rasterize(&binned.rasterizer, format, needs));
    (built, binned.bin_ms + build_ms)
}
