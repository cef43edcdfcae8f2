//! What every technique's parameters do, whatever the technique: one struct per technique, in the
//! technique's own file, parses itself (serde), checks itself, builds its `Technique` and prints
//! its canonical form (canonical.rs) through [`TechniqueParams`].

use super::Technique;
use super::canonical::CanonicalFields;
use serde::{Deserialize, Serialize};
use serde_json::{Map, Value};

/// One technique's parameters, as `TechniqueSpec` holds them.
pub trait TechniqueParams: ParametersJson {
    /// Checks the parameters: numbers finite and, where below zero means nothing, not negative;
    /// each parameter used only where it belongs.
    fn validate(&self) -> Result<(), TechniqueSpecError>;

    /// The technique to run; `None` for a technique whose visibility is imported from another
    /// renderer's files instead of shaded here (`external.rs`).
    fn build(&self) -> Option<Box<dyn Technique>>;

    /// The reference the technique's output means the same thing as.
    fn reference_kind(&self) -> ReferenceKind {
        ReferenceKind::Hard
    }

    /// Every field, with the defaults `build` uses filled in (canonical.rs).
    fn canonical_fields(&self, fields: &mut CanonicalFields);

    /// The parameters a label shows: all of them, unless some are too long to read in one.
    fn label_parameters(&self) -> Map<String, Value> {
        self.parameters()
    }
}

/// The parameters alone as a JSON object (a record's `parameters`), for every serializable
/// parameter struct: serde writes the same fields the spec does, less its `technique` tag.
pub trait ParametersJson {
    fn parameters(&self) -> Map<String, Value>;
}

impl<T: Serialize> ParametersJson for T {
    fn parameters(&self) -> Map<String, Value> {
        match serde_json::to_value(self) {
            Ok(Value::Object(m)) => m,
            _ => Map::new(),
        }
    }
}

/// Which reference a technique's output is scored against.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum ReferenceKind {
    /// The exact hard visibility of each pixel's surface point.
    Hard,
    /// Hard visibility averaged over a pixel's sub-pixel grid (filtered techniques).
    Coverage,
    /// The fraction of an area light each point sees (soft shadows).
    AreaLight,
}

/// A parameter problem: the parameter at fault (when one is) and what is wrong.
#[derive(Clone, Debug, PartialEq, thiserror::Error)]
#[error("{}{message}", field.map(|f| format!("{f}: ")).unwrap_or_default())]
pub struct TechniqueSpecError {
    pub field: Option<&'static str>,
    pub message: String,
}

pub(super) fn err(field: &'static str, message: impl Into<String>) -> TechniqueSpecError {
    TechniqueSpecError { field: Some(field), message: message.into() }
}

/// Distances, offsets and scales that have no meaning below zero (a negative bias moves the
/// comparison towards more acne, never less).
pub(super) fn non_negative(field: &'static str, x: f64) -> Result<(), TechniqueSpecError> {
    if x.is_finite() && x >= 0.0 {
        Ok(())
    } else {
        Err(err(field, format!("must be a finite number ≥ 0, found {x}")))
    }
}

pub(super) fn non_negative_opt(field: &'static str, x: Option<f64>) -> Result<(), TechniqueSpecError> {
    x.map_or(Ok(()), |x| non_negative(field, x))
}
