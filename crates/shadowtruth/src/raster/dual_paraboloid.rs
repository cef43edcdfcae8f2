//! A point light's dual-paraboloid shadow map (Brabec, Annen and Seidel, "Shadow mapping for
//! hemispherical and omnidirectional light sources", CGI 2002; docs/point-lights.md): two
//! hemispheres from the light's position, the first looking down (−y), the second up (+y), each
//! mapping a direction d (in its view space, looking down −z) to (d.x, d.y)/(1 − d.z) in the unit
//! disk, with depth linear in the distance.
//!
//! The map is not a projective one: the rasterizer maps a triangle's vertices and then draws
//! straight edges between them in the disk, where the true images of the edges are curves —
//! the paraboloid's tessellation-dependent error, which large triangles show most. Before the
//! map, a triangle is clipped to its hemisphere in view space (z ≤ 0), so that no vertex lies
//! behind the paraboloid; a point is shaded through the hemisphere its direction from the light
//! lies in (the first for y ≤ 0).

use super::projection::{LightView, Projection, finite_or_origin, usable_near_far, view_from_basis};
use crate::scene::{Light, LightKind};
use glam::{DVec3, Vec3};

/// The hemispheres' names, in their order.
pub const PARABOLOID_NAMES: [&str; 2] = ["front (-y)", "back (+y)"];

/// The two hemispheres of a point light's dual-paraboloid map at one resolution.
#[derive(Clone, Debug, PartialEq)]
pub struct DualParaboloid {
    /// The hemispheres in `PARABOLOID_NAMES` order, each `resolution`² texels.
    pub hemispheres: Vec<LightView>,
    position: Vec3,
}

impl DualParaboloid {
    /// The two hemispheres of the point `light` at `resolution`² texels each.
    pub fn new(light: &Light, resolution: u32) -> Self {
        let LightKind::Point { position, near, far, .. } = light.kind else {
            unreachable!("dual-paraboloid maps are built for point lights only")
        };
        let eye = finite_or_origin(position);
        let (n, f) = usable_near_far(near, far);
        let hemispheres = [(DVec3::NEG_Y, DVec3::NEG_X), (DVec3::Y, DVec3::X)]
            .into_iter()
            .map(|(forward, right)| {
                let light_from_world = view_from_basis(eye, right, right.cross(forward), forward).as_mat4();
                LightView {
                    resolution: resolution.max(1),
                    projection: Projection::Paraboloid,
                    light_from_world,
                    clip_from_world: light_from_world,
                    near: n as f32,
                    far: f as f32,
                    to_light: None,
                    position: Some(eye.as_vec3()),
                    light_size: light.size().ok(),
                }
            })
            .collect();
        DualParaboloid { hemispheres, position: eye.as_vec3() }
    }

    /// The hemisphere that shades `p`: the first (looking down) when p lies at or below the
    /// light, in f32.
    pub fn hemisphere_of(&self, p: Vec3) -> usize {
        usize::from(p.y - self.position.y > 0.0)
    }

    /// How many texels lie between `p`'s projection in hemisphere `h` and the disk's rim (the
    /// seam between the hemispheres); None when `p` does not project.
    pub fn texels_from_rim(&self, h: usize, p: Vec3) -> Option<f32> {
        let uvd = self.hemispheres[h].project(p)?;
        let (x, y) = (2.0 * uvd.x - 1.0, 2.0 * uvd.y - 1.0);
        Some((1.0 - (x * x + y * y).sqrt()) * 0.5 * self.hemispheres[h].resolution as f32)
    }
}

/// The part of world triangle `tri` in front of the paraboloid `view` (view-space z ≤ 0): up to
/// four vertices in the triangle's winding, cut where an edge crosses the plane z = 0. The
/// crossing is computed from the edge's endpoints in a canonical order, so two triangles
/// sharing the edge cut it at the same point.
pub(crate) fn front_part(view: &LightView, tri: &[Vec3; 3]) -> ([Vec3; 4], usize) {
    let z = tri.map(|p| view.light_from_world.transform_point3(p).z);
    let mut out = [Vec3::ZERO; 4];
    let mut len = 0;
    for i in 0..3 {
        let j = (i + 1) % 3;
        if z[i] <= 0.0 {
            out[len] = tri[i];
            len += 1;
        }
        if (z[i] <= 0.0) != (z[j] <= 0.0) {
            let key = |k: usize| tri[k].to_array().map(f32::to_bits);
            let (a, b) = if key(i) <= key(j) { (i, j) } else { (j, i) };
            let t = z[a] / (z[a] - z[b]);
            out[len] = tri[a] + (tri[b] - tri[a]) * t;
            len += 1;
        }
    }
    (out, len)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::scene::PointMap;

    fn lamp() -> Light {
        let kind = LightKind::Point {
            position: Vec3::new(1.0, 2.0, -3.0),
            near: 0.1,
            far: 50.0,
            radius: None,
            map: PointMap::DualParaboloid,
        };
        Light { name: "lamp".into(), kind, path: None, cascades: None }
    }

    /// Brabec et al.'s map worked by hand: straight down is the first disk's centre, 45° off
    /// the axis lands at r = tan(22.5°), the horizon at r = 1; depth is linear in the distance.
    #[test]
    fn directions_map_to_the_paraboloid_disk() {
        let dp = DualParaboloid::new(&lamp(), 64);
        let o = Vec3::new(1.0, 2.0, -3.0);
        let down = dp.hemispheres[0].project(o + Vec3::new(0.0, -4.0, 0.0)).unwrap();
        assert!((down.x - 0.5).abs() < 1e-6 && (down.y - 0.5).abs() < 1e-6, "{down}");
        assert!((down.z - (4.0 - 0.1) / (50.0 - 0.1)).abs() < 1e-6, "{down}");
        let slant = dp.hemispheres[0].project(o + Vec3::new(3.0, -3.0, 0.0)).unwrap();
        let r = ((2.0 * slant.x - 1.0).powi(2) + (2.0 * slant.y - 1.0).powi(2)).sqrt();
        assert!((r - 22.5f32.to_radians().tan()).abs() < 1e-6, "{r}");
        let horizon = dp.hemispheres[1].project(o + Vec3::new(0.0, 0.0, 5.0)).unwrap();
        let r = ((2.0 * horizon.x - 1.0).powi(2) + (2.0 * horizon.y - 1.0).powi(2)).sqrt();
        assert!((r - 1.0).abs() < 1e-6, "{r}");
        assert_eq!(dp.texels_from_rim(1, o + Vec3::new(0.0, 0.0, 5.0)).map(|t| t.abs() < 1e-4), Some(true));
        assert_eq!((dp.hemisphere_of(o + Vec3::NEG_Y), dp.hemisphere_of(o + Vec3::Y)), (0, 1));
        assert_eq!(dp.hemisphere_of(o + Vec3::X), 0);
        // The texel at the centre spans 4D/N, at the rim 2D/N.
        let centre = dp.hemispheres[0].texel_world_size(o + Vec3::new(0.0, -4.0, 0.0));
        assert!((centre - 4.0 * 4.0 / 64.0).abs() < 1e-5, "{centre}");
        let rim = dp.hemispheres[0].texel_world_size(o + Vec3::new(4.0, 0.0, 0.0));
        assert!((rim - 2.0 * 4.0 / 64.0).abs() < 1e-5, "{rim}");
    }

    #[test]
    fn a_triangle_across_the_horizon_is_cut_at_it() {
        let dp = DualParaboloid::new(&lamp(), 64);
        let o = Vec3::new(1.0, 2.0, -3.0);
        let tri =
            [o + Vec3::new(-1.0, -1.0, 0.0), o + Vec3::new(1.0, -1.0, 0.0), o + Vec3::new(0.0, 1.0, 1.0)];
        let (front, len) = front_part(&dp.hemispheres[0], &tri);
        assert_eq!(len, 4);
        for p in &front[..len] {
            assert!(p.y - o.y <= 1e-6, "{p}");
        }
        let (back, len) = front_part(&dp.hemispheres[1], &tri);
        assert_eq!(len, 3);
        assert!(back[..len].iter().all(|p| p.y - o.y >= -1e-6));
    }
}
