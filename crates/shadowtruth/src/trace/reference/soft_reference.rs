//! Fractional reference visibility (pixel coverage, area light) with its standard error, and its
//! file encoding: a two-channel f32 EXR, `V` visibility and `E` standard error, row 0 at the top,
//! with the sample count in a `samples` header attribute. f32 samples in a lossless EXR read
//! back bit for bit.

use super::gbuffer::{GBuffer, PixelClass};
use crate::trace::bvh::scene_bvh::SceneBvh;
use crate::trace::bvh::scratch::TraversalScratch;
use crate::trace::bvh::shadow_batch::RowShadows;
use exr::prelude::*;
use rayon::prelude::*;
use std::io::Cursor;

/// Sub-pixel grid of the coverage reference (4×4) unless one is given.
pub const DEFAULT_COVERAGE_GRID: u32 = 4;
/// Light-sample grid of the area-light reference (8×8) unless one is given.
pub const DEFAULT_AREA_LIGHT_GRID: u32 = 8;
/// Largest N of the N×N sample grid of a soft reference (4096 samples per pixel) that the
/// command and the Python package accept.
pub const MAX_REFERENCE_GRID: u32 = 64;

/// Which soft reference: the two share the type and the file format.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum SoftKind {
    /// Hard visibility averaged over an n×n grid of sub-pixel primary rays.
    Coverage,
    /// Fraction of n×n stratified light samples that are unoccluded.
    AreaLight,
}

impl SoftKind {
    /// The name used in the cache manifest, file names and on the command line.
    pub fn name(self) -> &'static str {
        match self {
            SoftKind::Coverage => "coverage",
            SoftKind::AreaLight => "area",
        }
    }
}

/// Fractional reference visibility per pixel, with its per-pixel standard error.
#[derive(Clone, Debug, PartialEq)]
pub struct SoftReference {
    pub width: u32,
    pub height: u32,
    /// Visibility in [0, 1] per pixel (1 = lit); 0 on pixels that are not `PixelClass::Evaluated`.
    pub visibility: Vec<f32>,
    /// Standard error of each pixel's visibility estimate (0 where not evaluated).
    pub std_error: Vec<f32>,
    /// Samples per pixel (n×n sub-pixels for coverage, n×n light samples for an area light).
    pub samples: u32,
}

/// Mean and standard error of the mean of `m` samples that are 0 or 1, `hits` of them 1.
///
/// The sample variance of 0/1 values is m/(m − 1)·p(1 − p), so the standard error of the mean
/// is √(p(1 − p)/(m − 1)); 0 for a single sample (no spread to estimate). This is the error of
/// independent samples: stratification only lowers the true error, so it is an upper bound that
/// falls as 1/√m where p stays fixed (a penumbra pixel).
pub(in crate::trace) fn mean_and_std_error(hits: u32, m: u32) -> (f32, f32) {
    debug_assert!(m > 0 && hits <= m);
    let p = hits as f64 / m as f64;
    let se = if m > 1 { (p * (1.0 - p) / (m - 1) as f64).sqrt() } else { 0.0 };
    (p as f32, se as f32)
}

/// How a pixel's estimate follows from its shadow rays (`trace_evaluated`).
#[derive(Clone, Copy, Debug)]
pub(in crate::trace) enum Estimate {
    /// The mean of `samples` 0/1 samples, of which the pixel's unoccluded rays are the 1s.
    Mean { samples: u32 },
    /// Known without its rays: (visibility, standard error).
    Known(f32, f32),
}

/// A soft reference of `samples` samples per pixel: `gather(scratch, rays, x, y, i)` adds the
/// shadow rays of each evaluated pixel (index i = y·width + x) to its row's `rays` under column
/// `x`, and says how the pixel's estimate follows from them; the other pixels hold zeros. A
/// row's rays are traced together, eight at a time across its pixels, and rows run in parallel
/// with one traversal scratch per worker; each ray's answer is its own, so the bits depend
/// neither on the thread count nor on how rays are batched.
pub(in crate::trace) fn trace_evaluated(
    bvh: &SceneBvh,
    gbuffer: &GBuffer,
    samples: u32,
    gather: impl Fn(&mut TraversalScratch, &mut RowShadows, usize, usize, usize) -> Estimate + Sync,
) -> SoftReference {
    let n = gbuffer.pixel_count();
    let w = gbuffer.width as usize;
    let mut visibility = vec![0f32; n];
    let mut std_error = vec![0f32; n];
    visibility.par_chunks_mut(w).zip(std_error.par_chunks_mut(w)).enumerate().for_each_init(
        || (bvh.scratch(), RowShadows::new(w), vec![Estimate::Known(0.0, 0.0); w]),
        |(scratch, rays, estimates), (y, (vis, err))| {
            let evaluated = |x: usize| gbuffer.class[y * w + x] == PixelClass::Evaluated;
            rays.clear();
            for x in (0..w).filter(|&x| evaluated(x)) {
                estimates[x] = gather(scratch, rays, x, y, y * w + x);
            }
            rays.finish(bvh, scratch);
            for x in (0..w).filter(|&x| evaluated(x)) {
                (vis[x], err[x]) = match estimates[x] {
                    Estimate::Mean { samples } => mean_and_std_error(rays.lit(x), samples),
                    Estimate::Known(visibility, std_error) => (visibility, std_error),
                };
            }
        },
    );
    SoftReference { width: gbuffer.width, height: gbuffer.height, visibility, std_error, samples }
}

/// Run-length-encoded 64×64 tiles written in increasing order. The exr crate compresses tiles in
/// parallel and, with `LineOrder::Unspecified` (`Encoding::FAST_LOSSLESS`), writes each as it
/// finishes, so that the bytes of one image would differ from run to run.
/// How every EXR of this tool is encoded: lossless, tiles in increasing order (the same image is
/// the same bytes).
pub const EXR_ENCODING: Encoding = Encoding { line_order: LineOrder::Increasing, ..Encoding::FAST_LOSSLESS };

impl SoftReference {
    /// Whether non-evaluated pixels hold zeros and evaluated ones a visibility in [0, 1] with a
    /// finite, non-negative error: what a stored reference must satisfy to be used for `gbuffer`.
    pub fn fits(&self, gbuffer: &GBuffer) -> bool {
        let n = gbuffer.pixel_count();
        self.width == gbuffer.width
            && self.height == gbuffer.height
            && self.visibility.len() == n
            && self.std_error.len() == n
            && gbuffer.class.iter().zip(self.visibility.iter().zip(&self.std_error)).all(|(c, (&v, &e))| {
                if *c == PixelClass::Evaluated {
                    (0.0..=1.0).contains(&v) && e.is_finite() && e >= 0.0
                } else {
                    v.to_bits() == 0 && e.to_bits() == 0
                }
            })
    }

    /// The reference as an EXR file: channels `V` and `E` (f32), row 0 at the top, lossless; the
    /// same reference gives the same bytes, whatever the thread count.
    pub fn to_exr(&self) -> std::io::Result<Vec<u8>> {
        let channels = vec![
            AnyChannel::new("E", FlatSamples::F32(self.std_error.clone())),
            AnyChannel::new("V", FlatSamples::F32(self.visibility.clone())),
        ];
        let mut attributes = LayerAttributes::named("visibility");
        attributes.other.insert(Text::from("samples"), AttributeValue::I32(self.samples as i32));
        let image = Image::from_layer(Layer::new(
            (self.width as usize, self.height as usize),
            attributes,
            EXR_ENCODING,
            AnyChannels::sort(SmallVec::from_vec(channels)),
        ));
        let mut bytes = Cursor::new(Vec::new());
        image.write().to_buffered(&mut bytes).map_err(std::io::Error::other)?;
        Ok(bytes.into_inner())
    }

    /// Reads what `to_exr` wrote (the same bits).
    pub fn from_exr(bytes: &[u8]) -> std::io::Result<Self> {
        let invalid = |what: &str| std::io::Error::new(std::io::ErrorKind::InvalidData, what.to_string());
        let image = read()
            .no_deep_data()
            .largest_resolution_level()
            .all_channels()
            .first_valid_layer()
            .all_attributes()
            .from_buffered(Cursor::new(bytes))
            .map_err(|e| std::io::Error::new(std::io::ErrorKind::InvalidData, e))?;
        let layer = &image.layer_data;
        let channel = |name: &str| -> std::io::Result<Vec<f32>> {
            let c = layer
                .channel_data
                .list
                .iter()
                .find(|c| c.name.eq(name))
                .ok_or_else(|| invalid(&format!("no channel {name}")))?;
            match &c.sample_data {
                FlatSamples::F32(v) => Ok(v.clone()),
                _ => Err(invalid(&format!("channel {name} is not f32"))),
            }
        };
        let samples = match layer.attributes.other.get(&Text::from("samples")) {
            Some(AttributeValue::I32(s)) if *s > 0 => *s as u32,
            _ => return Err(invalid("no positive `samples` attribute")),
        };
        Ok(SoftReference {
            width: layer.size.width() as u32,
            height: layer.size.height() as u32,
            visibility: channel("V")?,
            std_error: channel("E")?,
            samples,
        })
    }
}
