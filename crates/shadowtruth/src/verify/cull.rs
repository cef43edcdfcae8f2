//! A conservative cull for the adjudicator, independent of the tracer's BVH: a binary tree of
//! f64 boxes (median splits), whose query returns every triangle whose box, widened, meets the
//! segment. Widening each box by 2⁻¹² of the magnitudes involved dwarfs the f64 rounding of
//! the slab test (2⁻⁵² relative), so no triangle the segment meets — or passes within the
//! error band of — is ever left out.

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
const WIDEN: f64 = 1.0 / 4096.0;

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

    /// Calls `visit` with every triangle whose widened box meets the segment origin + s·direction,
    /// s ∈ [0, s_max] (s_max may be ∞). `stack` is reused between queries.
    pub fn for_each_near(
        &self,
        origin: DVec3,
        direction: DVec3,
        s_max: f64,
        stack: &mut Vec<u32>,
        mut visit: impl FnMut(u32) -> bool,
    ) {
        if self.nodes.is_empty() {
            return;
        }
        let scale = origin.abs().max_element()
            + if s_max.is_finite() { (direction * s_max).abs().max_element() } else { 0.0 };
        stack.clear();
        stack.push(0);
        while let Some(n) = stack.pop() {
            let node = &self.nodes[n as usize];
            let widen = DVec3::splat(
                WIDEN * (scale.max(node.lo.abs().max_element()).max(node.hi.abs().max_element())),
            );
            if !segment_meets_box(origin, direction, s_max, node.lo - widen, node.hi + widen) {
                continue;
            }
            if node.count > 0 {
                for &t in &self.order[node.first as usize..(node.first + node.count) as usize] {
                    if !visit(t) {
                        return;
                    }
                }
            } else {
                stack.push(node.first);
                stack.push(node.first + 1);
            }
        }
    }
}

/// Slab test of the segment against a box; an axis the segment does not move along keeps the
/// box when the origin lies within its slab.
fn segment_meets_box(origin: DVec3, direction: DVec3, s_max: f64, lo: DVec3, hi: DVec3) -> bool {
    let (mut enter, mut leave) = (0.0f64, s_max);
    for k in 0..3 {
        if direction[k] == 0.0 {
            if origin[k] < lo[k] || origin[k] > hi[k] {
                return false;
            }
            continue;
        }
        let (a, b) = ((lo[k] - origin[k]) / direction[k], (hi[k] - origin[k]) / direction[k]);
        enter = enter.max(a.min(b));
        leave = leave.min(a.max(b));
        if enter > leave {
            return false;
        }
    }
    true
}
