//! The `extras` that `shadowtruth view-export` writes (src/view_export/glb.rs): a node's
//! `closed`, a camera's `width` and `height`, a light node's `near`, `far`, `cone_deg` and size.
//! Other tools' extras are ignored unless they use these keys with a wrong type.

use super::problem::GltfProblem;
use serde_json::{Map, Value};

/// The extras object of one glTF object (empty when absent or not a JSON object).
pub(super) struct Extras {
    map: Map<String, Value>,
    /// JSON path of the extras, e.g. `nodes[3].extras`.
    path: String,
}

impl Extras {
    pub(super) fn read(raw: &gltf::json::Extras, owner: &str) -> Self {
        let map = raw
            .as_ref()
            .and_then(|raw| serde_json::from_str::<Value>(raw.get()).ok())
            .and_then(|v| match v {
                Value::Object(map) => Some(map),
                _ => None,
            })
            .unwrap_or_default();
        Extras { map, path: format!("{owner}.extras") }
    }

    /// A problem at `key` of the extras (`""` for the extras themselves).
    pub(super) fn problem(&self, key: &str, message: impl Into<String>) -> GltfProblem {
        let path = if key.is_empty() { self.path.clone() } else { format!("{}.{key}", self.path) };
        GltfProblem::new(path, message)
    }

    /// The value at `key` converted by one of json_input's converters; a bad value is reported.
    pub(super) fn get<T>(
        &self,
        key: &str,
        convert: impl Fn(&Value) -> Result<T, String>,
        problems: &mut Vec<GltfProblem>,
    ) -> Option<T> {
        let value = self.map.get(key)?;
        convert(value).map_err(|m| problems.push(self.problem(key, m))).ok()
    }
}
