//! The triangle budget of a scene being loaded, from a scene file or a glTF file alike.

use super::format::MAX_INSTANCED_TRIANGLES;
use crate::json_input::Problems;

/// Most triangles of a scene, in all and made by its procedural shapes together.
#[derive(Clone, Copy)]
pub(super) struct Limits {
    pub scene: u64,
    pub shapes: u64,
}

/// Triangles asked for so far (before degenerate ones are dropped), in all and by shapes:
/// checked before each mesh joins the scene and before each shape is built, so that a scene
/// over the limits fails with a message instead of exhausting memory. Each limit is named at the
/// first object over it only.
pub(super) struct Budget {
    limits: Limits,
    /// Unique triangles: what memory holds.
    total: u64,
    procedural: u64,
    /// Triangles counting every placement of instanced meshes: what the ids number.
    placed: u64,
}

impl Budget {
    pub(super) fn new(limits: Limits) -> Self {
        Budget { limits, total: 0, procedural: 0, placed: 0 }
    }

    /// Triangles the scene may still take.
    pub(super) fn remaining(&self) -> u64 {
        self.limits.scene.saturating_sub(self.total)
    }

    /// Whether a shape of `count` triangles may be built (reported before it is).
    pub(super) fn admit_shape(&mut self, object_path: &str, count: u64, problems: &mut Problems) -> bool {
        self.procedural += count;
        if self.procedural > self.limits.shapes {
            if self.procedural - count <= self.limits.shapes {
                let message = format!(
                    "the procedural shapes up to this one have {} triangles; a scene's shapes may have at \
                     most {} together",
                    self.procedural, self.limits.shapes
                );
                problems.report(&format!("{object_path}.shape"), message);
            }
            return false;
        }
        if self.total + count > self.limits.scene {
            self.over_scene_limit(&format!("{object_path}.shape"), count, problems);
            return false;
        }
        true
    }

    /// Whether a mesh of `count` triangles may join the scene `placements` times: stored once
    /// when it has several placements (instanced), each placement numbering its triangles; a
    /// problem is reported at `at`.
    pub(super) fn admit_mesh(
        &mut self,
        at: &str,
        count: u64,
        placements: usize,
        problems: &mut Problems,
    ) -> bool {
        if self.total.saturating_add(count) > self.limits.scene {
            self.over_scene_limit(at, count, problems);
            return false;
        }
        self.total += count;
        let before = self.placed;
        self.placed = self.placed.saturating_add(count.saturating_mul(placements as u64));
        if self.placed > MAX_INSTANCED_TRIANGLES {
            if before <= MAX_INSTANCED_TRIANGLES {
                let message = format!(
                    "the placements up to this one number {} triangles; a scene may number at most {}",
                    self.placed, MAX_INSTANCED_TRIANGLES
                );
                problems.report(at, message);
            }
            return false;
        }
        true
    }

    fn over_scene_limit(&mut self, at: &str, count: u64, problems: &mut Problems) {
        let before = self.total;
        self.total = self.total.saturating_add(count);
        if before <= self.limits.scene {
            let message = format!(
                "the objects up to this one have {} triangles; a scene may have at most {}",
                self.total, self.limits.scene
            );
            problems.report(at, message);
        }
    }
}
