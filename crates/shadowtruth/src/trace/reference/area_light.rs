//! The area-light reference (soft shadows, PCSS): the fraction of n×n stratified light samples
//! whose shadow ray from the pixel's surface point is unoccluded.
//!
//! - Directional light with `angular_diameter_deg` α: directions uniform in solid angle over the
//!   spherical cap of half-angle α/2 around the direction towards the light (a disk of uniform
//!   radiance, like the sun).
//! - Spot light with `radius` R: points uniform in area on the disk of radius R centred at the
//!   light's position and facing along its axis; each shadow ray is the segment to its point.
//! - Point light with `radius` R (a sphere light): directions uniform in solid angle over the
//!   cone the sphere subtends from the pixel's point (half-angle asin(R/d) at distance d, as
//!   Shirley et al. sample spheres, "Monte Carlo techniques for direct lighting calculations",
//!   TOG 1996), each shadow ray the segment to where its direction first meets the sphere: the
//!   fraction of the sphere's visible disk that is unoccluded. A point inside the sphere takes
//!   the segment to its centre for every sample.
//!
//! The unit square is split into n×n strata, each jittered by a hash of (pixel, stratum) (never
//! by a generator's state, so the bits do not depend on the thread count) and mapped to the unit
//! disk by Shirley & Chiu's concentric map, which keeps strata compact. Origins are offset as in
//! the hard reference (shadow_ray.rs): the ray never tests its own triangle and accepts only hits
//! certainly in front of its origin. A light sample below the receiver's tangent plane (N·ω ≤ 0) counts as
//! occluded: the receiver's own surface hides it. The standard error is √(p(1 − p)/(N − 1)),
//! that of N independent samples; stratification makes the true error smaller, so it is an
//! upper bound that falls as 1/√N on penumbra pixels.

use super::gbuffer::{GBuffer, PixelClass};
use super::hard::in_groups;
use super::sampling::{concentric_disk, concentric_polar, disk_point, jittered_stratum, orthonormal_frame};
use super::soft_reference::{Estimate, SoftReference, trace_evaluated};
use crate::scene::{Light, LightKind, Scene};
use crate::trace::bvh::in_packet_isa_where_available;
use crate::trace::bvh::scene_bvh::SceneBvh;
use crate::trace::bvh::shadow_ray::ShadowRay;
use glam::DVec3;

/// Why an area-light reference cannot be traced.
#[derive(Clone, Debug, PartialEq, thiserror::Error)]
pub enum AreaLightError {
    #[error("light '{light}' has no {field}: an area-light reference needs the light's size")]
    NoSize { light: String, field: &'static str },
    #[error("light '{light}': {field} = {value} is not a usable area-light size")]
    BadSize { light: String, field: &'static str, value: f32 },
    #[error("area-light reference of light '{light}': the sample grid must be at least 1×1")]
    NoSamples { light: String },
}

/// The light's shape as sampled.
#[derive(Clone, Copy, Debug)]
enum Emitter {
    /// A directional light's cap of directions.
    Cap(Cap),
    /// Disk centre, its frame and radius.
    Disk { centre: DVec3, tangent: DVec3, bitangent: DVec3, radius: f64 },
    /// Sphere centre and radius.
    Sphere { centre: DVec3, radius: f64 },
}

fn emitter(light: &Light, grid: u32) -> Result<Emitter, AreaLightError> {
    let name = || light.name.clone();
    if grid == 0 {
        return Err(AreaLightError::NoSamples { light: name() });
    }
    let size = light.size().map_err(|e| AreaLightError::NoSize { light: name(), field: e.field })?;
    if !size.is_usable() {
        return Err(AreaLightError::BadSize { light: name(), field: size.field(), value: size.value() });
    }
    // `size` is the kind's own: the angular diameter (degrees) of a directional light, the disk
    // radius (world units) of a spot.
    match &light.kind {
        LightKind::Directional { direction, .. } => {
            let alpha = size.value();
            // 1 − cos θ as 2 sin²(θ/2): no cancellation for small suns.
            let s = (0.25 * (alpha as f64).to_radians()).sin();
            Ok(Emitter::Cap(Cap::around(-direction.as_dvec3().normalize(), 2.0 * s * s)))
        }
        LightKind::Spot { position, direction, .. } => {
            let radius = size.value();
            let (tangent, bitangent) = orthonormal_frame(direction.as_dvec3().normalize());
            Ok(Emitter::Disk { centre: position.as_dvec3(), tangent, bitangent, radius: radius as f64 })
        }
        LightKind::Point { position, .. } => {
            Ok(Emitter::Sphere { centre: position.as_dvec3(), radius: size.value() as f64 })
        }
    }
}

/// Checks that an area-light reference of `light` on an n×n grid can be traced.
pub fn validate_area_light(light: &Light, grid: u32) -> Result<(), AreaLightError> {
    emitter(light, grid).map(|_| ())
}

/// Salt of the light-sample jitter, apart from any other use of the pixel hash.
const LIGHT_SALT: u64 = 0x4152_4541; // "AREA"

/// Traces the area-light reference with n×n light samples per evaluated pixel (`grid` = n).
pub fn trace_area_light_reference(
    scene: &Scene,
    bvh: &SceneBvh,
    gbuffer: &GBuffer,
    light: &Light,
    grid: u32,
) -> Result<SoftReference, AreaLightError> {
    let emitter = emitter(light, grid)?;
    Ok(trace_evaluated(bvh, gbuffer, grid * grid, |scratch, rays, x, _, i| {
        pixel_rays(scene, gbuffer, &emitter, grid, i, |ray| rays.push(bvh, scratch, x, ray))
    }))
}

/// The shadow rays of `trace_area_light_reference`, row by row in the order it traces them, a
/// group of rows at a time, so that `trace_shadow_rays` can time the rays alone
/// (`reference --timing --kind area`): `f` gets each group in turn. A group holds about
/// `max_bytes` of rays, but at least one row per thread.
pub fn area_light_shadow_rays(
    scene: &Scene,
    gbuffer: &GBuffer,
    light: &Light,
    grid: u32,
    max_bytes: usize,
    f: impl FnMut(&[Vec<ShadowRay>]),
) -> Result<(), AreaLightError> {
    let emitter = emitter(light, grid)?;
    let w = gbuffer.width as usize;
    let row_rays = |y: usize| {
        let mut row = Vec::new();
        for i in (y * w..(y + 1) * w).filter(|&i| gbuffer.class[i] == PixelClass::Evaluated) {
            pixel_rays(scene, gbuffer, &emitter, grid, i, |ray| row.push(ray));
        }
        row
    };
    in_groups(gbuffer.height as usize, w * (grid * grid) as usize, max_bytes, row_rays, f);
    Ok(())
}

/// The shadow rays of evaluated pixel `i` towards its n×n light samples (`grid` = n), each to
/// `emit`: those facing the point's side of the surface. The pixel's estimate is the mean over
/// all n×n samples.
fn pixel_rays(
    scene: &Scene,
    gbuffer: &GBuffer,
    emitter: &Emitter,
    grid: u32,
    i: usize,
    mut emit: impl FnMut(ShadowRay),
) -> Estimate {
    let point = gbuffer.surface_point(scene, i);
    let (p64, n64) = (point.position.as_dvec3(), point.normal.as_dvec3());
    let m = grid * grid;
    if let Emitter::Cap(cap) = emitter {
        let mut directions = [DVec3::ZERO; CAP_BLOCK];
        for first in (0..m).step_by(CAP_BLOCK) {
            cap_block(i as u64, first, grid, cap, &mut directions);
            for &dir in &directions[..(m - first).min(CAP_BLOCK as u32) as usize] {
                if n64.dot(dir) > 0.0 {
                    emit(ShadowRay::along(&point, dir));
                }
            }
        }
        return Estimate::Mean { samples: m };
    }
    for k in 0..m {
        let (u, v) = jittered_stratum(i as u64, k, grid, LIGHT_SALT);
        let (dx, dy) = concentric_disk(u, v);
        let target = match *emitter {
            Emitter::Sphere { centre, radius } => sphere_point(p64, (dx, dy), centre, radius),
            Emitter::Disk { centre, tangent, bitangent, radius } => {
                centre + radius * (dx * tangent + dy * bitangent)
            }
            Emitter::Cap(_) => unreachable!("a cap's samples are taken a block at a time"),
        };
        if n64.dot(target - p64) > 0.0 {
            emit(ShadowRay::to_point(&point, target));
        }
    }
    Estimate::Mean { samples: m }
}

/// The directions towards a directional light's disk: the cap of half-angle θmax around the
/// unit `axis` (towards the light), with `one_minus_cos` = 1 − cos θmax.
#[derive(Clone, Copy, Debug)]
struct Cap {
    axis: DVec3,
    tangent: DVec3,
    bitangent: DVec3,
    one_minus_cos: f64,
}

/// Samples a pixel's cap directions are computed for at once.
const CAP_BLOCK: usize = 16;

/// The cap directions of samples `first..first + CAP_BLOCK` of pixel `pixel` (those past the
/// grid's last are computed and ignored): `jittered_stratum`, `concentric_disk` and
/// `Cap::direction`, the same operations in the same order, so the same bits, but written as
/// loops over the block so that the compiler can take them a vector of samples at a time.
/// Compiled for the packets' instruction set where the processor has one
/// (`in_packet_isa_where_available`).
fn cap_block(pixel: u64, first: u32, grid: u32, cap: &Cap, out: &mut [DVec3; CAP_BLOCK]) {
    in_packet_isa_where_available(
        #[inline(always)]
        || cap_block_loops(pixel, first, grid, cap, out),
    )
}

#[inline(always)]
fn cap_block_loops(pixel: u64, first: u32, grid: u32, cap: &Cap, out: &mut [DVec3; CAP_BLOCK]) {
    // Each sample's point in its stratum, in the same loop for grids of 2ⁿ and for the others:
    // told which, the compiler takes the first a vector of samples at a time, hash and all,
    // where deciding it inside the loop (or in a closure called from both) it took every sample
    // alone: 1.02–1.10× the reference's rate on the forest (docs/scale.md).
    let (mut u, mut v) = ([0.0f64; CAP_BLOCK], [0.0f64; CAP_BLOCK]);
    #[allow(clippy::if_same_then_else)]
    if grid.is_power_of_two() {
        for j in 0..CAP_BLOCK {
            (u[j], v[j]) = jittered_stratum(pixel, first + j as u32, grid, LIGHT_SALT);
        }
    } else {
        for j in 0..CAP_BLOCK {
            (u[j], v[j]) = jittered_stratum(pixel, first + j as u32, grid, LIGHT_SALT);
        }
    }
    // Apart from the strata, so that the division here is taken a vector at a time too.
    let (mut r, mut t, mut by_a) = ([0.0f64; CAP_BLOCK], [0.0f64; CAP_BLOCK], [false; CAP_BLOCK]);
    for j in 0..CAP_BLOCK {
        (r[j], t[j], by_a[j]) = concentric_polar(u[j], v[j]);
    }
    let (mut dx, mut dy) = ([0.0f64; CAP_BLOCK], [0.0f64; CAP_BLOCK]);
    for j in 0..CAP_BLOCK {
        (dx[j], dy[j]) = disk_point((r[j], t[j], by_a[j]));
    }
    for j in 0..CAP_BLOCK {
        out[j] = cap.direction((dx[j], dy[j]));
    }
}

impl Cap {
    /// The cap of `one_minus_cos` = 1 − cos θmax around the unit `axis`.
    fn around(axis: DVec3, one_minus_cos: f64) -> Self {
        let (tangent, bitangent) = orthonormal_frame(axis);
        Cap { axis, tangent, bitangent, one_minus_cos }
    }

    /// The direction of concentric-disk point (dx, dy), uniform in solid angle: the disk's r² is
    /// the cap's area fraction, 1 − cos θ = r²(1 − cos θmax); sin θ / r = √(k(2 − r²k)).
    #[inline(always)]
    fn direction(&self, (dx, dy): (f64, f64)) -> DVec3 {
        let k = self.one_minus_cos;
        let r2k = (dx * dx + dy * dy) * k;
        let sin_over_r = (k * (2.0 - r2k)).sqrt();
        ((1.0 - r2k) * self.axis + sin_over_r * (dx * self.tangent + dy * self.bitangent)).normalize()
    }
}

/// Where the direction of disk point (dx, dy), uniform in solid angle over the cone a sphere
/// subtends from `p`, first meets the sphere; its centre when `p` lies inside it.
fn sphere_point(p: DVec3, disk: (f64, f64), centre: DVec3, radius: f64) -> DVec3 {
    let to_centre = centre - p;
    let d2 = to_centre.length_squared();
    let s2 = radius * radius / d2; // sin² θmax
    if s2.is_nan() || s2 >= 1.0 {
        return centre;
    }
    // 1 − cos θmax = sin²/(1 + cos): no cancellation for small or distant spheres.
    let one_minus_cos = s2 / (1.0 + (1.0 - s2).sqrt());
    let dir = Cap::around(to_centre / d2.sqrt(), one_minus_cos).direction(disk);
    // The nearer root of |p + t·dir − centre| = R; a grazing direction rounds to the tangent point.
    let b = dir.dot(to_centre);
    let t = b - (b * b - (d2 - radius * radius)).max(0.0).sqrt();
    p + t * dir
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A block of cap directions is each sample's direction as one sample at a time computes
    /// it, bit for bit, over grids whose sample count is and is not a multiple of the block.
    #[test]
    fn cap_blocks_give_each_samples_bits() {
        let s = (0.25 * 0.53f64.to_radians()).sin();
        let cap = Cap::around(DVec3::new(0.6, 0.45, 0.35).normalize(), 2.0 * s * s);
        for grid in [1u32, 3, 4, 5, 8] {
            for pixel in [0u64, 17, 123_456_789] {
                let mut block = [DVec3::ZERO; CAP_BLOCK];
                for first in (0..grid * grid).step_by(CAP_BLOCK) {
                    cap_block(pixel, first, grid, &cap, &mut block);
                    for (j, got) in
                        block.iter().enumerate().take(((grid * grid - first) as usize).min(CAP_BLOCK))
                    {
                        let (u, v) = jittered_stratum(pixel, first + j as u32, grid, LIGHT_SALT);
                        let one = cap.direction(concentric_disk(u, v));
                        assert_eq!(got.to_array().map(f64::to_bits), one.to_array().map(f64::to_bits));
                    }
                }
            }
        }
    }

    #[test]
    fn sphere_samples_lie_on_the_sphere_and_cover_its_visible_cap() {
        let (centre, radius) = (DVec3::new(1.0, 4.0, -2.0), 0.5);
        let p = DVec3::new(0.3, 0.2, 0.1);
        let axis = (centre - p).normalize();
        let d = (centre - p).length();
        // The tangent cone's half-angle: every sample within it, the rim reached.
        let cos_max = (1.0 - (radius / d).powi(2)).sqrt();
        let mut rim = 1.0f64;
        for &(dx, dy) in &[(0.0, 0.0), (1.0, 0.0), (0.0, -1.0), (0.6, 0.8), (-0.3, 0.2)] {
            let q = sphere_point(p, (dx, dy), centre, radius);
            assert!(((q - centre).length() - radius).abs() < 1e-12, "{q}");
            let cos = (q - p).normalize().dot(axis);
            assert!(cos >= cos_max - 1e-12, "{cos} < {cos_max}");
            // The sample faces p: it is on the near side of the sphere.
            assert!((q - centre).dot(p - centre) >= -1e-9);
            rim = rim.min(cos);
        }
        assert!((rim - cos_max).abs() < 1e-9, "the unit circle's points reach the rim: {rim} vs {cos_max}");
        // The centre of the disk is the sphere's nearest point.
        let q = sphere_point(p, (0.0, 0.0), centre, radius);
        assert!((q - (centre - radius * axis)).length() < 1e-12);
        assert_eq!(sphere_point(centre + DVec3::X * 0.1, (0.5, 0.5), centre, radius), centre);
    }
}
