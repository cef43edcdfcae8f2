//! A pixel's footprint on the surface it sees: where the rays through the next pixel to the
//! right and the next pixel down meet the plane of that surface. These are the ray differentials
//! of pbrt-v4 (Pharr, Jakob & Humphreys, "Physically Based Rendering", 4th ed., §10.1.1), and
//! for a planar surface they are exactly the points a GPU's 2×2 quad differences its texture
//! coordinates against: what the mipmapped filterable maps choose their level of detail from.

use super::Camera;
use glam::{DVec3, Vec3};

/// What every pixel of one camera image shares for its footprint, computed once per image.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct PixelFootprint {
    eye: DVec3,
    forward: DVec3,
    /// One pixel to the right and one pixel down on the image plane at unit distance along
    /// `forward` (the film's square pixels: 2·tan(fov_y/2)/height each).
    step_right: DVec3,
    step_down: DVec3,
}

impl PixelFootprint {
    pub fn of(camera: &Camera) -> Self {
        let (right, up, forward) = camera.basis();
        let pixel = 2.0 * ((camera.fov_y_deg as f64).to_radians() * 0.5).tan() / camera.height as f64;
        PixelFootprint {
            eye: camera.position.as_dvec3(),
            forward,
            step_right: pixel * right,
            step_down: -pixel * up,
        }
    }

    /// The points, on the plane through `position` with normal `normal`, that the rays through
    /// the pixel one to the right and one down (by the same offset from `position`'s own ray)
    /// reach; None for one that meets the plane behind the eye or runs parallel to it (a
    /// footprint without bound, at grazing incidence).
    #[inline]
    pub fn neighbours(&self, position: Vec3, normal: Vec3) -> [Option<DVec3>; 2] {
        let (p, n) = (position.as_dvec3(), normal.as_dvec3());
        let to_point = p - self.eye;
        let along = to_point.dot(self.forward);
        if along <= 0.0 {
            return [None, None];
        }
        // The ray through `position`, scaled to unit distance along the view: its neighbours'
        // directions are one pixel step away on that image plane.
        let direction = to_point / along;
        let distance = n.dot(to_point);
        // Two calls rather than an array `map`, whose closure is not inlined on this path.
        let meet = |step: DVec3| {
            let d = direction + step;
            let t = distance / n.dot(d);
            (t.is_finite() && t > 0.0).then(|| self.eye + t * d)
        };
        [meet(self.step_right), meet(self.step_down)]
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn camera(position: Vec3, look_at: Vec3, fov_y_deg: f32, height: u32) -> Camera {
        Camera {
            name: "c".into(),
            position,
            look_at,
            up: Vec3::Y,
            fov_y_deg,
            width: height,
            height,
            path: None,
        }
    }

    #[test]
    fn a_plane_facing_the_camera_is_one_pixel_of_film_per_unit_of_distance() {
        // 90° over 100 rows: a pixel is 2/100 of the distance wide. At 10 units straight ahead
        // (z = −10, facing the camera) its neighbours are 0.2 to the right and 0.2 down.
        let c = camera(Vec3::ZERO, Vec3::NEG_Z, 90.0, 100);
        let f = PixelFootprint::of(&c);
        let [right, down] = f.neighbours(Vec3::new(0.0, 0.0, -10.0), Vec3::Z);
        let (right, down) = (right.unwrap(), down.unwrap());
        assert!((right - DVec3::new(0.2, 0.0, -10.0)).length() < 1e-12, "{right}");
        assert!((down - DVec3::new(0.0, -0.2, -10.0)).length() < 1e-12, "{down}");
    }

    #[test]
    fn a_tilted_plane_stretches_the_footprint_by_the_secant() {
        // The floor y = −1 seen from the origin looking along −z, at the point 1 below and 10
        // ahead. The ray one row down meets the floor nearer: the exact intersection of the ray
        // (0, −0.1 − 0.02, −1)·t with y = −1, t = 1/0.12.
        let c = camera(Vec3::ZERO, Vec3::NEG_Z, 90.0, 100);
        let f = PixelFootprint::of(&c);
        let [_, down] = f.neighbours(Vec3::new(0.0, -1.0, -10.0), Vec3::Y);
        let t = 1.0 / 0.12;
        assert!((down.unwrap() - DVec3::new(0.0, -1.0, -t)).length() < 1e-9, "{down:?}");
    }

    #[test]
    fn grazing_and_backward_rays_have_no_footprint() {
        let c = camera(Vec3::ZERO, Vec3::NEG_Z, 90.0, 100);
        let f = PixelFootprint::of(&c);
        // The horizon of the floor: the ray a row up runs off it (t < 0).
        let [_, down] = f.neighbours(Vec3::new(0.0, 1e-3, -100.0), Vec3::NEG_Y);
        assert!(down.is_none());
        // A point behind the eye.
        assert_eq!(f.neighbours(Vec3::new(0.0, 0.0, 1.0), Vec3::Z), [None, None]);
    }
}
