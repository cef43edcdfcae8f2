//! The `shadowtruth/scene/v1` file format, read field by field so that every problem is reported.
//!
//! The JSON is parsed into a `serde_json::Value` and walked by hand rather than derived with
//! serde: a derive stops at the first error, while users fixing a scene want all of them at once,
//! each with its JSON path.

use super::shapes::Shape;
use super::{Camera, Light, LightKind, Problem, SCENE_FORMAT, Transform};
use glam::{DVec3, Vec3};
use serde_json::{Map, Value};
use std::collections::HashMap;
use std::path::{Path, PathBuf};

/// Largest camera image side, and largest image (64 megapixels).
pub(crate) const MAX_IMAGE_SIDE: u64 = 16384;
pub(crate) const MAX_IMAGE_PIXELS: u64 = 1 << 26;
/// Segment, ring and subdivision counts accepted for procedural shapes.
const MAX_SEGMENTS: u64 = 4096;
/// Largest procedural shape, in triangles.
const MAX_SHAPE_TRIANGLES: u64 = 1 << 24;

/// Marks a number that serde_json could not represent (e.g. `1e999`); see `parse_json`.
const NON_FINITE_MARK: &str = "\u{1}non-finite number\u{1}";
/// How many such numbers are marked before the file is reported as malformed instead.
const MAX_MARKED_NUMBERS: usize = 64;

/// Where an object's triangles come from.
#[derive(Clone, Debug)]
pub(crate) enum Geometry {
    /// An OBJ path, relative to the scene file's folder.
    Mesh(String),
    Shape(Shape),
}

/// One object as written in the file; fields that failed to read are `None`.
#[derive(Clone, Debug)]
pub(crate) struct ObjectDesc {
    /// JSON path of the object, e.g. `objects[2]`.
    pub path: String,
    pub name: String,
    pub geometry: Option<Geometry>,
    pub closed: bool,
    pub transform: Option<Transform>,
}

/// A scene file's content, before meshes are loaded.
#[derive(Clone, Debug, Default)]
pub(crate) struct SceneDesc {
    pub name: String,
    pub objects: Vec<ObjectDesc>,
    pub cameras: Vec<Camera>,
    pub lights: Vec<Light>,
}

/// Collects the problems of one scene file.
pub(crate) struct Problems {
    pub file: PathBuf,
    pub list: Vec<Problem>,
}

impl Problems {
    pub fn new(file: &Path) -> Self {
        Problems { file: file.to_path_buf(), list: Vec::new() }
    }

    pub fn report(&mut self, path: &str, message: impl Into<String>) {
        let (file, path) = (self.file.clone(), path.to_string());
        self.list.push(Problem { file, path, message: message.into() });
    }
}

/// Parses JSON text. A number too large for f64 (which serde_json rejects outright) is replaced
/// by a marker string and parsing is retried, so that it is reported later with its JSON path
/// instead of as a bare syntax error; any other syntax error is reported with line and column.
pub(crate) fn parse_json(text: &str, problems: &mut Problems) -> Option<Value> {
    let mut text = std::borrow::Cow::Borrowed(text);
    // Each retry re-parses the whole text: bound them so that hostile input stays cheap.
    let mut retries = 0;
    loop {
        match serde_json::from_str::<Value>(&text) {
            Ok(v) => return Some(v),
            Err(e) => {
                retries += 1;
                let marked = retries <= MAX_MARKED_NUMBERS
                    && e.to_string().starts_with("number out of range")
                    && mark_number(text.to_mut(), e.line(), e.column());
                if !marked {
                    // serde_json's message ends with "at line L column C".
                    problems.report("", format!("malformed JSON: {e}"));
                    return None;
                }
            }
        }
    }
}

/// Replaces the number token at (1-based `line`, byte `column`) by a marker string.
fn mark_number(text: &mut String, line: usize, column: usize) -> bool {
    let line_start = match line {
        0 => return false,
        1 => 0,
        n => match text.match_indices('\n').nth(n - 2) {
            Some((i, _)) => i + 1,
            None => return false,
        },
    };
    let bytes = text.as_bytes();
    let is_num = |b: u8| b.is_ascii_digit() || b"+-.eE".contains(&b);
    let at = (line_start + column.saturating_sub(1)).min(bytes.len());
    let mut start = at;
    while start > line_start && is_num(bytes[start - 1]) {
        start -= 1;
    }
    let mut end = at;
    while end < bytes.len() && is_num(bytes[end]) {
        end += 1;
    }
    if start == end {
        return false;
    }
    let token = text[start..end].to_string();
    let mark = serde_json::to_string(&format!("{NON_FINITE_MARK}{token}")).unwrap_or_default();
    text.replace_range(start..end, &mark);
    true
}

/// Reads the top level of a scene file.
pub(crate) fn read_scene(root: &Value, problems: &mut Problems) -> SceneDesc {
    let mut desc = SceneDesc::default();
    let Some(mut top) = Reader::new(root, String::new(), problems) else {
        return desc;
    };
    if let Some(format) = top.required("format", as_string)
        && format != SCENE_FORMAT
    {
        let message = format!("unsupported format \"{format}\"; expected \"{SCENE_FORMAT}\"");
        top.problem("format", message);
    }
    desc.name = top.required("name", as_string).unwrap_or_default();
    if let Some(items) = top.array("objects") {
        if items.is_empty() {
            top.problem("objects", "must contain at least one object");
        }
        desc.objects = top.each("objects", items, read_object);
    }
    if let Some(items) = top.array("cameras") {
        desc.cameras = top.each("cameras", items, read_camera).into_iter().flatten().collect();
    }
    if let Some(items) = top.array("lights") {
        desc.lights = top.each("lights", items, read_light).into_iter().flatten().collect();
    }
    top.finish();
    desc
}

fn read_object(r: &mut Reader) -> ObjectDesc {
    let name = r.required("name", as_name).unwrap_or_default();
    let mesh = r.optional("mesh", as_string);
    let shape = r.optional_object("shape", read_shape);
    let geometry = match (mesh, shape) {
        (Some(mesh), None) => Some(Geometry::Mesh(mesh)),
        (None, Some(shape)) => shape.map(Geometry::Shape),
        (Some(_), Some(_)) => {
            r.problem("", "has both `mesh` and `shape`; give exactly one");
            None
        }
        (None, None) => {
            // Only complain when neither field is present (a bad one was reported already).
            if !r.has("mesh") && !r.has("shape") {
                r.problem("", "needs a `mesh` (OBJ path) or a `shape`");
            }
            None
        }
    };
    let closed = r.optional("closed", as_bool).unwrap_or(false);
    let transform = match r.optional_object("transform", read_transform) {
        None => Some(Transform::default()),
        Some(t) => t,
    };
    ObjectDesc { path: r.path.clone(), name, geometry, closed, transform }
}

fn read_transform(r: &mut Reader) -> Option<Transform> {
    let nonzero = |v: &Value| {
        let s = as_vec3(v)?;
        match s.to_array().iter().position(|&c| c == 0.0) {
            Some(i) => Err(format!("component {i} is zero; a scale must not flatten the object")),
            None => Ok(s),
        }
    };
    let scale = r.optional_or("scale", nonzero, Vec3::ONE);
    let rotate_deg = r.optional_or("rotate_deg", as_vec3, Vec3::ZERO);
    let translate = r.optional_or("translate", as_vec3, Vec3::ZERO);
    Some(Transform { scale: scale?, rotate_deg: rotate_deg?, translate: translate? })
}

fn read_shape(r: &mut Reader) -> Option<Shape> {
    let Some(kind) = r.required("type", as_string) else {
        r.ignore_unknown = true;
        return None;
    };
    let segments = |r: &mut Reader| r.optional_or("segments", count(3, MAX_SEGMENTS), 32);
    let shape = match kind.as_str() {
        "plane" => {
            let size = r.required("size", as_positive_array::<2>);
            let subdivisions = r.optional_or("subdivisions", count(1, MAX_SEGMENTS), 1);
            Shape::Plane { size: size?, subdivisions: subdivisions? }
        }
        "box" => Shape::Box { size: r.required("size", as_positive_array::<3>)? },
        "sphere" => {
            let radius = r.required("radius", as_positive);
            let segments = segments(r);
            let rings = r.optional_or("rings", count(2, MAX_SEGMENTS), 16);
            Shape::Sphere { radius: radius?, segments: segments?, rings: rings? }
        }
        "cylinder" | "cone" => {
            let radius = r.required("radius", as_positive);
            let height = r.required("height", as_positive);
            let segments = segments(r);
            let (radius, height, segments) = (radius?, height?, segments?);
            if kind == "cone" {
                Shape::Cone { radius, height, segments }
            } else {
                Shape::Cylinder { radius, height, segments }
            }
        }
        other => {
            let message =
                format!("unknown shape type \"{other}\"; expected plane, box, sphere, cylinder or cone");
            r.problem("type", message);
            r.ignore_unknown = true;
            return None;
        }
    };
    if shape.triangle_count() > MAX_SHAPE_TRIANGLES {
        let message = format!(
            "would have {} triangles; at most {MAX_SHAPE_TRIANGLES} are allowed",
            shape.triangle_count()
        );
        r.problem("", message);
        return None;
    }
    Some(shape)
}

fn read_camera(r: &mut Reader) -> Option<Camera> {
    let name = r.required("name", as_name);
    let position = r.required("position", as_vec3);
    let look_at = r.required("look_at", as_vec3);
    let up = r.optional_or("up", as_vec3, Vec3::Y);
    let fov_y_deg = r.required("fov_y_deg", open_range(0.0, 180.0));
    let width = r.required("width", count(1, MAX_IMAGE_SIDE));
    let height = r.required("height", count(1, MAX_IMAGE_SIDE));
    let mut valid = true;
    if let (Some(w), Some(h)) = (width, height)
        && w as u64 * h as u64 > MAX_IMAGE_PIXELS
    {
        r.problem("", format!("image {w}×{h} has more than 64 megapixels"));
        valid = false;
    }
    if let (Some(position), Some(look_at), Some(up)) = (position, look_at, up) {
        let forward = look_at.as_dvec3() - position.as_dvec3();
        let up = up.as_dvec3();
        if forward == DVec3::ZERO {
            r.problem("look_at", "equals `position`: the camera has no viewing direction");
            valid = false;
        } else if !is_unit_safe(up) || forward.normalize().cross(up.normalize()).length() < 1e-6 {
            let message = "is zero or parallel to the viewing direction (look_at − position)";
            r.problem("up", message);
            valid = false;
        }
    }
    let camera = Camera {
        name: name?,
        position: position?,
        look_at: look_at?,
        up: up?,
        fov_y_deg: fov_y_deg? as f32,
        width: width?,
        height: height?,
    };
    valid.then_some(camera)
}

fn read_light(r: &mut Reader) -> Option<Light> {
    let name = r.required("name", as_name);
    let light_type = r.required("type", as_string);
    let direction = r.required("direction", as_direction);
    let light = match light_type.as_deref() {
        Some("directional") => {
            let angular = r.optional("angular_diameter_deg", open_range(0.0, 90.0));
            let kind = LightKind::Directional { direction: direction? };
            Light { name: name?, kind, angular_diameter_deg: angular.map(|a| a as f32), radius: None }
        }
        Some("spot") => {
            let position = r.required("position", as_vec3);
            let cone_deg = r.required("cone_deg", open_range(0.0, 180.0));
            let near = r.required("near", as_positive);
            let far = r.required("far", as_positive);
            let radius = r.optional("radius", as_positive);
            let (near, far) = (near?, far?);
            if far <= near {
                r.problem("far", format!("must be greater than `near` ({})", show(near)));
                return None;
            }
            let kind = LightKind::Spot {
                position: position?,
                direction: direction?,
                cone_deg: cone_deg? as f32,
                near: near as f32,
                far: far as f32,
            };
            Light { name: name?, kind, angular_diameter_deg: None, radius: radius.map(|x| x as f32) }
        }
        Some(other) => {
            r.problem("type", format!("unknown light type \"{other}\"; expected directional or spot"));
            r.ignore_unknown = true;
            return None;
        }
        None => {
            r.ignore_unknown = true;
            return None;
        }
    };
    Some(light)
}

/// Reports every repeated `name` among the items of a top-level array.
fn check_unique(problems: &mut Problems, key: &str, items: &[Value]) {
    let mut first: HashMap<&str, usize> = HashMap::new();
    for (i, item) in items.iter().enumerate() {
        if let Some(name) = item.get("name").and_then(Value::as_str) {
            if let Some(j) = first.get(name) {
                let message = format!("duplicate name \"{name}\" (already used by {key}[{j}])");
                problems.report(&format!("{key}[{i}].name"), message);
            } else {
                first.insert(name, i);
            }
        }
    }
}

/// Walks one JSON object, remembering which fields were asked for so that `finish` can name
/// the unknown ones together with the allowed ones.
pub(crate) struct Reader<'a, 'p> {
    map: &'a Map<String, Value>,
    path: String,
    problems: &'p mut Problems,
    known: Vec<&'static str>,
    /// Set when the object's kind is unknown: its other fields cannot be judged.
    ignore_unknown: bool,
}

impl<'a, 'p> Reader<'a, 'p> {
    /// A reader over `value`, or `None` (reported) when it is not a JSON object.
    fn new(value: &'a Value, path: String, problems: &'p mut Problems) -> Option<Self> {
        match value.as_object() {
            Some(map) => Some(Reader { map, path, problems, known: Vec::new(), ignore_unknown: false }),
            None => {
                let message = format!("expected an object, found {}", describe(value));
                problems.report(&path, message);
                None
            }
        }
    }

    fn field_path(&self, key: &str) -> String {
        match (self.path.is_empty(), key.is_empty()) {
            (_, true) => self.path.clone(),
            (true, false) => key.to_string(),
            (false, false) => format!("{}.{key}", self.path),
        }
    }

    /// Reports a problem at `key` of this object (`""` for the object itself).
    fn problem(&mut self, key: &str, message: impl Into<String>) {
        let path = self.field_path(key);
        self.problems.report(&path, message);
    }

    fn has(&self, key: &str) -> bool {
        self.map.contains_key(key)
    }

    fn get(&mut self, key: &'static str) -> Option<&'a Value> {
        self.known.push(key);
        self.map.get(key)
    }

    fn convert<T>(
        &mut self,
        key: &'static str,
        value: &Value,
        conv: impl Fn(&Value) -> Result<T, String>,
    ) -> Option<T> {
        match conv(value) {
            Ok(x) => Some(x),
            Err(message) => {
                self.problem(key, message);
                None
            }
        }
    }

    /// A required field; `None` (reported) when missing or invalid.
    fn required<T>(&mut self, key: &'static str, conv: impl Fn(&Value) -> Result<T, String>) -> Option<T> {
        match self.get(key) {
            Some(v) => self.convert(key, v, conv),
            None => {
                self.problem(key, "missing required field");
                None
            }
        }
    }

    /// A required array.
    fn array(&mut self, key: &'static str) -> Option<&'a [Value]> {
        let value = self.get(key);
        match value.map(Value::as_array) {
            Some(Some(items)) => Some(items),
            Some(None) => {
                let message = format!("expected an array, found {}", describe(value?));
                self.problem(key, message);
                None
            }
            None => {
                self.problem(key, "missing required field");
                None
            }
        }
    }

    /// An optional field; `None` when absent or invalid (reported).
    fn optional<T>(&mut self, key: &'static str, conv: impl Fn(&Value) -> Result<T, String>) -> Option<T> {
        let v = self.get(key)?;
        self.convert(key, v, conv)
    }

    /// An optional field with a default; `None` only when present and invalid (reported).
    fn optional_or<T>(
        &mut self,
        key: &'static str,
        conv: impl Fn(&Value) -> Result<T, String>,
        default: T,
    ) -> Option<T> {
        match self.get(key) {
            Some(v) => self.convert(key, v, conv),
            None => Some(default),
        }
    }

    /// An optional nested object read by `read`; `None` when absent, `Some(None)` when invalid.
    fn optional_object<T>(
        &mut self,
        key: &'static str,
        read: impl FnOnce(&mut Reader) -> Option<T>,
    ) -> Option<Option<T>> {
        let value = self.get(key)?;
        let path = self.field_path(key);
        let mut inner = Reader::new(value, path, self.problems)?;
        let result = read(&mut inner);
        inner.finish();
        Some(result)
    }

    /// Reads every element of the array at `key` with `read`, skipping non-objects (reported).
    fn each<T>(&mut self, key: &'static str, items: &'a [Value], read: impl Fn(&mut Reader) -> T) -> Vec<T> {
        let mut out = Vec::with_capacity(items.len());
        for (i, item) in items.iter().enumerate() {
            let path = format!("{}[{i}]", self.field_path(key));
            if let Some(mut inner) = Reader::new(item, path, self.problems) {
                out.push(read(&mut inner));
                inner.finish();
            }
        }
        check_unique(self.problems, key, items);
        out
    }

    /// Reports the fields that were never asked for.
    fn finish(self) {
        if self.ignore_unknown {
            return;
        }
        for key in self.map.keys() {
            if !self.known.contains(&key.as_str()) {
                let path = self.field_path(key);
                let allowed = self.known.join(", ");
                self.problems.report(&path, format!("unknown field `{key}`; allowed fields: {allowed}"));
            }
        }
    }
}

fn describe(v: &Value) -> String {
    match v {
        Value::Null => "null".into(),
        Value::Bool(b) => b.to_string(),
        Value::Number(n) => format!("the number {n}"),
        Value::String(s) => match s.strip_prefix(NON_FINITE_MARK) {
            Some(token) => format!("the number {token}"),
            None => format!("the string \"{s}\""),
        },
        Value::Array(items) => format!("an array of {} items", items.len()),
        Value::Object(_) => "an object".into(),
    }
}

/// A number as a user would write it: plain when moderate, in exponent form when huge or tiny.
fn show(x: f64) -> String {
    if x != 0.0 && !(1e-6..1e15).contains(&x.abs()) { format!("{x:e}") } else { format!("{x}") }
}

fn as_string(v: &Value) -> Result<String, String> {
    match v {
        Value::String(s) if !s.starts_with(NON_FINITE_MARK) => Ok(s.clone()),
        _ => Err(format!("expected a string, found {}", describe(v))),
    }
}

fn as_name(v: &Value) -> Result<String, String> {
    let s = as_string(v)?;
    if s.trim().is_empty() { Err("must not be empty".into()) } else { Ok(s) }
}

fn as_bool(v: &Value) -> Result<bool, String> {
    v.as_bool().ok_or_else(|| format!("expected true or false, found {}", describe(v)))
}

/// A finite number that also fits in f32 (the precision of the scene's geometry).
fn as_number(v: &Value) -> Result<f64, String> {
    if let Some(token) = v.as_str().and_then(|s| s.strip_prefix(NON_FINITE_MARK)) {
        return Err(format!("{token} is not a finite number"));
    }
    let x = v.as_f64().ok_or_else(|| format!("expected a number, found {}", describe(v)))?;
    if !x.is_finite() || !(x as f32).is_finite() {
        return Err(format!("{} is out of the f32 range", show(x)));
    }
    Ok(x)
}

fn as_positive(v: &Value) -> Result<f64, String> {
    let x = as_number(v)?;
    if x > 0.0 { Ok(x) } else { Err(format!("must be greater than 0, found {}", show(x))) }
}

fn open_range(lo: f64, hi: f64) -> impl Fn(&Value) -> Result<f64, String> {
    move |v| {
        let x = as_number(v)?;
        if x > lo && x < hi {
            Ok(x)
        } else {
            Err(format!("must be between {lo} and {hi} (exclusive), found {}", show(x)))
        }
    }
}

/// A whole number in `min..=max`.
fn count(min: u64, max: u64) -> impl Fn(&Value) -> Result<u32, String> {
    move |v| {
        let x = as_number(v)?;
        if x.fract() != 0.0 {
            return Err(format!("expected a whole number, found {}", show(x)));
        }
        if x < min as f64 || x > max as f64 {
            return Err(format!("must be between {min} and {max}, found {}", show(x)));
        }
        Ok(x as u32)
    }
}

fn as_array_of<const N: usize>(v: &Value) -> Result<[f64; N], String> {
    let items = match v.as_array() {
        Some(items) if items.len() == N => items,
        _ => {
            return Err(format!("expected an array of {N} numbers, found {}", describe(v)));
        }
    };
    let mut out = [0.0; N];
    for (i, item) in items.iter().enumerate() {
        out[i] = as_number(item).map_err(|m| format!("component {i}: {m}"))?;
    }
    Ok(out)
}

fn as_positive_array<const N: usize>(v: &Value) -> Result<[f64; N], String> {
    let a = as_array_of::<N>(v)?;
    match a.iter().position(|&x| x <= 0.0) {
        Some(i) => Err(format!("component {i} must be greater than 0, found {}", show(a[i]))),
        None => Ok(a),
    }
}

fn as_vec3(v: &Value) -> Result<Vec3, String> {
    Ok(DVec3::from(as_array_of::<3>(v)?).as_vec3())
}

fn is_unit_safe(d: DVec3) -> bool {
    let n = d.length();
    n.is_finite() && n > 0.0 && d.normalize().is_finite()
}

/// A non-zero direction, normalized (in f64, rounded once).
fn as_direction(v: &Value) -> Result<Vec3, String> {
    let d = DVec3::from(as_array_of::<3>(v)?);
    if !is_unit_safe(d) {
        return Err("must have a non-zero length".into());
    }
    Ok(d.normalize().as_vec3())
}

#[cfg(test)]
mod tests {
    use super::*;

    fn parse(text: &str) -> (Option<Value>, Vec<Problem>) {
        let mut problems = Problems::new(Path::new("s.json"));
        (parse_json(text, &mut problems), problems.list)
    }

    #[test]
    fn scene_format_out_of_range_numbers_are_marked_not_fatal() {
        let text = "{\n  \"ü\": \"é\", \"a\": [1, -1e999,\n 2E+400],\n\"b\": 1e999}";
        let (value, problems) = parse(text);
        assert!(problems.is_empty(), "{problems:?}");
        let value = value.unwrap();
        assert_eq!(as_number(&value["a"][0]), Ok(1.0));
        assert_eq!(as_number(&value["a"][1]), Err("-1e999 is not a finite number".into()));
        assert_eq!(as_number(&value["a"][2]), Err("2E+400 is not a finite number".into()));
        assert_eq!(as_number(&value["b"]), Err("1e999 is not a finite number".into()));
        assert!(as_string(&value["b"]).is_err());
    }

    #[test]
    fn scene_format_syntax_errors_keep_line_and_column() {
        let (value, problems) = parse("{\"a\": 1e999,\n \"b\": nan}");
        assert!(value.is_none());
        assert_eq!(problems.len(), 1);
        assert!(problems[0].message.contains("at line 2 column 8"), "{problems:?}");
    }

    #[test]
    fn scene_format_non_object_root_is_one_problem() {
        let mut problems = Problems::new(Path::new("s.json"));
        let desc = read_scene(&Value::Array(vec![]), &mut problems);
        assert!(desc.objects.is_empty());
        assert_eq!(problems.list.len(), 1);
        assert_eq!(problems.list[0].message, "expected an object, found an array of 0 items");
    }
}
