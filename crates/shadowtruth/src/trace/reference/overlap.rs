//! Where occluders overlap in the light's view: per shadowed pixel, whether the line from the
//! light to its surface point crosses surfaces of two different objects before it arrives. A
//! filterable map's *light bleeding* is false lit at such pixels: the filter mixes the depths of
//! the two occluders, and the mixture's variance lets light through (Lauritzen and McCool 2008,
//! "Layered variance shadow maps"). The attribution (`metrics::attribution`) names the false lit
//! pixels there, away from shadow boundaries, `light_bleeding`.
//!
//! This is a diagnostic, not the reference: the surfaces are found by closest hits from the
//! light's side (nearest first), each search starting just past the last surface found, up to
//! `MAX_SURFACES`; the receiver's own triangle and anything at or past its point end the walk.
//! Two surfaces of one closed object (its entry and exit) are one occluder.

use super::gbuffer::{GBuffer, LightSight, PixelClass};
use crate::scene::{Light, Scene};
use crate::trace::bvh::scene_bvh::SceneBvh;
use rayon::prelude::*;

/// The surfaces looked at along one line before giving up (a line through many surfaces of one
/// object, a mesh folded on itself).
const MAX_SURFACES: usize = 8;

/// Per pixel (row-major), whether its shadow line crosses two objects' surfaces.
#[derive(Clone, Debug, Default, PartialEq, Eq)]
pub struct ShadowOverlap {
    overlapped: Vec<bool>,
}

impl ShadowOverlap {
    /// Whether pixel `i`'s shadow line crosses surfaces of two different objects.
    pub fn at(&self, i: usize) -> bool {
        self.overlapped.get(i).copied().unwrap_or(false)
    }

    /// The overlapped pixels.
    pub fn count(&self) -> usize {
        self.overlapped.iter().filter(|&&o| o).count()
    }
}

/// Finds, for every evaluated pixel that `shadowed` (the pixels some reference shadows, by
/// index), whether its line to the light crosses two objects (see the module documentation).
pub fn trace_shadow_overlap(
    scene: &Scene,
    bvh: &SceneBvh,
    gbuffer: &GBuffer,
    light: &Light,
    shadowed: impl Fn(usize) -> bool + Sync,
) -> ShadowOverlap {
    let sight = LightSight::of(light);
    let (lo, hi) = bvh.scene_bounds();
    let reach = (hi - lo).length().max(1.0) as f64 * 2.0;
    let w = gbuffer.width.max(1) as usize;
    let mut overlapped = vec![false; gbuffer.pixel_count()];
    overlapped.par_chunks_mut(w).enumerate().for_each_init(
        || bvh.scratch(),
        |scratch, (y, row)| {
            for (x, out) in row.iter_mut().enumerate() {
                let i = y * w + x;
                if gbuffer.class[i] != PixelClass::Evaluated || !shadowed(i) {
                    continue;
                }
                let p = gbuffer.position[i].as_dvec3();
                // The line from the light (or from beyond the scene, towards a directional light)
                // to p.
                let start = match sight {
                    LightSight::Directional { towards } => p + towards * reach,
                    LightSight::Spot { position, .. } | LightSight::Point { position, .. } => position,
                };
                let offset = p - start;
                let length = offset.length();
                if length.is_nan() || length <= 0.0 {
                    continue;
                }
                let direction = (offset / length).as_vec3();
                let mut first_object = None;
                let mut tmin = 0.0f32;
                for _ in 0..MAX_SURFACES {
                    let Some(hit) = bvh.closest_hit(scratch, start.as_vec3(), direction, tmin, length as f32)
                    else {
                        break;
                    };
                    // The receiver's own surface, or anything at its point, ends the line.
                    if hit.triangle == gbuffer.triangle[i] || hit.t as f64 >= length * (1.0 - 1e-6) {
                        break;
                    }
                    let object = scene.object_of(hit.triangle);
                    match first_object {
                        None => first_object = Some(object),
                        Some(first) if first != object => {
                            *out = true;
                            break;
                        }
                        Some(_) => {}
                    }
                    tmin = next_after(hit.t);
                }
            }
        },
    );
    ShadowOverlap { overlapped }
}

/// The smallest f32 above `t` (≥ 0), where the next search starts.
fn next_after(t: f32) -> f32 {
    f32::from_bits(t.max(0.0).to_bits() + 1)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_next_search_starts_one_ulp_on() {
        assert_eq!(next_after(1.0), 1.0 + f32::EPSILON);
        assert!(next_after(0.0) > 0.0);
    }
}
