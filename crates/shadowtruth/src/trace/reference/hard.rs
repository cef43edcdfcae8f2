//! The exact hard reference: a pixel is lit when the segment from its surface point to the light
//! meets no triangle other than the ones that contain the point (docs/reference.md). The shadow
//! ray cannot hit its own surface (shadow_ray.rs); no scene-dependent epsilon enters.

use super::gbuffer::{GBuffer, LightSight, PixelClass};
use crate::scene::{Camera, Light, Scene};
use crate::trace::bvh::scene_bvh::{SceneBvh, WIDE_BATCH};
use crate::trace::bvh::scratch::TraversalScratch;
use crate::trace::bvh::shadow_batch::ShadowBatch;
use crate::trace::bvh::shadow_ray::{ShadowRay, SurfacePoint};
use rayon::prelude::*;

/// The grey levels of a reference mask PNG (docs/conventions.md, "Reference mask PNG").
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
#[repr(u8)]
pub enum MaskCode {
    Shadowed = 0,
    FacingAway = 64,
    Uncertain = 96,
    Background = 128,
    OutsideLight = 192,
    Lit = 255,
}

/// Hard visibility of every pixel: 1 lit, 0 shadowed (non-evaluated pixels hold 0).
pub struct HardReference {
    pub width: u32,
    pub height: u32,
    pub lit: Vec<u8>,
    /// Evaluated pixels (ascending) whose answer the tracer could not decide beyond doubt; `lit`
    /// holds its best guess there. `GBuffer::leave_out` takes them out of every score.
    pub uncertain: Vec<u32>,
}

impl HardReference {
    /// The mask in the PNG encoding of `MaskCode`.
    pub fn mask_codes(&self, gbuffer: &GBuffer) -> Vec<u8> {
        let mut codes = gbuffer
            .class
            .iter()
            .zip(&self.lit)
            .map(|(c, &lit)| {
                (match c {
                    PixelClass::Background => MaskCode::Background,
                    PixelClass::FacingAway => MaskCode::FacingAway,
                    PixelClass::OutsideLight => MaskCode::OutsideLight,
                    PixelClass::Uncertain => MaskCode::Uncertain,
                    PixelClass::Evaluated if lit != 0 => MaskCode::Lit,
                    PixelClass::Evaluated => MaskCode::Shadowed,
                }) as u8
            })
            .collect::<Vec<u8>>();
        for &i in &self.uncertain {
            codes[i as usize] = MaskCode::Uncertain as u8;
        }
        codes
    }

    /// The first pixel this reference lists as uncertain that `gbuffer` still evaluates (None
    /// once `GBuffer::leave_out` has taken the list out): a score over such a G-buffer would
    /// count a pixel the reference cannot decide.
    pub fn uncertain_still_evaluated(&self, gbuffer: &GBuffer) -> Option<u32> {
        self.uncertain
            .iter()
            .copied()
            .find(|&i| gbuffer.class.get(i as usize) == Some(&PixelClass::Evaluated))
    }

    /// Rebuilds the visibility from a mask in the PNG encoding.
    pub fn from_mask_codes(width: u32, height: u32, codes: &[u8]) -> Self {
        HardReference {
            width,
            height,
            lit: codes.iter().map(|&c| (c == MaskCode::Lit as u8) as u8).collect(),
            uncertain: (0..codes.len() as u32)
                .filter(|&i| codes[i as usize] == MaskCode::Uncertain as u8)
                .collect(),
        }
    }
}

/// The shadow ray from a surface point to the light's centre.
pub fn hard_shadow_ray(point: &SurfacePoint, light: &Light) -> ShadowRay {
    shadow_ray_to_centre(point, &LightSight::of(light))
}

/// `hard_shadow_ray` for a light prepared once per trace.
pub(in crate::trace) fn shadow_ray_to_centre(point: &SurfacePoint, light: &LightSight) -> ShadowRay {
    match *light {
        LightSight::Directional { towards } => ShadowRay::along(point, towards),
        LightSight::Spot { position, .. } | LightSight::Point { position, .. } => {
            ShadowRay::to_point(point, position)
        }
    }
}

/// Whether the segment from a surface point to the light's centre meets no other triangle, for
/// one point (the hard reference traces its rays in batches, `ShadowBatch`).
pub(in crate::trace) fn hard_visible(
    bvh: &SceneBvh,
    scratch: &mut TraversalScratch,
    point: &SurfacePoint,
    light: &LightSight,
) -> bool {
    bvh.shadow_occluder(scratch, &shadow_ray_to_centre(point, light)).is_none()
}

/// Pixels are traced in tiles of `TILE_COLUMNS` × `TILE_ROWS`, row by row within a tile, so that
/// where every pixel is evaluated a batch holds a tile of 4×4: one packet of sixteen with
/// AVX-512, otherwise a packet of 4×2 and then the 4×2 below. The shadow rays of a compact block
/// start closer together than those of eight pixels of one row, so a packet's rays share more
/// of their walk, and the next packet finds much of it in the cache. On the 200K forest at
/// 1920×1080, blocks of 4×2 ran shadow rays 1.29× as fast as rows of eight on one thread (1.28×
/// on two), and tiles of two such blocks 1.03× faster again (1.01×) (docs/scale.md).
const TILE_COLUMNS: usize = 4;
const TILE_ROWS: usize = WIDE_BATCH / TILE_COLUMNS;

/// Traces one shadow ray per evaluated pixel; the pixels whose answer is not certain are listed
/// in `uncertain` (docs/reference.md, "The reference's uncertainty").
pub fn trace_hard_reference(
    scene: &Scene,
    bvh: &SceneBvh,
    gbuffer: &GBuffer,
    light: &Light,
) -> HardReference {
    let mut lit = vec![0u8; gbuffer.pixel_count()];
    let w = gbuffer.width as usize;
    let sight = LightSight::of(light);
    let uncertain_bands: Vec<Vec<u32>> = lit
        .par_chunks_mut(w * TILE_ROWS)
        .enumerate()
        .map_init(
            || bvh.scratch(),
            |scratch, (band, rows)| {
                // The band's evaluated pixels, traced together a batch at a time.
                let first = band * TILE_ROWS * w;
                let mut uncertain = Vec::new();
                let mut answer = |j: usize, visible: bool, doubt: bool| {
                    rows[j] = visible as u8;
                    if doubt {
                        uncertain.push((first + j) as u32);
                    }
                };
                let mut batch = ShadowBatch::new();
                for_each_in_tiles(gbuffer, band, |j| {
                    let ray = shadow_ray_to_centre(&gbuffer.surface_point(scene, first + j), &sight);
                    batch.push(bvh, scratch, j, ray, &mut answer);
                });
                batch.finish(bvh, scratch, &mut answer);
                uncertain.sort_unstable();
                uncertain
            },
        )
        .collect();
    HardReference { width: gbuffer.width, height: gbuffer.height, lit, uncertain: uncertain_bands.concat() }
}

/// Calls `f(j)` for each evaluated pixel of band `band` (its rows from `band`·`TILE_ROWS`, `j`
/// counted from the band's first pixel) in the order the hard reference traces them: tile by
/// tile from the left, each tile row by row. Plain loops: the same order as a chain of
/// `flat_map`s ran shadow rays at 0.87× (docs/scale.md).
#[inline(always)]
fn for_each_in_tiles(gbuffer: &GBuffer, band: usize, mut f: impl FnMut(usize)) {
    let w = gbuffer.width as usize;
    let first = band * TILE_ROWS * w;
    let band_rows = (gbuffer.height as usize - band * TILE_ROWS).min(TILE_ROWS);
    for x0 in (0..w).step_by(TILE_COLUMNS) {
        for y in 0..band_rows {
            for j in y * w + x0..y * w + (x0 + TILE_COLUMNS).min(w) {
                if gbuffer.class[first + j] == PixelClass::Evaluated {
                    f(j);
                }
            }
        }
    }
}

/// The shadow rays of `trace_hard_reference`, band by band in the order it traces them, a group
/// of bands at a time, so that `trace_shadow_rays` can time the rays alone, without building
/// them (`reference --timing`): `f` gets each group in turn. A group holds about `max_bytes` of
/// rays, but at least one band per thread (a ray takes over 100 bytes, so a 1920×1080 view's
/// take over 100 MB, and one at the largest image size several GB).
pub fn hard_shadow_rays(
    scene: &Scene,
    gbuffer: &GBuffer,
    light: &Light,
    max_bytes: usize,
    f: impl FnMut(&[Vec<ShadowRay>]),
) {
    let sight = LightSight::of(light);
    let w = gbuffer.width as usize;
    let bands = (gbuffer.height as usize).div_ceil(TILE_ROWS);
    let band_rays = |band: usize| {
        let mut rays = Vec::new();
        for_each_in_tiles(gbuffer, band, |j| {
            let i = band * TILE_ROWS * w + j;
            rays.push(shadow_ray_to_centre(&gbuffer.surface_point(scene, i), &sight));
        });
        rays
    };
    in_groups(bands, w * TILE_ROWS, max_bytes, band_rays, f);
}

/// Prepared shadow rays a group of `units` (bands, rows) at a time: `rays_of(unit)` makes a
/// unit's rays, at most `unit_rays` of them, in parallel within a group, and `f` gets each group
/// in turn. A group holds about `max_bytes` of rays, but at least one unit per thread.
pub(super) fn in_groups(
    units: usize,
    unit_rays: usize,
    max_bytes: usize,
    rays_of: impl Fn(usize) -> Vec<ShadowRay> + Sync,
    mut f: impl FnMut(&[Vec<ShadowRay>]),
) {
    let unit_bytes = (unit_rays * std::mem::size_of::<ShadowRay>()).max(1);
    let group = (max_bytes / unit_bytes).max(rayon::current_num_threads()).max(1);
    for first in (0..units).step_by(group) {
        let rays: Vec<Vec<ShadowRay>> =
            (first..(first + group).min(units)).into_par_iter().map(&rays_of).collect();
        f(&rays);
    }
}

/// Traces `hard_shadow_rays`'s bands as `trace_hard_reference` does, in the same batches, and
/// returns how many rays are occluded (by the best guess where uncertain).
pub fn trace_shadow_rays(bvh: &SceneBvh, bands: &[Vec<ShadowRay>]) -> usize {
    bands
        .par_iter()
        .map_init(
            || bvh.scratch(),
            |scratch, rays| {
                let mut occluded = 0;
                let mut batches = rays.chunks(WIDE_BATCH).peekable();
                while let Some(batch) = batches.next() {
                    prefetch(batches.peek().copied().unwrap_or_default());
                    occluded += bvh.shadow_answers(scratch, batch).occluded.count_ones() as usize;
                }
                occluded
            },
        )
        .sum()
}

/// Asks for `rays` to be brought into the cache before they are read. Prepared rays are read once,
/// in order, a batch at a time; between two batches the walk is long enough that the next one's
/// first loads had been waiting on memory (18 % of the sixteen-lane walk's time on the forest at
/// 1920×1080; docs/scale.md).
#[inline(always)]
fn prefetch(rays: &[ShadowRay]) {
    #[cfg(target_arch = "x86_64")]
    for offset in (0..std::mem::size_of_val(rays)).step_by(64) {
        // SAFETY: the address lies within `rays`; a prefetch reads nothing and never faults, and
        // every x86_64 processor has SSE.
        unsafe {
            use std::arch::x86_64::{_MM_HINT_T0, _mm_prefetch};
            _mm_prefetch::<_MM_HINT_T0>(rays.as_ptr().cast::<i8>().add(offset));
        }
    }
    #[cfg(not(target_arch = "x86_64"))]
    let _ = rays;
}

/// The G-buffer and hard reference of a view as every score takes them: the G-buffer traced, the
/// reference traced over it, and the pixels the reference cannot decide beyond doubt left out
/// of the G-buffer (`GBuffer::leave_out`), so that nothing traced or scored over it afterwards
/// (the soft references, a technique's visibility) sees them. They stay listed in
/// `HardReference::uncertain` and are counted in `Counts::uncertain` (docs/reference.md, "The
/// reference's uncertainty").
pub fn trace_scored_view(
    scene: &Scene,
    bvh: &SceneBvh,
    camera: &Camera,
    light: &Light,
) -> (GBuffer, HardReference) {
    let mut gbuffer = GBuffer::trace(bvh, camera, light);
    let reference = trace_hard_reference(scene, bvh, &gbuffer, light);
    gbuffer.leave_out(&reference.uncertain);
    (gbuffer, reference)
}
