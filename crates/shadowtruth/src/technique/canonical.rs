//! One text per technique, however its parameters were written: the gate pairs a run with its
//! baseline run by it, so key order, `0.001` against `1e-3`, or a default written out against
//! one left out must not tell two runs apart.
//!
//! A spec's canonical form fills in every default its technique is built with (each parameter
//! struct's `build`), keeps the fields it was given that its technique does not read, and prints
//! the fields sorted by name with numbers printed from their f64 values:
//! `pcf(bias=constant,bias_depth=0.0,kernel=box,layers=nearest,size=3)`. Each parameter struct
//! writes its fields ([`super::TechniqueParams::canonical_fields`]); this file prints them
//! (`TechniqueSpec::canonical`, in spec.rs, puts the two together).

use serde::Serialize;
use serde_json::Value;
use std::collections::BTreeMap;

/// The field values of one spec, sorted by name.
#[derive(Default)]
pub struct CanonicalFields(BTreeMap<&'static str, String>);

impl CanonicalFields {
    pub(super) fn number(&mut self, key: &'static str, value: f64) {
        self.0.insert(key, canonical_number(value));
    }

    pub(super) fn count(&mut self, key: &'static str, value: u32) {
        self.0.insert(key, value.to_string());
    }

    pub(super) fn flag(&mut self, key: &'static str, value: bool) {
        self.0.insert(key, value.to_string());
    }

    /// An enum value by its serde name (`jitter4x4`, `receiver_plane`).
    pub(super) fn named(&mut self, key: &'static str, value: impl Serialize) {
        let name = match serde_json::to_value(value) {
            Ok(Value::String(s)) => s,
            other => format!("{other:?}"),
        };
        self.0.insert(key, name);
    }

    pub(super) fn number_if_given(&mut self, key: &'static str, value: Option<f64>) {
        if let Some(v) = value {
            self.number(key, v);
        }
    }

    pub(super) fn count_if_given(&mut self, key: &'static str, value: Option<u32>) {
        if let Some(v) = value {
            self.count(key, v);
        }
    }

    /// `name(key=value,...)`, or `name` alone without fields.
    pub(super) fn render(self, name: &str) -> String {
        if self.0.is_empty() {
            return name.to_string();
        }
        let inner: Vec<String> = self.0.into_iter().map(|(k, v)| format!("{k}={v}")).collect();
        format!("{name}({})", inner.join(","))
    }
}

/// A number printed from its f64 value, one way only (`-0.0` is `0.0`: the same bias).
fn canonical_number(value: f64) -> String {
    let value = if value == 0.0 { 0.0 } else { value };
    format!("{value:?}")
}

/// JSON with object keys sorted, numbers printed from their f64 values and no spaces: one text
/// for values that differ only in how they were printed. For parameters a
/// [`TechniqueSpec`](super::TechniqueSpec) cannot read.
pub fn canonical_json(value: &Value) -> String {
    match value {
        Value::Null | Value::Bool(_) | Value::String(_) => value.to_string(),
        Value::Number(n) => n.as_f64().map(canonical_number).unwrap_or_else(|| n.to_string()),
        Value::Array(items) => {
            let inner: Vec<String> = items.iter().map(canonical_json).collect();
            format!("[{}]", inner.join(","))
        }
        Value::Object(map) => {
            let sorted: BTreeMap<&String, &Value> = map.iter().collect();
            let inner: Vec<String> = sorted
                .into_iter()
                .map(|(k, v)| format!("{}:{}", Value::String(k.clone()), canonical_json(v)))
                .collect();
            format!("{{{}}}", inner.join(","))
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::technique::TechniqueSpec;
    use serde_json::json;

    fn spec(value: Value) -> TechniqueSpec {
        serde_json::from_value(value.clone()).unwrap_or_else(|e| panic!("{value}: {e}"))
    }

    fn canonical(text: &str) -> String {
        spec(serde_json::from_str(text).unwrap()).canonical()
    }

    #[test]
    fn printing_does_not_change_the_canonical_form() {
        let same = [
            r#"{"technique": "constant", "bias_depth": 0.001}"#,
            r#"{"bias_depth": 1e-3, "technique": "constant"}"#,
            r#"{"technique": "constant", "bias_depth": 0.0010}"#,
        ];
        for text in same {
            assert_eq!(canonical(text), "constant(bias_depth=0.001)", "{text}");
        }
        assert_eq!(
            canonical(r#"{"technique": "slope_scaled", "factor": 2, "units": 4}"#),
            canonical(r#"{"technique": "slope_scaled", "units": 4.0, "cull": "none", "factor": 2.0}"#)
        );
        assert_eq!(canonical(r#"{"technique": "constant", "bias_depth": -0.0}"#), "constant(bias_depth=0.0)");
    }

    #[test]
    fn defaults_are_filled_in() {
        let pairs = [
            (
                json!({"technique": "pcf"}),
                json!({"technique": "pcf", "kernel": "box", "size": 3, "bias": "constant", "bias_depth": 0}),
            ),
            (
                json!({"technique": "pcf", "kernel": "poisson"}),
                json!({"technique": "pcf", "kernel": "poisson", "taps": 16, "radius_texels": 1.5}),
            ),
            (
                json!({"technique": "pcf", "kernel": "jitter4x4"}),
                json!({"technique": "pcf", "kernel": "jitter4x4", "radius_texels": 2.0}),
            ),
            (
                json!({"technique": "pcf", "bias": "adaptive"}),
                json!({"technique": "pcf", "bias": "adaptive", "k": 1e-4, "epsilon": "original"}),
            ),
            (
                json!({"technique": "pcf", "layers": "dual", "z_offset": 0.01}),
                json!({"technique": "pcf", "layers": "dual", "z_offset": 0.01, "cull_back_faces": false}),
            ),
            (
                json!({"technique": "pcf", "bias": "slope_scaled"}),
                json!({"technique": "pcf", "bias": "slope_scaled", "factor": 0, "units": 0}),
            ),
            (
                json!({"technique": "mdsm", "depths": 2}),
                json!({"technique": "mdsm", "depths": 2, "size": 1, "neighbourhood": 3, "select": "min_max"}),
            ),
            (
                json!({"technique": "pcss"}),
                json!({
                    "technique": "pcss", "search_taps": 25, "filter_taps": 25,
                    "bias": "receiver_plane", "bias_depth": 0
                }),
            ),
            (json!({"technique": "constant"}), json!({"technique": "constant", "bias_depth": 0})),
            (
                json!({"technique": "adaptive"}),
                json!({"technique": "adaptive", "k": 0.0001, "epsilon": "original"}),
            ),
        ];
        for (short, long) in pairs {
            assert_eq!(spec(short.clone()).canonical(), spec(long.clone()).canonical(), "{short} vs {long}");
        }
        assert_eq!(
            spec(json!({"technique": "pcf"})).canonical(),
            "pcf(bias=constant,bias_depth=0.0,kernel=box,layers=nearest,size=3)"
        );
    }

    #[test]
    fn different_parameters_differ() {
        let distinct = [
            json!({"technique": "constant", "bias_depth": 0.001}),
            json!({"technique": "constant", "bias_world": 0.001}),
            json!({"technique": "constant", "bias_depth": 0.002}),
            json!({"technique": "receiver_plane", "bias_depth": 0.001}),
            json!({"technique": "second_depth", "bias_depth": 0.001}),
            json!({"technique": "pcf", "size": 5}),
            json!({"technique": "pcf", "kernel": "poisson", "taps": 25}),
            json!({"technique": "pcf", "kernel": "poisson", "radius_texels": 2.0}),
            json!({"technique": "pcf", "bias": "adaptive", "epsilon": "ehm"}),
            json!({"technique": "mdsm", "depths": 2, "size": 3}),
            json!({"technique": "slope_scaled", "factor": 2.0, "units": 4.0, "cull": "back"}),
            json!({"technique": "slope_scaled", "factor": 2.0, "units": 4.0}),
        ];
        let forms: Vec<String> = distinct.iter().map(|v| spec(v.clone()).canonical()).collect();
        for (i, a) in forms.iter().enumerate() {
            for b in &forms[i + 1..] {
                assert_ne!(a, b);
            }
        }
    }

    #[test]
    fn canonical_json_sorts_keys_and_reads_numbers() {
        let a: Value = serde_json::from_str(r#"{"b": [1, 2.50], "a": {"y": 1e-3, "x": "s"}}"#).unwrap();
        let b: Value = serde_json::from_str(r#"{"a": {"x": "s", "y": 0.001}, "b": [1.0, 2.5]}"#).unwrap();
        assert_eq!(canonical_json(&a), canonical_json(&b));
        assert_eq!(canonical_json(&a), r#"{"a":{"x":"s","y":0.001},"b":[1.0,2.5]}"#);
    }
}
