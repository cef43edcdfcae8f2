//! What a plan names. The default plan is every single-depth technique at a few settings over
//! resolutions 512 to 4096.

use shadowtruth::raster::DepthFormat;
use shadowtruth::technique::TechniqueSpec;
use std::path::PathBuf;

#[derive(Clone, Debug)]
pub struct Plan {
    /// The plan file, named in errors about what it selects (None for a plan built in code).
    pub source: Option<PathBuf>,
    pub scenes: Vec<PathBuf>,
    /// Camera names to run (None: every camera of each scene).
    pub cameras: Option<Vec<String>>,
    /// Light names to run (None: every light of each scene).
    pub lights: Option<Vec<String>>,
    pub techniques: Vec<TechniqueSpec>,
    pub resolutions: Vec<u32>,
    pub depth_formats: Vec<DepthFormat>,
    /// Timings are medians over this many builds and shading passes.
    pub repeats: usize,
    /// Write figures (PNG) under the report folder's `figures/`.
    pub figures: bool,
    /// A region (x, y, width, height in camera pixels) also written enlarged for every run.
    pub zoom: Option<[u32; 4]>,
    /// The coverage reference traces this many × this many sub-pixel rays per pixel.
    pub coverage_grid: u32,
    /// The area-light reference traces this many × this many light samples per pixel.
    pub area_light_grid: u32,
    /// A plan expanding to more runs than this is refused before anything is built.
    pub max_runs: u64,
    /// Another renderer's shadow map (`score --shadow-map`): every technique reads it instead of
    /// layers rasterized here, at its resolution and through its clip_from_world.
    pub shadow_map: Option<shadowtruth::import::ImportedShadowMap>,
    /// Where the shadow maps are drawn and the techniques shaded.
    pub pipeline: Pipeline,
    /// Frames evaluated along each view's camera and light paths (docs/temporal.md); 1 scores
    /// the paths' first key only.
    pub frames: usize,
}

/// Where a plan's shadow maps are drawn and its techniques shaded: the CPU rasterizer and
/// techniques, or a Vulkan device (crate shadowtruth-gpu, for the techniques it implements).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, clap::ValueEnum)]
pub enum Pipeline {
    #[default]
    Cpu,
    Gpu,
}

/// The soft references' grids: the library's, which the Python package takes too.
pub use shadowtruth::trace::{DEFAULT_AREA_LIGHT_GRID, DEFAULT_COVERAGE_GRID, MAX_REFERENCE_GRID};

/// Most frames along a path, in a plan and on the command line.
pub const MAX_FRAMES: usize = 10_000;

/// Largest number of timing repeats, in a plan and on the command line.
pub const MAX_REPEATS: usize = 1000;

/// A plan above this many runs is refused unless the limit is raised (`run --max-runs`).
pub const DEFAULT_MAX_RUNS: u64 = 100_000;

/// Timing repeats of a plan that names none.
pub const DEFAULT_REPEATS: usize = 3;

impl Plan {
    /// `techniques` at `resolutions` on every view of `scenes`, with what a plan file that
    /// names nothing else gets: f32 depths, [`DEFAULT_REPEATS`], figures without a zoom, the
    /// default reference grids and run limit, the CPU pipeline, one frame; built in code (no
    /// file).
    pub fn new(scenes: Vec<PathBuf>, techniques: Vec<TechniqueSpec>, resolutions: Vec<u32>) -> Self {
        Plan {
            source: None,
            scenes,
            cameras: None,
            lights: None,
            techniques,
            resolutions,
            depth_formats: vec![DepthFormat::F32],
            repeats: DEFAULT_REPEATS,
            figures: true,
            zoom: None,
            coverage_grid: DEFAULT_COVERAGE_GRID,
            area_light_grid: DEFAULT_AREA_LIGHT_GRID,
            max_runs: DEFAULT_MAX_RUNS,
            shadow_map: None,
            pipeline: Pipeline::Cpu,
            frames: 1,
        }
    }
}
