//! A forest: a hilly terrain and one closed object of trees on a jittered grid, each a
//! cylinder trunk sunk into the ground and an ellipsoid crown (src/scene/shapes.rs's closed
//! cylinder and sphere, scaled and moved).

use super::count::append_mesh;
use super::terrain::Terrain;
use super::{GeneratedObject, GeneratedScene};
use crate::scene::{IndexedMesh, Shape};
use crate::trace::splitmix::SplitMix64;
use glam::DVec3;

/// Mean distance between neighbouring trees in metres.
const SPACING_M: f64 = 7.0;
/// The share of the triangles that the terrain gets.
const TERRAIN_SHARE: f64 = 0.4;
const TRUNK_SEGMENTS: u32 = 12;
const CROWN_SEGMENTS: u32 = 16;
const CROWN_RINGS: u32 = 10;
const TERRAIN_STREAM: u64 = 0x6869_6c6c_7300_0000;
const TREE_STREAM: u64 = 0x7472_6565_7300_0000;

fn tree_triangles() -> u64 {
    Shape::Cylinder { radius: 1.0, height: 1.0, segments: TRUNK_SEGMENTS }.triangle_count()
        + Shape::Sphere { radius: 1.0, segments: CROWN_SEGMENTS, rings: CROWN_RINGS }.triangle_count()
}

pub(super) fn generate_forest(triangles: u64, seed: u64) -> GeneratedScene {
    let terrain_cells = Terrain::cells_for((triangles as f64 * TERRAIN_SHARE) as u64);
    let terrain_triangles = 2 * terrain_cells as u64 * terrain_cells as u64;
    let trees = (triangles.saturating_sub(terrain_triangles) / tree_triangles()).max(1);
    let per_side = (trees as f64).sqrt().ceil() as u64;
    let size_m = per_side as f64 * SPACING_M;
    let terrain = Terrain {
        cells: terrain_cells,
        size_m,
        relief_m: 0.06 * size_m,
        features: 2.0,
        seed: seed ^ TERRAIN_STREAM,
    };
    let mut rng = SplitMix64::new(seed ^ TREE_STREAM);
    let mut mesh = IndexedMesh::default();
    let mut top_m: f64 = 0.0;
    for k in 0..trees {
        let (row, col) = (k / per_side, k % per_side);
        let x = (col as f64 + rng.range([0.2, 0.8])) * SPACING_M - size_m / 2.0;
        let z = (row as f64 + rng.range([0.2, 0.8])) * SPACING_M - size_m / 2.0;
        let top = add_tree(&mut mesh, &terrain, DVec3::new(x, 0.0, z), &mut rng);
        top_m = top_m.max(top);
    }
    GeneratedScene {
        objects: vec![
            GeneratedObject { name: "terrain", mesh: terrain.mesh(), closed: false },
            GeneratedObject { name: "trees", mesh, closed: true },
        ],
        ground_size_m: size_m,
        top_m,
    }
}

/// Appends one tree standing at (x, z); returns the height of its crown's top.
fn add_tree(mesh: &mut IndexedMesh, terrain: &Terrain, at: DVec3, rng: &mut SplitMix64) -> f64 {
    let trunk_radius = rng.range([0.15, 0.35]);
    let height = rng.range([6.0, 14.0]);
    let r = trunk_radius;
    let ground = terrain.lowest_under(at.x - r, at.x + r, at.z - r, at.z + r);
    let base = ground - 0.3;
    let trunk =
        Shape::Cylinder { radius: trunk_radius, height: height + 0.3, segments: TRUNK_SEGMENTS }.mesh();
    append_mesh(mesh, &moved(&trunk, DVec3::ONE, DVec3::new(at.x, base, at.z)));
    let crown_radius = rng.range([0.35, 0.6]) * SPACING_M;
    let crown_half_height = crown_radius * rng.range([1.0, 1.8]);
    let centre = DVec3::new(at.x, ground + height, at.z);
    let crown = Shape::Sphere { radius: 1.0, segments: CROWN_SEGMENTS, rings: CROWN_RINGS }.mesh();
    let scale = DVec3::new(crown_radius, crown_half_height, crown_radius);
    append_mesh(mesh, &moved(&crown, scale, centre));
    centre.y + crown_half_height
}

/// `mesh` scaled by a positive `scale` (orientation kept) and moved by `offset`.
fn moved(mesh: &IndexedMesh, scale: DVec3, offset: DVec3) -> IndexedMesh {
    IndexedMesh {
        positions: mesh.positions.iter().map(|&p| p * scale + offset).collect(),
        triangles: mesh.triangles.clone(),
    }
}
