//! The ground of a generated scene: a square heightfield of value noise, as an open mesh whose
//! vertices lie on a regular grid (so that casters can be sunk below it exactly).

use glam::DVec3;
use shadowtruth::scene::IndexedMesh;
use shadowtruth::trace::splitmix::{mix64, unit_f64};

/// Octaves of value noise summed; each has half the wavelength and amplitude of the last.
const OCTAVES: u32 = 3;

/// A square heightfield of `cells × cells` quads over [−size/2, size/2]² in x and z.
pub(super) struct Terrain {
    pub cells: u32,
    pub size_m: f64,
    /// Largest height of the first octave (the sum stays below 2× this).
    pub relief_m: f64,
    /// Features per side of the first octave.
    pub features: f64,
    pub seed: u64,
}

impl Terrain {
    /// The grid side whose 2·cells² triangles are closest to `triangles`.
    pub fn cells_for(triangles: u64) -> u32 {
        ((triangles as f64 / 2.0).sqrt().round() as u32).max(1)
    }

    pub fn triangle_count(&self) -> u64 {
        2 * self.cells as u64 * self.cells as u64
    }

    /// x or z of grid line `i`.
    pub fn coordinate(&self, i: u32) -> f64 {
        (i as f64 / self.cells as f64 - 0.5) * self.size_m
    }

    /// The grid line at or below coordinate `x` (clamped to the grid).
    pub fn line_below(&self, x: f64) -> u32 {
        (((x / self.size_m + 0.5) * self.cells as f64).floor().max(0.0) as u32).min(self.cells)
    }

    /// Height of grid vertex (i, j).
    pub fn height(&self, i: u32, j: u32) -> f64 {
        let (x, z) = (self.coordinate(i) / self.size_m + 0.5, self.coordinate(j) / self.size_m + 0.5);
        let mut h = 0.0;
        for octave in 0..OCTAVES {
            let scale = (1u32 << octave) as f64;
            h += value_noise(
                self.seed.wrapping_add(octave as u64),
                x * self.features * scale,
                z * self.features * scale,
            ) / scale;
        }
        h * self.relief_m
    }

    /// The lowest grid vertex of the cells that the rectangle [x0, x1] × [z0, z1] touches: the
    /// piecewise-linear surface over the rectangle is nowhere below it.
    pub fn lowest_under(&self, x0: f64, x1: f64, z0: f64, z1: f64) -> f64 {
        let (i0, i1) = (self.line_below(x0), (self.line_below(x1) + 1).min(self.cells));
        let (j0, j1) = (self.line_below(z0), (self.line_below(z1) + 1).min(self.cells));
        let mut lowest = f64::INFINITY;
        for i in i0..=i1 {
            for j in j0..=j1 {
                lowest = lowest.min(self.height(i, j));
            }
        }
        lowest
    }

    /// The mesh: (cells + 1)² vertices, two triangles per cell, facing +y.
    pub fn mesh(&self) -> IndexedMesh {
        let n = self.cells;
        let mut mesh = IndexedMesh::default();
        mesh.positions.reserve((n as usize + 1).pow(2));
        for j in 0..=n {
            for i in 0..=n {
                mesh.positions.push(DVec3::new(self.coordinate(i), self.height(i, j), self.coordinate(j)));
            }
        }
        mesh.triangles.reserve(2 * n as usize * n as usize);
        let at = |i: u32, j: u32| j * (n + 1) + i;
        for j in 0..n {
            for i in 0..n {
                // Counter-clockwise seen from +y: (x, z) → (x, z + 1) → (x + 1, z).
                let (a, b, c, d) = (at(i, j), at(i + 1, j), at(i + 1, j + 1), at(i, j + 1));
                mesh.triangles.push([a, d, c]);
                mesh.triangles.push([a, c, b]);
            }
        }
        mesh
    }
}

/// Smooth value noise in [−1, 1]: hashed lattice values, smoothstep-interpolated.
fn value_noise(seed: u64, x: f64, z: f64) -> f64 {
    let (xi, zi) = (x.floor(), z.floor());
    let (fx, fz) = (x - xi, z - zi);
    let lattice = |i: f64, j: f64| {
        let key = seed
            ^ (i as i64 as u64).wrapping_mul(0x9E37_79B9)
            ^ (j as i64 as u64).wrapping_mul(0x85EB_CA6B) << 32;
        2.0 * unit_f64(mix64(key)) - 1.0
    };
    let s = |t: f64| t * t * (3.0 - 2.0 * t);
    let (sx, sz) = (s(fx), s(fz));
    let top = lattice(xi, zi) * (1.0 - sx) + lattice(xi + 1.0, zi) * sx;
    let bottom = lattice(xi, zi + 1.0) * (1.0 - sx) + lattice(xi + 1.0, zi + 1.0) * sx;
    top * (1.0 - sz) + bottom * sz
}
