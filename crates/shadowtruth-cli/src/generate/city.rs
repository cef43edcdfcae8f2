//! A city: a gentle terrain and one closed object of buildings, one per lot of a square grid of
//! lots, each a box of varied footprint and height whose faces are tessellated into a lattice
//! (the lattice's cell size is what sets the triangle count).

use super::count::append_mesh;
use super::generated::{GeneratedObject, GeneratedScene};
use super::terrain::Terrain;
use glam::DVec3;
use shadowtruth::scene::IndexedMesh;
use shadowtruth::trace::splitmix::SplitMix64;
use std::collections::HashMap;

/// Side of one lot (building and street) in metres.
const LOT_M: f64 = 30.0;
/// The share of the triangles that the terrain gets.
const TERRAIN_SHARE: f64 = 0.4;
/// Lots per side at most.
const MAX_LOTS: u32 = 32;
/// Stream constants: the terrain and the buildings draw from independent generators.
const TERRAIN_STREAM: u64 = 0x7465_7272_6169_6e00;
const BUILDING_STREAM: u64 = 0x6275_696c_6469_6e67;

/// A building's box before tessellation.
struct Building {
    min: DVec3,
    max: DVec3,
}

pub(super) fn generate_city(triangles: u64, seed: u64) -> GeneratedScene {
    let lots = ((triangles as f64 / 400.0).sqrt().round() as u32).clamp(1, MAX_LOTS);
    let size_m = lots as f64 * LOT_M;
    let terrain = Terrain {
        cells: Terrain::cells_for((triangles as f64 * TERRAIN_SHARE) as u64),
        size_m,
        relief_m: 0.02 * size_m,
        features: 3.0,
        seed: seed ^ TERRAIN_STREAM,
    };
    let buildings = place_buildings(&terrain, lots, seed ^ BUILDING_STREAM);
    let budget = triangles.saturating_sub(terrain.triangle_count());
    let cell_m = lattice_cell_for(&buildings, budget);
    let mut mesh = IndexedMesh::default();
    for b in &buildings {
        append_mesh(&mut mesh, &lattice_box(b, lattice_counts(b, cell_m)));
    }
    let top_m = buildings.iter().map(|b| b.max.y).fold(0.0, f64::max);
    GeneratedScene {
        objects: vec![
            GeneratedObject { name: "terrain", mesh: terrain.mesh(), closed: false, instances: vec![] },
            GeneratedObject { name: "buildings", mesh, closed: true, instances: vec![] },
        ],
        ground_size_m: size_m,
        top_m,
    }
}

/// One building per lot: footprint 45–85 % of the lot, heights from low houses to towers.
fn place_buildings(terrain: &Terrain, lots: u32, seed: u64) -> Vec<Building> {
    let mut rng = SplitMix64::new(seed);
    let mut out = Vec::with_capacity(lots as usize * lots as usize);
    for row in 0..lots {
        for col in 0..lots {
            let centre_x = (col as f64 + 0.5) * LOT_M - terrain.size_m / 2.0;
            let centre_z = (row as f64 + 0.5) * LOT_M - terrain.size_m / 2.0;
            let (w, d) = (rng.range([0.45, 0.85]) * LOT_M, rng.range([0.45, 0.85]) * LOT_M);
            let tall = rng.next_f64();
            let height = LOT_M * (0.3 + 4.0 * tall * tall * tall);
            let (x0, x1) = (centre_x - w / 2.0, centre_x + w / 2.0);
            let (z0, z1) = (centre_z - d / 2.0, centre_z + d / 2.0);
            // Sunk below the lowest terrain vertex around it: no gap under any wall.
            let ground = terrain.lowest_under(x0, x1, z0, z1);
            out.push(Building {
                min: DVec3::new(x0, ground - 0.5, z0),
                max: DVec3::new(x1, ground + height, z1),
            });
        }
    }
    out
}

/// Lattice cells along x, y and z of a building for a cell size.
fn lattice_counts(b: &Building, cell_m: f64) -> [u32; 3] {
    let e = b.max - b.min;
    [e.x, e.y, e.z].map(|l| ((l / cell_m).ceil() as u32).max(1))
}

fn box_triangles([nx, ny, nz]: [u32; 3]) -> u64 {
    let (nx, ny, nz) = (nx as u64, ny as u64, nz as u64);
    4 * (nx * ny + ny * nz + nz * nx)
}

/// The cell size whose buildings together have about `budget` triangles (bisection on a
/// logarithmic scale: the count falls as the cell grows).
fn lattice_cell_for(buildings: &[Building], budget: u64) -> f64 {
    let count = |cell: f64| buildings.iter().map(|b| box_triangles(lattice_counts(b, cell))).sum::<u64>();
    let (mut lo, mut hi) = (1e-3f64, 1e4f64);
    for _ in 0..60 {
        let mid = (lo * hi).sqrt();
        if count(mid) > budget { lo = mid } else { hi = mid }
    }
    // Of the two bracketing sizes, the one closer to the budget.
    if count(lo).abs_diff(budget) < count(hi).abs_diff(budget) { lo } else { hi }
}

/// A closed box tessellated into an `n[0] × n[1] × n[2]` lattice on its surface, every lattice
/// point one shared vertex (watertight), triangles counter-clockwise seen from outside.
fn lattice_box(b: &Building, n: [u32; 3]) -> IndexedMesh {
    let mut mesh = IndexedMesh::default();
    let mut index: HashMap<[u32; 3], u32> = HashMap::new();
    let extent = b.max - b.min;
    let mut vertex = |mesh: &mut IndexedMesh, p: [u32; 3]| -> u32 {
        *index.entry(p).or_insert_with(|| {
            let t =
                DVec3::new(p[0] as f64 / n[0] as f64, p[1] as f64 / n[1] as f64, p[2] as f64 / n[2] as f64);
            mesh.positions.push(b.min + extent * t);
            mesh.positions.len() as u32 - 1
        })
    };
    for axis in 0..3 {
        for high in [false, true] {
            // (u, v) with u × v = +axis; swapped on the low side so that u × v points outwards.
            let (mut u, mut v) = ((axis + 1) % 3, (axis + 2) % 3);
            if !high {
                std::mem::swap(&mut u, &mut v);
            }
            for i in 0..n[u] {
                for j in 0..n[v] {
                    let corner = |di: u32, dj: u32| {
                        let mut p = [0u32; 3];
                        p[axis] = if high { n[axis] } else { 0 };
                        p[u] = i + di;
                        p[v] = j + dj;
                        p
                    };
                    let q = [corner(0, 0), corner(1, 0), corner(1, 1), corner(0, 1)]
                        .map(|p| vertex(&mut mesh, p));
                    mesh.triangles.push([q[0], q[1], q[2]]);
                    mesh.triangles.push([q[0], q[2], q[3]]);
                }
            }
        }
    }
    mesh
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn generate_lattice_boxes_are_closed_and_face_outwards() {
        let b = Building { min: DVec3::new(-1.0, 0.0, -2.0), max: DVec3::new(1.0, 3.0, 2.0) };
        let n = [2, 3, 4];
        let mesh = lattice_box(&b, n);
        assert_eq!(mesh.triangles.len() as u64, box_triangles(n));
        // Closed: every directed edge has its reverse.
        let edges: std::collections::HashSet<(u32, u32)> =
            mesh.triangles.iter().flat_map(|t| [(t[0], t[1]), (t[1], t[2]), (t[2], t[0])]).collect();
        assert!(edges.iter().all(|&(a, b)| edges.contains(&(b, a))));
        // Outward: the normal points away from the centre.
        let centre = (b.min + b.max) / 2.0;
        for t in &mesh.triangles {
            let [p0, p1, p2] = t.map(|i| mesh.positions[i as usize]);
            assert!((p1 - p0).cross(p2 - p0).dot((p0 + p1 + p2) / 3.0 - centre) > 0.0);
        }
    }
}
