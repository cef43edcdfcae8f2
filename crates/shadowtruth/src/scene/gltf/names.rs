//! Unique names for the objects, cameras and lights a glTF gives: scene names must be unique
//! (a scene file refuses duplicates) but glTF node names need not be.

use std::collections::HashSet;

/// Names handed out so far, of one kind.
#[derive(Default)]
pub(super) struct UniqueNames {
    used: HashSet<String>,
}

impl UniqueNames {
    /// `wanted` (trimmed) when it is not empty and not used yet; else `wanted#2`, `wanted#3`, …;
    /// `fallback` when `wanted` is absent or blank.
    pub(super) fn take(&mut self, wanted: Option<&str>, fallback: impl FnOnce() -> String) -> String {
        let base = match wanted.map(str::trim) {
            Some(name) if !name.is_empty() => name.to_string(),
            _ => fallback(),
        };
        let mut name = base.clone();
        let mut k = 2;
        while !self.used.insert(name.clone()) {
            name = format!("{base}#{k}");
            k += 1;
        }
        name
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn repeated_and_blank_names_become_unique() {
        let mut names = UniqueNames::default();
        assert_eq!(names.take(Some("a"), || "x".into()), "a");
        assert_eq!(names.take(Some(" a "), || "x".into()), "a#2");
        assert_eq!(names.take(Some(""), || "light0".into()), "light0");
        assert_eq!(names.take(None, || "light0".into()), "light0#2");
    }
}
