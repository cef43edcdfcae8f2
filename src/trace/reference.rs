//! The exact hard reference: a pixel is lit when the segment from its surface point to the light
//! meets no triangle other than the ones that contain the point (docs/reference.md). The shadow
//! ray cannot hit its own surface (shadow_ray.rs); no scene-dependent epsilon enters.

use super::bvh::{RAYS_PER_BATCH, SceneBvh, TraversalScratch};
use super::gbuffer::{GBuffer, LightSight, PixelClass};
use super::shadow_ray::{ShadowRay, SurfacePoint};
use crate::scene::{Light, Scene};
use glam::Vec3;
use rayon::prelude::*;

/// The grey levels of a reference mask PNG (docs/conventions.md, "Reference mask PNG").
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
#[repr(u8)]
pub enum MaskCode {
    Shadowed = 0,
    FacingAway = 64,
    Background = 128,
    OutsideLight = 192,
    Lit = 255,
}

/// Hard visibility of every pixel: 1 lit, 0 shadowed (non-evaluated pixels hold 0).
pub struct HardReference {
    pub width: u32,
    pub height: u32,
    pub lit: Vec<u8>,
}

impl HardReference {
    /// The mask in the PNG encoding of `MaskCode`.
    pub fn mask_codes(&self, gbuffer: &GBuffer) -> Vec<u8> {
        gbuffer
            .class
            .iter()
            .zip(&self.lit)
            .map(|(c, &lit)| {
                (match c {
                    PixelClass::Background => MaskCode::Background,
                    PixelClass::FacingAway => MaskCode::FacingAway,
                    PixelClass::OutsideLight => MaskCode::OutsideLight,
                    PixelClass::Evaluated if lit != 0 => MaskCode::Lit,
                    PixelClass::Evaluated => MaskCode::Shadowed,
                }) as u8
            })
            .collect()
    }

    /// Rebuilds the visibility from a mask in the PNG encoding.
    pub fn from_mask_codes(width: u32, height: u32, codes: &[u8]) -> Self {
        HardReference {
            width,
            height,
            lit: codes.iter().map(|&c| (c == MaskCode::Lit as u8) as u8).collect(),
        }
    }
}

/// The shadow ray from a surface point to the light's centre.
pub fn hard_shadow_ray(point: &SurfacePoint, light: &Light) -> ShadowRay {
    shadow_ray_to_centre(point, &LightSight::of(light))
}

/// `hard_shadow_ray` for a light prepared once per trace.
pub(super) fn shadow_ray_to_centre(point: &SurfacePoint, light: &LightSight) -> ShadowRay {
    match *light {
        LightSight::Directional { towards } => ShadowRay::along(point, towards),
        LightSight::Spot { position, .. } => ShadowRay::to_point(point, position),
    }
}

/// Whether the segment from a surface point to the light's centre meets no other triangle, for
/// one point (the hard reference traces its rays in batches, `ShadowBatch`).
pub(super) fn hard_visible(
    bvh: &SceneBvh,
    scratch: &mut TraversalScratch,
    point: &SurfacePoint,
    light: &LightSight,
) -> bool {
    bvh.shadow_occluder(scratch, &shadow_ray_to_centre(point, light)).is_none()
}

/// What fills a batch's slots beyond its rays; never traced.
pub(super) const UNUSED_RAY: ShadowRay =
    ShadowRay { origin: Vec3::ZERO, direction: Vec3::X, tmax: 0.0, skip_triangle: u32::MAX };

/// Shadow rays of one row's pixels, gathered to be traced together.
struct ShadowBatch {
    columns: [usize; RAYS_PER_BATCH],
    rays: [ShadowRay; RAYS_PER_BATCH],
    len: usize,
}

impl ShadowBatch {
    fn new() -> Self {
        ShadowBatch { columns: [0; RAYS_PER_BATCH], rays: [UNUSED_RAY; RAYS_PER_BATCH], len: 0 }
    }

    fn push(&mut self, column: usize, ray: ShadowRay) {
        self.columns[self.len] = column;
        self.rays[self.len] = ray;
        self.len += 1;
    }

    fn is_full(&self) -> bool {
        self.len == RAYS_PER_BATCH
    }

    /// Writes each ray's visibility (1 lit) into its column of `row`, and empties the batch.
    fn trace_into(&mut self, bvh: &SceneBvh, scratch: &mut TraversalScratch, row: &mut [u8]) {
        let occluded = bvh.shadow_occluded(scratch, &self.rays[..self.len]);
        for (k, &x) in self.columns[..self.len].iter().enumerate() {
            row[x] = (occluded >> k & 1 == 0) as u8;
        }
        self.len = 0;
    }
}

/// Traces one shadow ray per evaluated pixel.
pub fn trace_hard_reference(
    scene: &Scene,
    bvh: &SceneBvh,
    gbuffer: &GBuffer,
    light: &Light,
) -> HardReference {
    let mut lit = vec![0u8; gbuffer.pixel_count()];
    let w = gbuffer.width as usize;
    let sight = LightSight::of(light);
    lit.par_chunks_mut(w).enumerate().for_each_init(
        || bvh.scratch(),
        |scratch, (y, row)| {
            // Up to `RAYS_PER_BATCH` evaluated pixels of the row, traced together.
            let mut batch = ShadowBatch::new();
            for x in 0..w {
                let i = y * w + x;
                if gbuffer.class[i] != PixelClass::Evaluated {
                    continue;
                }
                batch.push(x, shadow_ray_to_centre(&gbuffer.surface_point(scene, i), &sight));
                if batch.is_full() {
                    batch.trace_into(bvh, scratch, row);
                }
            }
            batch.trace_into(bvh, scratch, row);
        },
    );
    HardReference { width: gbuffer.width, height: gbuffer.height, lit }
}
