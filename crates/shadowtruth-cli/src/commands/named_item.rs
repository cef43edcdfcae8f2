//! A camera or light chosen by name on the command line, or the scene's first.

use anyhow::{Context, Result};
use std::path::Path;

/// The item of `items` named `name` (by `get`), or the first when no name is given; an unknown
/// name is refused with the names the scene file `file` has.
pub(super) fn pick<'a, T>(
    items: &'a [T],
    name: Option<&str>,
    get: impl Fn(&T) -> &str,
    what: &str,
    file: &Path,
) -> Result<&'a T> {
    let have = || items.iter().map(&get).collect::<Vec<_>>().join(", ");
    match name {
        Some(n) => items
            .iter()
            .find(|i| get(i) == n)
            .with_context(|| format!("{}: no {what} named '{n}' (have: {})", file.display(), have())),
        None => items.first().with_context(|| {
            format!("{}: {}", file.display(), shadowtruth::scene::missing_view_item(file, what))
        }),
    }
}
