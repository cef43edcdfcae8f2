//! What one shadow-map resolution of a view builds before any technique runs: the light view
//! (or the light's cascades, or a point light's cube), the light-map position of every evaluated
//! pixel (for the attribution) and the shading order. Shared by every depth format and technique.

use super::cascaded_map::CascadedMap;
use super::map_setting::MapSetting;
use super::point_faces::PointFaces;
use super::{Plan, PlanError};
use glam::Vec3;
use shadowtruth::metrics::LightUv;
use shadowtruth::raster::{DepthFormat, LightView};
use shadowtruth::scene::{Camera, Light, PixelFootprint};
use shadowtruth::technique::ShadeOrder;
use shadowtruth::trace::GBuffer;

pub(crate) struct MapSetup {
    /// The map (the first cascade's or face's, for a light with several).
    view: LightView,
    light_uv: LightUv,
    /// The one map's shading order; cascades and cubes hold their own.
    order: Option<ShadeOrder>,
    cascaded: Option<CascadedMap>,
    cube: Option<PointFaces>,
    resolution: u32,
    footprint: PixelFootprint,
}

impl MapSetup {
    /// The set-up of `light` seen by `camera` at `resolution`, over the pixels of `gbuffer`;
    /// `first_camera` fixes a path's default cascade distance.
    pub fn new(
        plan: &Plan,
        (gbuffer, camera, first_camera): (&GBuffer, &Camera, &Camera),
        light: &Light,
        bounds: (Vec3, Vec3),
        resolution: u32,
    ) -> Result<Self, PlanError> {
        let cascaded = light
            .cascades
            .is_some()
            .then(|| CascadedMap::new(light, camera, first_camera, bounds, resolution, gbuffer));
        let cube = light.is_point().then(|| PointFaces::new(light, resolution, gbuffer));
        let view = match (&plan.shadow_map, &cascaded, &cube) {
            (Some(map_file), _, _) => {
                map_file.light_view(light, bounds).map_err(|e| PlanError::Import(e.into()))?
            }
            (None, Some(c), _) => c.cascades.views[0].clone(),
            (None, None, Some(c)) => c.views()[0].clone(),
            (None, None, None) => LightView::new(light, bounds, resolution),
        };
        let light_uv = match (&cascaded, &cube) {
            (Some(c), _) => c.light_uv(gbuffer, resolution),
            (None, Some(c)) => c.light_uv(gbuffer),
            (None, None) => LightUv::new(gbuffer, &view),
        };
        let single = cascaded.is_none() && cube.is_none();
        let order = single.then(|| ShadeOrder::new(gbuffer, &view));
        Ok(MapSetup { view, light_uv, order, cascaded, cube, resolution, footprint: gbuffer.footprint })
    }

    /// The shadow map's resolution.
    pub fn resolution(&self) -> u32 {
        self.resolution
    }

    /// The setting of one depth format.
    pub fn setting(&self, format: DepthFormat, scene_bounds: (Vec3, Vec3)) -> MapSetting<'_> {
        MapSetting {
            view: &self.view,
            light_uv: &self.light_uv,
            order: self.order.as_ref(),
            cascaded: self.cascaded.as_ref(),
            cube: self.cube.as_ref(),
            resolution: self.resolution,
            footprint: self.footprint,
            format,
            scene_bounds,
        }
    }

    /// The light views the maps are drawn from (each cascade's or face's, or the one): equal
    /// views draw equal maps.
    pub fn views(&self) -> Vec<LightView> {
        match (&self.cascaded, &self.cube) {
            (Some(c), _) => c.cascades.views.clone(),
            (None, Some(c)) => c.views().to_vec(),
            (None, None) => vec![self.view.clone()],
        }
    }
}
