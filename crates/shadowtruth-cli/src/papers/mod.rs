//! Reproducing the papers' results: the island of Ehm et al.'s Figure 12 (a seeded generator, so
//! that the scene can be rebuilt bit for bit), and each paper's experiments as measured numbers
//! with a verdict and its sensitivity: Ehm et al.'s Figure 12 (`ehm_fig12.rs`, drawn by
//! `figure12.rs`), Fig. 4 (`ehm_pcf.rs`), Table 1, §3.3 and Table 2 (`ehm_cost.rs`), Pagot et al.'s Table 1 and Fig. 6
//! (`pagot.rs`) and Fig. 7 (`pagot_curved.rs`), Weiskopf & Ertl's Fig. 5 to 7 (`weiskopf.rs`). `run.rs` runs them in turn, each
//! given a `Suite` (`suite.rs`); `measure.rs` holds what they share, `names.rs` the names more
//! than one uses, `claims.rs` the rules.

pub mod claims;
mod ehm_cost;
mod ehm_fig12;
mod ehm_pcf;
mod figure12;
pub mod island;
mod measure;
mod names;
mod page;
mod pagot;
mod pagot_curved;
mod run;
mod suite;
mod weiskopf;

pub use island::*;
pub use page::claims_html;
pub use run::run_papers;
pub use suite::PapersOptions;
