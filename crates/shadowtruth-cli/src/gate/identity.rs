//! Which baseline run is the same run as a run of the report: the same view (scene, camera,
//! light), the same map (resolution, depth format), the same reference (kind and samples) and the
//! same technique with the same parameters. Parameters are compared in canonical form
//! (`TechniqueSpec::canonical`), so two reports pair however their parameters were printed; the
//! label is printed from the parameters, so it is shown but never compared.

use serde_json::Value;
use shadowtruth::record::RunRecord;
use shadowtruth::technique::{ReferenceKind, TechniqueSpec, canonical_json};
use std::collections::HashMap;
use std::fmt;

/// The technique of a run with its parameters, in a form that ignores how they were printed.
#[derive(Clone, Debug, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub enum TechniqueIdentity {
    /// Parameters this version reads: [`TechniqueSpec::canonical`].
    Spec(String),
    /// Parameters it cannot read (a report of another version): the technique and its parameters
    /// as canonical JSON. A variant of its own, so it never equals a parsed one.
    Unparsed(String),
}

impl TechniqueIdentity {
    pub fn of(run: &RunRecord) -> Self {
        Self::parse(run).map(|spec| Self::Spec(spec.canonical())).unwrap_or_else(|| {
            let raw = serde_json::json!({ "technique": run.technique, "parameters": run.parameters });
            Self::Unparsed(canonical_json(&raw))
        })
    }

    /// `{"technique": ..., ...parameters}` as a spec, when it reads as one.
    fn parse(run: &RunRecord) -> Option<TechniqueSpec> {
        // A `technique` key among the parameters would be overwritten and lost.
        if run.parameters.contains_key("technique") {
            return None;
        }
        let mut object = run.parameters.clone();
        object.insert("technique".into(), Value::String(run.technique.clone()));
        serde_json::from_value(Value::Object(object)).ok()
    }
}

/// What pairs a run with its baseline run.
#[derive(Clone, Debug, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub struct RunIdentity {
    pub scene: String,
    pub camera: String,
    pub light: String,
    pub resolution: u32,
    pub depth_format: String,
    /// The reference kind by its report name (`hard`, `coverage`, `area_light`).
    pub reference: &'static str,
    pub samples: u32,
    pub technique: TechniqueIdentity,
}

impl RunIdentity {
    pub fn of(run: &RunRecord) -> Self {
        RunIdentity {
            scene: run.scene.clone(),
            camera: run.camera.clone(),
            light: run.light.clone(),
            resolution: run.resolution,
            depth_format: run.depth_format.clone(),
            reference: reference_name(run.reference.kind),
            samples: run.reference.samples,
            technique: TechniqueIdentity::of(run),
        }
    }
}

fn reference_name(kind: ReferenceKind) -> &'static str {
    match kind {
        ReferenceKind::Hard => "hard",
        ReferenceKind::Coverage => "coverage",
        ReferenceKind::AreaLight => "area_light",
    }
}

/// A run as messages name it: `scene/camera/light label @resolution format [reference×samples]`.
#[derive(Clone, Debug, PartialEq)]
pub struct RunName {
    pub scene: String,
    pub camera: String,
    pub light: String,
    pub label: String,
    pub resolution: u32,
    pub depth_format: String,
    pub reference: &'static str,
    pub samples: u32,
}

impl RunName {
    pub fn of(run: &RunRecord) -> Self {
        RunName {
            scene: run.scene.clone(),
            camera: run.camera.clone(),
            light: run.light.clone(),
            label: run.label.clone(),
            resolution: run.resolution,
            depth_format: run.depth_format.clone(),
            reference: reference_name(run.reference.kind),
            samples: run.reference.samples,
        }
    }
}

impl fmt::Display for RunName {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(
            f,
            "{}/{}/{} {} @{} {} [{}×{}]",
            self.scene,
            self.camera,
            self.light,
            self.label,
            self.resolution,
            self.depth_format,
            self.reference,
            self.samples
        )
    }
}

/// The runs of a report matched with those of its baseline. Identities are unique within a
/// checked report, so each run has at most one partner.
#[derive(Clone, Debug, PartialEq)]
pub struct Pairing {
    /// For each run of the report, the index of its baseline run.
    pub partner: Vec<Option<usize>>,
    /// Baseline runs no run of the report pairs with, in baseline order.
    pub missing: Vec<usize>,
}

impl Pairing {
    pub fn new(report: &[RunIdentity], baseline: &[RunIdentity]) -> Self {
        let mut unpaired: HashMap<&RunIdentity, usize> =
            baseline.iter().enumerate().map(|(i, id)| (id, i)).collect();
        let partner: Vec<Option<usize>> = report.iter().map(|id| unpaired.remove(id)).collect();
        let mut missing: Vec<usize> = unpaired.into_values().collect();
        missing.sort_unstable();
        Pairing { partner, missing }
    }

    /// Runs of the report that pair with a baseline run.
    pub fn paired(&self) -> usize {
        self.partner.iter().flatten().count()
    }

    /// Runs of the report absent from the baseline, in report order.
    pub fn new_runs(&self) -> impl Iterator<Item = usize> + '_ {
        self.partner.iter().enumerate().filter(|(_, p)| p.is_none()).map(|(i, _)| i)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use serde_json::json;
    use shadowtruth::record::{ReferenceUsed, Timings};

    fn run(technique: &str, parameters: Value, label: &str) -> RunRecord {
        RunRecord {
            scene: "plane_box".into(),
            camera: "main".into(),
            light: "sun".into(),
            technique: technique.into(),
            parameters: parameters.as_object().cloned().expect("an object"),
            label: label.into(),
            resolution: 1024,
            depth_format: "f32".into(),
            counts: Default::default(),
            rates: Default::default(),
            timings: Timings::default(),
            layer_memory_bytes: 0,
            reference: Default::default(),
            soft: None,
            pipeline: None,
            cascades: None,
            point_map: None,
            temporal: None,
        }
    }

    #[test]
    fn printing_and_labels_do_not_change_the_identity() {
        let a = run("constant", json!({"bias_depth": 0.001}), "constant(bias_depth=0.001)");
        let b = run("constant", serde_json::from_str(r#"{"bias_depth": 1e-3}"#).unwrap(), "renamed");
        assert_eq!(RunIdentity::of(&a), RunIdentity::of(&b));
        let c = run("slope_scaled", json!({"factor": 2, "units": 4}), "s");
        let d = run("slope_scaled", json!({"units": 4.0, "cull": "none", "factor": 2.0}), "t");
        assert_eq!(RunIdentity::of(&c), RunIdentity::of(&d));
    }

    #[test]
    fn parameters_reference_and_place_change_the_identity() {
        let a = run("constant", json!({"bias_depth": 0.001}), "x");
        let base = RunIdentity::of(&a);
        let mut renamed = a.clone();
        renamed.parameters = json!({"bias_world": 0.001}).as_object().cloned().unwrap();
        let mut coverage = a.clone();
        coverage.reference = ReferenceUsed { kind: ReferenceKind::Coverage, samples: 16 };
        let mut more_samples = a.clone();
        more_samples.reference.samples = 4;
        let mut elsewhere = a.clone();
        elsewhere.depth_format = "unorm24".into();
        for other in [renamed, coverage, more_samples, elsewhere] {
            assert_ne!(RunIdentity::of(&other), base, "{}", RunName::of(&other));
        }
    }

    #[test]
    fn parameters_as_reports_write_them_read_back_as_the_spec() {
        let specs = [
            json!({"technique": "none"}),
            json!({"technique": "constant", "bias_world": 0.02}),
            json!({"technique": "slope_scaled", "factor": 1.5, "units": 2.0, "cull": "back"}),
            json!({"technique": "normal_offset", "scale_texels": 1.0, "falloff": "one_minus_n_dot_l"}),
            json!({"technique": "dual", "z_offset": 0.01, "cull_back_faces": true}),
            json!({"technique": "adaptive", "k": 2e-4, "epsilon": "ehm"}),
            json!({"technique": "pcf", "kernel": "poisson", "taps": 25, "bias": "adaptive_delta"}),
            json!({"technique": "pcf", "layers": "midpoint", "bias": "slope_scaled", "factor": 1.0}),
            json!({"technique": "mdsm", "depths": 3, "select": "max", "kernel": "jitter4x4"}),
            json!({"technique": "pcss", "filter_taps": 9, "bias": "constant", "bias_depth": 0.001}),
        ];
        for value in specs {
            let spec: TechniqueSpec = serde_json::from_value(value.clone()).unwrap();
            let written = run(spec.name(), Value::Object(spec.parameters()), &spec.label());
            assert_eq!(TechniqueIdentity::of(&written), TechniqueIdentity::Spec(spec.canonical()), "{value}");
        }
    }

    #[test]
    fn unreadable_parameters_fall_back_to_canonical_json() {
        let old = run("constant", json!({"depth_bias": 0.001}), "x");
        let printed_otherwise =
            run("constant", serde_json::from_str(r#"{"depth_bias": 1e-3}"#).unwrap(), "y");
        let id = TechniqueIdentity::of(&old);
        assert_eq!(
            id,
            TechniqueIdentity::Unparsed(
                r#"{"parameters":{"depth_bias":0.001},"technique":"constant"}"#.into()
            )
        );
        assert_eq!(TechniqueIdentity::of(&printed_otherwise), id);
        let unknown = run("future", json!({}), "future");
        assert!(matches!(TechniqueIdentity::of(&unknown), TechniqueIdentity::Unparsed(_)));
        let smuggled = run("none", json!({"technique": "none"}), "none");
        assert!(matches!(TechniqueIdentity::of(&smuggled), TechniqueIdentity::Unparsed(_)));
    }

    #[test]
    fn pairing_lists_missing_and_new_runs() {
        let id = |scene: &str| {
            let mut r = run("none", json!({}), "none");
            r.scene = scene.into();
            RunIdentity::of(&r)
        };
        let p = Pairing::new(&[id("a"), id("c"), id("d")], &[id("a"), id("b"), id("c"), id("e")]);
        assert_eq!(p.partner, vec![Some(0), Some(2), None]);
        assert_eq!(p.missing, vec![1, 3]);
        assert_eq!(p.paired(), 2);
        assert_eq!(p.new_runs().collect::<Vec<_>>(), vec![2]);
    }

    #[test]
    fn names_show_the_label_and_the_reference() {
        let a = run("constant", json!({"bias_depth": 0.001}), "constant(bias_depth=0.001)");
        assert_eq!(
            RunName::of(&a).to_string(),
            "plane_box/main/sun constant(bias_depth=0.001) @1024 f32 [hard×1]"
        );
    }
}
