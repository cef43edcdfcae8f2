//! Object transforms: scale, then rotation (degrees about x, then y, then z), then translation.

use glam::Vec3;

#[derive(Clone, Debug, PartialEq)]
pub struct Transform {
    pub scale: Vec3,
    pub rotate_deg: Vec3,
    pub translate: Vec3,
}
