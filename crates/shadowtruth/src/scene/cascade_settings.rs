//! A directional light's cascaded shadow maps, as a scene file sets them (docs/cascades.md).
//! The cascades themselves are built per camera and resolution in src/raster/cascades.rs.

use crate::json_input::{Reader, as_bool, as_number, as_positive, as_string, count, show};

/// How the camera's depth range is split between cascades.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum SplitScheme {
    /// Equal depth ranges.
    Uniform,
    /// Equal ratios: split i at n·(f/n)^(i/N).
    Logarithmic,
    /// Zhang et al.'s practical split: λ·logarithmic + (1 − λ)·uniform.
    Practical { lambda: f64 },
}

/// What each cascade's orthographic frustum is fitted to.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum CascadeFit {
    /// The bounding sphere of the split's slice of the camera frustum: the same size whatever
    /// way the camera turns, which is what texel snapping needs.
    Sphere,
    /// The light-space box of the slice's eight corners, clipped to the scene's: tight, but
    /// changing size and texel as the camera turns.
    Frustum,
}

#[derive(Clone, Copy, Debug, PartialEq)]
pub struct CascadeSettings {
    /// 1 to 8 cascades.
    pub count: u32,
    pub split: SplitScheme,
    pub fit: CascadeFit,
    /// Snap each cascade's origin to whole texels of its map.
    pub stabilize: bool,
    /// The fraction of each cascade's depth range, at its far end, over which it is blended
    /// into the next (0: no blending).
    pub blend_band: f64,
    /// View depth where the first cascade starts (world units; default max_distance / 1000).
    pub near_distance: Option<f64>,
    /// View depth where the last cascade ends; farther surfaces are lit, as in engines
    /// (default: the first frame's camera to the farthest corner of the scene's bounds).
    pub max_distance: Option<f64>,
}

/// The most cascades a light may have.
pub const MAX_CASCADES: u32 = 8;

impl CascadeSettings {
    /// The split scheme's name, as scene files and reports write it.
    pub fn split_name(&self) -> String {
        match self.split {
            SplitScheme::Uniform => "uniform".into(),
            SplitScheme::Logarithmic => "logarithmic".into(),
            SplitScheme::Practical { lambda } => format!("practical(λ={lambda})"),
        }
    }
}

/// Reads a light's `cascades` object:
/// `{"count", "split": "uniform" | "logarithmic" | "practical", "lambda", "fit": "sphere" |
/// "frustum", "stabilize", "blend_band", "near_distance", "max_distance"}`.
pub(super) fn read_cascades(r: &mut Reader) -> Option<CascadeSettings> {
    let count = r.optional_or("count", count(1, MAX_CASCADES as u64), 4);
    let split = r.optional_or("split", as_string, "practical".into());
    let lambda = r.optional("lambda", as_number);
    let fit = r.optional_or("fit", as_fit, CascadeFit::Sphere);
    let stabilize = r.optional_or("stabilize", as_bool, true);
    let blend_band = r.optional_or("blend_band", as_number, 0.0);
    let near_distance = r.optional("near_distance", as_positive);
    let max_distance = r.optional("max_distance", as_positive);
    let split = match split?.as_str() {
        "uniform" | "logarithmic" if lambda.is_some() => {
            r.problem("lambda", "is read by the practical split only");
            return None;
        }
        "uniform" => SplitScheme::Uniform,
        "logarithmic" => SplitScheme::Logarithmic,
        "practical" => match lambda.unwrap_or(0.5) {
            l if (0.0..=1.0).contains(&l) => SplitScheme::Practical { lambda: l },
            l => {
                r.problem("lambda", format!("must be between 0 and 1, found {}", show(l)));
                return None;
            }
        },
        other => {
            let message = format!("unknown split \"{other}\"; expected uniform, logarithmic or practical");
            r.problem("split", message);
            return None;
        }
    };
    let blend_band = blend_band?;
    if !(0.0..1.0).contains(&blend_band) {
        r.problem("blend_band", format!("must be at least 0 and below 1, found {}", show(blend_band)));
        return None;
    }
    if let (Some(n), Some(f)) = (near_distance, max_distance)
        && n >= f
    {
        r.problem("near_distance", format!("must be less than `max_distance` ({})", show(f)));
        return None;
    }
    let (count, fit, stabilize) = (count?, fit?, stabilize?);
    Some(CascadeSettings { count, split, fit, stabilize, blend_band, near_distance, max_distance })
}

fn as_fit(v: &serde_json::Value) -> Result<CascadeFit, String> {
    match as_string(v)?.as_str() {
        "sphere" => Ok(CascadeFit::Sphere),
        "frustum" => Ok(CascadeFit::Frustum),
        other => Err(format!("unknown fit \"{other}\"; expected sphere or frustum")),
    }
}
