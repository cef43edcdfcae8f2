//! Which part of a plan's schedule one `run` does: the views of its shard (`shard.rs`), less the
//! maps that an interrupted report folder already holds in full (`run --resume`). A map — one
//! (view, resolution, depth format) — is the unit of resuming because its layers and its grid
//! figure are built from all of its runs together.

use super::Shard;
use shadowtruth::scene::ViewKey;
use std::collections::HashSet;

/// One (view, resolution, depth format) of the schedule.
#[derive(Clone, Debug, PartialEq, Eq, Hash)]
pub struct MapKey {
    pub scene: String,
    pub camera: String,
    pub light: String,
    pub resolution: u32,
    pub depth_format: String,
}

impl MapKey {
    pub fn new(view: ViewKey, resolution: u32, depth_format: &str) -> Self {
        MapKey {
            scene: view.scene.into(),
            camera: view.camera.into(),
            light: view.light.into(),
            resolution,
            depth_format: depth_format.into(),
        }
    }
}

/// The part of the schedule to run (the default: all of it).
#[derive(Clone, Debug, Default)]
pub struct Portion {
    pub shard: Option<Shard>,
    /// Maps already done, whose runs are not run again.
    pub done: HashSet<MapKey>,
}

impl Portion {
    /// Whether the view at `position` of the schedule belongs to this portion's shard.
    pub fn owns_view(&self, position: usize) -> bool {
        self.shard.is_none_or(|s| s.owns(position))
    }

    /// Whether the map is still to be run.
    pub fn runs_map(&self, view: ViewKey, resolution: u32, depth_format: &str) -> bool {
        self.done.is_empty() || !self.done.contains(&MapKey::new(view, resolution, depth_format))
    }
}
