//! The node test of the BVH walk: which of a wide node's eight children a ray may meet, and how
//! far along the ray it enters each.
//!
//! Conservative, so that the walk reaches every triangle the ray can hit (docs/reference.md).
//! Child boxes are exact f32 planes (wide_bvh.rs); the only rounding is the test's own. Along
//! each axis the ray enters a child's slab at the plane it faces and leaves at the other (chosen
//! by the direction's sign), at t = (plane − origin) · (1/d). The reciprocal is rounded once and
//! then shrunk (for entry distances) or grown (for exit distances) by 4 ulps of relative size,
//! which outweighs the three roundings of the reciprocal, the difference and the product: an
//! entry distance is never later than the exact one, an exit never earlier, as far as their
//! signs allow (a distance keeps its exact sign through both roundings, so a box behind the
//! origin stays behind it). This is Ize's robust traversal ("Robust BVH Ray Traversal",
//! JCGT 2(2), 2013) with the slack folded into the reciprocal, so it costs nothing per node.
//! The interval [tmin, tmax] is closed and tmin ≥ 0.
//!
//! Two forms with the same answers: `intersect_node`, four children at a time on any processor
//! (simd4.rs), and `intersect_node_wide`, eight at a time with AVX2, chosen at run time
//! (`packet_isa::wide_available`); each does the same operations in the same order, lane by lane.
//! tests/node_test_forms.rs compares the two forms' references. Packets of rays (packet.rs)
//! take each lane's slab distance with one fused rounding instead of two, as conservatively
//! (`Packet::lane_test`).

use super::simd4::{F4, Span4};
use super::wide_bvh::WideNode;
use glam::Vec3A;

/// Relative shrink and growth of the reciprocal direction: covers the three roundings of a slab
/// distance (2⁻²⁴ each) with room to spare.
pub(in crate::trace) const SLACK: f32 = 4.0 * f32::EPSILON;

/// What the node test needs of a ray.
pub(crate) struct NodeRay {
    pub(in crate::trace) origin: Vec3A,
    /// 1/d shrunk by `SLACK`: entry distances are never late.
    pub(in crate::trace) inv_near: Vec3A,
    /// 1/d grown by `SLACK`: exit distances are never early.
    pub(in crate::trace) inv_far: Vec3A,
    /// Whether the ray moves along each axis: a component so small that its (grown) reciprocal
    /// overflows counts as no motion, and keeps the children whose slab holds the origin.
    moves: [bool; 3],
    /// Whether the direction is negative along each axis: the ray then enters a slab at its
    /// maximum plane.
    pub(in crate::trace) negative: [bool; 3],
}

impl NodeRay {
    pub(crate) fn new(origin: Vec3A, direction: Vec3A) -> Self {
        let inv = Vec3A::ONE / direction;
        let inv_far = inv * (1.0 + SLACK);
        NodeRay {
            origin,
            inv_near: inv * (1.0 - SLACK),
            inv_far,
            moves: inv_far.is_finite_mask().into(),
            negative: direction.to_array().map(|d| d < 0.0),
        }
    }

    /// Whether the ray moves along every axis: the 8-lane test handles no other.
    pub(crate) fn all_axes_move(&self) -> bool {
        self.moves.iter().all(|&m| m)
    }

    /// The planes a ray meets first and last along `axis`, as (near, far).
    #[inline(always)]
    fn planes<'a>(&self, node: &'a WideNode, axis: usize) -> (&'a [f32; 8], &'a [f32; 8]) {
        if self.negative[axis] { (&node.hi[axis], &node.lo[axis]) } else { (&node.lo[axis], &node.hi[axis]) }
    }
}

/// The children a ray may meet: bit c of `mask` for child c, and the distance at which it may
/// enter each (meaningful where its bit is set).
pub(in crate::trace) struct NodeHits {
    pub(in crate::trace) mask: u32,
    pub(in crate::trace) enter: [f32; 8],
}

/// How far a box must grow outwards so that it holds every point within `margin` of it, with
/// the rounding of the widened plane covered: margin + (|plane| + margin) · `SLACK`. Infinite
/// planes (empty slots) stay infinite.
#[inline(always)]
fn widening(plane: F4, margin: f32) -> F4 {
    plane.abs().min(F4::splat(f32::MAX)).add(F4::splat(margin)).mul(F4::splat(SLACK)).add(F4::splat(margin))
}

/// Conservative slab test of the eight children of `node` against [tmin, tmax], their boxes
/// widened by `margin`. Four children at a time, on any processor.
#[inline(always)]
pub(in crate::trace) fn intersect_node<const WIDEN: bool>(
    node: &WideNode,
    ray: &NodeRay,
    tmin: f32,
    tmax: f32,
    margin: f32,
) -> NodeHits {
    let mut hits = NodeHits { mask: 0, enter: [0.0; 8] };
    for half in 0..2 {
        let mut span = Span4::new(tmin, tmax);
        for axis in 0..3 {
            let (near, far) = ray.planes(node, axis);
            let (mut near, mut far) = (F4::load(near, half * 4), F4::load(far, half * 4));
            if WIDEN {
                let sign = if ray.negative[axis] { -1.0 } else { 1.0 };
                near = near.add(widening(near, margin).mul(F4::splat(-sign)));
                far = far.add(widening(far, margin).mul(F4::splat(sign)));
            }
            if ray.moves[axis] {
                let o = F4::splat(ray.origin[axis]);
                span.clip(
                    near.sub(o).mul(F4::splat(ray.inv_near[axis])),
                    far.sub(o).mul(F4::splat(ray.inv_far[axis])),
                );
            } else {
                let (lo, hi) = if ray.negative[axis] { (far, near) } else { (near, far) };
                span.keep_if_between(lo, hi, ray.origin[axis]);
            }
        }
        hits.mask |= span.hit_bits() << (half * 4);
        span.store_enter(&mut hits.enter, half * 4);
    }
    hits
}

/// The node test the walks use on this machine, in words (`reference --timing` prints it).
pub fn node_test_name() -> &'static str {
    #[cfg(target_arch = "x86_64")]
    match super::packet_isa::packet_isa() {
        Some(super::packet_isa::PacketIsa::Avx512) => {
            return "8 children at a time (AVX2; rays walked sixteen to a packet with AVX-512)";
        }
        Some(super::packet_isa::PacketIsa::Avx2) => return "8 children at a time (AVX2)",
        None => {}
    }
    "4 children at a time (portable)"
}

/// Whether a test of the 8-lane form can run it here. A processor without AVX2 cannot, and
/// fails the test (it must not pass for a form it never ran) unless `SHADOWTRUTH_NODE_TEST` is
/// `portable`, which says that the portable form alone is under test.
#[cfg(all(test, target_arch = "x86_64"))]
pub(super) fn wide_form_testable() -> bool {
    if is_x86_feature_detected!("avx2") {
        return true;
    }
    let portable_only = std::env::var("SHADOWTRUTH_NODE_TEST").is_ok_and(|v| v == "portable");
    assert!(
        portable_only,
        "this processor has no AVX2, so the 8-lane node test under test cannot run: run the tests \
         on one with AVX2, or set SHADOWTRUTH_NODE_TEST=portable to test the portable form alone"
    );
    eprintln!("not run: no AVX2, and SHADOWTRUTH_NODE_TEST=portable tests the portable form alone");
    false
}

/// A ray as the 8-lane test takes it: each operand broadcast once per walk, not once per node,
/// and the byte offsets in a node of the planes it enters and leaves by along each axis.
#[cfg(target_arch = "x86_64")]
pub(in crate::trace) struct WideRay {
    origin: [std::arch::x86_64::__m256; 3],
    inv_near: [std::arch::x86_64::__m256; 3],
    inv_far: [std::arch::x86_64::__m256; 3],
    near_offset: [usize; 3],
    far_offset: [usize; 3],
    negative: [bool; 3],
}

#[cfg(target_arch = "x86_64")]
impl WideRay {
    #[target_feature(enable = "avx2")]
    #[inline]
    pub(in crate::trace) fn new(ray: &NodeRay) -> Self {
        use std::arch::x86_64::_mm256_set1_ps;
        let (near_offset, far_offset) = plane_offsets(ray.negative);
        WideRay {
            origin: std::array::from_fn(|axis| _mm256_set1_ps(ray.origin[axis])),
            inv_near: std::array::from_fn(|axis| _mm256_set1_ps(ray.inv_near[axis])),
            inv_far: std::array::from_fn(|axis| _mm256_set1_ps(ray.inv_far[axis])),
            near_offset,
            far_offset,
            negative: ray.negative,
        }
    }
}

/// Per axis, the byte offsets in a `WideNode` of the plane arrays a ray with these direction
/// signs enters a slab by and leaves it by.
pub(in crate::trace) fn plane_offsets(negative: [bool; 3]) -> ([usize; 3], [usize; 3]) {
    let lo = std::mem::offset_of!(WideNode, lo);
    let hi = std::mem::offset_of!(WideNode, hi);
    let plane = |axis: usize, max: bool| if max { hi } else { lo } + 32 * axis;
    (
        std::array::from_fn(|axis| plane(axis, negative[axis])),
        std::array::from_fn(|axis| plane(axis, !negative[axis])),
    )
}

/// `intersect_node` for a ray that moves along every axis, eight children at a time; `WIDEN`
/// says whether `margin` is to be applied at all. Callable only where AVX2 is enabled
/// (`packet_isa::wide_available`).
#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx2")]
#[inline]
pub(in crate::trace) fn intersect_node_wide<const WIDEN: bool>(
    node: &WideNode,
    ray: &WideRay,
    tmin: f32,
    tmax: f32,
    margin: f32,
) -> NodeHits {
    use std::arch::x86_64::*;
    let bytes = node as *const WideNode as *const u8;
    // SAFETY: `offset` is that of one of the node's six plane arrays (`WideRay::new`), each
    // eight f32 aligned to 32 by `WideNode`'s alignment.
    let load = |offset: usize| unsafe { _mm256_load_ps(bytes.add(offset) as *const f32) };
    let widened = |plane: __m256, outwards: f32| {
        let abs = _mm256_andnot_ps(_mm256_set1_ps(-0.0), plane);
        let m = _mm256_set1_ps(margin);
        let finite = _mm256_min_ps(abs, _mm256_set1_ps(f32::MAX));
        let w = _mm256_add_ps(_mm256_mul_ps(_mm256_add_ps(finite, m), _mm256_set1_ps(SLACK)), m);
        _mm256_add_ps(plane, _mm256_mul_ps(w, _mm256_set1_ps(outwards)))
    };
    let (mut enter, mut exit) = (_mm256_set1_ps(tmin), _mm256_set1_ps(tmax));
    for axis in 0..3 {
        let (mut near, mut far) = (load(ray.near_offset[axis]), load(ray.far_offset[axis]));
        if WIDEN {
            let sign = if ray.negative[axis] { -1.0 } else { 1.0 };
            near = widened(near, -sign);
            far = widened(far, sign);
        }
        let t_near = _mm256_mul_ps(_mm256_sub_ps(near, ray.origin[axis]), ray.inv_near[axis]);
        let t_far = _mm256_mul_ps(_mm256_sub_ps(far, ray.origin[axis]), ray.inv_far[axis]);
        enter = _mm256_max_ps(enter, t_near);
        exit = _mm256_min_ps(exit, t_far);
    }
    let mask = _mm256_movemask_ps(_mm256_cmp_ps::<_CMP_LE_OQ>(enter, exit)) as u32;
    let mut hits = NodeHits { mask, enter: [0.0; 8] };
    // SAFETY: eight f32.
    unsafe { _mm256_storeu_ps(hits.enter.as_mut_ptr(), enter) };
    hits
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::trace::bvh::wide_bvh::ChildRef;
    use crate::trace::splitmix::SplitMix64;

    /// A coordinate on a grid of 1/64 within ±64: sums and differences of two are exact in f32.
    fn grid(rng: &mut SplitMix64) -> f32 {
        (rng.range([-4096.0, 4096.0]).round() / 64.0) as f32
    }

    fn grid_point(rng: &mut SplitMix64) -> Vec3A {
        Vec3A::new(grid(rng), grid(rng), grid(rng))
    }

    /// A node whose children are the given boxes, the other slots empty.
    fn node(boxes: &[(Vec3A, Vec3A)]) -> WideNode {
        let mut node = WideNode {
            lo: [[f32::INFINITY; 8]; 3],
            hi: [[f32::NEG_INFINITY; 8]; 3],
            child: [ChildRef::ROOT; 8],
        };
        for (c, (lo, hi)) in boxes.iter().enumerate() {
            for axis in 0..3 {
                node.lo[axis][c] = lo[axis];
                node.hi[axis][c] = hi[axis];
            }
        }
        node
    }

    /// Rays from a grid point through another grid point q (so that the exact ray passes through
    /// q at t = 1), against boxes that only touch q: a point box, and boxes with q on a face, an
    /// edge or a corner. Every one must be reported, entered no later than t = 1.
    #[test]
    fn boxes_that_touch_the_ray_at_one_point_are_hit() {
        let mut rng = SplitMix64::new(7);
        for _ in 0..20_000 {
            let (o, q) = (grid_point(&mut rng), grid_point(&mut rng));
            let d = q - o;
            if d.cmpeq(Vec3A::ZERO).any() {
                continue;
            }
            let ray = NodeRay::new(o, d);
            let up = |v: Vec3A| v + Vec3A::splat(1.0);
            let touching = [
                (q, q),
                (q, up(q)),
                (q - Vec3A::ONE, q),
                (Vec3A::new(q.x, q.y - 1.0, q.z - 1.0), Vec3A::new(q.x + 1.0, q.y, q.z)),
            ];
            let hits = intersect_node::<false>(&node(&touching), &ray, 0.0, 1.0, 0.0);
            assert_eq!(hits.mask, 0b1111, "ray {o} → {q}: a box touching the ray at t = 1 was culled");
            assert!(hits.enter[..4].iter().all(|&t| t <= 1.0), "{:?}", hits.enter);
            // The same boxes moved back by 3d (exactly, on this grid): along the direction's
            // largest component, if it is at least 2 (against the boxes' unit size), each then
            // lies wholly behind the origin, and is never met.
            if d.abs().max_element() >= 2.0 {
                let behind: Vec<_> = touching.iter().map(|&(lo, hi)| (lo - 3.0 * d, hi - 3.0 * d)).collect();
                let mask = intersect_node::<false>(&node(&behind), &ray, 0.0, f32::INFINITY, 0.0).mask;
                assert_eq!(mask, 0, "ray {o} → {q}: a box behind the origin was met");
            }
        }
    }

    /// The 8-lane form gives the portable form's answers, mask and entry distances, bit for bit.
    #[cfg(target_arch = "x86_64")]
    #[test]
    fn both_forms_agree_bit_for_bit() {
        if !wide_form_testable() {
            return;
        }
        let mut rng = SplitMix64::new(11);
        for round in 0..20_000 {
            let boxes: Vec<_> = (0..8)
                .map(|_| {
                    let (a, b) = (grid_point(&mut rng), grid_point(&mut rng));
                    (a.min(b), a.max(b))
                })
                .collect();
            let node = node(&boxes[..1 + round % 8]);
            let (o, q) = (grid_point(&mut rng), grid_point(&mut rng));
            let d = (q - o).normalize();
            if !d.is_finite() || d.cmpeq(Vec3A::ZERO).any() {
                continue;
            }
            let ray = NodeRay::new(o, d);
            let margin = if round % 3 == 0 { 0.01 } else { 0.0 };
            // SAFETY: AVX2 checked above.
            let (portable, wide) = unsafe {
                let wide_ray = WideRay::new(&ray);
                match margin > 0.0 {
                    true => (
                        intersect_node::<true>(&node, &ray, 0.0, 50.0, margin),
                        intersect_node_wide::<true>(&node, &wide_ray, 0.0, 50.0, margin),
                    ),
                    false => (
                        intersect_node::<false>(&node, &ray, 0.0, 50.0, margin),
                        intersect_node_wide::<false>(&node, &wide_ray, 0.0, 50.0, margin),
                    ),
                }
            };
            assert_eq!(portable.mask, wide.mask);
            for c in 0..8 {
                if portable.mask & (1 << c) != 0 {
                    assert_eq!(portable.enter[c].to_bits(), wide.enter[c].to_bits());
                }
            }
        }
    }
}
