//! Receiver-plane depth bias (Isidoro, "Shadow Mapping: GPU-based Tips and Techniques", GDC 2006;
//! docs/formulas.md, "Receiver-plane bias"). The receiver's depth is tilted along its own plane to
//! the point where the map was sampled: `z_c = z + z_u·(u_c − u) + z_v·(v_c − v)` at the centre
//! (u_c, v_c) of the texel that holds the receiver. A GPU takes (z_u, z_v) from screen-space
//! derivatives; we take them exactly from the hit triangle's plane in (u, v, d) space (planes stay
//! planes under the light's projection), through its projected vertices or, where one lies
//! behind the light, through points of the plane around the receiver. No clamp; `bias_depth`
//! adds a constant bias only when asked.

use super::canonical::CanonicalFields;
use super::params::non_negative;
use super::{
    LayerNeeds, Sample, ShadeContext, Technique, TechniqueParams, TechniqueSpecError, texel_at, texel_centre,
};
use crate::raster::{LightView, Projection};
use glam::{DVec2, DVec3, Vec3};
use serde::{Deserialize, Serialize};

pub struct ReceiverPlane {
    pub bias_depth: f32,
}

/// (∂d/∂u, ∂d/∂v) of the plane through a triangle's three projected vertices, in f64; None when
/// a vertex lies behind the light or the triangle is seen edge-on from the light.
pub fn receiver_plane_slope(view: &LightView, tri: &[Vec3; 3]) -> Option<(f64, f64)> {
    let p0 = view.project(tri[0])?.as_dvec3();
    let p1 = view.project(tri[1])?.as_dvec3();
    let p2 = view.project(tri[2])?.as_dvec3();
    slope_through(p0, p1, p2)
}

/// `receiver_plane_slope`, or, when a vertex lies behind a perspective light (a large floor
/// under a point light's face), the same plane's slope from three points of it around `point`
/// (in front of the light): d is affine in (u, v) over a plane, so any three of its points give
/// the slope. The points are `point` and two steps of 1 % of its view depth along the plane,
/// which keeps them in front of the light (the view depth changes by at most the step).
pub fn receiver_plane_slope_at(view: &LightView, tri: &[Vec3; 3], point: Vec3) -> Option<(f64, f64)> {
    if let Some(slope) = receiver_plane_slope(view, tri) {
        return Some(slope);
    }
    let (v0, v1, v2) = (tri[0].as_dvec3(), tri[1].as_dvec3(), tri[2].as_dvec3());
    let normal = (v1 - v0).cross(v2 - v0).try_normalize()?;
    let tangent = (v1 - v0).normalize();
    let bitangent = normal.cross(tangent);
    let clip_from_world = view.clip_from_world.as_dmat4();
    let project = |p: DVec3| match view.projection {
        // Not a matrix: the paraboloid's own map, in f32.
        Projection::Paraboloid => view.project(p.as_vec3()).map(Vec3::as_dvec3),
        _ => {
            let c = clip_from_world * p.extend(1.0);
            (c.w > 0.0).then(|| DVec3::new(0.5 * c.x / c.w + 0.5, 0.5 * c.y / c.w + 0.5, c.z / c.w))
        }
    };
    let p = point.as_dvec3();
    let step = 0.01 * view.view_depth(point) as f64;
    slope_through(project(p)?, project(p + step * tangent)?, project(p + step * bitangent)?)
}

/// (∂d/∂u, ∂d/∂v) of the plane through three projected points; None when they are collinear in
/// (u, v).
fn slope_through(p0: DVec3, p1: DVec3, p2: DVec3) -> Option<(f64, f64)> {
    let (e1, e2) = (p1 - p0, p2 - p0);
    let det = DVec2::new(e1.x, e1.y).perp_dot(DVec2::new(e2.x, e2.y));
    if det.abs() < 1e-300 {
        return None;
    }
    let z_u = (e1.z * e2.y - e2.z * e1.y) / det;
    let z_v = (e1.x * e2.z - e2.x * e1.z) / det;
    Some((z_u, z_v))
}

impl Technique for ReceiverPlane {
    fn layer_needs(&self) -> LayerNeeds {
        LayerNeeds::default()
    }

    fn visibility(&self, s: &Sample, ctx: &ShadeContext) -> f32 {
        let slope = receiver_plane_slope_at(ctx.view, &ctx.scene.triangle(s.triangle), s.position);
        self.test(s, ctx, slope)
    }

    /// The slope of a triangle whose vertices are all in front of the light does not depend on
    /// the receiver: it is computed once for a run of samples on one triangle.
    fn visibility_of_run(&self, samples: &[Sample], ctx: &ShadeContext, out: &mut [f32]) {
        let mut last: Option<(u32, Option<(f64, f64)>)> = None;
        for (s, v) in samples.iter().zip(out) {
            let of_vertices = match last {
                Some((triangle, slope)) if triangle == s.triangle => slope,
                _ => {
                    let slope = receiver_plane_slope(ctx.view, &ctx.scene.triangle(s.triangle));
                    last = Some((s.triangle, slope));
                    slope
                }
            };
            // `receiver_plane_slope_at`: the vertices' slope, or else the one around the receiver.
            let slope = of_vertices
                .or_else(|| receiver_plane_slope_at(ctx.view, &ctx.scene.triangle(s.triangle), s.position));
            *v = self.test(s, ctx, slope);
        }
    }
}

impl ReceiverPlane {
    /// The tilted comparison of `s` with its receiver plane's `slope` (None: untilted).
    #[inline]
    fn test(&self, s: &Sample, ctx: &ShadeContext, slope: Option<(f64, f64)>) -> f32 {
        let Some(uvd) = ctx.view.project(s.position) else { return 1.0 };
        let map = ctx.layers.nearest();
        let (x, row) = texel_at(map.resolution, uvd.x, uvd.y);
        let (u_c, v_c) = texel_centre(map.resolution, x, row);
        let z_c = match slope {
            Some((z_u, z_v)) => uvd.z + (z_u * (u_c - uvd.x) as f64 + z_v * (v_c - uvd.y) as f64) as f32,
            None => uvd.z,
        };
        (z_c - self.bias_depth <= map.at(x, row)) as u8 as f32
    }
}

/// `receiver_plane`: an optional constant `bias_depth` (light-depth units) on top of the tilt.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct ReceiverPlaneParams {
    #[serde(default)]
    pub bias_depth: f64,
}

impl TechniqueParams for ReceiverPlaneParams {
    fn validate(&self) -> Result<(), TechniqueSpecError> {
        non_negative("bias_depth", self.bias_depth)
    }

    fn build(&self) -> Option<Box<dyn Technique>> {
        Some(Box::new(ReceiverPlane { bias_depth: self.bias_depth as f32 }))
    }

    fn canonical_fields(&self, f: &mut CanonicalFields) {
        f.number("bias_depth", self.bias_depth)
    }
}
