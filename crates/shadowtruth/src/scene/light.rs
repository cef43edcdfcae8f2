//! Directional, spot and point lights, each with the optional area-light size of its own kind
//! (used by the soft references and PCSS).

use super::cascade_settings::CascadeSettings;
use super::path::LightPath;
use super::point_map::PointMap;
use glam::Vec3;

#[derive(Clone, Debug, PartialEq)]
pub enum LightKind {
    /// `direction` points from the light towards the scene (normalized on load).
    /// `angular_diameter_deg`: the angular diameter of the light's disk, when it is an area light.
    Directional { direction: Vec3, angular_diameter_deg: Option<f32> },
    /// A point light with a cone: `direction` is the unit axis, `cone_deg` the full cone angle,
    /// `near` and `far` the depth range along the axis. `radius` (world units): the radius of a
    /// disk centred at `position` and facing along the axis, when it is an area light.
    Spot { position: Vec3, direction: Vec3, cone_deg: f32, near: f32, far: f32, radius: Option<f32> },
    /// A light at `position` shining every way, up to the distance `far` (its range); `near` is
    /// the near plane of its shadow map's faces. `radius` (world units): the radius of a sphere
    /// centred at `position`, when it is an area light. `map`: a cube or two paraboloids.
    Point { position: Vec3, near: f32, far: f32, radius: Option<f32>, map: PointMap },
}

#[derive(Clone, Debug, PartialEq)]
pub struct Light {
    pub name: String,
    pub kind: LightKind,
    /// A keyframed path (docs/temporal.md); the kind's direction and position are its first
    /// key's.
    pub path: Option<LightPath>,
    /// Cascaded shadow maps instead of one map fitted to the scene (directional lights only;
    /// docs/cascades.md).
    pub cascades: Option<CascadeSettings>,
}

/// The size of an area light: what the area-light reference samples and PCSS filters by.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum LightSize {
    /// A directional light's angular diameter, degrees.
    AngularDiameterDeg(f32),
    /// A spot light's disk radius or a point light's sphere radius, world units.
    Radius(f32),
}

impl LightSize {
    /// The scene-file fields of the two sizes (a directional light's, a spot or point light's).
    pub const ANGULAR_DIAMETER_FIELD: &str = "angular_diameter_deg";
    pub const RADIUS_FIELD: &str = "radius";

    /// The scene-file field that gives this size.
    pub fn field(self) -> &'static str {
        match self {
            LightSize::AngularDiameterDeg(_) => Self::ANGULAR_DIAMETER_FIELD,
            LightSize::Radius(_) => Self::RADIUS_FIELD,
        }
    }

    /// The size in its own unit (degrees or world units).
    pub fn value(self) -> f32 {
        match self {
            LightSize::AngularDiameterDeg(x) | LightSize::Radius(x) => x,
        }
    }

    /// Whether the area-light reference can sample it: an angular diameter strictly between 0°
    /// and 180°, or a positive, finite radius. Scene files hold only such sizes; lights built in
    /// code may not.
    pub fn is_usable(self) -> bool {
        match self {
            LightSize::AngularDiameterDeg(a) => a > 0.0 && a < 180.0,
            LightSize::Radius(r) => r > 0.0 && r.is_finite(),
        }
    }
}

/// A light without an area size; `field` names the scene-file field its kind is sized by.
#[derive(Clone, Copy, Debug, PartialEq, Eq, thiserror::Error)]
#[error("has no {field}")]
pub struct NoLightSize {
    pub field: &'static str,
}

impl LightKind {
    /// The area size of the light: the angular diameter of a directional light, the disk radius
    /// of a spot light, the sphere radius of a point light; or which of the two it lacks.
    pub fn size(&self) -> Result<LightSize, NoLightSize> {
        let (size, field) = match *self {
            LightKind::Directional { angular_diameter_deg, .. } => {
                (angular_diameter_deg.map(LightSize::AngularDiameterDeg), LightSize::ANGULAR_DIAMETER_FIELD)
            }
            LightKind::Spot { radius, .. } | LightKind::Point { radius, .. } => {
                (radius.map(LightSize::Radius), LightSize::RADIUS_FIELD)
            }
        };
        size.ok_or(NoLightSize { field })
    }
}

impl Light {
    /// The light at time `t` of its path (itself when it has none), without the path.
    pub fn at_time(&self, t: f64) -> Light {
        let mut light = Light { path: None, ..self.clone() };
        if let Some(path) = &self.path {
            let towards = path.direction.at(t).try_normalize().unwrap_or(glam::DVec3::NEG_Y).as_vec3();
            match &mut light.kind {
                LightKind::Directional { direction, .. } => *direction = towards,
                LightKind::Spot { position, direction, .. } => {
                    *direction = towards;
                    if let Some(track) = &path.position {
                        *position = track.at(t).as_vec3();
                    }
                }
                // Scene files give point lights no path.
                LightKind::Point { .. } => {}
            }
        }
        light
    }

    pub fn is_directional(&self) -> bool {
        matches!(self.kind, LightKind::Directional { .. })
    }

    /// Whether the light is a point light, whose shadow map has several faces.
    pub fn is_point(&self) -> bool {
        matches!(self.kind, LightKind::Point { .. })
    }

    /// The light's position (a spot or point light's), or None for a directional light.
    pub fn position(&self) -> Option<Vec3> {
        match self.kind {
            LightKind::Directional { .. } => None,
            LightKind::Spot { position, .. } | LightKind::Point { position, .. } => Some(position),
        }
    }

    /// See [`LightKind::size`].
    pub fn size(&self) -> Result<LightSize, NoLightSize> {
        self.kind.size()
    }
}
