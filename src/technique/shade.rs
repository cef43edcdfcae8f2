//! The shading pass: one technique over every evaluated pixel of a G-buffer.

use super::{Layers, Sample, Technique};
use crate::raster::LightView;
use crate::scene::Scene;
use crate::trace::GBuffer;
use glam::Mat4;
use rayon::prelude::*;

/// What a technique reads besides the sample, prepared once per shading pass.
pub struct ShadeContext<'a> {
    pub scene: &'a Scene,
    pub view: &'a LightView,
    pub layers: Layers<'a>,
    /// The inverse of `view.clip_from_world`: light rays through texel centres.
    pub world_from_clip: Mat4,
    /// The length of the scene's bounding-box diagonal (Dou et al.'s sceneScale).
    pub scene_scale: f32,
}

impl<'a> ShadeContext<'a> {
    pub fn new(scene: &'a Scene, view: &'a LightView, layers: Layers<'a>) -> Self {
        let (lo, hi) = scene.bounds();
        ShadeContext {
            scene,
            view,
            layers,
            world_from_clip: view.clip_from_world.inverse(),
            scene_scale: (hi - lo).length(),
        }
    }
}

/// Visibility of every evaluated pixel, in the order of `gbuffer.evaluated`.
pub fn shade_evaluated(technique: &dyn Technique, gbuffer: &GBuffer, ctx: &ShadeContext) -> Vec<f32> {
    let g = gbuffer;
    g.evaluated
        .par_iter()
        .with_min_len(4096)
        .map(|&i| {
            let i = i as usize;
            let s = Sample { position: g.position[i], normal: g.normal[i], triangle: g.triangle[i] };
            technique.visibility(&s, ctx)
        })
        .collect()
}
