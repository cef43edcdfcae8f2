//! What `shadowtruth generate` is asked for, and the bounds of what it promises.

/// How far the generated triangle count may be from the request, as a fraction of it (for
/// requests of at least `MIN_COUNT_FOR_TOLERANCE` triangles).
pub(crate) const COUNT_TOLERANCE: f64 = 0.02;
/// Below this request the tolerance is not promised: buildings and trees come in whole units.
pub(crate) const MIN_COUNT_FOR_TOLERANCE: u64 = 20_000;
/// The smallest request accepted: a terrain and a few casters.
pub(crate) const MIN_TRIANGLES: u64 = 1_000;
/// The smallest `--instanced` request: its terrain alone is 131 072 triangles and its tree at
/// least 2 000, so that below this the count could not be met within the tolerance.
pub(crate) const MIN_INSTANCED_TRIANGLES: u64 = 200_000;

/// What kind of scene to generate.
#[derive(Clone, Copy, Debug, PartialEq, Eq, clap::ValueEnum)]
pub(crate) enum SceneKind {
    /// Terrain and closed buildings of varied heights in blocks.
    City,
    /// Terrain and closed trees (trunk and crown).
    Forest,
}

/// The request: kind, triangle count, seed and the camera's image size.
#[derive(Clone, Copy, Debug)]
pub(crate) struct GenerateOptions {
    pub kind: SceneKind,
    pub triangles: u64,
    pub seed: u64,
    pub width_px: u32,
    pub height_px: u32,
    /// A forest of one tree mesh placed at every tree by `instances` (src/scene/instance.rs).
    pub instanced: bool,
}
