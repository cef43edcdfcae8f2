//! The command back-end: the plan's `command` techniques, each a renderer run by its command
//! line (docs/engines.md). Per view and resolution the view is exported once (`view-export`'s
//! folder, into a temporary folder of the view); per setting the command runs once, writes its
//! visibility (and depth) there, and the files are read back and scored like `external`.

use super::command_process::run_command;
use super::imported::read_external;
use super::{MapBackend, ProducedRun, RunRecorder};
use crate::plan::events::TracedView;
use crate::plan::map_setting::MapSetting;
use crate::plan::{Plan, PlanError};
use crate::view_export::write_view_export;
use shadowtruth::metrics::Stopwatch;
use shadowtruth::technique::{CommandParams, CommandRun, ExternalParams, TechniqueSpec};
use std::path::{Path, PathBuf};

/// Views exported for renderers' commands, each (view, resolution) once, into one temporary
/// folder removed with this value. The schedule writes nothing of its own: these are the
/// renderers' inputs and outputs, not the plan's.
pub(crate) struct ExportedViews {
    folder: Option<tempfile::TempDir>,
    /// (camera, light, resolution) of each export, its index the export's folder name. The
    /// camera and light by identity (their addresses): names need not be unique across scenes.
    exported: Vec<(usize, usize, u32)>,
}

impl ExportedViews {
    pub fn new() -> Self {
        ExportedViews { folder: None, exported: Vec::new() }
    }

    /// The folder of `traced` exported at `resolution`, written the first time it is asked for,
    /// and a folder beside it for the `k`-th run of a command there.
    pub fn folders(
        &mut self,
        traced: &TracedView,
        resolution: u32,
        k: usize,
    ) -> Result<(PathBuf, PathBuf), PlanError> {
        if self.folder.is_none() {
            let folder = tempfile::Builder::new()
                .prefix("shadowtruth-engine-")
                .tempdir()
                .map_err(|source| PlanError::Io { path: std::env::temp_dir(), source })?;
            self.folder = Some(folder);
        }
        let root = self.folder.as_ref().expect("made above").path();
        let (camera, light) =
            (std::ptr::from_ref(traced.camera) as usize, std::ptr::from_ref(traced.light) as usize);
        let key = (camera, light, resolution);
        let index = match self.exported.iter().position(|e| *e == key) {
            Some(i) => i,
            None => {
                let dir = root.join(format!("view{}", self.exported.len()));
                write_view_export(traced.scene, traced.camera, traced.light, resolution, &dir, |_| ())
                    .map_err(|e| {
                        let view = view_name(traced);
                        PlanError::Invalid(format!("exporting {view} for a command technique: {e:#}"))
                    })?;
                self.exported.push(key);
                self.exported.len() - 1
            }
        };
        Ok((root.join(format!("view{index}")), root.join(format!("view{index}-run{k}"))))
    }
}

/// One command's visibility of every evaluated pixel, and the time its run took, ms.
type RenderedRun = (Vec<f32>, f64);

/// The command techniques of one view.
pub(in crate::plan) struct CommandBackend<'p> {
    techniques: Vec<&'p TechniqueSpec>,
    exports: ExportedViews,
    /// The last resolution's visibility of each technique and the time its run took: a
    /// renderer draws its own maps, so the plan's depth formats score the same images.
    ran: Option<(u32, Vec<RenderedRun>)>,
}

impl<'p> CommandBackend<'p> {
    /// The plan's command techniques; nothing is exported or run until a map asks.
    pub fn new(plan: &'p Plan) -> Self {
        let techniques = plan.techniques.iter().filter(|t| matches!(t, TechniqueSpec::Command(_))).collect();
        CommandBackend { techniques, exports: ExportedViews::new(), ran: None }
    }
}

impl MapBackend for CommandBackend<'_> {
    fn produce(
        &mut self,
        traced: &TracedView,
        map: &MapSetting,
        recorder: &mut dyn RunRecorder,
    ) -> Result<(), PlanError> {
        if self.techniques.is_empty() {
            return Ok(());
        }
        if self.ran.as_ref().is_none_or(|(resolution, _)| *resolution != map.resolution) {
            let runs = self.run_all(traced, map.resolution, recorder)?;
            self.ran = Some((map.resolution, runs));
        }
        let (_, runs) = self.ran.as_ref().expect("run above");
        for (spec, (visibility, ms)) in self.techniques.iter().zip(runs) {
            let produced = ProducedRun {
                spec,
                visibility,
                prepare_ms: *ms,
                shade_ms: 0.0,
                shade_range_ms: None,
                layer_memory_bytes: 0,
                pipeline: None,
            };
            recorder.record(produced)?;
        }
        Ok(())
    }
}

impl CommandBackend<'_> {
    /// Every command technique's run at `resolution`: its visibility and its time, ms.
    fn run_all(
        &mut self,
        traced: &TracedView,
        resolution: u32,
        recorder: &mut dyn RunRecorder,
    ) -> Result<Vec<RenderedRun>, PlanError> {
        let mut runs = Vec::with_capacity(self.techniques.len());
        for (k, spec) in self.techniques.iter().enumerate() {
            let TechniqueSpec::Command(params) = spec else { unreachable!("only command techniques") };
            recorder.stage(&format!("{}: running {}", view_name(traced), spec.label()))?;
            let sw = Stopwatch::start();
            let visibility = run_setting(&mut self.exports, params, traced, resolution, k, spec)?;
            runs.push((visibility, sw.ms()));
        }
        Ok(runs)
    }
}

fn view_name(traced: &TracedView) -> String {
    format!("{}/{}/{}", traced.scene.name, traced.camera.name, traced.light.name)
}

/// Runs one setting (`spec`, whose parameters are `params`) of a command for a view at
/// `resolution`, as the `k`-th run there, and reads back what it wrote: the visibility of every
/// evaluated pixel (NaN for a surface mismatch). Errors name the view, the technique and the
/// command.
pub(crate) fn run_setting(
    exports: &mut ExportedViews,
    params: &CommandParams,
    traced: &TracedView,
    resolution: u32,
    k: usize,
    spec: &TechniqueSpec,
) -> Result<Vec<f32>, PlanError> {
    let (view_dir, run_dir) = exports.folders(traced, resolution, k)?;
    run_and_read(params, traced, resolution, &view_dir, &run_dir)
        .map_err(|e| PlanError::Invalid(format!("{}: technique {}: {e}", view_name(traced), spec.label())))
}

/// Runs one setting of a command for a view and reads back what it wrote, as the visibility of
/// every evaluated pixel (NaN for a surface mismatch).
fn run_and_read(
    params: &CommandParams,
    traced: &TracedView,
    resolution: u32,
    view_dir: &Path,
    run_dir: &Path,
) -> Result<Vec<f32>, String> {
    std::fs::create_dir_all(run_dir).map_err(|e| format!("creating {}: {e}", run_dir.display()))?;
    let visibility_file = run_dir.join(format!("visibility.{}", params.visibility_format.extension()));
    let depth_file = run_dir.join("depth.exr");
    let text = |p: &Path| p.to_string_lossy().into_owned();
    let (view_text, visibility_text, depth_text) =
        (text(view_dir), text(&visibility_file), text(&depth_file));
    let argv = params.argv(&CommandRun {
        view_dir: &view_text,
        visibility_file: &visibility_text,
        depth_file: &depth_text,
        resolution,
        scene: &traced.scene.name,
        camera: &traced.camera.name,
        light: &traced.light.name,
    });
    run_command(&argv, run_dir, params.timeout_s()).map_err(|e| format!("`{}`: {e}", shown(&argv)))?;
    // What it wrote is read as an `external` technique's files.
    let files = ExternalParams {
        name: params.name.clone(),
        visibility: visibility_text,
        depth: params.writes_depth().then_some(depth_text),
        depth_tolerance: params.depth_tolerance,
        channel: None,
        flip_y: params.flip_y,
    };
    read_external(&files, traced)
        .map_err(|e| format!("`{}` ran, but what it wrote cannot be scored: {e}", shown(&argv)))
}

/// A command line as a person would type it (arguments with spaces quoted).
fn shown(argv: &[String]) -> String {
    let quote = |a: &String| if a.contains([' ', '"']) { format!("{a:?}") } else { a.clone() };
    argv.iter().map(quote).collect::<Vec<_>>().join(" ")
}
