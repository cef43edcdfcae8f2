//! The G-buffer of one (camera, light): per pixel the primary hit of the pixel-centre ray and its
//! class. The reference and every technique evaluate exactly these surface points.

use super::pixel_buffer::zeroed_pixels;
use crate::scene::{Camera, Film, Light, LightKind, PixelFootprint, Scene};
use crate::trace::bvh::hit::Hit;
use crate::trace::bvh::in_packet_isa_where_available;
use crate::trace::bvh::primary_certificate::PrimaryCertainty;
use crate::trace::bvh::scene_bvh::SceneBvh;
use crate::trace::bvh::shadow_ray::SurfacePoint;
use crate::trace::bvh::watertight::barycentric_point;
use crate::trace::reference::facing::{LightPlace, Plane};
use glam::{DVec3, Vec3};
use rayon::prelude::*;
use std::cmp::Ordering;

/// What a pixel shows, as far as shadows are concerned.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
#[repr(u8)]
pub enum PixelClass {
    /// The pixel-centre ray hits nothing.
    Background,
    /// The surface, with its normal turned towards the camera, has N·L ≤ 0 (decided exactly,
    /// `facing.rs`): in attached shadow.
    FacingAway,
    /// Outside the spot light's cone or depth range, or beyond a point light's range.
    OutsideLight,
    /// Scored: lit or shadowed by occluders only.
    Evaluated,
    /// The reference cannot decide beyond doubt which surface the pixel sees (whether its ray
    /// hits anything, and what first), or, for a pixel otherwise evaluated, whether its point
    /// is lit (docs/reference.md, "The reference's uncertainty"): left out of every score, and
    /// counted.
    Uncertain,
}

// SAFETY: `PixelClass` is `repr(u8)` and zero is `Background`.
unsafe impl bytemuck::Zeroable for PixelClass {}
const _: () = assert!(PixelClass::Background as u8 == 0);

/// Per-pixel surface data in row-major order (row 0 at the top).
#[derive(Clone)]
pub struct GBuffer {
    pub width: u32,
    pub height: u32,
    pub class: Vec<PixelClass>,
    /// Surface point, from the hit triangle's vertices and barycentrics. Its rounding-error
    /// bound is a function of it and the triangle, computed where a shadow ray needs it rather
    /// than stored (at 4096² that is 192 MiB).
    pub position: Vec<Vec3>,
    /// The hit's barycentrics (b1, b2) on its triangle's f32 vertices: the surface point the
    /// reference is about is exactly v0 + b1·(v1 − v0) + b2·(v2 − v0), on the triangle's plane;
    /// `position` is its rounding to f32.
    pub barycentric: Vec<[f32; 2]>,
    /// Unit geometric normal, turned towards the camera.
    pub normal: Vec<Vec3>,
    /// Scene triangle id (u32::MAX for background).
    pub triangle: Vec<u32>,
    /// Indices of the evaluated pixels, ascending: the loop every technique runs over.
    pub evaluated: Vec<u32>,
    /// The camera's pixel footprint, for the techniques that filter over it.
    pub footprint: PixelFootprint,
}

impl GBuffer {
    pub fn pixel_count(&self) -> usize {
        self.class.len()
    }

    pub fn count(&self, class: PixelClass) -> usize {
        self.class.iter().filter(|&&c| c == class).count()
    }

    /// The surface point of pixel `i` of a G-buffer traced in `scene`, as the shadow test takes
    /// it: the same error bound as the primary hit computed.
    pub fn surface_point(&self, scene: &Scene, i: usize) -> SurfacePoint {
        let (position, triangle) = (self.position[i], self.triangle[i]);
        let vertices = scene.triangle(triangle);
        SurfacePoint {
            position,
            normal: self.normal[i],
            triangle,
            barycentric: self.barycentric[i],
            vertices,
        }
    }

    /// The object pixel `i` shows in `scene` (`u32::MAX` for none): its triangle's, looked up
    /// rather than stored (64 MiB at 4096²).
    pub fn object(&self, scene: &Scene, i: usize) -> u32 {
        match self.triangle[i] {
            u32::MAX => u32::MAX,
            triangle => scene.object_of(triangle),
        }
    }

    /// Gives back the barycentrics' memory (8 bytes a pixel, 128 MiB at 4096²) once every ray
    /// from the surface points has been traced: shading and scoring read the positions. After
    /// this, [`GBuffer::surface_point`] panics.
    pub fn release_barycentrics(&mut self) {
        self.barycentric = Vec::new();
    }

    /// Leaves `pixels` (evaluated ones, ascending) out of every score: their class becomes
    /// `Uncertain` (the reference could not decide them beyond doubt).
    pub fn leave_out(&mut self, pixels: &[u32]) {
        if pixels.is_empty() {
            return;
        }
        for &i in pixels {
            self.class[i as usize] = PixelClass::Uncertain;
        }
        let class = &self.class;
        self.evaluated.retain(|&i| class[i as usize] == PixelClass::Evaluated);
    }
}

/// A light as per-point questions need it, its constants (a normalized direction, a cone's
/// cosine) computed once rather than at every pixel.
#[derive(Clone, Copy, Debug)]
pub(in crate::trace) enum LightSight {
    Directional { towards: DVec3 },
    Spot { position: DVec3, axis: DVec3, cos_half: f64, near: f64, far: f64 },
    Point { position: DVec3, range: f64 },
}

impl LightSight {
    pub(in crate::trace) fn of(light: &Light) -> Self {
        match &light.kind {
            // The definition's D: the f32 direction (normalized on load) reversed, exactly.
            LightKind::Directional { direction, .. } => {
                LightSight::Directional { towards: (-*direction).as_dvec3() }
            }
            LightKind::Spot { position, direction, cone_deg, near, far, .. } => LightSight::Spot {
                position: position.as_dvec3(),
                axis: direction.as_dvec3().normalize(),
                cos_half: (0.5 * (*cone_deg as f64).to_radians()).cos(),
                near: *near as f64,
                far: *far as f64,
            },
            LightKind::Point { position, far, .. } => {
                LightSight::Point { position: position.as_dvec3(), range: *far as f64 }
            }
        }
    }

    /// The light's f32 position or direction towards it, for the exact facing test (the f64
    /// values here are those f32 ones, converted exactly).
    #[inline(always)]
    pub(in crate::trace) fn place(&self) -> LightPlace {
        match *self {
            LightSight::Directional { towards } => LightPlace::Towards(towards.as_vec3()),
            LightSight::Spot { position, .. } | LightSight::Point { position, .. } => {
                LightPlace::Point(position.as_vec3())
            }
        }
    }

    /// Whether the light reaches `p`: a spot light strictly inside its cone, within [near, far]
    /// along its axis; a point light within its range (its near plane is its maps' alone).
    #[inline(always)]
    pub(in crate::trace) fn reaches(&self, p: DVec3) -> bool {
        match *self {
            LightSight::Directional { .. } => true,
            LightSight::Spot { position, axis, cos_half, near, far } => {
                let offset = p - position;
                let along = offset.dot(axis);
                offset.normalize().dot(axis) > cos_half && along >= near && along <= far
            }
            LightSight::Point { position, range } => (p - position).length_squared() <= range * range,
        }
    }
}

/// The surface seen along one primary ray, classified for a light.
pub(in crate::trace) struct SurfaceSample {
    pub class: PixelClass,
    /// From the hit triangle's vertices and barycentrics (not origin + t·dir), with its
    /// error bound; the normal is the geometric one, turned towards the ray's origin.
    pub point: SurfacePoint,
}

/// The surface point of a primary ray's closest hit, and its class. Shared by the G-buffer
/// (pixel-centre rays) and the pixel-coverage reference (sub-pixel rays).
#[inline(always)]
pub(in crate::trace) fn surface_sample(hit: &Hit, dir: Vec3, light: &LightSight) -> SurfaceSample {
    let verts = &hit.vertices;
    let p = barycentric_point(verts, hit.barycentric);
    let plane = Plane::new(verts);
    let camera = plane.camera_side(dir);
    let mut ng = plane.normal().normalize();
    if camera == Ordering::Less {
        ng = -ng;
    }
    let p32 = p.as_vec3();
    let class = if !plane.faces_light(camera, light.place()) {
        PixelClass::FacingAway
    } else if !light.reaches(p32.as_dvec3()) {
        PixelClass::OutsideLight
    } else {
        PixelClass::Evaluated
    };
    let point = SurfacePoint {
        position: p32,
        normal: ng.as_vec3(),
        triangle: hit.triangle,
        barycentric: [hit.barycentric[1], hit.barycentric[2]],
        vertices: *verts,
    };
    SurfaceSample { class, point }
}

impl GBuffer {
    /// Traces the pixel-centre ray of every pixel of `camera` and classifies it for `light`.
    pub fn trace(bvh: &SceneBvh, camera: &Camera, light: &Light) -> GBuffer {
        let (w, h) = (camera.width, camera.height);
        let n = camera.pixel_count();
        let film = camera.film();
        let columns = film.columns();
        let sight = LightSight::of(light);
        // Zeroed memory: a background pixel's values but its triangle, which the tiles write.
        let mut class: Vec<PixelClass> = zeroed_pixels(n);
        let mut position: Vec<Vec3> = zeroed_pixels(n);
        let mut barycentric: Vec<[f32; 2]> = zeroed_pixels(n);
        let mut normal: Vec<Vec3> = zeroed_pixels(n);
        let mut triangle: Vec<u32> = zeroed_pixels(n);
        let band = w as usize * TILE;
        class
            .par_chunks_mut(band)
            .zip(position.par_chunks_mut(band))
            .zip(barycentric.par_chunks_mut(band))
            .zip(normal.par_chunks_mut(band))
            .zip(triangle.par_chunks_mut(band))
            .enumerate()
            .for_each_init(
                || (bvh.scratch(), vec![Vec3::ZERO; band], TileRays::new()),
                |(scratch, dirs, tile), (b, ((((cls, pos), bary), nrm), tri))| {
                    // The last band may have fewer rows.
                    let dirs = &mut dirs[..cls.len()];
                    band_directions(&film, &columns, b, dirs);
                    for_each_tile(w as usize, cls.len() / w as usize, |pixels| {
                        let (tile_dirs, hits, certainties) = tile.gather(dirs, pixels);
                        bvh.certified_closest_hits(scratch, camera.position, tile_dirs, hits, certainties);
                        let out = TileOut { cls, pos, bary, nrm, tri };
                        let walked = TileHits { pixels, directions: tile_dirs, hits, certainties };
                        in_packet_isa_where_available(
                            #[inline(always)]
                            || shade_tile(walked, &sight, out),
                        );
                    });
                },
            );
        // Counted first: grown by doubling, the list would hold up to twice the room it needs.
        let is_evaluated = |&i: &u32| class[i as usize] == PixelClass::Evaluated;
        let mut evaluated = Vec::with_capacity((0..n as u32).filter(is_evaluated).count());
        evaluated.extend((0..n as u32).filter(is_evaluated));
        let footprint = PixelFootprint::of(camera);
        GBuffer { width: w, height: h, class, position, barycentric, normal, triangle, evaluated, footprint }
    }
}

/// A tile's walked rays: each pixel's index in the band, direction, certified hit and its
/// certainty.
#[derive(Clone, Copy)]
struct TileHits<'a> {
    pixels: &'a [usize],
    directions: &'a [Vec3],
    hits: &'a [Option<Hit>],
    certainties: &'a [PrimaryCertainty],
}

/// A band's G-buffer arrays, which a tile's pixels are written to.
struct TileOut<'a> {
    cls: &'a mut [PixelClass],
    pos: &'a mut [Vec3],
    bary: &'a mut [[f32; 2]],
    nrm: &'a mut [Vec3],
    tri: &'a mut [u32],
}

/// Each pixel of a tile from its certified hit (`surface_sample`): its class, surface point,
/// barycentrics, normal and triangle, and `u32::MAX` for a pixel whose ray hits nothing.
/// Run compiled for the packets' instruction set (`in_packet_isa_where_available`), everything
/// it calls inlined: 1.02–1.06× the G-buffer's rate on the forest (docs/scale.md).
#[inline(always)]
fn shade_tile(walked: TileHits, sight: &LightSight, out: TileOut) {
    let TileHits { pixels, directions, hits, certainties } = walked;
    let TileOut { cls, pos, bary, nrm, tri } = out;
    for (k, &j) in pixels.iter().enumerate() {
        let uncertain = certainties[k] == PrimaryCertainty::Uncertain;
        let Some(hit) = &hits[k] else {
            tri[j] = u32::MAX;
            if uncertain {
                cls[j] = PixelClass::Uncertain;
            }
            continue;
        };
        let sample = surface_sample(hit, directions[k], sight);
        let p = sample.point;
        cls[j] = if uncertain { PixelClass::Uncertain } else { sample.class };
        pos[j] = p.position;
        bary[j] = p.barycentric;
        nrm[j] = p.normal;
        tri[j] = p.triangle;
    }
}

/// Primary rays are walked in tiles of `TILE` × `TILE` pixels, row by row within a tile, bands of
/// `TILE` rows at a time: sixteen rays whose directions are close in both axes walk as one packet
/// where the processor has AVX-512, as two packets of 4×2 otherwise. On the 200K forest at
/// 1920×1080 (one thread), primary rays ran 1.24× as fast in packets of 4×4 as in rows of eight
/// with AVX-512 (rows of sixteen were no faster than rows of eight), and 1.14× as fast in
/// packets of 4×2 with AVX2; the G-buffer 1.17× and 1.08× (docs/scale.md).
const TILE: usize = 4;

/// Calls `f(pixels)` for each tile of a band of `rows` rows (at most `TILE`) of `width` pixels,
/// from the left, with its pixels' indices in the band, row by row within the tile.
fn for_each_tile(width: usize, rows: usize, mut f: impl FnMut(&[usize])) {
    let mut pixels = [0; TILE * TILE];
    for x0 in (0..width).step_by(TILE) {
        let mut n = 0;
        for y in 0..rows {
            for x in x0..(x0 + TILE).min(width) {
                pixels[n] = y * width + x;
                n += 1;
            }
        }
        f(&pixels[..n]);
    }
}

/// A tile's rays and what the walk writes for them, reused from tile to tile.
struct TileRays {
    directions: [Vec3; TILE * TILE],
    hits: [Option<Hit>; TILE * TILE],
    certainties: [PrimaryCertainty; TILE * TILE],
}

impl TileRays {
    fn new() -> Self {
        TileRays {
            directions: [Vec3::ZERO; TILE * TILE],
            hits: [None; TILE * TILE],
            certainties: [PrimaryCertainty::Certain; TILE * TILE],
        }
    }

    /// The directions of the band's `pixels` (from `band_directions`), and room for their hits
    /// and certainties.
    fn gather(
        &mut self,
        band_directions: &[Vec3],
        pixels: &[usize],
    ) -> (&[Vec3], &mut [Option<Hit>], &mut [PrimaryCertainty]) {
        let n = pixels.len();
        for (direction, &j) in self.directions.iter_mut().zip(pixels) {
            *direction = band_directions[j];
        }
        (&self.directions[..n], &mut self.hits[..n], &mut self.certainties[..n])
    }
}

/// The pixel-centre directions of band `b` (rows from `b`·`TILE`), row by row, into `directions`
/// (a row per `columns.len()` entries; the last band may have fewer rows).
fn band_directions(film: &Film, columns: &[f64], b: usize, directions: &mut [Vec3]) {
    for (r, row) in directions.chunks_mut(columns.len()).enumerate() {
        row_directions(film, columns, b * TILE + r, row);
    }
}

/// The pixel-centre ray directions of `camera`, row by row: the G-buffer's rays.
pub fn primary_directions(camera: &Camera) -> Vec<Vec3> {
    let (film, w) = (camera.film(), camera.width as usize);
    let columns = film.columns();
    let mut directions: Vec<Vec3> = zeroed_pixels(camera.pixel_count());
    directions.par_chunks_mut(w).enumerate().for_each(|(y, dirs)| row_directions(&film, &columns, y, dirs));
    directions
}

/// The pixel-centre directions of row `y`.
fn row_directions(film: &Film, columns: &[f64], y: usize, directions: &mut [Vec3]) {
    let row = film.row(y as u32);
    for (x, dir) in directions.iter_mut().enumerate() {
        *dir = row.direction(columns, x as u32);
    }
}

/// A primary ray's closest hit as `primary_hits` writes it: what a tracer's hit record holds
/// (the Embree tool's too), without the vertices `Hit` carries for the G-buffer.
#[derive(Clone, Copy, Debug, PartialEq, bytemuck::Zeroable)]
pub struct PrimaryHit {
    /// Scene triangle id, u32::MAX where the ray hits nothing.
    pub triangle: u32,
    pub t: f32,
    pub barycentric: [f32; 3],
}

impl PrimaryHit {
    const MISS: PrimaryHit = PrimaryHit { triangle: u32::MAX, t: f32::INFINITY, barycentric: [0.0; 3] };
}

/// The closest hits of rays from the camera along `directions` (`primary_directions`), walked
/// tile by tile as the G-buffer walks them (`TILE`), without the surface work the G-buffer adds:
/// the tracer's own share of primary rays, which `reference --timing` times.
pub fn primary_hits(bvh: &SceneBvh, camera: &Camera, directions: &[Vec3]) -> Vec<PrimaryHit> {
    // Every record is written by its tile, so the directions must be the camera's pixels.
    assert_eq!(directions.len(), camera.pixel_count(), "one direction per pixel of the camera");
    let w = camera.width as usize;
    // Zeroed memory, which the tiles write, as the G-buffer's.
    let mut records: Vec<PrimaryHit> = zeroed_pixels(directions.len());
    records.par_chunks_mut(w * TILE).zip(directions.par_chunks(w * TILE)).for_each_init(
        || (bvh.scratch(), TileRays::new()),
        |(scratch, tile), (records, dirs)| {
            for_each_tile(w, dirs.len() / w, |pixels| {
                let (tile_dirs, hits, _) = tile.gather(dirs, pixels);
                bvh.closest_hits(scratch, camera.position, tile_dirs, hits);
                for (&j, hit) in pixels.iter().zip(hits.iter()) {
                    records[j] = match hit {
                        Some(h) => PrimaryHit { triangle: h.triangle, t: h.t, barycentric: h.barycentric },
                        None => PrimaryHit::MISS,
                    };
                }
            });
        },
    );
    records
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::scene::load_scene;
    use crate::trace::bvh::primary_certificate::refine_barycentrics;
    use crate::trace::bvh::watertight::WatertightRay;
    use std::path::Path;

    /// The rays `reference --timing` times as primary rays are the G-buffer's, with the same
    /// hits: the same triangle per pixel as a single ray's walk, and the same surface point from
    /// its barycentrics once they are computed again in f64 (`refine_barycentrics`), as the
    /// G-buffer does. Also at a size that is no multiple of the tiles' in either axis, so that
    /// partial tiles and a short last band write every pixel too.
    #[test]
    fn primary_hits_are_the_gbuffer_hits() {
        for (name, size) in [("rocks", None), ("spot", None), ("rocks", Some((157, 91)))] {
            let path = Path::new(env!("CARGO_MANIFEST_DIR")).join(format!("../../scenes/{name}.json"));
            let scene = load_scene(&path).expect("bundled scene");
            let (mut camera, light) = (scene.cameras[0].clone(), &scene.lights[0]);
            if let Some((width, height)) = size {
                (camera.width, camera.height) = (width, height);
            }
            let camera = &camera;
            let bvh = SceneBvh::build(&scene);
            let mut scratch = bvh.scratch();
            let g = GBuffer::trace(&bvh, camera, light);
            let directions = primary_directions(camera);
            let records = primary_hits(&bvh, camera, &directions);
            assert_eq!(records.len(), g.pixel_count());
            let mut hits = 0;
            for (i, r) in records.iter().enumerate() {
                assert_eq!(r.triangle, g.triangle[i], "{name}: pixel {i}");
                let single =
                    bvh.closest_hit(&mut scratch, camera.position, directions[i], 0.0, f32::INFINITY);
                assert_eq!(r.triangle, single.map_or(u32::MAX, |h| h.triangle), "{name}: pixel {i}");
                if r.triangle != u32::MAX {
                    let vertices = scene.triangle(r.triangle);
                    let mut hit = Hit { triangle: r.triangle, t: r.t, barycentric: r.barycentric, vertices };
                    let walk = WatertightRay::new(camera.position.into(), directions[i].into());
                    refine_barycentrics(&walk, &mut hit);
                    let p = barycentric_point(&vertices, hit.barycentric).as_vec3();
                    assert_eq!(p.to_array().map(f32::to_bits), g.position[i].to_array().map(f32::to_bits));
                    hits += 1;
                }
            }
            assert!(hits > records.len() / 2, "{name}: the view must mostly hit ({hits})");
        }
    }
}
