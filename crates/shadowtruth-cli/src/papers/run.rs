//! The papers suite run: each paper's experiments in turn, each writing the runs of its set-up
//! into the ordinary report, measuring its claims on that set-up and on the others of its
//! sensitivity grid (`measure.rs`), and returning the claims.

use super::claims::Claim;
use super::suite::{PapersOptions, Suite};
use super::{ehm_cost, ehm_fig12, ehm_pcf, pagot, pagot_curved, weiskopf};
use crate::plan::{PlanError, Sink};
use shadowtruth::trace::ReferenceCache;
use std::path::Path;

/// Runs the whole suite into the report folder `dir` through `sinks` (report.json, figures,
/// progress) and returns the claims (written by the caller as `claims.json`). `scenes_dir`
/// holds `papers/island.json`, `papers/casters.json`, `papers/curved.json` and `papers/l_above.json`.
pub fn run_papers(
    scenes_dir: &Path,
    dir: &Path,
    cache: Option<&ReferenceCache>,
    sinks: &mut [&mut dyn Sink],
    options: PapersOptions,
) -> Result<Vec<Claim>, PlanError> {
    // Without a cache (--no-cache), one for this run only: nothing is read from or written to
    // the persistent one.
    let run_dir =
        tempfile::tempdir().map_err(|source| PlanError::Io { path: std::env::temp_dir(), source })?;
    let run_cache = ReferenceCache::new(run_dir.path());
    let cache = cache.unwrap_or(&run_cache);
    let mut suite =
        Suite { scenes_dir: scenes_dir.to_path_buf(), dir: dir.to_path_buf(), cache, sinks, options };
    let mut claims = ehm_fig12::claims(&mut suite)?;
    claims.extend(ehm_pcf::claims(&mut suite)?);
    claims.extend(ehm_cost::claims(&mut suite)?);
    claims.extend(pagot::claims(&mut suite)?);
    claims.extend(pagot_curved::claims(&mut suite)?);
    claims.extend(weiskopf::claims(&mut suite)?);
    Ok(claims)
}
