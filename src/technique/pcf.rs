//! Percentage-closer filtering (Reeves, Salesin & Cook 1987; formulas.md §6) with a bias per tap,
//! on top of any depth-layer test, and the n-shadow test of multiple-depth shadow maps.
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
//!   tap texel (the light ray through its centre meets the receiver's tangent plane) minus the
//!   adaptive epsilon at that depth.
//! - `adaptive_delta` (Ehm et al. 2015, Algorithm 1): three potential occluders per receiver, at
//!   its texel and one texel over in x and in y; every tap extrapolates
//!   `d_o + Δx·(x − x₀) + Δy·(row − row₀)` minus the epsilon of the receiver's texel.

use super::adaptive::potential_occluder_depth;
use super::kernel::{Kernel, hash};
use super::{AdaptiveBias, LayerNeeds, Layers, Sample, ShadeContext, Technique, receiver_plane_slope};

/// How each tap's receiver depth is biased.
pub enum TapBias {
    Constant {
        bias_depth: f32,
    },
    /// glPolygonOffset applied to the map (see `LayerNeeds`); the taps compare plainly.
    SlopeScaled,
    ReceiverPlane {
        bias_depth: f32,
    },
    Adaptive(AdaptiveBias),
    AdaptiveDelta(AdaptiveBias),
}

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
    /// `d(x, row) = d0 + du·(x − x0) + dv·(row − row0)` over texel indices.
    Affine {
        d0: f32,
        x0: i64,
        row0: i64,
        du: f32,
        dv: f32,
    },
    /// The potential occluder of every tap texel, minus the epsilon there.
    PerTapAdaptive,
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
        let res = ctx.layers.resolution();
        match self {
            TapBias::Constant { bias_depth } => TapDepth::Flat(uvd.z - bias_depth),
            TapBias::SlopeScaled => TapDepth::Flat(uvd.z),
            TapBias::ReceiverPlane { bias_depth } => {
                match receiver_plane_slope(ctx.view, &ctx.scene.triangles[s.triangle as usize]) {
                    Some((z_u, z_v)) => {
                        let (u_c, v_c) = texel_centre_of(res, x0, row0);
                        let d0 = uvd.z as f64 + z_u * (u_c - uvd.x) as f64 + z_v * (v_c - uvd.y) as f64;
                        // One texel right is +1/N in u; one row down is −1/N in v.
                        let n = res as f64;
                        TapDepth::Affine {
                            d0: (d0 - *bias_depth as f64) as f32,
                            x0,
                            row0,
                            du: (z_u / n) as f32,
                            dv: (-z_v / n) as f32,
                        }
                    }
                    None => TapDepth::Flat(uvd.z - bias_depth),
                }
            }
            TapBias::Adaptive(_) => TapDepth::PerTapAdaptive,
            TapBias::AdaptiveDelta(a) => {
                let at = |x, row| potential_occluder_depth(s, ctx, texel_centre_of(res, x, row));
                let d_o = at(x0, row0);
                let epsilon = a.epsilon(s, ctx, d_o.unwrap_or(uvd.z)).unwrap_or(0.0);
                match (d_o, at(x0 + 1, row0), at(x0, row0 + 1)) {
                    (Some(d0), Some(dx), Some(dy)) => {
                        TapDepth::Affine { d0: d0 - epsilon, x0, row0, du: dx - d0, dv: dy - d0 }
                    }
                    _ => TapDepth::Flat(d_o.unwrap_or(uvd.z) - epsilon),
                }
            }
        }
    }

    /// The depth tap (x, row) compares.
    #[inline]
    pub fn depth_at(
        &self,
        prepared: &TapDepth,
        s: &Sample,
        ctx: &ShadeContext,
        x: i64,
        row: i64,
        d: f32,
    ) -> f32 {
        match *prepared {
            TapDepth::Flat(z) => z,
            TapDepth::Affine { d0, x0, row0, du, dv } => d0 + du * (x - x0) as f32 + dv * (row - row0) as f32,
            TapDepth::PerTapAdaptive => {
                let TapBias::Adaptive(a) = self else { return d };
                let res = ctx.layers.resolution();
                let d_o = potential_occluder_depth(s, ctx, texel_centre_of(res, x, row)).unwrap_or(d);
                d_o - a.epsilon(s, ctx, d_o).unwrap_or(0.0)
            }
        }
    }
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
#[allow(clippy::too_many_arguments)]
pub fn filtered_visibility(
    kernel: &Kernel,
    radius_texels: f32,
    bias: &TapBias,
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
        let d = bias.depth_at(prepared, s, ctx, x, row, uvd.z);
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

    fn visibility(&self, s: &Sample, ctx: &ShadeContext) -> f32 {
        let Some(uvd) = ctx.view.project(s.position) else { return 1.0 };
        let (x0, row0) = receiver_texel(ctx.layers.resolution(), uvd);
        let prepared = self.bias.prepare(s, ctx, uvd, x0, row0);
        filtered_visibility(
            &self.kernel,
            self.radius_texels,
            &self.bias,
            self.threshold,
            s,
            ctx,
            uvd,
            &prepared,
        )
    }
}
