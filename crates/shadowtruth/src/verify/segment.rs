//! The exact decision of whether the segment from a surface point to the light meets one
//! triangle (docs/reference.md, "The definition"), with the predicates of `exact.rs`: no
//! rounding can change the answer.
//!
//! The surface point p is the anchored one, exactly on its own triangle's plane (never its f32
//! rounding). The segment from p towards a spot light ends at the light's position L (closed at
//! both ends); towards a directional light it is the ray p + s·D, s ≥ 0, with D the light's f32
//! direction reversed. A triangle is closed: touching an edge or a vertex, or ending on it,
//! counts as meeting. Triangles that contain p are not occluders. A triangle with zero area in
//! exact arithmetic never occludes.

use super::exact::{AnchoredPoint, Diff, Term, det2_sign, det3_sign, dot_sign};
use glam::Vec3;
use std::cmp::Ordering::{self, Equal};

/// Where the light is, seen from the surface point.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Toward {
    /// A spot light's position: the segment ends there.
    Point(Vec3),
    /// The reversed direction of a directional light: the segment is a ray.
    Direction(Vec3),
}

/// What the exact test says of one triangle.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Contact {
    Misses,
    Meets,
    /// The triangle contains p: by definition not an occluder.
    ContainsOrigin,
}

/// Whether the segment from `p` towards the light meets `triangle`.
pub fn contact(p: &AnchoredPoint, toward: Toward, triangle: &[Vec3; 3]) -> Contact {
    let [a, b, c] = triangle.map(Term::vec);
    let pt = p.terms();
    let (e1, e2) = (Diff::between(b, a), Diff::between(c, a));
    let side_p = det3_sign([e1, e2, Diff::between(pt, a)]);
    let (dir, side_end) = match toward {
        Toward::Point(l) => {
            (Diff::between(Term::vec(l), pt), det3_sign([e1, e2, Diff::between(Term::vec(l), a)]))
        }
        Toward::Direction(d) => (Diff::plain(d), det3_sign([e1, e2, Diff::plain(d)])),
    };
    if side_p == Equal {
        return match in_plane(triangle) {
            None => Contact::Misses,
            Some(plane) if plane.contains(pt) => Contact::ContainsOrigin,
            Some(plane) if side_end == Equal => {
                if plane.edges_meet(pt, toward) {
                    Contact::Meets
                } else {
                    Contact::Misses
                }
            }
            Some(_) => Contact::Misses,
        };
    }
    let away_or_parallel = match toward {
        Toward::Point(_) => side_end == side_p,
        Toward::Direction(_) => side_end == side_p || side_end == Equal,
    };
    if away_or_parallel {
        return Contact::Misses;
    }
    // The line through p crosses the plane at one point; it lies in the closed triangle when the
    // volumes spanned with the three edges never take strictly opposite signs.
    let edge = |u: [Term; 3], v: [Term; 3]| det3_sign([Diff::between(u, pt), Diff::between(v, pt), dir]);
    let signs = [edge(a, b), edge(b, c), edge(c, a)];
    if no_opposite_signs(&signs) { Contact::Meets } else { Contact::Misses }
}

pub(super) fn no_opposite_signs(signs: &[Ordering]) -> bool {
    !(signs.contains(&Ordering::Less) && signs.contains(&Ordering::Greater))
}

/// A triangle seen in 2D by dropping the axis along which its plane does not project flat.
struct PlaneView {
    axes: [usize; 2],
    triangle: [[Term<'static>; 3]; 3],
    orientation: Ordering,
}

fn in_plane(triangle: &[Vec3; 3]) -> Option<PlaneView> {
    let [a, b, c] = triangle.map(Term::vec);
    [[1, 2], [2, 0], [0, 1]].into_iter().find_map(|axes| {
        let orientation = det2_sign([pair(b, a, axes), pair(c, a, axes)]);
        (orientation != Equal).then_some(PlaneView { axes, triangle: [a, b, c], orientation })
    })
}

/// The 2D difference u − v on two axes.
fn pair<'a>(u: [Term<'a>; 3], v: [Term<'a>; 3], axes: [usize; 2]) -> [Diff<'a>; 2] {
    axes.map(|k| Diff { x: u[k], y: v[k] })
}

impl PlaneView {
    /// Whether the closed triangle contains q (q on its plane).
    fn contains(&self, q: [Term; 3]) -> bool {
        let [a, b, c] = self.triangle;
        [(a, b), (b, c), (c, a)].iter().all(|&(u, v)| {
            let s = det2_sign([pair(v, u, self.axes), pair(q, u, self.axes)]);
            s == Equal || s == self.orientation
        })
    }

    /// Whether the in-plane segment (or ray) from p, which lies outside the triangle, meets
    /// one of its closed edges.
    fn edges_meet(&self, p: [Term; 3], toward: Toward) -> bool {
        let [a, b, c] = self.triangle;
        [(a, b), (b, c), (c, a)].iter().any(|&(u, v)| self.meets_edge(p, toward, u, v))
    }

    fn meets_edge(&self, p: [Term; 3], toward: Toward, u: [Term; 3], v: [Term; 3]) -> bool {
        let axes = self.axes;
        let dir = match toward {
            Toward::Point(l) => pair(Term::vec(l), p, axes),
            Toward::Direction(d) => axes.map(|k| Diff::of(d[k])),
        };
        let (side_u, side_v) = (det2_sign([dir, pair(u, p, axes)]), det2_sign([dir, pair(v, p, axes)]));
        if side_u == side_v && side_u != Equal {
            return false;
        }
        // Past the end of a segment: (q − L)·dir > 0.
        let before_end = |q: [Term; 3]| match toward {
            Toward::Point(l) => dot_sign(pair(q, Term::vec(l), axes), dir) != Ordering::Greater,
            Toward::Direction(_) => true,
        };
        if side_u == Equal && side_v == Equal {
            // Collinear: the edge's interval along the line overlaps [0, end].
            let ahead = |q: [Term; 3]| dot_sign(pair(q, p, axes), dir) != Ordering::Less;
            return (ahead(u) || ahead(v)) && (before_end(u) || before_end(v));
        }
        // The line crosses the closed edge at p + t·dir with t = cross(u − p, v − u) / cross(dir, v − u).
        let den = det2_sign([dir, pair(v, u, axes)]);
        let num = det2_sign([pair(u, p, axes), pair(v, u, axes)]);
        let t_nonnegative = num == Equal || num == den;
        let t_at_most_one = match toward {
            Toward::Point(l) => {
                let past = det2_sign([pair(u, Term::vec(l), axes), pair(v, u, axes)]);
                past == Equal || past != den
            }
            Toward::Direction(_) => true,
        };
        t_nonnegative && t_at_most_one
    }
}
