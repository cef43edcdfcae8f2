//! One shadow map of a view at one depth format, as every technique reads it: the light view
//! (or cascades), the light-map position of every evaluated pixel and the shading order, all
//! borrowed from the resolution's set-up (`map_setup.rs`).

use super::cascaded_map::CascadedMap;
use glam::Vec3;
use shadowtruth::metrics::LightUv;
use shadowtruth::raster::{DepthFormat, LightView};
use shadowtruth::scene::Scene;
use shadowtruth::technique::{BuiltLayers, ShadeContext, ShadeOrder, Technique, shade_evaluated};

/// One shadow map's set-up within a view: the light view and what is built from it once.
pub(crate) struct MapSetting<'a> {
    /// The map (the first cascade's, for a light with cascades).
    pub view: &'a LightView,
    pub light_uv: &'a LightUv,
    /// The shading order of the one map (None for cascades, which hold their own).
    pub order: Option<&'a ShadeOrder>,
    pub cascaded: Option<&'a CascadedMap>,
    pub resolution: u32,
    pub format: DepthFormat,
    /// The scene's bounds, computed once per view.
    pub scene_bounds: (Vec3, Vec3),
}

impl<'a> MapSetting<'a> {
    /// The light views of the map: each cascade's, or the one.
    pub(crate) fn views(&self) -> Vec<&'a LightView> {
        match self.cascaded {
            Some(c) => c.cascades.views.iter().collect(),
            None => vec![self.view],
        }
    }

    /// What the technique reads of each map, with `layers` (one per map, in `views` order).
    pub(crate) fn contexts<'s>(&self, scene: &'s Scene, layers: &'s [BuiltLayers]) -> Vec<ShadeContext<'s>>
    where
        'a: 's,
    {
        let views = self.views().into_iter().zip(layers);
        views
            .map(|(view, l)| ShadeContext::with_bounds(scene, view, l.as_layers(), self.scene_bounds))
            .collect()
    }

    /// The technique's visibility of every evaluated pixel through `contexts` (`contexts`).
    pub(crate) fn shade(&self, technique: &dyn Technique, contexts: &[ShadeContext]) -> Vec<f32> {
        match (self.cascaded, self.order) {
            (Some(cascaded), _) => cascaded.orders.shade(technique, contexts),
            (None, Some(order)) => shade_evaluated(technique, order, &contexts[0]),
            (None, None) => unreachable!("one map has its shading order"),
        }
    }
}
