//! Shading through cascaded shadow maps (docs/cascades.md): every evaluated pixel is shaded by
//! the technique through the cascade its view depth falls in, with that cascade's light view and
//! layers (so biases in texels are that cascade's texels); in a blend band, through two cascades,
//! mixed linearly; beyond the last cascade, lit. A point light's cube map is shaded the same
//! way, its faces (or paraboloids) cascades that never blend (`CascadeOrders::of_faces`).

use super::shade::shade_into;
use super::{ShadeContext, ShadeOrder, Technique};
use crate::raster::{CascadeChoice, Cascades, LightView};
use crate::trace::GBuffer;
use rayon::prelude::*;

/// Which cascades shade each evaluated pixel, and each cascade's shading orders: built once per
/// (view, cascade set, resolution) and shared by every technique.
pub struct CascadeOrders {
    /// Per evaluated pixel (in `gbuffer.evaluated` order), the cascade(s) that shade it.
    pub choices: Vec<CascadeChoice>,
    /// Per cascade, the pixels it shades first (alone or as the nearer of a blend).
    first: Vec<ShadeOrder>,
    /// Per cascade, the pixels it shades as the farther of a blend.
    second: Vec<ShadeOrder>,
}

impl CascadeOrders {
    pub fn new(gbuffer: &GBuffer, cascades: &Cascades) -> Self {
        let choices: Vec<CascadeChoice> =
            gbuffer.evaluated.par_iter().map(|&i| cascades.choose(gbuffer.position[i as usize])).collect();
        Self::from_choices(gbuffer, &cascades.views, choices)
    }

    /// Each evaluated pixel shaded through its face of a point light's map (a cube's face, a
    /// paraboloid's hemisphere): `face[k]` indexes `faces` for evaluated pixel k.
    pub fn of_faces(gbuffer: &GBuffer, faces: &[LightView], face: &[u8]) -> Self {
        let choices = face.iter().map(|&f| CascadeChoice::One(f as usize)).collect();
        Self::from_choices(gbuffer, faces, choices)
    }

    /// The shading orders of `views` for the pixels `choices` sends to each.
    fn from_choices(gbuffer: &GBuffer, views: &[LightView], choices: Vec<CascadeChoice>) -> Self {
        let count = views.len();
        let (mut first, mut second) = (vec![Vec::new(); count], vec![Vec::new(); count]);
        for (k, choice) in choices.iter().enumerate() {
            match *choice {
                CascadeChoice::One(c) => first[c].push(k as u32),
                CascadeChoice::Blend { index, .. } => {
                    first[index].push(k as u32);
                    second[index + 1].push(k as u32);
                }
                CascadeChoice::Beyond => {}
            }
        }
        let order = |(c, slots): (usize, Vec<u32>)| ShadeOrder::of_pixels(gbuffer, &views[c], slots);
        CascadeOrders {
            choices,
            first: first.into_iter().enumerate().map(order).collect(),
            second: second.into_iter().enumerate().map(order).collect(),
        }
    }

    /// The technique's visibility of every evaluated pixel (in `gbuffer.evaluated` order), with
    /// `contexts[c]` the light view and layers of cascade c.
    pub fn shade(&self, technique: &dyn Technique, contexts: &[ShadeContext]) -> Vec<f32> {
        let n = self.choices.len();
        let (mut nearer, mut farther) = (vec![1.0f32; n], vec![1.0f32; n]);
        for (c, ctx) in contexts.iter().enumerate() {
            shade_into(technique, &self.first[c], ctx, &mut nearer);
            shade_into(technique, &self.second[c], ctx, &mut farther);
        }
        for (k, choice) in self.choices.iter().enumerate() {
            if let CascadeChoice::Blend { weight, .. } = *choice {
                nearer[k] += weight * (farther[k] - nearer[k]);
            }
        }
        nearer
    }

    /// The cascade of each evaluated pixel (the nearer of a blend), or None beyond the last.
    pub fn cascade_of(&self, k: usize) -> Option<usize> {
        match self.choices[k] {
            CascadeChoice::One(c) | CascadeChoice::Blend { index: c, .. } => Some(c),
            CascadeChoice::Beyond => None,
        }
    }
}
