//! What several commands do with their shared options once clap has checked them (the value
//! parsers themselves are in `option_values.rs`, shared with `tune`).

use anyhow::{Context, Result};

/// Sizes the worker pool to `threads` (already checked by `option_values::threads_parser`);
/// None keeps one thread per core.
pub(super) fn set_threads(threads: Option<usize>) -> Result<()> {
    if let Some(n) = threads {
        rayon::ThreadPoolBuilder::new().num_threads(n).build_global().context("setting up worker threads")?;
    }
    Ok(())
}
