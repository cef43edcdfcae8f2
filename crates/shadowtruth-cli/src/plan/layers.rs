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

/// Rasterizes the layers `needs` asks for, `repeats` times, each build into the previous one's
/// memory (the first into `spare`'s, when given); returns the last build and its time in
/// milliseconds: the median of the repeats plus the binning's.
pub fn build_layers_timed(
    binned: &BinnedView,
    format: DepthFormat,
    needs: &LayerNeeds,
    repeats: usize,
    spare: Option<BuiltLayers>,
) -> (BuiltLayers, f64) {
    let mut layers = spare;
    let ((), build_ms) = timed_median(repeats, || {
        layers = Some(BuiltLayers::rasterize_reusing(&binned.rasterizer, format, needs, layers.take()));
    });
    (layers.expect("built at least once"), binned.bin_ms + build_ms)
}
