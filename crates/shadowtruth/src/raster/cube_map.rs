//! A point light's cube shadow map (docs/point-lights.md): six 90° perspective faces from the
//! light's position, in the order and orientation of OpenGL's and Vulkan's cube faces (+x, −x,
//! +y, −y, +z, −z), each face chosen for a point by the major axis of its direction from the
//! light, as a cube-map lookup chooses it.
//!
//! Every face is drawn `guard_texels` beyond each of its edges at its own texel size (a face of
//! N² texels is a map of (N + 2g)² whose frustum is widened to match): a filter tap up to g
//! texels past an edge reads the scene in its direction, as a seamless cube lookup reads the
//! neighbouring face, and so every technique runs on a face unchanged. Beyond the guard band a
//! tap clamps to the map's edge; with g = 0 every filter clamps at the seams, the seam error
//! engines without seamless filtering show.
//!
//! Each face is a right-handed light view (the light looks down −z), so its u runs opposite to
//! the cube's s coordinate (cube maps are left-handed); v runs along −t, the cube's t pointing
//! down the face. Face selection and the depth of every texel do not depend on that choice.

use super::projection::{LightView, finite_or_origin, perspective, view_from_basis};
use crate::scene::{CubeSettings, Light, LightKind, PointMap};
use glam::{DVec3, Vec3};

/// The faces' names, in the cube's order.
pub const CUBE_FACE_NAMES: [&str; 6] = ["+x", "-x", "+y", "-y", "+z", "-z"];

/// A point is *near a seam* within this many texels of its face's edge: where a 5×5 PCF kernel
/// and its bilinear taps reach past the edge.
pub const SEAM_TEXELS: f32 = 3.0;

/// The six faces of a point light's cube map at one resolution.
#[derive(Clone, Debug, PartialEq)]
pub struct CubeMap {
    /// The faces in `CUBE_FACE_NAMES` order, each `resolution + 2·guard_texels` texels square.
    pub faces: Vec<LightView>,
    /// The resolution N of a face without its guard band.
    pub resolution: u32,
    pub guard_texels: u32,
    position: Vec3,
}

impl CubeMap {
    /// The cube of the point `light` with faces of `resolution`² texels (plus its guard band;
    /// none for a light whose map is dual paraboloids, which `DualParaboloid` builds).
    pub fn new(light: &Light, resolution: u32) -> Self {
        let LightKind::Point { position, near, far, map, .. } = light.kind else {
            unreachable!("cube maps are built for point lights only")
        };
        let cube = match map {
            PointMap::Cube(cube) => cube,
            PointMap::DualParaboloid => CubeSettings { guard_texels: 0 },
        };
        let guard = cube.guard_texels;
        let eye = finite_or_origin(position);
        let n = resolution.max(1);
        // The face's frustum widened by the guard band: tan of its half-angle is (N + 2g)/N.
        let tan_half_fov = (n + 2 * guard) as f64 / n as f64;
        let faces = (0..6)
            .map(|face| {
                let (forward, up) = face_axes(face);
                let light_from_world = view_from_basis(eye, forward.cross(up), up, forward);
                let view = perspective(light_from_world, eye, tan_half_fov, (near, far), n + 2 * guard);
                LightView { light_size: light.size().ok(), ..view }
            })
            .collect();
        CubeMap { faces, resolution: n, guard_texels: guard, position: eye.as_vec3() }
    }

    /// The face that shades `p`: the major axis of p − position, computed in f32 as a shader
    /// computes the lookup vector; ties go to x, then y (the faces' order), its sign to the
    /// positive face at 0.
    pub fn face_of(&self, p: Vec3) -> usize {
        let d = p - self.position;
        let a = d.abs();
        let (axis, sign) = if a.x >= a.y && a.x >= a.z {
            (0, d.x)
        } else if a.y >= a.z {
            (1, d.y)
        } else {
            (2, d.z)
        };
        2 * axis + usize::from(sign < 0.0)
    }

    /// How many texels of `face` lie between `p`'s projection and the nearest edge of the face
    /// proper (its N² texels, inside the guard band); None when `p` does not project.
    pub fn texels_from_edge(&self, face: usize, p: Vec3) -> Option<f32> {
        let uvd = self.faces[face].project(p)?;
        let side = self.faces[face].resolution as f32;
        let (g, n) = (self.guard_texels as f32, self.resolution as f32);
        let (x, y) = (uvd.x * side - g, uvd.y * side - g);
        Some(x.min(n - x).min(y).min(n - y))
    }
}

/// The forward and up axes of cube face `face` (OpenGL's table of cube-map faces: up is −t).
fn face_axes(face: usize) -> (DVec3, DVec3) {
    match face {
        0 => (DVec3::X, DVec3::Y),
        1 => (DVec3::NEG_X, DVec3::Y),
        2 => (DVec3::Y, DVec3::NEG_Z),
        3 => (DVec3::NEG_Y, DVec3::Z),
        4 => (DVec3::Z, DVec3::Y),
        _ => (DVec3::NEG_Z, DVec3::Y),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn lamp(guard_texels: u32) -> Light {
        let kind = LightKind::Point {
            position: Vec3::new(1.0, 2.0, -3.0),
            near: 0.1,
            far: 50.0,
            radius: None,
            map: PointMap::Cube(CubeSettings { guard_texels }),
        };
        Light { name: "lamp".into(), kind, path: None, cascades: None }
    }

    #[test]
    fn each_axis_direction_lands_in_its_face_centre() {
        let cube = CubeMap::new(&lamp(0), 64);
        let dirs = [Vec3::X, Vec3::NEG_X, Vec3::Y, Vec3::NEG_Y, Vec3::Z, Vec3::NEG_Z];
        for (face, d) in dirs.into_iter().enumerate() {
            let p = Vec3::new(1.0, 2.0, -3.0) + 4.0 * d;
            assert_eq!(cube.face_of(p), face, "{}", CUBE_FACE_NAMES[face]);
            let uvd = cube.faces[face].project(p).unwrap();
            assert!((uvd.x - 0.5).abs() < 1e-6 && (uvd.y - 0.5).abs() < 1e-6, "{uvd}");
            assert!((cube.faces[face].view_depth(p) - 4.0).abs() < 1e-5);
        }
    }

    /// The cube's (s, t) of OpenGL's table (the OpenGL 4.6 specification, table 8.19), worked by
    /// hand for one direction per face: u = 1 − s (the faces are right-handed), v = 1 − t.
    #[test]
    fn faces_follow_the_cube_map_orientation_table() {
        let cube = CubeMap::new(&lamp(0), 64);
        let origin = Vec3::new(1.0, 2.0, -3.0);
        // (direction, face, s, t) with s = (sc/|ma| + 1)/2, t = (tc/|ma| + 1)/2.
        let cases = [
            (Vec3::new(2.0, 0.5, 1.0), 0, (1.0 - 0.5) / 2.0, (1.0 - 0.25) / 2.0), // sc = −rz, tc = −ry
            (Vec3::new(-2.0, 0.5, 1.0), 1, (1.0 + 0.5) / 2.0, (1.0 - 0.25) / 2.0), // sc = rz, tc = −ry
            (Vec3::new(0.5, 2.0, 1.0), 2, (1.0 + 0.25) / 2.0, (1.0 + 0.5) / 2.0), // sc = rx, tc = rz
            (Vec3::new(0.5, -2.0, 1.0), 3, (1.0 + 0.25) / 2.0, (1.0 - 0.5) / 2.0), // sc = rx, tc = −rz
            (Vec3::new(0.5, 1.0, 2.0), 4, (1.0 + 0.25) / 2.0, (1.0 - 0.5) / 2.0), // sc = rx, tc = −ry
            (Vec3::new(0.5, 1.0, -2.0), 5, (1.0 - 0.25) / 2.0, (1.0 - 0.5) / 2.0), // sc = −rx, tc = −ry
        ];
        for (d, face, s, t) in cases {
            assert_eq!(cube.face_of(origin + d), face);
            let uvd = cube.faces[face].project(origin + d).unwrap();
            let (u, v) = (1.0 - s, 1.0 - t);
            assert!((uvd.x - u).abs() < 1e-6 && (uvd.y - v).abs() < 1e-6, "{face}: {uvd} vs ({u}, {v})");
        }
    }

    #[test]
    fn the_guard_band_keeps_the_face_texel_and_widens_the_map() {
        let (plain, guarded) = (CubeMap::new(&lamp(0), 64), CubeMap::new(&lamp(4), 64));
        assert_eq!(plain.faces[0].resolution, 64);
        assert_eq!(guarded.faces[0].resolution, 72);
        let p = Vec3::new(1.0, 2.0, -3.0) + Vec3::new(3.0, 1.0, 0.5);
        let texel = |cube: &CubeMap| cube.faces[cube.face_of(p)].texel_world_size(p);
        assert!((texel(&plain) - texel(&guarded)).abs() < 1e-6);
        // The face's edge towards +z (45°; the +x face's u runs along +z) sits g texels inside
        // the guarded map: u·(N + 2g) = N + g.
        let edge = Vec3::new(1.0, 2.0, -3.0) + Vec3::new(2.0, 0.0, 2.0);
        let u = guarded.faces[0].project(edge).unwrap().x * 72.0;
        assert!((u - 68.0).abs() < 1e-4, "{u}");
        assert!(guarded.texels_from_edge(0, edge).unwrap().abs() < 1e-4);
        // A direction 2 texels past the edge (a texel is 2/N in tan) is still inside the map.
        let past = Vec3::new(1.0, 2.0, -3.0) + Vec3::new(2.0, 0.0, 2.0 * (1.0 + 4.0 / 64.0));
        let u = guarded.faces[0].project(past).unwrap().x * 72.0;
        assert!((u - 70.0).abs() < 1e-4, "{u}");
    }

    #[test]
    fn ties_go_to_x_then_y() {
        let cube = CubeMap::new(&lamp(0), 8);
        let o = Vec3::new(1.0, 2.0, -3.0);
        assert_eq!(cube.face_of(o + Vec3::new(1.0, 1.0, 1.0)), 0);
        assert_eq!(cube.face_of(o + Vec3::new(-1.0, 1.0, 1.0)), 1);
        assert_eq!(cube.face_of(o + Vec3::new(0.5, -1.0, 1.0)), 3);
        assert_eq!(cube.face_of(o), 0);
    }
}
