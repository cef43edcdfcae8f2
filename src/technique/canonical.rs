//! One text per technique, however its parameters were written: the gate pairs a run with its
//! baseline run by it, so key order, `0.001` against `1e-3`, or a default written out against
//! one left out must not tell two runs apart.
//!
//! A spec's canonical form fills in every default its technique is built with (the defaults of
//! `build` in spec.rs), keeps the fields it was given that its technique does not read, and prints
//! the fields sorted by name with numbers printed from their f64 values:
//! `pcf(bias=constant,bias_depth=0.0,kernel=box,layers=nearest,size=3)`.

use super::{EpsilonSpec, KernelSpec, LayerSpec, TapBiasSpec, TechniqueSpec};
use serde::Serialize;
use serde_json::Value;
use std::collections::BTreeMap;

/// The field values of one spec, sorted by name.
#[derive(Default)]
struct Fields(BTreeMap<&'static str, String>);

impl Fields {
    fn number(&mut self, key: &'static str, value: f64) {
        self.0.insert(key, canonical_number(value));
    }

    fn count(&mut self, key: &'static str, value: u32) {
        self.0.insert(key, value.to_string());
    }

    fn flag(&mut self, key: &'static str, value: bool) {
        self.0.insert(key, value.to_string());
    }

    /// An enum value by its serde name (`jitter4x4`, `receiver_plane`).
    fn named(&mut self, key: &'static str, value: impl Serialize) {
        let name = match serde_json::to_value(value) {
            Ok(Value::String(s)) => s,
            other => format!("{other:?}"),
        };
        self.0.insert(key, name);
    }

    fn number_if_given(&mut self, key: &'static str, value: Option<f64>) {
        if let Some(v) = value {
            self.number(key, v);
        }
    }

    fn count_if_given(&mut self, key: &'static str, value: Option<u32>) {
        if let Some(v) = value {
            self.count(key, v);
        }
    }

    /// `name(key=value,...)`, or `name` alone without fields.
    fn render(self, name: &str) -> String {
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

/// The kernel fields: the size of a box (`default_size` when omitted), the taps of a Poisson
/// kernel (16) and the radius of Poisson (1.5) and jitter (2.0) kernels.
fn kernel_fields(
    f: &mut Fields,
    kernel: KernelSpec,
    size: Option<u32>,
    taps: Option<u32>,
    radius_texels: Option<f64>,
    default_size: u32,
) {
    f.named("kernel", kernel);
    match kernel {
        KernelSpec::Box => f.count("size", size.unwrap_or(default_size)),
        _ => f.count_if_given("size", size),
    }
    match kernel {
        KernelSpec::Poisson => f.count("taps", taps.unwrap_or(16)),
        _ => f.count_if_given("taps", taps),
    }
    match kernel {
        KernelSpec::Poisson => f.number("radius_texels", radius_texels.unwrap_or(1.5)),
        KernelSpec::Jitter4x4 => f.number("radius_texels", radius_texels.unwrap_or(2.0)),
        _ => f.number_if_given("radius_texels", radius_texels),
    }
}

/// The per-tap bias fields: `bias_depth` (0) for the constant and receiver-plane biases, `k`
/// (1e-4) and `epsilon` (original) for the adaptive ones.
fn tap_bias_fields(
    f: &mut Fields,
    bias: TapBiasSpec,
    bias_depth: Option<f64>,
    k: Option<f64>,
    epsilon: Option<EpsilonSpec>,
) {
    f.named("bias", bias);
    match bias {
        TapBiasSpec::Constant | TapBiasSpec::ReceiverPlane => {
            f.number("bias_depth", bias_depth.unwrap_or(0.0))
        }
        _ => f.number_if_given("bias_depth", bias_depth),
    }
    let adaptive = matches!(bias, TapBiasSpec::Adaptive | TapBiasSpec::AdaptiveDelta);
    if adaptive {
        f.number("k", k.unwrap_or(1e-4));
        f.named("epsilon", epsilon.unwrap_or_default());
    } else {
        f.number_if_given("k", k);
        if let Some(e) = epsilon {
            f.named("epsilon", e);
        }
    }
}

/// The depth-layer fields of PCF: `z_offset` (0) for dual layers, `cull_back_faces` (false) for
/// midpoint and dual layers.
fn layer_fields(f: &mut Fields, layers: LayerSpec, z_offset: Option<f64>, cull_back_faces: Option<bool>) {
    f.named("layers", layers);
    match layers {
        LayerSpec::Dual => f.number("z_offset", z_offset.unwrap_or(0.0)),
        _ => f.number_if_given("z_offset", z_offset),
    }
    match (layers, cull_back_faces) {
        (LayerSpec::Midpoint | LayerSpec::Dual, c) => f.flag("cull_back_faces", c.unwrap_or(false)),
        (_, Some(c)) => f.flag("cull_back_faces", c),
        (_, None) => {}
    }
}

impl TechniqueSpec {
    /// The technique and its parameters with every default filled in, sorted, numbers printed
    /// from their f64 values: equal for two specs exactly when they are the same technique with
    /// the same parameters, however each was written.
    pub fn canonical(&self) -> String {
        let mut f = Fields::default();
        match *self {
            TechniqueSpec::None => {}
            TechniqueSpec::Constant { bias_depth, bias_world } => {
                // A world-space bias wins when both are given (spec.rs `build`).
                match bias_world {
                    None => f.number("bias_depth", bias_depth.unwrap_or(0.0)),
                    Some(w) => {
                        f.number("bias_world", w);
                        f.number_if_given("bias_depth", bias_depth);
                    }
                }
            }
            TechniqueSpec::SlopeScaled { factor, units, cull } => {
                f.number("factor", factor);
                f.number("units", units);
                f.named("cull", cull);
            }
            TechniqueSpec::NormalOffset { scale_texels, falloff } => {
                f.number("scale_texels", scale_texels);
                f.named("falloff", falloff);
            }
            TechniqueSpec::ReceiverPlane { bias_depth } | TechniqueSpec::SecondDepth { bias_depth } => {
                f.number("bias_depth", bias_depth)
            }
            TechniqueSpec::Midpoint { cull_back_faces } => f.flag("cull_back_faces", cull_back_faces),
            TechniqueSpec::Dual { z_offset, cull_back_faces } => {
                f.number("z_offset", z_offset);
                f.flag("cull_back_faces", cull_back_faces);
            }
            TechniqueSpec::Adaptive { k, epsilon } => {
                f.number("k", k);
                f.named("epsilon", epsilon);
            }
            TechniqueSpec::Pcf {
                kernel,
                size,
                taps,
                radius_texels,
                bias,
                bias_depth,
                factor,
                units,
                k,
                epsilon,
                layers,
                z_offset,
                cull_back_faces,
            } => {
                kernel_fields(&mut f, kernel, size, taps, radius_texels, 3);
                tap_bias_fields(&mut f, bias, bias_depth, k, epsilon);
                if bias == TapBiasSpec::SlopeScaled {
                    f.number("factor", factor.unwrap_or(0.0));
                    f.number("units", units.unwrap_or(0.0));
                } else {
                    f.number_if_given("factor", factor);
                    f.number_if_given("units", units);
                }
                layer_fields(&mut f, layers, z_offset, cull_back_faces);
            }
            TechniqueSpec::Mdsm {
                depths,
                neighbourhood,
                select,
                kernel,
                size,
                taps,
                radius_texels,
                bias,
                bias_depth,
                k,
                epsilon,
            } => {
                f.count("depths", depths);
                f.count("neighbourhood", neighbourhood);
                f.named("select", select);
                kernel_fields(&mut f, kernel, size, taps, radius_texels, 1);
                tap_bias_fields(&mut f, bias, bias_depth, k, epsilon);
            }
            TechniqueSpec::Pcss { search_taps, filter_taps, bias, bias_depth, k, epsilon } => {
                f.count("search_taps", search_taps);
                f.count("filter_taps", filter_taps);
                tap_bias_fields(&mut f, bias, bias_depth, k, epsilon);
            }
        }
        f.render(self.name())
    }
}

/// JSON with object keys sorted, numbers printed from their f64 values and no spaces: one text
/// for values that differ only in how they were printed. For parameters a [`TechniqueSpec`]
/// cannot read.
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
