//! Instanced geometry: a mesh stored once in its own space and placed by many instances.
//!
//! An instance's world triangles are defined exactly as if the mesh had been flattened into
//! the scene: each vertex is transformed in f64 and rounded once to f32 (`world_vertex`), the
//! winding is reversed under a mirroring transform, and a triangle whose world vertices are
//! degenerate is skipped. Every consumer (the tracer, the rasterizers, the exports) reads
//! instanced triangles through these rules, so an instanced scene and its flattened copy have
//! the same triangles bit for bit (docs/reference.md, "Instanced geometry").

use glam::{DAffine3, DVec3, Vec3};

/// A mesh in its own space, shared by the instances that place it.
#[derive(Clone, Debug, PartialEq)]
pub struct SharedMesh {
    pub positions: Vec<DVec3>,
    /// Counter-clockwise seen from outside; triangles degenerate in the mesh's own space are
    /// already dropped.
    pub triangles: Vec<[u32; 3]>,
}

impl SharedMesh {
    /// Object-space bounds (min, max) of the vertices that triangles use.
    pub fn bounds(&self) -> (DVec3, DVec3) {
        let mut lo = DVec3::splat(f64::INFINITY);
        let mut hi = DVec3::splat(f64::NEG_INFINITY);
        for &i in self.triangles.iter().flatten() {
            lo = lo.min(self.positions[i as usize]);
            hi = hi.max(self.positions[i as usize]);
        }
        (lo, hi)
    }
}

/// One placement of a shared mesh: its triangles are scene ids `first_triangle ..
/// first_triangle + mesh triangle count`, all of object `object`.
#[derive(Clone, Debug, PartialEq)]
pub struct Instance {
    pub mesh: u32,
    pub object: u32,
    pub world_from_local: DAffine3,
    /// A negative determinant: the winding is reversed so that closed meshes stay
    /// counter-clockwise seen from outside.
    pub mirrored: bool,
    pub first_triangle: u32,
}

impl Instance {
    /// An instance whose triangle ids are not numbered yet. `mirrored`: whether the transform
    /// mirrors, decided from the transform's parts (a determinant of tiny scales underflows).
    pub fn new(mesh: u32, object: u32, world_from_local: DAffine3, mirrored: bool) -> Self {
        Instance { mesh, object, world_from_local, mirrored, first_triangle: 0 }
    }

    /// World triangle `local` of this instance, degenerate or not.
    #[inline]
    pub fn triangle(&self, mesh: &SharedMesh, local: usize) -> [Vec3; 3] {
        let [a, b, c] =
            mesh.triangles[local].map(|i| world_vertex(&self.world_from_local, mesh.positions[i as usize]));
        if self.mirrored { [a, c, b] } else { [a, b, c] }
    }

    /// World triangle `local` from `world`, the mesh's vertices already in world space
    /// (`world_vertex` of each): the same triangle as [`Instance::triangle`].
    #[inline]
    pub fn triangle_of(&self, world: &[Vec3], mesh: &SharedMesh, local: usize) -> [Vec3; 3] {
        let [a, b, c] = mesh.triangles[local].map(|i| world[i as usize]);
        if self.mirrored { [a, c, b] } else { [a, b, c] }
    }

    /// World triangle `local`, or `None` when it is degenerate in world space (the triangle
    /// that flattening would have dropped).
    #[inline]
    pub fn world_triangle(&self, mesh: &SharedMesh, local: usize) -> Option<[Vec3; 3]> {
        let tri = self.triangle(mesh, local);
        (!is_degenerate(&tri)).then_some(tri)
    }
}

/// An object-space vertex in world space, transformed in f64 and rounded once to f32: the one
/// rule for flattened and instanced geometry alike.
#[inline]
pub fn world_vertex(world_from_local: &DAffine3, p: DVec3) -> Vec3 {
    world_from_local.transform_point3(p).as_vec3()
}

/// The eight corners of the box (lo, hi).
pub fn box_corners(lo: DVec3, hi: DVec3) -> [DVec3; 8] {
    std::array::from_fn(|c| {
        let pick = |bit: usize, l: f64, h: f64| if c & bit != 0 { h } else { l };
        DVec3::new(pick(1, lo.x, hi.x), pick(2, lo.y, hi.y), pick(4, lo.z, hi.z))
    })
}

/// Zero area in f32 world space: two vertices equal or the edges parallel. The cross product is
/// taken in f64, where the differences and products of f32 coordinates are (nearly) exact, so
/// tiny but valid triangles are kept.
#[inline]
pub fn is_degenerate([a, b, c]: &[Vec3; 3]) -> bool {
    if a == b || b == c || a == c {
        return true;
    }
    let (a, b, c) = (a.as_dvec3(), b.as_dvec3(), c.as_dvec3());
    (b - a).cross(c - a) == DVec3::ZERO
}
