//! Percentage-closer soft shadows (Fernando 2005; docs/formulas.md, "PCSS", following the 2014
//! NVIDIA SoftShadows sample): a blocker search over the region of the map that can hide the
//! light from the receiver, the average blocker depth (averaged in map depth, converted to view
//! distance), a penumbra estimate from similar triangles, then PCF over a kernel scaled to it.
//!
//! - Spot light of radius R (perspective map): with W the frustum width at the near plane z_n and
//!   λ = R/W, the search radius is `λ·(z_r − z_n)/z_r` and the filter radius
//!   `λ·(z_r − z_b)/z_b·z_n/z_r` in map units (×N for texels).
//! - Directional light of angular diameter α (orthographic map): the search radius is
//!   `(z_r − z_n)·tan(α/2)` and the filter radius `(z_r − z_b)·tan(α/2)` in world units, over the
//!   texel size for texels (our derivation: docs/formulas.md, "PCSS").
//!
//! No blocker: lit. Every search tap a blocker: shadowed (the sample's early-outs). The blocker
//! test and the filter taps use the same per-tap bias (`receiver_plane` as in the sample, or
//! `adaptive_delta`).

use super::canonical::CanonicalFields;
use super::filter_params::TapBiasFields;
use super::kernel::{Kernel, POISSON_SIZES};
use super::params::err;
use super::pcf::{TapThreshold, filtered_visibility, receiver_seed, receiver_texel};
use super::tap_bias::TapBias;
use super::{
    EpsilonSpec, LayerNeeds, ReferenceKind, Sample, ShadeContext, TapBiasSpec, Technique, TechniqueParams,
    TechniqueSpecError,
};
use crate::raster::{LightSize, Projection};
use serde::{Deserialize, Serialize};

pub struct Pcss {
    pub search: Kernel,
    pub filter: Kernel,
    pub bias: TapBias,
}

impl Pcss {
    /// (search radius, light-size factor) in texels for a receiver at view distance `z_r`; the
    /// filter radius is `factor · penumbra(z_b)` (see [`Pcss::filter_radius_texels`]). None when
    /// the light has no size.
    fn search_radius_texels(ctx: &ShadeContext, z_r: f32) -> Option<f32> {
        let view = ctx.view;
        let n = view.resolution as f32;
        match (view.light_size?, view.projection) {
            (LightSize::AngularDiameterDeg(a), Projection::Orthographic { left, right, bottom, top }) => {
                let texel_world = (right - left).max(top - bottom) / n;
                Some((z_r - view.near).max(0.0) * (0.5 * a).to_radians().tan() / texel_world)
            }
            (LightSize::Radius(r), Projection::Perspective { tan_half_fov }) => {
                let lambda = r / (2.0 * view.near * tan_half_fov);
                Some(lambda * (z_r - view.near).max(0.0) / z_r * n)
            }
            _ => None,
        }
    }

    fn filter_radius_texels(ctx: &ShadeContext, z_r: f32, z_b: f32) -> Option<f32> {
        let view = ctx.view;
        let n = view.resolution as f32;
        match (view.light_size?, view.projection) {
            (LightSize::AngularDiameterDeg(a), Projection::Orthographic { left, right, bottom, top }) => {
                let texel_world = (right - left).max(top - bottom) / n;
                Some((z_r - z_b).max(0.0) * (0.5 * a).to_radians().tan() / texel_world)
            }
            (LightSize::Radius(r), Projection::Perspective { tan_half_fov }) => {
                let lambda = r / (2.0 * view.near * tan_half_fov);
                Some(lambda * (z_r - z_b).max(0.0) / z_b.max(1e-20) * view.near / z_r * n)
            }
            _ => None,
        }
    }
}

/// View distance of light depth `d` (the inverse of `LightView::depth_of_view_depth`).
fn view_distance(ctx: &ShadeContext, d: f32) -> f32 {
    let (n, f) = (ctx.view.near, ctx.view.far);
    match ctx.view.projection {
        Projection::Orthographic { .. } | Projection::Paraboloid => n + d * (f - n),
        Projection::Perspective { .. } => f * n / (f - d * (f - n)),
    }
}

impl Technique for Pcss {
    fn layer_needs(&self) -> LayerNeeds {
        LayerNeeds::default()
    }

    /// The search and filter radii come from the frustum's size.
    fn needs_projective_map(&self) -> bool {
        true
    }

    fn visibility(&self, s: &Sample, ctx: &ShadeContext) -> f32 {
        let Some(uvd) = ctx.view.project(s.position) else { return 1.0 };
        let z_r = ctx.view.view_depth(s.position);
        let Some(search_radius) = Self::search_radius_texels(ctx, z_r) else { return 1.0 };
        let res = ctx.layers.resolution();
        let (x0, row0) = receiver_texel(res, uvd);
        let prepared = self.bias.prepare(s, ctx, uvd, x0, row0);
        let map = ctx.layers.nearest();
        let last = res as i64 - 1;
        let n = res as f32;
        let (xs, ys) = (uvd.x * n, (1.0 - uvd.y) * n);
        let (mut blockers, mut sum_depth) = (0u32, 0.0f32);
        self.search.for_each_tap(xs, ys, search_radius, receiver_seed(s), |x, row, _| {
            let d = prepared.at(ctx, x, row);
            let z = map.at(x.clamp(0, last) as u32, row.clamp(0, last) as u32);
            if z < d {
                blockers += 1;
                sum_depth += z;
            }
        });
        if blockers == 0 {
            return 1.0;
        }
        if blockers == self.search.taps() {
            return 0.0;
        }
        let z_b = view_distance(ctx, sum_depth / blockers as f32);
        let Some(radius) = Self::filter_radius_texels(ctx, z_r, z_b) else { return 1.0 };
        filtered_visibility(&self.filter, radius, TapThreshold::Nearest, s, ctx, uvd, &prepared)
    }
}

fn default_taps() -> u32 {
    25
}

fn default_bias() -> TapBiasSpec {
    TapBiasSpec::ReceiverPlane
}

/// `pcss`: `search_taps` Poisson taps (16, 25, 32), `filter_taps` (16, 25, 32 Poisson; another
/// square k² a regular k×k grid) and the per-tap `bias` of both.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct PcssParams {
    #[serde(default = "default_taps")]
    pub search_taps: u32,
    #[serde(default = "default_taps")]
    pub filter_taps: u32,
    #[serde(default = "default_bias")]
    pub bias: TapBiasSpec,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub bias_depth: Option<f64>,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub k: Option<f64>,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub epsilon: Option<EpsilonSpec>,
}

impl PcssParams {
    fn tap_bias_fields(&self) -> TapBiasFields {
        TapBiasFields { bias: self.bias, bias_depth: self.bias_depth, k: self.k, epsilon: self.epsilon }
    }

    /// The filter kernel: a Poisson set, or a regular grid for another square.
    fn filter(&self) -> Kernel {
        let taps = self.filter_taps;
        if POISSON_SIZES.contains(&taps) {
            Kernel::Poisson { taps }
        } else {
            Kernel::Grid { size: (taps as f64).sqrt().round() as u32 }
        }
    }

    fn validate_taps(&self) -> Result<(), TechniqueSpecError> {
        if !POISSON_SIZES.contains(&self.search_taps) {
            return Err(err("search_taps", "must be 16, 25 or 32 (the Poisson sets)"));
        }
        let (taps, root) = (self.filter_taps, (self.filter_taps as f64).sqrt().round() as u32);
        if !POISSON_SIZES.contains(&taps) && (root * root != taps || !(2..=16).contains(&root)) {
            return Err(err("filter_taps", "must be 16, 25, 32 (Poisson) or a square from 4 to 256 (grid)"));
        }
        if matches!(self.bias, TapBiasSpec::SlopeScaled | TapBiasSpec::Adaptive) {
            return Err(err("bias", "pcss takes bias constant, receiver_plane or adaptive_delta"));
        }
        Ok(())
    }
}

impl TechniqueParams for PcssParams {
    fn validate(&self) -> Result<(), TechniqueSpecError> {
        self.validate_taps()?;
        self.tap_bias_fields().validate()
    }

    fn build(&self) -> Option<Box<dyn Technique>> {
        Some(Box::new(Pcss {
            search: Kernel::Poisson { taps: self.search_taps },
            filter: self.filter(),
            bias: self.tap_bias_fields().tap_bias(),
        }))
    }

    fn reference_kind(&self) -> ReferenceKind {
        ReferenceKind::AreaLight
    }

    fn canonical_fields(&self, f: &mut CanonicalFields) {
        f.count("search_taps", self.search_taps);
        f.count("filter_taps", self.filter_taps);
        self.tap_bias_fields().canonical_fields(f);
    }
}
