//! The pixel-coverage reference: the hard visibility averaged over a pixel's footprint, what an
//! anti-aliased image should show, to judge filtered techniques against.
//!
//! For each pixel whose centre sample is evaluated, n×n primary rays go through the centres of an
//! n×n grid of sub-pixel strata (a box filter; fixed centres, no jitter, so a 1×1 grid is the
//! pixel-centre ray and reproduces the hard reference bit for bit). Each sub-ray hits its own
//! surface point, classified as in the G-buffer and shadow-tested exactly like the hard
//! reference. Sub-rays that hit nothing are left out of the mean (the pixel's visibility is that
//! of its surfaces); sub-samples on surfaces facing away from the light or outside a spot
//! light's cone count as shadowed.

use super::bvh::SceneBvh;
use super::gbuffer::{GBuffer, PixelClass, primary_sample};
use super::reference::hard_visible;
use super::sampling::stratum_centre;
use super::soft_reference::{SoftReference, mean_and_std_error};
use crate::scene::{Camera, Light, Scene};
use rayon::prelude::*;

/// Traces the coverage reference on an n×n sub-pixel grid (`grid` = n ≥ 1).
///
/// `gbuffer` must be the G-buffer of (`scene`, `camera`, `light`): it decides which pixels are
/// evaluated. Panics if `grid` is 0 (callers validate user input).
pub fn trace_coverage_reference(
    scene: &Scene,
    bvh: &SceneBvh,
    gbuffer: &GBuffer,
    camera: &Camera,
    light: &Light,
    grid: u32,
) -> SoftReference {
    assert!(grid >= 1, "the coverage grid must be at least 1×1");
    let m = grid * grid;
    let n = gbuffer.pixel_count();
    let w = gbuffer.width as usize;
    let basis = camera.basis();
    let mut visibility = vec![0f32; n];
    let mut std_error = vec![0f32; n];
    visibility.par_chunks_mut(w).zip(std_error.par_chunks_mut(w)).enumerate().for_each_init(
        || bvh.scratch(),
        |scratch, (y, (vis, err))| {
            for x in 0..w {
                let i = y * w + x;
                if gbuffer.class[i] != PixelClass::Evaluated {
                    continue;
                }
                let (mut hits, mut surfaces) = (0u32, 0u32);
                for k in 0..m {
                    let (sx, sy) = stratum_centre(k, grid);
                    let dir = camera.film_direction(&basis, x as f64 + sx, y as f64 + sy);
                    let Some(s) = primary_sample(scene, bvh, scratch, camera.position, dir, light) else {
                        continue;
                    };
                    surfaces += 1;
                    if s.class == PixelClass::Evaluated
                        && hard_visible(bvh, scratch, s.position, s.normal, light)
                    {
                        hits += 1;
                    }
                }
                (vis[x], err[x]) = if surfaces > 0 {
                    mean_and_std_error(hits, surfaces)
                } else {
                    // Only possible if no sub-ray reproduces the centre hit: fall back to the
                    // centre's hard visibility.
                    let lit = hard_visible(bvh, scratch, gbuffer.position[i], gbuffer.normal[i], light);
                    (lit as u32 as f32, 0.0)
                };
            }
        },
    );
    SoftReference { width: gbuffer.width, height: gbuffer.height, visibility, std_error, samples: m }
}
