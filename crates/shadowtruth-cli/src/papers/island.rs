//! The island of Ehm et al., "Adaptive depth bias for soft shadows" (WSCG 2015), Figure 12, as a
//! seeded procedural scene: noisy terrain rising from a sea plane, a few dozen thin-trunked trees,
//! one spot light shining across it, a `front` camera on the lit side and a `back` camera where
//! the light grazes the slopes. The paper's scene is not published; this is an analogue with the
//! properties its figure relies on: a perspective (spot) shadow map, a front that is well lit and
//! a back that the light grazes (Figure 12: few errors on the front, projective aliasing on the
//! back), thin occluders (trunks) whose shadows detach under a large bias, and a scene whose
//! bounding box is the island's own, since Ehm et al.'s enhanced epsilon scales with sceneScale,
//! the bounding-box diagonal (Dou et al. 2014).
//!
//! # Algorithm
//!
//! Everything is generated serially from `seed` with SplitMix64 (Steele, Lea & Flood 2014), a
//! 64-bit counter hashed by a finalizer: tiny, statistically good enough for placement, and
//! identical on every platform. Two independent streams (`TERRAIN_STREAM`, `TREE_STREAM`) keep
//! the terrain unchanged when the tree rules change. Only `+ − × ÷`, `floor` and `sqrt` are used
//! (all correctly rounded in IEEE 754), never `sin`, `exp` or `pow`, whose results differ between
//! math libraries: the same seed gives the same bytes everywhere.
//!
//! 1. **Terrain.** A `GRID_QUADS`² grid over `[−TERRAIN_HALF_SIZE_M, TERRAIN_HALF_SIZE_M]²` (x, z).
//!    Height = `PEAK_HEIGHT_M · falloff(r) · max(0, NOISE_BASE + NOISE_AMPLITUDE · fbm(x, z)) −
//!    SEA_FLOOR_DEPTH_M`, where `r` is the distance from the centre over `ISLAND_RADIUS_M`,
//!    `falloff(r) = max(0, 1 − r²)` (1 at the centre, 0 from `r = 1` on) and `fbm` is
//!    `OCTAVES` octaves of 2D gradient noise (Perlin 2002: quintic fade, gradients picked by a
//!    hash of the lattice point from 8 unit directions), frequency `NOISE_FREQUENCY_PER_M`
//!    doubling and amplitude halving per octave, each octave shifted by a seeded offset so that
//!    their lattices do not line up. The island therefore rises from a flat sea floor, sinks
//!    below the sea towards the edges, and has hills and valleys of a few metres' wavelength.
//!    Heights are rounded to `HEIGHT_DECIMALS` decimals and the rounded values are the truth:
//!    they are what the OBJ holds and what trees are placed on. Each grid quad is split along
//!    its (i, j)–(i+1, j+1) diagonal into two counter-clockwise (upward-facing) triangles.
//! 2. **Sea.** An open `plane` of `SEA_SIZE_M` at y = 0, `SEA_FLOOR_DEPTH_M` above the flat sea
//!    floor, exactly as wide as the terrain grid: the scene's bounding box (and so sceneScale,
//!    about 17 m) is that of the island and its surroundings, not of an open sea. The cameras see
//!    sky beyond the sea's edge (background, not scored).
//! 3. **Light.** The spot `sun_spot` sits over the sea at `LIGHT_POSITION` and aims at
//!    `LIGHT_TARGET`, across the island; `LIGHT_CONE_DEG` covers the whole island, `LIGHT_NEAR_M`
//!    and `LIGHT_FAR_M` bracket it, and `LIGHT_RADIUS_M` gives it an area for soft shadows.
//! 4. **Featured tree (tree00).** The land grid vertex on the light's side of the island whose
//!    normal faces the light most (slope between `FEATURED_SLOPE_MIN` and `FEATURED_SLOPE_MAX`
//!    as the normal's y, at least `FEATURED_MIN_HEIGHT_M` above the sea): its trunk is lit and
//!    its shadow falls up the lit slope behind it. It has the thickest trunk (`FEATURED_TRUNK_*`).
//! 5. **Cameras.** `front` stands `FRONT_CAMERA_DISTANCE_M` from the featured tree, between the
//!    light's direction and its side (`FRONT_CAMERA_SIDE`), so the tree's shadow is seen beside
//!    the tree rather than hidden behind it; it looks at the point between the trunk and its
//!    shadow. `back` stands on the far side of the island from the light (`BACK_CAMERA_*`),
//!    facing the slopes that turn away from the light, where the rays graze the surface.
//! 6. **Trees.** Uniform candidates in the disk of radius `ISLAND_RADIUS_M` are rejected when
//!    under `TREE_MIN_HEIGHT_M`, steeper than `TREE_MIN_NORMAL_Y`, closer than `TREE_SPACING_M`
//!    to another tree, or within `VIEW_CORRIDOR_M` of the front camera's line of sight to the
//!    featured trunk (so nothing hides it), until `TREE_COUNT` trees stand or `TREE_ATTEMPTS`
//!    candidates were tried. Each is a closed `cylinder` trunk (radius and height drawn from
//!    `TRUNK_RADIUS_M`, `TRUNK_HEIGHT_M`) sunk `TRUNK_SINK_M` below the lowest ground under it,
//!    and a closed crown: a `cone` (`CONE_*`) or, with probability `SPHERE_CROWN_PROBABILITY`, a
//!    `sphere` (`SPHERE_RADIUS_M`), starting at `CROWN_START` of the trunk's height so that the
//!    lower trunk stays bare and visible.
//!
//! Objects are named `terrain`, `sea`, `tree00_trunk`, `tree00_crown`, `tree01_trunk`, …

use crate::decimals::{rounded, rounded_f32, rounded_vec3};
use glam::{DVec3, Vec3};
use shadowtruth::atomic_file::write_atomic;
use shadowtruth::scene::{
    Camera, Geometry, Light, LightKind, ObjectPlacement, SceneFile, SceneFileObject, Shape, Transform,
};
use shadowtruth::trace::splitmix::{SplitMix64, finalizer};
use std::fmt::Write as _;
use std::path::Path;

/// The seed of the committed `scenes/papers/island.json` (the paper's year).
pub const ISLAND_SEED: u64 = 2015;
/// The featured tree's trunk object name.
pub const FEATURED_TRUNK: &str = "tree00_trunk";
/// Scene file name, and the terrain mesh's path relative to it.
pub const ISLAND_SCENE_FILE: &str = "island.json";
pub const ISLAND_TERRAIN_FILE: &str = "meshes/island_terrain.obj";

/// Quads per side of the terrain grid: 96² quads = 18 432 triangles, 0.125 m apart, keeps the
/// OBJ under 600 KB while hills still span a dozen quads.
const GRID_QUADS: usize = 96;
/// Half the side of the terrain grid; beyond `ISLAND_RADIUS_M` it is flat sea floor.
const TERRAIN_HALF_SIZE_M: f64 = 6.0;
/// Where the falloff reaches zero; the coast lies about a metre inside it, so the island is
/// about 10 m across.
const ISLAND_RADIUS_M: f64 = 5.8;
/// Height scale: hills up to about a metre, as tall as the trees, low against a 10 m island, so
/// that most slopes stay gentler than the light's elevation (grazing rather than facing away).
const PEAK_HEIGHT_M: f64 = 1.4;
/// Mean of the noise factor: the island's bulk height before noise.
const NOISE_BASE: f64 = 0.7;
/// Amplitude of the fBm (whose values stay within about ±1): deep enough valleys that some
/// slopes turn away from the light.
const NOISE_AMPLITUDE: f64 = 0.45;
/// Lowest octave's frequency: a wavelength of about 3 m, a few hills across the island.
const NOISE_FREQUENCY_PER_M: f64 = 0.3;
/// Octaves of fBm; the finest has a wavelength of 3.3 m / 8 ≈ 0.4 m, three grid quads.
const OCTAVES: usize = 4;
/// The flat sea floor lies this far under the sea plane: the sea is slightly above the lowest
/// terrain, so the coast is where the terrain crosses y = 0.
const SEA_FLOOR_DEPTH_M: f64 = 0.3;
/// Decimals of the written heights (10 µm): far below any shadow feature.
const HEIGHT_DECIMALS: usize = 5;
/// Side of the sea plane: the terrain grid's, so that the sea adds nothing to the scene's bounds
/// (an 80 m sea made sceneScale 113 m instead of 17 m, and the enhanced epsilon's cap a metre).
const SEA_SIZE_M: f64 = 2.0 * TERRAIN_HALF_SIZE_M;

/// The light over the sea on the island's −x side, 6 m up: the rays meet flat ground at about
/// 45° on the near shore, 27° in the middle and 20° on the far shore, so the slopes facing the
/// light (the front) are well lit and those turned away from it (the back) are grazed, as in
/// Figure 12. (3.2 m grazed the whole island: a third of the front had N·L < 0.2.)
const LIGHT_POSITION: [f64; 3] = [-11.0, 6.0, -2.0];
/// Aimed across the island's middle.
const LIGHT_TARGET: [f64; 3] = [0.5, 0.0, 0.5];
/// Full cone angle that covers the island from the light's distance (checked by the tests).
const LIGHT_CONE_DEG: f64 = 72.0;
/// Depth range: the island lies about 5 to 17 m along the axis (checked by the tests with a
/// margin); a far near plane keeps the perspective depth precise.
const LIGHT_NEAR_M: f64 = 2.0;
const LIGHT_FAR_M: f64 = 25.0;
/// Radius of the light's disk for soft-shadow techniques and the area-light reference.
const LIGHT_RADIUS_M: f64 = 0.3;

/// Featured tree: slope range (normal's y) and lowest ground, so it stands on a real slope
/// facing the light, above the beach.
const FEATURED_SLOPE_MIN: f64 = 0.82;
const FEATURED_SLOPE_MAX: f64 = 0.97;
const FEATURED_MIN_HEIGHT_M: f64 = 0.4;
/// Its trunk: the thickest of the island, bare for 0.75 m, so the front view sees it clearly.
const FEATURED_TRUNK_RADIUS_M: f64 = 0.055;
const FEATURED_TRUNK_HEIGHT_M: f64 = 1.0;
const FEATURED_CONE_RADIUS_M: f64 = 0.3;
const FEATURED_CONE_HEIGHT_M: f64 = 0.8;

/// Front camera: distance from the featured tree (horizontal), height above it, and the mix
/// of the towards-light and sideways directions it stands in (a unit pair, 53° off the light).
const FRONT_CAMERA_DISTANCE_M: f64 = 4.5;
const FRONT_CAMERA_HEIGHT_M: f64 = 2.6;
const FRONT_CAMERA_TOWARDS_LIGHT: f64 = 0.6;
const FRONT_CAMERA_SIDE: f64 = 0.8;
/// How far along the tree's shadow the front camera looks, and how high.
const FRONT_LOOK_ALONG_SHADOW_M: f64 = 0.6;
const FRONT_LOOK_HEIGHT_M: f64 = 0.3;
const FRONT_FOV_DEG: f64 = 40.0;
/// Back camera: beyond the island from the light, a little to the side, looking back at the
/// slopes that turn away from the light.
const BACK_CAMERA_AWAY_M: f64 = 6.5;
const BACK_CAMERA_SIDE_M: f64 = -2.5;
const BACK_CAMERA_HEIGHT_M: f64 = 4.5;
const BACK_LOOK_AWAY_M: f64 = 0.8;
const BACK_LOOK_HEIGHT_M: f64 = 0.3;
const BACK_FOV_DEG: f64 = 45.0;
/// Both cameras: the paper's figure size.
const IMAGE_WIDTH: u32 = 1024;
const IMAGE_HEIGHT: u32 = 768;

/// Trees including the featured one, and how many candidates may be tried for them.
const TREE_COUNT: usize = 32;
const TREE_ATTEMPTS: usize = 20_000;
/// Lowest ground for a tree: above the beach.
const TREE_MIN_HEIGHT_M: f64 = 0.25;
/// Steepest ground for a tree, as the normal's y (about 35°).
const TREE_MIN_NORMAL_Y: f64 = 0.82;
/// Least distance between two trees' axes: crowns barely touch.
const TREE_SPACING_M: f64 = 0.7;
/// Clear corridor around the front camera's line of sight to the featured trunk.
const VIEW_CORRIDOR_M: f64 = 0.8;
/// Trunk radius and height ranges: thin trunks (about 1 % of the island's width).
const TRUNK_RADIUS_M: [f64; 2] = [0.035, 0.05];
const TRUNK_HEIGHT_M: [f64; 2] = [0.6, 1.0];
/// The trunk's bottom lies this far under the lowest ground around it: no gap on slopes.
const TRUNK_SINK_M: f64 = 0.03;
/// Crowns start at this fraction of the trunk's height (the rest of the trunk is inside).
const CROWN_START: f64 = 0.75;
const CONE_RADIUS_M: [f64; 2] = [0.22, 0.34];
const CONE_HEIGHT_M: [f64; 2] = [0.55, 0.9];
const SPHERE_RADIUS_M: [f64; 2] = [0.2, 0.3];
const SPHERE_CROWN_PROBABILITY: f64 = 0.3;
/// Tessellation: enough for round silhouettes in a 1024-pixel view.
const TRUNK_SEGMENTS: u32 = 16;
const CROWN_SEGMENTS: u32 = 24;
const SPHERE_RINGS: u32 = 12;

/// Stream selectors xored into the seed (arbitrary distinct constants).
const TERRAIN_STREAM: u64 = 0x7465_7272_6169_6e00; // "terrain"
const TREE_STREAM: u64 = 0x7472_6565_7300_0000; // "trees"

/// A generated island: the scene file's text and the terrain OBJ's text.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Island {
    pub scene_json: String,
    pub terrain_obj: String,
}

/// Generates the island for `seed`; the same seed gives the same bytes.
pub fn generate_island(seed: u64) -> Island {
    let terrain = Heightfield::generate(seed);
    let light = Spot::new();
    let featured = featured_site(&terrain, &light);
    let front = front_camera(&terrain, &light, featured);
    let back = back_camera(&light);
    let trees = place_trees(seed, &terrain, featured, front.position);
    Island { scene_json: scene_json(&light, &[front, back], &trees), terrain_obj: terrain.obj(seed) }
}

/// Writes `dir/island.json` and `dir/meshes/island_terrain.obj` (creating the folders), each
/// atomically; the mesh first, so the scene never names a mesh that is not there yet.
pub fn write_island(dir: &Path, seed: u64) -> std::io::Result<()> {
    let island = generate_island(seed);
    write_atomic(&dir.join(ISLAND_TERRAIN_FILE), island.terrain_obj.as_bytes())?;
    write_atomic(&dir.join(ISLAND_SCENE_FILE), island.scene_json.as_bytes())
}

/// 1/√2: the diagonal gradients' components.
const DIAGONAL: f64 = std::f64::consts::FRAC_1_SQRT_2;
/// The 8 unit gradients of the noise lattice (axes and diagonals).
const GRADIENTS: [[f64; 2]; 8] = [
    [1.0, 0.0],
    [-1.0, 0.0],
    [0.0, 1.0],
    [0.0, -1.0],
    [DIAGONAL, DIAGONAL],
    [-DIAGONAL, DIAGONAL],
    [DIAGONAL, -DIAGONAL],
    [-DIAGONAL, -DIAGONAL],
];

/// 2D gradient noise (Perlin 2002) of one octave: values within about ±0.7, zero on the lattice.
fn gradient_noise(key: u64, x: f64, z: f64) -> f64 {
    let (x0, z0) = (x.floor(), z.floor());
    let (fx, fz) = (x - x0, z - z0);
    let (ix, iz) = (x0 as i64, z0 as i64);
    let corner = |dx: i64, dz: i64| {
        let h = finalizer(key ^ finalizer((ix + dx) as u64 ^ finalizer((iz + dz) as u64)));
        let [gx, gz] = GRADIENTS[(h & 7) as usize];
        gx * (fx - dx as f64) + gz * (fz - dz as f64)
    };
    let fade = |t: f64| t * t * t * (t * (t * 6.0 - 15.0) + 10.0);
    let (u, v) = (fade(fx), fade(fz));
    let lower = corner(0, 0) + u * (corner(1, 0) - corner(0, 0));
    let upper = corner(0, 1) + u * (corner(1, 1) - corner(0, 1));
    lower + v * (upper - lower)
}

/// Seeded fBm: `OCTAVES` octaves, frequency ×2 and amplitude ×½ each, scaled so that its values
/// mostly stay within ±1.
struct Fbm {
    keys: [u64; OCTAVES],
    offsets: [[f64; 2]; OCTAVES],
}

impl Fbm {
    fn new(rng: &mut SplitMix64) -> Self {
        let mut keys = [0; OCTAVES];
        let mut offsets = [[0.0; 2]; OCTAVES];
        for o in 0..OCTAVES {
            keys[o] = rng.next_u64();
            // Offsets of up to 256 lattice cells decorrelate the octaves' lattices.
            offsets[o] = [rng.range([0.0, 256.0]), rng.range([0.0, 256.0])];
        }
        Fbm { keys, offsets }
    }

    fn at(&self, x: f64, z: f64) -> f64 {
        let (mut sum, mut amplitude, mut frequency) = (0.0, 1.0, NOISE_FREQUENCY_PER_M);
        for o in 0..OCTAVES {
            let [ox, oz] = self.offsets[o];
            sum += amplitude * gradient_noise(self.keys[o], x * frequency + ox, z * frequency + oz);
            amplitude *= 0.5;
            frequency *= 2.0;
        }
        // One octave stays within about ±0.7 and the amplitudes sum to 1.875, so the bound is
        // ±2 after this scale; sums of independent octaves rarely pass ±1 (about 3 σ).
        sum * 2.0 / (0.7 * 1.875)
    }
}

/// The terrain: rounded heights on the grid, row-major by z then x.
struct Heightfield {
    heights: Vec<f64>,
}

/// Grid spacing (0.125 m: exact in binary, so grid coordinates are exact).
const CELL_M: f64 = 2.0 * TERRAIN_HALF_SIZE_M / GRID_QUADS as f64;

fn grid_coord(i: usize) -> f64 {
    -TERRAIN_HALF_SIZE_M + CELL_M * i as f64
}

impl Heightfield {
    fn generate(seed: u64) -> Self {
        let mut rng = SplitMix64::new(seed ^ TERRAIN_STREAM);
        let fbm = Fbm::new(&mut rng);
        let n = GRID_QUADS + 1;
        let mut heights = Vec::with_capacity(n * n);
        for j in 0..n {
            for i in 0..n {
                let (x, z) = (grid_coord(i), grid_coord(j));
                let r2 = (x * x + z * z) / (ISLAND_RADIUS_M * ISLAND_RADIUS_M);
                let falloff = (1.0 - r2).max(0.0);
                let noise = NOISE_BASE + NOISE_AMPLITUDE * fbm.at(x, z);
                let h = PEAK_HEIGHT_M * falloff * noise.max(0.0) - SEA_FLOOR_DEPTH_M;
                heights.push(rounded(h, HEIGHT_DECIMALS));
            }
        }
        Heightfield { heights }
    }

    fn h(&self, i: usize, j: usize) -> f64 {
        self.heights[j * (GRID_QUADS + 1) + i]
    }

    fn vertex(&self, i: usize, j: usize) -> DVec3 {
        DVec3::new(grid_coord(i), self.h(i, j), grid_coord(j))
    }

    /// The triangle of the mesh above (x, z) (clamped to the grid), as in `obj`.
    fn triangle_at(&self, x: f64, z: f64) -> [DVec3; 3] {
        let cell = |c: f64| ((c + TERRAIN_HALF_SIZE_M) / CELL_M).floor().clamp(0.0, (GRID_QUADS - 1) as f64);
        let (i, j) = (cell(x) as usize, cell(z) as usize);
        let (u, v) = ((x - grid_coord(i)) / CELL_M, (z - grid_coord(j)) / CELL_M);
        let (a, b, c, d) =
            (self.vertex(i, j), self.vertex(i + 1, j), self.vertex(i + 1, j + 1), self.vertex(i, j + 1));
        if v >= u { [a, d, c] } else { [a, c, b] }
    }

    /// Height of the mesh's surface at (x, z).
    fn height_at(&self, x: f64, z: f64) -> f64 {
        let [a, b, c] = self.triangle_at(x, z);
        let n = (b - a).cross(c - a);
        // The plane through a with normal n, solved for y.
        a.y - (n.x * (x - a.x) + n.z * (z - a.z)) / n.y
    }

    /// Unit upward normal of the mesh's surface at (x, z).
    fn normal_at(&self, x: f64, z: f64) -> DVec3 {
        let [a, b, c] = self.triangle_at(x, z);
        (b - a).cross(c - a).normalize()
    }

    /// Unit normal at grid vertex (i, j) (interior), from central differences.
    fn vertex_normal(&self, i: usize, j: usize) -> DVec3 {
        let dx = (self.h(i + 1, j) - self.h(i - 1, j)) / (2.0 * CELL_M);
        let dz = (self.h(i, j + 1) - self.h(i, j - 1)) / (2.0 * CELL_M);
        DVec3::new(-dx, 1.0, -dz).normalize()
    }

    /// The OBJ text: vertices row by row, two counter-clockwise triangles per quad.
    fn obj(&self, seed: u64) -> String {
        let n = GRID_QUADS + 1;
        let mut out = String::with_capacity(600_000);
        out.push_str("# island terrain (Ehm et al. 2015, Figure 12 analogue)\n");
        let _ = writeln!(out, "# generated by `shadowtruth island --seed {seed}`; do not edit");
        let _ = writeln!(out, "# {} vertices, {} triangles", n * n, 2 * GRID_QUADS * GRID_QUADS);
        for j in 0..n {
            for i in 0..n {
                let (x, y, z) = (grid_coord(i), self.h(i, j), grid_coord(j));
                let _ = writeln!(out, "v {} {} {}", short(x, 5), fixed(y, HEIGHT_DECIMALS), short(z, 5));
            }
        }
        for j in 0..GRID_QUADS {
            for i in 0..GRID_QUADS {
                // OBJ indices are 1-based; a = (i, j), b = (i+1, j), c = (i+1, j+1), d = (i, j+1).
                let a = j * n + i + 1;
                let (b, c, d) = (a + 1, a + n + 1, a + n);
                // Counter-clockwise seen from above (+y): (a, d, c) and (a, c, b).
                let _ = writeln!(out, "f {a} {d} {c}\nf {a} {c} {b}");
            }
        }
        out
    }
}

/// The spot light's placement.
struct Spot {
    position: DVec3,
    target: DVec3,
}

impl Spot {
    fn new() -> Self {
        Spot { position: DVec3::from(LIGHT_POSITION), target: DVec3::from(LIGHT_TARGET) }
    }

    /// Horizontal unit vector from `p` towards the light.
    fn towards(&self, p: DVec3) -> DVec3 {
        DVec3::new(self.position.x - p.x, 0.0, self.position.z - p.z).normalize()
    }
}

/// Where the featured tree stands: the ground point (x, ground y, z).
fn featured_site(terrain: &Heightfield, light: &Spot) -> DVec3 {
    let mut best: Option<(f64, DVec3)> = None;
    for j in 1..GRID_QUADS {
        for i in 1..GRID_QUADS {
            let p = terrain.vertex(i, j);
            let n = terrain.vertex_normal(i, j);
            // The light's side of the island: nearer the light than the island's centre is.
            let on_lit_side = (p - light.position).length() < light.position.length();
            if !on_lit_side
                || p.y < FEATURED_MIN_HEIGHT_M
                || n.y < FEATURED_SLOPE_MIN
                || n.y > FEATURED_SLOPE_MAX
            {
                continue;
            }
            let n_dot_l = n.dot((light.position - p).normalize());
            // Strictly greater: the first of equals wins, in grid order.
            if best.is_none_or(|(b, _)| n_dot_l > b) {
                best = Some((n_dot_l, p));
            }
        }
    }
    // Every seed's island has such a slope; the centre is a fallback that keeps the scene valid.
    best.map_or(DVec3::new(0.0, terrain.height_at(0.0, 0.0), 0.0), |(_, p)| p)
}

struct CameraSpec {
    name: &'static str,
    position: DVec3,
    look_at: DVec3,
    fov_y_deg: f64,
}

fn front_camera(terrain: &Heightfield, light: &Spot, tree: DVec3) -> CameraSpec {
    let towards = light.towards(tree);
    let side = DVec3::new(-towards.z, 0.0, towards.x);
    let offset = (towards * FRONT_CAMERA_TOWARDS_LIGHT + side * FRONT_CAMERA_SIDE) * FRONT_CAMERA_DISTANCE_M;
    let mut position = tree + offset + DVec3::Y * FRONT_CAMERA_HEIGHT_M;
    // Never below the ground it stands over.
    position.y = position.y.max(terrain.height_at(position.x, position.z) + FRONT_CAMERA_HEIGHT_M);
    let look_at = tree - towards * FRONT_LOOK_ALONG_SHADOW_M + DVec3::Y * FRONT_LOOK_HEIGHT_M;
    CameraSpec {
        name: "front",
        position: round3(position),
        look_at: round3(look_at),
        fov_y_deg: FRONT_FOV_DEG,
    }
}

fn back_camera(light: &Spot) -> CameraSpec {
    let away = -light.towards(light.target);
    let side = DVec3::new(-away.z, 0.0, away.x);
    let position = light.target
        + away * BACK_CAMERA_AWAY_M
        + side * BACK_CAMERA_SIDE_M
        + DVec3::Y * BACK_CAMERA_HEIGHT_M;
    let look_at = DVec3::new(light.target.x, BACK_LOOK_HEIGHT_M, light.target.z) + away * BACK_LOOK_AWAY_M;
    CameraSpec { name: "back", position: round3(position), look_at: round3(look_at), fov_y_deg: BACK_FOV_DEG }
}

enum Crown {
    Cone { radius: f64, height: f64 },
    Sphere { radius: f64 },
}

struct Tree {
    /// Where the trunk's axis meets the ground.
    ground: DVec3,
    trunk_radius: f64,
    trunk_height: f64,
    /// y of the trunk's bottom (under the ground).
    trunk_base_y: f64,
    crown: Crown,
}

/// The 8 directions in which the ground under a trunk's rim is sampled.
const RIM_DIRECTIONS: [[f64; 2]; 8] = GRADIENTS;

fn make_tree(
    terrain: &Heightfield,
    x: f64,
    z: f64,
    trunk_radius: f64,
    trunk_height: f64,
    crown: Crown,
) -> Tree {
    let ground = DVec3::new(x, terrain.height_at(x, z), z);
    let rim_low = RIM_DIRECTIONS
        .iter()
        .map(|[dx, dz]| terrain.height_at(x + dx * trunk_radius, z + dz * trunk_radius))
        .fold(ground.y, f64::min);
    Tree { ground, trunk_radius, trunk_height, trunk_base_y: rounded(rim_low - TRUNK_SINK_M, 4), crown }
}

/// Distance from `p` to the segment [a, b], in the xz plane.
fn distance_to_segment_xz(p: DVec3, a: DVec3, b: DVec3) -> f64 {
    let flat = |v: DVec3| DVec3::new(v.x, 0.0, v.z);
    let (p, a, b) = (flat(p), flat(a), flat(b));
    let ab = b - a;
    let t = ((p - a).dot(ab) / ab.length_squared().max(1e-12)).clamp(0.0, 1.0);
    (p - (a + ab * t)).length()
}

fn place_trees(seed: u64, terrain: &Heightfield, featured: DVec3, camera: DVec3) -> Vec<Tree> {
    let featured_crown = Crown::Cone { radius: FEATURED_CONE_RADIUS_M, height: FEATURED_CONE_HEIGHT_M };
    let mut trees = vec![make_tree(
        terrain,
        featured.x,
        featured.z,
        FEATURED_TRUNK_RADIUS_M,
        FEATURED_TRUNK_HEIGHT_M,
        featured_crown,
    )];
    let mut rng = SplitMix64::new(seed ^ TREE_STREAM);
    for _ in 0..TREE_ATTEMPTS {
        if trees.len() == TREE_COUNT {
            break;
        }
        // Uniform in the island's disk by rejection from its square (no trigonometry).
        let (x, z) = (rng.range([-1.0, 1.0]), rng.range([-1.0, 1.0]));
        // Every candidate draws the same numbers, accepted or not, so streams stay aligned.
        let trunk_radius = rounded(rng.range(TRUNK_RADIUS_M), 3);
        let trunk_height = rounded(rng.range(TRUNK_HEIGHT_M), 2);
        let sphere = rng.next_f64() < SPHERE_CROWN_PROBABILITY;
        let (crown_a, crown_b) = (rng.next_f64(), rng.next_f64());
        if x * x + z * z > 1.0 {
            continue;
        }
        let (x, z) = (rounded(x * ISLAND_RADIUS_M, 3), rounded(z * ISLAND_RADIUS_M, 3));
        let p = DVec3::new(x, terrain.height_at(x, z), z);
        let crowded = trees.iter().any(|t| {
            let d = DVec3::new(t.ground.x - x, 0.0, t.ground.z - z);
            d.length() < TREE_SPACING_M
        });
        if p.y < TREE_MIN_HEIGHT_M
            || terrain.normal_at(x, z).y < TREE_MIN_NORMAL_Y
            || crowded
            || distance_to_segment_xz(p, camera, featured) < VIEW_CORRIDOR_M
        {
            continue;
        }
        let lerp = |[lo, hi]: [f64; 2], t: f64| rounded(lo + (hi - lo) * t, 3);
        let crown = if sphere {
            Crown::Sphere { radius: lerp(SPHERE_RADIUS_M, crown_a) }
        } else {
            Crown::Cone { radius: lerp(CONE_RADIUS_M, crown_a), height: lerp(CONE_HEIGHT_M, crown_b) }
        };
        trees.push(make_tree(terrain, x, z, trunk_radius, trunk_height, crown));
    }
    trees
}

/// Decimals of the scene file's positions and sizes (0.1 mm).
const POSITION_DECIMALS: usize = 4;
/// Decimals of its angles and depth range.
const ANGLE_DECIMALS: usize = 2;

fn scene_json(light: &Spot, cameras: &[CameraSpec], trees: &[Tree]) -> String {
    let mut objects = vec![
        SceneFileObject {
            name: "terrain".into(),
            geometry: Geometry::Mesh(ISLAND_TERRAIN_FILE.into()),
            closed: false,
            placement: ObjectPlacement::Single(Transform::default()),
        },
        SceneFileObject {
            name: "sea".into(),
            geometry: Geometry::Shape(Shape::Plane { size: [rounded(SEA_SIZE_M, 1); 2], subdivisions: 1 }),
            closed: false,
            placement: ObjectPlacement::Single(Transform::default()),
        },
    ];
    for (k, tree) in trees.iter().enumerate() {
        objects.extend(tree_objects(k, tree));
    }
    let file = SceneFile {
        name: "island".into(),
        objects,
        cameras: cameras.iter().map(camera).collect(),
        lights: vec![sun_spot(light)],
    };
    file.to_json().expect("the island has no paths and no instanced objects")
}

/// An object placed at `at` (rounded to the file's precision), closed.
fn placed_solid(name: String, shape: Shape, at: DVec3) -> SceneFileObject {
    SceneFileObject {
        name,
        geometry: Geometry::Shape(shape),
        closed: true,
        placement: ObjectPlacement::Single(Transform {
            translate: rounded_vec3(at, POSITION_DECIMALS),
            ..Transform::default()
        }),
    }
}

/// Tree `k`'s trunk and crown objects.
fn tree_objects(k: usize, t: &Tree) -> [SceneFileObject; 2] {
    let size = |x: f64| rounded(x, POSITION_DECIMALS);
    let trunk = Shape::Cylinder {
        radius: size(t.trunk_radius),
        height: size(t.ground.y - t.trunk_base_y + t.trunk_height),
        segments: TRUNK_SEGMENTS,
    };
    let base = DVec3::new(t.ground.x, t.trunk_base_y, t.ground.z);
    let crown_y = t.ground.y + CROWN_START * t.trunk_height;
    let (crown, centre_y) = match t.crown {
        Crown::Cone { radius, height } => {
            (Shape::Cone { radius: size(radius), height: size(height), segments: CROWN_SEGMENTS }, crown_y)
        }
        // The sphere's lower part wraps the trunk's top.
        Crown::Sphere { radius } => (
            Shape::Sphere { radius: size(radius), segments: CROWN_SEGMENTS, rings: SPHERE_RINGS },
            crown_y + 0.7 * radius,
        ),
    };
    [
        placed_solid(format!("tree{k:02}_trunk"), trunk, base),
        placed_solid(format!("tree{k:02}_crown"), crown, DVec3::new(t.ground.x, centre_y, t.ground.z)),
    ]
}

fn camera(c: &CameraSpec) -> Camera {
    Camera {
        name: c.name.into(),
        position: rounded_vec3(c.position, POSITION_DECIMALS),
        look_at: rounded_vec3(c.look_at, POSITION_DECIMALS),
        up: Vec3::Y,
        fov_y_deg: rounded_f32(c.fov_y_deg, ANGLE_DECIMALS),
        width: IMAGE_WIDTH,
        height: IMAGE_HEIGHT,
        path: None,
    }
}

/// The spot light; its axis is written unnormalised, from the light to its target (the reader
/// normalises it).
fn sun_spot(light: &Spot) -> Light {
    let kind = LightKind::Spot {
        position: rounded_vec3(light.position, POSITION_DECIMALS),
        direction: rounded_vec3(light.target - light.position, POSITION_DECIMALS),
        cone_deg: rounded_f32(LIGHT_CONE_DEG, ANGLE_DECIMALS),
        near: rounded_f32(LIGHT_NEAR_M, ANGLE_DECIMALS),
        far: rounded_f32(LIGHT_FAR_M, ANGLE_DECIMALS),
        radius: Some(rounded_f32(LIGHT_RADIUS_M, 3)),
    };
    Light { name: "sun_spot".into(), kind, path: None, cascades: None }
}

fn round3(v: DVec3) -> DVec3 {
    DVec3::new(rounded(v.x, 3), rounded(v.y, 3), rounded(v.z, 3))
}

/// `x` with exactly `decimals` decimals, never "-0.0…".
fn fixed(x: f64, decimals: usize) -> String {
    let s = format!("{x:.decimals$}");
    match s.strip_prefix('-') {
        Some(rest) if rest.bytes().all(|b| b == b'0' || b == b'.') => rest.to_string(),
        _ => s,
    }
}

/// `x` rounded to `decimals` decimals, without trailing zeros.
fn short(x: f64, decimals: usize) -> String {
    let s = fixed(x, decimals);
    if s.contains('.') { s.trim_end_matches('0').trim_end_matches('.').to_string() } else { s }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn papers_island_number_text_reads_back() {
        assert_eq!(fixed(-0.000001, 5), "0.00000");
        assert_eq!(short(2.5000, 4), "2.5");
        assert_eq!(short(-3.0, 4), "-3");
    }

    #[test]
    fn papers_island_height_at_matches_grid_vertices() {
        let t = Heightfield::generate(ISLAND_SEED);
        for (i, j) in [(10, 20), (48, 48), (95, 1)] {
            let v = t.vertex(i, j);
            assert!((t.height_at(v.x, v.z) - v.y).abs() < 1e-12);
        }
    }
}
