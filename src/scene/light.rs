//! Directional and spot lights, with the optional area-light sizes used by soft references.

use glam::Vec3;

#[derive(Clone, Debug, PartialEq)]
pub enum LightKind {
    /// `direction` points from the light towards the scene (normalized on load).
    Directional { direction: Vec3 },
    /// A point light with a cone: `direction` is the unit axis, `cone_deg` the full cone angle,
    /// `near` and `far` the depth range along the axis.
    Spot {
        position: Vec3,
        direction: Vec3,
        cone_deg: f32,
        near: f32,
        far: f32,
    },
}

#[derive(Clone, Debug, PartialEq)]
pub struct Light {
    pub name: String,
    pub kind: LightKind,
    /// Directional area light: angular diameter of the light's disk.
    pub angular_diameter_deg: Option<f32>,
    /// Spot area light: radius of a disk facing along the axis.
    pub radius: Option<f32>,
}

impl Light {
    pub fn is_directional(&self) -> bool {
        matches!(self.kind, LightKind::Directional { .. })
    }
}
