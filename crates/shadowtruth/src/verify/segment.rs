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

#[cfg(test)]
mod tests {
    use super::*;
    use glam::vec3;

    fn to(l: Vec3) -> Toward {
        Toward::Point(l)
    }

    /// A flat quad of two triangles at height y around (cx, cz), sharing the edge from (−h, h) to
    /// (h, −h): `first` is the half with the corner (−h, −h), `second` the other.
    fn quad(cx: f32, y: f32, cz: f32, h: f32) -> ([Vec3; 3], [Vec3; 3]) {
        let v = |dx: f32, dz: f32| vec3(cx + dx, y, cz + dz);
        ([v(-h, -h), v(h, -h), v(-h, h)], [v(h, -h), v(h, h), v(-h, h)])
    }

    #[test]
    fn far_from_the_origin_the_other_half_of_a_flat_quad_is_never_met() {
        // At (2·10⁴, 10⁵) an f32 is a multiple of 2⁻⁹ to 2⁻⁶: the rounded surface point near the
        // shared edge can fall across it. The anchored point is exactly on the plane, on its own
        // half or exactly on the edge, so the other half never occludes it; the f32-rounded point,
        // checked the same way, is "exactly" shadowed by its neighbour somewhere — the wrong point.
        let (first, second) = quad(2e4, 1e5, -2e4, 8.0);
        let tilted = |t: [Vec3; 3]| t.map(|v| vec3(v.x, v.y + 0.5 * (v.x - 2e4) - 0.25 * (v.z + 2e4), v.z));
        let (tfirst, tsecond) = (tilted(first), tilted(second));
        let lights = [
            to(vec3(2e4 + 3.0, 1e5 + 40.0, -2e4 + 5.0)),
            to(vec3(2e4 - 30.0, 1e5 + 2.0, -2e4 - 20.0)),
            Toward::Direction(vec3(0.3, 1.0, -0.2)),
            Toward::Direction(vec3(-0.05, 0.01, 0.07)),
        ];
        let (mut rounded_met, mut on_edge) = (0, 0);
        for k in 0..4000u32 {
            // Barycentrics with b1 + b2 within a few f32 steps of 1: next to the shared edge.
            let b1 = (k as f32 + 0.5) / 4000.0;
            let b2 = (1.0 - b1) - (k % 5) as f32 * f32::EPSILON * 0.5;
            for (own, other) in [(first, second), (tfirst, tsecond)] {
                let p = AnchoredPoint::new(own, [b1, b2]);
                for &light in &lights {
                    let exact = contact(&p, light, &other);
                    assert_ne!(exact, Contact::Meets, "k = {k}, {light:?}");
                    on_edge += (exact == Contact::ContainsOrigin) as usize;
                    rounded_met += (contact(&AnchoredPoint::at(p.approx().as_vec3()), light, &other)
                        == Contact::Meets) as usize;
                }
            }
        }
        assert!(on_edge > 0, "some points lie exactly on the shared edge");
        assert!(rounded_met > 0, "the rounded point is met by the other half somewhere");
    }

    #[test]
    fn a_point_one_rational_step_off_the_edge_is_inside_the_neighbour() {
        // b2 one f32 step past 1 − b1: the anchored point lies just across the shared edge, inside
        // the other half, which then contains it (not an occluder) — and a triangle a step above the
        // plane, over that point, is met.
        let (first, second) = quad(2e4, 1e5, -2e4, 8.0);
        let b1 = 0.25f32;
        let b2 = (1.0 - b1).next_up();
        let p = AnchoredPoint::new(first, [b1, b2]);
        let up = to(vec3(2e4, 1e5 + 50.0, -2e4));
        assert_eq!(contact(&p, up, &second), Contact::ContainsOrigin);
        let one_step_up = second.map(|v| vec3(v.x, 1e5f32.next_up(), v.z));
        assert_eq!(contact(&p, up, &one_step_up), Contact::Meets);
        let one_step_down = second.map(|v| vec3(v.x, 1e5f32.next_down(), v.z));
        assert_eq!(contact(&p, up, &one_step_down), Contact::Misses);
        // On its own half exactly at the edge (b1 + b2 = 1): on both halves.
        let q = AnchoredPoint::new(first, [b1, 1.0 - b1]);
        assert_eq!(contact(&q, up, &second), Contact::ContainsOrigin);
        assert_eq!(contact(&q, up, &first), Contact::ContainsOrigin);
    }
}
