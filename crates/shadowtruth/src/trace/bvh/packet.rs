//! Rays walked down the tree together, one per lane of a vector (lane_vector.rs): eight with
//! AVX2, sixteen with AVX-512. Neighbouring pixels' primary rays, or their shadow rays towards a
//! light (parallel towards a directional one, so as coherent as rays get). Every function here
//! is `#[inline(always)]` and runs inside `packet_isa::in_packet_isa`, which compiles it for AVX2
//! or for AVX-512, whichever the processor has and the width needs.
//!
//! A packet visits a node when any of its rays may meet it, so one walk's branches and node
//! loads serve every ray. The answers are those of single-ray walks (bvh.rs), bit for bit:
//! - the node test is conservative per lane, as the single-ray test is (node_test.rs): each ray
//!   reaches every node that the exact ray meets, and so every triangle it may hit (and perhaps
//!   more, where another ray of the packet leads there);
//! - at a leaf, a vectorised copy of the watertight test's first steps (the shear and the edge
//!   functions, operation for operation as `WatertightRay::shear`) rejects only the rays whose
//!   edge functions are all non-zero and of mixed signs, which the scalar test rejects too;
//!   a closest-hit walk then finishes the test for every lane at once, operation for
//!   operation as `WatertightRay::intersect` (`Packet::intersect`), and leaves to the scalar
//!   test only the lanes with an edge function exactly zero, which it settles in f64; a shadow
//!   ray or a certificate gets its own scalar test (`leaf`), which decides, except where a
//!   shadow packet finds a lane certainly hitting, by the scalar test's own bounds on the same
//!   numbers (`Packet::certify_hits`);
//! - the closest hit is the least (distance, scene id) over every triangle reached, and the
//!   any-hit answer whether one occludes, neither of which depends on the order of the visits.
//!
//! Rays join a packet only when they share their direction's signs and the watertight test's
//! axis order, and move along every axis (`Packet::new`); otherwise they are walked one by one.
//! tests/node_test_forms.rs compares every reference traced this way with the portable form,
//! which walks single rays.

#![cfg(target_arch = "x86_64")]

use super::lane_vector::{L8, LaneMask, LaneVector};
use super::node_test::{SLACK, plane_offsets};
use super::watertight::{RayTriangleHit, WatertightRay};
use super::wide_bvh::{ChildRef, WideNode};
use glam::{Vec3, Vec3A};
use std::arch::x86_64::*;

/// Rays in a packet of eight (`L8`), the width on every processor with AVX2.
pub(in crate::trace) const LANES: usize = L8::LANES;

/// A packet's rays as the walk needs them, lane by lane.
pub(in crate::trace) struct Packet<V: LaneVector = L8> {
    origin: [V; 3],
    inv_near: [V; 3],
    inv_far: [V; 3],
    /// origin · inv_near rounded up, and origin · inv_far rounded down, per axis: the node test
    /// takes a slab distance as plane · inv − these, rounded once (`lane_test`).
    origin_near: [V; 3],
    origin_far: [V; 3],
    near_offset: [usize; 3],
    far_offset: [usize; 3],
    /// The watertight test's axis order, shared by every ray.
    axes: [usize; 3],
    /// Its shear factors, lane by lane.
    shear: [V; 2],
    /// Its scale of the main axis (1/d along it), lane by lane.
    scale: V,
    /// Lanes that hold a ray (the others repeat the last).
    pub(in crate::trace) lanes: u32,
    /// The rays' octant as the tree places children in slots (`order_children` in
    /// cwbvh_convert.rs): bit 2, 1, 0 set where the rays move down x, y, z. Slot `octant` holds
    /// the child a ray meets first, slot `octant ^ 7` the one it meets last.
    octant: usize,
    /// For shadow rays (`certify`), lane by lane, the certified test's bound on the sheared
    /// coordinates' error as (fixed, per unit of reach): a lane is then rejected only where two
    /// edge functions have opposite signs beyond their bound (certified.rs).
    slack: Option<[V; 2]>,
    /// For shadow rays (`certify_hits`), lane by lane, the certified test's bound on the
    /// vertices' distances along the ray as (fixed, per unit of reach), and the least length of
    /// the exact segment rounded down: a lane whose edge functions all share a sign beyond their
    /// bound, and whose triangle lies wholly within its segment beyond that bound, certainly hits.
    segment: Option<[V; 3]>,
    /// Bounds of every lane's slab distances, eight children at a time (`Frustum`), where the
    /// rays share an origin.
    frustum: Option<Frustum>,
}

/// What bounds the slab distances of all of a packet's rays at once, per axis: the lanes'
/// extreme origins and the extremes of their shrunk and grown reciprocals. A lane computes
/// fl(fl(plane − o)·inv); both roundings are monotone, so over o and inv in those ranges the
/// value is bounded by its value at a corner. Entry distances take the lowest corner, exit
/// distances the highest: a child that some lane's own test keeps is kept here too. The test
/// runs over a node's eight children (not over lanes), so each value is in every one of eight
/// lanes, for the test to read it as an operand.
struct Frustum {
    /// The origin that gives the lowest entry distance (the largest where the ray moves up the
    /// axis, the smallest where it moves down).
    near_origin: [__m256; 3],
    /// The origin that gives the highest exit distance.
    far_origin: [__m256; 3],
    /// Smallest and largest shrunk reciprocal.
    inv_near: [[__m256; 2]; 3],
    /// Smallest and largest grown reciprocal.
    inv_far: [[__m256; 2]; 3],
}

impl Frustum {
    /// The frustum of lanes whose origins span `origin_extremes` ([least, greatest] per axis).
    #[inline(always)]
    unsafe fn new<V: LaneVector>(
        origin_extremes: [[f32; 2]; 3],
        inv_near: &[V; 3],
        inv_far: &[V; 3],
        negative: [bool; 3],
    ) -> Self {
        // SAFETY: the caller runs where the processor has AVX2, in code compiled for it.
        unsafe {
            // Plain loops: `array::map` is not compiled with AVX2, so its closure would call
            // `extremes` instead of inlining it.
            let zero = _mm256_setzero_ps();
            let mut f = Frustum {
                near_origin: [zero; 3],
                far_origin: [zero; 3],
                inv_near: [[zero; 2]; 3],
                inv_far: [[zero; 2]; 3],
            };
            let splat = |[lo, hi]: [f32; 2]| [_mm256_set1_ps(lo), _mm256_set1_ps(hi)];
            for axis in 0..3 {
                let origin = splat(origin_extremes[axis]);
                f.near_origin[axis] = origin[!negative[axis] as usize];
                f.far_origin[axis] = origin[negative[axis] as usize];
                f.inv_near[axis] = splat(inv_near[axis].extremes());
                f.inv_far[axis] = splat(inv_far[axis].extremes());
            }
            f
        }
    }
}

/// A packet's rays component by component, lane by lane (lanes past the last ray repeat it).
struct Lanes<V: LaneVector> {
    origin: [V; 3],
    direction: [V; 3],
    shear: [V; 2],
    scale: V,
}

impl<V: LaneVector> Lanes<V> {
    /// The lanes of `rays` (one to `V::LANES`), or `None` where they do not share the watertight
    /// test's axis order. Where they share their direction too (shadow rays towards a
    /// directional light), its components, shear and scale are broadcast from the first ray:
    /// the same numbers, without gathering them lane by lane (shadow rays ran 1.045× as fast:
    /// docs/scale.md).
    ///
    /// # Safety
    /// The processor has `V`'s instruction set, and the caller is compiled for it.
    #[inline(always)]
    unsafe fn of(rays: &[WatertightRay]) -> Option<Lanes<V>> {
        let first = rays.first()?;
        if rays.len() > V::LANES {
            return None;
        }
        let bits = |v: Vec3A| v.to_array().map(f32::to_bits);
        let mut origin: [V::Array; 3] = Default::default();
        let (mut same_axes, mut same_direction) = (true, true);
        for k in 0..V::LANES {
            let ray = &rays[k.min(rays.len() - 1)];
            same_axes &= (ray.kx, ray.ky, ray.kz) == (first.kx, first.ky, first.kz);
            same_direction &= bits(ray.direction) == bits(first.direction);
            let o = ray.origin.to_array();
            for axis in 0..3 {
                origin[axis].as_mut()[k] = o[axis];
            }
        }
        if !same_axes {
            return None;
        }
        // SAFETY: the caller's.
        unsafe {
            let origin = [V::load(&origin[0]), V::load(&origin[1]), V::load(&origin[2])];
            if same_direction {
                let d = first.direction.to_array();
                return Some(Lanes {
                    origin,
                    direction: [V::splat(d[0]), V::splat(d[1]), V::splat(d[2])],
                    shear: [V::splat(first.sx), V::splat(first.sy)],
                    scale: V::splat(first.sz),
                });
            }
            let (mut direction, mut shear, mut scale): ([V::Array; 3], [V::Array; 2], V::Array) =
                Default::default();
            for k in 0..V::LANES {
                let ray = &rays[k.min(rays.len() - 1)];
                let d = ray.direction.to_array();
                for axis in 0..3 {
                    direction[axis].as_mut()[k] = d[axis];
                }
                shear[0].as_mut()[k] = ray.sx;
                shear[1].as_mut()[k] = ray.sy;
                scale.as_mut()[k] = ray.sz;
            }
            Some(Lanes {
                origin,
                direction: [V::load(&direction[0]), V::load(&direction[1]), V::load(&direction[2])],
                shear: [V::load(&shear[0]), V::load(&shear[1])],
                scale: V::load(&scale),
            })
        }
    }
}

/// A bound's coefficient `v` in f32, rounded up with room for the f32 evaluation of the bound
/// (a factor 1 + 2⁻¹⁰).
#[inline(always)]
fn round_up(v: f64) -> f32 {
    (v * (1.0 + 2f64.powi(-10))) as f32
}

/// |v|·2⁻²² + 2⁻¹⁴⁹, lane by lane: at least two units in the last place of v (and the least
/// subnormal where v is zero), so that v plus it, rounded, is at least every number that rounds
/// to v, and v minus it at most every such number.
#[inline(always)]
unsafe fn two_ulps<V: LaneVector>(v: V) -> V {
    // SAFETY: the caller's: the processor has `V`'s instruction set.
    unsafe { v.abs().mul(V::splat(2f32.powi(-22))).add(V::splat(f32::from_bits(1))) }
}

impl<V: LaneVector> Packet<V> {
    /// The packet of `rays` (one to `V::LANES`), or `None` if they cannot share a walk. Each
    /// lane's reciprocals are those `NodeRay::new` computes for its ray (the same operations, a
    /// vector at a time); lanes past the last ray repeat it.
    ///
    /// # Safety
    /// The processor has `V`'s instruction set, and the caller is compiled for it.
    #[inline(always)]
    pub(in crate::trace) unsafe fn new(rays: &[WatertightRay]) -> Option<Self> {
        // SAFETY: the caller's.
        unsafe {
            let lanes = Lanes::<V>::of(rays)?;
            let first = &rays[0];
            // Plain arrays, not `array::map`, whose closures are not compiled for `V`'s set.
            let [dx, dy, dz] = lanes.direction;
            let one = V::splat(1.0);
            let inv = [one.div(dx), one.div(dy), one.div(dz)];
            // Rays from one point (a camera's) only: rays from scattered points (the shadow rays
            // of neighbouring pixels) can start far apart across a silhouette, and a frustum
            // around them keeps far more than any lane meets.
            let one_origin = rays.iter().all(|r| r.origin == first.origin);
            let [ox, oy, oz] = lanes.origin;
            let origin_extremes = one_origin.then(|| [ox.extremes(), oy.extremes(), oz.extremes()]);
            Self::of_lanes(lanes, inv, [first.kx, first.ky, first.kz], rays.len(), origin_extremes)
        }
    }

    /// The packet of the rays from `origin` along `directions` (two to `V::LANES`, lanes past
    /// the last repeating it), with each lane's watertight ray written to `watertight`: what
    /// `WatertightRay::new` and `Packet::new` make of them, computed a vector at a time (making
    /// the sixteen rays one by one, then gathering them back into lanes, took a fifth of a
    /// primary packet's time: docs/scale.md). `None` where they cannot share a walk.
    ///
    /// # Safety
    /// The processor has `V`'s instruction set, and the caller is compiled for it.
    #[inline(always)]
    pub(in crate::trace) unsafe fn from_origin<const N: usize>(
        origin: Vec3,
        directions: &[Vec3],
        watertight: &mut [WatertightRay; N],
    ) -> Option<Self> {
        assert!(N == V::LANES && (1..=N).contains(&directions.len()));
        let last = directions.len() - 1;
        let mut d: [V::Array; 3] = Default::default();
        for k in 0..N {
            let direction = directions[k.min(last)];
            for axis in 0..3 {
                d[axis].as_mut()[k] = direction[axis];
            }
        }
        // SAFETY: the caller's.
        // Plain arrays, not `array::map`, whose closures are not compiled for `V`'s set.
        let (direction, zero, one) =
            unsafe { ([V::load(&d[0]), V::load(&d[1]), V::load(&d[2])], V::splat(0.0), V::splat(1.0)) };
        // `WatertightRay::new`'s axis order, lane by lane: the main axis is x where |x| beats
        // both others, else y where |y| beats |z|, else z; every lane must choose alike.
        let [ax, ay, az] = [direction[0].abs(), direction[1].abs(), direction[2].abs()];
        let x_beats_y = ax.gt(ay).bits();
        let main_x = x_beats_y & ax.gt(az).bits();
        let main_y = !x_beats_y & ay.gt(az).bits() & V::ALL;
        let kz = match (main_x, main_y) {
            (0, 0) => 2,
            (x, 0) if x == V::ALL => 0,
            (0, y) if y == V::ALL => 1,
            _ => return None,
        };
        let below = direction[kz].lt(zero).bits();
        if below != 0 && below != V::ALL {
            return None;
        }
        let (mut kx, mut ky) = ((kz + 1) % 3, (kz + 2) % 3);
        // Keep the winding of the projected triangle independent of the ray's octant.
        if below != 0 {
            std::mem::swap(&mut kx, &mut ky);
        }
        let inv = [one.div(direction[0]), one.div(direction[1]), one.div(direction[2])];
        // `WatertightRay::new`'s sz = 1/d[kz], the same division, and its shear.
        let (scale, shear) = (inv[kz], [direction[kx].mul(inv[kz]), direction[ky].mul(inv[kz])]);
        let (mut sx, mut sy, mut sz) = Default::default();
        shear[0].store(&mut sx);
        shear[1].store(&mut sy);
        scale.store(&mut sz);
        for (k, ray) in watertight.iter_mut().enumerate() {
            *ray = WatertightRay {
                origin: origin.into(),
                direction: directions[k.min(last)].into(),
                kx,
                ky,
                kz,
                sx: V::Array::as_ref(&sx)[k],
                sy: V::Array::as_ref(&sy)[k],
                sz: V::Array::as_ref(&sz)[k],
            };
        }
        // SAFETY: the caller's.
        let o = unsafe { [V::splat(origin.x), V::splat(origin.y), V::splat(origin.z)] };
        let lanes = Lanes { origin: o, direction, shear, scale };
        let extremes = [[origin.x; 2], [origin.y; 2], [origin.z; 2]];
        // SAFETY: the caller's.
        unsafe { Self::of_lanes(lanes, inv, [kx, ky, kz], directions.len(), Some(extremes)) }
    }

    /// The packet of `count` rays whose lanes are `lanes`, with `inv` the reciprocals of their
    /// directions and `axes` their watertight axis order; with a frustum where they share an
    /// origin, whose extremes per axis are then `origin_extremes` (`Frustum`).
    ///
    /// # Safety
    /// The processor has `V`'s instruction set, and the caller is compiled for it.
    #[inline(always)]
    unsafe fn of_lanes(
        lanes: Lanes<V>,
        inv: [V; 3],
        axes: [usize; 3],
        count: usize,
        origin_extremes: Option<[[f32; 2]; 3]>,
    ) -> Option<Self> {
        // SAFETY: the caller's.
        unsafe {
            let (zero, inf) = (V::splat(0.0), V::splat(f32::INFINITY));
            let (mut inv_near, mut inv_far, mut negative) = ([zero; 3], [zero; 3], [false; 3]);
            for axis in 0..3 {
                let d = lanes.direction[axis];
                inv_near[axis] = inv[axis].mul(V::splat(1.0 - SLACK));
                inv_far[axis] = inv[axis].mul(V::splat(1.0 + SLACK));
                let below = d.lt(zero).bits();
                let finite = inv_far[axis].abs().lt(inf).bits();
                // Every lane moves along the axis, and in the same direction.
                if finite != V::ALL || (below != 0 && below != V::ALL) {
                    return None;
                }
                negative[axis] = below == V::ALL;
            }
            let (near_offset, far_offset) = plane_offsets(negative);
            let origin = lanes.origin;
            let (mut origin_near, mut origin_far) = ([zero; 3], [zero; 3]);
            for axis in 0..3 {
                let (near, far) = (origin[axis].mul(inv_near[axis]), origin[axis].mul(inv_far[axis]));
                origin_near[axis] = near.add(two_ulps(near));
                origin_far[axis] = far.sub(two_ulps(far));
                // Beyond f32 the bound would not hold: such rays walk one by one.
                if origin_near[axis].abs().lt(inf).and(origin_far[axis].abs().lt(inf)).bits() != V::ALL {
                    return None;
                }
            }
            let frustum =
                origin_extremes.map(|extremes| Frustum::new(extremes, &inv_near, &inv_far, negative));
            Some(Packet {
                origin,
                inv_near,
                inv_far,
                origin_near,
                origin_far,
                near_offset,
                far_offset,
                axes,
                shear: lanes.shear,
                scale: lanes.scale,
                lanes: (1u32 << count) - 1,
                octant: (negative[0] as usize) << 2 | (negative[1] as usize) << 1 | negative[2] as usize,
                slack: None,
                segment: None,
                frustum,
            })
        }
    }

    /// Makes the leaf rejection that of the certified shadow test, with each lane's
    /// (fixed, per unit of reach) coefficients of the sheared coordinates' error bound (one per
    /// lane). They are rounded to f32 upwards (a factor 1 + 2⁻¹⁰ covers that and the f32
    /// evaluation of the bound in `candidates`).
    #[inline(always)]
    pub(in crate::trace) fn certify(&mut self, coefficients: &[(f64, f64)]) {
        let (mut fixed, mut per_reach) = (V::Array::default(), V::Array::default());
        for (k, &(f, r)) in coefficients.iter().enumerate().take(V::LANES) {
            fixed.as_mut()[k] = round_up(f);
            per_reach.as_mut()[k] = round_up(r);
        }
        // SAFETY: a `Packet<V>` exists only where the processor has `V`'s set (`Packet::new`).
        self.slack = Some(unsafe { [V::load(&fixed), V::load(&per_reach)] });
    }

    /// Makes the leaf test also find the lanes that certainly hit, as the certified shadow test
    /// would (`CertifiedRay::classify`), from each lane's (fixed, per unit of reach)
    /// coefficients of its distances' error bound and its segment's least length (`certify` must
    /// have set the edge functions' bound). The coefficients are rounded up as `certify` rounds
    /// them, the length down and one f32 step further.
    #[inline(always)]
    pub(in crate::trace) fn certify_hits(&mut self, bounds: &[(f64, f64, f64)]) {
        let down = |v: f64| if v.is_finite() { (v as f32).next_down() } else { v as f32 };
        let (mut fixed, mut per_reach, mut least) = Default::default();
        for (k, &(f, r, length)) in bounds.iter().enumerate().take(V::LANES) {
            V::Array::as_mut(&mut fixed)[k] = round_up(f);
            V::Array::as_mut(&mut per_reach)[k] = round_up(r);
            V::Array::as_mut(&mut least)[k] = down(length);
        }
        // SAFETY: a `Packet<V>` exists only where the processor has `V`'s set (`Packet::new`).
        self.segment = Some(unsafe { [V::load(&fixed), V::load(&per_reach), V::load(&least)] });
    }

    /// Pushes the children of `node` that some lane of `lanes` may meet within [0, tmax[lane]]
    /// onto `stack[..*depth]`, and pops the one to visit next (`None` when no child is met).
    ///
    /// Inner children are kept when the packet's frustum meets them (`Frustum`), with all of
    /// `lanes`: one test of eight boxes for the whole packet. A leaf child kept so is tested
    /// lane by lane (`lane_test`). Both tests are conservative for each lane's exact ray (the
    /// frustum bounds the single-ray test's distances, which are), so a lane reaches every leaf
    /// its ray meets. The frustum's exit is the largest tmax of `lanes`, kept in `reach` while
    /// they walk (`Reach`). Nearest first, children are sorted by the frustum's entry distance;
    /// otherwise they go in node order. Every slot is tested: an empty one's inverted box is
    /// missed.
    #[inline(always)]
    fn push_children<const NEAREST: bool>(
        &self,
        node: &WideNode,
        tmax: &V::Array,
        lanes: u32,
        reach: &mut Reach,
        stack: &mut [(ChildRef, u32, f32)],
        depth: &mut usize,
    ) -> Option<(ChildRef, u32)> {
        let Some(f) = &self.frustum else {
            return self.push_children_lane_by_lane::<NEAREST>(node, tmax, lanes, stack, depth);
        };
        // SAFETY: a `Packet<V>` exists only where the processor has `V`'s set (`Packet::new`),
        // which includes AVX2, and its walk is compiled for it (`packet_isa.rs`).
        unsafe {
            let bytes = node as *const WideNode as *const u8;
            // SAFETY: `offset` is that of one of the node's plane arrays (`plane_offsets`).
            let planes = |offset: usize| _mm256_loadu_ps(bytes.add(offset) as *const f32);
            let tmax_lanes = V::load(tmax);
            // The largest tmax of the lanes walking: the others count as −∞.
            if reach.lanes != lanes {
                let walking = V::Mask::from_bits(lanes);
                let [_, largest] = tmax_lanes.select(walking, V::splat(f32::NEG_INFINITY)).extremes();
                *reach = Reach { lanes, tmax: largest };
            }
            let (mut enter, mut exit) = (_mm256_setzero_ps(), _mm256_set1_ps(reach.tmax));
            for axis in 0..3 {
                let near = _mm256_sub_ps(planes(self.near_offset[axis]), f.near_origin[axis]);
                let [lo, hi] = f.inv_near[axis];
                enter = _mm256_max_ps(enter, _mm256_min_ps(_mm256_mul_ps(near, lo), _mm256_mul_ps(near, hi)));
                let far = _mm256_sub_ps(planes(self.far_offset[axis]), f.far_origin[axis]);
                let [lo, hi] = f.inv_far[axis];
                exit = _mm256_min_ps(exit, _mm256_max_ps(_mm256_mul_ps(far, lo), _mm256_mul_ps(far, hi)));
            }
            let mut met = _mm256_movemask_ps(_mm256_cmp_ps::<_CMP_LE_OQ>(enter, exit)) as u32;
            let mut keys = [0.0f32; 8];
            if NEAREST {
                // SAFETY: eight f32.
                _mm256_storeu_ps(keys.as_mut_ptr(), enter);
            }
            let base = *depth;
            let mut top = base;
            // Room for eight more: a node at level L (root 1) finds at most 7·(L − 1) entries
            // beneath it, and the stack holds 7·depth + 1 (`SceneBvh::scratch`).
            assert!(stack.len() >= base + 8, "the packet stack is sized to the tree");
            while met != 0 {
                let c = met.trailing_zeros() as usize;
                met &= met - 1;
                let child = node.child[c];
                let hit = if child.is_leaf() { self.lane_test(node, c, tmax_lanes).0 & lanes } else { lanes };
                // SAFETY: top < base + 8 ≤ stack.len() (asserted above).
                *stack.get_unchecked_mut(top) = (child, hit, keys[c]);
                top += (hit != 0) as usize;
            }
            *depth = top;
            pop_next::<NEAREST>(stack, base, depth)
        }
    }

    /// Pushes the children of `node` that some lane of `lanes` may meet within [0, tmax[lane]]
    /// onto `stack[..*depth]`, each with those lanes, and pops the one to visit next (`None`
    /// when no child is met). Nearest first, the children are sorted by the distance at which
    /// the lowest lane enters them, so the nearest is next; otherwise the child the rays meet
    /// last goes first (`octant`).
    /// Every slot is tested: an empty one's inverted box is missed (testing it costs less than
    /// skipping it).
    #[inline(always)]
    fn push_children_lane_by_lane<const NEAREST: bool>(
        &self,
        node: &WideNode,
        tmax: &V::Array,
        lanes: u32,
        stack: &mut [(ChildRef, u32, f32)],
        depth: &mut usize,
    ) -> Option<(ChildRef, u32)> {
        // SAFETY: a `Packet<V>` exists only where the processor has `V`'s set (`Packet::new`).
        let tmax = unsafe { V::load(tmax) };
        let lowest = lanes.trailing_zeros() as usize;
        let base = *depth;
        let mut top = base;
        // Room for eight more: a node at level L (root 1) finds at most 7·(L − 1) entries
        // beneath it, and the stack holds 7·depth + 1 (`SceneBvh::scratch`).
        assert!(stack.len() >= base + 8, "the packet stack is sized to the tree");
        for i in 0..8 {
            // In any order, slot i ^ octant: the child the rays meet last is pushed last, so
            // visited first. Towards a light, that is the child nearest the light, where
            // occluders lie more often than beside the surface the rays leave: shadow rays
            // ran 1.04× as fast as in slot order (docs/scale.md). The answers do not depend
            // on the order.
            let c = if NEAREST { i } else { i ^ self.octant };
            let (met, enter) = self.lane_test(node, c, tmax);
            let hit = met & lanes;
            let key = if NEAREST { enter.lane(lowest) } else { 0.0 };
            // Written whether met or not, kept only if met: no branch on a coin toss.
            // SAFETY: top < base + 8 ≤ stack.len() (asserted above).
            unsafe { *stack.get_unchecked_mut(top) = (node.child[c], hit, key) };
            top += (hit != 0) as usize;
        }
        *depth = top;
        pop_next::<NEAREST>(stack, base, depth)
    }

    /// The lanes whose own node test meets child `slot` of `node` within [0, tmax[lane]]
    /// (`lane_test`).
    #[inline(always)]
    pub(in crate::trace) fn lanes_meeting(&self, node: &WideNode, slot: usize, tmax: &V::Array) -> u32 {
        // SAFETY: a `Packet<V>` exists only where the processor has `V`'s set (`Packet::new`).
        self.lane_test(node, slot, unsafe { V::load(tmax) }).0
    }

    /// The lanes whose node test meets child `c` of `node` within [0, tmax[lane]], and each
    /// lane's entry distance. Along each axis a slab distance is plane · inv − origin · inv,
    /// one fused rounding (`mul_sub`) instead of the single-ray test's two (a subtraction, then
    /// a product), with origin · inv rounded outwards by two ulps (`origin_near`,
    /// `origin_far`). It is as conservative: the rounded product moves a distance by less than
    /// that margin, and `SLACK` in the reciprocals covers their rounding and the fused one
    /// (node_test.rs), so an entry is never later than the exact one nor an exit earlier. The
    /// margin costs each box about one ulp of the origin's coordinate; the fused form saves an
    /// operation per plane.
    #[inline(always)]
    fn lane_test(&self, node: &WideNode, c: usize, tmax: V) -> (u32, V) {
        let bytes = node as *const WideNode as *const u8;
        // SAFETY: `offset` is that of one of the node's plane arrays (`plane_offsets`), and
        // c < 8; a `Packet<V>` exists only where the processor has `V`'s set.
        let plane = |offset: usize| unsafe { V::splat(*(bytes.add(offset) as *const f32).add(c)) };
        // SAFETY: as above.
        let (mut enter, mut exit) = (unsafe { V::splat(0.0) }, tmax);
        for axis in 0..3 {
            let t_near = plane(self.near_offset[axis]).mul_sub(self.inv_near[axis], self.origin_near[axis]);
            let t_far = plane(self.far_offset[axis]).mul_sub(self.inv_far[axis], self.origin_far[axis]);
            enter = enter.max(t_near);
            exit = exit.min(t_far);
        }
        (enter.le(exit).bits(), enter)
    }

    /// The lanes of `lanes` whose ray the watertight test might not reject for `triangle`: all
    /// but those whose three edge functions are non-zero and of mixed signs. And the triangle
    /// as each lane's test sees it (`LaneTriangle`), with the lanes that certainly hit it where
    /// the packet knows its segments (`certify_hits`).
    #[inline(always)]
    fn candidates(&self, triangle: &[Vec3; 3], lanes: u32) -> (u32, LaneTriangle<V>) {
        let ((ax, ay, az), (bx, by, bz), (cx, cy, cz)) =
            (self.sheared(&triangle[0]), self.sheared(&triangle[1]), self.sheared(&triangle[2]));
        let dz = [az, bz, cz];
        let edge = |px: V, py: V, qx: V, qy: V| px.mul(qy).sub(py.mul(qx));
        let e = [edge(cx, cy, bx, by), edge(ax, ay, cx, cy), edge(bx, by, ax, ay)];
        let mut seen = LaneTriangle { edges: e, z_unscaled: dz, certain: 0 };
        let signs = EdgeSigns::of(&e);
        let Some([fixed, per_reach]) = self.slack else {
            let [some_zero, some_negative, some_positive] =
                [signs.zero, signs.negative, signs.positive].map(LaneMask::bits);
            return (lanes & (some_zero | !(some_negative & some_positive)), seen);
        };
        // Only lanes whose edge functions have strictly mixed signs can be rejected, and only
        // those whose signs agree can certainly hit; the others go to the scalar test whatever
        // the bound.
        let mixed = signs.negative.and(signs.positive).bits() & lanes;
        let agree = match self.segment {
            Some(_) => lanes & !mixed & !signs.zero.bits(),
            None => 0,
        };
        if mixed == 0 && agree == 0 {
            return (lanes, seen);
        }
        // `CertifiedRay::classify`'s bound, lane by lane: reach is the largest |x|, |y| and
        // translated main-axis coordinate, σ = fixed + per_reach·reach, across the largest
        // |x| and |y|, and the edge functions' bound 2·(2σ(2·across + σ) + 4.01u·across²)
        // (u = 2⁻²⁴) and 4·2⁻¹⁴⁹ for underflow, which the factor 1 + 2⁻¹⁰ covers where reach
        // ≥ 2⁻⁴⁰ (σ ≥ 2⁻⁵⁹ there: see `sound`).
        // SAFETY: a `Packet<V>` exists only where the processor has `V`'s set (`Packet::new`).
        let splat = |x: f32| unsafe { V::splat(x) };
        let max3 = |a: V, b: V, c: V| a.abs().max(b.abs()).max(c.abs());
        let across = max3(ax, bx, cx).max(max3(ay, by, cy));
        let reach = across.max(max3(dz[0], dz[1], dz[2]));
        let sigma = fixed.add(per_reach.mul(reach));
        let two_across_sigma = across.add(across).add(sigma);
        let bound = splat(4.0)
            .mul(sigma.mul(two_across_sigma))
            .add(splat(8.02 * f32::EPSILON * 0.5).mul(across.mul(across)));
        let bound = bound.mul(splat(1.0 + 2f32.powi(-10)));
        let below = splat(0.0).sub(bound);
        let clear = |x: V| (x.lt(below), x.gt(bound));
        let ((n0, p0), (n1, p1), (n2, p2)) = (clear(e[0]), clear(e[1]), clear(e[2]));
        let clearly_mixed = n0.or(n1).or(n2).and(p0.or(p1).or(p2));
        // Below 2⁻⁴⁰ the f32 bound may underflow: such lanes go to the scalar test.
        let sound = reach.ge(splat(2f32.powi(-40)));
        if let (Some([z_fixed, z_per_reach, least_length]), true) = (self.segment, agree != 0) {
            // `CertifiedRay::crossing_near`'s certain hit, lane by lane: every edge function
            // beyond its bound with one sign, and every vertex's distance (scaled as
            // `intersect` scales it, so the scalar test's numbers) beyond its bound inside
            // the segment. The bound is evaluated as the edge functions' is (the factor covers
            // its rounding), and the sum below the length rounded down stays below the length.
            let clear = n0.and(n1).and(n2).or(p0.and(p1).and(p2));
            let z = [self.scale.mul(dz[0]), self.scale.mul(dz[1]), self.scale.mul(dz[2])];
            let (z_min, z_max) = (z[0].min(z[1]).min(z[2]), z[0].max(z[1]).max(z[2]));
            let z_error = z_fixed.add(z_per_reach.mul(reach)).mul(splat(1.0 + 2f32.powi(-10)));
            let inside = z_min.gt(z_error).and(z_max.add(z_error).lt(least_length));
            seen.certain = clear.and(inside).and(sound).bits() & agree;
        }
        (lanes & !clearly_mixed.and(sound).bits(), seen)
    }

    /// `WatertightRay::shear` of vertex `v`, lane by lane: translated to the lane's origin, then
    /// sheared; (x, y, the main axis's coordinate not yet scaled).
    #[inline(always)]
    fn sheared(&self, v: &Vec3) -> (V, V, V) {
        // Read where it lies, each coordinate broadcast from memory: a copy of the vertex
        // indexed by the axis order went through the stack.
        let ([kx, ky, kz], [sx, sy], v) = (self.axes, self.shear, v.as_ref());
        // SAFETY: a `Packet<V>` exists only where the processor has `V`'s set (`Packet::new`).
        let splat = |x: f32| unsafe { V::splat(x) };
        let (dx, dy, dz) = (
            splat(v[kx]).sub(self.origin[kx]),
            splat(v[ky]).sub(self.origin[ky]),
            splat(v[kz]).sub(self.origin[kz]),
        );
        (dx.sub(sx.mul(dz)), dy.sub(sy.mul(dz)), dz)
    }

    /// `WatertightRay::intersect` over [0, tmax] for each lane of `lanes`, with the triangle as
    /// `candidates` saw it: the same operations in the same order, lane by lane, so the same
    /// distances; the barycentrics are left as the edge functions and their sum, divided once a
    /// lane's closest hit is known (`BestHits::hits`). Lanes with an edge function exactly zero
    /// are left to the scalar test (`LaneHits::scalar`), which settles them in f64.
    #[inline(always)]
    pub(in crate::trace) fn intersect(
        &self,
        seen: &LaneTriangle<V>,
        lanes: u32,
        tmax: &V::Array,
    ) -> LaneHits<V> {
        // SAFETY: a `Packet<V>` exists only where the processor has `V`'s set (`Packet::new`).
        let (tmax, zero) = unsafe { (V::load(tmax), V::splat(0.0)) };
        let [u, v, w] = seen.edges;
        let signs = EdgeSigns::of(&seen.edges);
        let det = u.add(v).add(w);
        let [z0, z1, z2] = seen.z_unscaled;
        let z = [self.scale.mul(z0), self.scale.mul(z1), self.scale.mul(z2)];
        let t_scaled = u.mul(z[0]).add(v.mul(z[1])).add(w.mul(z[2]));
        let t = t_scaled.div(det);
        let within = t.ge(zero).and(t.le(tmax)).bits();
        let unsolved = signs.negative.and(signs.positive).or(det.eq(zero)).bits();
        let scalar = signs.zero.bits() & lanes;
        LaneHits { hit: within & !unsolved & lanes & !scalar, scalar, t, edges: seen.edges, det }
    }
}

/// A triangle as each lane's watertight test sees it: the edge functions and the vertices' main
/// axis coordinates, translated to the lane's origin and not yet scaled.
pub(in crate::trace) struct LaneTriangle<V: LaneVector = L8> {
    edges: [V; 3],
    z_unscaled: [V; 3],
    /// The lanes that certainly hit it (`Packet::certify_hits`).
    pub(in crate::trace) certain: u32,
}

/// Lane by lane, whether some of three edge functions is zero, negative, positive.
struct EdgeSigns<V: LaneVector> {
    zero: V::Mask,
    negative: V::Mask,
    positive: V::Mask,
}

impl<V: LaneVector> EdgeSigns<V> {
    #[inline(always)]
    fn of(e: &[V; 3]) -> EdgeSigns<V> {
        // SAFETY: the edge functions exist, so the processor has `V`'s set.
        let zero = unsafe { V::splat(0.0) };
        EdgeSigns {
            zero: e[0].eq(zero).or(e[1].eq(zero)).or(e[2].eq(zero)),
            negative: e[0].lt(zero).or(e[1].lt(zero)).or(e[2].lt(zero)),
            positive: e[0].gt(zero).or(e[1].gt(zero)).or(e[2].gt(zero)),
        }
    }
}

/// What `Packet::intersect` found: the lanes that hit, with their distances and their
/// barycentrics as the edge functions over their sum (`det`), and the lanes the scalar test must
/// settle.
pub(in crate::trace) struct LaneHits<V: LaneVector = L8> {
    pub(in crate::trace) hit: u32,
    pub(in crate::trace) scalar: u32,
    pub(in crate::trace) t: V,
    pub(in crate::trace) edges: [V; 3],
    pub(in crate::trace) det: V,
}

impl<V: LaneVector> LaneHits<V> {
    /// Makes lane `k` hit as the scalar test found: its barycentrics as edge functions over a
    /// sum of 1, which the division leaves as they are (b·(1/1) = b exactly).
    #[inline(always)]
    pub(in crate::trace) fn set_lane(&mut self, k: usize, hit: RayTriangleHit) {
        let set = |v: &mut V, x: f32| {
            let mut lanes = V::Array::default();
            v.store(&mut lanes);
            lanes.as_mut()[k] = x;
            // SAFETY: `v` exists, so the processor has `V`'s set.
            *v = unsafe { V::load(&lanes) };
        };
        set(&mut self.t, hit.t);
        for (edge, b) in self.edges.iter_mut().zip(hit.barycentric) {
            set(edge, b);
        }
        set(&mut self.det, 1.0);
        self.hit |= 1 << k;
    }
}

/// Calls `f(lane)` for each lane of `lanes`, lowest first, and returns those for which it said
/// the lane is finished.
#[inline(always)]
pub(in crate::trace) fn each_lane(mut lanes: u32, mut f: impl FnMut(usize) -> bool) -> u32 {
    let mut finished = 0;
    while lanes != 0 {
        let lane = lanes.trailing_zeros() as usize;
        lanes &= lanes - 1;
        finished |= (f(lane) as u32) << lane;
    }
    finished
}

/// The largest tmax of a packet's lanes `lanes` (none: 0), which the frustum test of a node
/// (`Packet::push_children`) takes as its exit: computed when the lanes walking change, not at
/// every node (a reduction across the lanes that every frustum test waited on: primary rays
/// ran 1.1× as fast without it, docs/scale.md). An inner child passes its parent's lanes on,
/// and a leaf's hits may shrink the lanes' tmax, after which it is computed again; so it is
/// always the very value a node's own reduction would give.
#[derive(Clone, Copy, Default)]
struct Reach {
    lanes: u32,
    tmax: f32,
}

/// Pops the entry to visit next of those pushed onto `stack[base..*depth]`; nearest first,
/// they are sorted farthest first (by their key) before, so that the nearest comes next.
#[inline(always)]
fn pop_next<const NEAREST: bool>(
    stack: &mut [(ChildRef, u32, f32)],
    base: usize,
    depth: &mut usize,
) -> Option<(ChildRef, u32)> {
    if NEAREST {
        // Insertion sort: a node has few met children.
        for i in base + 1..*depth {
            let entry = stack[i];
            let mut k = i;
            while k > base && stack[k - 1].2 < entry.2 {
                stack[k] = stack[k - 1];
                k -= 1;
            }
            stack[k] = entry;
        }
    }
    if *depth == base {
        return None;
    }
    *depth -= 1;
    Some((stack[*depth].0, stack[*depth].1))
}

/// Walks `nodes` with the packet, for the lanes in `*active`, and calls
/// `leaf(i, candidates, seen, tmax)` for each primitive `i` (in tree order) of the leaves it
/// reaches, with the lanes that may hit it (`triangles[i]` is its triangle, `seen` as they see
/// it), but those of `skipped(i)` (a shadow ray's own triangle). `leaf` may shrink `tmax[lane]`
/// (closest hits), and returns the lanes it finished (any hit), which leave `*active`. Nearest
/// first, children go in the order the lowest lane enters them.
#[inline(always)]
#[allow(clippy::too_many_arguments)]
pub(in crate::trace) fn walk_packet<V: LaneVector, const NEAREST: bool>(
    nodes: &[WideNode],
    triangles: &[[Vec3; 3]],
    stack: &mut [(ChildRef, u32, f32)],
    packet: &Packet<V>,
    active: &mut u32,
    tmax: &mut V::Array,
    skipped: impl Fn(usize) -> u32,
    mut leaf: impl FnMut(usize, u32, &LaneTriangle<V>, &mut V::Array) -> u32,
) {
    if nodes.is_empty() {
        return;
    }
    let mut depth = 0;
    let mut current = (ChildRef::ROOT, *active);
    let mut reach = Reach::default();
    loop {
        let (child, lanes) = (current.0, current.1 & *active);
        if lanes != 0 && child.is_leaf() {
            reach = Reach::default();
            for i in child.primitives() {
                // A triangle left to no lane is not looked at: the tiles' rays start on the same
                // triangle, whose leaf they all reach (docs/scale.md).
                let lanes = lanes & *active & !skipped(i);
                if lanes == 0 {
                    continue;
                }
                let (candidates, seen) = packet.candidates(&triangles[i], lanes);
                if candidates != 0 {
                    *active &= !leaf(i, candidates, &seen, tmax);
                }
            }
            if *active == 0 {
                return;
            }
        } else if lanes != 0 {
            let node = &nodes[child.index()];
            if let Some(next) =
                packet.push_children::<NEAREST>(node, tmax, lanes, &mut reach, stack, &mut depth)
            {
                current = next;
                continue;
            }
        }
        if depth == 0 {
            return;
        }
        depth -= 1;
        current = (stack[depth].0, stack[depth].1);
    }
}

#[cfg(test)]
mod tests {
    use super::{LANES, Packet};
    use crate::trace::bvh::hit::Hit;
    use crate::trace::bvh::lane_vector::{L8, L16, LaneVector};
    use crate::trace::bvh::packet_isa::{PacketQuery, packet_isa_for};
    use crate::trace::bvh::primary_certificate::PrimaryCertainty;
    use crate::trace::splitmix::SplitMix64;
    use crate::trace::{SceneBvh, ShadowRay, WatertightRay};
    use glam::{DVec3, Vec3, vec3};

    /// A soup of small triangles in a box, with a few large ones across it, so that rays meet
    /// many leaves and share edges.
    fn soup(rng: &mut SplitMix64) -> Vec<[Vec3; 3]> {
        let mut point = |s: f64| Vec3::from_array(std::array::from_fn(|_| rng.range([-s, s]) as f32));
        let mut tris: Vec<[Vec3; 3]> = (0..3000)
            .map(|_| {
                let c = point(4.0);
                [c, c + point(0.4), c + point(0.4)]
            })
            .collect();
        tris.push([vec3(-5.0, -1.0, -5.0), vec3(5.0, -1.0, -5.0), vec3(5.0, -1.0, 5.0)]);
        tris.push([vec3(-5.0, -1.0, -5.0), vec3(5.0, -1.0, 5.0), vec3(-5.0, -1.0, 5.0)]);
        tris
    }

    /// Rays through the shared vertices and edges of a grid, where edge functions are exactly
    /// zero and a packet's lanes go to the scalar test, get the single-ray closest hits bit for
    /// bit, and so do the lanes between them that the packet solves itself. The directions'
    /// main component is −8, so every shear is exact and the sheared vertices are exactly 0.
    #[test]
    fn rays_through_shared_edges_and_vertices_hit_as_single_rays() {
        if !super::super::node_test::wide_form_testable() {
            return;
        }
        let mut tris = Vec::new();
        for (i, j) in (0..8).flat_map(|i| (0..8).map(move |j| (i as f32, j as f32))) {
            let [a, b, c, d] =
                [vec3(i, j, 0.0), vec3(i + 1.0, j, 0.0), vec3(i + 1.0, j + 1.0, 0.0), vec3(i, j + 1.0, 0.0)];
            tris.extend([[a, b, c], [a, c, d]]);
        }
        let bvh = SceneBvh::build_from_triangles(&tris);
        let mut scratch = bvh.scratch();
        let origin = vec3(0.0, 0.0, 8.0);
        // Vertices, edge midpoints and the centres between them, sixteen to a packet (eight
        // without AVX-512).
        let directions: Vec<Vec3> =
            (2..14).flat_map(|x| (2..14).map(move |y| vec3(x as f32 * 0.5, y as f32 * 0.5, -8.0))).collect();
        let mut hits = vec![None; directions.len()];
        bvh.closest_hits(&mut scratch, origin, &directions, &mut hits);
        for (hit, &d) in hits.iter().zip(&directions) {
            let single = bvh.closest_hit(&mut scratch, origin, d, 0.0, f32::INFINITY);
            let bits =
                |h: &Option<Hit>| h.map(|h| (h.triangle, h.t.to_bits(), h.barycentric.map(f32::to_bits)));
            assert_eq!(bits(hit), bits(&single), "direction {d}");
            assert!(single.is_some(), "every ray meets the grid");
        }
        let rays: Vec<WatertightRay> =
            directions[..8].iter().map(|d| WatertightRay::new(origin.into(), (*d).into())).collect();
        // SAFETY: AVX2 checked above.
        assert!(unsafe { Packet::<L8>::new(&rays) }.is_some(), "the rays must walk as packets");
    }

    /// Certified closest hits walked once (`certified_closest_hits`, whose walk notes the
    /// triangles each certificate needs) are those of the two walks (`closest_hits`, then
    /// `certify_primaries`) and of single rays, through stacks of grids a hair apart: 10 layers
    /// (every layer noted within one lane's room) and 24 (more than a lane notes, so the
    /// certificate walks on its own), each layer crossed just beyond the hit, within the walk's
    /// look beyond it; some layers repeat another exactly, so that hits tie.
    #[test]
    fn certificates_through_stacked_layers_as_two_walks() {
        if !super::super::node_test::wide_form_testable() {
            return;
        }
        for layers in [10, 24] {
            let mut tris = Vec::new();
            for layer in 0..layers {
                let z = -((layer / 2) as f32) * 1e-4;
                for (i, j) in (0..8).flat_map(|i| (0..8).map(move |j| (i as f32, j as f32))) {
                    let [a, b, c, d] =
                        [vec3(i, j, z), vec3(i + 1.0, j, z), vec3(i + 1.0, j + 1.0, z), vec3(i, j + 1.0, z)];
                    tris.extend([[a, b, c], [a, c, d]]);
                }
            }
            let bvh = SceneBvh::build_from_triangles(&tris);
            let mut scratch = bvh.scratch();
            let origin = vec3(0.3, 0.2, 8.0);
            let directions: Vec<Vec3> = (0..64)
                .map(|k| {
                    vec3(0.6 + (k % 8) as f32 * 0.83, 0.7 + (k / 8) as f32 * 0.79, -8.0) - vec3(0.3, 0.2, 0.0)
                })
                .collect();
            let n = directions.len();
            let (mut fused, mut fused_certainties) = (vec![None; n], vec![PrimaryCertainty::Uncertain; n]);
            bvh.certified_closest_hits(&mut scratch, origin, &directions, &mut fused, &mut fused_certainties);
            let (mut two, mut two_certainties) = (vec![None; n], vec![PrimaryCertainty::Uncertain; n]);
            bvh.closest_hits(&mut scratch, origin, &directions, &mut two);
            bvh.certify_primaries(&mut scratch, origin, &directions, &mut two, &mut two_certainties);
            assert_eq!((&fused, &fused_certainties), (&two, &two_certainties), "{layers} layers");
            for (k, &d) in directions.iter().enumerate() {
                let mut single = bvh.closest_hit(&mut scratch, origin, d, 0.0, f32::INFINITY);
                let certainty = bvh.certify_primary(&mut scratch, origin, d, &mut single);
                assert_eq!((fused_certainties[k], fused[k]), (certainty, single), "{layers} layers, ray {k}");
                assert!(single.is_some(), "every ray meets the layers");
            }
            let certain = fused_certainties.iter().filter(|&&c| c == PrimaryCertainty::Certain).count();
            assert!(certain > n / 2, "the layers are told apart ({certain} of {n} certain)");
        }
    }

    /// A packet calls a hit certain only where the single ray's test does: shadow rays whose
    /// origins, known to within 10⁻³, lie at distances on either side of that error in front of
    /// a large triangle (so that the triangle's nearest distance is or is not beyond the
    /// distances' bound), towards a directional light and, with the segment ending just beyond
    /// or just before the triangle, towards a point.
    #[test]
    fn packets_find_certain_hits_as_single_rays() {
        if !super::super::node_test::wide_form_testable() {
            return;
        }
        let tris = [
            [vec3(-20.0, -20.0, 0.0), vec3(20.0, -20.0, 0.0), vec3(0.0, 20.0, 0.0)],
            [vec3(50.0, 50.0, 50.0), vec3(51.0, 50.0, 50.0), vec3(50.0, 51.0, 50.0)],
        ];
        let bvh = SceneBvh::build_from_triangles(&tris);
        let mut scratch = bvh.scratch();
        let towards = vec3(0.1, 0.2, 1.0).normalize().as_dvec3();
        let (mut shadowed, mut uncertain) = (0, 0);
        for (round, distance) in [1e-4, 1e-3, 2e-3, 3e-3, 4e-3, 6e-3, 1e-2, 0.1].into_iter().enumerate() {
            for length in [f64::INFINITY, distance * 10.0, distance * 1.01, distance * 0.99] {
                let rays: Vec<ShadowRay> = (0..16)
                    .map(|k| ShadowRay {
                        origin: DVec3::new((k % 4) as f64 - 1.5, (k / 4) as f64 - 1.5, 0.0)
                            - towards * distance,
                        origin_error: 1e-3,
                        direction: towards,
                        direction_error: 0.0,
                        length,
                        length_error: if length.is_finite() { 1e-6 } else { 0.0 },
                        skip_triangle: 1,
                        surface: tris[1],
                    })
                    .collect();
                let bits = bvh.shadow_answers(&mut scratch, &rays);
                for (k, ray) in rays.iter().enumerate() {
                    let single = bvh.shadow_answer(&mut scratch, ray);
                    let at = format!("distance {distance}, length {length}, ray {k} (round {round})");
                    assert_eq!(bits.occluded >> k & 1 == 1, single.shadowed(), "{at}");
                    assert_eq!(bits.uncertain >> k & 1 == 1, single.is_uncertain(), "{at}");
                    shadowed += (single.shadowed() && !single.is_uncertain()) as usize;
                    uncertain += single.is_uncertain() as usize;
                }
            }
        }
        assert!(shadowed >= 64 && uncertain >= 64, "certain hits {shadowed}, doubts {uncertain}");
    }

    /// Every number of a packet, as bits, for comparing two packets.
    fn packet_bits<V: LaneVector>(p: &Packet<V>) -> Vec<u32> {
        let mut bits = Vec::new();
        let mut lanes = |v: &V| {
            let mut a = V::Array::default();
            v.store(&mut a);
            bits.extend(a.as_ref().iter().map(|x| x.to_bits()));
        };
        let vectors = [&p.origin, &p.inv_near, &p.inv_far, &p.origin_near, &p.origin_far];
        vectors.into_iter().flatten().chain(&p.shear).chain([&p.scale]).for_each(&mut lanes);
        let f = p.frustum.as_ref().map(|f| {
            let wide = f.near_origin.iter().chain(&f.far_origin).chain(f.inv_near.iter().flatten());
            // SAFETY: an __m256 is eight f32's bits.
            let lanes = |v: &std::arch::x86_64::__m256| unsafe { std::mem::transmute::<_, [u32; 8]>(*v) };
            wide.chain(f.inv_far.iter().flatten()).flat_map(lanes).collect::<Vec<u32>>()
        });
        bits.extend(f.into_iter().flatten());
        let words =
            [p.near_offset, p.far_offset, p.axes].into_iter().flatten().chain([p.lanes as usize, p.octant]);
        bits.extend(words.map(|w| w as u32));
        bits
    }

    /// A packet of rays from one origin (`Packet::from_origin`, which computes their watertight
    /// rays a vector at a time) is the packet `Packet::new` makes of `WatertightRay::new`'s rays,
    /// bit for bit, with the same watertight rays, and neither walks where the other does not:
    /// directions whose components tie in magnitude (where the main axis is chosen by the
    /// comparisons' order), change sign between lanes, or are zero.
    #[test]
    fn packets_from_an_origin_are_packets_of_watertight_rays() {
        if !super::super::node_test::wide_form_testable() {
            return;
        }
        fn component(rng: &mut SplitMix64) -> f32 {
            match rng.next_u64() % 16 {
                0 => 0.5,
                1 => -0.5,
                2 => 0.0,
                3 => 1.0,
                _ => rng.range([-1.0, 1.0]) as f32,
            }
        }
        fn vector(rng: &mut SplitMix64) -> Vec3 {
            vec3(component(rng), component(rng), component(rng))
        }
        fn compare<V: LaneVector, const N: usize>(rng: &mut SplitMix64) -> bool {
            let origin = vector(rng) * 100.0;
            let count = 2 + (rng.next_u64() % (N as u64 - 1)) as usize;
            let shared = vector(rng);
            let directions: Vec<Vec3> = (0..count)
                .map(|_| match rng.next_u64() % 64 {
                    0 => vector(rng),
                    _ => shared + vector(rng) * 0.01,
                })
                .collect();
            let mut from_origin = [WatertightRay::UNUSED; N];
            // SAFETY: the caller checked `V`'s set.
            let packet = unsafe { Packet::<V>::from_origin(origin, &directions, &mut from_origin) };
            let rays: Vec<WatertightRay> = (0..N)
                .map(|k| WatertightRay::new(origin.into(), directions[k.min(count - 1)].into()))
                .collect();
            // SAFETY: as above.
            let expected = unsafe { Packet::<V>::new(&rays[..count]) };
            assert_eq!(
                packet.as_ref().map(packet_bits),
                expected.as_ref().map(packet_bits),
                "{directions:?}"
            );
            if packet.is_some() {
                for (made, ray) in from_origin.iter().zip(&rays) {
                    let ray_bits = |r: &WatertightRay| {
                        let floats = [r.origin.to_array(), r.direction.to_array(), [r.sx, r.sy, r.sz]];
                        (floats.map(|f| f.map(f32::to_bits)), [r.kx, r.ky, r.kz])
                    };
                    assert_eq!(ray_bits(made), ray_bits(ray), "{directions:?}");
                }
            }
            packet.is_some()
        }
        let mut rng = SplitMix64::new(11);
        let eight = (0..4000).filter(|_| compare::<L8, 8>(&mut rng)).count();
        assert!((400..3600).contains(&eight), "{eight} of 4000 packets of eight walk");
        if packet_isa_for(PacketQuery::SixteenLanes).is_some() {
            let sixteen = (0..4000).filter(|_| compare::<L16, 16>(&mut rng)).count();
            assert!((400..3600).contains(&sixteen), "{sixteen} of 4000 packets of sixteen walk");
        }
    }

    /// Packets give the single-ray answers bit for bit: closest hits (triangle, distance,
    /// barycentrics) of rays fanned out from one origin and their certificates, and occlusion
    /// of parallel shadow rays (some of them skipping the triangle they start on), two to
    /// sixteen at once: one packet of sixteen (closest hits, shadow rays) where the processor
    /// has AVX-512, packets of eight otherwise.
    #[test]
    fn packets_answer_as_single_rays() {
        if !super::super::node_test::wide_form_testable() {
            return;
        }
        let mut rng = SplitMix64::new(5);
        let tris = soup(&mut rng);
        let bvh = SceneBvh::build_from_triangles(&tris);
        let mut scratch = bvh.scratch();
        let (mut packed, mut packed_sixteen, mut hit_count, mut doubts) = (0, 0, 0, 0);
        let sixteen = packet_isa_for(PacketQuery::SixteenLanes).is_some();
        let forms_packet = |origins: &[Vec3], dirs: &[Vec3]| {
            let rays: Vec<WatertightRay> =
                origins.iter().zip(dirs).map(|(o, d)| WatertightRay::new((*o).into(), (*d).into())).collect();
            match rays.len() {
                // SAFETY: AVX2 and FMA checked above.
                ..=LANES => unsafe { Packet::<L8>::new(&rays) }.is_some(),
                // SAFETY: AVX-512 checked above.
                _ if sixteen => unsafe { Packet::<L16>::new(&rays) }.is_some(),
                // Two packets of eight, the first always full.
                // SAFETY: AVX2 and FMA checked above.
                _ => unsafe { Packet::<L8>::new(&rays[..LANES]) }.is_some(),
            }
        };
        for round in 0..3000 {
            let origin = Vec3::from_array(std::array::from_fn(|_| rng.range([-6.0, 6.0]) as f32));
            let centre = Vec3::from_array(std::array::from_fn(|_| rng.range([-3.0, 3.0]) as f32));
            let spread = if round % 2 == 0 { 0.02 } else { 1.0 };
            let n = 2 + round % 15;
            let dirs: Vec<Vec3> = (0..n)
                .map(|_| {
                    let jitter =
                        Vec3::from_array(std::array::from_fn(|_| rng.range([-spread, spread]) as f32));
                    (centre + jitter - origin).normalize()
                })
                .collect();
            let primary_packet = forms_packet(&vec![origin; n], &dirs);
            packed += primary_packet as usize;
            packed_sixteen += (primary_packet && n > LANES) as usize;
            let mut hits = vec![None; n];
            bvh.closest_hits(&mut scratch, origin, &dirs, &mut hits);
            let mut certainties = vec![PrimaryCertainty::Uncertain; n];
            let mut certified = hits.clone();
            bvh.certify_primaries(&mut scratch, origin, &dirs, &mut certified, &mut certainties);
            // One packet for both walks gives the same answers as a packet for each.
            let (mut fused, mut fused_certainties) = (vec![None; n], vec![PrimaryCertainty::Certain; n]);
            bvh.certified_closest_hits(&mut scratch, origin, &dirs, &mut fused, &mut fused_certainties);
            assert_eq!((&fused, &fused_certainties), (&certified, &certainties), "round {round}");
            for (k, d) in dirs.iter().enumerate() {
                let single = bvh.closest_hit(&mut scratch, origin, *d, 0.0, f32::INFINITY);
                assert_eq!(
                    hits[k].map(|h| (h.triangle, h.t.to_bits(), h.barycentric.map(f32::to_bits))),
                    single.map(|h| (h.triangle, h.t.to_bits(), h.barycentric.map(f32::to_bits)))
                );
                let mut single_certified = single;
                let certainty = bvh.certify_primary(&mut scratch, origin, *d, &mut single_certified);
                assert_eq!(
                    (certainties[k], certified[k]),
                    (certainty, single_certified),
                    "round {round}, ray {k}"
                );
                hit_count += single.is_some() as usize;
            }
            let towards = dirs[0];
            // Origins known to within nothing to 10⁻³, so that the certified rejection of the
            // packet and the doubts of the f64 test are both exercised.
            let rays: Vec<ShadowRay> = (0..n)
                .map(|k| {
                    let o = origin + Vec3::from_array(std::array::from_fn(|_| rng.range([-0.3, 0.3]) as f32));
                    let spot = k % 3 == 0;
                    ShadowRay {
                        origin: o.as_dvec3(),
                        origin_error: [0.0, 1e-7, 1e-3][(round + k) % 3],
                        direction: towards.as_dvec3(),
                        direction_error: if spot { 1e-7 } else { 0.0 },
                        length: if spot { 2.0 } else { f64::INFINITY },
                        length_error: if spot { 1e-6 } else { 0.0 },
                        skip_triangle: (k * 7) as u32,
                        surface: tris[k * 7],
                    }
                })
                .collect();
            let shadow_packet =
                forms_packet(&rays.iter().map(|r| r.origin.as_vec3()).collect::<Vec<_>>(), &vec![towards; n]);
            packed += shadow_packet as usize;
            packed_sixteen += (shadow_packet && n > LANES) as usize;
            if round % 15 == 0 {
                // One ray alone, and none.
                let one = bvh.shadow_answers(&mut scratch, &rays[..1]);
                let single = bvh.shadow_answer(&mut scratch, &rays[0]);
                assert_eq!(
                    (one.occluded == 1, one.uncertain == 1),
                    (single.shadowed(), single.is_uncertain())
                );
                let none = bvh.shadow_answers(&mut scratch, &[]);
                assert_eq!((none.occluded, none.uncertain), (0, 0));
            }
            let bits = bvh.shadow_answers(&mut scratch, &rays);
            for (k, ray) in rays.iter().enumerate() {
                let single = bvh.shadow_answer(&mut scratch, ray);
                assert_eq!(bits.occluded >> k & 1 == 1, single.shadowed(), "round {round}, ray {k}");
                assert_eq!(bits.uncertain >> k & 1 == 1, single.is_uncertain(), "round {round}, ray {k}");
                doubts += single.is_uncertain() as usize;
            }
        }
        // Both kinds of query must mostly have run as packets, not one ray at a time.
        assert!(
            packed > 3000 && hit_count > 1000 && doubts > 100,
            "the test needs packets ({packed}), hits ({hit_count}) and uncertain answers ({doubts})"
        );
        // Where the processor has AVX-512, batches of nine to sixteen ran as one packet.
        assert!(!sixteen || packed_sixteen > 2000, "sixteen-lane packets: {packed_sixteen}");
        eprintln!(
            "batches of nine to sixteen rays walked as {}",
            if sixteen { "packets of sixteen (AVX-512)" } else { "two packets of eight (AVX2)" }
        );
    }
}
