//! A conservative cull for the adjudicator, independent of the tracer's BVH: a binary tree of
//! f64 boxes (median splits), whose query returns every triangle whose box, widened, meets the
//! segment or ray, nearest boxes first.
//!
//! It only has to be conservative for the exact tests that follow it: every triangle the exact
//! segment meets must be visited. Two things separate the f64 slab test from the exact segment.
//! (1) The segment itself: its origin is an anchored point known to `origin_error` per axis, its
//! direction L − p̃ is rounded once (u·|d| per axis, u = 2⁻⁵³), so every point of the exact
//! segment, s ∈ [0, s_max], lies within 2·origin_error + u·|d·s_max| of the computed one at the
//! same s (for rays the direction is an f32 vector, exact). (2) The slab test: each parameter
//! (lo − o)/d is rounded twice, which moves it by at most 2u·|lo − o|/|d| (1 + u), the same as
//! testing a slab moved by 2u(1 + u)·|lo − o| ≤ 4u·scale, where scale bounds |o|, |d·s_max| and
//! the box's coordinates. The minima, maxima and comparisons are exact, and an axis the computed
//! direction does not move along is compared exactly. So widening each box by
//! 2⁻⁴⁰·scale + 2·origin_error (2⁻⁴⁰ is 2¹⁰ times 4u + u, and the widening's own rounding is
//! u of it) keeps every box the exact segment meets.

use glam::{DVec3, Vec3};

struct Node {
    lo: DVec3,
    hi: DVec3,
    /// Leaf: `first..first + count` of `order`; inner: children at `first` and `first + 1`.
    first: u32,
    count: u32,
}

pub struct Cull {
    nodes: Vec<Node>,
    order: Vec<u32>,
}

const LEAF_SIZE: usize = 4;
/// Relative widening of boxes, against the largest coordinate magnitude in the test.
const WIDEN: f64 = 1.0 / (1u64 << 40) as f64;

/// A segment or ray as the cull tests it.
#[derive(Clone, Copy, Debug)]
pub struct Query {
    pub origin: DVec3,
    /// A bound on |origin − exact origin| per axis (its largest entry is used).
    pub origin_error: DVec3,
    pub direction: DVec3,
}

impl Cull {
    /// A tree over the triangles that `include` keeps (by id, their index in `triangles`).
    pub fn new(triangles: &[[Vec3; 3]], include: impl Fn(&[Vec3; 3]) -> bool) -> Cull {
        let bounds: Vec<(DVec3, DVec3)> = triangles
            .iter()
            .map(|t| {
                let (a, b, c) = (t[0].as_dvec3(), t[1].as_dvec3(), t[2].as_dvec3());
                (a.min(b).min(c), a.max(b).max(c))
            })
            .collect();
        let order: Vec<u32> =
            (0..triangles.len() as u32).filter(|&i| include(&triangles[i as usize])).collect();
        let mut cull = Cull { nodes: Vec::new(), order };
        if !cull.order.is_empty() {
            cull.nodes.push(Node { lo: DVec3::ZERO, hi: DVec3::ZERO, first: 0, count: 0 });
            cull.split(0, 0, cull.order.len(), &bounds);
        }
        cull
    }

    fn split(&mut self, node: usize, start: usize, end: usize, bounds: &[(DVec3, DVec3)]) {
        let ids = &mut self.order[start..end];
        let (mut lo, mut hi) = (DVec3::INFINITY, DVec3::NEG_INFINITY);
        for &i in ids.iter() {
            lo = lo.min(bounds[i as usize].0);
            hi = hi.max(bounds[i as usize].1);
        }
        self.nodes[node].lo = lo;
        self.nodes[node].hi = hi;
        if ids.len() <= LEAF_SIZE {
            self.nodes[node].first = start as u32;
            self.nodes[node].count = ids.len() as u32;
            return;
        }
        let centre = |i: u32| bounds[i as usize].0 + bounds[i as usize].1;
        let axis = (hi - lo).max_position();
        let mid = ids.len() / 2;
        ids.select_nth_unstable_by(mid, |&a, &b| centre(a)[axis].total_cmp(&centre(b)[axis]));
        let first = self.nodes.len();
        self.nodes.push(Node { lo: DVec3::ZERO, hi: DVec3::ZERO, first: 0, count: 0 });
        self.nodes.push(Node { lo: DVec3::ZERO, hi: DVec3::ZERO, first: 0, count: 0 });
        self.nodes[node].first = first as u32;
        self.split(first, start, start + mid, bounds);
        self.split(first + 1, start + mid, end, bounds);
    }

    /// Calls `visit` with every triangle whose widened box meets origin + s·direction,
    /// s ∈ [0, s_max] (s_max may be ∞), nearer boxes first. `visit` may lower s_max (to a value
    /// no smaller than any s it still needs) and returns false to stop. `stack` is reused
    /// between queries.
    pub fn for_each_near(
        &self,
        q: Query,
        mut s_max: f64,
        stack: &mut Vec<(u32, f64)>,
        mut visit: impl FnMut(u32, &mut f64) -> bool,
    ) {
        if self.nodes.is_empty() {
            return;
        }
        let reach = if s_max.is_finite() { (q.direction * s_max).abs().max_element() } else { 0.0 };
        let scale = q.origin.abs().max_element().max(reach);
        let slack = 2.0 * q.origin_error.max_element();
        let enter = |n: u32, s_max: f64| {
            let node = &self.nodes[n as usize];
            let magnitude = scale.max(node.lo.abs().max_element()).max(node.hi.abs().max_element());
            let widen = DVec3::splat(WIDEN * magnitude + slack);
            segment_enters_box(q.origin, q.direction, s_max, node.lo - widen, node.hi + widen)
        };
        stack.clear();
        if let Some(s) = enter(0, s_max) {
            stack.push((0, s));
        }
        while let Some((n, entry)) = stack.pop() {
            if entry > s_max {
                continue;
            }
            let node = &self.nodes[n as usize];
            if node.count > 0 {
                for &t in &self.order[node.first as usize..(node.first + node.count) as usize] {
                    if !visit(t, &mut s_max) {
                        return;
                    }
                }
                continue;
            }
            let children = [node.first, node.first + 1].map(|c| (c, enter(c, s_max)));
            let ordered = match (children[0].1, children[1].1) {
                (Some(a), Some(b)) if a < b => [children[1], children[0]],
                _ => children,
            };
            // The farther child goes on the stack first, so the nearer one is walked first.
            for (c, s) in ordered {
                if let Some(s) = s {
                    stack.push((c, s));
                }
            }
        }
    }
}

/// Slab test of the segment against a box: the parameter where it enters, if it does; an axis
/// the segment does not move along keeps the box when the origin lies within its slab.
fn segment_enters_box(origin: DVec3, direction: DVec3, s_max: f64, lo: DVec3, hi: DVec3) -> Option<f64> {
    let (mut enter, mut leave) = (0.0f64, s_max);
    for k in 0..3 {
        if direction[k] == 0.0 {
            if origin[k] < lo[k] || origin[k] > hi[k] {
                return None;
            }
            continue;
        }
        let (a, b) = ((lo[k] - origin[k]) / direction[k], (hi[k] - origin[k]) / direction[k]);
        enter = enter.max(a.min(b));
        leave = leave.min(a.max(b));
        if enter > leave {
            return None;
        }
    }
    Some(enter)
}
