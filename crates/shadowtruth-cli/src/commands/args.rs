//! What several commands do with their shared options once clap has checked them (the value
//! parsers themselves are in `option_values.rs`, shared with `tune`).

use anyhow::{Context, Result};

/// Sizes the worker pool to `threads` (already checked by `option_values::threads_parser`);
/// None keeps one thread per core.
pub(super) fn set_threads(threads: Option<usize>) -> Result<()> {
    if let Some(n) = threads {
        rayon::ThreadPoolBuilder::new().num_threads(n).build_global().context("setting up worker threads")?;
    }
    Ok(())
}

/// Refuses an output file whose extension is not `extension` (any case): a file named `x.jpg`
/// that holds a PNG misleads whoever opens it. `what` names what is written, for the message.
pub(super) fn check_output_extension(out: &std::path::Path, extension: &str, what: &str) -> Result<()> {
    let given = out.extension().and_then(|e| e.to_str()).unwrap_or_default();
    if given.eq_ignore_ascii_case(extension) {
        return Ok(());
    }
    let named = if given.is_empty() { "no extension".to_string() } else { format!("'.{given}'") };
    anyhow::bail!(
        "{}: this writes {what}, so the file must end in .{extension} (it has {named}); for example {}",
        out.display(),
        out.with_extension(extension).display()
    )
}

#[cfg(test)]
mod tests {
    use super::check_output_extension;
    use std::path::Path;

    #[test]
    fn an_output_must_be_named_for_what_it_holds() {
        assert!(check_output_extension(Path::new("mask.png"), "png", "a PNG").is_ok());
        assert!(check_output_extension(Path::new("dir.d/MASK.PNG"), "png", "a PNG").is_ok());
        let jpg = check_output_extension(Path::new("out/mask.jpg"), "png", "a PNG mask").unwrap_err();
        assert_eq!(
            jpg.to_string(),
            "out/mask.jpg: this writes a PNG mask, so the file must end in .png (it has '.jpg'); for example out/mask.png"
        );
        let bare = check_output_extension(Path::new("cov"), "exr", "an EXR").unwrap_err().to_string();
        assert!(bare.contains("(it has no extension)") && bare.ends_with("for example cov.exr"), "{bare}");
    }
}
