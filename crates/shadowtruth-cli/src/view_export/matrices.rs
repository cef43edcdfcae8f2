//! The camera's and the light's matrices in the three graphics APIs' forms (docs/conventions.md,
//! "Exported views"). The project's own clip space (`LightView::clip_from_world`) is D3D's:
//! z/w ∈ [0, 1], y up; the other two forms are exact row operations on it.

use glam::{DMat4, DVec3, DVec4, Mat4, Vec3};
use shadowtruth::raster::{LightView, Projection};
use shadowtruth::scene::Camera;
use shadowtruth::trace::{GBuffer, PixelClass};

/// A graphics API's clip-space and texture conventions.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) enum Api {
    /// z/w ∈ [−1, 1], y up in NDC, window row 0 at the bottom, texture t up.
    OpenGl,
    /// z/w ∈ [0, 1], y down in NDC and framebuffer, texture t down.
    Vulkan,
    /// z/w ∈ [0, 1], y up in NDC, framebuffer row 0 at the top, texture v down.
    D3d,
}

impl Api {
    pub(crate) const ALL: [Api; 3] = [Api::OpenGl, Api::Vulkan, Api::D3d];

    pub(crate) fn key(self) -> &'static str {
        match self {
            Api::OpenGl => "opengl",
            Api::Vulkan => "vulkan",
            Api::D3d => "d3d",
        }
    }

    /// A D3D-form matrix (one whose output is D3D clip coordinates) in this form, by row
    /// operations: OpenGL's z row becomes 2z − w, Vulkan's y row is negated, D3D's is left as
    /// it is (so its bits, signed zeros included, are kept).
    fn convert_d3d(self, m: DMat4) -> DMat4 {
        let mut rows = m.transpose();
        match self {
            Api::OpenGl => rows.z_axis = 2.0 * rows.z_axis - rows.w_axis,
            Api::Vulkan => rows.y_axis = -rows.y_axis,
            Api::D3d => {}
        }
        rows.transpose()
    }

    /// (s·w, t·w, depth·w, w) from this API's clip coordinates: s, t the texture coordinates of a
    /// map rendered with this API (t in the API's own direction), depth the stored [0, 1] depth.
    fn texture_from_clip(self) -> DMat4 {
        let half = |x: f64, y: f64, z: f64| DVec4::new(x, y, z, 0.0);
        let (y_sign, z_scale, z_offset) = match self {
            Api::OpenGl => (0.5, 0.5, 0.5),
            Api::Vulkan => (0.5, 1.0, 0.0),
            Api::D3d => (-0.5, 1.0, 0.0),
        };
        DMat4::from_cols(
            half(0.5, 0.0, 0.0),
            half(0.0, y_sign, 0.0),
            half(0.0, 0.0, z_scale),
            DVec4::new(0.5, 0.5, z_offset, 1.0),
        )
    }
}

/// One API's projection of a view.
#[derive(Clone, Debug)]
pub(crate) struct ApiMatrices {
    pub api: Api,
    pub clip_from_view: Mat4,
    pub clip_from_world: Mat4,
    /// Light only: texture coordinates and stored depth of a world point (after the divide).
    pub texture_from_world: Option<Mat4>,
}

/// The matrices of a camera or a light's shadow map.
#[derive(Clone, Debug)]
pub(crate) struct ViewMatrices {
    pub near: f32,
    pub far: f32,
    pub view_from_world: Mat4,
    pub apis: Vec<ApiMatrices>,
}

/// Depth range of a camera: near = ½ the smallest view depth of the G-buffer's hits (so no
/// visible surface is clipped), far = the largest view depth of the scene bounds' corners plus
/// 1 %. Without hits, near = far/1000; without usable bounds, far = 1.
pub(crate) fn camera_depth_range(camera: &Camera, gbuffer: &GBuffer, bounds: (Vec3, Vec3)) -> (f32, f32) {
    let (_, _, forward) = camera.basis();
    let eye = camera.position.as_dvec3();
    let depth = |p: DVec3| (p - eye).dot(forward);
    let (lo, hi) = (bounds.0.as_dvec3(), bounds.1.as_dvec3());
    let corners = (0..8).map(|i| {
        DVec3::new(
            if i & 1 == 0 { lo.x } else { hi.x },
            if i & 2 == 0 { lo.y } else { hi.y },
            if i & 4 == 0 { lo.z } else { hi.z },
        )
    });
    let deepest = corners.map(depth).fold(f64::NEG_INFINITY, f64::max);
    let far = if deepest.is_finite() && deepest > 0.0 { 1.01 * deepest } else { 1.0 };
    let nearest_hit = gbuffer
        .class
        .iter()
        .zip(&gbuffer.position)
        .filter(|(c, _)| **c != PixelClass::Background)
        .map(|(_, p)| depth(p.as_dvec3()))
        .fold(f64::INFINITY, f64::min);
    let near = if nearest_hit.is_finite() && nearest_hit > 0.0 { 0.5 * nearest_hit } else { far * 1e-3 };
    let far = far.max(2.0 * near);
    (near as f32, far as f32)
}

/// The camera's matrices: view from its basis (right, up, −forward), projection from
/// `fov_y_deg`, width/height and (near, far); built in f64 and rounded once to f32.
pub(crate) fn camera_matrices(camera: &Camera, near: f32, far: f32) -> ViewMatrices {
    let (r, u, f) = camera.basis();
    let eye = camera.position.as_dvec3();
    let view_from_world = DMat4::from_cols(
        DVec4::new(r.x, u.x, -f.x, 0.0),
        DVec4::new(r.y, u.y, -f.y, 0.0),
        DVec4::new(r.z, u.z, -f.z, 0.0),
        DVec4::new(-r.dot(eye), -u.dot(eye), f.dot(eye), 1.0),
    );
    // The same tangent as the primary rays (src/scene/camera.rs).
    let t = ((camera.fov_y_deg as f64).to_radians() * 0.5).tan();
    let aspect = camera.width as f64 / camera.height as f64;
    let d3d = perspective_d3d(1.0 / (t * aspect), 1.0 / t, near as f64, far as f64);
    let apis = Api::ALL
        .iter()
        .map(|&api| {
            let clip_from_view = api.convert_d3d(d3d);
            ApiMatrices {
                api,
                clip_from_view: clip_from_view.as_mat4(),
                clip_from_world: api.convert_d3d(d3d * view_from_world).as_mat4(),
                texture_from_world: None,
            }
        })
        .collect();
    ViewMatrices { near, far, view_from_world: view_from_world.as_mat4(), apis }
}

/// The light's matrices. `view_from_world` is `light_from_world` and D3D's `clip_from_world` is
/// `clip_from_world`, bit for bit; the other forms are exact row operations on it (OpenGL's
/// 2z − w rounded once). `clip_from_view` is rebuilt from the projection's stored (f32)
/// parameters, so its product with the view matches `clip_from_world` to f32 rounding.
pub(crate) fn light_matrices(view: &LightView) -> ViewMatrices {
    let (n, f) = (view.near as f64, view.far as f64);
    let d3d_projection = match view.projection {
        Projection::Orthographic { left, right, bottom, top } => {
            let (l, r, b, t) = (left as f64, right as f64, bottom as f64, top as f64);
            DMat4::from_cols(
                DVec4::new(2.0 / (r - l), 0.0, 0.0, 0.0),
                DVec4::new(0.0, 2.0 / (t - b), 0.0, 0.0),
                DVec4::new(0.0, 0.0, -1.0 / (f - n), 0.0),
                DVec4::new(-(r + l) / (r - l), -(t + b) / (t - b), -n / (f - n), 1.0),
            )
        }
        Projection::Perspective { tan_half_fov } => {
            let s = 1.0 / tan_half_fov as f64;
            perspective_d3d(s, s, n, f)
        }
        Projection::Paraboloid => unreachable!("a paraboloid hemisphere is exported without matrices"),
    };
    let d3d_clip_from_world = view.clip_from_world.as_dmat4();
    let apis = Api::ALL
        .iter()
        .map(|&api| {
            let clip_from_world = api.convert_d3d(d3d_clip_from_world);
            ApiMatrices {
                api,
                clip_from_view: api.convert_d3d(d3d_projection).as_mat4(),
                clip_from_world: clip_from_world.as_mat4(),
                texture_from_world: Some((api.texture_from_clip() * clip_from_world).as_mat4()),
            }
        })
        .collect();
    ViewMatrices { near: view.near, far: view.far, view_from_world: view.light_from_world, apis }
}

/// D3D-form perspective: x_c = sx·x, y_c = sy·y, z_c/w_c = f(D − n)/(D(f − n)), w_c = D = −z.
fn perspective_d3d(sx: f64, sy: f64, n: f64, f: f64) -> DMat4 {
    DMat4::from_cols(
        DVec4::new(sx, 0.0, 0.0, 0.0),
        DVec4::new(0.0, sy, 0.0, 0.0),
        DVec4::new(0.0, 0.0, -f / (f - n), -1.0),
        DVec4::new(0.0, 0.0, -f * n / (f - n), 0.0),
    )
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Hand-worked: a camera at the origin looking down −z with a 90° field of view and a
    /// square image; the point (1, 1, −2) is at x_ndc = y_ndc = ½ and view depth 2.
    #[test]
    fn hand_worked_camera_projection() {
        let camera = Camera {
            name: "c".into(),
            path: None,
            position: Vec3::ZERO,
            look_at: Vec3::NEG_Z,
            up: Vec3::Y,
            fov_y_deg: 90.0,
            width: 100,
            height: 100,
        };
        let m = camera_matrices(&camera, 1.0, 3.0);
        let p = glam::Vec4::new(1.0, 1.0, -2.0, 1.0);
        for a in &m.apis {
            let c = a.clip_from_world * p;
            let ndc = c / c.w;
            assert!((c.w - 2.0).abs() < 1e-6, "{c}");
            assert!((ndc.x - 0.5).abs() < 1e-6);
            // D3D depth f(D − n)/(D(f − n)) = 3·1/(2·2) = ¾; OpenGL 2·¾ − 1 = ½.
            let (y, z) = match a.api {
                Api::OpenGl => (0.5, 0.5),
                Api::Vulkan => (-0.5, 0.75),
                Api::D3d => (0.5, 0.75),
            };
            assert!((ndc.y - y).abs() < 1e-6 && (ndc.z - z).abs() < 1e-6, "{:?} {ndc}", a.api);
        }
    }

    #[test]
    fn texture_coordinates_follow_each_api() {
        // D3D clip point at the top-left corner of the map (x = −1, y = +1), depth ¼.
        let d3d = DVec4::new(-1.0, 1.0, 0.25, 1.0);
        for api in Api::ALL {
            let t = api.texture_from_clip() * (api.convert_d3d(DMat4::IDENTITY) * d3d);
            let expected_t = if api == Api::OpenGl { 1.0 } else { 0.0 };
            assert_eq!((t.x, t.y, t.z, t.w), (0.0, expected_t, 0.25, 1.0), "{api:?}");
        }
    }
}
