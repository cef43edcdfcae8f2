//! Whether a primary ray's closest hit is certainly the exact one (docs/reference.md, "The
//! reference's uncertainty"). The camera's f32 origin and the pixel's f32 direction define the
//! ray exactly, so the certified test (certified.rs) runs with no origin or direction error:
//! the hit triangle must certainly be crossed, and a second walk over [0, t + δt] must find no
//! other triangle that may be crossed before it — f32 first, f64 where f32 cannot tell. Two
//! triangles in one plane crossed at one point tie exactly; the lowest scene id wins, as the
//! definition says, even where the f32 distances happened to differ. A ray that hits nothing
//! is certified by finding no triangle it may cross at all.

use super::certified::{CertifiedRay, Crossing, Verdict, in_one_plane};
use super::hit::Hit;
use super::node_test::NodeRay;
use super::scene_bvh::SceneBvh;
use super::scratch::TraversalScratch;
use super::walk::{ANY_ORDER, walk};
use super::watertight::WatertightRay;
use crate::scene::is_degenerate;
use glam::{Vec3, Vec3A};

/// What the certificate says of a primary ray's closest hit.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(in crate::trace) enum PrimaryCertainty {
    Certain,
    /// A triangle in the hit's plane, crossed at the same point, with a lower id: the exact
    /// closest hit.
    Tie(Hit),
    Uncertain,
}

/// The exact ray in f32 and in f64, as segments up to a distance.
struct RayForms {
    origin: Vec3,
    direction: Vec3,
}

impl RayForms {
    fn in_f32(&self, length: f64, length_error: f64) -> CertifiedRay<f32> {
        CertifiedRay::new(self.origin.to_array(), 0.0, self.direction.to_array(), 0.0, length, length_error)
    }

    fn in_f64(&self, length: f64, length_error: f64) -> CertifiedRay<f64> {
        let (o, d) = (self.origin.as_dvec3(), self.direction.as_dvec3());
        CertifiedRay::new(o.to_array(), 0.0, d.to_array(), 0.0, length, length_error)
    }

    /// Whether the ray crosses `v`: f32 first, then f64 where f32 is in doubt.
    fn crossing(&self, v: &[Vec3A; 3]) -> Crossing {
        match self.in_f32(f64::INFINITY, 0.0).crossing(&v.map(|p| p.to_array())) {
            Crossing::Doubt { .. } => {
                self.in_f64(f64::INFINITY, 0.0).crossing(&v.map(|p| p.as_dvec3().to_array()))
            }
            decided => decided,
        }
    }
}

impl SceneBvh {
    /// Certifies `hit`, the closest hit of the ray from `origin` along `direction`.
    pub(in crate::trace) fn certify_primary(
        &self,
        scratch: &mut TraversalScratch,
        origin: Vec3,
        direction: Vec3,
        hit: Option<&Hit>,
    ) -> PrimaryCertainty {
        let forms = RayForms { origin, direction };
        let (length, length_error, own) = match hit {
            Some(h) => {
                // In f64: f32's bound on the distance grows with the cube of the distance over
                // the triangle's projected area, too loose to order surfaces that nearly touch.
                let v = h.vertices.map(|p| p.as_dvec3().to_array());
                let Crossing::Through { t_lo, t_hi } = forms.in_f64(f64::INFINITY, 0.0).crossing(&v) else {
                    return PrimaryCertainty::Uncertain;
                };
                (0.5 * (t_lo + t_hi), 0.5 * (t_hi - t_lo), Some((h.triangle, h.vertices)))
            }
            None => (f64::INFINITY, 0.0, None),
        };
        let walk_ray = WatertightRay::new(origin.into(), direction.into());
        let fast = CertifiedRay::of_walk(&walk_ray, 0.0, 0.0, length, length_error);
        let mut precise: Option<CertifiedRay<f64>> = None;
        let mut verdict = PrimaryCertainty::Certain;
        let mut tie: Option<(u32, [Vec3; 3])> = None;
        // True (and the verdict uncertain) for a triangle certainly crossed before the hit, or
        // one that may be; an exact tie in the hit's plane is noted instead.
        let mut test = |id: u32, v: &[Vec3A; 3]| -> bool {
            if own.is_some_and(|(own_id, _)| own_id == id) {
                return false;
            }
            let mut verdict_f64 = || {
                let precise = precise.get_or_insert_with(|| forms.in_f64(length, length_error));
                precise.classify(&v.map(|p| p.as_dvec3().to_array()))
            };
            let in_doubt = match fast.classify(&v.map(|p| p.to_array())) {
                Verdict::Miss => return false,
                Verdict::Hit => false,
                Verdict::Doubt { .. } => match verdict_f64() {
                    Verdict::Miss => return false,
                    Verdict::Hit => false,
                    Verdict::Doubt { .. } => true,
                },
            };
            let triangle = v.map(Vec3::from);
            if in_doubt && is_degenerate(&triangle) {
                return false;
            }
            if let (true, Some((own_id, own_vertices))) = (in_doubt, own)
                && in_one_plane(&own_vertices, &triangle)
            {
                // Crossed, if at all, at the hit's own point: an exact tie, lowest id first.
                if id > own_id || tie.is_some_and(|(t, _)| t < id) {
                    return false;
                }
                match forms.crossing(v) {
                    Crossing::Miss => return false,
                    Crossing::Through { .. } => {
                        tie = Some((id, triangle));
                        return false;
                    }
                    Crossing::Doubt { .. } => {}
                }
            }
            verdict = PrimaryCertainty::Uncertain;
            true
        };
        let node_ray = NodeRay::new(walk_ray.origin, walk_ray.direction);
        let reach = length + length_error;
        let mut tmax = if reach.is_finite() { (reach as f32).next_up() } else { f32::INFINITY };
        let mut over = false;
        walk::<ANY_ORDER>(&self.tree, &mut scratch.outer, &node_ray, 0.0, &mut tmax, 0.0, |i, _| {
            over = test(self.scene_ids[i], &self.triangles[i]);
            over
        });
        if let (Some(instances), false) = (&self.instances, over) {
            instances.any_triangle(scratch, &walk_ray, tmax, &mut test);
        }
        match (verdict, tie) {
            (PrimaryCertainty::Certain, Some((id, vertices))) => tie_hit(&walk_ray, id, vertices),
            (verdict, _) => verdict,
        }
    }
}

/// `hit`'s barycentrics computed again in f64 and rounded to f32. The f32 watertight test's
/// are off by up to a few ulps of the edge functions over their sum, which on a sliver moves
/// the point along its long edges by more than the point's documented precision
/// (docs/reference.md, "The adjudicator"); in f64 the point lies within f32 rounding of the
/// ray's exact crossing.
pub(in crate::trace) fn refine_barycentrics(origin: Vec3, direction: Vec3, hit: &mut Hit) {
    let ray = RayForms { origin, direction }.in_f64(f64::INFINITY, 0.0);
    if let Some(b) = ray.barycentrics(&hit.vertices.map(|p| p.as_dvec3().to_array())) {
        hit.barycentric = b.map(|b| b as f32);
    }
}

/// The hit on triangle `id` (which ties with the tracer's), from the watertight test.
fn tie_hit(ray: &WatertightRay, id: u32, vertices: [Vec3; 3]) -> PrimaryCertainty {
    let [a, b, c] = vertices.map(Vec3A::from);
    match ray.intersect(a, b, c, 0.0, f32::INFINITY) {
        Some(h) => PrimaryCertainty::Tie(Hit { triangle: id, t: h.t, barycentric: h.barycentric, vertices }),
        None => PrimaryCertainty::Uncertain,
    }
}
