//! Reproducing the papers' results: the island of Ehm et al.'s Figure 12 (a seeded generator, so
//! that the scene can be rebuilt bit for bit), the claims of Figure 12, Weiskopf & Ertl's Fig. 5,
//! Pagot et al.'s Table 1 and Fig. 6 and Ehm et al.'s Fig. 4 and Table 1, each as measured
//! numbers with a verdict.

pub mod claims;
pub mod island;
mod page;
mod suite;

pub use claims::{Claim, Verdict};
pub use island::*;
pub use page::claims_html;
pub use suite::{ISLAND_RESOLUTION, L_SHAPE_RESOLUTIONS, run_papers};
