//! The filterable shadow maps (docs/formulas.md, "Filterable shadow maps"): the map stores
//! moments of a warped depth, blurred and read with bilinear filtering, and the receiver's
//! visibility is reconstructed from the filtered moments.
//!
//! - `vsm`: variance shadow maps (Donnelly & Lauritzen, I3D 2006), Chebyshev's bound with a
//!   minimum variance and light-bleeding reduction (Lauritzen, GPU Gems 3 ch. 8, 2007);
//! - `esm`: exponential shadow maps (Annen, Mertens, Seidel, Flerackers & Kautz, GI 2008);
//! - `evsm2`, `evsm4`: exponential variance shadow maps with the positive warp, or both
//!   (Lauritzen & McCool, "Layered Variance Shadow Maps", GI 2008), the minimum variance scaled
//!   by the warp's slope as in MJP's Shadows sample;
//! - `msm`: the four-moment Hamburger moment shadow map (Peters & Klein, I3D 2015).
//!
//! Their output is a filtered visibility: they are scored against the pixel-coverage reference,
//! like PCF.

use super::canonical::CanonicalFields;
use super::moment_tests::{chebyshev_upper_bound, hamburger_shadow_intensity, reduce_bleeding, saturate};
use super::params::{err, non_negative};
use super::{
    LayerNeeds, ReferenceKind, Sample, ShadeContext, Technique, TechniqueParams, TechniqueSpecError,
};
use crate::raster::{
    MAX_BLUR_RADIUS_TEXELS, MapBlur, MomentWarp, evsm_negative, evsm_positive, level_of_detail,
};
use glam::Vec3;
use serde::{Deserialize, Serialize};

/// The moments a filterable technique reads and how they are filtered.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct MomentNeeds {
    pub warp: MomentWarp,
    pub blur: MapBlur,
    /// Whether the blurred map has a mip chain, read trilinearly at the pixel's footprint.
    pub mipmaps: bool,
}

/// How a filterable technique turns filtered moments into visibility.
#[derive(Clone, Copy, Debug, PartialEq)]
enum Reconstruction {
    Vsm { min_variance: f32, bleeding_reduction: f32 },
    Esm { exponent: f32 },
    Evsm { positive: f32, negative: Option<f32>, variance_bias: f32, bleeding_reduction: f32 },
    Msm { moment_bias: f32, depth_bias: f32, bleeding_reduction: f32 },
}

pub struct Filterable {
    needs: MomentNeeds,
    reconstruction: Reconstruction,
}

impl Technique for Filterable {
    fn layer_needs(&self) -> LayerNeeds {
        LayerNeeds { moments: Some(self.needs), ..LayerNeeds::default() }
    }

    fn visibility(&self, s: &Sample, ctx: &ShadeContext) -> f32 {
        let Some(uvd) = ctx.view.project(s.position) else { return 1.0 };
        let layer = ctx.layers.moments();
        let m = if self.needs.mipmaps {
            layer.sample_at_lod(uvd.x, uvd.y, footprint_lod(s, ctx, uvd, layer.resolution()))
        } else {
            layer.sample(uvd.x, uvd.y)
        };
        visibility_from_moments(self.reconstruction, m, uvd.z)
    }
}

/// The level of detail at which a GPU reads a map of `resolution` texels a side for the pixel of
/// `s` (at map position `uvd`): from the differences between its map coordinates and those of its
/// neighbours to the right and below on the same plane (`PixelFootprint`), each projected as the
/// pixel is. +∞ (the last level) where a neighbour has no footprint or no projection.
#[inline]
pub fn footprint_lod(s: &Sample, ctx: &ShadeContext, uvd: Vec3, resolution: u32) -> f32 {
    let difference = |neighbour: Option<glam::DVec3>| {
        let uv = ctx.view.project(neighbour?.as_vec3())?;
        Some([uv.x - uvd.x, uv.y - uvd.y])
    };
    let [right, down] = ctx.footprint.neighbours(s.position, s.normal);
    match (difference(right), difference(down)) {
        (Some(dx), Some(dy)) => level_of_detail(resolution, dx, dy),
        _ => f32::INFINITY,
    }
}

/// The visibility of a receiver at light depth `d` under filtered moments `m`.
fn visibility_from_moments(r: Reconstruction, m: [f32; 4], d: f32) -> f32 {
    match r {
        Reconstruction::Vsm { min_variance, bleeding_reduction } => {
            reduce_bleeding(chebyshev_upper_bound(m[0], m[1], d, min_variance), bleeding_reduction)
        }
        // Annen et al. eq. 5: s(d) = e^{−c·d} · E[e^{c·z}], saturated.
        Reconstruction::Esm { exponent } => saturate(m[0] * (-exponent * d).exp()),
        Reconstruction::Evsm { positive, negative, variance_bias, bleeding_reduction } => {
            let bound = |mean: f32, second: f32, warped: f32, exponent: f32| {
                let scale = variance_bias * exponent * warped;
                chebyshev_upper_bound(mean, second, warped, scale * scale)
            };
            let mut p = bound(m[0], m[1], evsm_positive(d, positive), positive);
            if let Some(negative) = negative {
                p = p.min(bound(m[2], m[3], evsm_negative(d, negative), negative));
            }
            reduce_bleeding(p, bleeding_reduction)
        }
        Reconstruction::Msm { moment_bias, depth_bias, bleeding_reduction } => {
            let shadow = hamburger_shadow_intensity(m, d - depth_bias, moment_bias);
            reduce_bleeding(1.0 - shadow, bleeding_reduction)
        }
    }
}

/// The map filtering every filterable technique takes: `blur` (`box` by default, `gaussian` or
/// `none`) over `blur_radius_texels` (default 1: a 3×3 box), and `mipmaps` (default false:
/// level 0 read bilinearly; true: the blurred map's mip chain read trilinearly).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum BlurSpec {
    None,
    #[default]
    Box,
    Gaussian,
}

const DEFAULT_BLUR_RADIUS_TEXELS: u32 = 1;

/// The technique that reads `warp`'s moments under the blur and mipmaps a spec names.
fn filterable(
    warp: MomentWarp,
    (blur, radius, mipmaps): (BlurSpec, Option<u32>, bool),
    reconstruction: Reconstruction,
) -> Option<Box<dyn Technique>> {
    let needs = MomentNeeds { warp, blur: map_blur(blur, radius), mipmaps };
    Some(Box::new(Filterable { needs, reconstruction }))
}

fn map_blur(blur: BlurSpec, radius: Option<u32>) -> MapBlur {
    let radius_texels = radius.unwrap_or(DEFAULT_BLUR_RADIUS_TEXELS);
    match blur {
        BlurSpec::None => MapBlur::None,
        BlurSpec::Box => MapBlur::Box { radius_texels },
        BlurSpec::Gaussian => MapBlur::Gaussian { radius_texels },
    }
}

fn check_blur(blur: BlurSpec, radius: Option<u32>) -> Result<(), TechniqueSpecError> {
    match (blur, radius) {
        (BlurSpec::None, Some(_)) => {
            Err(err("blur_radius_texels", "is read only with a blur (box or gaussian)"))
        }
        (_, Some(r)) if r > MAX_BLUR_RADIUS_TEXELS => {
            Err(err("blur_radius_texels", format!("must be at most {MAX_BLUR_RADIUS_TEXELS}, found {r}")))
        }
        _ => Ok(()),
    }
}

/// The map's filtering fields; `mipmaps` only when on, so that the names of maps without them
/// are what they were before mipmaps existed.
fn filtering_fields(f: &mut CanonicalFields, blur: BlurSpec, radius: Option<u32>, mipmaps: bool) {
    f.named("blur", blur);
    if blur != BlurSpec::None {
        f.count("blur_radius_texels", radius.unwrap_or(DEFAULT_BLUR_RADIUS_TEXELS));
    }
    if mipmaps {
        f.flag("mipmaps", true);
    }
}

/// A bleeding reduction in [0, 1).
fn check_bleeding(x: f64) -> Result<(), TechniqueSpecError> {
    if x.is_finite() && (0.0..1.0).contains(&x) {
        Ok(())
    } else {
        Err(err("bleeding_reduction", format!("must be a number in [0, 1), found {x}")))
    }
}

/// An exponent in (0, `max`]: beyond it e^{c} (or e^{2c} for a second moment) overflows f32.
fn check_exponent(field: &'static str, x: f64, max: f64) -> Result<(), TechniqueSpecError> {
    if x.is_finite() && x > 0.0 && x <= max {
        Ok(())
    } else {
        Err(err(field, format!("must be in (0, {max}] (larger overflows a 32-bit float), found {x}")))
    }
}

/// The largest ESM exponent (e^{88} < f32::MAX < e^{89}) and EVSM exponent (its second moment
/// is e^{2c}).
const MAX_ESM_EXPONENT: f64 = 88.0;
const MAX_EVSM_EXPONENT: f64 = 44.0;

/// `vsm`: `min_variance` (light-depth units², default 1e-5), `bleeding_reduction` (default 0),
/// and the map's filtering.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct VsmParams {
    #[serde(default = "default_vsm_min_variance")]
    pub min_variance: f64,
    #[serde(default)]
    pub bleeding_reduction: f64,
    #[serde(default)]
    pub blur: BlurSpec,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub blur_radius_texels: Option<u32>,
    #[serde(default, skip_serializing_if = "std::ops::Not::not")]
    pub mipmaps: bool,
}

fn default_vsm_min_variance() -> f64 {
    1e-5
}

impl TechniqueParams for VsmParams {
    fn validate(&self) -> Result<(), TechniqueSpecError> {
        non_negative("min_variance", self.min_variance)?;
        check_bleeding(self.bleeding_reduction)?;
        check_blur(self.blur, self.blur_radius_texels)
    }

    fn build(&self) -> Option<Box<dyn Technique>> {
        let reconstruction = Reconstruction::Vsm {
            min_variance: self.min_variance as f32,
            bleeding_reduction: self.bleeding_reduction as f32,
        };
        filterable(MomentWarp::Depth2, (self.blur, self.blur_radius_texels, self.mipmaps), reconstruction)
    }

    fn reference_kind(&self) -> ReferenceKind {
        ReferenceKind::Coverage
    }

    fn canonical_fields(&self, f: &mut CanonicalFields) {
        f.number("min_variance", self.min_variance);
        f.number("bleeding_reduction", self.bleeding_reduction);
        filtering_fields(f, self.blur, self.blur_radius_texels, self.mipmaps);
    }
}

/// `esm`: the `exponent` c (default 80, at most 88) and the map's filtering.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct EsmParams {
    #[serde(default = "default_esm_exponent")]
    pub exponent: f64,
    #[serde(default)]
    pub blur: BlurSpec,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub blur_radius_texels: Option<u32>,
    #[serde(default, skip_serializing_if = "std::ops::Not::not")]
    pub mipmaps: bool,
}

fn default_esm_exponent() -> f64 {
    80.0
}

impl TechniqueParams for EsmParams {
    fn validate(&self) -> Result<(), TechniqueSpecError> {
        check_exponent("exponent", self.exponent, MAX_ESM_EXPONENT)?;
        check_blur(self.blur, self.blur_radius_texels)
    }

    fn build(&self) -> Option<Box<dyn Technique>> {
        let exponent = self.exponent as f32;
        let warp = MomentWarp::Exponential { exponent };
        filterable(warp, (self.blur, self.blur_radius_texels, self.mipmaps), Reconstruction::Esm { exponent })
    }

    fn reference_kind(&self) -> ReferenceKind {
        ReferenceKind::Coverage
    }

    fn canonical_fields(&self, f: &mut CanonicalFields) {
        f.number("exponent", self.exponent);
        filtering_fields(f, self.blur, self.blur_radius_texels, self.mipmaps);
    }
}

/// `evsm2` and `evsm4`: the warps' exponents (`positive_exponent` default 40,
/// `negative_exponent` default 5, evsm4 only; each at most 44), `variance_bias` (default 0.01:
/// the minimum variance is (variance_bias · c · warped depth)²), `bleeding_reduction` (default
/// 0) and the map's filtering.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct EvsmParams {
    #[serde(default = "default_positive_exponent")]
    pub positive_exponent: f64,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub negative_exponent: Option<f64>,
    #[serde(default = "default_variance_bias")]
    pub variance_bias: f64,
    #[serde(default)]
    pub bleeding_reduction: f64,
    #[serde(default)]
    pub blur: BlurSpec,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub blur_radius_texels: Option<u32>,
    #[serde(default, skip_serializing_if = "std::ops::Not::not")]
    pub mipmaps: bool,
}

fn default_positive_exponent() -> f64 {
    40.0
}

const DEFAULT_NEGATIVE_EXPONENT: f64 = 5.0;

fn default_variance_bias() -> f64 {
    0.01
}

/// `evsm2` (the positive warp) and `evsm4` (both): one parameter struct, two names.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(transparent)]
pub struct Evsm2Params(pub EvsmParams);

#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(transparent)]
pub struct Evsm4Params(pub EvsmParams);

impl EvsmParams {
    fn validate(&self, four: bool) -> Result<(), TechniqueSpecError> {
        check_exponent("positive_exponent", self.positive_exponent, MAX_EVSM_EXPONENT)?;
        match (four, self.negative_exponent) {
            (false, Some(_)) => return Err(err("negative_exponent", "is read by evsm4 only")),
            (true, Some(c)) => check_exponent("negative_exponent", c, MAX_EVSM_EXPONENT)?,
            _ => {}
        }
        non_negative("variance_bias", self.variance_bias)?;
        check_bleeding(self.bleeding_reduction)?;
        check_blur(self.blur, self.blur_radius_texels)
    }

    fn build(&self, four: bool) -> Option<Box<dyn Technique>> {
        let positive = self.positive_exponent as f32;
        let negative = four.then(|| self.negative_exponent.unwrap_or(DEFAULT_NEGATIVE_EXPONENT) as f32);
        let warp = match negative {
            Some(negative) => MomentWarp::Evsm4 { positive, negative },
            None => MomentWarp::Evsm2 { positive },
        };
        let reconstruction = Reconstruction::Evsm {
            positive,
            negative,
            variance_bias: self.variance_bias as f32,
            bleeding_reduction: self.bleeding_reduction as f32,
        };
        filterable(warp, (self.blur, self.blur_radius_texels, self.mipmaps), reconstruction)
    }

    fn canonical_fields(&self, f: &mut CanonicalFields, four: bool) {
        f.number("positive_exponent", self.positive_exponent);
        if four {
            f.number("negative_exponent", self.negative_exponent.unwrap_or(DEFAULT_NEGATIVE_EXPONENT));
        }
        f.number("variance_bias", self.variance_bias);
        f.number("bleeding_reduction", self.bleeding_reduction);
        filtering_fields(f, self.blur, self.blur_radius_texels, self.mipmaps);
    }
}

impl TechniqueParams for Evsm2Params {
    fn validate(&self) -> Result<(), TechniqueSpecError> {
        self.0.validate(false)
    }

    fn build(&self) -> Option<Box<dyn Technique>> {
        self.0.build(false)
    }

    fn reference_kind(&self) -> ReferenceKind {
        ReferenceKind::Coverage
    }

    fn canonical_fields(&self, f: &mut CanonicalFields) {
        self.0.canonical_fields(f, false)
    }
}

impl TechniqueParams for Evsm4Params {
    fn validate(&self) -> Result<(), TechniqueSpecError> {
        self.0.validate(true)
    }

    fn build(&self) -> Option<Box<dyn Technique>> {
        self.0.build(true)
    }

    fn reference_kind(&self) -> ReferenceKind {
        ReferenceKind::Coverage
    }

    fn canonical_fields(&self, f: &mut CanonicalFields) {
        self.0.canonical_fields(f, true)
    }
}

/// `msm`: `moment_bias` α (default 3·10⁻⁵), `depth_bias` (light-depth units, default 0),
/// `bleeding_reduction` (default 0) and the map's filtering.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct MsmParams {
    #[serde(default = "default_moment_bias")]
    pub moment_bias: f64,
    #[serde(default)]
    pub depth_bias: f64,
    #[serde(default)]
    pub bleeding_reduction: f64,
    #[serde(default)]
    pub blur: BlurSpec,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub blur_radius_texels: Option<u32>,
    #[serde(default, skip_serializing_if = "std::ops::Not::not")]
    pub mipmaps: bool,
}

fn default_moment_bias() -> f64 {
    3e-5
}

impl TechniqueParams for MsmParams {
    fn validate(&self) -> Result<(), TechniqueSpecError> {
        if !(self.moment_bias.is_finite() && (0.0..1.0).contains(&self.moment_bias)) {
            return Err(err(
                "moment_bias",
                format!("must be a number in [0, 1), found {}", self.moment_bias),
            ));
        }
        non_negative("depth_bias", self.depth_bias)?;
        check_bleeding(self.bleeding_reduction)?;
        check_blur(self.blur, self.blur_radius_texels)
    }

    fn build(&self) -> Option<Box<dyn Technique>> {
        let reconstruction = Reconstruction::Msm {
            moment_bias: self.moment_bias as f32,
            depth_bias: self.depth_bias as f32,
            bleeding_reduction: self.bleeding_reduction as f32,
        };
        filterable(MomentWarp::Power4, (self.blur, self.blur_radius_texels, self.mipmaps), reconstruction)
    }

    fn reference_kind(&self) -> ReferenceKind {
        ReferenceKind::Coverage
    }

    fn canonical_fields(&self, f: &mut CanonicalFields) {
        f.number("moment_bias", self.moment_bias);
        f.number("depth_bias", self.depth_bias);
        f.number("bleeding_reduction", self.bleeding_reduction);
        filtering_fields(f, self.blur, self.blur_radius_texels, self.mipmaps);
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    const VSM: Reconstruction = Reconstruction::Vsm { min_variance: 0.0, bleeding_reduction: 0.0 };

    #[test]
    fn one_occluder_is_exact_for_vsm_esm_and_msm_far_behind() {
        // A filter region wholly covered by one occluder at 0.4: variance 0, so VSM is the depth
        // test exactly; ESM is e^{c(0.4 − d)}, 1 in front and below e^{−8} a tenth behind.
        let m = MomentWarp::Depth2.moments(0.4);
        assert_eq!(visibility_from_moments(VSM, m, 0.4), 1.0);
        assert_eq!(visibility_from_moments(VSM, m, 0.41), 0.0);
        let esm = Reconstruction::Esm { exponent: 80.0 };
        let e = MomentWarp::Exponential { exponent: 80.0 }.moments(0.4);
        assert_eq!(visibility_from_moments(esm, e, 0.3), 1.0);
        assert!(visibility_from_moments(esm, e, 0.5) < (-7.9f32).exp());
    }

    #[test]
    fn two_overlapping_occluders_bleed_by_chebyshevs_bound() {
        // Half the region at 0.2, half at 0.5 (the second occluder overlapping the first in the
        // light's view), receiver at 0.8: truly unlit. VSM's bound is σ²/(σ² + (0.8 − μ)²) with
        // μ = 0.35, σ² = 0.0225: 0.0225/0.225 = 0.1 of light bleeds through, worked by hand.
        let m: [f32; 4] = std::array::from_fn(|c| {
            0.5 * (MomentWarp::Depth2.moments(0.2)[c] + MomentWarp::Depth2.moments(0.5)[c])
        });
        let v = visibility_from_moments(VSM, m, 0.8);
        assert!((v - 0.1).abs() < 1e-6, "{v}");
        // A bleeding reduction of 0.1 or more removes it; below, it is rescaled.
        let reduced = |amount| {
            visibility_from_moments(
                Reconstruction::Vsm { min_variance: 0.0, bleeding_reduction: amount },
                m,
                0.8,
            )
        };
        assert_eq!(reduced(0.1), 0.0);
        assert!((reduced(0.05) - 0.05 / 0.95).abs() < 1e-6);
        // At 0.51, just behind the second occluder, the bound is 0.0225/(0.0225 + 0.0256).
        let near = visibility_from_moments(VSM, m, 0.51);
        assert!((near - 0.0225 / 0.0481).abs() < 1e-5, "{near}");
    }

    #[test]
    fn evsm4_is_the_smaller_of_its_two_bounds() {
        let (positive, negative) = (40.0f32, 5.0f32);
        let warp = MomentWarp::Evsm4 { positive, negative };
        let m: [f32; 4] = std::array::from_fn(|c| 0.5 * (warp.moments(0.2)[c] + warp.moments(0.5)[c]));
        let r = Reconstruction::Evsm {
            positive,
            negative: Some(negative),
            variance_bias: 0.0,
            bleeding_reduction: 0.0,
        };
        let d = 0.8;
        let p = chebyshev_upper_bound(m[0], m[1], evsm_positive(d, positive), 0.0);
        let n = chebyshev_upper_bound(m[2], m[3], evsm_negative(d, negative), 0.0);
        assert_eq!(visibility_from_moments(r, m, d), p.min(n));
        // The positive warp all but removes VSM's bleeding here: e^{40·0.6} dwarfs the mean.
        assert!(p < 1e-6, "{p}");
    }

    #[test]
    fn a_mip_level_of_a_grating_reads_its_coverage() {
        // Columns alternate between an occluder at 0.3 and the receiver's own depth 0.8. Level 1
        // averages one of each: μ = 0.55, σ² = 0.0625, d − μ = 0.25, so VSM's bound is ½, the lit
        // fraction of the footprint (worked by hand); level 0 at an occluder's texel centre is 0.
        let depth = (0..8).flat_map(|_| (0..8).map(|x| if x % 2 == 0 { 0.3 } else { 0.8 })).collect();
        let base = crate::raster::DepthLayer { resolution: 8, depth };
        let layer = crate::raster::MomentLayer::from_depth(&base, MomentWarp::Depth2, MapBlur::None, true);
        assert_eq!(layer.levels.len(), 4);
        let (u, v) = (1.0 / 16.0, 0.5 + 1.0 / 16.0);
        assert_eq!(visibility_from_moments(VSM, layer.sample_at_lod(u, v, 0.0), 0.8), 0.0);
        for lod in [1.0, 1.5, 2.0, 3.0, f32::INFINITY, f32::NAN] {
            let v = visibility_from_moments(VSM, layer.sample_at_lod(u, v, lod), 0.8);
            assert!((v - 0.5).abs() < 1e-6, "λ = {lod}: {v}");
        }
        // Halfway to level 1: the moments are the mean of level 0's and level 1's.
        let half = layer.sample_at_lod(u, v, 0.5);
        assert!((half[0] - 0.5 * (0.3 + 0.55)).abs() < 1e-6, "{half:?}");
    }

    #[test]
    fn mipmaps_are_named_only_when_on() {
        let name = |json: &str| {
            let spec: crate::technique::TechniqueSpec = serde_json::from_str(json).unwrap();
            spec.canonical()
        };
        assert!(!name(r#"{"technique": "vsm"}"#).contains("mipmaps"));
        assert_eq!(name(r#"{"technique": "vsm", "mipmaps": false}"#), name(r#"{"technique": "vsm"}"#));
        assert!(name(r#"{"technique": "esm", "mipmaps": true}"#).contains(",mipmaps=true"));
    }

    #[test]
    fn parameters_are_checked() {
        let vsm = |json: &str| serde_json::from_str::<VsmParams>(json).unwrap().validate();
        assert!(vsm("{}").is_ok());
        assert_eq!(vsm(r#"{"bleeding_reduction": 1}"#).unwrap_err().field, Some("bleeding_reduction"));
        assert_eq!(
            vsm(r#"{"blur": "none", "blur_radius_texels": 2}"#).unwrap_err().field,
            Some("blur_radius_texels")
        );
        assert_eq!(vsm(r#"{"blur_radius_texels": 33}"#).unwrap_err().field, Some("blur_radius_texels"));
        let esm = serde_json::from_str::<EsmParams>(r#"{"exponent": 89}"#).unwrap();
        assert_eq!(esm.validate().unwrap_err().field, Some("exponent"));
        let evsm2: Evsm2Params = serde_json::from_str(r#"{"negative_exponent": 5}"#).unwrap();
        assert_eq!(evsm2.validate().unwrap_err().field, Some("negative_exponent"));
        assert!(serde_json::from_str::<MsmParams>(r#"{"momentbias": 1}"#).is_err());
    }
}
