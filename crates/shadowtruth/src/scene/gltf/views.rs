//! glTF cameras and `KHR_lights_punctual` lights as our `Camera`s and `Light`s (docs/gltf.md):
//! both look down their node's −z with +y up; the numbers glTF lacks come from view-export's
//! `extras` when present, else from documented defaults.

use super::extras::Extras;
use super::names::UniqueNames;
use super::nodes::NodeItem;
use super::problem::GltfProblem;
use crate::json_input::{as_positive, count, open_range};
use crate::scene::format::{MAX_IMAGE_PIXELS, MAX_IMAGE_SIDE};
use crate::scene::point_map::as_layout;
use crate::scene::{Camera, CubeSettings, Light, LightKind, MAX_GUARD_TEXELS, PointMap, box_corners};
use glam::{DAffine3, DVec3};
use gltf::khr_lights_punctual::Kind;

/// Image height when the camera's extras give no size; the width follows `aspectRatio`.
const DEFAULT_HEIGHT: u32 = 720;
/// `aspectRatio` when the camera has none (glTF leaves it to the viewport).
const DEFAULT_ASPECT: f64 = 16.0 / 9.0;
/// A spot light's default near distance, as a fraction of its far distance.
const DEFAULT_NEAR_FRACTION: f64 = 1e-3;

/// The node's −z (looking direction) and +y, unit, in world space; `None` when degenerate.
fn frame(world: &DAffine3) -> Option<(DVec3, DVec3)> {
    let forward = world.matrix3 * DVec3::NEG_Z;
    let up = world.matrix3 * DVec3::Y;
    let ok = forward.length() > 0.0 && up.length() > 0.0 && forward.is_finite() && up.is_finite();
    let (forward, up) = (forward.normalize(), up.normalize());
    (ok && forward.cross(up).length() > 1e-6).then_some((forward, up))
}

pub(super) fn cameras(
    document: &gltf::Document,
    items: &[NodeItem],
    problems: &mut Vec<GltfProblem>,
) -> Vec<Camera> {
    let nodes: Vec<gltf::Node> = document.nodes().collect();
    let mut names = UniqueNames::default();
    let mut out = Vec::new();
    for (k, item) in items.iter().enumerate() {
        let node = &nodes[item.node];
        let Some(camera) = node.camera() else { continue };
        let name = names.take(node.name(), || format!("camera{k}"));
        if let Some(camera) = camera_of(&camera, item, name, problems) {
            out.push(camera);
        }
    }
    out
}

fn camera_of(
    camera: &gltf::Camera,
    item: &NodeItem,
    name: String,
    problems: &mut Vec<GltfProblem>,
) -> Option<Camera> {
    let at = format!("cameras[{}]", camera.index());
    let gltf::camera::Projection::Perspective(p) = camera.projection() else {
        let message = "orthographic cameras are not supported: shadowtruth's cameras are pinholes";
        problems.push(GltfProblem::new(format!("{at}.type"), message));
        return None;
    };
    let fov_y_deg = (p.yfov() as f64).to_degrees() as f32;
    if !(fov_y_deg > 0.0 && fov_y_deg < 180.0) {
        problems.push(GltfProblem::new(format!("{at}.perspective.yfov"), "must be between 0 and π radians"));
        return None;
    }
    let extras = Extras::read(camera.extras(), &at);
    let width = extras.get("width", count(1, MAX_IMAGE_SIDE), problems);
    let height = extras.get("height", count(1, MAX_IMAGE_SIDE), problems);
    let (width, height) = match (width, height) {
        (Some(w), Some(h)) => (w, h),
        _ => (width_of_aspect(p.aspect_ratio(), &at, problems)?, DEFAULT_HEIGHT),
    };
    if width as u64 * height as u64 > MAX_IMAGE_PIXELS {
        problems.push(extras.problem("", format!("image {width}×{height} has more than 64 megapixels")));
        return None;
    }
    let Some((forward, up)) = frame(&item.world) else {
        problems.push(GltfProblem::new(
            format!("nodes[{}]", item.node),
            "its transform flattens the camera's frame",
        ));
        return None;
    };
    let position = item.world.translation;
    // A look_at far enough from a distant position that f32 rounding keeps the direction.
    let look_at = position + forward * position.length().max(1.0);
    let (position, look_at, up) = (position.as_vec3(), look_at.as_vec3(), up.as_vec3());
    if !(position.is_finite() && look_at.is_finite()) {
        problems.push(outside_f32(item));
        return None;
    }
    Some(Camera { name, position, look_at, up, fov_y_deg, width, height, path: None })
}

/// The image width for `aspectRatio` at the default height: `None` (reported) when the ratio is
/// not positive or gives a width outside 1 ..= `MAX_IMAGE_SIDE` pixels.
fn width_of_aspect(aspect: Option<f32>, at: &str, problems: &mut Vec<GltfProblem>) -> Option<u32> {
    let aspect = aspect.map_or(DEFAULT_ASPECT, f64::from);
    let width = (aspect * DEFAULT_HEIGHT as f64).round();
    if aspect > 0.0 && (1.0..=MAX_IMAGE_SIDE as f64).contains(&width) {
        return Some(width as u32);
    }
    let message = format!(
        "{aspect} gives a {width}×{DEFAULT_HEIGHT} image; the width must be 1 to {MAX_IMAGE_SIDE} pixels \
         (give the camera extras width and height for another size)"
    );
    problems.push(GltfProblem::new(format!("{at}.perspective.aspectRatio"), message));
    None
}

pub(super) fn lights(
    document: &gltf::Document,
    items: &[NodeItem],
    bounds: impl Fn() -> (DVec3, DVec3),
    problems: &mut Vec<GltfProblem>,
) -> Vec<Light> {
    let nodes: Vec<gltf::Node> = document.nodes().collect();
    let mut names = UniqueNames::default();
    let mut out = Vec::new();
    for (k, item) in items.iter().enumerate() {
        let node = &nodes[item.node];
        let Some(light) = node.light() else { continue };
        let name = names.take(node.name(), || format!("light{k}"));
        let extras = Extras::read(node.extras(), &format!("nodes[{}]", item.node));
        if let Some(kind) = light_kind(&light, item, &extras, &bounds, problems) {
            out.push(Light { name, kind, path: None, cascades: None });
        }
    }
    out
}

fn light_kind(
    light: &gltf::khr_lights_punctual::Light,
    item: &NodeItem,
    extras: &Extras,
    bounds: &impl Fn() -> (DVec3, DVec3),
    problems: &mut Vec<GltfProblem>,
) -> Option<LightKind> {
    let at = format!("extensions.KHR_lights_punctual.lights[{}]", light.index());
    if let Kind::Point = light.kind() {
        // A point light shines every way: only its node's position matters.
        return point_light(light, item, extras, &at, bounds, problems);
    }
    let Some((forward, _)) = frame(&item.world) else {
        problems.push(GltfProblem::new(
            format!("nodes[{}]", item.node),
            "its transform flattens the light's frame",
        ));
        return None;
    };
    let direction = forward.as_vec3();
    match light.kind() {
        Kind::Directional => {
            let angular = extras.get("angular_diameter_deg", open_range(0.0, 90.0), problems);
            Some(LightKind::Directional { direction, angular_diameter_deg: angular.map(|a| a as f32) })
        }
        Kind::Point => unreachable!("point lights are read above"),
        Kind::Spot { outer_cone_angle, .. } => {
            let cone_deg = match extras.get("cone_deg", open_range(0.0, 180.0), problems) {
                Some(cone) => cone,
                None => 2.0 * (outer_cone_angle as f64).to_degrees(),
            };
            if !(cone_deg > 0.0 && cone_deg < 180.0) {
                let message =
                    "gives a full cone of 180° or more (or 0°); spot cones must lie strictly between";
                problems.push(GltfProblem::new(format!("{at}.spot.outerConeAngle"), message));
                return None;
            }
            let position = item.world.translation;
            let range = spot_light_range(light.range(), &at, problems)?;
            let (near, far) = spot_range(position, range, extras, &at, bounds, problems)?;
            let radius = light_radius(extras, problems)?;
            let (position, cone_deg) = (position.as_vec3(), cone_deg as f32);
            if !position.is_finite() {
                problems.push(outside_f32(item));
                return None;
            }
            Some(LightKind::Spot { position, direction, cone_deg, near, far, radius })
        }
    }
}

/// A point light: its node's position, its range as far (as for a spot light), and from the
/// extras its near plane, sphere `radius`, `shadow_map` and cube map's `guard_texels`.
fn point_light(
    light: &gltf::khr_lights_punctual::Light,
    item: &NodeItem,
    extras: &Extras,
    at: &str,
    bounds: &impl Fn() -> (DVec3, DVec3),
    problems: &mut Vec<GltfProblem>,
) -> Option<LightKind> {
    let position = item.world.translation;
    let range = spot_light_range(light.range(), at, problems)?;
    let (near, far) = spot_range(position, range, extras, at, bounds, problems)?;
    let radius = light_radius(extras, problems)?;
    let guard = extras.get("guard_texels", count(0, MAX_GUARD_TEXELS as u64), problems);
    let map = match extras.get("shadow_map", as_layout, problems) {
        Some("dual_paraboloid") => PointMap::DualParaboloid,
        _ => PointMap::Cube(CubeSettings {
            guard_texels: guard.unwrap_or(CubeSettings::default().guard_texels),
        }),
    };
    let position = position.as_vec3();
    if !position.is_finite() {
        problems.push(outside_f32(item));
        return None;
    }
    Some(LightKind::Point { position, near, far, radius, map })
}

/// The extras' area-light `radius` (`Some(None)` when absent); None when it is not usable
/// (reported).
fn light_radius(extras: &Extras, problems: &mut Vec<GltfProblem>) -> Option<Option<f32>> {
    let radius = extras.get("radius", as_positive, problems).map(|r| r as f32);
    if radius.is_some_and(|r| !(r.is_finite() && r > 0.0)) {
        problems.push(extras.problem("radius", "must be positive within the range of f32 numbers"));
        return None;
    }
    Some(radius)
}

/// A camera or light node whose world position f32 cannot hold.
fn outside_f32(item: &NodeItem) -> GltfProblem {
    GltfProblem::new(format!("nodes[{}]", item.node), "its world position leaves the range of f32 numbers")
}

/// The light's `range` (`Some(None)` when absent); `None` when it is not positive (reported at
/// `{at}.range`: KHR_lights_punctual ranges are greater than zero).
fn spot_light_range(range: Option<f32>, at: &str, problems: &mut Vec<GltfProblem>) -> Option<Option<f64>> {
    match range.map(f64::from) {
        Some(r) if !(r > 0.0 && r.is_finite()) => {
            problems.push(GltfProblem::new(format!("{at}.range"), format!("{r} must be greater than 0")));
            None
        }
        range => Some(range),
    }
}

/// Where a spot light's far distance comes from, for the message when it is not beyond near.
enum FarSource {
    Extras,
    Range,
    Default,
}

/// A spot or point light's (near, far): the extras' when given; else far is `range`, or the distance to
/// the farthest corner of the scene's bounds plus 1 %; near is far / 1000. `at` is the light's
/// JSON path (`extensions.KHR_lights_punctual.lights[i]`).
fn spot_range(
    position: DVec3,
    range: Option<f64>,
    extras: &Extras,
    at: &str,
    bounds: &impl Fn() -> (DVec3, DVec3),
    problems: &mut Vec<GltfProblem>,
) -> Option<(f32, f32)> {
    let (far, source) = match (extras.get("far", as_positive, problems), range) {
        (Some(far), _) => (far, FarSource::Extras),
        (None, Some(range)) => (range, FarSource::Range),
        (None, None) => {
            let farthest = farthest_corner(bounds(), position);
            (if farthest.is_finite() && farthest > 0.0 { farthest * 1.01 } else { 1.0 }, FarSource::Default)
        }
    };
    let near = extras.get("near", as_positive, problems).unwrap_or(far * DEFAULT_NEAR_FRACTION);
    // Compared as the f32 the light keeps, so that rounding cannot make them equal or infinite.
    let (near32, far32) = (near as f32, far as f32);
    if !(near32 > 0.0 && far32.is_finite() && near32 < far32) {
        let problem = match source {
            FarSource::Extras => extras.problem(
                "far",
                format!("{far} must be greater than near ({near}), both within the range of f32 numbers"),
            ),
            FarSource::Range => GltfProblem::new(
                format!("{at}.range"),
                format!("{far} must be greater than the light's near distance ({near}), within the range of f32"),
            ),
            FarSource::Default => extras.problem(
                "near",
                format!("{near} must be positive and less than the light's far distance ({far}, from the scene's bounds)"),
            ),
        };
        problems.push(problem);
        return None;
    }
    Some((near32, far32))
}

/// The distance from `p` to the farthest corner of the box (lo, hi).
fn farthest_corner((lo, hi): (DVec3, DVec3), p: DVec3) -> f64 {
    box_corners(lo, hi).iter().map(|c| c.distance(p)).fold(0.0, f64::max)
}
