//! The adjudicator: the hard reference decided again with exact predicates on the f32 inputs,
//! independent of the tracer's BVH and arithmetic, and `verify_view`, which checks the traced
//! G-buffer and reference against it pixel by pixel (docs/reference.md).
//!
//! For each pixel: the exact closest hit of its primary ray (`primary.rs`) against the
//! G-buffer's, and the exact shadow answer at the G-buffer's anchored surface point
//! (`segment.rs`, exact signs from `exact.rs`), both found behind a conservative cull of its own
//! (`cull.rs`). The error band is the tracer's own declared uncertainty: a disagreement on a
//! pixel the tracer flagged is allowed and counted, one on any other pixel is a bug.

mod cull;
mod exact;
mod pixel_selection;
mod primary;
mod segment;

pub use exact::{AnchoredPoint, Diff, Filtered, Term, det2_sign, det3_exact, det3_filtered, det3_sign};
pub use pixel_selection::{DEFAULT_SAMPLE_PIXELS, PixelSelection};
pub use primary::{PrimaryRay, RayHit};
pub use segment::{Contact, Toward, contact};

use crate::scene::{Camera, Light, LightKind, Scene, is_degenerate};
use crate::trace::{
    GBuffer, PixelClass, SceneBvh, SurfacePoint, hard_shadow_ray, primary_directions, trace_hard_reference,
};
use cull::{Cull, Query};
use glam::{DVec3, Vec3};
use rayon::prelude::*;
use serde::Serialize;
use std::borrow::Cow;

/// The adjudicator's decision for one surface point.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Judgement {
    /// The exact answer: some triangle other than those containing p meets the segment.
    pub exact_shadowed: bool,
    /// A triangle the segment meets, when it is shadowed.
    pub triangle: Option<u32>,
}

/// Scratch space of the cull, reused between queries.
pub type CullStack = Vec<(u32, f64)>;

/// The scene's triangles behind their own cull.
pub struct Adjudicator<'a> {
    /// Every scene triangle by id, in world space.
    triangles: Cow<'a, [[Vec3; 3]]>,
    cull: Cull,
}

impl<'a> Adjudicator<'a> {
    pub fn new(scene: &'a Scene) -> Self {
        // Instanced triangles are judged in world space, as flattened (src/scene/instance.rs).
        let triangles: Cow<'a, [[Vec3; 3]]> = match scene.instances.is_empty() {
            true => Cow::Borrowed(&scene.flat_triangles),
            false => Cow::Owned((0..scene.triangle_count() as u32).map(|id| scene.triangle(id)).collect()),
        };
        let cull = Cull::new(&triangles, |t| !is_degenerate(t));
        Adjudicator { triangles, cull }
    }

    /// The anchored surface point of a hit: barycentrics (b1, b2) on triangle `id`.
    pub fn anchored(&self, id: u32, barycentric: [f32; 2]) -> AnchoredPoint {
        AnchoredPoint::new(self.triangles[id as usize], barycentric)
    }

    /// Judges the segment from `point` (anchored on its triangle by its barycentrics) to
    /// `light`'s centre.
    pub fn judge(&self, point: &SurfacePoint, light: &Light, stack: &mut CullStack) -> Judgement {
        let p = self.anchored(point.triangle, point.barycentric);
        let (toward, direction, s_max) = match &light.kind {
            LightKind::Spot { position, .. } | LightKind::Point { position, .. } => {
                (Toward::Point(*position), position.as_dvec3() - p.approx(), 1.0)
            }
            LightKind::Directional { direction, .. } => {
                (Toward::Direction(-*direction), -direction.as_dvec3(), f64::INFINITY)
            }
        };
        let query = Query { origin: p.approx(), origin_error: p.error(), direction };
        let mut meets = None;
        self.cull.for_each_near(query, s_max, stack, |t, _| {
            if t == point.triangle || contact(&p, toward, &self.triangles[t as usize]) != Contact::Meets {
                return true;
            }
            meets = Some(t);
            false
        });
        Judgement { exact_shadowed: meets.is_some(), triangle: meets }
    }

    /// The exact closest hit of `ray` (s > 0), ties to the lowest triangle id.
    pub fn closest_hit(&self, ray: &PrimaryRay, stack: &mut CullStack) -> Option<RayHit> {
        let query = Query {
            origin: ray.origin.as_dvec3(),
            origin_error: DVec3::ZERO,
            direction: ray.direction.as_dvec3(),
        };
        let mut best: Option<RayHit> = None;
        self.cull.for_each_near(query, f64::INFINITY, stack, |t, s_max| {
            let triangle = &self.triangles[t as usize];
            if let Some(hit) = primary::ray_hit(ray, t, triangle) {
                let better = best.as_ref().is_none_or(|b| {
                    primary::nearer(ray, &hit, triangle, b, &self.triangles[b.triangle as usize])
                });
                if better {
                    *s_max = s_max.min(hit.interval().1);
                    best = Some(hit);
                }
            }
            true
        });
        best
    }

    /// Whether triangle `id`, seen along `ray`, faces `light` exactly.
    pub fn faces_light(&self, ray: &PrimaryRay, id: u32, light: &Light) -> bool {
        primary::faces_light(ray, &self.triangles[id as usize], light)
    }

    /// How far the G-buffer's anchored point lies from the exact hit point, as a fraction of
    /// the point's documented precision: 2⁻¹⁸·max_i |v_i − origin|∞ / max(|n̂·d̂|, 2⁻¹⁰)
    /// (docs/reference.md). Computed in f64, to about 10⁻⁵ of the ratio.
    pub fn point_error_ratio(&self, ray: &PrimaryRay, hit: &RayHit, barycentric: [f32; 2]) -> f64 {
        let t = &self.triangles[hit.triangle as usize];
        let x = primary::hit_point(ray, hit, t);
        let p = self.anchored(hit.triangle, barycentric).approx();
        let o = ray.origin.as_dvec3();
        let reach = t.iter().map(|v| (v.as_dvec3() - o).abs().max_element()).fold(0.0, f64::max);
        let [a, b, c] = t.map(|v| v.as_dvec3());
        let cosine = (b - a).cross(c - a).normalize().dot(ray.direction.as_dvec3().normalize()).abs();
        let precision = 2f64.powi(-18) * reach / cosine.max(2f64.powi(-10));
        (x - p).abs().max_element() / precision
    }
}

/// What a case is about.
#[derive(Clone, Debug, PartialEq, Serialize)]
#[serde(tag = "kind", rename_all = "snake_case")]
pub enum Disagreement {
    /// The pixel's shadow: the tracer's answer at its surface point is not the exact one.
    Shadow {
        /// The triangle the pixel's surface point lies on.
        surface_triangle: u32,
        traced_shadowed: bool,
        exact_shadowed: bool,
        /// The tracer's occluder when it says shadowed, else the triangle the exact segment meets.
        triangle: Option<u32>,
        at_boundary: bool,
    },
    /// The pixel's primary hit: another triangle, a hit against a miss, or a point farther from
    /// the exact hit than its precision.
    Primary {
        traced_triangle: Option<u32>,
        exact_triangle: Option<u32>,
        /// |X − p|∞ over the point's precision, where both hit the same triangle.
        point_error_ratio: Option<f64>,
    },
    /// The right triangle, classed on the wrong side of the light: `facing_away` against
    /// facing it, or the reverse (counted with the primary disagreements).
    Facing { triangle: u32, traced_facing: bool, exact_facing: bool },
}

/// One pixel where the tracer and the exact answer differ.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct Case {
    pub x: u32,
    pub y: u32,
    /// The tracer flagged the pixel as uncertain: the disagreement is allowed.
    pub in_band: bool,
    #[serde(flatten)]
    pub disagreement: Disagreement,
}

impl Case {
    pub fn outside_band(&self) -> bool {
        !self.in_band
    }

    fn at_boundary(&self) -> bool {
        matches!(self.disagreement, Disagreement::Shadow { at_boundary: true, .. })
    }
}

/// Most cases kept in a `ViewVerification` (outside the band first).
pub const MAX_CASES: usize = 20;

/// The G-buffer and hard reference of one (camera, light) checked against the adjudicator.
#[derive(Clone, Debug, Serialize)]
pub struct ViewVerification {
    pub camera: String,
    pub light: String,
    pub width: u32,
    pub height: u32,
    /// Pixels the G-buffer evaluates, as traced (the reference's uncertain ones among them).
    pub evaluated: usize,
    /// Pixels the tracer flagged as uncertain: its shadow answer (`HardReference::uncertain`)
    /// plus its primary hit (`PixelClass::Uncertain`).
    pub uncertain: usize,
    /// Pixels whose shadow answer is checked: evaluated ones (sampled, or all) and every one the
    /// tracer flagged that has a surface point.
    pub checked: usize,
    /// Checked pixels next to a shadow boundary (a 3×3 neighbourhood holding both answers).
    pub checked_at_boundary: usize,
    /// Checked pixels whose traced shadow answer is the exact one.
    pub agree: usize,
    pub disagree_at_boundary: usize,
    pub disagree_away_from_boundary: usize,
    /// Shadow disagreements on pixels the tracer flagged: allowed.
    pub disagree_in_band: usize,
    /// Shadow disagreements on pixels the tracer did not flag: the reference is wrong there.
    pub disagree_outside_band: usize,
    /// Checked pixels (shadow or primary) the tracer flagged, whether or not they agree.
    pub in_band: usize,
    /// Pixels whose primary hit is checked: the shadow-checked ones and, sampled or all, every
    /// pixel of the image (background and unscored ones too).
    pub primary_checked: usize,
    pub primary_disagree_in_band: usize,
    pub primary_disagree_outside_band: usize,
    /// The largest |X − p|∞ over the point's precision among pixels whose traced and exact
    /// primary hits are on the same triangle (at most 1 where they agree).
    pub max_point_error_ratio: f64,
    /// The first `MAX_CASES` disagreements, those outside the band first.
    pub cases: Vec<Case>,
    pub seconds: f64,
}

impl ViewVerification {
    /// No disagreement outside the band, of shadow or of primary hit.
    pub fn passed(&self) -> bool {
        self.disagree_outside_band == 0 && self.primary_disagree_outside_band == 0
    }
}

/// The exact primary hit of one pixel against the G-buffer's.
struct PrimaryCheck {
    exact: Option<u32>,
    ratio: Option<f64>,
    /// Whether the surface exactly faces the light, where the traced hit is the exact one.
    facing: Option<bool>,
}

/// Every `stride`-th index of `0..n` for about `selection`'s count.
fn stride(n: usize, selection: PixelSelection) -> usize {
    match selection {
        PixelSelection::All => 1,
        PixelSelection::Sample(k) => n.div_ceil(k.max(1)).max(1),
    }
}

/// Traces the G-buffer and hard reference of (`camera`, `light`) and checks the selected pixels
/// against the adjudicator: their shadow answers, and their primary hits.
pub fn verify_view(
    scene: &Scene,
    bvh: &SceneBvh,
    adjudicator: &Adjudicator,
    camera: &Camera,
    light: &Light,
    selection: PixelSelection,
) -> ViewVerification {
    let start = std::time::Instant::now();
    let g = GBuffer::trace(bvh, camera, light);
    let reference = trace_hard_reference(scene, bvh, &g, light);
    let n = g.pixel_count();
    let primary_flagged: Vec<bool> = g.class.iter().map(|&c| c == PixelClass::Uncertain).collect();
    let mut flagged = primary_flagged.clone();
    for &i in &reference.uncertain {
        flagged[i as usize] = true;
    }
    let boundary = shadow_boundary(&g, &reference.lit);
    // Shadow: sampled evaluated pixels, those at a boundary, and every flagged one with a point.
    let every = stride(g.evaluated.len(), selection);
    let mut shadow_pixels = vec![false; n];
    for (k, &i) in g.evaluated.iter().enumerate() {
        shadow_pixels[i as usize] = k % every == 0 || boundary[i as usize] || flagged[i as usize];
    }
    for (i, selected) in shadow_pixels.iter_mut().enumerate() {
        *selected |= primary_flagged[i] && g.triangle[i] != u32::MAX;
    }
    let every = stride(n, selection);
    let primary_pixels: Vec<usize> = (0..n).filter(|&i| i % every == 0 || shadow_pixels[i]).collect();
    let shadow_pixels: Vec<usize> = (0..n).filter(|&i| shadow_pixels[i]).collect();

    let judged: Vec<Judgement> = shadow_pixels
        .par_iter()
        .map_init(Vec::new, |stack, &i| adjudicator.judge(&g.surface_point(scene, i), light, stack))
        .collect();
    let directions = primary_directions(camera);
    let primary: Vec<PrimaryCheck> = primary_pixels
        .par_iter()
        .map_init(Vec::new, |stack, &i| {
            let ray = PrimaryRay { origin: camera.position, direction: directions[i] };
            let hit = adjudicator.closest_hit(&ray, stack);
            let exact = hit.as_ref().map(|h| h.triangle);
            let same = hit.filter(|h| h.triangle == g.triangle[i]);
            let ratio = same.map(|h| adjudicator.point_error_ratio(&ray, &h, g.barycentric[i]));
            let facing = same.map(|h| adjudicator.faces_light(&ray, h.triangle, light));
            PrimaryCheck { exact, ratio, facing }
        })
        .collect();

    let mut v = ViewVerification {
        camera: camera.name.clone(),
        light: light.name.clone(),
        width: g.width,
        height: g.height,
        evaluated: g.evaluated.len(),
        uncertain: reference.uncertain.len() + g.count(PixelClass::Uncertain),
        checked: shadow_pixels.len(),
        checked_at_boundary: shadow_pixels.iter().filter(|&&i| boundary[i]).count(),
        agree: 0,
        disagree_at_boundary: 0,
        disagree_away_from_boundary: 0,
        disagree_in_band: 0,
        disagree_outside_band: 0,
        in_band: primary_pixels.iter().filter(|&&i| flagged[i]).count(),
        primary_checked: primary_pixels.len(),
        primary_disagree_in_band: 0,
        primary_disagree_outside_band: 0,
        max_point_error_ratio: 0.0,
        cases: Vec::new(),
        seconds: 0.0,
    };
    let at = |i: usize| ((i % g.width as usize) as u32, (i / g.width as usize) as u32);
    let mut scratch = bvh.scratch();
    for (&i, j) in shadow_pixels.iter().zip(&judged) {
        let traced_shadowed = reference.lit[i] == 0;
        if traced_shadowed == j.exact_shadowed {
            v.agree += 1;
            continue;
        }
        if boundary[i] {
            v.disagree_at_boundary += 1;
        } else {
            v.disagree_away_from_boundary += 1;
        }
        if flagged[i] {
            v.disagree_in_band += 1;
        } else {
            v.disagree_outside_band += 1;
        }
        let point = g.surface_point(scene, i);
        let triangle = if traced_shadowed {
            bvh.shadow_occluder(&mut scratch, &hard_shadow_ray(&point, light))
        } else {
            j.triangle
        };
        let (x, y) = at(i);
        v.cases.push(Case {
            x,
            y,
            in_band: flagged[i],
            disagreement: Disagreement::Shadow {
                surface_triangle: point.triangle,
                traced_shadowed,
                exact_shadowed: j.exact_shadowed,
                triangle,
                at_boundary: boundary[i],
            },
        });
    }
    for (&i, check) in primary_pixels.iter().zip(&primary) {
        let traced = (g.triangle[i] != u32::MAX).then_some(g.triangle[i]);
        if let Some(r) = check.ratio {
            v.max_point_error_ratio = v.max_point_error_ratio.max(r);
        }
        let (x, y) = at(i);
        // The tracer decides facing exactly too, so a pixel it could not flag cannot differ.
        let traced_facing = match g.class[i] {
            PixelClass::FacingAway => Some(false),
            PixelClass::OutsideLight | PixelClass::Evaluated => Some(true),
            PixelClass::Background | PixelClass::Uncertain => None,
        };
        if let (Some(exact_facing), Some(traced_facing)) = (check.facing, traced_facing)
            && exact_facing != traced_facing
        {
            v.primary_disagree_outside_band += 1;
            let triangle = g.triangle[i];
            let disagreement = Disagreement::Facing { triangle, traced_facing, exact_facing };
            v.cases.push(Case { x, y, in_band: false, disagreement });
        }
        if traced == check.exact && check.ratio.is_none_or(|r| r <= 1.0) {
            continue;
        }
        if primary_flagged[i] {
            v.primary_disagree_in_band += 1;
        } else {
            v.primary_disagree_outside_band += 1;
        }
        v.cases.push(Case {
            x,
            y,
            in_band: primary_flagged[i],
            disagreement: Disagreement::Primary {
                traced_triangle: traced,
                exact_triangle: check.exact,
                point_error_ratio: check.ratio,
            },
        });
    }
    v.cases.sort_by_key(|c| (c.in_band, !c.at_boundary(), c.y, c.x));
    v.cases.truncate(MAX_CASES);
    v.seconds = start.elapsed().as_secs_f64();
    v
}

/// Evaluated pixels whose 3×3 neighbourhood holds both a lit and a shadowed evaluated pixel.
fn shadow_boundary(g: &GBuffer, lit: &[u8]) -> Vec<bool> {
    let (w, h) = (g.width as i64, g.height as i64);
    let state = |x: i64, y: i64| {
        let i = (y * w + x) as usize;
        (g.class[i] == PixelClass::Evaluated).then_some(lit[i] != 0)
    };
    let mut out = vec![false; g.pixel_count()];
    for &i in &g.evaluated {
        let (x, y) = (i as i64 % w, i as i64 / w);
        let mine = lit[i as usize] != 0;
        out[i as usize] = (-1..=1).any(|dy| {
            (-1..=1).any(|dx| {
                let (nx, ny) = (x + dx, y + dy);
                nx >= 0 && ny >= 0 && nx < w && ny < h && state(nx, ny) == Some(!mine)
            })
        });
    }
    out
}
