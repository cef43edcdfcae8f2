//! A forest: a hilly terrain and one closed object of trees on a jittered grid, each a
//! cylinder trunk sunk into the ground and an ellipsoid crown (src/scene/shapes.rs's closed
//! cylinder and sphere, scaled and moved).

use super::count::append_mesh;
use super::generated::{GeneratedObject, GeneratedScene};
use super::terrain::Terrain;
use glam::DVec3;
use shadowtruth::scene::{IndexedMesh, Shape, Transform};
use shadowtruth::trace::splitmix::SplitMix64;

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
    let grove = Grove::new(trees, terrain_cells, seed);
    let (terrain, size_m) = (&grove.terrain, grove.size_m);
    let mut rng = SplitMix64::new(seed ^ TREE_STREAM);
    let mut mesh = IndexedMesh::default();
    let mut top_m: f64 = 0.0;
    for k in 0..trees {
        let (x, z) = grove.spot(k, &mut rng);
        let top = add_tree(&mut mesh, terrain, DVec3::new(x, 0.0, z), &mut rng);
        top_m = top_m.max(top);
    }
    GeneratedScene {
        objects: vec![
            GeneratedObject { name: "terrain", mesh: terrain.mesh(), closed: false, instances: vec![] },
            GeneratedObject { name: "trees", mesh, closed: true, instances: vec![] },
        ],
        ground_size_m: size_m,
        top_m,
    }
}

/// Terrain cells of an instanced forest: its trees take the triangles, the terrain a fixed
/// 2·256² = 131 072.
const INSTANCED_TERRAIN_CELLS: u32 = 256;
/// Triangles of the one tree of an instanced forest: a thousandth of the request, within
/// these bounds, so that a forest of 100M triangles has about a thousand trees.
const INSTANCED_TREE_TRIANGLES: [u64; 2] = [2_000, 500_000];

/// A forest of one tree mesh (trunk and crown, finely tessellated) placed at every tree with a
/// random yaw and size: memory of one tree, `triangles` numbered.
pub(super) fn generate_instanced_forest(triangles: u64, seed: u64) -> GeneratedScene {
    let terrain_triangles = 2 * INSTANCED_TERRAIN_CELLS as u64 * INSTANCED_TERRAIN_CELLS as u64;
    let tree = fine_tree((triangles / 1000).clamp(INSTANCED_TREE_TRIANGLES[0], INSTANCED_TREE_TRIANGLES[1]));
    let trees = (triangles.saturating_sub(terrain_triangles) / tree.triangles.len() as u64).max(2);
    let grove = Grove::new(trees, INSTANCED_TERRAIN_CELLS, seed);
    let (terrain, size_m) = (&grove.terrain, grove.size_m);
    let mut rng = SplitMix64::new(seed ^ TREE_STREAM);
    let mut instances = Vec::new();
    let mut top_m: f64 = 0.0;
    for k in 0..trees {
        let (x, z) = grove.spot(k, &mut rng);
        let size = rng.range([0.7, 1.3]);
        let ground = terrain.lowest_under(x - size, x + size, z - size, z + size) - 0.3;
        top_m = top_m.max(ground + FINE_TREE_HEIGHT_M * size);
        instances.push(Transform {
            scale: glam::Vec3::splat(size as f32),
            rotate_deg: glam::Vec3::new(0.0, rng.range([0.0, 360.0]) as f32, 0.0),
            translate: glam::Vec3::new(x as f32, ground as f32, z as f32),
        });
    }
    GeneratedScene {
        objects: vec![
            GeneratedObject { name: "terrain", mesh: terrain.mesh(), closed: false, instances: vec![] },
            GeneratedObject { name: "tree", mesh: tree, closed: true, instances },
        ],
        ground_size_m: size_m,
        top_m,
    }
}

/// Height of the instanced forest's tree, its base at y = 0.
const FINE_TREE_HEIGHT_M: f64 = 12.0;

/// One tree of about `triangles` triangles: a trunk and an ellipsoid crown, their segment and
/// ring counts grown until they reach it.
fn fine_tree(triangles: u64) -> IndexedMesh {
    let mut segments = CROWN_SEGMENTS;
    let crown = |segments: u32| Shape::Sphere { radius: 1.0, segments, rings: segments / 2 };
    while crown(segments).triangle_count() < triangles && segments < 4096 {
        segments += 2;
    }
    let mut mesh = IndexedMesh::default();
    let trunk = Shape::Cylinder { radius: 0.3, height: 8.0, segments: TRUNK_SEGMENTS }.mesh();
    append_mesh(&mut mesh, &trunk);
    let crown_centre = DVec3::new(0.0, 8.0, 0.0);
    append_mesh(&mut mesh, &moved(&crown(segments).mesh(), DVec3::new(3.0, 4.0, 3.0), crown_centre));
    mesh
}

/// Trees on a jittered square grid `SPACING_M` apart over a hilly terrain of `cells` cells.
struct Grove {
    per_side: u64,
    size_m: f64,
    terrain: Terrain,
}

impl Grove {
    fn new(trees: u64, cells: u32, seed: u64) -> Self {
        let per_side = (trees as f64).sqrt().ceil() as u64;
        let size_m = per_side as f64 * SPACING_M;
        let terrain =
            Terrain { cells, size_m, relief_m: 0.06 * size_m, features: 2.0, seed: seed ^ TERRAIN_STREAM };
        Grove { per_side, size_m, terrain }
    }

    /// Where tree `k` stands (x, z): jittered within its grid cell by two draws from `rng`.
    fn spot(&self, k: u64, rng: &mut SplitMix64) -> (f64, f64) {
        let (row, col) = (k / self.per_side, k % self.per_side);
        let x = (col as f64 + rng.range([0.2, 0.8])) * SPACING_M - self.size_m / 2.0;
        let z = (row as f64 + rng.range([0.2, 0.8])) * SPACING_M - self.size_m / 2.0;
        (x, z)
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
