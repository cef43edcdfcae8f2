//! Reading JSON input files field by field, so that every problem is reported with its file and
//! JSON path (e.g. `objects[2].transform.scale`). Scene files and plan files are read with it.
//!
//! The JSON is parsed into a `serde_json::Value` and walked by hand rather than derived with
//! serde: a derive stops at the first error, while users fixing a file want all of them at once.

use serde_json::{Map, Value};
use std::collections::HashMap;
use std::fmt;
use std::path::{Path, PathBuf};

/// One problem in an input file: `file`, JSON path such as `objects[2].transform.scale`, message.
#[derive(Clone, Debug, PartialEq)]
pub struct Problem {
    pub file: PathBuf,
    pub path: String,
    pub message: String,
}

/// `invalid WHAT (N problems):` and one indented line per problem: how the errors of an input
/// file are printed.
pub fn write_problems(f: &mut fmt::Formatter<'_>, what: &str, problems: &[Problem]) -> fmt::Result {
    let n = problems.len();
    writeln!(f, "invalid {what} ({n} problem{}):", if n == 1 { "" } else { "s" })?;
    for p in problems {
        writeln!(f, "  {p}")?;
    }
    Ok(())
}

impl fmt::Display for Problem {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        if self.path.is_empty() {
            write!(f, "{}: {}", self.file.display(), self.message)
        } else {
            write!(f, "{}: {}: {}", self.file.display(), self.path, self.message)
        }
    }
}

/// Marks a number that serde_json could not represent (e.g. `1e999`); see `parse_json`.
pub(crate) const NON_FINITE_MARK: &str = "\u{1}non-finite number\u{1}";
/// How many such numbers are marked before the file is reported as malformed instead.
const MAX_MARKED_NUMBERS: usize = 64;

/// Collects the problems of one input file.
pub struct Problems {
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
pub fn parse_json(text: &str, problems: &mut Problems) -> Option<Value> {
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

/// Walks one JSON object, remembering which fields were asked for so that `finish` can name
/// the unknown ones together with the allowed ones.
pub struct Reader<'a, 'p> {
    map: &'a Map<String, Value>,
    pub(crate) path: String,
    problems: &'p mut Problems,
    known: Vec<&'static str>,
    /// Set when the object's kind is unknown: its other fields cannot be judged.
    pub(crate) ignore_unknown: bool,
}

impl<'a, 'p> Reader<'a, 'p> {
    /// A reader over `value`, or `None` (reported) when it is not a JSON object.
    pub fn new(value: &'a Value, path: String, problems: &'p mut Problems) -> Option<Self> {
        match value.as_object() {
            Some(map) => Some(Reader { map, path, problems, known: Vec::new(), ignore_unknown: false }),
            None => {
                let message = format!("expected an object, found {}", describe(value));
                problems.report(&path, message);
                None
            }
        }
    }

    pub(crate) fn field_path(&self, key: &str) -> String {
        match (self.path.is_empty(), key.is_empty()) {
            (_, true) => self.path.clone(),
            (true, false) => key.to_string(),
            (false, false) => format!("{}.{key}", self.path),
        }
    }

    /// Reports a problem at `key` of this object (`""` for the object itself).
    pub fn problem(&mut self, key: &str, message: impl Into<String>) {
        let path = self.field_path(key);
        self.problems.report(&path, message);
    }

    pub(crate) fn has(&self, key: &str) -> bool {
        self.map.contains_key(key)
    }

    pub(crate) fn get(&mut self, key: &'static str) -> Option<&'a Value> {
        self.known.push(key);
        self.map.get(key)
    }

    pub(crate) fn convert<T>(
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
    pub fn required<T>(
        &mut self,
        key: &'static str,
        conv: impl Fn(&Value) -> Result<T, String>,
    ) -> Option<T> {
        match self.get(key) {
            Some(v) => self.convert(key, v, conv),
            None => {
                self.problem(key, "missing required field");
                None
            }
        }
    }

    /// A required array.
    pub fn array(&mut self, key: &'static str) -> Option<&'a [Value]> {
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
    pub(crate) fn optional<T>(
        &mut self,
        key: &'static str,
        conv: impl Fn(&Value) -> Result<T, String>,
    ) -> Option<T> {
        let v = self.get(key)?;
        self.convert(key, v, conv)
    }

    /// An optional field with a default; `None` only when present and invalid (reported).
    pub fn optional_or<T>(
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

    /// An optional array of at least one item, each converted by `item`: `None` when absent,
    /// `Some(None)` when invalid (the array, or each bad item at `key[i]`, reported).
    pub fn optional_list<T>(
        &mut self,
        key: &'static str,
        item: impl Fn(&Value) -> Result<T, String>,
    ) -> Option<Option<Vec<T>>> {
        let value = self.get(key)?;
        let Some(items) = value.as_array() else {
            self.problem(key, format!("expected an array, found {}", describe(value)));
            return Some(None);
        };
        if items.is_empty() {
            self.problem(key, "an empty list: give at least one value, or leave the field out");
            return Some(None);
        }
        let mut out = Vec::with_capacity(items.len());
        for (i, x) in items.iter().enumerate() {
            match item(x) {
                Ok(v) => out.push(v),
                Err(message) => self.problem(&format!("{key}[{i}]"), message),
            }
        }
        Some((out.len() == items.len()).then_some(out))
    }

    /// A required array of at least one item, as [`Reader::optional_list`].
    pub fn required_list<T>(
        &mut self,
        key: &'static str,
        item: impl Fn(&Value) -> Result<T, String>,
    ) -> Option<Vec<T>> {
        if !self.has(key) {
            self.get(key);
            self.problem(key, "missing required field");
            return None;
        }
        self.optional_list(key, item).flatten()
    }

    /// An optional nested object read by `read`; `None` when absent, `Some(None)` when invalid.
    pub(crate) fn optional_object<T>(
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
    pub(crate) fn each<T>(
        &mut self,
        key: &'static str,
        items: &'a [Value],
        read: impl Fn(&mut Reader) -> T,
    ) -> Vec<T> {
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
    pub fn finish(self) {
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

pub fn describe(v: &Value) -> String {
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
pub(crate) fn show(x: f64) -> String {
    if x != 0.0 && !(1e-6..1e15).contains(&x.abs()) { format!("{x:e}") } else { format!("{x}") }
}

pub fn as_string(v: &Value) -> Result<String, String> {
    match v {
        Value::String(s) if !s.starts_with(NON_FINITE_MARK) => Ok(s.clone()),
        _ => Err(format!("expected a string, found {}", describe(v))),
    }
}

pub fn as_name(v: &Value) -> Result<String, String> {
    let s = as_string(v)?;
    if s.trim().is_empty() { Err("must not be empty".into()) } else { Ok(s) }
}

pub(crate) fn as_bool(v: &Value) -> Result<bool, String> {
    v.as_bool().ok_or_else(|| format!("expected true or false, found {}", describe(v)))
}

/// A finite number that also fits in f32 (the precision of the scene's geometry).
pub(crate) fn as_number(v: &Value) -> Result<f64, String> {
    if let Some(token) = v.as_str().and_then(|s| s.strip_prefix(NON_FINITE_MARK)) {
        return Err(format!("{token} is not a finite number"));
    }
    let x = v.as_f64().ok_or_else(|| format!("expected a number, found {}", describe(v)))?;
    if !x.is_finite() || !(x as f32).is_finite() {
        return Err(format!("{} is out of the f32 range", show(x)));
    }
    Ok(x)
}

pub(crate) fn as_positive(v: &Value) -> Result<f64, String> {
    let x = as_number(v)?;
    if x > 0.0 { Ok(x) } else { Err(format!("must be greater than 0, found {}", show(x))) }
}

pub(crate) fn open_range(lo: f64, hi: f64) -> impl Fn(&Value) -> Result<f64, String> {
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
pub fn count(min: u64, max: u64) -> impl Fn(&Value) -> Result<u32, String> {
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

pub(crate) fn as_array_of<const N: usize>(v: &Value) -> Result<[f64; N], String> {
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

pub(crate) fn as_positive_array<const N: usize>(v: &Value) -> Result<[f64; N], String> {
    let a = as_array_of::<N>(v)?;
    match a.iter().position(|&x| x <= 0.0) {
        Some(i) => Err(format!("component {i} must be greater than 0, found {}", show(a[i]))),
        None => Ok(a),
    }
}

/// Reports every repeated `name` among the items of a top-level array.
pub(crate) fn check_unique(problems: &mut Problems, key: &str, items: &[Value]) {
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

#[cfg(test)]
mod tests {
    use super::*;

    fn parse(text: &str) -> (Option<Value>, Vec<Problem>) {
        let mut problems = Problems::new(Path::new("s.json"));
        (parse_json(text, &mut problems), problems.list)
    }

    #[test]
    fn out_of_range_numbers_are_marked_not_fatal() {
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
    fn syntax_errors_keep_line_and_column() {
        let (value, problems) = parse("{\"a\": 1e999,\n \"b\": nan}");
        assert!(value.is_none());
        assert_eq!(problems.len(), 1);
        assert!(problems[0].message.contains("at line 2 column 8"), "{problems:?}");
    }
}
