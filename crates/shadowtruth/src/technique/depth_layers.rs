//! Techniques that compare against more than the nearest surface (docs/formulas.md, "Second
//! depth", "Midpoint" and "Dual depth layers").
//!
//! - `second_depth` (Wang & Molnar, UNC TR94-019, 1994): the map holds the back faces of closed
//!   objects (front faces culled) and both sides of open ones; lit when `z_ref ≤ z_map`.
//!   Receivers facing away from the light are never evaluated (N·L ≤ 0 is attached shadow).
//! - `midpoint` (Woo, "The Shadow Depth Map Revisited", Graphics Gems III, 1992): the threshold
//!   halfway between the two nearest surfaces z1 < z2.
//! - `dual` (Weiskopf & Ertl, "Shadow Mapping Based on Dual Depth Layers", Eurographics 2003):
//!   `z1 + min((z2 − z1)/2, z_offset)`.
//!
//! Where a texel has no second surface, z2 is the far plane (the cleared value 1). Midpoint is
//! computed as `z1 + (z2 − z1)/2`, the same arithmetic as dual, so that dual with an offset of
//! at least ½ is midpoint bit for bit and dual with offset 0 is the plain test.

use super::canonical::CanonicalFields;
use super::params::non_negative;
use super::{LayerNeeds, Sample, ShadeContext, Technique, TechniqueParams, TechniqueSpecError, texel_at};
use crate::raster::Culling;
use serde::{Deserialize, Serialize};

pub struct SecondDepth {
    pub bias_depth: f32,
}

impl Technique for SecondDepth {
    fn layer_needs(&self) -> LayerNeeds {
        LayerNeeds { culling: Culling::FrontFacesOfClosed, ..LayerNeeds::default() }
    }

    fn visibility(&self, s: &Sample, ctx: &ShadeContext) -> f32 {
        match ctx.view.project(s.position) {
            Some(uvd) => super::depth_test(ctx.layers.nearest(), uvd, self.bias_depth),
            None => 1.0,
        }
    }
}

/// The two nearest layers, with or without the back faces of closed objects.
fn two_layers(cull_back_faces: bool) -> LayerNeeds {
    let culling = if cull_back_faces { Culling::BackFacesOfClosed } else { Culling::None };
    LayerNeeds { culling, second_layer: true, ..LayerNeeds::default() }
}

/// Lit when `z_ref ≤ z1 + min((z2 − z1)/2, z_offset)`.
fn dual_test(s: &Sample, ctx: &ShadeContext, z_offset: f32) -> f32 {
    let Some(uvd) = ctx.view.project(s.position) else { return 1.0 };
    let pairs = ctx.layers.two_nearest();
    let (x, row) = texel_at(pairs.resolution, uvd.x, uvd.y);
    let [z1, z2] = pairs.at(x, row);
    (uvd.z <= z1 + ((z2 - z1) * 0.5).min(z_offset)) as u8 as f32
}

pub struct Midpoint {
    pub cull_back_faces: bool,
}

impl Technique for Midpoint {
    fn layer_needs(&self) -> LayerNeeds {
        two_layers(self.cull_back_faces)
    }

    fn visibility(&self, s: &Sample, ctx: &ShadeContext) -> f32 {
        dual_test(s, ctx, f32::INFINITY)
    }
}

pub struct DualDepth {
    pub z_offset: f32,
    pub cull_back_faces: bool,
}

impl Technique for DualDepth {
    fn layer_needs(&self) -> LayerNeeds {
        two_layers(self.cull_back_faces)
    }

    fn visibility(&self, s: &Sample, ctx: &ShadeContext) -> f32 {
        dual_test(s, ctx, self.z_offset)
    }
}

/// `second_depth`: an optional constant `bias_depth` (light-depth units).
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct SecondDepthParams {
    #[serde(default)]
    pub bias_depth: f64,
}

impl TechniqueParams for SecondDepthParams {
    fn validate(&self) -> Result<(), TechniqueSpecError> {
        non_negative("bias_depth", self.bias_depth)
    }

    fn build(&self) -> Option<Box<dyn Technique>> {
        Some(Box::new(SecondDepth { bias_depth: self.bias_depth as f32 }))
    }

    fn canonical_fields(&self, f: &mut CanonicalFields) {
        f.number("bias_depth", self.bias_depth)
    }
}

/// `midpoint`: whether the back faces of closed objects are left out of both layers.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct MidpointParams {
    #[serde(default)]
    pub cull_back_faces: bool,
}

impl TechniqueParams for MidpointParams {
    fn validate(&self) -> Result<(), TechniqueSpecError> {
        Ok(())
    }

    fn build(&self) -> Option<Box<dyn Technique>> {
        Some(Box::new(Midpoint { cull_back_faces: self.cull_back_faces }))
    }

    fn canonical_fields(&self, f: &mut CanonicalFields) {
        f.flag("cull_back_faces", self.cull_back_faces)
    }
}

/// `dual`: the largest offset `z_offset` above z1 (light-depth units), and back-face culling.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct DualParams {
    pub z_offset: f64,
    #[serde(default)]
    pub cull_back_faces: bool,
}

impl TechniqueParams for DualParams {
    fn validate(&self) -> Result<(), TechniqueSpecError> {
        non_negative("z_offset", self.z_offset)
    }

    fn build(&self) -> Option<Box<dyn Technique>> {
        Some(Box::new(DualDepth { z_offset: self.z_offset as f32, cull_back_faces: self.cull_back_faces }))
    }

    fn canonical_fields(&self, f: &mut CanonicalFields) {
        f.number("z_offset", self.z_offset);
        f.flag("cull_back_faces", self.cull_back_faces);
    }
}
