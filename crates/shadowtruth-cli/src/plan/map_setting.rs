//! One shadow map of a view at one depth format, as every technique reads it: the light view
//! (or cascades, or a cube's faces), the light-map position of every evaluated pixel and the shading order, all
//! borrowed from the resolution's set-up (`map_setup.rs`).

use super::cascaded_map::CascadedMap;
use super::point_faces::PointFaces;
use glam::Vec3;
use shadowtruth::metrics::LightUv;
use shadowtruth::raster::{DepthFormat, LightView};
use shadowtruth::scene::{PixelFootprint, Scene};
use shadowtruth::technique::{BuiltLayers, ShadeContext, ShadeOrder, Technique, shade_evaluated};

/// One shadow map's set-up within a view: the light view and what is built from it once.
pub(crate) struct MapSetting<'a> {
    /// The map (the first cascade's or face's, for a light with several).
    pub view: &'a LightView,
    pub light_uv: &'a LightUv,
    /// The shading order of the one map (None for cascades and cubes, which hold their own).
    pub order: Option<&'a ShadeOrder>,
    pub cascaded: Option<&'a CascadedMap>,
    pub cube: Option<&'a PointFaces>,
    pub resolution: u32,
    /// The camera's pixel footprint (the G-buffer's).
    pub footprint: PixelFootprint,
    pub format: DepthFormat,
    /// The scene's bounds, computed once per view.
    pub scene_bounds: (Vec3, Vec3),
}

impl<'a> MapSetting<'a> {
    /// The light views of the map: each cascade's or face's, or the one.
    pub(crate) fn views(&self) -> Vec<&'a LightView> {
        match (self.cascaded, self.cube) {
            (Some(c), _) => c.cascades.views.iter().collect(),
            (None, Some(c)) => c.views().iter().collect(),
            (None, None) => vec![self.view],
        }
    }

    /// What the technique reads of each map, with `layers` (one per map, in `views` order).
    pub(crate) fn contexts<'s>(&self, scene: &'s Scene, layers: &'s [BuiltLayers]) -> Vec<ShadeContext<'s>>
    where
        'a: 's,
    {
        let views = self.views().into_iter().zip(layers);
        views
            .map(|(view, l)| {
                ShadeContext::with_bounds(scene, self.footprint, view, l.as_layers(), self.scene_bounds)
            })
            .collect()
    }

    /// The technique's visibility of every evaluated pixel through `contexts` (`contexts`).
    pub(crate) fn shade(&self, technique: &dyn Technique, contexts: &[ShadeContext]) -> Vec<f32> {
        match (self.cascaded, self.cube, self.order) {
            (Some(cascaded), _, _) => cascaded.orders.shade(technique, contexts),
            (None, Some(cube), _) => cube.orders.shade(technique, contexts),
            (None, None, Some(order)) => shade_evaluated(technique, order, &contexts[0]),
            (None, None, None) => unreachable!("one map has its shading order"),
        }
    }
}
