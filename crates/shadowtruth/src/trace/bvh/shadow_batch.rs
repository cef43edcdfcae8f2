//! Shadow rays gathered to be traced `WIDE_BATCH` at a time (`SceneBvh::shadow_occluded`,
//! which walks them together where it can): a tile's pixels in the hard reference, and a row's
//! light samples or sub-pixel surfaces (`RowShadows`) in the soft references, so that a pixel
//! with fewer rays than a batch does not trace a batch of its own.

use super::scene_bvh::{SceneBvh, WIDE_BATCH};
use super::scratch::TraversalScratch;
use super::shadow_ray::ShadowRay;
use glam::{DVec3, Vec3};

/// Up to `WIDE_BATCH` shadow rays, each with its caller's tag (a pixel's column, or
/// nothing), waiting to be traced.
pub(in crate::trace) struct ShadowBatch {
    tags: [usize; WIDE_BATCH],
    rays: [ShadowRay; WIDE_BATCH],
    len: usize,
}

/// What fills the slots beyond a batch's rays; never traced.
const UNUSED_RAY: ShadowRay = ShadowRay {
    origin: DVec3::ZERO,
    origin_error: 0.0,
    direction: DVec3::X,
    direction_error: 0.0,
    length: 0.0,
    length_error: 0.0,
    skip_triangle: u32::MAX,
    surface: [Vec3::ZERO; 3],
};

impl ShadowBatch {
    pub(in crate::trace) fn new() -> Self {
        ShadowBatch { tags: [0; WIDE_BATCH], rays: [UNUSED_RAY; WIDE_BATCH], len: 0 }
    }

    /// Adds `ray`; once the batch is full, traces it and calls `visible(tag, lit, uncertain)`
    /// for each ray (`lit` the best guess where `uncertain`).
    #[inline(always)]
    pub(in crate::trace) fn push(
        &mut self,
        bvh: &SceneBvh,
        scratch: &mut TraversalScratch,
        tag: usize,
        ray: ShadowRay,
        visible: impl FnMut(usize, bool, bool),
    ) {
        self.tags[self.len] = tag;
        self.rays[self.len] = ray;
        self.len += 1;
        if self.len == WIDE_BATCH {
            self.finish(bvh, scratch, visible);
        }
    }

    /// Traces the rays waiting, calls `visible(tag, lit, uncertain)` for each, and empties the
    /// batch.
    #[inline(never)]
    pub(in crate::trace) fn finish(
        &mut self,
        bvh: &SceneBvh,
        scratch: &mut TraversalScratch,
        mut visible: impl FnMut(usize, bool, bool),
    ) {
        if self.len == 0 {
            return;
        }
        let bits = bvh.shadow_answers(scratch, &self.rays[..self.len]);
        for (k, &tag) in self.tags[..self.len].iter().enumerate() {
            visible(tag, bits.occluded >> k & 1 == 0, bits.uncertain >> k & 1 != 0);
        }
        self.len = 0;
    }
}

/// A row's shadow rays, each under its pixel's column, traced `WIDE_BATCH` at a time
/// across the row's pixels, with each column's count of unoccluded rays.
pub(in crate::trace) struct RowShadows {
    batch: ShadowBatch,
    lit: Vec<u32>,
}

impl RowShadows {
    pub(in crate::trace) fn new(width: usize) -> Self {
        RowShadows { batch: ShadowBatch::new(), lit: vec![0; width] }
    }

    /// Adds the shadow ray of the pixel in column `x`.
    #[inline(always)]
    pub(in crate::trace) fn push(
        &mut self,
        bvh: &SceneBvh,
        scratch: &mut TraversalScratch,
        x: usize,
        ray: ShadowRay,
    ) {
        let lit = &mut self.lit;
        self.batch.push(bvh, scratch, x, ray, |x, visible, _| lit[x] += visible as u32);
    }

    /// Traces the rays still waiting: every count is final.
    pub(in crate::trace) fn finish(&mut self, bvh: &SceneBvh, scratch: &mut TraversalScratch) {
        let lit = &mut self.lit;
        self.batch.finish(bvh, scratch, |x, visible, _| lit[x] += visible as u32);
    }

    /// The unoccluded rays of column `x` (after `finish`).
    pub(in crate::trace) fn lit(&self, x: usize) -> u32 {
        self.lit[x]
    }

    /// Zero counts for the next row (after `finish`).
    pub(in crate::trace) fn clear(&mut self) {
        self.lit.fill(0);
    }
}
