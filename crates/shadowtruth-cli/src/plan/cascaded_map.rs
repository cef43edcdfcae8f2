//! A light's cascades for one view and resolution (docs/cascades.md): the cascades, which of
//! them shades each evaluated pixel, and the record of the run's counts per cascade.

use glam::Vec3;
use shadowtruth::metrics::{LightUv, falseness};
use shadowtruth::raster::{CascadeChoice, Cascades, default_max_distance};
use shadowtruth::record::{CascadeCounts, CascadeRecord, CascadesRecord};
use shadowtruth::scene::{Camera, CascadeFit, CascadeSettings, Light};
use shadowtruth::technique::CascadeOrders;
use shadowtruth::trace::{GBuffer, HardReference};

/// The cascades of one (camera, light, resolution), built once and shared by every technique.
pub(crate) struct CascadedMap {
    pub settings: CascadeSettings,
    pub cascades: Cascades,
    pub orders: CascadeOrders,
    /// World size of one camera pixel per unit of view depth.
    pixel_world_per_depth: f64,
}

impl CascadedMap {
    /// The cascades of `light` (which has them) for `camera`; `first_camera` fixes the default
    /// maximum distance over a path (the camera itself for a still view).
    pub fn new(
        light: &Light,
        camera: &Camera,
        first_camera: &Camera,
        scene_bounds: (Vec3, Vec3),
        resolution: u32,
        gbuffer: &GBuffer,
    ) -> Self {
        let settings = light.cascades.expect("a light with cascades");
        let max_distance =
            settings.max_distance.unwrap_or_else(|| default_max_distance(first_camera, scene_bounds));
        let cascades = Cascades::new(&settings, light, camera, scene_bounds, resolution, max_distance);
        let orders = CascadeOrders::new(gbuffer, &cascades);
        let tan_half_fov = (0.5 * (camera.fov_y_deg as f64).to_radians()).tan();
        CascadedMap {
            settings,
            cascades,
            orders,
            pixel_world_per_depth: 2.0 * tan_half_fov / camera.height as f64,
        }
    }

    /// The light-map position of every evaluated pixel in the map of its cascade.
    pub fn light_uv(&self, gbuffer: &GBuffer, resolution: u32) -> LightUv {
        LightUv::through(gbuffer, resolution, |p| match self.cascades.choose(p) {
            CascadeChoice::One(c) | CascadeChoice::Blend { index: c, .. } => Some(&self.cascades.views[c]),
            CascadeChoice::Beyond => None,
        })
    }

    /// The cascades and the counts of `visibility` (per evaluated pixel) in each.
    pub fn record(&self, gbuffer: &GBuffer, reference: &HardReference, visibility: &[f32]) -> CascadesRecord {
        let count = self.cascades.views.len();
        let mut counts = vec![CascadeCounts::default(); count + 1];
        for (k, (&i, &v)) in gbuffer.evaluated.iter().zip(visibility).enumerate() {
            let c = &mut counts[self.orders.cascade_of(k).unwrap_or(count)];
            c.evaluated += 1;
            // A surface mismatch (an imported buffer's NaN) is scored neither way, as in `counts`.
            if v.is_nan() {
                continue;
            }
            let (false_shadow, false_lit) = falseness(reference.lit[i as usize] != 0, v);
            c.false_shadow += false_shadow as u64;
            c.false_lit += false_lit as u64;
        }
        let splits = &self.cascades.splits;
        let cascades = (0..count)
            .map(|c| {
                let texel_world = self.cascades.texel_world(c);
                CascadeRecord {
                    near: if c == 0 { 0.0 } else { splits[c] },
                    far: splits[c + 1],
                    texel_world,
                    texel_pixels_at_far: texel_world / (self.pixel_world_per_depth * splits[c + 1]),
                    counts: counts[c],
                }
            })
            .collect();
        CascadesRecord {
            split: self.settings.split_name(),
            fit: match self.settings.fit {
                CascadeFit::Sphere => "sphere".into(),
                CascadeFit::Frustum => "frustum".into(),
            },
            stabilize: self.settings.stabilize,
            blend_band: self.settings.blend_band,
            cascades,
            beyond: counts[count],
        }
    }
}
