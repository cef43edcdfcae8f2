//! Opening the files that inputs name, within bounds.
//!
//! Two kinds of name, two rules:
//!
//! - A path written **inside an input file** (a scene's mesh, a glTF object) is untrusted: it is
//!   read only when it names a regular file inside the folder of the file that names it.
//!   [`open_inside`] refuses an absolute path, a `..` that climbs out of the folder and a symbolic
//!   link that leads out of it (the canonical paths are compared: a scene that arrives as an
//!   archive may bring its own links), and anything but a regular file, so that a FIFO or a device
//!   (`/dev/zero`) is never opened.
//! - A path given **on the command line** is the user's own choice, so any readable file will do
//!   (a FIFO from process substitution included), but [`read_named`] still reads no more than a
//!   bound, so that `/dev/zero` ends in an error rather than an exhausted memory.
//!
//! Errors are messages meant to follow the field that named the file (`objects[0].mesh: …`);
//! they never quote a file's bytes.

use std::fs::File;
use std::io::Read;
use std::path::{Component, Path, PathBuf};

/// A regular file inside a folder, opened, with its length when it was opened.
#[derive(Debug)]
pub struct InsideFile {
    /// The folder joined with the path as written (what messages show).
    pub path: PathBuf,
    pub file: File,
    pub len_bytes: u64,
}

/// Opens `relative`, a path written in an input file, inside `folder`, the folder of that file
/// (see the module comment for what is refused).
pub fn open_inside(folder: &Path, relative: &str) -> Result<InsideFile, String> {
    let lexical = lexically_inside(relative)?;
    let folder = if folder.as_os_str().is_empty() { Path::new(".") } else { folder };
    let path = folder.join(&lexical);
    let shown = path.display();
    let metadata = std::fs::metadata(&path).map_err(|e| format!("cannot read {shown}: {e}"))?;
    if !metadata.is_file() {
        return Err(format!(
            "{shown} is {}, not a regular file",
            crate::atomic_file::kind_name(&metadata.file_type())
        ));
    }
    let canonical = path.canonicalize().map_err(|e| format!("cannot resolve {shown}: {e}"))?;
    let canonical_folder =
        folder.canonicalize().map_err(|e| format!("cannot resolve {}: {e}", folder.display()))?;
    if !canonical.starts_with(&canonical_folder) {
        return Err(format!(
            "{shown} leads out of the folder {} through a symbolic link: only files inside it are read",
            folder.display()
        ));
    }
    let file = File::open(&canonical).map_err(|e| format!("cannot open {shown}: {e}"))?;
    // The file checked again as opened: it may have been replaced since the check above.
    let opened = file.metadata().map_err(|e| format!("cannot read {shown}: {e}"))?;
    if !opened.is_file() {
        return Err(format!(
            "{shown} is {}, not a regular file",
            crate::atomic_file::kind_name(&opened.file_type())
        ));
    }
    Ok(InsideFile { path, file, len_bytes: opened.len() })
}

/// Reads `relative` inside `folder` (as [`open_inside`]) whole, when it holds at most
/// `max_bytes`. Returns the path as shown in messages and the bytes.
pub fn read_inside(folder: &Path, relative: &str, max_bytes: u64) -> Result<(PathBuf, Vec<u8>), String> {
    let inside = open_inside(folder, relative)?;
    let bytes = read_at_most(inside.file, max_bytes, &inside.path.display().to_string())?;
    Ok((inside.path, bytes))
}

/// Reads a file named on the command line whole, when it holds at most `max_bytes`.
pub fn read_named(path: &Path, max_bytes: u64) -> Result<Vec<u8>, String> {
    let shown = path.display().to_string();
    let file = File::open(path).map_err(|e| format!("cannot read {shown}: {e}"))?;
    if file.metadata().is_ok_and(|m| m.is_dir()) {
        return Err(format!("{shown} is a folder, not a file"));
    }
    read_at_most(file, max_bytes, &shown)
}

/// As [`read_named`], as UTF-8 text.
pub fn read_named_text(path: &Path, max_bytes: u64) -> Result<String, String> {
    let bytes = read_named(path, max_bytes)?;
    String::from_utf8(bytes).map_err(|e| format!("{}: not UTF-8 text: {e}", path.display()))
}

/// The bytes of `file` when there are at most `max_bytes`; one more is read to tell.
fn read_at_most(file: File, max_bytes: u64, shown: &str) -> Result<Vec<u8>, String> {
    let mut bytes = Vec::new();
    file.take(max_bytes.saturating_add(1))
        .read_to_end(&mut bytes)
        .map_err(|e| format!("cannot read {shown}: {e}"))?;
    if bytes.len() as u64 > max_bytes {
        return Err(format!("{shown} holds more than {} bytes, the most this tool reads there", max_bytes));
    }
    Ok(bytes)
}

/// `relative` with `.` and inner `..` folded away, when it stays inside its folder.
fn lexically_inside(relative: &str) -> Result<PathBuf, String> {
    if relative.is_empty() {
        return Err("is empty: expected a path relative to the file's folder".into());
    }
    if relative.contains('\0') {
        return Err("holds a NUL character".into());
    }
    let mut out = PathBuf::new();
    let mut depth = 0usize;
    for component in Path::new(relative).components() {
        match component {
            Component::Normal(part) => {
                out.push(part);
                depth += 1;
            }
            Component::CurDir => {}
            Component::ParentDir if depth > 0 => {
                out.pop();
                depth -= 1;
            }
            Component::ParentDir => {
                return Err(format!(
                    "\"{relative}\" leaves the folder of the file that names it: only files inside it are read"
                ));
            }
            Component::RootDir | Component::Prefix(_) => {
                return Err(format!(
                    "\"{relative}\" is an absolute path: only paths relative to the file's folder, inside it, are read"
                ));
            }
        }
    }
    if depth == 0 {
        return Err(format!("\"{relative}\" names the folder itself, not a file in it"));
    }
    Ok(out)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn folder_with_file() -> tempfile::TempDir {
        let dir = tempfile::tempdir().unwrap();
        std::fs::create_dir_all(dir.path().join("scene/meshes")).unwrap();
        std::fs::write(dir.path().join("scene/meshes/a.obj"), b"v 0 0 0\n").unwrap();
        std::fs::write(dir.path().join("outside.obj"), b"v 1 1 1\n").unwrap();
        dir
    }

    #[test]
    fn files_inside_the_folder_are_read() {
        let dir = folder_with_file();
        let scene = dir.path().join("scene");
        for relative in ["meshes/a.obj", "./meshes/a.obj", "meshes/../meshes/a.obj"] {
            let (_, bytes) = read_inside(&scene, relative, 100).unwrap();
            assert_eq!(bytes, b"v 0 0 0\n", "{relative}");
        }
    }

    #[test]
    fn paths_that_leave_the_folder_are_refused_before_opening() {
        let dir = folder_with_file();
        let scene = dir.path().join("scene");
        let outside = dir.path().join("outside.obj").display().to_string();
        for (relative, says) in [
            ("../outside.obj", "leaves the folder"),
            ("meshes/../../outside.obj", "leaves the folder"),
            (outside.as_str(), "absolute path"),
            ("/dev/zero", "absolute path"),
            ("", "is empty"),
            (".", "names the folder itself"),
            ("meshes/a.obj\0", "NUL"),
        ] {
            let error = open_inside(&scene, relative).unwrap_err();
            assert!(error.contains(says), "{relative:?}: {error}");
        }
    }

    #[cfg(unix)]
    #[test]
    fn a_link_out_of_the_folder_and_a_fifo_are_refused() {
        let dir = folder_with_file();
        let scene = dir.path().join("scene");
        std::os::unix::fs::symlink(dir.path().join("outside.obj"), scene.join("link.obj")).unwrap();
        let error = open_inside(&scene, "link.obj").unwrap_err();
        assert!(error.contains("symbolic link"), "{error}");
        // A link that stays inside is followed.
        std::os::unix::fs::symlink(scene.join("meshes/a.obj"), scene.join("inner.obj")).unwrap();
        assert!(open_inside(&scene, "inner.obj").is_ok());
        let fifo = scene.join("pipe.obj");
        let status = std::process::Command::new("mkfifo").arg(&fifo).status().unwrap();
        assert!(status.success());
        // Opening the FIFO would block until a writer came: the check must come first.
        let error = open_inside(&scene, "pipe.obj").unwrap_err();
        assert!(error.contains("a FIFO"), "{error}");
        let error = open_inside(&scene, "meshes").unwrap_err();
        assert!(error.contains("a folder"), "{error}");
    }

    #[test]
    fn reads_stop_at_the_bound() {
        let dir = folder_with_file();
        let error = read_inside(&dir.path().join("scene"), "meshes/a.obj", 7).unwrap_err();
        assert!(error.contains("more than 7 bytes"), "{error}");
        assert_eq!(read_named(&dir.path().join("scene/meshes/a.obj"), 8).unwrap().len(), 8);
        // A device that never ends is read up to the bound and refused.
        let error = read_named(Path::new("/dev/zero"), 1 << 20).unwrap_err();
        assert!(error.contains("more than 1048576 bytes"), "{error}");
        let error = read_named(dir.path(), 10).unwrap_err();
        assert!(error.contains("a folder"), "{error}");
    }
}
