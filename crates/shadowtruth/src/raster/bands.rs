//! A scene's triangles binned by band of map rows, once per light view: every layer rasterized
//! from the view (any culling, offset or format) reuses the bins.
//!
//! Binning is the one pass that reads every triangle of the scene, so it is kept to a bound per
//! triangle: a placed mesh's vertices are projected once each (not once per corner), and a
//! triangle that covers no texel centre under any setting (most of a dense mesh at map
//! resolution, everything outside the light's frustum) is dropped here, never set up.

use super::clip::outcode;
use super::setup::{RasterTriangle, SUBTEXEL, centres_between, guard_band, setup_triangle, snap};
use super::{LightView, Projection, RasterSettings};
use crate::scene::{Scene, is_degenerate, world_vertex};
use glam::Vec3;
use rayon::prelude::*;
use std::ops::Range;

/// Rows per parallel band (fixed: it never changes the arithmetic, only the scheduling).
pub(super) const BAND_ROWS: u32 = 32;
/// Flat triangles per parallel binning chunk.
const FLAT_CHUNK: u32 = 2048;
/// Triangles of one placed mesh per parallel binning chunk: a chunk projects all the mesh's
/// vertices when it reads at least as many corners, so meshes up to this size are binned whole.
const INSTANCE_CHUNK: u32 = 1 << 18;

/// Scene triangles per band of `BAND_ROWS` rows (CSR: band b owns `triangles[start[b]..start[b + 1]]`),
/// in scene order. A triangle may be listed in a band it turns out not to cover (the bands come
/// from a cheap bound, and culling is left to the bands), never left out of one it covers, so
/// the bins serve every setting.
pub(super) struct Bands {
    start: Vec<usize>,
    triangles: Vec<u32>,
}

impl Bands {
    pub fn new(scene: &Scene, view: &LightView) -> Self {
        let band_count = view.resolution.div_ceil(BAND_ROWS) as usize;
        assert!(band_count < u16::MAX as usize, "a {}² map has too many bands", view.resolution);
        let binned: Vec<Vec<Binned>> = chunks(scene)
            .into_par_iter()
            .map_init(Scratch::default, |scratch, chunk| chunk.bin(scene, view, scratch))
            .collect();
        let mut start = vec![0usize; band_count + 1];
        for &Binned { bands, .. } in binned.iter().flatten() {
            for b in bands.0..bands.1 {
                start[b as usize + 1] += 1;
            }
        }
        for b in 0..band_count {
            start[b + 1] += start[b];
        }
        let mut fill = start.clone();
        let mut triangles = vec![0u32; start[band_count]];
        for &Binned { id, bands } in binned.iter().flatten() {
            for b in bands.0..bands.1 {
                triangles[fill[b as usize]] = id;
                fill[b as usize] += 1;
            }
        }
        Bands { start, triangles }
    }

    /// The ids of the triangles that band `band` may cover, ascending.
    pub fn band(&self, band: usize) -> &[u32] {
        &self.triangles[self.start[band]..self.start[band + 1]]
    }
}

/// A triangle that may cover texel centres, and the bands [lo, hi) it may cover.
#[derive(Clone, Copy)]
struct Binned {
    id: u32,
    bands: (u16, u16),
}

/// A run of triangle ids binned by one parallel task.
enum Chunk {
    Flat(Range<u32>),
    /// Local triangles `locals` of instance `instance`.
    Instance {
        instance: usize,
        locals: Range<u32>,
    },
}

/// The flat triangles in `FLAT_CHUNK`s, then each instance in `INSTANCE_CHUNK`s, in id order.
fn chunks(scene: &Scene) -> Vec<Chunk> {
    let flat = scene.flat_triangles.len() as u32;
    let mut chunks: Vec<Chunk> =
        (0..flat).step_by(FLAT_CHUNK as usize).map(|s| Chunk::Flat(s..flat.min(s + FLAT_CHUNK))).collect();
    for (index, instance) in scene.instances.iter().enumerate() {
        let count = scene.meshes[instance.mesh as usize].triangles.len() as u32;
        chunks.extend(
            (0..count)
                .step_by(INSTANCE_CHUNK as usize)
                .map(|s| Chunk::Instance { instance: index, locals: s..count.min(s + INSTANCE_CHUNK) }),
        );
    }
    chunks
}

/// Per-task buffers, kept across chunks.
#[derive(Default)]
struct Scratch {
    world: Vec<Vec3>,
    vertices: Vec<BinVertex>,
    setup: Vec<RasterTriangle>,
}

impl Chunk {
    /// The triangles of the chunk that may cover texel centres, with their bands.
    fn bin(&self, scene: &Scene, view: &LightView, scratch: &mut Scratch) -> Vec<Binned> {
        let mut binned = Vec::new();
        let mut keep = |id: u32, bands: (u16, u16)| {
            if bands.0 < bands.1 {
                binned.push(Binned { id, bands });
            }
        };
        let guard = guard_band(view.resolution);
        match self {
            Chunk::Flat(ids) => {
                for id in ids.clone() {
                    let tri = scene.flat_triangles[id as usize];
                    let vertices = tri.map(|p| BinVertex::of(view, p, guard));
                    keep(id, band_range(&tri, &vertices, view, &mut scratch.setup));
                }
            }
            &Chunk::Instance { instance: index, ref locals } => {
                let instance = &scene.instances[index];
                let mesh = &scene.meshes[instance.mesh as usize];
                // Each vertex projected once when the chunk reads at least as many corners as the
                // mesh has vertices: the same `world_vertex` and `clip_of` of the same vertex, so
                // the same bits as projecting each corner. (Bands do not depend on the winding,
                // so a mirrored placement's corners are read in the mesh's order.)
                let whole = 3 * locals.len() >= mesh.positions.len();
                if whole {
                    scratch.world.clear();
                    let world_from_local = &instance.world_from_local;
                    scratch.world.extend(mesh.positions.iter().map(|&p| world_vertex(world_from_local, p)));
                    scratch.vertices.clear();
                    scratch.vertices.extend(scratch.world.iter().map(|&p| BinVertex::of(view, p, guard)));
                }
                for local in locals.clone() {
                    let (tri, vertices) = if whole {
                        let corners = mesh.triangles[local as usize];
                        (
                            corners.map(|i| scratch.world[i as usize]),
                            corners.map(|i| scratch.vertices[i as usize]),
                        )
                    } else {
                        let tri = instance.triangle(mesh, local as usize);
                        (tri, tri.map(|p| BinVertex::of(view, p, guard)))
                    };
                    let bands = band_range(&tri, &vertices, view, &mut scratch.setup);
                    // A triangle degenerate in world space is not in the scene
                    // (`Scene::triangles`); tested last, as few triangles get this far.
                    if bands.0 < bands.1 && !is_degenerate(&tri) {
                        keep(instance.first_triangle + local, bands);
                    }
                }
            }
        }
        binned
    }
}

/// A world vertex as the band bound reads it: its clip-space outcode and snapped raster position
/// (the set-up's own divide, viewport and snap), valid when `in_front`. Twelve bytes, as every
/// vertex of a placed mesh is read from here: the snapped position saturates to i32 (the set-up's
/// own is within ±2^29 inside the guard band, and a row bound beyond ±2^31 clamps to the same
/// edge of the map).
#[derive(Clone, Copy, Debug)]
struct BinVertex {
    x: i32,
    y: i32,
    /// Bit i set when outside clip plane i (`clip.rs`).
    outcode: u8,
    /// `FINITE`: the clip coordinates are finite (a vertex that is not makes its triangles
    /// vanish); `IN_FRONT`: w > 0, the divide is defined.
    flags: u8,
}

const FINITE: u8 = 1;
const IN_FRONT: u8 = 2;

impl BinVertex {
    #[inline]
    fn of(view: &LightView, p: Vec3, guard: f32) -> Self {
        let c = view.clip_of(p);
        let in_front = c.w > 0.0;
        let n = view.resolution as f32;
        let saturate = |t: i64| t.clamp(i32::MIN as i64, i32::MAX as i64) as i32;
        let (x, y) = if in_front {
            let x = snap((0.5 * c.x * (1.0 / c.w) + 0.5) * n);
            (saturate(x), saturate(snap((1.0 - (0.5 * c.y * (1.0 / c.w) + 0.5)) * n)))
        } else {
            (0, 0)
        };
        let flags = if c.is_finite() { FINITE } else { 0 } | if in_front { IN_FRONT } else { 0 };
        BinVertex { x, y, outcode: outcode(c, guard), flags }
    }
}

/// The bands [lo, hi) that a triangle with projected vertices `v` may cover under any setting,
/// (0, 0) when none, if the vertices alone say so; None when the triangle needs its set-up (a
/// paraboloid's, or one crossing w = 0).
///
/// A triangle entirely outside one clip plane is clipped away whatever the setting. With every
/// w > 0 the rows come from its snapped vertices, widened by a row each way for the rounding of
/// clipped vertices (clipping only shrinks the triangle), and a triangle inside every plane
/// whose snapped box holds no texel centre is set up from exactly those vertices, so it covers
/// nothing.
#[inline]
fn quick_band_range(v: &[BinVertex; 3], view: &LightView) -> Option<(u16, u16)> {
    if v[0].flags & v[1].flags & v[2].flags & FINITE == 0 {
        return Some((0, 0));
    }
    if view.projection == Projection::Paraboloid {
        return None;
    }
    if v[0].outcode & v[1].outcode & v[2].outcode != 0 {
        return Some((0, 0));
    }
    if v[0].flags & v[1].flags & v[2].flags & IN_FRONT == 0 {
        return None;
    }
    // Three-way minima and maxima written out, as this runs for every triangle of the scene.
    let min3 = |a: i32, b: i32, c: i32| a.min(b).min(c) as i64;
    let max3 = |a: i32, b: i32, c: i32| a.max(b).max(c) as i64;
    let (y_lo, y_hi) = (min3(v[0].y, v[1].y, v[2].y), max3(v[0].y, v[1].y, v[2].y));
    let n = view.resolution;
    if v[0].outcode | v[1].outcode | v[2].outcode == 0 {
        let (x_lo, x_hi) = (min3(v[0].x, v[1].x, v[2].x), max3(v[0].x, v[1].x, v[2].x));
        if centres_between(x_lo, x_hi, n).is_none() || centres_between(y_lo, y_hi, n).is_none() {
            return Some((0, 0));
        }
    }
    let rows = centres_between(y_lo - SUBTEXEL, y_hi + SUBTEXEL, n);
    Some(bands_of_rows(rows.map(|(first, last)| (first as u32, last as u32))))
}

/// The bands [lo, hi) that world triangle `tri` (its projected vertices `v`) may cover under any
/// setting: `quick_band_range`, or else the rows of its full set-up without culling (culling only
/// removes triangles; offsets never move rows).
#[inline]
fn band_range(
    tri: &[Vec3; 3],
    v: &[BinVertex; 3],
    view: &LightView,
    scratch: &mut Vec<RasterTriangle>,
) -> (u16, u16) {
    quick_band_range(v, view).unwrap_or_else(|| {
        scratch.clear();
        setup_triangle(tri, false, view, &RasterSettings::default(), scratch);
        bands_of_rows(scratch.iter().map(|t| t.rows).reduce(|a, b| (a.0.min(b.0), a.1.max(b.1))))
    })
}

/// The bands holding rows [first, last].
fn bands_of_rows(rows: Option<(u32, u32)>) -> (u16, u16) {
    rows.map_or((0, 0), |(first, last)| ((first / BAND_ROWS) as u16, (last / BAND_ROWS + 1) as u16))
}
