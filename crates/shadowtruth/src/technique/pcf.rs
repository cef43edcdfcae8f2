//! Percentage-closer filtering (Reeves, Salesin & Cook 1987; docs/formulas.md, "PCF per-tap
//! biases and layer tests") with a bias per tap, on top of any depth-layer test, and the n-shadow
//! test of multiple-depth shadow maps.
//!
//! Every tap reads one texel and compares a receiver depth *for that texel* against the texel's
//! thresholds: the nearest depth, the depth-layer threshold (second depth, midpoint, dual), or the
//! n depths of an n-SM, where the tap passes the fraction of the n depths it is not behind
//! (Pagot, Comba & Oliveira 2004: PCF(k, n) over k taps then takes at most n·k + 1 values).
//!
//! Per-tap receiver depth:
//! - `constant`: d − b for every tap; `slope_scaled`: d, the offset being in the map.
//! - `receiver_plane` (Isidoro 2006): the receiver's plane (exact, from its triangle) at the tap
//!   texel's centre, minus an optional `bias_depth`.
//! - `adaptive` (Dou et al. 2014, per tap as Ehm et al. 2015 do): the potential occluder of the
//!   tap texel (the light's line through its centre meets the receiver's tangent plane) minus the
//!   adaptive epsilon at that depth.
//! - `adaptive_delta` (Ehm et al. 2015, Algorithm 1): three potential occluders per receiver, at
//!   its texel and one texel over in x and in y; every tap extrapolates
//!   `d_o = d_o0 + Δx·(x − x₀) + Δy·(row − row₀)` and subtracts the epsilon at its own `d_o`
//!   (the algorithm's per-tap `calculateAdaptiveEpsilon`).
//!
//! Both adaptive biases take the potential occluders from `TangentPlane` (`adaptive.rs`) with one
//! miss rule (`adaptive_taps`); they agree up to the rounding of the extrapolation (see
//! `TapDepth::Delta`).

use super::adaptive::{Epsilon, TangentPlane};
use super::canonical::CanonicalFields;
use super::filter_params::{KernelFields, TapBiasFields};
use super::kernel::{Kernel, hash};
use super::params::{err, non_negative, non_negative_opt};
use super::tap_bias::TapBias;
use super::{
    AdaptiveBias, DualDepth, EpsilonSpec, KernelSpec, LayerNeeds, Layers, Midpoint, ReferenceKind, Sample,
    SecondDepth, ShadeContext, TapBiasSpec, Technique, TechniqueParams, TechniqueSpecError,
    receiver_plane_slope_at,
};
use serde::{Deserialize, Serialize};

/// What a tap compares against, per texel.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum TapThreshold {
    /// The nearest (or, for second depth, the nearest unculled) depth.
    Nearest,
    /// `z1 + min((z2 − z1)/2, z_offset)` of the two nearest layers (∞: midpoint).
    TwoLayers { z_offset: f32 },
    /// The n depths of a multiple-depth map: the fraction passed.
    MultiDepth,
}

/// The receiver depth each tap compares, prepared once per receiver.
#[derive(Clone, Copy, Debug)]
pub enum TapDepth {
    Flat(f32),
    Affine(AffineDepth),
    /// `adaptive`: the potential occluder of each tap texel on the tangent plane, minus the
    /// epsilon at its depth.
    PerTapAdaptive {
        plane: TangentPlane,
        epsilon: Epsilon,
    },
    /// `adaptive_delta`: the potential occluders extrapolated linearly from three (Algorithm 1),
    /// each minus the epsilon at its own depth. The map holds d = z/w, affine in (u, v) over a
    /// plane under both projections, so this is the same plane's depth as `PerTapAdaptive`'s:
    /// the two differ by the f32 rounding of the extrapolation only (a few ulps of d), which
    /// decides a tap only where its texel holds a surface that close to the extrapolated plane.
    Delta {
        occluders: AffineDepth,
        epsilon: Epsilon,
    },
}

/// `d(x, row) = d0 + du·(x − x0) + dv·(row − row0)` over texel indices.
#[derive(Clone, Copy, Debug)]
pub struct AffineDepth {
    pub d0: f32,
    pub x0: i64,
    pub row0: i64,
    pub du: f32,
    pub dv: f32,
}

impl AffineDepth {
    #[inline]
    pub fn at(&self, x: i64, row: i64) -> f32 {
        self.d0 + self.du * (x - self.x0) as f32 + self.dv * (row - self.row0) as f32
    }
}

/// The adaptive tap depths of receiver `s` at depth `d` in texel (x0, row0): per tap, or as Ehm
/// et al.'s Algorithm 1 takes them (the potential occluders of the receiver's texel and of one
/// texel over in x and in y, extrapolated). The one miss rule of both: only a tangent plane the
/// light sees edge-on has no potential occluders, and then every tap compares `d` (minus the
/// epsilon there).
fn adaptive_taps(
    a: &AdaptiveBias,
    s: &Sample,
    ctx: &ShadeContext,
    d: f32,
    (x0, row0): (i64, i64),
    delta: bool,
) -> TapDepth {
    let epsilon = a.epsilon_of(s, ctx).unwrap_or(Epsilon::ZERO);
    let Some(plane) = TangentPlane::of(s, ctx) else { return TapDepth::Flat(epsilon.below(d)) };
    if !delta {
        return TapDepth::PerTapAdaptive { plane, epsilon };
    }
    let res = ctx.layers.resolution();
    let at = |x, row| plane.depth_at(ctx, texel_centre_of(res, x, row));
    let d0 = at(x0, row0);
    let (du, dv) = (at(x0 + 1, row0) - d0, at(x0, row0 + 1) - d0);
    let occluders = AffineDepth { d0: d0 as f32, x0, row0, du: du as f32, dv: dv as f32 };
    TapDepth::Delta { occluders, epsilon }
}

/// Light-map coordinates (u, v) of the centre of texel (x, row), for any (even off-map) texel.
#[inline]
pub fn texel_centre_of(resolution: u32, x: i64, row: i64) -> (f32, f32) {
    let n = resolution as f32;
    ((x as f32 + 0.5) / n, 1.0 - (row as f32 + 0.5) / n)
}

impl TapBias {
    /// The tap depths of receiver `s` at projected (u, v, d), texel (x0, row0).
    pub fn prepare(&self, s: &Sample, ctx: &ShadeContext, uvd: glam::Vec3, x0: i64, row0: i64) -> TapDepth {
        match self {
            TapBias::Constant { bias_depth } => TapDepth::Flat(uvd.z - bias_depth),
            TapBias::SlopeScaled => TapDepth::Flat(uvd.z),
            TapBias::ReceiverPlane { bias_depth } => {
                receiver_plane_taps(s, ctx, uvd, (x0, row0), *bias_depth)
            }
            TapBias::Adaptive(a) => adaptive_taps(a, s, ctx, uvd.z, (x0, row0), false),
            TapBias::AdaptiveDelta(a) => adaptive_taps(a, s, ctx, uvd.z, (x0, row0), true),
        }
    }
}

impl TapDepth {
    /// The depth tap (x, row) compares.
    #[inline]
    pub fn at(&self, ctx: &ShadeContext, x: i64, row: i64) -> f32 {
        match self {
            TapDepth::Flat(z) => *z,
            TapDepth::Affine(affine) => affine.at(x, row),
            TapDepth::PerTapAdaptive { plane, epsilon } => {
                let centre = texel_centre_of(ctx.layers.resolution(), x, row);
                epsilon.below(plane.depth_at(ctx, centre) as f32)
            }
            TapDepth::Delta { occluders, epsilon } => epsilon.below(occluders.at(x, row)),
        }
    }
}

/// The receiver's plane at every tap texel's centre, minus `bias_depth` (the flat `d − bias_depth`
/// when its triangle has no slope).
fn receiver_plane_taps(
    s: &Sample,
    ctx: &ShadeContext,
    uvd: glam::Vec3,
    (x0, row0): (i64, i64),
    bias_depth: f32,
) -> TapDepth {
    let Some((z_u, z_v)) = receiver_plane_slope_at(ctx.view, &ctx.scene.triangle(s.triangle), s.position)
    else {
        return TapDepth::Flat(uvd.z - bias_depth);
    };
    let res = ctx.layers.resolution();
    let (u_c, v_c) = texel_centre_of(res, x0, row0);
    let d0 = uvd.z as f64 + z_u * (u_c - uvd.x) as f64 + z_v * (v_c - uvd.y) as f64;
    // One texel right is +1/N in u; one row down is −1/N in v.
    let n = res as f64;
    TapDepth::Affine(AffineDepth {
        d0: (d0 - bias_depth as f64) as f32,
        x0,
        row0,
        du: (z_u / n) as f32,
        dv: (-z_v / n) as f32,
    })
}

/// The fraction of texel (x, row)'s thresholds that depth `d` passes (`d ≤ z`).
#[inline]
pub fn tap_pass(layers: &Layers, threshold: TapThreshold, x: u32, row: u32, d: f32) -> f32 {
    match (threshold, layers) {
        (TapThreshold::Nearest, _) => (d <= layers.nearest().at(x, row)) as u8 as f32,
        (TapThreshold::TwoLayers { z_offset }, _) => {
            let [z1, z2] = layers.two_nearest().at(x, row);
            (d <= z1 + ((z2 - z1) * 0.5).min(z_offset)) as u8 as f32
        }
        (TapThreshold::MultiDepth, Layers::MultiDepth(m)) => {
            let depths = m.at(x, row);
            depths.iter().filter(|&&z| d <= z).count() as f32 / depths.len() as f32
        }
        (TapThreshold::MultiDepth, _) => panic!("the technique asked for a multiple-depth map"),
    }
}

/// A per-receiver seed for jittered kernels: a hash of the receiver's position bits, so the same
/// receiver gets the same taps on every run and thread count.
#[inline]
pub fn receiver_seed(s: &Sample) -> u32 {
    hash(s.position.x.to_bits() ^ hash(s.position.y.to_bits() ^ hash(s.position.z.to_bits())))
}

/// A filtered shadow test: `kernel` taps, each biased by `bias` and tested against `threshold`.
pub struct Pcf {
    pub kernel: Kernel,
    /// Extent of Poisson and jitter kernels, in texels.
    pub radius_texels: f32,
    pub bias: TapBias,
    pub threshold: TapThreshold,
    /// The layers the threshold reads (and the polygon offset of `slope_scaled`).
    pub needs: LayerNeeds,
}

/// Σ weight · pass over the taps of `kernel` around projected receiver `uvd`.
pub fn filtered_visibility(
    kernel: &Kernel,
    radius_texels: f32,
    threshold: TapThreshold,
    s: &Sample,
    ctx: &ShadeContext,
    uvd: glam::Vec3,
    prepared: &TapDepth,
) -> f32 {
    let res = ctx.layers.resolution();
    let n = res as f32;
    let (xs, ys) = (uvd.x * n, (1.0 - uvd.y) * n);
    let last = res as i64 - 1;
    let mut visibility = 0.0;
    kernel.for_each_tap(xs, ys, radius_texels, receiver_seed(s), |x, row, w| {
        let d = prepared.at(ctx, x, row);
        let (cx, crow) = (x.clamp(0, last) as u32, row.clamp(0, last) as u32);
        visibility += w * tap_pass(&ctx.layers, threshold, cx, crow, d);
    });
    visibility.clamp(0.0, 1.0)
}

/// The receiver's texel (unclamped) in texel-space indices.
#[inline]
pub fn receiver_texel(resolution: u32, uvd: glam::Vec3) -> (i64, i64) {
    let n = resolution as f32;
    ((uvd.x * n).floor() as i64, ((1.0 - uvd.y) * n).floor() as i64)
}

impl Technique for Pcf {
    fn layer_needs(&self) -> LayerNeeds {
        self.needs
    }

    fn needs_projective_map(&self) -> bool {
        self.bias.needs_projective_map()
    }

    fn visibility(&self, s: &Sample, ctx: &ShadeContext) -> f32 {
        let Some(uvd) = ctx.view.project(s.position) else { return 1.0 };
        let (x0, row0) = receiver_texel(ctx.layers.resolution(), uvd);
        let prepared = self.bias.prepare(s, ctx, uvd, x0, row0);
        filtered_visibility(&self.kernel, self.radius_texels, self.threshold, s, ctx, uvd, &prepared)
    }
}

/// The depth-layer test under each PCF tap.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum LayerSpec {
    #[default]
    Nearest,
    SecondDepth,
    Midpoint,
    Dual,
}

fn is_nearest(l: &LayerSpec) -> bool {
    *l == LayerSpec::Nearest
}

/// A box of this side (in texels) when `pcf` names no size.
pub const DEFAULT_BOX_SIZE: u32 = 3;

/// `pcf`: the kernel, the per-tap bias (with `factor` and `units` for `slope_scaled`) and the
/// depth-layer test under each tap (with `z_offset` and `cull_back_faces` where it reads two
/// layers).
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct PcfParams {
    #[serde(default)]
    pub kernel: KernelSpec,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub size: Option<u32>,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub taps: Option<u32>,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub radius_texels: Option<f64>,
    #[serde(default)]
    pub bias: TapBiasSpec,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub bias_depth: Option<f64>,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub factor: Option<f64>,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub units: Option<f64>,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub k: Option<f64>,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub epsilon: Option<EpsilonSpec>,
    #[serde(default, skip_serializing_if = "is_nearest")]
    pub layers: LayerSpec,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub z_offset: Option<f64>,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub cull_back_faces: Option<bool>,
}

impl PcfParams {
    fn kernel_fields(&self) -> KernelFields {
        KernelFields {
            kernel: self.kernel,
            size: self.size,
            taps: self.taps,
            radius_texels: self.radius_texels,
        }
    }

    fn tap_bias_fields(&self) -> TapBiasFields {
        TapBiasFields { bias: self.bias, bias_depth: self.bias_depth, k: self.k, epsilon: self.epsilon }
    }

    /// `factor`/`units` only with bias slope_scaled, `z_offset`/`cull_back_faces` only with the
    /// layers that read two depths.
    fn validate_layers(&self) -> Result<(), TechniqueSpecError> {
        let slope = self.bias == TapBiasSpec::SlopeScaled;
        for (field, value) in [("factor", self.factor), ("units", self.units)] {
            if !slope && value.is_some() {
                return Err(err(field, "belongs to bias \"slope_scaled\""));
            }
            non_negative_opt(field, value)?;
        }
        match (self.layers, self.z_offset) {
            (LayerSpec::Dual, Some(z)) => non_negative("z_offset", z)?,
            (LayerSpec::Dual, None) => return Err(err("z_offset", "layers \"dual\" needs a z_offset ≥ 0")),
            (_, Some(_)) => return Err(err("z_offset", "belongs to layers \"dual\"")),
            _ => {}
        }
        if self.cull_back_faces.is_some() && !matches!(self.layers, LayerSpec::Midpoint | LayerSpec::Dual) {
            return Err(err("cull_back_faces", "belongs to layers \"midpoint\" and \"dual\""));
        }
        Ok(())
    }

    /// What each tap compares against and the layers it reads, as the depth-layer technique
    /// underneath asks for them, with the polygon offset of bias slope_scaled.
    fn threshold_and_needs(&self) -> (TapThreshold, LayerNeeds) {
        let cull = self.cull_back_faces.unwrap_or(false);
        let (threshold, mut needs) = match self.layers {
            LayerSpec::Nearest => (TapThreshold::Nearest, LayerNeeds::default()),
            LayerSpec::SecondDepth => (TapThreshold::Nearest, SecondDepth { bias_depth: 0.0 }.layer_needs()),
            LayerSpec::Midpoint => (
                TapThreshold::TwoLayers { z_offset: f32::INFINITY },
                Midpoint { cull_back_faces: cull }.layer_needs(),
            ),
            LayerSpec::Dual => {
                let z_offset = self.z_offset.unwrap_or(0.0) as f32;
                (
                    TapThreshold::TwoLayers { z_offset },
                    DualDepth { z_offset, cull_back_faces: cull }.layer_needs(),
                )
            }
        };
        if self.bias == TapBiasSpec::SlopeScaled {
            needs.slope_factor = self.factor.unwrap_or(0.0) as f32;
            needs.slope_units = self.units.unwrap_or(0.0) as f32;
        }
        (threshold, needs)
    }

    /// `factor` and `units` (0) with bias slope_scaled, `z_offset` (0) with dual layers,
    /// `cull_back_faces` (false) with midpoint and dual layers.
    fn canonical_layer_fields(&self, f: &mut CanonicalFields) {
        if self.bias == TapBiasSpec::SlopeScaled {
            f.number("factor", self.factor.unwrap_or(0.0));
            f.number("units", self.units.unwrap_or(0.0));
        } else {
            f.number_if_given("factor", self.factor);
            f.number_if_given("units", self.units);
        }
        f.named("layers", self.layers);
        match self.layers {
            LayerSpec::Dual => f.number("z_offset", self.z_offset.unwrap_or(0.0)),
            _ => f.number_if_given("z_offset", self.z_offset),
        }
        match (self.layers, self.cull_back_faces) {
            (LayerSpec::Midpoint | LayerSpec::Dual, c) => f.flag("cull_back_faces", c.unwrap_or(false)),
            (_, Some(c)) => f.flag("cull_back_faces", c),
            (_, None) => {}
        }
    }
}

impl TechniqueParams for PcfParams {
    fn validate(&self) -> Result<(), TechniqueSpecError> {
        self.kernel_fields().validate()?;
        self.tap_bias_fields().validate()?;
        self.validate_layers()
    }

    fn build(&self) -> Option<Box<dyn Technique>> {
        let (threshold, needs) = self.threshold_and_needs();
        let kernel = self.kernel_fields();
        Some(Box::new(Pcf {
            kernel: kernel.kernel(DEFAULT_BOX_SIZE),
            radius_texels: kernel.radius_texels(),
            bias: self.tap_bias_fields().tap_bias(),
            threshold,
            needs,
        }))
    }

    fn reference_kind(&self) -> ReferenceKind {
        ReferenceKind::Coverage
    }

    fn canonical_fields(&self, f: &mut CanonicalFields) {
        self.kernel_fields().canonical_fields(f, DEFAULT_BOX_SIZE);
        self.tap_bias_fields().canonical_fields(f);
        self.canonical_layer_fields(f);
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::raster::{DepthLayer, LightView};
    use crate::scene::{PixelFootprint, load_scene_str};
    use crate::technique::EpsilonScale;
    use glam::Vec3;
    use std::path::Path;

    #[test]
    fn delta_extrapolates_the_per_tap_potential_occluders_past_the_near_plane() {
        // A steep receiver at the top of the scene under a directional light: its taps reach in
        // front of the near plane, where both keep the plane's depth (no fallback).
        let text = r#"{ "format": "shadowtruth/scene/v1", "name": "t",
            "objects": [{ "name": "p", "shape": { "type": "plane", "size": [4, 4] } }],
            "cameras": [{ "name": "c", "position": [0, 5, 5], "look_at": [0, 0, 0], "fov_y_deg": 45, "width": 8, "height": 8 }],
            "lights": [{ "name": "sun", "type": "directional", "direction": [0.3, -1, 0.2] }] }"#;
        let scene = load_scene_str(text, Path::new("t.json"), Path::new(".")).unwrap();
        let view = LightView::new(&scene.lights[0], scene.bounds(), 32);
        let map = DepthLayer::new_empty(32);
        let ctx =
            ShadeContext::new(&scene, PixelFootprint::of(&scene.cameras[0]), &view, Layers::Nearest(&map));
        let s = Sample {
            position: Vec3::new(-1.0, 0.0, -1.0),
            normal: Vec3::new(-3.0, 1.0, -2.0).normalize(),
            triangle: 0,
        };
        let uvd = view.project(s.position).unwrap();
        let (x0, row0) = receiver_texel(32, uvd);
        let bias = || AdaptiveBias { k: 1e-4, epsilon: EpsilonScale::Ehm };
        let (per_tap, delta) = (TapBias::Adaptive(bias()), TapBias::AdaptiveDelta(bias()));
        let (pa, pd) = (per_tap.prepare(&s, &ctx, uvd, x0, row0), delta.prepare(&s, &ctx, uvd, x0, row0));
        assert!(matches!(pa, TapDepth::PerTapAdaptive { .. }) && matches!(pd, TapDepth::Delta { .. }));
        let mut before_near = 0;
        for row in row0 - 5..=row0 + 5 {
            for x in x0 - 5..=x0 + 5 {
                let (a, d) = (pa.at(&ctx, x, row), pd.at(&ctx, x, row));
                assert!((a - d).abs() <= 4.0 * f32::EPSILON * a.abs().max(1.0), "({x}, {row}): {a} vs {d}");
                before_near += (a < 0.0) as u32;
            }
        }
        assert!(before_near > 0);
    }
}
