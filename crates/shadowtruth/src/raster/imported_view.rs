//! A light view from a bare `clip_from_world` (another renderer's shadow map, or one that
//! `shadowtruth depth-map` wrote), for the conventions of docs/conventions.md: clip x, y in
//! [−1, 1] across the map, z/w = d in [0, 1], smaller closer; orthographic (w = 1) with d linear
//! in the view depth, or a symmetric perspective with w the view depth.
//!
//! The matrix is kept as given, so projecting a point is exactly what the renderer did. The rest
//! of the view (light_from_world, the frustum, near and far) is recovered from it and the given
//! near and far planes, for the techniques that read them (world-space biases, normal offset):
//! the matrix must be such a projection times a rigid light_from_world, within 1e-4.

use super::{LightView, Projection};
use crate::scene::{Light, LightKind};
use glam::{DMat4, DVec3, DVec4, Mat4};

/// How far from a rigid transform and an exact projection a matrix may be (relative).
const TOLERANCE: f64 = 1e-4;

impl LightView {
    /// The view whose clip_from_world is `clip_from_world` (see the module documentation), for
    /// `light` (its direction or position and size are the view's) and a `resolution`² map.
    pub fn from_clip_from_world(
        light: &Light,
        clip_from_world: Mat4,
        near: f32,
        far: f32,
        resolution: u32,
    ) -> Result<LightView, String> {
        if !(clip_from_world.is_finite() && near.is_finite() && far.is_finite() && far > near) {
            return Err(format!("clip_from_world must be finite and near < far (near {near}, far {far})"));
        }
        let m = clip_from_world.as_dmat4();
        let row = |i: usize| m.row(i);
        let xyz = |r: DVec4| r.truncate();
        let (n, f) = (near as f64, far as f64);
        let orthographic = row(3) == DVec4::new(0.0, 0.0, 0.0, 1.0);
        let (projection, z_row) = if orthographic {
            // d = (D − n)/(f − n) with D = −z_view: row 2 is −z_row/(f − n), less n/(f − n).
            let scale = 1.0 / (f - n);
            close(xyz(row(2)).length(), scale, "the depth row's length is not 1/(far − near)")?;
            let z_row = -(row(2) + DVec4::new(0.0, 0.0, 0.0, n * scale)) / scale;
            let (sx, sy) = (xyz(row(0)).length(), xyz(row(1)).length());
            let projection = Projection::Orthographic {
                left: (-(1.0 + row(0).w) / sx) as f32,
                right: ((1.0 - row(0).w) / sx) as f32,
                bottom: (-(1.0 + row(1).w) / sy) as f32,
                top: ((1.0 - row(1).w) / sy) as f32,
            };
            (projection, z_row)
        } else {
            // w = D = −z_view: row 3 is −z_row; x and y scaled by 1/tan(fov/2), no offset.
            let z_row = -row(3);
            close(xyz(z_row).length(), 1.0, "the w row is not a unit direction (a perspective view)")?;
            let (sx, sy) = (xyz(row(0)).length(), xyz(row(1)).length());
            close(sy, sx, "the frustum is not square")?;
            (Projection::Perspective { tan_half_fov: (1.0 / sx) as f32 }, z_row)
        };
        let (right, up) = (xyz(row(0)).normalize(), xyz(row(1)).normalize());
        let back = xyz(z_row);
        for (a, b) in [(right, up), (right, back), (up, back)] {
            close(a.dot(b), 0.0, "the light's axes are not orthogonal")?;
        }
        let light_from_world = light_from_world(&m, right, up, z_row, orthographic);
        let view = LightView {
            resolution,
            projection,
            light_from_world: light_from_world.as_mat4(),
            clip_from_world,
            near,
            far,
            to_light: None,
            position: None,
            light_size: light.size().ok(),
        };
        Ok(match light.kind {
            LightKind::Directional { direction, .. } => {
                let forward = direction.as_dvec3().try_normalize().unwrap_or(DVec3::NEG_Y);
                LightView { to_light: Some((-forward).as_vec3()), ..view }
            }
            LightKind::Spot { position, .. } | LightKind::Point { position, .. } => {
                LightView { position: Some(position), ..view }
            }
        })
    }
}

/// light_from_world with rows (right, up, back) and translations that reproduce the matrix:
/// orthographic x, y offsets belong to the frustum (left, right, …), so the rows' own are 0 there.
fn light_from_world(m: &DMat4, right: DVec3, up: DVec3, z_row: DVec4, orthographic: bool) -> DMat4 {
    let (tx, ty) = if orthographic { (0.0, 0.0) } else { (m.row(0).w, m.row(1).w) };
    let sx = m.row(0).truncate().length();
    let sy = m.row(1).truncate().length();
    DMat4::from_cols(
        DVec4::new(right.x, up.x, z_row.x, 0.0),
        DVec4::new(right.y, up.y, z_row.y, 0.0),
        DVec4::new(right.z, up.z, z_row.z, 0.0),
        DVec4::new(tx / sx, ty / sy, z_row.w, 1.0),
    )
}

fn close(a: f64, b: f64, what: &str) -> Result<(), String> {
    // Relative to the expected value, absolute only where that is zero: a depth scale of
    // 1/(far − near) ≪ 1 must still match to 1e-4 of itself.
    let bound = if b == 0.0 { TOLERANCE } else { TOLERANCE * b.abs() };
    if (a - b).abs() <= bound { Ok(()) } else { Err(format!("{what} ({a} against {b})")) }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::scene::Light;
    use glam::Vec3;

    fn lights() -> Vec<Light> {
        let json = serde_json::json!({
            "format": "shadowtruth/scene/v1", "name": "s",
            "objects": [{ "name": "ground", "shape": { "type": "plane", "size": [8, 8] } }],
            "cameras": [{ "name": "c", "position": [0, 4, 6], "look_at": [0, 0, 0], "fov_y_deg": 45, "width": 8, "height": 8 }],
            "lights": [
                { "name": "sun", "type": "directional", "direction": [-0.3, -1, -0.2] },
                { "name": "spot", "type": "spot", "position": [1, 5, 1], "direction": [-0.2, -1, 0.1],
                  "cone_deg": 70, "near": 0.5, "far": 20 }
            ]
        });
        let text = serde_json::to_string(&json).unwrap();
        let scene =
            crate::scene::load_scene_str(&text, std::path::Path::new("s.json"), std::path::Path::new("."))
                .unwrap();
        scene.lights
    }

    /// Our own views, rebuilt from their matrix alone: the same view, up to rounding.
    #[test]
    fn our_views_come_back_from_their_matrix() {
        for light in lights() {
            let ours = LightView::new(&light, (Vec3::splat(-4.0), Vec3::splat(4.0)), 512);
            let back =
                LightView::from_clip_from_world(&light, ours.clip_from_world, ours.near, ours.far, 512)
                    .unwrap();
            assert_eq!(back.clip_from_world, ours.clip_from_world);
            assert_eq!(std::mem::discriminant(&back.projection), std::mem::discriminant(&ours.projection));
            let p = Vec3::new(0.7, 0.3, -1.1);
            assert!((back.view_depth(p) - ours.view_depth(p)).abs() < 1e-4, "{}", light.name);
            assert!(
                (back.texel_world_size(p) - ours.texel_world_size(p)).abs()
                    < 1e-6 * ours.texel_world_size(p).max(1.0)
            );
            assert!(
                (back.light_from_world.transform_point3(p) - ours.light_from_world.transform_point3(p))
                    .abs()
                    .max_element()
                    < 1e-4
            );
            assert_eq!(
                (back.to_light.is_some(), back.position.is_some()),
                (ours.to_light.is_some(), ours.position.is_some())
            );
        }
    }

    #[test]
    fn a_matrix_that_is_no_such_projection_is_refused() {
        let light = &lights()[0];
        let ours = LightView::new(light, (Vec3::splat(-4.0), Vec3::splat(4.0)), 64);
        let sheared = ours.clip_from_world
            * Mat4::from_cols_array(&[
                1.0, 0.0, 0.0, 0.0, 0.3, 1.0, 0.0, 0.0, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0, 0.0, 1.0,
            ]);
        assert!(LightView::from_clip_from_world(light, sheared, ours.near, ours.far, 64).is_err());
        assert!(
            LightView::from_clip_from_world(light, ours.clip_from_world, ours.near, ours.far * 2.0, 64)
                .is_err()
        );
    }
}
