//! The node test of the BVH walk: which of a wide node's eight children a ray may meet.
//!
//! Conservative, so that the walk reaches every triangle the ray can hit (docs/reference.md):
//! boxes are widened by the rounding of their dequantization, and slab distances by a few ulps
//! (Ize, "Robust BVH Ray Traversal", JCGT 2(2), 2013). Two forms with the same answers:
//! `intersect_node`, four children at a time on any processor (simd4.rs), and
//! `intersect_node_wide`, eight at a time with AVX2 and FMA, chosen at run time
//! (`wide_available`). Every operation of the wide form rounds as the portable one does (a
//! fused multiply–add of a quantized plane is exact in its product), and it takes each slab's
//! near and far plane by the ray's signs instead of a min and max of the two, which gives the
//! same two numbers; tests/node_test_forms.rs compares the two forms' traversals.

use super::simd4::{F4, Span4};
use glam::Vec3A;
use obvhs::cwbvh::node::{CwBvhNode, extract_byte64};

/// obvhs's child-ordering code for a direction (private in obvhs, same bits).
#[inline]
fn octant_inv4(dir: Vec3A) -> u32 {
    (if dir.x < 0.0 { 0 } else { 0x0404_0404 })
        | (if dir.y < 0.0 { 0 } else { 0x0202_0202 })
        | (if dir.z < 0.0 { 0 } else { 0x0101_0101 })
}

/// Conservative slab test of the eight children of `node` against the closed interval
/// [tmin, tmax]. Boxes are widened by the rounding of their dequantization, and slab distances
/// by a few ulps (Ize, "Robust BVH Ray Traversal", JCGT 2(2), 2013). An axis along which the ray
/// does not move keeps the children whose slab holds the origin. Four children at a time.
#[inline(always)]
pub(super) fn intersect_node(node: &CwBvhNode, ray: &NodeRay, tmin: f32, tmax: f32, margin: f32) -> u32 {
    let NodeFrame { lo_base, hi_base, extent: e } = NodeFrame::new(node, margin);
    let quantized = [
        (&node.child_min_x, &node.child_max_x),
        (&node.child_min_y, &node.child_max_y),
        (&node.child_min_z, &node.child_max_z),
    ];
    let mut hits = 0u32;
    for half in 0..2 {
        let mut span = Span4::new(tmin, tmax);
        for (axis, (q_min, q_max)) in quantized.iter().enumerate() {
            let lo = F4::from_u8(q_min, half * 4).mul_add(e[axis], lo_base[axis]);
            let hi = F4::from_u8(q_max, half * 4).mul_add(e[axis], hi_base[axis]);
            if ray.moves[axis] {
                let (o, inv) = (ray.origin[axis], ray.inv_dir[axis]);
                let t0 = lo.sub_scalar(o).mul_scalar(inv);
                let t1 = hi.sub_scalar(o).mul_scalar(inv);
                span.clip(t0.min(t1), t0.max(t1));
            } else {
                span.keep_if_between(lo, hi, ray.origin[axis]);
            }
        }
        hits |= span.hit_bits() << (half * 4);
    }
    let (child_bits8, bit_index8) = node.get_child_and_index_bits(ray.oct_inv4);
    let mut hit_mask = 0;
    for c in 0..8 {
        if hits & (1 << c) != 0 && node.child_meta[c] != 0 {
            hit_mask |= extract_byte64(child_bits8, c) << extract_byte64(bit_index8, c);
        }
    }
    hit_mask
}

/// What the node test needs of a ray.
pub(crate) struct NodeRay {
    origin: Vec3A,
    inv_dir: Vec3A,
    /// Whether the ray moves along each axis (a zero component has no slab distances).
    moves: [bool; 3],
    /// The child order for the ray's direction.
    pub(super) oct_inv4: u32,
    /// Per axis, the byte offsets in a node of the quantized planes the ray enters and leaves
    /// a child's slab by: the minimum plane first where the ray moves towards +, else the maximum.
    near_offset: [usize; 3],
    far_offset: [usize; 3],
}

/// Byte offset of `child_min_x` in a `CwBvhNode`; then `child_max_x`, `child_min_y`, … 8 bytes apart.
const PLANES_OFFSET: usize = std::mem::offset_of!(CwBvhNode, child_min_x);

impl NodeRay {
    pub(crate) fn new(origin: Vec3A, direction: Vec3A) -> Self {
        let negative = direction.to_array().map(|d| d < 0.0);
        let plane = |axis: usize, max: bool| PLANES_OFFSET + 16 * axis + 8 * max as usize;
        NodeRay {
            origin,
            inv_dir: Vec3A::ONE / direction,
            // A component so small that its reciprocal overflows counts as no motion.
            moves: (Vec3A::ONE / direction).is_finite_mask().into(),
            oct_inv4: octant_inv4(direction),
            near_offset: std::array::from_fn(|axis| plane(axis, negative[axis])),
            far_offset: std::array::from_fn(|axis| plane(axis, !negative[axis])),
        }
    }

    /// Whether the ray moves along every axis: the 8-lane test handles no other.
    pub(crate) fn all_axes_move(&self) -> bool {
        self.moves.iter().all(|&m| m)
    }
}

/// A node's quantization frame: per axis the bases of its children's minimum and maximum planes
/// (the node's origin moved out by the rounding of dequantization, and by `margin`), and the
/// step of one quantization unit.
struct NodeFrame {
    lo_base: [f32; 3],
    hi_base: [f32; 3],
    extent: [f32; 3],
}

impl NodeFrame {
    #[inline(always)]
    fn new(node: &CwBvhNode, margin: f32) -> Self {
        let p = Vec3A::from(node.p);
        let e = node.compute_extent();
        let widen = (p.abs() + e * 255.0) * (4.0 * f32::EPSILON) + Vec3A::splat(margin);
        NodeFrame { lo_base: (p - widen).to_array(), hi_base: (p + widen).to_array(), extent: e.to_array() }
    }
}

/// The node test the walks use on this machine, in words (`reference --timing` prints it).
pub fn node_test_name() -> &'static str {
    #[cfg(target_arch = "x86_64")]
    if wide_available() {
        return "8 children at a time (AVX2, FMA)";
    }
    "4 children at a time (portable)"
}

/// Whether the 8-lane test may run: the processor has AVX2 and FMA, and
/// `SHADOWTRUTH_NODE_TEST` is not `portable` (which keeps the portable form, for comparing the
/// two). Decided once per process.
#[cfg(target_arch = "x86_64")]
pub(super) fn wide_available() -> bool {
    static WIDE: std::sync::OnceLock<bool> = std::sync::OnceLock::new();
    *WIDE.get_or_init(|| {
        let forced_portable = std::env::var("SHADOWTRUTH_NODE_TEST").is_ok_and(|v| v == "portable");
        !forced_portable && is_x86_feature_detected!("avx2") && is_x86_feature_detected!("fma")
    })
}

/// `intersect_node` for a ray that moves along every axis, eight children at a time. Callable
/// only where AVX2 and FMA are enabled (`wide_available`).
#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx2,fma")]
#[inline]
pub(super) fn intersect_node_wide(node: &CwBvhNode, ray: &NodeRay, tmin: f32, tmax: f32, margin: f32) -> u32 {
    use std::arch::x86_64::*;
    let NodeFrame { lo_base, hi_base, extent } = NodeFrame::new(node, margin);
    let bytes = node as *const CwBvhNode as *const u8;
    // The eight quantized planes at `offset`, as f32.
    let planes = |offset: usize| {
        // SAFETY: `offset` is that of one of the node's six 8-byte plane arrays.
        let eight = unsafe { _mm_loadl_epi64(bytes.add(offset) as *const __m128i) };
        _mm256_cvtepi32_ps(_mm256_cvtepu8_epi32(eight))
    };
    let grow = |x: __m256, k: f32| {
        let abs = _mm256_andnot_ps(_mm256_set1_ps(-0.0), x);
        _mm256_add_ps(x, _mm256_mul_ps(abs, _mm256_set1_ps(k)))
    };
    let slack = 4.0 * f32::EPSILON;
    let (mut enter, mut exit) = (_mm256_set1_ps(tmin), _mm256_set1_ps(tmax));
    for axis in 0..3 {
        let negative = ray.inv_dir[axis] < 0.0;
        let (near_base, far_base) =
            if negative { (hi_base[axis], lo_base[axis]) } else { (lo_base[axis], hi_base[axis]) };
        let e = _mm256_set1_ps(extent[axis]);
        let (o, inv) = (_mm256_set1_ps(ray.origin[axis]), _mm256_set1_ps(ray.inv_dir[axis]));
        let near_plane = _mm256_fmadd_ps(planes(ray.near_offset[axis]), e, _mm256_set1_ps(near_base));
        let far_plane = _mm256_fmadd_ps(planes(ray.far_offset[axis]), e, _mm256_set1_ps(far_base));
        let near = _mm256_mul_ps(_mm256_sub_ps(near_plane, o), inv);
        let far = _mm256_mul_ps(_mm256_sub_ps(far_plane, o), inv);
        enter = _mm256_max_ps(enter, grow(near, -slack));
        exit = _mm256_min_ps(exit, grow(far, slack));
    }
    let hits = _mm256_movemask_ps(_mm256_cmp_ps::<_CMP_LE_OQ>(enter, exit)) as u32;
    // SAFETY: `child_meta` is 8 bytes.
    let meta = unsafe { _mm_loadl_epi64(node.child_meta.as_ptr() as *const __m128i) };
    let empty = _mm_movemask_epi8(_mm_cmpeq_epi8(meta, _mm_setzero_si128())) as u32 & 0xff;
    let (child_bits8, bit_index8) = node.get_child_and_index_bits(ray.oct_inv4);
    let mut live = hits & !empty;
    let mut hit_mask = 0;
    while live != 0 {
        let c = live.trailing_zeros() as usize;
        live &= live - 1;
        hit_mask |= extract_byte64(child_bits8, c) << extract_byte64(bit_index8, c);
    }
    hit_mask
}
