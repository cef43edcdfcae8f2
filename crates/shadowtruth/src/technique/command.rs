//! `command`: another renderer run by shadowtruth itself, once per setting, through one protocol
//! (docs/engines.md): the view is exported once (`view-export`'s folder), the command line `run`
//! is filled in — `{view}` the exported folder, `{visibility}` and `{depth}` the files the
//! renderer writes, `{resolution}` the plan's shadow-map resolution, `{scene}`, `{camera}`,
//! `{light}` the view's names, and `{NAME}` each of the entry's own settings — and what the
//! renderer wrote is read back and scored like `external`. The settings sweep as lists and `tune`
//! searches them, so the engine's own parameters are measured by running the engine.
//!
//! This file holds what the technique is (its fields, its checks, its command line); running it
//! belongs to the command crate's schedule.

use super::canonical::{CanonicalFields, canonical_json};
use super::params::err;
use super::{Technique, TechniqueParams, TechniqueSpecError};
use crate::import::DEFAULT_DEPTH_TOLERANCE;
use serde::{Deserialize, Serialize};
use serde_json::{Map, Value};

/// The placeholders shadowtruth fills in itself; every other `{NAME}` is a setting.
pub const COMMAND_PLACEHOLDERS: [&str; 7] =
    ["view", "visibility", "depth", "resolution", "scene", "camera", "light"];

/// The fields of a `command` entry that are never settings.
const OWN_FIELDS: [&str; 6] = ["name", "run", "timeout_s", "flip_y", "depth_tolerance", "visibility_format"];

/// A fields whose list is one value, not a sweep: the command line.
pub const COMMAND_LIST_FIELDS: [&str; 1] = ["run"];

/// Seconds a command may run unless told: a software-rasterized engine render of a 2048² map
/// takes seconds; ten minutes means it hangs.
pub const DEFAULT_COMMAND_TIMEOUT_S: f64 = 600.0;
/// The longest timeout accepted (a day).
pub const MAX_COMMAND_TIMEOUT_S: f64 = 86_400.0;
/// Arguments of a command line at most, and bytes of one argument.
const MAX_ARGS: usize = 256;
const MAX_ARG_BYTES: usize = 4096;

/// `command`: the renderer's `name`, its command line `run` (program and arguments, no shell),
/// `timeout_s`, whether its images have row 0 at the bottom (`flip_y`), the relative
/// `depth_tolerance` of its depth buffer, the format of the visibility file it writes, and its
/// settings: every other field, a number, string or boolean that fills `{NAME}` in `run`.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct CommandParams {
    pub name: String,
    pub run: Vec<String>,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub timeout_s: Option<f64>,
    #[serde(default, skip_serializing_if = "std::ops::Not::not")]
    pub flip_y: bool,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub depth_tolerance: Option<f64>,
    #[serde(default, skip_serializing_if = "VisibilityFormat::is_exr")]
    pub visibility_format: VisibilityFormat,
    /// The renderer's own settings, by name (sorted).
    #[serde(flatten)]
    pub settings: Map<String, Value>,
}

/// The file a command writes its visibility to (`{visibility}`): an f32 or f16 EXR, or a PNG
/// (alpha 0 marks background). The depth file is always an EXR.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum VisibilityFormat {
    #[default]
    Exr,
    Png,
}

impl VisibilityFormat {
    fn is_exr(&self) -> bool {
        *self == VisibilityFormat::Exr
    }

    /// The file extension, without its dot.
    pub fn extension(self) -> &'static str {
        match self {
            VisibilityFormat::Exr => "exr",
            VisibilityFormat::Png => "png",
        }
    }
}

/// What shadowtruth fills in for one run of a command.
#[derive(Clone, Debug)]
pub struct CommandRun<'a> {
    pub view_dir: &'a str,
    pub visibility_file: &'a str,
    pub depth_file: &'a str,
    pub resolution: u32,
    pub scene: &'a str,
    pub camera: &'a str,
    pub light: &'a str,
}

impl CommandParams {
    /// The command line of one run: every placeholder filled in.
    pub fn argv(&self, run: &CommandRun) -> Vec<String> {
        self.run.iter().map(|arg| fill(arg, |name| self.value_of(name, run))).collect()
    }

    /// Whether the renderer is asked for a depth buffer (`{depth}` in its command line).
    pub fn writes_depth(&self) -> bool {
        self.run.iter().any(|arg| placeholders(arg).any(|p| p == "depth"))
    }

    /// The timeout in seconds, its default filled in.
    pub fn timeout_s(&self) -> f64 {
        self.timeout_s.unwrap_or(DEFAULT_COMMAND_TIMEOUT_S)
    }

    /// The relative depth tolerance (`crate::import`), its default filled in.
    pub fn depth_tolerance(&self) -> f64 {
        self.depth_tolerance.unwrap_or(DEFAULT_DEPTH_TOLERANCE)
    }

    fn value_of(&self, name: &str, run: &CommandRun) -> String {
        match name {
            "view" => run.view_dir.to_string(),
            "visibility" => run.visibility_file.to_string(),
            "depth" => run.depth_file.to_string(),
            "resolution" => run.resolution.to_string(),
            "scene" => run.scene.to_string(),
            "camera" => run.camera.to_string(),
            "light" => run.light.to_string(),
            setting => self.settings.get(setting).map(setting_text).unwrap_or_default(),
        }
    }

    fn validate_run(&self) -> Result<(), TechniqueSpecError> {
        if self.run.is_empty() || self.run[0].trim().is_empty() {
            return Err(err("run", "an empty command line: give the program and its arguments"));
        }
        if self.run.len() > MAX_ARGS || self.run.iter().any(|a| a.len() > MAX_ARG_BYTES || a.contains('\0')) {
            return Err(err(
                "run",
                format!("at most {MAX_ARGS} arguments of at most {MAX_ARG_BYTES} bytes each, without NUL"),
            ));
        }
        if let Some(e) = self.run.iter().find_map(|arg| pieces(arg).err()) {
            return Err(err("run", e));
        }
        if !self.run.iter().any(|arg| placeholders(arg).any(|p| p == "visibility")) {
            return Err(err(
                "run",
                "never names `{visibility}`: the file the renderer writes its shadows to",
            ));
        }
        for arg in &self.run {
            pieces(arg).map_err(|e| err("run", e))?;
            for p in placeholders(arg) {
                if !COMMAND_PLACEHOLDERS.contains(&p) && !self.settings.contains_key(p) {
                    return Err(err(
                        "run",
                        format!(
                            "\"{arg}\": `{{{p}}}` is neither one of {{{}}} nor a setting of this entry",
                            COMMAND_PLACEHOLDERS.join("}, {")
                        ),
                    ));
                }
            }
        }
        Ok(())
    }

    /// Every setting a scalar that the command line reads: a setting it never names would be
    /// a number changed without effect.
    fn validate_settings(&self) -> Result<(), TechniqueSpecError> {
        for (name, value) in &self.settings {
            if OWN_FIELDS.contains(&name.as_str()) || COMMAND_PLACEHOLDERS.contains(&name.as_str()) {
                return Err(TechniqueSpecError {
                    field: None,
                    message: format!("`{name}` cannot be a setting: shadowtruth fills it in"),
                });
            }
            let problem = match value {
                Value::Number(n) if n.as_f64().is_some_and(f64::is_finite) => None,
                Value::String(_) | Value::Bool(_) => None,
                other => Some(format!("must be a number, a string or a boolean, found {other}")),
            };
            let unused = !self.run.iter().any(|arg| placeholders(arg).any(|p| p == name));
            let problem =
                problem
                    .or(unused
                        .then(|| format!("is never named as `{{{name}}}` in `run`, so it changes nothing")));
            if let Some(problem) = problem {
                return Err(TechniqueSpecError {
                    field: None,
                    message: format!("setting `{name}` {problem}"),
                });
            }
        }
        Ok(())
    }
}

/// One piece of an argument: text as written, or a `{NAME}` placeholder.
#[derive(Debug, PartialEq)]
enum Piece<'a> {
    Text(&'a str),
    Placeholder(&'a str),
}

/// The pieces of `arg`: `{NAME}` (NAME of letters, digits and `_`) is a placeholder, `{{` and
/// `}}` are a literal brace (as in Rust's and Python's format strings), any other brace is an
/// error, so that a brace meant literally is never read as a placeholder or dropped.
fn pieces(arg: &str) -> Result<Vec<Piece<'_>>, String> {
    let mut out = Vec::new();
    let (bytes, mut start, mut i) = (arg.as_bytes(), 0, 0);
    while i < bytes.len() {
        let doubled = bytes.get(i + 1) == Some(&bytes[i]);
        match bytes[i] {
            b'{' | b'}' if doubled => {
                out.push(Piece::Text(&arg[start..i + 1]));
                i += 2;
                start = i;
            }
            b'{' => {
                let name_len =
                    arg[i + 1..].bytes().take_while(|b| b.is_ascii_alphanumeric() || *b == b'_').count();
                if name_len == 0 || bytes.get(i + 1 + name_len) != Some(&b'}') {
                    return Err(format!(
                        "\"{arg}\": a `{{` that opens no `{{NAME}}`; write `{{{{` for a literal brace"
                    ));
                }
                out.push(Piece::Text(&arg[start..i]));
                out.push(Piece::Placeholder(&arg[i + 1..i + 1 + name_len]));
                i += name_len + 2;
                start = i;
            }
            b'}' => {
                return Err(format!(
                    "\"{arg}\": a `}}` that closes no `{{NAME}}`; write `}}}}` for a literal brace"
                ));
            }
            _ => i += 1,
        }
    }
    out.push(Piece::Text(&arg[start..]));
    Ok(out)
}

/// `{NAME}` placeholders of one argument, in order (none when it is malformed: `validate`
/// refuses it first).
fn placeholders(arg: &str) -> impl Iterator<Item = &str> {
    pieces(arg).unwrap_or_default().into_iter().filter_map(|p| match p {
        Piece::Placeholder(name) => Some(name),
        Piece::Text(_) => None,
    })
}

/// `arg` with every `{NAME}` replaced by `value(NAME)` and every doubled brace made single.
fn fill(arg: &str, value: impl Fn(&str) -> String) -> String {
    let pieces = pieces(arg).expect("validated");
    pieces
        .into_iter()
        .map(|p| match p {
            Piece::Text(t) => t.to_string(),
            Piece::Placeholder(name) => value(name),
        })
        .collect()
}

/// A setting as its command line reads it: strings bare, numbers and booleans as JSON prints
/// them.
fn setting_text(value: &Value) -> String {
    match value {
        Value::String(s) => s.clone(),
        other => other.to_string(),
    }
}

impl TechniqueParams for CommandParams {
    fn validate(&self) -> Result<(), TechniqueSpecError> {
        if self.name.trim().is_empty() {
            return Err(err("name", "an empty name: name the renderer"));
        }
        self.validate_run()?;
        self.validate_settings()?;
        if let Some(t) = self.timeout_s
            && !(t > 0.0 && t <= MAX_COMMAND_TIMEOUT_S)
        {
            return Err(err(
                "timeout_s",
                format!("must be more than 0 and at most {MAX_COMMAND_TIMEOUT_S}, found {t}"),
            ));
        }
        if let Some(t) = self.depth_tolerance {
            super::params::non_negative("depth_tolerance", t)?;
            if !self.writes_depth() {
                return Err(err("depth_tolerance", "given without `{depth}` in `run`"));
            }
        }
        Ok(())
    }

    /// None: the schedule runs the command and reads what it wrote.
    fn build(&self) -> Option<Box<dyn Technique>> {
        None
    }

    fn canonical_fields(&self, f: &mut CanonicalFields) {
        f.named("name", &self.name);
        f.named("run", canonical_json(&Value::from(self.run.clone())));
        f.number("timeout_s", self.timeout_s());
        f.flag("flip_y", self.flip_y);
        f.named("visibility_format", self.visibility_format);
        if self.writes_depth() {
            f.number("depth_tolerance", self.depth_tolerance());
        }
        f.named("settings", canonical_json(&Value::Object(self.settings.clone())));
    }

    /// The name and the settings: the command line is in the record's parameters, too long for
    /// a label.
    fn label_parameters(&self) -> Map<String, Value> {
        let mut m = self.settings.clone();
        m.insert("name".into(), Value::from(self.name.clone()));
        m
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::technique::TechniqueSpec;
    use serde_json::json;

    fn spec(value: Value) -> Result<TechniqueSpec, String> {
        let spec: TechniqueSpec = serde_json::from_value(value).map_err(|e| e.to_string())?;
        spec.validate().map_err(|e| e.to_string())?;
        Ok(spec)
    }

    fn three() -> Value {
        json!({"technique": "command", "name": "three", "bias": -0.0005, "type": "pcf",
               "run": ["node", "render.mjs", "--view", "{view}", "--visibility", "{visibility}",
                       "--map-size={resolution}", "--bias", "{bias}", "--shadow-type", "{type}"]})
    }

    #[test]
    fn the_command_line_is_filled_in() {
        let Ok(TechniqueSpec::Command(p)) = spec(three()) else { panic!("a command") };
        let run = CommandRun {
            view_dir: "v",
            visibility_file: "out/vis.exr",
            depth_file: "out/depth.exr",
            resolution: 2048,
            scene: "s",
            camera: "c",
            light: "l",
        };
        let argv = p.argv(&run);
        assert_eq!(
            argv,
            [
                "node",
                "render.mjs",
                "--view",
                "v",
                "--visibility",
                "out/vis.exr",
                "--map-size=2048",
                "--bias",
                "-0.0005",
                "--shadow-type",
                "pcf"
            ]
        );
        assert!(!p.writes_depth());
        assert_eq!(p.timeout_s(), DEFAULT_COMMAND_TIMEOUT_S);
    }

    #[test]
    fn doubled_braces_are_literal_braces() {
        let mut v = three();
        v["run"] = json!(["awk", "BEGIN {{ print \"{bias}\" }}", "{{visibility}}{visibility}"]);
        v.as_object_mut().unwrap().remove("type");
        let Ok(TechniqueSpec::Command(p)) = spec(v) else { panic!("a command") };
        let run = CommandRun {
            view_dir: "v",
            visibility_file: "o.exr",
            depth_file: "d.exr",
            resolution: 1,
            scene: "s",
            camera: "c",
            light: "l",
        };
        assert_eq!(p.argv(&run), ["awk", "BEGIN { print \"-0.0005\" }", "{visibility}o.exr"]);
    }

    #[test]
    fn labels_name_the_renderer_and_its_settings_and_records_keep_the_command_line() {
        let s = spec(three()).unwrap();
        assert_eq!(s.label(), "command(bias=-0.0005,name=three,type=pcf)");
        assert!(s.parameters().contains_key("run"));
        let round: TechniqueSpec = serde_json::from_value(serde_json::to_value(&s).unwrap()).unwrap();
        assert_eq!(round, s);
        let mut other = three();
        other["bias"] = json!(-0.0005000);
        assert_eq!(spec(other).unwrap().canonical(), s.canonical());
    }

    #[test]
    fn what_the_command_line_cannot_use_is_refused() {
        let with = |key: &str, value: Value| {
            let mut v = three();
            v[key] = value;
            spec(v).unwrap_err()
        };
        assert!(with("unused", json!(1)).contains("setting `unused` is never named"));
        assert!(with("bias", json!([1])).contains("must be a number, a string or a boolean"));
        assert!(with("bias", json!(null)).contains("must be a number"));
        assert!(with("run", json!([])).contains("empty command line"));
        assert!(with("run", json!(["node", "x"])).contains("never names `{visibility}`"));
        assert!(with("run", json!(["node", "{visibility}", "{nope}"])).contains("`{nope}` is neither"));
        assert!(with("run", json!(["node", "{visibility}", "{bias", "}"])).contains("opens no `{NAME}`"));
        assert!(with("run", json!(["node", "{visibility}", "a}"])).contains("closes no `{NAME}`"));
        assert!(
            with("run", json!(["node", "{visibility}", "{ exit }"])).contains("write `{{` for a literal")
        );
        assert!(with("timeout_s", json!(0)).contains("timeout_s"));
        assert!(with("depth_tolerance", json!(0.01)).contains("without `{depth}`"));
        assert!(with("name", json!(" ")).contains("name"));
        let mut v = three();
        v["view"] = json!("x");
        assert!(spec(v).unwrap_err().contains("`view` cannot be a setting"));
    }
}
