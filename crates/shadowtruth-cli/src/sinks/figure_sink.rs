//! The figures of a plan's runs, as a sink of the schedule's events: each view's reference
//! figure when it is traced; each run's technique and error figures (and zoom) and the grid of
//! one (view, resolution, depth format), drawn and encoded together in parallel once its runs
//! are done; for runs over a path, each run's animated error map as its frames arrive
//! (`frame_movie.rs`) and its flicker heat map when it ends (`flicker_map.rs`).

use crate::drawing::figures::{
    GridCell, ViewCanvas, downscale, grid, run_stem, view_stem, write_reference_figure, write_run_figures,
    zoom,
};
use crate::drawing::flicker_map::write_flicker_map;
use crate::drawing::frame_movie::FrameMovies;
use crate::drawing::indexed_image::IndexedImage;
use crate::plan::{Event, PlanError, Sink, TracedView};
use rayon::prelude::*;
use shadowtruth::metrics::Stopwatch;
use shadowtruth::raster::DepthFormat;
use shadowtruth::record::RunRecord;
use shadowtruth::scene::ViewKey;
use shadowtruth::technique::ReferenceKind;
use std::path::{Path, PathBuf};

/// Widest cell of the per-(view, resolution, depth format) grid figures, in pixels.
const GRID_CELL_WIDTH: u32 = 512;

/// A run waiting for its figures: (stem, caption, visibility, the reference it is judged by).
struct PendingRun {
    stem: String,
    caption: String,
    visibility: Vec<f32>,
    kind: ReferenceKind,
}

/// The file under `figures/` of the grid of one (view, resolution, depth format), written after
/// every figure of its runs: `run --resume` takes it as the sign that the map's figures are done.
/// `<view stem>.r<resolution>.<format>.grid.png`: the view's stem tells views apart, and the
/// format is one of the tool's own names.
pub fn grid_file_name(view: ViewKey, resolution: u32, depth_format: DepthFormat) -> String {
    format!("{}.r{resolution}.{}.grid.png", view_stem(view), depth_format.name())
}

/// Writes figures under a report folder's `figures/`.
pub struct FigureSink {
    dir: PathBuf,
    zoom: Option<[u32; 4]>,
    canvas: Option<ViewCanvas>,
    pending: Vec<PendingRun>,
    /// The animated error maps of the runs over a path being written.
    movies: FrameMovies,
    /// Wall time spent drawing and writing figures (the runs wait for it), milliseconds.
    spent_ms: f64,
}

impl FigureSink {
    /// Figures into `figures_dir`; `zoom` (x, y, width, height in camera pixels) is also
    /// written enlarged for every run.
    pub fn new(figures_dir: &Path, zoom: Option<[u32; 4]>) -> Self {
        FigureSink {
            dir: figures_dir.to_path_buf(),
            zoom,
            canvas: None,
            pending: Vec::new(),
            movies: FrameMovies::new(figures_dir),
            spent_ms: 0.0,
        }
    }

    /// Wall time spent on figures so far, milliseconds.
    pub fn spent_ms(&self) -> f64 {
        self.spent_ms
    }

    fn io(&self) -> impl FnOnce(std::io::Error) -> PlanError + use<> {
        let path = self.dir.clone();
        move |source| PlanError::Io { path, source }
    }

    fn view_traced(&mut self, view: &TracedView) -> Result<(), PlanError> {
        let sw = Stopwatch::start();
        let canvas = ViewCanvas::new(view.gbuffer, &view.references.hard, view.light);
        let stem = view_stem(view.key());
        write_reference_figure(&self.dir, &stem, view.gbuffer, &view.references.hard, &canvas)
            .map_err(self.io())?;
        self.canvas = Some(canvas);
        self.spent_ms += sw.ms();
        Ok(())
    }

    fn run_done(&mut self, record: &RunRecord, visibility: &[f32]) {
        self.pending.push(PendingRun {
            stem: run_stem(record),
            caption: format!("{}  error {:.3}%", record.label, 100.0 * record.rates.error),
            visibility: visibility.to_vec(),
            kind: record.reference.kind,
        });
    }

    /// One frame of a run over a path, appended to the run's animated error map.
    fn frame_done(
        &mut self,
        view: &TracedView,
        record: &RunRecord,
        visibility: &[f32],
        frame: (u32, u32),
    ) -> Result<(), PlanError> {
        let sw = Stopwatch::start();
        self.movies.frame_done(view, record, visibility, frame).map_err(self.io())?;
        self.spent_ms += sw.ms();
        Ok(())
    }

    /// The flicker heat map of a run over a path. Under a still camera every frame shows the same
    /// surfaces, so the heat is drawn over the last frame's shaded image; under a moving one no
    /// image fits every frame, and it is drawn over plain grey.
    fn flicker_done(&mut self, record: &RunRecord, heat: &[u16], size: (u32, u32)) -> Result<(), PlanError> {
        let sw = Stopwatch::start();
        let still_camera =
            record.temporal.as_ref().is_some_and(|t| matches!(t.moving.as_str(), "light" | "none"));
        let view = view_stem(ViewKey::new(&record.scene, &record.camera, &record.light));
        let base = if still_camera { self.movies.last_base(&view, size) } else { None };
        write_flicker_map(&self.dir, &run_stem(record), heat, size, base).map_err(self.io())?;
        self.spent_ms += sw.ms();
        Ok(())
    }

    /// Every pending run's figures, then the grid of their error maps.
    fn maps_done(
        &mut self,
        view: &TracedView,
        resolution: u32,
        format: DepthFormat,
    ) -> Result<(), PlanError> {
        let sw = Stopwatch::start();
        let pending = std::mem::take(&mut self.pending);
        let canvas = self.canvas.as_ref().expect("a view is traced before its runs");
        // Each run's grid cell is shrunk beside its figures, in parallel, so that only the small
        // cells are kept for the grid.
        let shrink = view.gbuffer.width.div_ceil(GRID_CELL_WIDTH).max(1);
        let cells: Vec<(String, IndexedImage)> = pending
            .par_iter()
            .map(|run| {
                let reference = view.references.for_kind(run.kind).0;
                let figures = write_run_figures(
                    &self.dir,
                    &run.stem,
                    view.gbuffer,
                    reference,
                    &run.visibility,
                    canvas,
                )?;
                if let Some([x, y, w, h]) = self.zoom {
                    let path = self.dir.join(format!("{}.error.zoom.png", run.stem));
                    zoom(&figures.error_image, (x, y, w, h), 4).write_png(&path)?;
                }
                Ok((run.caption.clone(), downscale(&figures.error_image, shrink)))
            })
            .collect::<std::io::Result<_>>()
            .map_err(self.io())?;
        let cells: Vec<GridCell> =
            cells.iter().map(|(caption, image)| GridCell { image, caption: caption.clone() }).collect();
        let path = self.dir.join(grid_file_name(view.key(), resolution, format));
        grid(&cells, 4, GRID_CELL_WIDTH).write_png(&path).map_err(self.io())?;
        self.spent_ms += sw.ms();
        Ok(())
    }
}

impl Sink for FigureSink {
    fn on_event(&mut self, event: &Event) -> Result<(), PlanError> {
        match event {
            Event::ViewTraced(view) => self.view_traced(view),
            Event::RunDone { record, visibility, .. } => {
                self.run_done(record, visibility);
                Ok(())
            }
            Event::MapsDone { view, resolution, format } => self.maps_done(view, *resolution, *format),
            Event::FrameDone { view, record, visibility, frame, frames } => {
                self.frame_done(view, record, visibility, (*frame, *frames))
            }
            Event::FlickerDone { record, heat, width, height } => {
                self.flicker_done(record, heat, (*width, *height))
            }
            Event::Planned { .. } | Event::Stage(_) | Event::SceneBuilt(_) => Ok(()),
        }
    }
}
