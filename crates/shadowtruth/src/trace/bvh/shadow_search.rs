//! One shadow ray's search for an occluder, triangle by triangle, with a certificate: each
//! triangle the walk reaches is tested first in f32 (certified.rs), and only where f32 cannot
//! be sure, again in f64 relative to the exact point's f64 rounding. What neither can decide
//! is looked at once more against the definition: a triangle exactly in the plane of the
//! surface (Shewchuk's exact orientation test, the `robust` crate) or degenerate never occludes.
//! Whatever still remains makes the answer uncertain, unless a certain occluder turns up.

use super::certified::{CertifiedRay, Verdict, in_one_plane, known_in_one_plane, walk_limit};
use super::shadow_ray::ShadowRay;
use super::watertight::WatertightRay;
use crate::scene::is_degenerate;
use glam::Vec3;

/// The hard answer for one shadow ray.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum ShadowAnswer {
    Lit,
    /// A triangle certainly meets the segment.
    Shadowed {
        occluder: u32,
    },
    /// No triangle certainly meets it, and `triangle` may: too close to call even in f64.
    /// `likely_shadowed` is what the computed numbers say.
    Uncertain {
        triangle: u32,
        likely_shadowed: bool,
    },
}

impl ShadowAnswer {
    /// The best guess: shadowed when certain or likely.
    pub fn shadowed(self) -> bool {
        match self {
            ShadowAnswer::Lit => false,
            ShadowAnswer::Shadowed { .. } => true,
            ShadowAnswer::Uncertain { likely_shadowed, .. } => likely_shadowed,
        }
    }

    pub fn is_uncertain(self) -> bool {
        matches!(self, ShadowAnswer::Uncertain { .. })
    }
}

/// What one shadow ray's search has found so far. Its f32 test (`fast_test`) is passed to
/// `test` rather than kept: a packet decides most of its lanes' triangles itself (packet.rs), and
/// makes a lane's test only for the few it leaves.
#[derive(Clone, Copy)]
pub(in crate::trace) struct ShadowSearch<'r> {
    ray: &'r ShadowRay,
    occluder: Option<u32>,
    doubt: Option<(u32, bool)>,
}

impl<'r> ShadowSearch<'r> {
    pub(in crate::trace) fn new(ray: &'r ShadowRay) -> Self {
        ShadowSearch { ray, occluder: None, doubt: None }
    }

    /// The f32 certified test of `ray`, whose f32 form `walk` is (`walk_ray`).
    #[inline(always)]
    pub(in crate::trace) fn fast_test(ray: &ShadowRay, walk: &WatertightRay) -> CertifiedRay<f32> {
        // Rounding to f32 moves each coordinate by at most 2⁻²⁴ of itself (2⁻¹⁴⁹ below the
        // normal range); a direction already in f32 (a directional light's) does not move.
        let origin_error =
            ray.origin_error + 2f64.powi(-24) * ray.origin.abs().max_element() + 2f64.powi(-149);
        let direction_error = match walk.direction.as_dvec3() == ray.direction {
            true => ray.direction_error,
            false => ray.direction_error + 2f64.powi(-24),
        };
        CertifiedRay::of_walk(walk, origin_error, direction_error, ray.length, ray.length_error)
    }

    /// The f32 ray the walk follows (its node tests are conservative for the exact segment
    /// because every box is widened by the scene's `SceneBvh::segment_margin`).
    pub(in crate::trace) fn walk_ray(ray: &ShadowRay) -> (WatertightRay, f32) {
        let walk = WatertightRay::new(ray.origin.as_vec3a(), ray.direction.as_vec3a());
        (walk, walk_limit(ray.length, ray.length_error))
    }

    /// Tests the scene triangle `id` with the ray's f32 test `fast` (`fast_test`); true once
    /// the search is over (a certain occluder).
    #[inline(always)]
    pub(in crate::trace) fn test(&mut self, fast: &CertifiedRay<f32>, id: u32, v: &[Vec3; 3]) -> bool {
        if id == self.ray.skip_triangle {
            return false;
        }
        match fast.classify(&v.map(|p| p.to_array())) {
            Verdict::Miss => false,
            Verdict::Hit => {
                self.occluder = Some(id);
                true
            }
            Verdict::Doubt { .. } => self.test_precisely(id, v),
        }
    }

    #[cold]
    #[inline(never)]
    fn test_precisely(&mut self, id: u32, v: &[Vec3; 3]) -> bool {
        let ray = self.ray;
        // The pixels under a decal ask of the same coplanar pair, ray after ray.
        if known_in_one_plane(&ray.surface, v) {
            return false;
        }
        // Made here rather than kept: a packet holds eight searches, and doubts are rare.
        let precise = CertifiedRay::new(
            ray.origin.to_array(),
            ray.origin_error,
            ray.direction.to_array(),
            ray.direction_error,
            ray.length,
            ray.length_error,
        );
        match precise.classify(&v.map(|p| p.as_dvec3().to_array())) {
            Verdict::Miss => false,
            Verdict::Hit => {
                self.occluder = Some(id);
                true
            }
            Verdict::Doubt { likely_hit } => {
                // In the surface's plane: the segment, which leaves that plane at its start, meets such
                // a triangle at most at the surface point, which the definition does not count.
                if !is_degenerate(v) && !in_one_plane(&ray.surface, v) {
                    let doubt = self.doubt.get_or_insert((id, likely_hit));
                    doubt.1 |= likely_hit;
                }
                false
            }
        }
    }

    pub(in crate::trace) fn answer(&self) -> ShadowAnswer {
        match (self.occluder, self.doubt) {
            (Some(occluder), _) => ShadowAnswer::Shadowed { occluder },
            (None, Some((triangle, likely_shadowed))) => {
                ShadowAnswer::Uncertain { triangle, likely_shadowed }
            }
            (None, None) => ShadowAnswer::Lit,
        }
    }
}
