//! The adjudicator: the hard reference decided again with exact predicates on the f32 inputs,
//! independent of the tracer's BVH and arithmetic, and `verify_view`, which checks the traced
//! reference against it pixel by pixel (docs/reference.md).
//!
//! For each pixel: the exact answer (`segment.rs`, exact signs from `exact.rs`), found behind a
//! conservative cull of its own (`cull.rs`), and the error band (`band.rs`): whether the
//! tracer's documented rounding could change the answer. A disagreement inside the band is
//! allowed; one outside it is a bug.

mod band;
mod cull;
mod exact;
mod pixel_selection;
mod segment;

pub use band::{Frame, Robustness};
pub use exact::{Diff, det2_sign, det3_sign};
pub use pixel_selection::{DEFAULT_SAMPLE_PIXELS, PixelSelection};
pub use segment::{Contact, Toward, contact};

use crate::scene::{Camera, Light, LightKind, Scene, is_degenerate};
use crate::trace::{GBuffer, PixelClass, SceneBvh, SurfacePoint, hard_shadow_ray, trace_hard_reference};
use cull::Cull;
use glam::Vec3;
use rayon::prelude::*;
use serde::Serialize;
use std::borrow::Cow;

/// What the tracer must answer for a pixel.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize)]
#[serde(rename_all = "snake_case")]
pub enum Expected {
    Lit,
    Shadowed,
    /// The exact answer lies inside the error band: either answer is accepted.
    Either,
}

/// The adjudicator's decision for one pixel.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Judgement {
    /// The exact answer: some triangle other than those containing p meets the segment.
    pub exact_shadowed: bool,
    pub expected: Expected,
    /// A triangle that decides it: one the segment meets, else a fragile one.
    pub triangle: Option<u32>,
    /// The exact test and the band contradict each other on some triangle: a defect of the
    /// adjudicator itself, never expected.
    pub inconsistent: bool,
}

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

    /// Judges the segment from `point` to `light`'s centre. `stack` is reused between calls.
    pub fn judge(&self, point: &SurfacePoint, light: &Light, stack: &mut Vec<u32>) -> Judgement {
        let p = point.position;
        let (toward, direction, length, s_max) = match &light.kind {
            LightKind::Spot { position, .. } => {
                let d = position.as_dvec3() - p.as_dvec3();
                (Toward::Point(*position), d, d.length(), 1.0)
            }
            LightKind::Directional { direction, .. } => {
                (Toward::Direction(-*direction), -direction.as_dvec3(), f64::INFINITY, f64::INFINITY)
            }
        };
        let frame = Frame::new(point, direction, length);
        let own = SamePlane::new(&self.triangles[point.triangle as usize], direction);
        let (mut meets, mut fragile, mut robust_hit, mut inconsistent) = (None, None, None, false);
        self.cull.for_each_near(p.as_dvec3(), direction, s_max, stack, |t| {
            if t == point.triangle {
                return true;
            }
            let triangle = &self.triangles[t as usize];
            let exact = contact(p, toward, triangle);
            if exact == Contact::Meets {
                meets.get_or_insert(t);
            }
            let robustness = match frame.robustness(triangle) {
                Robustness::Fragile if own.leaves_plane_of(triangle) => Robustness::Miss,
                r => r,
            };
            match robustness {
                Robustness::Hit => {
                    inconsistent |= exact != Contact::Meets;
                    robust_hit = Some(t);
                    return false;
                }
                Robustness::Miss => inconsistent |= exact == Contact::Meets,
                Robustness::Fragile => {
                    fragile.get_or_insert(t);
                }
            }
            true
        });
        let expected = match (robust_hit, fragile) {
            (Some(_), _) => Expected::Shadowed,
            (None, Some(_)) => Expected::Either,
            (None, None) => Expected::Lit,
        };
        Judgement {
            exact_shadowed: meets.is_some(),
            expected,
            triangle: robust_hit.or(meets).or(fragile),
            inconsistent,
        }
    }
}

/// The plane of the triangle the surface point lies on, and whether the segment leaves it
/// steeply enough that the tracer certainly passes every triangle in that plane: its origin lies
/// strictly off the plane (the offset clears the point's error box), so the exact distance to
/// the plane is negative and the computed one at most the test's error bound, which the test
/// rejects (docs/reference.md). Steeply enough: the cosine between the segment and the normal
/// exceeds 2⁻²⁰, far above the 2⁻²³ by which the direction's rounding can tilt it.
struct SamePlane {
    triangle: [glam::Vec3; 3],
    leaves: bool,
}

impl SamePlane {
    fn new(triangle: &[glam::Vec3; 3], direction: glam::DVec3) -> SamePlane {
        let [a, b, c] = triangle.map(|v| v.as_dvec3());
        let normal = (b - a).cross(c - a).normalize();
        SamePlane { triangle: *triangle, leaves: normal.dot(direction.normalize()).abs() > 2f64.powi(-20) }
    }

    /// Whether `other` lies exactly in the plane and the segment leaves it steeply.
    fn leaves_plane_of(&self, other: &[glam::Vec3; 3]) -> bool {
        let [a, b, c] = self.triangle;
        let (e1, e2) = (Diff::vec(b, a), Diff::vec(c, a));
        self.leaves
            && other.iter().all(|&v| det3_sign([e1, e2, Diff::vec(v, a)]) == std::cmp::Ordering::Equal)
    }
}

/// One pixel where the tracer and the exact answer differ (or the adjudicator contradicts
/// itself).
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct Case {
    pub x: u32,
    pub y: u32,
    /// The triangle the pixel's surface point lies on.
    pub surface_triangle: u32,
    pub traced_shadowed: bool,
    pub exact_shadowed: bool,
    pub expected: Expected,
    /// The tracer's occluder when it says shadowed, else the adjudicator's deciding triangle.
    pub triangle: Option<u32>,
    pub at_boundary: bool,
    pub inconsistent: bool,
}

impl Case {
    pub fn outside_band(&self) -> bool {
        match self.expected {
            Expected::Lit => self.traced_shadowed,
            Expected::Shadowed => !self.traced_shadowed,
            Expected::Either => false,
        }
    }
}

/// Most cases kept in a `ViewVerification` (outside the band first).
pub const MAX_CASES: usize = 20;

/// The reference of one (camera, light) checked against the adjudicator.
#[derive(Clone, Debug, Serialize)]
pub struct ViewVerification {
    pub camera: String,
    pub light: String,
    pub width: u32,
    pub height: u32,
    pub evaluated: usize,
    pub checked: usize,
    /// Checked pixels next to a shadow boundary (a 3×3 neighbourhood holding both answers).
    pub checked_at_boundary: usize,
    /// Checked pixels whose traced answer is the exact one.
    pub agree: usize,
    pub disagree_at_boundary: usize,
    pub disagree_away_from_boundary: usize,
    /// Disagreements whose exact answer lies inside the error band.
    pub disagree_in_band: usize,
    /// Disagreements outside the band: the reference is wrong there.
    pub disagree_outside_band: usize,
    /// Checked pixels whose exact answer lies inside the band (whether or not they agree).
    pub in_band: usize,
    pub inconsistent: usize,
    /// The first `MAX_CASES` disagreements, those outside the band first.
    pub cases: Vec<Case>,
    pub seconds: f64,
}

impl ViewVerification {
    pub fn passed(&self) -> bool {
        self.disagree_outside_band == 0 && self.inconsistent == 0
    }

    /// Counts a pixel where the traced and exact answers differ (or the exact one is
    /// inconsistent) and keeps it as a case.
    fn add_case(&mut self, case: Case) {
        if case.traced_shadowed != case.exact_shadowed {
            if case.at_boundary {
                self.disagree_at_boundary += 1;
            } else {
                self.disagree_away_from_boundary += 1;
            }
            if case.outside_band() {
                self.disagree_outside_band += 1;
            } else {
                self.disagree_in_band += 1;
            }
        }
        self.cases.push(case);
    }
}

/// The evaluated pixels to check: every `stride`-th one for a sample, and every pixel at a
/// shadow boundary.
fn chosen_pixels(g: &GBuffer, boundary: &[bool], selection: PixelSelection) -> Vec<usize> {
    let stride = match selection {
        PixelSelection::All => 1,
        PixelSelection::Sample(n) => g.evaluated.len().div_ceil(n.max(1)).max(1),
    };
    g.evaluated
        .iter()
        .enumerate()
        .filter(|&(k, &i)| k % stride == 0 || boundary[i as usize])
        .map(|(_, &i)| i as usize)
        .collect()
}

/// Traces the hard reference of (`camera`, `light`) and checks the selected pixels against the
/// adjudicator.
pub fn verify_view(
    scene: &Scene,
    bvh: &SceneBvh,
    adjudicator: &Adjudicator,
    camera: &Camera,
    light: &Light,
    selection: PixelSelection,
) -> ViewVerification {
    let start = std::time::Instant::now();
    let g = GBuffer::trace(scene, bvh, camera, light);
    let reference = trace_hard_reference(scene, bvh, &g, light);
    let boundary = shadow_boundary(&g, &reference.lit);
    let chosen = chosen_pixels(&g, &boundary, selection);
    let judged: Vec<(usize, Judgement)> = chosen
        .par_iter()
        .map_init(Vec::new, |stack, &i| (i, adjudicator.judge(&g.surface_point(scene, i), light, stack)))
        .collect();
    let mut v = ViewVerification {
        camera: camera.name.clone(),
        light: light.name.clone(),
        width: g.width,
        height: g.height,
        evaluated: g.evaluated.len(),
        checked: judged.len(),
        checked_at_boundary: chosen.iter().filter(|&&i| boundary[i]).count(),
        agree: 0,
        disagree_at_boundary: 0,
        disagree_away_from_boundary: 0,
        disagree_in_band: 0,
        disagree_outside_band: 0,
        in_band: 0,
        inconsistent: 0,
        cases: Vec::new(),
        seconds: 0.0,
    };
    let mut scratch = bvh.scratch();
    for (i, j) in judged {
        let traced_shadowed = reference.lit[i] == 0;
        v.in_band += (j.expected == Expected::Either) as usize;
        v.inconsistent += j.inconsistent as usize;
        if traced_shadowed == j.exact_shadowed && !j.inconsistent {
            v.agree += 1;
            continue;
        }
        let point = g.surface_point(scene, i);
        let triangle = if traced_shadowed {
            bvh.shadow_occluder(&mut scratch, &hard_shadow_ray(&point, light))
        } else {
            j.triangle
        };
        let case = Case {
            x: (i % g.width as usize) as u32,
            y: (i / g.width as usize) as u32,
            surface_triangle: point.triangle,
            traced_shadowed,
            exact_shadowed: j.exact_shadowed,
            expected: j.expected,
            triangle,
            at_boundary: boundary[i],
            inconsistent: j.inconsistent,
        };
        v.add_case(case);
    }
    v.cases.sort_by_key(|c| (!c.outside_band() && !c.inconsistent, !c.at_boundary, c.y, c.x));
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
