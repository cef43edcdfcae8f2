//! How many runs a plan expands to, counted from its lists' lengths before anything is expanded,
//! and the lazy expansion of a technique entry into its variants.

use serde_json::{Map, Value};
use shadowtruth::technique::COMMAND_LIST_FIELDS;

/// One entry of a plan's `techniques`: a JSON object whose list-valued parameters sweep.
#[derive(Clone, Debug)]
pub(crate) struct TechniqueEntry {
    /// JSON path of the entry, e.g. `techniques[3]`.
    pub path: String,
    pub map: Map<String, Value>,
}

/// One combination of an entry's swept values.
pub(crate) struct Variant {
    pub map: Map<String, Value>,
    /// For each swept key, the index of its value in the entry's list.
    swept: Vec<(String, usize)>,
}

impl Variant {
    /// JSON path of `key` in the plan (`techniques[3].bias_depth[2]` for a swept key), or of the
    /// entry itself when the key is unknown.
    pub fn path_of(&self, entry_path: &str, key: Option<&str>) -> String {
        match key {
            None => entry_path.to_string(),
            Some(key) => match self.swept.iter().find(|(k, _)| k == key) {
                Some((_, i)) => format!("{entry_path}.{key}[{i}]"),
                None => format!("{entry_path}.{key}"),
            },
        }
    }
}

impl TechniqueEntry {
    /// The swept keys with their number of values, in the map's (alphabetical) order.
    fn sweeps(&self) -> impl Iterator<Item = (&String, usize)> {
        self.map
            .iter()
            .filter(|(k, _)| self.sweeps_key(k))
            .filter_map(|(k, v)| v.as_array().map(|list| (k, list.len())))
    }

    /// Whether a list under `key` sweeps: not for a field whose value is itself a list (a
    /// command technique's command line).
    fn sweeps_key(&self, key: &str) -> bool {
        let command = self.map.get("technique").and_then(Value::as_str) == Some("command");
        !(command && COMMAND_LIST_FIELDS.contains(&key))
    }

    /// The number of variants (saturating).
    pub fn variant_count(&self) -> u128 {
        self.sweeps().fold(1u128, |n, (_, len)| n.saturating_mul(len as u128))
    }

    /// `bias_depth: 1000 values × factor: 1000 values`, or `one setting`.
    fn describe_sweeps(&self) -> String {
        let parts: Vec<String> = self.sweeps().map(|(k, n)| format!("{k}: {n} values")).collect();
        if parts.is_empty() { "one setting".into() } else { parts.join(" × ") }
    }

    /// Every variant, keys in alphabetical order, the first key's values varying slowest.
    pub fn variants(&self) -> impl Iterator<Item = Variant> + '_ {
        let count = self.variant_count();
        (0..count).map(move |mut n| {
            let mut map = self.map.clone();
            let mut swept = Vec::new();
            for (key, value) in self.map.iter().rev().filter(|(k, _)| self.sweeps_key(k)) {
                if let Value::Array(list) = value {
                    let i = (n % list.len() as u128) as usize;
                    n /= list.len() as u128;
                    map.insert(key.clone(), list[i].clone());
                    swept.push((key.clone(), i));
                }
            }
            Variant { map, swept }
        })
    }
}

/// The factors of a plan's run count.
pub(crate) struct PlanSize<'a> {
    pub entries: &'a [TechniqueEntry],
    pub resolutions: u64,
    pub depth_formats: u64,
    /// Scenes, cameras and lights named (1 where the plan leaves them to the scene files: the
    /// count is then a lower bound).
    pub scenes: u64,
    pub cameras: u64,
    pub lights: u64,
}

impl PlanSize<'_> {
    /// The number of runs (saturating), at least.
    pub fn runs(&self) -> u128 {
        let techniques = self.entries.iter().fold(0u128, |n, e| n.saturating_add(e.variant_count()));
        [self.resolutions, self.depth_formats, self.scenes, self.cameras, self.lights]
            .iter()
            .fold(techniques, |n, &f| n.saturating_mul(f as u128))
    }

    /// `None` when the plan fits in `max_runs`; else the JSON path of the entry that multiplies
    /// it most and the message.
    pub fn refusal(&self, max_runs: u64) -> Option<(String, String)> {
        let runs = self.runs();
        if runs <= max_runs as u128 {
            return None;
        }
        let biggest = self.entries.iter().max_by_key(|e| e.variant_count())?;
        let message = format!(
            "the plan expands to at least {runs} runs, more than the limit of {max_runs} (raise it with \
             --max-runs): this entry alone gives {} settings ({}), × {} resolutions × {} depth formats",
            biggest.variant_count(),
            biggest.describe_sweeps(),
            self.resolutions,
            self.depth_formats
        );
        Some((biggest.path.clone(), message))
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use serde_json::json;

    fn entry(value: Value) -> TechniqueEntry {
        TechniqueEntry { path: "techniques[0]".into(), map: value.as_object().unwrap().clone() }
    }

    #[test]
    fn variants_vary_the_alphabetically_first_key_slowest() {
        let e = entry(json!({"technique": "pcf", "size": [3, 5], "bias_depth": [0.1, 0.2, 0.3]}));
        assert_eq!(e.variant_count(), 6);
        let got: Vec<(u64, f64)> = e
            .variants()
            .map(|v| (v.map["size"].as_u64().unwrap(), v.map["bias_depth"].as_f64().unwrap()))
            .collect();
        assert_eq!(got, [(3, 0.1), (5, 0.1), (3, 0.2), (5, 0.2), (3, 0.3), (5, 0.3)]);
        let last = e.variants().last().unwrap();
        assert_eq!(last.path_of("techniques[0]", Some("bias_depth")), "techniques[0].bias_depth[2]");
        assert_eq!(last.path_of("techniques[0]", Some("technique")), "techniques[0].technique");
    }

    #[test]
    fn a_command_line_is_one_value_and_its_settings_sweep() {
        let run = json!(["node", "render.mjs", "{visibility}", "{bias}"]);
        let e = entry(json!({"technique": "command", "name": "three", "run": run, "bias": [-0.001, 0]}));
        assert_eq!(e.variant_count(), 2);
        for v in e.variants() {
            assert_eq!(v.map["run"], run);
        }
        // Elsewhere a list is a sweep, whatever its key.
        assert_eq!(entry(json!({"technique": "pcf", "run": [1, 2, 3]})).variant_count(), 3);
    }

    #[test]
    fn a_huge_plan_is_counted_not_expanded() {
        let values: Vec<u32> = (0..10_000).collect();
        let e = entry(json!({"technique": "slope_scaled", "factor": values, "units": values}));
        let entries = [e];
        let size = PlanSize {
            entries: &entries,
            resolutions: 4,
            depth_formats: 1,
            scenes: 1,
            cameras: 1,
            lights: 1,
        };
        assert_eq!(size.runs(), 400_000_000);
        let (at, message) = size.refusal(100_000).expect("refused");
        assert_eq!(at, "techniques[0]");
        assert!(
            message.contains("400000000 runs") && message.contains("factor: 10000 values × units"),
            "{message}"
        );
        assert!(size.refusal(400_000_000).is_none());
    }
}
