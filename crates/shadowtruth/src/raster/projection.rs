//! Light projections: orthographic for a directional light (frustum fitted to the scene bounds),
//! perspective for a spot light and for each face of a point light's cube (`cube_map.rs`). Depth
//! d ∈ [0, 1], smaller is closer.

use crate::scene::{Light, LightKind, LightSize};
use glam::{DMat4, DVec3, DVec4, Mat4, Vec3, Vec4};

#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Projection {
    /// Light-view bounds of the map (x from left to right, y from bottom to top).
    Orthographic { left: f32, right: f32, bottom: f32, top: f32 },
    /// Symmetric frustum of half-angle `atan(tan_half_fov)`; square map.
    Perspective { tan_half_fov: f32 },
    /// One hemisphere of a dual-paraboloid map (Brabec, Annen and Seidel 2002): the direction
    /// d = (p − eye)/|p − eye| in view space maps to (x, y) = (d.x, d.y)/(1 − d.z) ∈ the unit
    /// disk (the view looks down −z), and depth is linear in the distance: d = (|p − eye| −
    /// near)/(far − near). Not a matrix: `clip_from_world` holds `light_from_world`, and the
    /// rasterizer and `project` apply the map per vertex and per receiver (`paraboloid_clip`).
    Paraboloid,
}

/// The light's camera for one shadow-map resolution.
#[derive(Clone, Debug, PartialEq)]
pub struct LightView {
    pub resolution: u32,
    pub projection: Projection,
    /// Light view space: right-handed, the light looks down −z.
    pub light_from_world: Mat4,
    /// Clip space: x, y ∈ [−1, 1] across the map after the divide, z/w = d ∈ [0, 1].
    pub clip_from_world: Mat4,
    /// Near and far planes (distances along the light's axis).
    pub near: f32,
    pub far: f32,
    /// Unit vector towards the light for a directional light; None for a spot light.
    pub to_light: Option<Vec3>,
    /// Position of a spot or point light.
    pub position: Option<Vec3>,
    /// The light's area size, when the scene gives one (PCSS reads it).
    pub light_size: Option<LightSize>,
}

impl LightView {
    /// The view of `light` at `resolution`, fitted to `scene_bounds` for a directional light.
    ///
    /// Directional: orthographic, looking along `direction`, x/y bounds fitted exactly to the 8
    /// corners of `scene_bounds` in light view space, near/far their view-depth range padded by
    /// 1 % on each side (so that no caster lies on a clip plane). The eye sits two bounding
    /// radii behind the bounds' centre, so near > 0. Empty or non-finite bounds fall back to the
    /// unit cube [−1, 1]³. Spot: perspective from `position` along `direction`, full fov =
    /// `cone_deg` (clamped to [0.01°, 179°]), the light's near/far (fixed up to 0 < near < far).
    /// Point: a 90° view along +x from its position, the +x face of a cube without a guard band
    /// (its maps have several views: `CubeMap`, `DualParaboloid`). Matrices are built in f64 and
    /// rounded once to f32. Never panics.
    pub fn new(light: &Light, scene_bounds: (Vec3, Vec3), resolution: u32) -> Self {
        let view = match light.kind {
            LightKind::Directional { direction, .. } => directional(direction, scene_bounds, resolution),
            LightKind::Spot { position, direction, cone_deg, near, far, .. } => {
                spot(position, direction, cone_deg, near, far, resolution)
            }
            LightKind::Point { position, near, far, .. } => {
                let eye = finite_or_origin(position);
                let light_from_world = view_from_basis(eye, DVec3::Z, DVec3::Y, DVec3::X);
                perspective(light_from_world, eye, 1.0, (near, far), resolution)
            }
        };
        LightView { light_size: light.size().ok(), ..view }
    }

    /// (u, v, d) of world point `p`, computed in f32 through `clip_from_world` as a GPU would:
    /// u, v ∈ [0, 1] across the map (v up), d the light depth. None when w ≤ 0.
    #[inline]
    pub fn project(&self, p: Vec3) -> Option<Vec3> {
        let c = self.clip_of(p);
        if c.w <= 0.0 {
            return None;
        }
        let inv_w = 1.0 / c.w;
        Some(Vec3::new(0.5 * c.x * inv_w + 0.5, 0.5 * c.y * inv_w + 0.5, c.z * inv_w))
    }

    /// The clip-space position of world point `p` in f32, as a vertex shader computes it:
    /// `clip_from_world · p`, or a paraboloid's map (w = 1; w = 0 for a direction straight
    /// behind it, and for the eye itself).
    #[inline]
    pub fn clip_of(&self, p: Vec3) -> Vec4 {
        match self.projection {
            Projection::Paraboloid => paraboloid_clip(self, p),
            _ => self.clip_from_world * p.extend(1.0),
        }
    }

    /// Distance of `p` along the light's axis (the view-space −z); for a paraboloid, its
    /// distance from the eye (what its depth is linear in).
    #[inline]
    pub fn view_depth(&self, p: Vec3) -> f32 {
        let q = self.light_from_world.transform_point3(p);
        match self.projection {
            Projection::Paraboloid => q.length(),
            _ => -q.z,
        }
    }

    /// Light depth d of a point at view depth `view_depth` (linear for orthographic,
    /// f(D − n)/(D(f − n)) for perspective), in f64.
    pub fn depth_of_view_depth(&self, view_depth: f64) -> f64 {
        let (n, f) = (self.near as f64, self.far as f64);
        match self.projection {
            Projection::Orthographic { .. } | Projection::Paraboloid => (view_depth - n) / (f - n),
            Projection::Perspective { .. } => f * (view_depth - n) / (view_depth * (f - n)),
        }
    }

    /// World size of one texel at `p`: frustum width / N (orthographic), 2·D·tan(fov/2)/N
    /// (perspective), or for a paraboloid D·(2/N)·(1 + cos θ) at distance D and angle θ from its
    /// axis (r = tan(θ/2) in the disk, so a texel of 2/N in r spans (4/N)·cos²(θ/2) radians).
    pub fn texel_world_size(&self, p: Vec3) -> f32 {
        let n = self.resolution as f32;
        match self.projection {
            Projection::Orthographic { left, right, bottom, top } => (right - left).max(top - bottom) / n,
            Projection::Perspective { tan_half_fov } => 2.0 * self.view_depth(p) * tan_half_fov / n,
            Projection::Paraboloid => {
                let q = self.light_from_world.transform_point3(p);
                let distance = q.length();
                (distance - q.z) * 2.0 / n
            }
        }
    }
}

/// A paraboloid hemisphere's clip position of `p` (`Projection::Paraboloid`), in f32 as a
/// vertex shader computes it: q = light_from_world · p, L = |q|, h = L − q.z (L·(1 + cos θ));
/// x = q.x/h, y = q.y/h, z = (L − near)/(far − near), w = 1. A point straight behind the
/// paraboloid or at its eye (h = 0) has w = 0.
#[inline]
pub(crate) fn paraboloid_clip(view: &LightView, p: Vec3) -> Vec4 {
    let q = view.light_from_world.transform_point3(p);
    let distance = q.length();
    let h = distance - q.z;
    if h.is_nan() || h <= 0.0 {
        return Vec4::ZERO;
    }
    let depth = (distance - view.near) / (view.far - view.near);
    Vec4::new(q.x / h, q.y / h, depth, 1.0)
}

/// Unit view direction in f64; a zero or non-finite direction falls back to straight down.
fn unit_direction(direction: Vec3) -> DVec3 {
    direction.as_dvec3().try_normalize().unwrap_or(DVec3::NEG_Y)
}

/// light_from_world for an eye at `eye` looking along the unit `forward` (view −z). The up
/// vector is world y unless `forward` is within ~8° of it (|forward·y| > 0.99), then world x:
/// a fixed choice per direction, so the map does not spin as a light moves slightly.
fn light_from_world(eye: DVec3, forward: DVec3) -> DMat4 {
    let up_hint = if forward.y.abs() > 0.99 { DVec3::X } else { DVec3::Y };
    let right = forward.cross(up_hint).normalize();
    view_from_basis(eye, right, right.cross(forward), forward)
}

/// light_from_world of an eye at `eye` with the orthonormal, right-handed `right`, `up` and
/// `forward` (view x, y and −z).
pub(crate) fn view_from_basis(eye: DVec3, right: DVec3, up: DVec3, forward: DVec3) -> DMat4 {
    DMat4::from_cols(
        DVec4::new(right.x, up.x, -forward.x, 0.0),
        DVec4::new(right.y, up.y, -forward.y, 0.0),
        DVec4::new(right.z, up.z, -forward.z, 0.0),
        DVec4::new(-right.dot(eye), -up.dot(eye), forward.dot(eye), 1.0),
    )
}

/// Bounds as f64 (min, max), or the unit cube when they are empty or not finite.
fn usable_bounds((lo, hi): (Vec3, Vec3)) -> (DVec3, DVec3) {
    let (lo, hi) = (lo.as_dvec3(), hi.as_dvec3());
    if lo.is_finite() && hi.is_finite() && lo.cmple(hi).all() {
        (lo, hi)
    } else {
        (DVec3::splat(-1.0), DVec3::splat(1.0))
    }
}

/// (lo − pad, hi + pad) with pad = 1 % of the range, or `min_pad` for an empty range.
fn padded(lo: f64, hi: f64, min_pad: f64) -> (f64, f64) {
    let pad = if hi > lo { 0.01 * (hi - lo) } else { min_pad };
    (lo - pad, hi + pad)
}

/// A directional light's space over a scene: light_from_world (the eye two bounding radii behind
/// the bounds' centre, so near > 0) and the light-space box of the bounds' eight corners (x, y,
/// and the view depth D = −z), in f64. Independent of any camera, so every map of the light
/// (the single one, each cascade) shares it.
pub(crate) struct DirectionalFrame {
    pub light_from_world: DMat4,
    forward: DVec3,
    /// The bounds' radius (at least 1e-3): the scale of the small widths given to flat extents.
    scale: f64,
    pub min: DVec3,
    pub max: DVec3,
}

impl DirectionalFrame {
    pub fn new(direction: Vec3, scene_bounds: (Vec3, Vec3)) -> Self {
        let forward = unit_direction(direction);
        let (lo, hi) = usable_bounds(scene_bounds);
        let centre = 0.5 * (lo + hi);
        let scale = (0.5 * (hi - lo).length()).max(1e-3);
        let eye = centre - forward * (2.0 * scale);
        let light_from_world = light_from_world(eye, forward);
        let mut min = DVec3::splat(f64::INFINITY);
        let mut max = DVec3::splat(f64::NEG_INFINITY);
        for i in 0..8 {
            let corner = DVec3::new(
                if i & 1 == 0 { lo.x } else { hi.x },
                if i & 2 == 0 { lo.y } else { hi.y },
                if i & 4 == 0 { lo.z } else { hi.z },
            );
            let p = light_from_world.transform_point3(corner);
            let p = DVec3::new(p.x, p.y, -p.z); // view depth D = −z
            min = min.min(p);
            max = max.max(p);
        }
        DirectionalFrame { light_from_world, forward, scale, min, max }
    }

    /// The x and y ranges of the scene's box; a flat extent (bounds seen edge-on) gets a small
    /// width so that the projection stays invertible.
    pub fn scene_xy(&self) -> ((f64, f64), (f64, f64)) {
        let min_extent = 1e-3 * self.scale;
        let fit = |lo: f64, hi: f64| if hi > lo { (lo, hi) } else { padded(lo, hi, min_extent) };
        (fit(self.min.x, self.max.x), fit(self.min.y, self.max.y))
    }

    /// The orthographic map over light-space x ∈ `x`, y ∈ `y`, its depth range the scene's
    /// padded by 1 % on each side (so that no caster lies on a clip plane).
    pub fn orthographic(
        &self,
        (left, right): (f64, f64),
        (bottom, top): (f64, f64),
        resolution: u32,
    ) -> LightView {
        let (near, far) = padded(self.min.z, self.max.z, 1e-3 * self.scale);
        // d = (D − n)/(f − n) with D = −z_view; x, y map [left, right], [bottom, top] to [−1, 1].
        let (w, h, depth) = (right - left, top - bottom, far - near);
        let clip_from_light = DMat4::from_cols(
            DVec4::new(2.0 / w, 0.0, 0.0, 0.0),
            DVec4::new(0.0, 2.0 / h, 0.0, 0.0),
            DVec4::new(0.0, 0.0, -1.0 / depth, 0.0),
            DVec4::new(-(right + left) / w, -(top + bottom) / h, -near / depth, 1.0),
        );
        LightView {
            resolution,
            projection: Projection::Orthographic {
                left: left as f32,
                right: right as f32,
                bottom: bottom as f32,
                top: top as f32,
            },
            light_from_world: self.light_from_world.as_mat4(),
            clip_from_world: (clip_from_light * self.light_from_world).as_mat4(),
            near: near as f32,
            far: far as f32,
            to_light: Some((-self.forward).as_vec3()),
            position: None,
            light_size: None,
        }
    }
}

/// The map fitted exactly to the scene's box in light space.
fn directional(direction: Vec3, scene_bounds: (Vec3, Vec3), resolution: u32) -> LightView {
    let frame = DirectionalFrame::new(direction, scene_bounds);
    let (x, y) = frame.scene_xy();
    frame.orthographic(x, y, resolution)
}

fn spot(position: Vec3, direction: Vec3, cone_deg: f32, near: f32, far: f32, resolution: u32) -> LightView {
    let forward = unit_direction(direction);
    let eye = finite_or_origin(position);
    let cone_deg = if cone_deg.is_finite() { (cone_deg as f64).clamp(0.01, 179.0) } else { 90.0 };
    let tan_half_fov = (0.5 * cone_deg).to_radians().tan();
    perspective(light_from_world(eye, forward), eye, tan_half_fov, (near, far), resolution)
}

/// A light's f64 position, or the origin when it is not finite.
pub(crate) fn finite_or_origin(position: Vec3) -> DVec3 {
    let eye = position.as_dvec3();
    if eye.is_finite() { eye } else { DVec3::ZERO }
}

/// A light's near and far in f64, fixed up to 0 < near < far.
pub(crate) fn usable_near_far(near: f32, far: f32) -> (f64, f64) {
    let n = if near.is_finite() && near > 0.0 { near as f64 } else { 1e-3 };
    let f = if far.is_finite() && far as f64 > n * (1.0 + 1e-6) { far as f64 } else { 2.0 * n };
    (n, f)
}

/// The square perspective map of an eye at `eye` with view `light_from_world`, half-angle
/// atan(`tan_half_fov`) and the light's near/far (fixed up to 0 < near < far).
pub(crate) fn perspective(
    light_from_world: DMat4,
    eye: DVec3,
    tan_half_fov: f64,
    (near, far): (f32, f32),
    resolution: u32,
) -> LightView {
    let (n, f) = usable_near_far(near, far);

    // w = D = −z_view, z = f(D − n)/(f − n), so z/w = f(D − n)/(D(f − n)) (D3D [0, 1] depth).
    let s = 1.0 / tan_half_fov;
    let clip_from_light = DMat4::from_cols(
        DVec4::new(s, 0.0, 0.0, 0.0),
        DVec4::new(0.0, s, 0.0, 0.0),
        DVec4::new(0.0, 0.0, -f / (f - n), -1.0),
        DVec4::new(0.0, 0.0, -f * n / (f - n), 0.0),
    );
    LightView {
        resolution,
        projection: Projection::Perspective { tan_half_fov: tan_half_fov as f32 },
        light_from_world: light_from_world.as_mat4(),
        clip_from_world: (clip_from_light * light_from_world).as_mat4(),
        near: n as f32,
        far: f as f32,
        to_light: None,
        position: Some(eye.as_vec3()),
        light_size: None,
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn light(kind: LightKind) -> Light {
        Light { name: "l".into(), kind, path: None, cascades: None }
    }

    fn sun(direction: Vec3) -> Light {
        light(LightKind::Directional { direction: direction.normalize(), angular_diameter_deg: None })
    }

    fn lamp() -> Light {
        light(LightKind::Spot {
            position: Vec3::new(3.0, 6.0, 2.0),
            direction: Vec3::new(-0.4, -1.0, -0.3).normalize(),
            cone_deg: 70.0,
            near: 0.5,
            far: 30.0,
            radius: None,
        })
    }

    /// World point at view depth `d` on the light's axis (offset sideways by `side` in view x).
    fn on_axis(view: &LightView, d: f64, side: f64) -> Vec3 {
        let world_from_light = view.light_from_world.as_dmat4().inverse();
        world_from_light.transform_point3(DVec3::new(side, 0.0, -d)).as_vec3()
    }

    const BOUNDS: (Vec3, Vec3) = (Vec3::new(-5.0, 0.0, -4.0), Vec3::new(5.0, 2.5, 4.0));

    #[test]
    fn directional_corners_project_into_the_map() {
        for dir in [Vec3::new(-0.3, -1.0, -0.2), Vec3::new(0.0, -1.0, 0.0), Vec3::new(1.0, -0.1, 0.3)] {
            let view = LightView::new(&sun(dir), BOUNDS, 512);
            assert!(view.near > 0.0 && view.far > view.near);
            let (lo, hi) = BOUNDS;
            let (mut umin, mut umax) = (f32::INFINITY, f32::NEG_INFINITY);
            for i in 0..8 {
                let c = Vec3::new(
                    if i & 1 == 0 { lo.x } else { hi.x },
                    if i & 2 == 0 { lo.y } else { hi.y },
                    if i & 4 == 0 { lo.z } else { hi.z },
                );
                let p = view.project(c).unwrap();
                let eps = 1e-5;
                assert!(p.x > -eps && p.x < 1.0 + eps && p.y > -eps && p.y < 1.0 + eps, "{dir} {p}");
                // Padded depth range: strictly inside.
                assert!(p.z > 0.0 && p.z < 1.0, "{dir} {p}");
                umin = umin.min(p.x);
                umax = umax.max(p.x);
            }
            // The fit is exact: the corners touch both sides of the map.
            assert!(umin.abs() < 1e-5 && (umax - 1.0).abs() < 1e-5);
        }
    }

    #[test]
    fn near_and_far_planes_map_to_zero_and_one() {
        for view in [
            LightView::new(&sun(Vec3::new(-0.3, -1.0, -0.2)), BOUNDS, 512),
            LightView::new(&lamp(), BOUNDS, 512),
        ] {
            let (n, f) = (view.near as f64, view.far as f64);
            let near = view.project(on_axis(&view, n, 0.01)).unwrap();
            let far = view.project(on_axis(&view, f, 0.01)).unwrap();
            assert!(near.z.abs() < 1e-5, "{near}");
            assert!((far.z - 1.0).abs() < 1e-5, "{far}");
            assert!(view.depth_of_view_depth(n).abs() < 1e-12);
            assert!((view.depth_of_view_depth(f) - 1.0).abs() < 1e-12);
        }
    }

    #[test]
    fn spot_depth_matches_the_perspective_formula() {
        let view = LightView::new(&lamp(), BOUNDS, 512);
        assert_eq!(view.near, 0.5);
        assert_eq!(view.far, 30.0);
        for d in [0.6, 1.0, 2.5, 7.0, 20.0, 29.0] {
            let p = view.project(on_axis(&view, d, 0.2 * d)).unwrap();
            let expected = view.depth_of_view_depth(d);
            assert!((p.z as f64 - expected).abs() < 4e-6, "{d}: {} vs {expected}", p.z);
            assert!(((view.view_depth(on_axis(&view, d, 0.0)) as f64) - d).abs() < 1e-4 * d);
        }
        // The cone edge maps to the map edge: a point at half-angle cone/2 in view x.
        let t = (35f64).to_radians().tan();
        let edge = view.project(on_axis(&view, 4.0, 4.0 * t)).unwrap();
        assert!((edge.x - 1.0).abs() < 1e-5 && (edge.y - 0.5).abs() < 1e-5, "{edge}");
    }

    #[test]
    fn vertical_and_degenerate_inputs_do_not_break() {
        let down = LightView::new(&sun(Vec3::NEG_Y), BOUNDS, 64);
        assert!(down.clip_from_world.is_finite());
        let empty = (Vec3::splat(f32::INFINITY), Vec3::splat(f32::NEG_INFINITY));
        let v = LightView::new(&sun(Vec3::new(0.0, -1.0, 0.5)), empty, 64);
        assert!(v.clip_from_world.is_finite() && v.near > 0.0);
        let point = (Vec3::ONE, Vec3::ONE);
        let v = LightView::new(&sun(Vec3::new(0.2, -1.0, 0.5)), point, 64);
        assert!(v.clip_from_world.is_finite() && v.near > 0.0 && v.far > v.near);
        let zero = light(LightKind::Directional { direction: Vec3::ZERO, angular_diameter_deg: None });
        assert!(LightView::new(&zero, BOUNDS, 64).clip_from_world.is_finite());
        let bad_spot = light(LightKind::Spot {
            position: Vec3::ZERO,
            direction: Vec3::ZERO,
            cone_deg: 400.0,
            near: -1.0,
            far: f32::NAN,
            radius: None,
        });
        let v = LightView::new(&bad_spot, BOUNDS, 64);
        assert!(v.clip_from_world.is_finite() && v.near > 0.0 && v.far > v.near);
    }
}
