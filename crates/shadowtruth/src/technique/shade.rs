//! The shading pass: one technique over every evaluated pixel of a G-buffer.

use super::{Layers, Sample, Technique};
use crate::raster::LightView;
use crate::scene::{PixelFootprint, Scene};
use crate::trace::GBuffer;
use glam::{DMat4, Mat4, Vec3};
use rayon::prelude::*;

/// What a technique reads besides the sample, prepared once per shading pass.
pub struct ShadeContext<'a> {
    pub scene: &'a Scene,
    pub view: &'a LightView,
    pub layers: Layers<'a>,
    /// The inverse of `view.clip_from_world`: light rays through texel centres.
    pub world_from_clip: Mat4,
    /// The same inverse in f64, for the PCF taps' potential occluders.
    pub world_from_clip_f64: DMat4,
    /// The length of the scene's bounding-box diagonal (Dou et al.'s sceneScale).
    pub scene_scale: f32,
    /// The camera's pixel footprint (the G-buffer's), for the techniques that filter over it.
    pub footprint: PixelFootprint,
}

impl<'a> ShadeContext<'a> {
    /// The context of shading pixels seen with `footprint` (their G-buffer's) through `view`.
    pub fn new(scene: &'a Scene, footprint: PixelFootprint, view: &'a LightView, layers: Layers<'a>) -> Self {
        Self::with_bounds(scene, footprint, view, layers, scene.bounds())
    }

    /// As [`ShadeContext::new`], with the scene's bounds computed once by the caller (they walk
    /// every triangle, every placement of an instanced mesh included).
    pub fn with_bounds(
        scene: &'a Scene,
        footprint: PixelFootprint,
        view: &'a LightView,
        layers: Layers<'a>,
        bounds: (Vec3, Vec3),
    ) -> Self {
        ShadeContext {
            scene,
            view,
            layers,
            world_from_clip: view.clip_from_world.inverse(),
            world_from_clip_f64: view.clip_from_world.as_dmat4().inverse(),
            scene_scale: (bounds.1 - bounds.0).length(),
            footprint,
        }
    }
}

/// The order in which to shade the evaluated pixels of one G-buffer for one light view: sorted
/// by the shadow-map texel each receiver projects to, so that depth-map reads walk the map row
/// by row instead of jumping across it (camera order is random order for the map). Built once
/// per (camera, light, resolution) and shared by every technique.
pub struct ShadeOrder {
    /// Samples of the G-buffer's sample arrays, in shading order.
    samples: Vec<Sample>,
    /// `slot[j]`: the position in `gbuffer.evaluated` of the j-th sample shaded.
    slot: Vec<u32>,
}

impl ShadeOrder {
    pub fn new(gbuffer: &GBuffer, view: &LightView) -> Self {
        Self::of_pixels(gbuffer, view, (0..gbuffer.evaluated.len() as u32).collect())
    }

    /// The order of some of the evaluated pixels: `slots` are positions in `gbuffer.evaluated`
    /// (a cascade's pixels).
    pub fn of_pixels(gbuffer: &GBuffer, view: &LightView, slots: Vec<u32>) -> Self {
        let n = view.resolution as u64;
        let mut keyed: Vec<u64> = slots
            .into_par_iter()
            .map(|k| {
                let i = gbuffer.evaluated[k as usize];
                let texel = match view.project(gbuffer.position[i as usize]) {
                    Some(uvd) => {
                        let (x, row) = super::texel_at(view.resolution, uvd.x, uvd.y);
                        row as u64 * n + x as u64
                    }
                    None => n * n,
                };
                (texel << 32) | k as u64
            })
            .collect();
        keyed.par_sort_unstable();
        let slot: Vec<u32> = keyed.iter().map(|&key| key as u32).collect();
        let samples = slot
            .par_iter()
            .map(|&k| {
                let i = gbuffer.evaluated[k as usize] as usize;
                Sample {
                    position: gbuffer.position[i],
                    normal: gbuffer.normal[i],
                    triangle: gbuffer.triangle[i],
                }
            })
            .collect();
        ShadeOrder { samples, slot }
    }
}

/// Visibility of every evaluated pixel, in the order of `gbuffer.evaluated`, shaded in `order`.
pub fn shade_evaluated(technique: &dyn Technique, order: &ShadeOrder, ctx: &ShadeContext) -> Vec<f32> {
    let mut visibility = vec![0.0; order.slot.len()];
    shade_into(technique, order, ctx, &mut visibility);
    visibility
}

/// Samples per parallel task, shaded as one run (`Technique::visibility_of_run`).
const SHADE_RUN: usize = 4096;

/// Samples shaded in parallel before they are put in `gbuffer.evaluated` order: a buffer of this
/// many rather than one the size of the image (64 MiB at 4096², beside the visibility it fills).
const SHADE_BLOCK: usize = 256 * SHADE_RUN;

/// Shades the pixels of `order` into `visibility` (indexed as `gbuffer.evaluated`), leaving the
/// other entries as they are.
pub fn shade_into(technique: &dyn Technique, order: &ShadeOrder, ctx: &ShadeContext, visibility: &mut [f32]) {
    let mut shaded = vec![0.0; order.samples.len().min(SHADE_BLOCK)];
    for (samples, slots) in order.samples.chunks(SHADE_BLOCK).zip(order.slot.chunks(SHADE_BLOCK)) {
        let shaded = &mut shaded[..samples.len()];
        shaded
            .par_chunks_mut(SHADE_RUN)
            .zip(samples.par_chunks(SHADE_RUN))
            .for_each(|(out, samples)| technique.visibility_of_run(samples, ctx, out));
        for (&k, &v) in slots.iter().zip(shaded.iter()) {
            visibility[k as usize] = v;
        }
    }
}
