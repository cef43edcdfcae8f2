//! f32 values as JSON numbers, for view.json and the GLB's JSON chunk alike.

use serde_json::Value;

/// An f32 as the JSON number of its shortest decimal (which reads back as the same f32), not
/// of its f64 widening.
pub(super) fn num(x: f32) -> Value {
    let shortest: f64 = x.to_string().parse().unwrap_or(x as f64);
    let exact = if shortest as f32 == x || x.is_nan() { shortest } else { x as f64 };
    serde_json::Number::from_f64(exact).map_or(Value::Null, Value::Number)
}

pub(super) fn nums(xs: &[f32]) -> Value {
    Value::Array(xs.iter().map(|&x| num(x)).collect())
}
