//! `shadowtruth/report/v1`: one record per (scene, camera, light, technique with its parameters,
//! resolution, depth format).

use crate::metrics::{Counts, Rates, SoftErrors};
use crate::technique::ReferenceKind;
use serde::{Deserialize, Serialize};

mod journal;
mod load;

pub use journal::{JOURNAL_FILE, JournalEntry, journal_header, journal_line, load_journaled_report};
pub use load::{MAX_REPORT_BYTES, ReportReadError, load_report};

pub const REPORT_SCHEMA: &str = "shadowtruth/report/v1";

#[derive(Clone, Debug, Serialize, Deserialize)]
pub struct Tool {
    pub name: String,
    pub version: String,
}

#[derive(Clone, Debug, Serialize, Deserialize)]
pub struct Machine {
    pub cores: usize,
    pub cpu: String,
}

impl Machine {
    pub fn this() -> Self {
        let cpu = std::fs::read_to_string("/proc/cpuinfo")
            .ok()
            .and_then(|s| {
                s.lines()
                    .find(|l| l.starts_with("model name"))
                    .and_then(|l| l.split(':').nth(1))
                    .map(|m| m.trim().to_string())
            })
            .unwrap_or_else(|| std::env::consts::ARCH.to_string());
        Machine { cores: std::thread::available_parallelism().map(|n| n.get()).unwrap_or(1), cpu }
    }
}

/// What was loaded for a scene: triangles kept, degenerate triangles dropped, BVH build time.
#[derive(Clone, Debug, Serialize, Deserialize)]
pub struct SceneRecord {
    pub name: String,
    pub file: String,
    pub triangles: u64,
    pub dropped_degenerate: u64,
    pub bvh_build_ms: f64,
}

#[derive(Clone, Copy, Debug, Default, Serialize, Deserialize)]
pub struct Timings {
    /// Building what the technique reads (its depth layer), milliseconds.
    pub prepare: f64,
    /// The shading pass over the evaluated pixels, milliseconds.
    pub shade: f64,
    /// Shading time per evaluated pixel, nanoseconds: the median of the repeats.
    pub ns_per_pixel: f64,
    /// The least of the repeats' `ns_per_pixel`; with `ns_per_pixel_max`, the noise of the cost.
    /// Absent where the shading was not timed here over repeats (another renderer's buffer, a
    /// path's mean over frames) and in older reports.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub ns_per_pixel_min: Option<f64>,
    /// The greatest of the repeats' `ns_per_pixel`.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub ns_per_pixel_max: Option<f64>,
}

impl Timings {
    /// Whether the shading was timed here: another renderer's buffer records no cost (0 ms).
    pub fn cost_measured(&self) -> bool {
        self.shade > 0.0
    }

    /// The range of the cost over the repeats; the median alone where none was recorded.
    pub fn cost_range(&self) -> [f64; 2] {
        [
            self.ns_per_pixel_min.unwrap_or(self.ns_per_pixel),
            self.ns_per_pixel_max.unwrap_or(self.ns_per_pixel),
        ]
    }
}

#[derive(Clone, Debug, Serialize, Deserialize)]
pub struct RunRecord {
    pub scene: String,
    pub camera: String,
    pub light: String,
    pub technique: String,
    pub parameters: serde_json::Map<String, serde_json::Value>,
    /// `technique(param=value,...)`, for tables and captions.
    pub label: String,
    pub resolution: u32,
    pub depth_format: String,
    pub counts: Counts,
    pub rates: Rates,
    pub timings: Timings,
    /// Bytes of the depth layers this run read.
    pub layer_memory_bytes: u64,
    /// The reference the run was scored against.
    #[serde(default)]
    pub reference: ReferenceUsed,
    /// Soft errors, for runs scored against a fractional reference (coverage, area light).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub soft: Option<SoftErrors>,
    /// The device of a run on the GPU pipeline (absent for the CPU's).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub pipeline: Option<PipelineUsed>,
    /// A run on cascaded shadow maps: the cascades and their counts (docs/cascades.md).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub cascades: Option<CascadesRecord>,
    /// A run under a point light: its map (a cube or dual paraboloids) and the counts of each
    /// face (docs/point-lights.md).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub point_map: Option<PointMapRecord>,
    /// A run over the frames of a path: per-frame errors and flicker (docs/temporal.md). Its
    /// `counts` are then summed over every frame.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub temporal: Option<TemporalRecord>,
}

/// The cascade set a run read, and its counts per cascade (of its last frame, for a run over a
/// path).
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct CascadesRecord {
    /// "uniform", "logarithmic" or "practical(λ=…)".
    pub split: String,
    /// "sphere" or "frustum".
    pub fit: String,
    pub stabilize: bool,
    pub blend_band: f64,
    pub cascades: Vec<CascadeRecord>,
    /// Evaluated pixels beyond the last cascade (lit).
    pub beyond: CascadeCounts,
}

/// One cascade: the view depths it serves, its texel as the camera sees it, and its pixels.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct CascadeRecord {
    pub near: f64,
    pub far: f64,
    /// World size of one texel.
    pub texel_world: f64,
    /// Camera pixels one texel spans at the cascade's far split (more is blockier).
    pub texel_pixels_at_far: f64,
    pub counts: CascadeCounts,
}

/// Evaluated pixels shaded through one cascade (the nearer of a blend) and its false ones.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Serialize, Deserialize)]
pub struct CascadeCounts {
    pub evaluated: u64,
    pub false_shadow: u64,
    pub false_lit: u64,
}

/// The map a run under a point light read, and its counts per face.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct PointMapRecord {
    /// "cube" or "dual_paraboloid".
    pub layout: String,
    /// A cube's texels drawn beyond each face's edges (0: filters clamp at the seams; 0 for
    /// paraboloids).
    pub guard_texels: u32,
    /// Each face's map side: `resolution + 2·guard_texels`.
    pub face_texels: u32,
    /// The faces in the map's order (a cube's +x, −x, +y, −y, +z, −z; the paraboloids' front
    /// (−y), back (+y)).
    pub faces: Vec<PointFaceRecord>,
}

/// One face of a point light's map and the evaluated pixels it shaded.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct PointFaceRecord {
    /// "+x", "-x", "+y", "-y", "+z", "-z", "front (-y)" or "back (+y)".
    pub face: String,
    /// Evaluated pixels within `raster::SEAM_TEXELS` texels of the face's edge (a paraboloid's
    /// rim), and their false ones.
    pub near_seam: CascadeCounts,
    pub counts: CascadeCounts,
}

/// A run over the frames of a path (docs/temporal.md).
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct TemporalRecord {
    pub frames: u32,
    /// What moves: "camera", "light", "both" or "none".
    pub moving: String,
    /// The error rate of each frame.
    pub frame_errors: Vec<f64>,
    /// Per frame, its flickering pixels against the frame before (0 for the first).
    pub frame_flicker: Vec<u64>,
    /// The mean of `frame_errors`.
    pub mean_error: f64,
    pub worst_frame: u32,
    pub worst_frame_error: f64,
    /// Flickering pixels over the surface points compared between consecutive frames.
    pub flicker_rate: f64,
    pub flicker_pixels: u64,
    pub compared_pixels: u64,
}

/// The GPU a run's map was drawn and its technique shaded on.
#[derive(Clone, Debug, PartialEq, Eq, Serialize, Deserialize)]
pub struct PipelineUsed {
    /// "gpu".
    pub name: String,
    pub adapter: String,
    pub driver: String,
    pub backend: String,
}

/// Which reference a run was scored against and with how many samples per pixel (1 for hard).
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
pub struct ReferenceUsed {
    pub kind: ReferenceKind,
    pub samples: u32,
}

impl Default for ReferenceUsed {
    fn default() -> Self {
        ReferenceUsed { kind: ReferenceKind::Hard, samples: 1 }
    }
}

#[derive(Clone, Debug, Serialize, Deserialize)]
pub struct Report {
    pub schema: String,
    pub tool: Tool,
    pub machine: Machine,
    /// RFC 3339, UTC.
    pub created: String,
    pub scenes: Vec<SceneRecord>,
    pub runs: Vec<RunRecord>,
    /// What `run` was asked to do, for `run --resume` and `merge` (absent in other reports).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub schedule: Option<ScheduleRecord>,
    /// The share of the schedule a `run --shard K/N` folder holds (absent in a whole run).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub shard: Option<ShardRecord>,
}

/// A plan's schedule as `run` expands it: its identity (a digest of every view's inputs, the
/// techniques in canonical form and the options that change results or outputs) and the order
/// of its views and maps, so that shards merge and interrupted runs resume in that order.
#[derive(Clone, Debug, PartialEq, Eq, Serialize, Deserialize)]
pub struct ScheduleRecord {
    /// SHA-256, hex.
    pub identity: String,
    /// Every (scene, camera, light) view of the plan, in schedule order.
    pub views: Vec<ViewName>,
    /// The shadow-map resolutions in schedule order.
    pub resolutions: Vec<u32>,
    /// The depth formats in schedule order.
    pub depth_formats: Vec<String>,
    /// Runs per (view, resolution, depth format): one per technique setting.
    pub runs_per_map: usize,
}

/// The names of one (scene, camera, light) view.
#[derive(Clone, Debug, PartialEq, Eq, Hash, PartialOrd, Ord, Serialize, Deserialize)]
pub struct ViewName {
    pub scene: String,
    pub camera: String,
    pub light: String,
}

impl ViewName {
    pub fn of_run(run: &RunRecord) -> Self {
        ViewName { scene: run.scene.clone(), camera: run.camera.clone(), light: run.light.clone() }
    }
}

impl std::fmt::Display for ViewName {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(f, "{}/{}/{}", self.scene, self.camera, self.light)
    }
}

/// Shard `index` of `count` (1-based), as `run --shard index/count` wrote it.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize)]
pub struct ShardRecord {
    pub index: u32,
    pub count: u32,
}

impl std::fmt::Display for ShardRecord {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(f, "{}/{}", self.index, self.count)
    }
}

impl Report {
    pub fn new() -> Self {
        Report {
            schema: REPORT_SCHEMA.into(),
            tool: Tool { name: env!("CARGO_PKG_NAME").into(), version: env!("CARGO_PKG_VERSION").into() },
            machine: Machine::this(),
            created: humantime::format_rfc3339_seconds(std::time::SystemTime::now()).to_string(),
            scenes: Vec::new(),
            runs: Vec::new(),
            schedule: None,
            shard: None,
        }
    }
}

impl Default for Report {
    fn default() -> Self {
        Self::new()
    }
}

/// A run with this label and no pixels, for the tests of reading and journaling reports.
#[cfg(test)]
pub(crate) fn test_run(label: &str) -> RunRecord {
    let counts = crate::metrics::Counts::default();
    RunRecord {
        scene: "a".into(),
        camera: "c".into(),
        light: "l".into(),
        technique: "t".into(),
        parameters: Default::default(),
        label: label.into(),
        resolution: 32,
        depth_format: "f32".into(),
        counts,
        rates: counts.rates(),
        timings: Default::default(),
        layer_memory_bytes: 0,
        reference: Default::default(),
        soft: None,
        pipeline: None,
        cascades: None,
        point_map: None,
        temporal: None,
    }
}
