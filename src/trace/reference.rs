//! The exact hard reference: a pixel is lit when the segment from its surface point to the light
//! hits no triangle. The origin is offset by `offset_ray_origin`, never by a scene epsilon.

use super::bvh::{SceneBvh, TraversalScratch};
use super::gbuffer::{GBuffer, PixelClass, to_light};
use super::offset::offset_ray_origin;
use crate::scene::{Light, LightKind};
use glam::Vec3;
use rayon::prelude::*;

/// The grey levels of a reference mask PNG (DESIGN.md, `shadowtruth reference`).
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

/// Whether the segment from surface point `p` (unit geometric normal `n`, on the side the shadow
/// ray leaves towards) to the light's centre hits no triangle. Shared by the hard reference and
/// the sub-pixel samples of the pixel-coverage reference.
pub(super) fn hard_visible(
    bvh: &SceneBvh,
    scratch: &mut TraversalScratch,
    p: Vec3,
    n: Vec3,
    light: &Light,
) -> bool {
    let origin = offset_ray_origin(p, n);
    let (dir, tmax) = match &light.kind {
        LightKind::Directional { .. } => (to_light(light, p.as_dvec3()).as_vec3(), f32::INFINITY),
        LightKind::Spot { position, .. } => {
            let to = position.as_dvec3() - origin.as_dvec3();
            (to.normalize().as_vec3(), to.length() as f32)
        }
    };
    !bvh.occluded(scratch, origin, dir, 0.0, tmax)
}

/// Traces one shadow ray per evaluated pixel.
pub fn trace_hard_reference(bvh: &SceneBvh, gbuffer: &GBuffer, light: &Light) -> HardReference {
    let mut lit = vec![0u8; gbuffer.pixel_count()];
    let w = gbuffer.width as usize;
    lit.par_chunks_mut(w).enumerate().for_each_init(
        || bvh.scratch(),
        |scratch, (y, row)| {
            for (x, out) in row.iter_mut().enumerate() {
                let i = y * w + x;
                if gbuffer.class[i] != PixelClass::Evaluated {
                    continue;
                }
                *out = hard_visible(bvh, scratch, gbuffer.position[i], gbuffer.normal[i], light) as u8;
            }
        },
    );
    HardReference { width: gbuffer.width, height: gbuffer.height, lit }
}
