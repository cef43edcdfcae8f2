//! Object transforms: scale, then rotation (degrees about x, then y, then z), then translation.

use glam::{DAffine3, DMat3, DVec3, Vec3};

#[derive(Clone, Debug, PartialEq)]
pub struct Transform {
    pub scale: Vec3,
    pub rotate_deg: Vec3,
    pub translate: Vec3,
}

impl Default for Transform {
    fn default() -> Self {
        Transform { scale: Vec3::ONE, rotate_deg: Vec3::ZERO, translate: Vec3::ZERO }
    }
}

impl Transform {
    /// The affine map `T · Rz · Ry · Rx · S`, in f64 so that each vertex is rounded to f32 once.
    pub fn affine(&self) -> DAffine3 {
        let [ax, ay, az] = self.rotate_deg.as_dvec3().to_array().map(sin_cos_deg);
        let rx = DMat3::from_cols(DVec3::X, DVec3::new(0.0, ax.1, ax.0), DVec3::new(0.0, -ax.0, ax.1));
        let ry = DMat3::from_cols(DVec3::new(ay.1, 0.0, -ay.0), DVec3::Y, DVec3::new(ay.0, 0.0, ay.1));
        let rz = DMat3::from_cols(DVec3::new(az.1, az.0, 0.0), DVec3::new(-az.0, az.1, 0.0), DVec3::Z);
        let linear = rz * ry * rx * DMat3::from_diagonal(self.scale.as_dvec3());
        DAffine3::from_mat3_translation(linear, self.translate.as_dvec3())
    }

    /// Maps an object-space point to world space, rounding once to f32.
    pub fn apply(&self, p: Vec3) -> Vec3 {
        self.affine().transform_point3(p.as_dvec3()).as_vec3()
    }

    /// True when the scale mirrors (negative determinant): triangle winding must then be
    /// flipped so that closed objects stay counter-clockwise seen from outside.
    pub fn mirrors(&self) -> bool {
        // Count signs rather than multiply: a product of tiny scales underflows to zero.
        self.scale.to_array().iter().filter(|&&c| c < 0.0).count() % 2 == 1
    }
}

/// (sin, cos) of an angle in degrees, exact at multiples of 90° so that axis-aligned rotations
/// keep axis-aligned geometry exactly axis-aligned.
fn sin_cos_deg(deg: f64) -> (f64, f64) {
    let r = deg.rem_euclid(360.0);
    if r == 0.0 {
        (0.0, 1.0)
    } else if r == 90.0 {
        (1.0, 0.0)
    } else if r == 180.0 {
        (0.0, -1.0)
    } else if r == 270.0 {
        (-1.0, 0.0)
    } else {
        deg.to_radians().sin_cos()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn t(scale: [f32; 3], rot: [f32; 3], tr: [f32; 3]) -> Transform {
        Transform { scale: scale.into(), rotate_deg: rot.into(), translate: tr.into() }
    }

    #[test]
    fn scene_transform_right_handed_rotations() {
        let x = Vec3::X;
        assert_eq!(t([1.0; 3], [0.0, 90.0, 0.0], [0.0; 3]).apply(x), Vec3::new(0.0, 0.0, -1.0));
        assert_eq!(t([1.0; 3], [0.0, 0.0, 90.0], [0.0; 3]).apply(x), Vec3::Y);
        assert_eq!(t([1.0; 3], [90.0, 0.0, 0.0], [0.0; 3]).apply(Vec3::Y), Vec3::Z);
        assert_eq!(t([1.0; 3], [0.0, -270.0, 0.0], [0.0; 3]).apply(x), Vec3::new(0.0, 0.0, -1.0));
    }

    #[test]
    fn scene_transform_order_is_scale_rotate_xyz_translate() {
        // Scale x by 2, rotate x then y then z by 90°, translate.
        // (1,0,0) → (2,0,0) → Rx: (2,0,0) → Ry: (0,0,-2) → Rz: (0,0,-2) → + (1,2,3).
        let tf = t([2.0, 1.0, 1.0], [90.0, 90.0, 90.0], [1.0, 2.0, 3.0]);
        assert_eq!(tf.apply(Vec3::X), Vec3::new(1.0, 2.0, 1.0));
        // (0,1,0) → Rx: (0,0,1) → Ry: (1,0,0) → Rz: (0,1,0) → + t.
        assert_eq!(tf.apply(Vec3::Y), Vec3::new(1.0, 3.0, 3.0));
    }

    #[test]
    fn scene_transform_mirror_detection() {
        assert!(t([-1.0, 1.0, 1.0], [0.0; 3], [0.0; 3]).mirrors());
        assert!(!t([-1.0, -1.0, 1.0], [0.0; 3], [0.0; 3]).mirrors());
        assert!(t([-1e-20, 1e-20, 1e-20], [0.0; 3], [0.0; 3]).mirrors());
    }
}
