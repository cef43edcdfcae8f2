//! Names more than one paper's experiments use.

/// Ehm et al.'s paper, cited by its Figure 12 (`ehm_fig12.rs`) and by its PCF results
/// (`ehm_pcf.rs`).
pub(super) const EHM: &str =
    "Ehm, Ederer, Klein & Nischwitz, Adaptive depth bias for soft shadows (WSCG 2015)";

/// The plane the casters' shadows fall on (scenes/papers/casters.json).
pub(super) const PLANE: &str = "plane";

/// Pagot et al.'s paper, cited by its Table 1 and Fig. 6 (`pagot.rs`) and its Fig. 7
/// (`pagot_curved.rs`).
pub(super) const PAGOT: &str = "Pagot, Comba & Oliveira, Multiple-depth shadow maps (SIBGRAPI 2004)";
