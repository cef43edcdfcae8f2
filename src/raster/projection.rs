//! Light projections: orthographic for a directional light (frustum fitted to the scene bounds),
//! perspective for a spot light. Depth d ∈ [0, 1], smaller is closer.

use crate::scene::Light;
use glam::{Mat4, Vec3};

#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Projection {
    /// Light-view bounds of the map (x from left to right, y from bottom to top).
    Orthographic {
        left: f32,
        right: f32,
        bottom: f32,
        top: f32,
    },
    /// Symmetric frustum of half-angle `atan(tan_half_fov)`; square map.
    Perspective { tan_half_fov: f32 },
}

/// The light's camera for one shadow-map resolution.
#[derive(Clone, Debug, PartialEq)]
pub struct LightView {
    pub resolution: u32,
    pub projection: Projection,
    /// Light view space: right-handed, the light looks down −z.
    pub light_from_world: Mat4,
    /// Clip space: x, y ∈ [−1, 1] across the map after the divide, z/w = d ∈ [0, 1].
    pub clip_from_world: Mat4,
    /// Near and far planes (distances along the light's axis).
    pub near: f32,
    pub far: f32,
    /// Unit vector towards the light for a directional light; None for a spot light.
    pub to_light: Option<Vec3>,
    /// Position of a spot light.
    pub position: Option<Vec3>,
}

impl LightView {
    /// The view of `light` at `resolution`, fitted to `scene_bounds` for a directional light.
    pub fn new(light: &Light, scene_bounds: (Vec3, Vec3), resolution: u32) -> Self {
        let _ = (light, scene_bounds, resolution);
        todo!()
    }

    /// (u, v, d) of world point `p`, computed in f32 through `clip_from_world` as a GPU would:
    /// u, v ∈ [0, 1] across the map (v up), d the light depth. None when w ≤ 0.
    #[inline]
    pub fn project(&self, p: Vec3) -> Option<Vec3> {
        let c = self.clip_from_world * p.extend(1.0);
        if c.w <= 0.0 {
            return None;
        }
        let inv_w = 1.0 / c.w;
        Some(Vec3::new(
            0.5 * c.x * inv_w + 0.5,
            0.5 * c.y * inv_w + 0.5,
            c.z * inv_w,
        ))
    }

    /// Distance of `p` along the light's axis (the view-space −z).
    #[inline]
    pub fn view_depth(&self, p: Vec3) -> f32 {
        -(self.light_from_world.transform_point3(p).z)
    }

    /// Light depth d of a point at view depth `view_depth` (linear for orthographic,
    /// f(D − n)/(D(f − n)) for perspective), in f64.
    pub fn depth_of_view_depth(&self, view_depth: f64) -> f64 {
        let (n, f) = (self.near as f64, self.far as f64);
        match self.projection {
            Projection::Orthographic { .. } => (view_depth - n) / (f - n),
            Projection::Perspective { .. } => f * (view_depth - n) / (view_depth * (f - n)),
        }
    }

    /// World size of one texel at `p`: frustum width / N (orthographic) or 2·D·tan(fov/2)/N.
    pub fn texel_world_size(&self, p: Vec3) -> f32 {
        let n = self.resolution as f32;
        match self.projection {
            Projection::Orthographic {
                left,
                right,
                bottom,
                top,
            } => (right - left).max(top - bottom) / n,
            Projection::Perspective { tan_half_fov } => 2.0 * self.view_depth(p) * tan_half_fov / n,
        }
    }
}
