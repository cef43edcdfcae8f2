//! Error attribution: why a pixel is wrong (docs/conventions.md, "Attribution"). Every false
//! pixel of a run is put in exactly one class:
//!
//! - **aliasing**: the pixel lies within one shadow-map texel footprint of a reference shadow
//!   boundary, so no shadow map of this resolution can be expected to get it right;
//! - **seam**: any other false pixel that a point light's map shades within `SEAM_TEXELS` of its
//!   face's edge (a paraboloid's rim), where a filter's taps reach past the face
//!   (`LightUv::with_seams`; no pixel is near a seam otherwise);
//! - **acne**: any other false shadow (reference lit, technique shadowed);
//! - **light bleeding**: any other false lit where occluders of two objects overlap in the light's
//!   view at the pixel or within `BLEEDING_TEXELS` of it in the map (`trace::ShadowOverlap`, when
//!   the caller gives it): the error filterable maps make where a filter mixes two occluders'
//!   depths;
//! - **leak**: any other false lit (reference shadowed, technique lit).
//!
//! Definitions, exactly as computed:
//!
//! - A pixel is *false* with the ½ threshold of `score_hard`: on an evaluated pixel (one of
//!   `GBuffer::evaluated`; `visibility[k]` belongs to pixel `gbuffer.evaluated[k]`) the technique
//!   says lit when `v ≥ ½`, the reference says lit when `HardReference::lit[i] == 1`; the pixel
//!   is false when the two differ; a NaN (a surface mismatch of an imported buffer) is never
//!   false. Hence `aliasing + seam + acne + light_bleeding + leak == false_shadow + false_lit`.
//! - Every evaluated pixel i has a light-map position `(u, v)` from
//!   `LightView::project(gbuffer.position[i])`, kept in texel units `(u·N, v·N)`,
//!   N = `view.resolution` (`LightUv`, computed once per G-buffer and view).
//! - A false pixel p is *within one texel footprint of a reference shadow boundary* when some
//!   other evaluated pixel q in its search window (below) has a reference value different from
//!   p's and a light-map position within one texel of p's on both axes:
//!   `|u_p − u_q|·N ≤ 1` and `|v_p − v_q|·N ≤ 1`. A reference boundary lies between two such
//!   samples, hence within one texel of p. Pixels that do not project (w ≤ 0) have no position:
//!   they are never a q, and as a p they are acne or leak.
//! - The search window is the square of radius R pixels around p (clipped to the image), where
//!   R is meant to cover one texel on screen. It is estimated from p's own 4-neighbours
//!   (x ± 1, y ± 1) that are evaluated, project, and show the same object as p: each gives a uv
//!   step per pixel `s = max(|Δu|, |Δv|)·N` (texels per pixel), and with the smallest of them
//!   `R = ceil(1 / s_min) + 1`, clamped to [1, 64]. When no neighbour qualifies, R = 64.
//!   **The cap**: a boundary sample farther than 64 pixels from p on screen (in x or y) is not
//!   found, and such a pixel counts as acne or leak. The estimate is local (p's own
//!   neighbours), so on a strongly sheared or curved projection a boundary sample one texel
//!   away in uv may lie just outside the window; the `+ 1` absorbs most of that.
//! - A false-lit pixel p that is not aliasing is *light bleeding* when occluders overlap at p, or
//!   at some evaluated pixel q within `BLEEDING_TEXELS` = 4 texels of p's light-map position on
//!   both axes, found in the window of reach 4 texels (`R = ceil(4 / s_min) + 1`, the same cap).
//!   *Occluders overlap* at a pixel when the line from the light to its point crosses surfaces
//!   of two different objects (`trace::ShadowOverlap`); a filter of the map that reaches such a
//!   place mixes the two occluders' depths. Without an overlap map every such pixel is a leak.
//!
//! Cost: only false pixels are searched, in parallel; a window is scanned only when a
//! summed-area table says it holds a pixel with the opposite reference value (or where
//! occluders overlap), and the scan stops at the first such sample. The search allocates nothing. The counts are sums of
//! independent per-pixel decisions, so they are identical for any thread count.

use super::classify::Counts;
use crate::raster::LightView;
use crate::scene::Scene;
use crate::trace::{GBuffer, HardReference, PixelClass, ShadowOverlap};
use glam::Vec3;
use rayon::prelude::*;
use serde::{Deserialize, Serialize};

/// The largest search radius in pixels (see the module documentation).
pub const MAX_RADIUS: usize = 64;

/// How far in the light map, in texels, a false lit pixel may lie from a point where occluders
/// overlap and still be light bleeding: a filter's reach (a 3×3 blur and a bilinear read, with a
/// texel to spare).
pub const BLEEDING_TEXELS: f32 = 4.0;

/// The shadow-map resolution whose texel footprint attributes a renderer's buffer when its own
/// resolution is not told (`score --resolution`, the Python package's `score`): 2048, the most
/// common shipping size of a directional light's map.
pub const DEFAULT_ATTRIBUTION_RESOLUTION: u32 = 2048;

/// The false pixels of one run, by cause.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Serialize, Deserialize)]
pub struct Attribution {
    /// False pixels within one texel footprint of a reference shadow boundary.
    pub aliasing: u64,
    /// Other false pixels near a seam of a point light's map.
    #[serde(default)]
    pub seam: u64,
    /// Other false shadows (reference lit, technique shadowed).
    pub acne: u64,
    /// Other false lits (reference shadowed, technique lit) under one occluder.
    pub leak: u64,
    /// Other false lits where occluders of two objects overlap in the light's view.
    #[serde(default)]
    pub light_bleeding: u64,
}

impl Attribution {
    /// All false pixels.
    pub fn total(&self) -> u64 {
        self.aliasing + self.seam + self.acne + self.leak + self.light_bleeding
    }
}

impl Counts {
    /// These counts with the attribution filled in.
    pub fn with_attribution(self, a: Attribution) -> Counts {
        let Attribution { aliasing, seam, acne, leak, light_bleeding } = a;
        Counts { aliasing, seam, acne, leak, light_bleeding, ..self }
    }
}

/// The uv of every evaluated pixel, shared by every run at the same (camera, light, resolution).
pub struct LightUv {
    width: u32,
    height: u32,
    resolution: u32,
    /// Per pixel (row-major), the light-map position in texels `(u·N, v·N)`; NaN for pixels
    /// that are not evaluated or do not project.
    texel: Vec<[f32; 2]>,
    /// Per pixel, whether its map shades it near a seam (empty: none is).
    near_seam: Vec<bool>,
}

impl LightUv {
    /// Projects every evaluated pixel of `gbuffer` into `view` (in parallel over rows).
    pub fn new(gbuffer: &GBuffer, view: &LightView) -> LightUv {
        Self::through(gbuffer, view.resolution, |_| Some(view))
    }

    /// Projects every evaluated pixel of `gbuffer` into the map `view_of` its surface point
    /// chooses (a cascade), each `resolution`² texels; None leaves it unprojected.
    pub fn through<'v>(
        gbuffer: &GBuffer,
        resolution: u32,
        view_of: impl Fn(Vec3) -> Option<&'v LightView> + Sync,
    ) -> LightUv {
        Self::through_maps(gbuffer, resolution, |p| view_of(p).map(|view| (view, 0)))
    }

    /// Projects every evaluated pixel of `gbuffer` into the map (`view`, `index`) its surface
    /// point chooses, each `resolution`² texels: the maps laid side by side along u, map `index`
    /// from u = 2·index, so that pixels on different maps (a cube's faces) are never within a
    /// texel of each other.
    pub fn through_maps<'v>(
        gbuffer: &GBuffer,
        resolution: u32,
        map_of: impl Fn(Vec3) -> Option<(&'v LightView, usize)> + Sync,
    ) -> LightUv {
        let w = gbuffer.width as usize;
        let n = resolution as f32;
        let mut texel = vec![[f32::NAN; 2]; gbuffer.pixel_count()];
        if w > 0 {
            texel.par_chunks_mut(w).enumerate().for_each(|(y, row)| {
                for (x, out) in row.iter_mut().enumerate() {
                    let i = y * w + x;
                    if gbuffer.class[i] != PixelClass::Evaluated {
                        continue;
                    }
                    let position = gbuffer.position[i];
                    let Some((view, index)) = map_of(position) else { continue };
                    if let Some(p) = view.project(position) {
                        *out = [(p.x + 2.0 * index as f32) * n, p.y * n];
                    }
                }
            });
        }
        LightUv { width: gbuffer.width, height: gbuffer.height, resolution, texel, near_seam: Vec::new() }
    }

    /// These positions with the pixels that lie near a seam of their map: `near_seam` per
    /// evaluated pixel, in `gbuffer.evaluated` order (a point light's faces,
    /// `SEAM_TEXELS` from an edge).
    pub fn with_seams(mut self, gbuffer: &GBuffer, near_seam: impl Fn(usize) -> bool) -> LightUv {
        let mut per_pixel = vec![false; self.texel.len()];
        for (k, &i) in gbuffer.evaluated.iter().enumerate() {
            per_pixel[i as usize] = near_seam(k);
        }
        self.near_seam = per_pixel;
        self
    }

    /// Whether pixel `i` lies near a seam of its map.
    pub fn near_seam(&self, i: usize) -> bool {
        self.near_seam.get(i).copied().unwrap_or(false)
    }

    /// The shadow-map resolution N these positions are measured in.
    pub fn resolution(&self) -> u32 {
        self.resolution
    }

    /// The light-map position of pixel `i` in texels `(u·N, v·N)`, if it is evaluated and
    /// projects.
    pub fn texel(&self, i: usize) -> Option<[f32; 2]> {
        let t = self.texel[i];
        (!t[0].is_nan() && !t[1].is_nan()).then_some(t)
    }
}

/// Classes every false pixel of `visibility` (one value per evaluated pixel, in
/// `gbuffer.evaluated` order; `gbuffer` traced in `scene`) as aliasing, seam (where `light_uv` says so), acne, light bleeding
/// (where `overlap` says occluders overlap; never without it) or leak; see the module
/// documentation.
pub fn attribute(
    scene: &Scene,
    gbuffer: &GBuffer,
    reference: &HardReference,
    visibility: &[f32],
    light_uv: &LightUv,
    overlap: Option<&ShadowOverlap>,
) -> Attribution {
    assert_eq!(visibility.len(), gbuffer.evaluated.len(), "one visibility per evaluated pixel");
    assert_eq!(
        (light_uv.width, light_uv.height),
        (gbuffer.width, gbuffer.height),
        "the light uv belongs to this G-buffer"
    );
    assert_eq!(reference.lit.len(), gbuffer.pixel_count());

    let any_false = gbuffer
        .evaluated
        .par_iter()
        .zip(visibility.par_iter())
        .any(|(&i, &v)| !v.is_nan() && (reference.lit[i as usize] != 0) != (v >= 0.5));
    if !any_false {
        return Attribution::default();
    }
    let table = OppositeTable::new(light_uv, reference);
    let (w, h) = (light_uv.width as usize, light_uv.height as usize);
    let overlap = overlap.map(|o| (o, CountTable::new(w, h, |i| o.at(i) && light_uv.texel(i).is_some())));
    let search = Search { scene, gbuffer, lit: &reference.lit, uv: light_uv, table: &table, overlap };

    gbuffer
        .evaluated
        .par_iter()
        .zip(visibility.par_iter())
        .with_min_len(4096)
        .map(|(&i, &v)| {
            let i = i as usize;
            let r_lit = reference.lit[i] != 0;
            let v_lit = v >= 0.5;
            // NaN: a surface mismatch, which is no false pixel (classify.rs).
            if v.is_nan() || r_lit == v_lit {
                Attribution::default()
            } else if search.near_boundary(i) {
                Attribution { aliasing: 1, ..Attribution::default() }
            } else if light_uv.near_seam(i) {
                Attribution { seam: 1, ..Attribution::default() }
            } else if r_lit {
                Attribution { acne: 1, ..Attribution::default() }
            } else if search.near_overlap(i) {
                Attribution { light_bleeding: 1, ..Attribution::default() }
            } else {
                Attribution { leak: 1, ..Attribution::default() }
            }
        })
        .reduce(Attribution::default, |a, b| Attribution {
            aliasing: a.aliasing + b.aliasing,
            seam: a.seam + b.seam,
            acne: a.acne + b.acne,
            leak: a.leak + b.leak,
            light_bleeding: a.light_bleeding + b.light_bleeding,
        })
}

/// A summed-area table of the pixels where a predicate holds: whether a window holds any of
/// them is then O(1).
struct CountTable {
    /// Row stride: width + 1.
    stride: usize,
    /// `sums[y·stride + x]`: the pixels in [0, x) × [0, y) where the predicate holds.
    sums: Vec<u32>,
}

impl CountTable {
    fn new(width: usize, height: usize, holds: impl Fn(usize) -> bool) -> Self {
        let stride = width + 1;
        let mut sums = vec![0u32; stride * (height + 1)];
        for y in 0..height {
            let mut row = 0u32;
            for x in 0..width {
                row += holds(y * width + x) as u32;
                sums[(y + 1) * stride + x + 1] = sums[y * stride + x + 1] + row;
            }
        }
        CountTable { stride, sums }
    }

    /// The pixels in the inclusive window [x0, x1] × [y0, y1] where the predicate holds.
    fn count(&self, x0: usize, y0: usize, x1: usize, y1: usize) -> u32 {
        let (t, s) = (&self.sums, self.stride);
        t[(y1 + 1) * s + x1 + 1] + t[y0 * s + x0] - t[y0 * s + x1 + 1] - t[(y1 + 1) * s + x0]
    }
}

/// The pixels that can be a boundary sample q (evaluated, projecting), split by their reference
/// value.
struct OppositeTable {
    lit: CountTable,
    shadowed: CountTable,
}

impl OppositeTable {
    fn new(uv: &LightUv, reference: &HardReference) -> Self {
        let (w, h) = (uv.width as usize, uv.height as usize);
        let candidate = |i: usize, lit: bool| uv.texel(i).is_some() && (reference.lit[i] != 0) == lit;
        OppositeTable {
            lit: CountTable::new(w, h, |i| candidate(i, true)),
            shadowed: CountTable::new(w, h, |i| candidate(i, false)),
        }
    }

    /// Candidates with reference value `lit` in the inclusive window [x0, x1] × [y0, y1].
    fn count(&self, lit: bool, x0: usize, y0: usize, x1: usize, y1: usize) -> u32 {
        if lit { &self.lit } else { &self.shadowed }.count(x0, y0, x1, y1)
    }
}

struct Search<'a> {
    scene: &'a Scene,
    gbuffer: &'a GBuffer,
    lit: &'a [u8],
    uv: &'a LightUv,
    table: &'a OppositeTable,
    /// Where occluders overlap, and its table (over pixels that project).
    overlap: Option<(&'a ShadowOverlap, CountTable)>,
}

impl Search<'_> {
    /// The window of pixel `i` for a reach of `texels` in the map: its clipped bounds.
    fn window(&self, i: usize, texels: f32) -> (usize, usize, usize, usize) {
        let (w, h) = (self.uv.width as usize, self.uv.height as usize);
        let (x, y) = (i % w, i / w);
        let r = window_radius(self.scene, self.gbuffer, self.uv, x, y, texels);
        (x.saturating_sub(r), y.saturating_sub(r), (x + r).min(w - 1), (y + r).min(h - 1))
    }

    /// Whether some pixel q of `i`'s window for `texels`, where `wanted(q)`, lies within
    /// `texels` of `i` in the light map on both axes.
    fn any_within(
        &self,
        i: usize,
        window: (usize, usize, usize, usize),
        texels: f32,
        wanted: impl Fn(usize) -> bool,
    ) -> bool {
        let Some(tp) = self.uv.texel(i) else {
            return false;
        };
        let w = self.uv.width as usize;
        let (x0, y0, x1, y1) = window;
        for qy in y0..=y1 {
            let row = qy * w;
            for q in row + x0..=row + x1 {
                if !wanted(q) {
                    continue;
                }
                let tq = self.uv.texel[q];
                // NaN (no position) fails both comparisons.
                if (tq[0] - tp[0]).abs() <= texels && (tq[1] - tp[1]).abs() <= texels {
                    return true;
                }
            }
        }
        false
    }

    /// Whether pixel `i` has a boundary sample q in its window (see the module documentation).
    fn near_boundary(&self, i: usize) -> bool {
        if self.uv.texel(i).is_none() {
            return false;
        }
        let window = self.window(i, 1.0);
        let (x0, y0, x1, y1) = window;
        let p_lit = self.lit[i] != 0;
        if self.table.count(!p_lit, x0, y0, x1, y1) == 0 {
            return false;
        }
        let p_code = self.lit[i];
        self.any_within(i, window, 1.0, |q| self.lit[q] != p_code)
    }

    /// Whether occluders overlap at pixel `i`, or at a pixel within `BLEEDING_TEXELS` of it in
    /// the map (see the module documentation).
    fn near_overlap(&self, i: usize) -> bool {
        let Some((overlap, table)) = &self.overlap else {
            return false;
        };
        if overlap.at(i) {
            return true;
        }
        if self.uv.texel(i).is_none() {
            return false;
        }
        let window = self.window(i, BLEEDING_TEXELS);
        let (x0, y0, x1, y1) = window;
        table.count(x0, y0, x1, y1) > 0 && self.any_within(i, window, BLEEDING_TEXELS, |q| overlap.at(q))
    }
}

/// The search radius R of pixel (x, y) for a reach of `texels` in the map:
/// `ceil(texels / s_min) + 1` clamped to [1, 64], `s_min` the smallest uv step per pixel (in
/// texels, max over u and v) to a 4-neighbour that is evaluated, projects and shows the same
/// object; 64 when there is none.
fn window_radius(scene: &Scene, gbuffer: &GBuffer, uv: &LightUv, x: usize, y: usize, texels: f32) -> usize {
    let (w, h) = (uv.width as usize, uv.height as usize);
    let i = y * w + x;
    let Some(tp) = uv.texel(i) else {
        return MAX_RADIUS;
    };
    let object = gbuffer.object(scene, i);
    let mut smallest = f32::INFINITY;
    let neighbours = [
        (x > 0).then(|| i - 1),
        (x + 1 < w).then(|| i + 1),
        (y > 0).then(|| i - w),
        (y + 1 < h).then(|| i + w),
    ];
    for q in neighbours.into_iter().flatten() {
        if gbuffer.object(scene, q) != object {
            continue;
        }
        if let Some(tq) = uv.texel(q) {
            let step = (tq[0] - tp[0]).abs().max((tq[1] - tp[1]).abs());
            smallest = smallest.min(step);
        }
    }
    if smallest == f32::INFINITY {
        return MAX_RADIUS; // no neighbour helps
    }
    // A zero step (a texel wider than the screen can tell) gives 1/0 = ∞: the cap.
    let r = (texels / smallest).ceil() + 1.0;
    if r.is_finite() && r < MAX_RADIUS as f32 { (r as usize).max(1) } else { MAX_RADIUS }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::raster::Projection;
    use crate::scene::{Camera, PixelFootprint};
    use glam::{Mat4, Vec3, Vec4};

    const N: u32 = 4;

    /// An orthographic view of resolution 4 whose texel coordinates (u·N, v·N) are the world
    /// (x, y): clip x = 2x/N − 1, so u = x/N. Exact in binary for the values used here.
    fn view() -> LightView {
        let s = 2.0 / N as f32;
        let clip_from_world = Mat4::from_cols(
            Vec4::new(s, 0.0, 0.0, 0.0),
            Vec4::new(0.0, s, 0.0, 0.0),
            Vec4::new(0.0, 0.0, 0.5, 0.0),
            Vec4::new(-1.0, -1.0, 0.5, 1.0),
        );
        LightView {
            resolution: N,
            projection: Projection::Orthographic { left: 0.0, right: N as f32, bottom: 0.0, top: N as f32 },
            light_from_world: Mat4::IDENTITY,
            clip_from_world,
            near: 0.0,
            far: 1.0,
            to_light: Some(Vec3::Z),
            position: None,
            light_size: None,
        }
    }

    /// A pixel of a hand-made G-buffer: object and texel position, or background.
    #[derive(Clone, Copy)]
    enum Px {
        Bg,
        At(u32, f32, f32),
    }

    fn gbuffer(width: u32, height: u32, pixels: &[Px]) -> GBuffer {
        assert_eq!(pixels.len(), (width * height) as usize);
        let mut g = GBuffer {
            width,
            height,
            class: vec![PixelClass::Background; pixels.len()],
            position: vec![Vec3::ZERO; pixels.len()],
            barycentric: vec![[0.0; 2]; pixels.len()],
            normal: vec![Vec3::Z; pixels.len()],
            triangle: vec![u32::MAX; pixels.len()],
            evaluated: Vec::new(),
            footprint: PixelFootprint::of(&Camera {
                name: "c".into(),
                position: Vec3::Z,
                look_at: Vec3::ZERO,
                up: Vec3::Y,
                fov_y_deg: 60.0,
                width,
                height,
                path: None,
            }),
        };
        for (i, px) in pixels.iter().enumerate() {
            if let Px::At(object, tu, tv) = *px {
                g.class[i] = PixelClass::Evaluated;
                g.position[i] = Vec3::new(tu, tv, 0.0);
                g.triangle[i] = object;
                g.evaluated.push(i as u32);
            }
        }
        g
    }

    /// The scene of the hand-made G-buffers: triangle k belongs to object k (the objects
    /// `Px::At` names; the geometry is never read).
    fn objects() -> Scene {
        let mut scene = Scene::empty("objects".into(), std::path::Path::new(""), Vec::new(), Vec::new());
        scene.flat_triangles = vec![[Vec3::ZERO, Vec3::X, Vec3::Y]; 4];
        scene.flat_triangle_object = (0..4).collect();
        scene
    }

    fn reference(lit: &[u8], g: &GBuffer) -> HardReference {
        HardReference { width: g.width, height: g.height, lit: lit.to_vec(), uncertain: Vec::new() }
    }

    /// One row of 8 pixels on object 0, half a texel apart (R = ceil(1/0.5) + 1 = 3), and a
    /// second row whose pixel 3 shows object 1 at a chosen texel position; the rest of that
    /// row is background. Pixel 2 of the first row (texel x = 1) is the false pixel.
    fn scene(other: (f32, f32)) -> GBuffer {
        let mut px = vec![Px::Bg; 16];
        for (k, p) in px.iter_mut().enumerate().take(8) {
            *p = Px::At(0, 0.5 * k as f32, 0.0);
        }
        px[8 + 3] = Px::At(1, other.0, other.1);
        gbuffer(8, 2, &px)
    }

    fn run(g: &GBuffer, lit: &[u8], visibility_of: impl Fn(usize) -> f32) -> Attribution {
        let r = reference(lit, g);
        let v: Vec<f32> = g.evaluated.iter().map(|&i| visibility_of(i as usize)).collect();
        attribute(&objects(), g, &r, &v, &LightUv::new(g, &view()), None)
    }

    #[test]
    fn light_uv_holds_texel_positions_of_evaluated_pixels_only() {
        let g = scene((1.0, 1.0));
        let uv = LightUv::new(&g, &view());
        assert_eq!(uv.texel(2), Some([1.0, 0.0]));
        assert_eq!(uv.texel(11), Some([1.0, 1.0]));
        assert_eq!(uv.texel(8), None);
        assert_eq!(uv.resolution(), N);
    }

    #[test]
    fn radius_follows_the_smallest_uv_step_and_the_cap() {
        let g = scene((1.0, 1.0));
        let uv = LightUv::new(&g, &view());
        assert_eq!(window_radius(&objects(), &g, &uv, 2, 0, 1.0), 3, "half a texel per pixel");
        // Object 1 stands alone (its neighbours are background or another object).
        assert_eq!(window_radius(&objects(), &g, &uv, 3, 1, 1.0), MAX_RADIUS);
        // Four texels per pixel: ceil(1/4) + 1 = 2.
        let px: Vec<Px> = (0..3).map(|k| Px::At(0, 4.0 * k as f32, 0.0)).collect();
        let g = gbuffer(3, 1, &px);
        let uv = LightUv::new(&g, &view());
        assert_eq!(window_radius(&objects(), &g, &uv, 1, 0, 1.0), 2);
        // A tiny step (a texel covers many pixels) is clamped to the cap.
        let px: Vec<Px> = (0..3).map(|k| Px::At(0, 1e-3 * k as f32, 0.0)).collect();
        let g = gbuffer(3, 1, &px);
        let uv = LightUv::new(&g, &view());
        assert_eq!(window_radius(&objects(), &g, &uv, 1, 0, 1.0), MAX_RADIUS);
    }

    /// The first row is lit in truth except as noted; pixel 11 (object 1) carries the other
    /// reference value. Pixel 2 is false, every other pixel right.
    fn false_shadow_at_2(other: (f32, f32)) -> Attribution {
        let g = scene(other);
        let mut lit = vec![0u8; 16];
        lit[..8].fill(1);
        run(&g, &lit, |i| if i == 2 { 0.0 } else { lit[i] as f32 })
    }

    #[test]
    fn a_false_shadow_one_texel_from_a_boundary_is_aliasing() {
        // q at exactly one texel in v (and 0 in u), one row down.
        let a = false_shadow_at_2((1.0, 1.0));
        assert_eq!(a, Attribution { aliasing: 1, seam: 0, acne: 0, leak: 0, light_bleeding: 0 });
        // Exactly one texel on both axes.
        let a = false_shadow_at_2((2.0, -1.0));
        assert_eq!(a, Attribution { aliasing: 1, seam: 0, acne: 0, leak: 0, light_bleeding: 0 });
    }

    #[test]
    fn a_false_shadow_two_texels_from_a_boundary_is_acne() {
        // Same pixel on screen, two texels away in v: no boundary within one texel.
        let a = false_shadow_at_2((1.0, 2.0));
        assert_eq!(a, Attribution { aliasing: 0, seam: 0, acne: 1, leak: 0, light_bleeding: 0 });
        // Two texels in u, zero in v.
        let a = false_shadow_at_2((3.0, 0.0));
        assert_eq!(a, Attribution { aliasing: 0, seam: 0, acne: 1, leak: 0, light_bleeding: 0 });
        // Just over one texel.
        let a = false_shadow_at_2((1.0, 1.0 + 1.0 / 64.0));
        assert_eq!(a, Attribution { aliasing: 0, seam: 0, acne: 1, leak: 0, light_bleeding: 0 });
    }

    #[test]
    fn a_false_lit_is_aliasing_or_leak_by_the_same_rule() {
        let leak_at_2 = |other: (f32, f32)| {
            let g = scene(other);
            let mut lit = vec![0u8; 16];
            lit[8 + 3] = 1;
            run(&g, &lit, |i| if i == 2 { 1.0 } else { lit[i] as f32 })
        };
        assert_eq!(
            leak_at_2((0.0, 1.0)),
            Attribution { aliasing: 1, seam: 0, acne: 0, leak: 0, light_bleeding: 0 }
        );
        assert_eq!(
            leak_at_2((-1.0, 1.0)),
            Attribution { aliasing: 0, seam: 0, acne: 0, leak: 1, light_bleeding: 0 }
        );
    }

    #[test]
    fn the_boundary_is_searched_within_the_window_only() {
        // A row of 12 pixels, half a texel apart (R = 3); the reference turns shadowed at
        // pixel 7 and the false shadow sits at pixel 3: 4 pixels (2 texels) away, out of
        // reach. At pixel 4 (3 pixels, 1.5 texels) still acne; at pixel 5 (2 pixels, 1 texel)
        // aliasing.
        let px: Vec<Px> = (0..12).map(|k| Px::At(0, 0.5 * k as f32, 0.0)).collect();
        let g = gbuffer(12, 1, &px);
        let lit: Vec<u8> = (0..12).map(|k| (k < 7) as u8).collect();
        let at = |p: usize| run(&g, &lit, |i| if i == p { 0.0 } else { lit[i] as f32 });
        assert_eq!(at(3), Attribution { aliasing: 0, seam: 0, acne: 1, leak: 0, light_bleeding: 0 });
        assert_eq!(at(4), Attribution { aliasing: 0, seam: 0, acne: 1, leak: 0, light_bleeding: 0 });
        assert_eq!(at(5), Attribution { aliasing: 1, seam: 0, acne: 0, leak: 0, light_bleeding: 0 });
        // The pixel on the shadowed side of the boundary, falsely lit: aliasing.
        let a = run(&g, &lit, |i| if i == 8 { 1.0 } else { lit[i] as f32 });
        assert_eq!(a, Attribution { aliasing: 1, seam: 0, acne: 0, leak: 0, light_bleeding: 0 });
    }

    #[test]
    fn a_false_pixel_near_a_seam_is_seam_unless_it_is_aliasing() {
        // The row of `the_boundary_is_searched_within_the_window_only`, its pixels 0 to 4 near a
        // seam of their map: a false pixel there that is not near the boundary is seam, one
        // within a texel of it stays aliasing, and one away from the seam stays acne.
        let px: Vec<Px> = (0..12).map(|k| Px::At(0, 0.5 * k as f32, 0.0)).collect();
        let g = gbuffer(12, 1, &px);
        let lit: Vec<u8> = (0..12).map(|k| (k < 7) as u8).collect();
        let uv = LightUv::new(&g, &view()).with_seams(&g, |k| k <= 4 || k == 6);
        let at = |p: usize| {
            let v: Vec<f32> = g
                .evaluated
                .iter()
                .map(|&i| if i as usize == p { 0.0 } else { lit[i as usize] as f32 })
                .collect();
            attribute(&objects(), &g, &reference(&lit, &g), &v, &uv, None)
        };
        assert_eq!(at(3), Attribution { seam: 1, ..Attribution::default() });
        assert_eq!(at(6), Attribution { aliasing: 1, ..Attribution::default() });
        assert_eq!(at(5), Attribution { aliasing: 1, ..Attribution::default() });
        let far = LightUv::new(&g, &view()).with_seams(&g, |k| k >= 5);
        let v: Vec<f32> =
            g.evaluated.iter().map(|&i| if i == 3 { 0.0 } else { lit[i as usize] as f32 }).collect();
        assert_eq!(
            attribute(&objects(), &g, &reference(&lit, &g), &v, &far, None),
            Attribution { acne: 1, ..Attribution::default() }
        );
    }

    #[test]
    fn background_pixels_never_make_a_boundary() {
        // Pixel 11 is background (reference 0) right next to a lit false-shadow pixel.
        let mut px = vec![Px::Bg; 16];
        for (k, p) in px.iter_mut().enumerate().take(8) {
            *p = Px::At(0, 0.5 * k as f32, 0.0);
        }
        let g = gbuffer(8, 2, &px);
        let mut lit = vec![0u8; 16];
        lit[..8].fill(1);
        let a = run(&g, &lit, |i| if i == 3 { 0.0 } else { 1.0 });
        assert_eq!(a, Attribution { aliasing: 0, seam: 0, acne: 1, leak: 0, light_bleeding: 0 });
    }

    #[test]
    fn counts_take_the_attribution() {
        let c = Counts { false_shadow: 3, ..Counts::default() }.with_attribution(Attribution {
            aliasing: 1,
            seam: 5,
            acne: 2,
            leak: 0,
            light_bleeding: 4,
        });
        assert_eq!(
            (c.false_shadow, c.aliasing, c.seam, c.acne, c.leak, c.light_bleeding),
            (3, 1, 5, 2, 0, 4)
        );
    }
}
