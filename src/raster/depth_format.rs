//! Depth buffer formats: how a depth in [0, 1] is stored, and the minimum resolvable difference r
//! that glPolygonOffset's `units` multiply.

#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub enum DepthFormat {
    F32,
    Unorm24,
    Unorm16,
}

impl DepthFormat {
    pub fn name(self) -> &'static str {
        match self {
            DepthFormat::F32 => "f32",
            DepthFormat::Unorm24 => "unorm24",
            DepthFormat::Unorm16 => "unorm16",
        }
    }

    pub fn parse(name: &str) -> Option<Self> {
        match name {
            "f32" => Some(DepthFormat::F32),
            "unorm24" => Some(DepthFormat::Unorm24),
            "unorm16" => Some(DepthFormat::Unorm16),
            _ => None,
        }
    }

    /// The depth as stored (unorm: clamp to [0, 1], round to nearest).
    pub fn store(self, depth: f32) -> f32 {
        todo!("{depth}")
    }

    /// r: 1/(2^b − 1) for unorm, 2^(e − 23) for f32 where e is the exponent of `max_depth`.
    pub fn min_resolvable_difference(self, max_depth: f32) -> f32 {
        todo!("{max_depth}")
    }
}
