//! The shadow map's camera as engines place it (docs/conventions.md, "Exported views"): an eye
//! position, a target and an up vector from which a standard lookAt rebuilds `light_from_world`.

use glam::{DVec3, Vec3};
use shadowtruth::raster::LightView;
use shadowtruth::scene::{Light, LightKind};

/// The light view's frame in world space: the eye and the unit basis of its view space.
pub(crate) struct ShadowEye {
    pub position: Vec3,
    pub right: DVec3,
    pub up: DVec3,
    pub forward: DVec3,
}

impl ShadowEye {
    /// The frame of `view.light_from_world`, read back from its inverse so that the glb's light
    /// node and view.json's eye are the same basis as the matrix itself. A spot light's eye is
    /// its own position (the inverse would round it); a directional map's eye is the matrix's.
    pub(crate) fn of(light: &Light, view: &LightView) -> ShadowEye {
        let world_from_light = view.light_from_world.as_dmat4().inverse();
        let basis = |i: usize| world_from_light.col(i).truncate().normalize();
        let position = match light.kind {
            LightKind::Spot { position, .. } | LightKind::Point { position, .. } => position,
            LightKind::Directional { .. } => world_from_light.col(3).truncate().as_vec3(),
        };
        ShadowEye { position, right: basis(0), up: basis(1), forward: -basis(2) }
    }

    /// A point straight ahead of the eye, at the middle of the map's depth range: far enough
    /// that rounding it to f32 moves the direction by about the f32 rounding of the eye.
    pub(crate) fn target(&self, view: &LightView) -> Vec3 {
        let distance = 0.5 * (view.near as f64 + view.far as f64);
        (self.position.as_dvec3() + self.forward * distance).as_vec3()
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use glam::{DMat4, Vec3};

    /// gluLookAt: rows (s, u, −f) with f = normalize(target − eye), s = normalize(f × up),
    /// u = s × f, and the eye moved to the origin.
    fn look_at(eye: DVec3, target: DVec3, up: DVec3) -> DMat4 {
        let f = (target - eye).normalize();
        let s = f.cross(up).normalize();
        let u = s.cross(f);
        DMat4::from_cols(
            DVec3::new(s.x, u.x, -f.x).extend(0.0),
            DVec3::new(s.y, u.y, -f.y).extend(0.0),
            DVec3::new(s.z, u.z, -f.z).extend(0.0),
            DVec3::new(-s.dot(eye), -u.dot(eye), f.dot(eye)).extend(1.0),
        )
    }

    fn light(kind: LightKind) -> Light {
        Light { name: "l".into(), kind, path: None, cascades: None }
    }

    #[test]
    fn look_at_from_the_eye_rebuilds_light_from_world() {
        let bounds = (Vec3::new(-10.0, -0.5, -10.0), Vec3::new(10.0, 2.0, 10.0));
        let lights = [
            light(LightKind::Directional {
                direction: Vec3::new(-0.3, -1.0, -0.2).normalize(),
                angular_diameter_deg: None,
            }),
            // Within 8° of vertical: the view's up hint is world x, not y.
            light(LightKind::Directional {
                direction: Vec3::new(0.01, -1.0, 0.02).normalize(),
                angular_diameter_deg: None,
            }),
            light(LightKind::Spot {
                position: Vec3::new(3.0, 6.0, -2.0),
                direction: Vec3::new(-0.4, -1.0, 0.3).normalize(),
                cone_deg: 50.0,
                near: 0.5,
                far: 30.0,
                radius: None,
            }),
        ];
        for l in &lights {
            let view = LightView::new(l, bounds, 1024);
            let eye = ShadowEye::of(l, &view);
            let target = eye.target(&view);
            let rebuilt =
                look_at(eye.position.as_dvec3(), target.as_dvec3(), eye.up.as_vec3().as_dvec3()).as_mat4();
            let (got, want) = (rebuilt.to_cols_array(), view.light_from_world.to_cols_array());
            for (g, w) in got.iter().zip(want) {
                // A few f32 roundings of the eye's coordinates (about 10 units here).
                assert!((g - w).abs() <= 1e-5, "{:?}: {rebuilt} vs {}", l.kind, view.light_from_world);
            }
        }
    }
}
