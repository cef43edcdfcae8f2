//! The pinhole camera (docs/conventions.md, "Camera"): pixel centres, row 0 at the top.

use super::path::CameraPath;
use glam::{DVec3, Vec3};

#[derive(Clone, Debug, PartialEq)]
pub struct Camera {
    pub name: String,
    pub position: Vec3,
    pub look_at: Vec3,
    pub up: Vec3,
    pub fov_y_deg: f32,
    pub width: u32,
    pub height: u32,
    /// A keyframed path (docs/temporal.md); `position` and `look_at` are its first key's.
    pub path: Option<CameraPath>,
}

impl Camera {
    /// Orthonormal basis (right, up, forward), computed in f64.
    pub fn basis(&self) -> (DVec3, DVec3, DVec3) {
        let f = (self.look_at.as_dvec3() - self.position.as_dvec3()).normalize();
        let r = f.cross(self.up.as_dvec3()).normalize();
        let u = r.cross(f);
        (r, u, f)
    }

    /// What every primary ray of this camera shares, computed once per image.
    pub fn film(&self) -> Film {
        Film {
            basis: self.basis(),
            tan_half_fov: ((self.fov_y_deg as f64).to_radians() * 0.5).tan(),
            width: self.width as f64,
            height: self.height as f64,
        }
    }

    /// The camera at time `t` of its path (itself when it has none), without the path.
    pub fn at_time(&self, t: f64) -> Camera {
        let mut camera = Camera { path: None, ..self.clone() };
        if let Some(path) = &self.path {
            camera.position = path.position.at(t).as_vec3();
            camera.look_at = path.look_at.at(t).as_vec3();
        }
        camera
    }

    /// Unit viewing direction in f64 (what cascade splits measure depth along).
    pub fn forward(&self) -> DVec3 {
        (self.look_at.as_dvec3() - self.position.as_dvec3()).normalize()
    }

    pub fn pixel_count(&self) -> usize {
        self.width as usize * self.height as usize
    }
}

/// A camera's image plane: its basis (right, up, forward) and the tangent of half its vertical
/// field of view.
#[derive(Clone, Copy, Debug)]
pub struct Film {
    basis: (DVec3, DVec3, DVec3),
    tan_half_fov: f64,
    width: f64,
    height: f64,
}

impl Film {
    /// Unit direction of the ray through the centre of pixel (x, y), row 0 at the top.
    /// Computed in f64 and rounded once, so every consumer sees the same bits.
    pub fn pixel_direction(&self, x: u32, y: u32) -> Vec3 {
        self.direction(x as f64 + 0.5, y as f64 + 0.5)
    }

    /// Unit direction of the ray through the image point (px, py), in pixels from the top-left
    /// corner (pixel (x, y) covers [x, x + 1) × [y, y + 1)). `pixel_direction` is this at the
    /// pixel centre, so sub-pixel rays and centre rays share one formula.
    pub fn direction(&self, px: f64, py: f64) -> Vec3 {
        self.row_at(py).direction_at(self.sx(px))
    }

    /// The horizontal image-plane coordinate of every pixel centre's column, for `FilmRow`.
    pub fn columns(&self) -> Vec<f64> {
        (0..self.width as u32).map(|x| self.sx(x as f64 + 0.5)).collect()
    }

    /// The pixel centres of row `y`: `FilmRow::direction` is `pixel_direction` with the parts
    /// that are constant along a row or down a column computed once.
    pub fn row(&self, y: u32) -> FilmRow {
        self.row_at(y as f64 + 0.5)
    }

    fn sx(&self, px: f64) -> f64 {
        let (w, h, t) = (self.width, self.height, self.tan_half_fov);
        (2.0 * px / w - 1.0) * t * w / h
    }

    fn row_at(&self, py: f64) -> FilmRow {
        let (r, u, f) = self.basis;
        let sy = (1.0 - 2.0 * py / self.height) * self.tan_half_fov;
        FilmRow { forward: f, right: r, up_offset: sy * u }
    }
}

/// The image plane along one row (`Film::row`).
#[derive(Clone, Copy, Debug)]
pub struct FilmRow {
    forward: DVec3,
    right: DVec3,
    /// The row's offset along the camera's up vector.
    up_offset: DVec3,
}

impl FilmRow {
    /// The unit direction through the pixel centre of column `x`, given `Film::columns`.
    #[inline]
    pub fn direction(&self, columns: &[f64], x: u32) -> Vec3 {
        self.direction_at(columns[x as usize])
    }

    /// f + sx·r + sy·u, in that order, normalized in f64 and rounded once.
    #[inline]
    fn direction_at(&self, sx: f64) -> Vec3 {
        (self.forward + sx * self.right + self.up_offset).normalize().as_vec3()
    }
}
