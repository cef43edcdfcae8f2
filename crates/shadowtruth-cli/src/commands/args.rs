//! Option types several commands share, each checked by clap as it parses, so that a command's
//! body receives valid values and a bad one is named with its option.

use anyhow::{Context, Result};
use clap::builder::{PossibleValuesParser, RangedU64ValueParser, TypedValueParser};
use shadowtruth::raster::DepthFormat;

/// Worker threads at most, on every command (as `tune` has it).
pub(super) use crate::tune::MAX_THREADS;

/// `--threads N`: 1 to [`MAX_THREADS`].
pub(super) fn threads_parser() -> RangedU64ValueParser<usize> {
    RangedU64ValueParser::<usize>::new().range(1..=MAX_THREADS as u64)
}

/// Sizes the worker pool to `threads` (already checked by [`threads_parser`]); None keeps one
/// thread per core.
pub(super) fn set_threads(threads: Option<usize>) -> Result<()> {
    if let Some(n) = threads {
        rayon::ThreadPoolBuilder::new().num_threads(n).build_global().context("setting up worker threads")?;
    }
    Ok(())
}

/// A depth format by its name (`f32`, `unorm24`, `unorm16`).
pub(super) fn depth_format_parser() -> impl TypedValueParser<Value = DepthFormat> {
    let names = [DepthFormat::F32, DepthFormat::Unorm24, DepthFormat::Unorm16].map(DepthFormat::name);
    PossibleValuesParser::new(names).map(|name| DepthFormat::parse(&name).expect("one of the names above"))
}
