//! The depth layers a technique reads, rasterized from a light view: what `LayerNeeds` asks
//! for, built and owned (`Layers` borrows from it for shading).

use super::{LayerNeeds, Layers};
use crate::raster::{
    DepthFormat, DepthLayer, DepthPairLayer, LightView, MomentLayer, MultiDepthLayer, RasterSettings,
    Rasterizer,
};
use crate::scene::Scene;

/// The depth layers of one group of techniques.
#[derive(Clone, Debug, PartialEq)]
pub enum BuiltLayers {
    Nearest(DepthLayer),
    TwoNearest(DepthPairLayer),
    MultiDepth(MultiDepthLayer),
    Moments(MomentLayer),
}

impl BuiltLayers {
    /// Rasterizes the layers `needs` asks for (see [`Technique::layer_needs`]) from `view` in
    /// `format`.
    ///
    /// [`Technique::layer_needs`]: super::Technique::layer_needs
    pub fn build(scene: &Scene, view: &LightView, format: DepthFormat, needs: &LayerNeeds) -> BuiltLayers {
        Self::rasterize(&Rasterizer::new(scene, view), format, needs)
    }

    /// As [`BuiltLayers::build`], with the view's triangles already binned (shared by every
    /// group of techniques on that view).
    pub fn rasterize(rasterizer: &Rasterizer, format: DepthFormat, needs: &LayerNeeds) -> BuiltLayers {
        Self::rasterize_reusing(rasterizer, format, needs, None)
    }

    /// As [`BuiltLayers::rasterize`], into `spare`'s allocation where it holds layers of the
    /// same kind. A 4096² map is 64 MiB: touching fresh memory of that size costs more than
    /// rasterizing a small scene into it, and an engine renders each frame into the same map.
    pub fn rasterize_reusing(
        rasterizer: &Rasterizer,
        format: DepthFormat,
        needs: &LayerNeeds,
        spare: Option<BuiltLayers>,
    ) -> BuiltLayers {
        let settings = RasterSettings {
            format,
            culling: needs.culling,
            slope_factor: needs.slope_factor,
            slope_units: needs.slope_units,
            ..RasterSettings::default()
        };
        // The same choice of kind as below: moments first, then a second layer.
        let moments = needs.moments.is_some();
        match (spare, needs.second_layer) {
            (Some(BuiltLayers::Nearest(mut layer)), false) if !moments && needs.multi_depth.is_none() => {
                rasterizer.nearest_into(&settings, &mut layer);
                return BuiltLayers::Nearest(layer);
            }
            (Some(BuiltLayers::TwoNearest(mut layer)), true) if !moments => {
                rasterizer.two_nearest_into(&settings, &mut layer);
                return BuiltLayers::TwoNearest(layer);
            }
            _ => {}
        }
        if let Some(m) = needs.moments {
            return BuiltLayers::Moments(MomentLayer::from_depth(
                &rasterizer.nearest(&settings),
                m.warp,
                m.blur,
                m.mipmaps,
            ));
        }
        match (needs.second_layer, needs.multi_depth) {
            (true, _) => BuiltLayers::TwoNearest(rasterizer.two_nearest(&settings)),
            (false, Some(m)) => BuiltLayers::MultiDepth(MultiDepthLayer::from_base(
                &rasterizer.nearest(&settings),
                m.depths,
                m.neighbourhood,
                m.selection,
            )),
            (false, None) => BuiltLayers::Nearest(rasterizer.nearest(&settings)),
        }
    }

    pub fn as_layers(&self) -> Layers<'_> {
        match self {
            BuiltLayers::Nearest(l) => Layers::Nearest(l),
            BuiltLayers::TwoNearest(l) => Layers::TwoNearest(l),
            BuiltLayers::MultiDepth(l) => Layers::MultiDepth(l),
            BuiltLayers::Moments(l) => Layers::Moments(l),
        }
    }

    pub fn memory_bytes(&self) -> usize {
        match self {
            BuiltLayers::Nearest(l) => l.memory_bytes(),
            BuiltLayers::TwoNearest(l) => l.memory_bytes(),
            BuiltLayers::MultiDepth(l) => l.memory_bytes(),
            BuiltLayers::Moments(l) => l.memory_bytes(),
        }
    }
}
