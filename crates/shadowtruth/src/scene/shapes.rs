//! Procedural shapes, built as indexed meshes in f64 object space.
//!
//! Every vertex is computed once and shared by index, so adjacent triangles meet at bit-identical
//! vertices after the transform: closed shapes are watertight. Triangles are counter-clockwise
//! seen from outside (outward normal = cross(v1 − v0, v2 − v0)); the plane faces +y.

use glam::DVec3;
use std::f64::consts::{PI, TAU};

/// A procedural shape, in object space before its transform. Serialised as a scene file's
/// `shape` object (`format_write.rs`): its `type` and its fields by their names here.
#[derive(Clone, Debug, PartialEq, serde::Serialize)]
#[serde(tag = "type", rename_all = "lowercase")]
pub enum Shape {
    /// A rectangle `size = [sx, sz]` in the xz plane at y = 0, centred, normal +y, tessellated
    /// into `subdivisions × subdivisions` quads.
    Plane { size: [f64; 2], subdivisions: u32 },
    /// An axis-aligned box centred at the origin.
    Box { size: [f64; 3] },
    /// A UV sphere centred at the origin; the poles are triangle fans.
    Sphere { radius: f64, segments: u32, rings: u32 },
    /// Axis y, from y = 0 to y = height, with both caps.
    Cylinder { radius: f64, height: f64, segments: u32 },
    /// Base disk at y = 0, apex at y = height.
    Cone { radius: f64, height: f64, segments: u32 },
}

/// Vertices and counter-clockwise index triangles.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct IndexedMesh {
    pub positions: Vec<DVec3>,
    pub triangles: Vec<[u32; 3]>,
}

impl Shape {
    /// Number of triangles `mesh()` will produce (checked before building huge meshes).
    pub fn triangle_count(&self) -> u64 {
        match *self {
            Shape::Plane { subdivisions: n, .. } => 2 * n as u64 * n as u64,
            Shape::Box { .. } => 12,
            Shape::Sphere { segments, rings, .. } => 2 * segments as u64 * (rings as u64 - 1),
            Shape::Cylinder { segments, .. } => 4 * segments as u64,
            Shape::Cone { segments, .. } => 2 * segments as u64,
        }
    }

    pub fn mesh(&self) -> IndexedMesh {
        match *self {
            Shape::Plane { size, subdivisions } => plane(size, subdivisions),
            Shape::Box { size } => cuboid(size),
            Shape::Sphere { radius, segments, rings } => sphere(radius, segments, rings),
            Shape::Cylinder { radius, height, segments } => cylinder(radius, height, segments),
            Shape::Cone { radius, height, segments } => cone(radius, height, segments),
        }
    }
}

impl IndexedMesh {
    fn vertex(&mut self, p: DVec3) -> u32 {
        self.positions.push(p);
        self.positions.len() as u32 - 1
    }

    /// Adds `n` points of a circle of `radius` at height `y`; returns the first index.
    /// The angle grows from +x towards +z.
    fn ring(&mut self, radius: f64, y: f64, n: u32) -> u32 {
        let first = self.positions.len() as u32;
        for i in 0..n {
            let (s, c) = (TAU * i as f64 / n as f64).sin_cos();
            self.vertex(DVec3::new(radius * c, y, radius * s));
        }
        first
    }

    /// Side band between two rings of `n` points (`upper` above `lower`), outward facing.
    fn band(&mut self, upper: u32, lower: u32, n: u32) {
        for i in 0..n {
            let j = (i + 1) % n;
            self.triangles.push([lower + i, upper + i, lower + j]);
            self.triangles.push([lower + j, upper + i, upper + j]);
        }
    }

    /// Fan from `apex` to a ring: `above` when the apex lies above the ring (outward = up).
    fn fan(&mut self, apex: u32, ring: u32, n: u32, above: bool) {
        for i in 0..n {
            let j = (i + 1) % n;
            let tri = if above { [ring + i, apex, ring + j] } else { [apex, ring + i, ring + j] };
            self.triangles.push(tri);
        }
    }
}

fn plane([sx, sz]: [f64; 2], n: u32) -> IndexedMesh {
    let mut m = IndexedMesh::default();
    let coord = |size: f64, i: u32| size * (i as f64 / n as f64 - 0.5);
    for i in 0..=n {
        for k in 0..=n {
            m.vertex(DVec3::new(coord(sx, i), 0.0, coord(sz, k)));
        }
    }
    let v = |i: u32, k: u32| i * (n + 1) + k;
    for i in 0..n {
        for k in 0..n {
            // Counter-clockwise in the (z, x) plane, i.e. normal +y.
            m.triangles.push([v(i, k), v(i, k + 1), v(i + 1, k + 1)]);
            m.triangles.push([v(i, k), v(i + 1, k + 1), v(i + 1, k)]);
        }
    }
    m
}

fn cuboid(size: [f64; 3]) -> IndexedMesh {
    let h = DVec3::from(size) * 0.5;
    // Corner index bits: 1 = +x, 2 = +y, 4 = +z.
    let positions = (0..8)
        .map(|c| {
            let s = |bit: u32| if c & bit != 0 { 1.0 } else { -1.0 };
            DVec3::new(s(1), s(2), s(4)) * h
        })
        .collect();
    // Each face as a quad, counter-clockwise seen from outside.
    let faces = [[1, 3, 7, 5], [0, 4, 6, 2], [2, 6, 7, 3], [0, 1, 5, 4], [4, 5, 7, 6], [0, 2, 3, 1]];
    let triangles = faces.iter().flat_map(|&[a, b, c, d]| [[a, b, c], [a, c, d]]).collect();
    IndexedMesh { positions, triangles }
}

fn sphere(radius: f64, segments: u32, rings: u32) -> IndexedMesh {
    let mut m = IndexedMesh::default();
    let north = m.vertex(DVec3::new(0.0, radius, 0.0));
    let south = m.vertex(DVec3::new(0.0, -radius, 0.0));
    let bands: Vec<u32> = (1..rings)
        .map(|j| {
            let (s, c) = (PI * j as f64 / rings as f64).sin_cos();
            m.ring(radius * s, radius * c, segments)
        })
        .collect();
    m.fan(north, bands[0], segments, true);
    for w in bands.windows(2) {
        m.band(w[0], w[1], segments);
    }
    m.fan(south, bands[bands.len() - 1], segments, false);
    m
}

fn cylinder(radius: f64, height: f64, n: u32) -> IndexedMesh {
    let mut m = IndexedMesh::default();
    let bottom = m.ring(radius, 0.0, n);
    let top = m.ring(radius, height, n);
    let bottom_centre = m.vertex(DVec3::ZERO);
    let top_centre = m.vertex(DVec3::new(0.0, height, 0.0));
    m.band(top, bottom, n);
    m.fan(bottom_centre, bottom, n, false);
    // The top cap faces +y: reverse the downward fan's order.
    for i in 0..n {
        m.triangles.push([top_centre, top + (i + 1) % n, top + i]);
    }
    m
}

fn cone(radius: f64, height: f64, n: u32) -> IndexedMesh {
    let mut m = IndexedMesh::default();
    let base = m.ring(radius, 0.0, n);
    let centre = m.vertex(DVec3::ZERO);
    let apex = m.vertex(DVec3::new(0.0, height, 0.0));
    m.fan(apex, base, n, true);
    m.fan(centre, base, n, false);
    m
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::collections::HashMap;

    /// Every directed edge appears once and its reverse once: closed, consistently oriented.
    fn assert_watertight(m: &IndexedMesh) {
        let mut edges = HashMap::new();
        for t in &m.triangles {
            for k in 0..3 {
                *edges.entry((t[k], t[(k + 1) % 3])).or_insert(0) += 1;
            }
        }
        for (&(a, b), &n) in &edges {
            assert_eq!(n, 1, "edge {a}->{b} used {n} times");
            assert_eq!(edges.get(&(b, a)), Some(&1), "edge {a}->{b} has no opposite");
        }
    }

    fn signed_volume(m: &IndexedMesh) -> f64 {
        let p = |i: u32| m.positions[i as usize];
        m.triangles.iter().map(|t| p(t[0]).dot(p(t[1]).cross(p(t[2]))) / 6.0).sum()
    }

    fn min_area(m: &IndexedMesh) -> f64 {
        let p = |i: u32| m.positions[i as usize];
        let area = |t: &[u32; 3]| (p(t[1]) - p(t[0])).cross(p(t[2]) - p(t[0])).length() / 2.0;
        m.triangles.iter().map(area).fold(f64::INFINITY, f64::min)
    }

    #[test]
    fn scene_shapes_closed_are_watertight_and_outward() {
        let cases = [
            (Shape::Box { size: [1.0, 2.0, 3.0] }, 6.0, 1e-12),
            (Shape::Sphere { radius: 1.0, segments: 64, rings: 32 }, 4.0 / 3.0 * PI, 0.01),
            // Two triangular pyramids on an equilateral triangle of circumradius 2.
            (Shape::Sphere { radius: 2.0, segments: 3, rings: 2 }, 4.0 * 3f64.sqrt(), 1e-12),
            (Shape::Cylinder { radius: 1.0, height: 2.0, segments: 64 }, 2.0 * PI, 0.01),
            (Shape::Cone { radius: 1.0, height: 3.0, segments: 64 }, PI, 0.01),
        ];
        for (shape, volume, tol) in cases {
            let m = shape.mesh();
            assert_eq!(m.triangles.len() as u64, shape.triangle_count(), "{shape:?}");
            assert_watertight(&m);
            let v = signed_volume(&m);
            assert!(v > 0.0, "{shape:?}: volume {v}");
            assert!((v - volume).abs() <= tol * volume.abs().max(1.0), "{shape:?}: {v}");
            assert!(min_area(&m) > 0.0, "{shape:?} has a degenerate triangle");
        }
    }

    #[test]
    fn scene_shapes_plane_faces_up() {
        let shape = Shape::Plane { size: [2.0, 4.0], subdivisions: 3 };
        let m = shape.mesh();
        assert_eq!(m.triangles.len(), 18);
        let p = |i: u32| m.positions[i as usize];
        let mut area = 0.0;
        for t in &m.triangles {
            let n = (p(t[1]) - p(t[0])).cross(p(t[2]) - p(t[0]));
            assert!(n.y > 0.0 && n.x == 0.0 && n.z == 0.0);
            area += n.y / 2.0;
        }
        assert!((area - 8.0).abs() < 1e-12);
        let xs: Vec<f64> = m.positions.iter().map(|v| v.x).collect();
        assert_eq!(xs.iter().cloned().fold(f64::INFINITY, f64::min), -1.0);
        assert_eq!(xs.iter().cloned().fold(f64::NEG_INFINITY, f64::max), 1.0);
    }
}
