//! The shading pass: one technique over every evaluated pixel of a G-buffer.

use super::{Sample, Technique};
use crate::raster::{DepthLayer, LightView};
use crate::trace::GBuffer;
use rayon::prelude::*;

/// What a shading pass reads besides the technique.
pub struct ShadeContext<'a> {
    pub gbuffer: &'a GBuffer,
    pub view: &'a LightView,
    pub nearest: &'a DepthLayer,
}

/// Visibility of every evaluated pixel, in the order of `gbuffer.evaluated`.
pub fn shade_evaluated(technique: &dyn Technique, ctx: &ShadeContext) -> Vec<f32> {
    let g = ctx.gbuffer;
    g.evaluated
        .par_iter()
        .with_min_len(4096)
        .map(|&i| {
            let s = Sample {
                position: g.position[i as usize],
                normal: g.normal[i as usize],
            };
            technique.visibility(&s, ctx.view, ctx.nearest)
        })
        .collect()
}
