//! Whether an imported shadow map was rendered from the scene's light: its `clip_from_world`
//! must project along a directional light's direction (orthographic, the direction the depth
//! axis), or from a spot light's position along its direction (perspective, the centre of
//! projection the position and the w axis the direction).
//!
//! Tolerance: 1e-4, relative. A direction off by an angle θ moves the shadow of a point by θ
//! times its distance to its occluder, at most θ times the scene's size; a centre of projection
//! off by δ moves shadows by about δ. So both are bounded by 1e-4 of the scene's size (its
//! diagonal, or its distance from the origin where that is larger, since f32 matrices lose
//! precision with it): a tenth of a texel of a 1024² map over the scene, while a map of the
//! light rounded to f32 (about 1e-7 relative, 1e-6 after recovering the centre) stays far inside
//! it. A map of another light is further off than that.

use crate::scene::{Light, LightKind};
use glam::{DMat3, DVec3, DVec4, Mat4, Vec3};

/// The relative tolerance of the module documentation.
const RELATIVE_TOLERANCE: f64 = 1e-4;

/// Whether `clip_from_world` is a map of `light` in a scene of `scene_bounds`; the error says
/// which quantity differs by how much.
pub(super) fn check_map_light(
    clip_from_world: Mat4,
    light: &Light,
    scene_bounds: (Vec3, Vec3),
) -> Result<(), String> {
    let m = clip_from_world.as_dmat4();
    let orthographic = m.row(3) == DVec4::new(0.0, 0.0, 0.0, 1.0);
    let name = &light.name;
    match light.kind {
        LightKind::Directional { direction, .. } => {
            if !orthographic {
                return Err(format!(
                    "a perspective projection (row 3 is not 0 0 0 1), but light '{name}' is directional: its \
                     map is orthographic"
                ));
            }
            // d grows along row 2's xyz: the light's direction, away from the light.
            check_direction("its depth axis (row 2)", m.row(2).truncate(), direction, name)
        }
        LightKind::Spot { position, direction, .. } => {
            if orthographic {
                return Err(format!(
                    "an orthographic projection (row 3 is 0 0 0 1), but light '{name}' is a spot light: its \
                     map is a perspective projection"
                ));
            }
            check_centre(&m.transpose(), position, scene_bounds, name)?;
            // w, the view depth, grows along row 3's xyz.
            check_direction("its axis (row 3)", m.row(3).truncate(), direction, name)
        }
        LightKind::Point { .. } => Err(format!(
            "one map, but light '{name}' is a point light: its shadow map is a cube of six faces"
        )),
    }
}

/// The angle between `axis` and the light's `direction` within the tolerance (radians).
fn check_direction(what: &str, axis: DVec3, direction: Vec3, light: &str) -> Result<(), String> {
    let direction = direction.as_dvec3();
    let angle = axis.cross(direction).length().atan2(axis.dot(direction));
    if angle.is_nan() || angle > RELATIVE_TOLERANCE {
        return Err(format!(
            "{what} is {}° from the direction {} of light '{light}' (at most {}°)",
            angle.to_degrees() as f32,
            show(direction),
            RELATIVE_TOLERANCE.to_degrees() as f32
        ));
    }
    Ok(())
}

/// The centre of projection (where x, y and w are all 0) within the tolerance of the light's
/// `position`; `rows` is the matrix transposed (its columns are the matrix's rows).
fn check_centre(
    rows: &glam::DMat4,
    position: Vec3,
    scene_bounds: (Vec3, Vec3),
    light: &str,
) -> Result<(), String> {
    let (x, y, w) = (rows.x_axis, rows.y_axis, rows.w_axis);
    let a = DMat3::from_cols(x.truncate(), y.truncate(), w.truncate()).transpose();
    let scale = x.truncate().length() * y.truncate().length() * w.truncate().length();
    let determinant = a.determinant().abs();
    if determinant.is_nan() || determinant <= 1e-12 * scale {
        return Err("rows 0, 1 and 3 have no common zero: the matrix has no centre of projection".into());
    }
    let centre = a.inverse() * -DVec3::new(x.w, y.w, w.w);
    let position = position.as_dvec3();
    let allowed = RELATIVE_TOLERANCE * scene_scale(scene_bounds, position);
    let off = centre.distance(position);
    if off.is_nan() || off > allowed {
        return Err(format!(
            "its centre of projection {} is {} from the position {} of light '{light}' (at most {}: 1e-4 \
             of the scene's size)",
            show(centre),
            off as f32,
            show(position),
            allowed as f32
        ));
    }
    Ok(())
}

/// The scene's size: its diagonal, or the largest distance from the origin of its corners and
/// the light's position where that is larger.
fn scene_scale((lo, hi): (Vec3, Vec3), position: DVec3) -> f64 {
    let (lo, hi) = (lo.as_dvec3(), hi.as_dvec3());
    let diagonal = (hi - lo).length();
    let far = lo.abs().max(hi.abs()).max(position.abs()).max_element();
    diagonal.max(far).max(f64::MIN_POSITIVE)
}

fn show(v: DVec3) -> String {
    format!("({}, {}, {})", v.x as f32, v.y as f32, v.z as f32)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::raster::LightView;

    fn lights() -> Vec<Light> {
        let json = serde_json::json!({
            "format": "shadowtruth/scene/v1", "name": "s",
            "objects": [{ "name": "ground", "shape": { "type": "plane", "size": [8, 8] } }],
            "cameras": [{ "name": "c", "position": [0, 4, 6], "look_at": [0, 0, 0], "fov_y_deg": 45, "width": 8, "height": 8 }],
            "lights": [
                { "name": "sun", "type": "directional", "direction": [-0.3, -1, -0.2] },
                { "name": "spot", "type": "spot", "position": [1, 5, 1], "direction": [-0.2, -1, 0.1],
                  "cone_deg": 70, "near": 0.5, "far": 20 },
                { "name": "narrow", "type": "spot", "position": [300, 500, -200], "direction": [-0.6, -1, 0.4],
                  "cone_deg": 5, "near": 1, "far": 2000 }
            ]
        });
        let text = serde_json::to_string(&json).unwrap();
        let scene =
            crate::scene::load_scene_str(&text, std::path::Path::new("s.json"), std::path::Path::new("."))
                .unwrap();
        scene.lights
    }

    const BOUNDS: (Vec3, Vec3) = (Vec3::new(-4.0, 0.0, -4.0), Vec3::new(4.0, 1.0, 4.0));

    #[test]
    fn our_own_maps_are_their_lights_maps() {
        for light in lights() {
            let view = LightView::new(&light, BOUNDS, 256);
            assert_eq!(check_map_light(view.clip_from_world, &light, BOUNDS), Ok(()), "{}", light.name);
        }
    }

    #[test]
    fn another_lights_map_is_refused_naming_what_differs() {
        let lights = lights();
        let (sun, spot) = (&lights[0], &lights[1]);
        let of = |light: &Light| LightView::new(light, BOUNDS, 256).clip_from_world;
        let e = check_map_light(of(spot), sun, BOUNDS).unwrap_err();
        assert!(e.contains("perspective projection") && e.contains("'sun' is directional"), "{e}");
        let e = check_map_light(of(sun), spot, BOUNDS).unwrap_err();
        assert!(e.contains("orthographic projection"), "{e}");
        // The sun turned by 0.01 rad (0.573°) about z.
        let mut turned = sun.clone();
        let LightKind::Directional { direction, .. } = &mut turned.kind else { unreachable!() };
        *direction = glam::Quat::from_rotation_z(0.01) * direction.normalize();
        let e = check_map_light(of(&turned), sun, BOUNDS).unwrap_err();
        assert!(e.starts_with("its depth axis (row 2) is 0.56"), "{e}"); // 0.01 rad · |d × z|
        // The spot moved by 0.01 along its own axis: the same axis, another centre.
        let mut moved = spot.clone();
        let LightKind::Spot { position, direction, .. } = &mut moved.kind else { unreachable!() };
        *position += 0.01 * direction.normalize();
        let e = check_map_light(of(&moved), spot, BOUNDS).unwrap_err();
        assert!(e.starts_with("its centre of projection") && e.contains(" is 0.0099"), "{e}");
        // Within the tolerance (1e-4 of the scene's 11.3 diagonal): the same light.
        let mut close = spot.clone();
        let LightKind::Spot { position, .. } = &mut close.kind else { unreachable!() };
        *position += Vec3::new(2e-4, 0.0, 0.0);
        assert_eq!(check_map_light(of(&close), spot, BOUNDS), Ok(()));
    }
}
