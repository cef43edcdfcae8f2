//! Writes a file so that readers see the old content or the new one, never a half-written file:
//! the bytes go to a temporary file beside the target (`tempfile`, named
//! `.shadowtruth-tmp.PID.NAME.RANDOM`), which is then renamed over it.
//!
//! A process killed while writing leaves its temporary file behind; `remove_stray_temp_files`
//! removes such strays. To tell a stray from a file that a live process is still writing, every
//! writer holds an exclusive advisory lock (flock, through `fs4`) on its temporary file from just
//! after creating it until the rename, and the system drops the lock when the process dies: a
//! temporary file whose lock can be taken is a stray. A lock is used rather than the PID in the
//! name because PIDs are reused and mean nothing across PID namespaces (containers sharing a
//! folder); the PID in the name only keeps a process from removing its own files, which file
//! systems that emulate flock with per-process locks (NFS) would let it lock.
//!
//! A cleaner may lock a temporary file in the instant between its creation and its writer's
//! lock; the writer's lock then waits until the cleaner has removed it, the writer finds its file
//! gone and starts over with a new one.

use std::io::Write;
use std::path::Path;
use tempfile::NamedTempFile;

/// The start of the name of every temporary file this tool writes.
pub const TEMP_PREFIX: &str = ".shadowtruth-tmp.";

/// How many temporary files a write creates before giving up when cleaners keep removing them.
const TEMP_FILE_ATTEMPTS: usize = 8;

/// The longest part of the target's name kept in a temporary file's name.
const TARGET_NAME_CHARS: usize = 64;

/// Writes `bytes` to `path` through a synced temporary file renamed over it.
pub fn write_atomic(path: &Path, bytes: &[u8]) -> std::io::Result<()> {
    replace_file(path, bytes, true)
}

/// As `write_atomic`, without the fsync: for derived files that a rerun regenerates (figures),
/// where an fsync costs more than drawing the file. A killed process still never leaves a
/// half-written file.
pub fn write_atomic_unsynced(path: &Path, bytes: &[u8]) -> std::io::Result<()> {
    replace_file(path, bytes, false)
}

fn replace_file(path: &Path, bytes: &[u8], sync: bool) -> std::io::Result<()> {
    let mut tmp = temp_file_for(path)?;
    tmp.write_all(bytes)?;
    if sync {
        tmp.as_file().sync_all()?;
    }
    // On failure the temporary file is removed when the returned `NamedTempFile` drops.
    tmp.persist(path).map_err(|e| e.error)?;
    Ok(())
}

/// A new temporary file beside `path` (its folder created), locked by this process until it is
/// persisted to `path` or dropped: for a file written piece by piece (an animation) that must
/// appear whole.
pub fn temp_file_for(path: &Path) -> std::io::Result<NamedTempFile> {
    let dir = path.parent().filter(|d| !d.as_os_str().is_empty()).unwrap_or(Path::new("."));
    std::fs::create_dir_all(dir)?;
    let name = path.file_name().map(|n| n.to_string_lossy().into_owned()).unwrap_or_default();
    locked_temp_file(dir, &name)
}

/// A new temporary file in `dir` for the target `target_name`, exclusively locked by this
/// process (see the module comment).
fn locked_temp_file(dir: &Path, target_name: &str) -> std::io::Result<NamedTempFile> {
    let short_name: String = target_name.chars().take(TARGET_NAME_CHARS).collect();
    let prefix = format!("{}{short_name}.", own_temp_prefix());
    for _ in 0..TEMP_FILE_ATTEMPTS {
        let tmp = temp_file_builder(&prefix).tempfile_in(dir)?;
        // On a file system without locks no cleaner can lock the file either, so it is never
        // taken for a stray: writing on without the lock is safe.
        let _ = fs4::FileExt::lock(tmp.as_file());
        if tmp.path().exists() {
            return Ok(tmp);
        }
    }
    Err(std::io::Error::other(format!("temporary files in {} kept being removed", dir.display())))
}

/// Temporary files named `prefix` + random characters, created with the permissions of a plain
/// new file (`tempfile` alone would make them private to their owner, and so the renamed file).
fn temp_file_builder(prefix: &str) -> tempfile::Builder<'_, 'static> {
    let mut builder = tempfile::Builder::new();
    builder.prefix(prefix);
    #[cfg(unix)]
    builder.permissions(std::os::unix::fs::PermissionsExt::from_mode(0o666));
    builder
}

/// The prefix of this process's temporary files.
fn own_temp_prefix() -> String {
    format!("{TEMP_PREFIX}{}.", std::process::id())
}

/// Removes from `dir` (not its subfolders) the temporary files whose writers died before renaming
/// them; those a live process still writes are kept. Returns how many were removed; a missing
/// folder holds none.
pub fn remove_stray_temp_files(dir: &Path) -> std::io::Result<usize> {
    let entries = match std::fs::read_dir(dir) {
        Err(e) if e.kind() == std::io::ErrorKind::NotFound => return Ok(0),
        entries => entries?,
    };
    let own = own_temp_prefix();
    let mut removed = 0;
    for entry in entries {
        let entry = entry?;
        let name = entry.file_name().to_string_lossy().into_owned();
        let another_process_temp = name.starts_with(TEMP_PREFIX) && !name.starts_with(&own);
        if another_process_temp && entry.file_type()?.is_file() && remove_if_unlocked(&entry.path()) {
            removed += 1;
        }
    }
    Ok(removed)
}

/// Removes `path` when its lock can be taken: no live process is writing it. The lock is held
/// until the file is gone, so that a writer that created it a moment ago sees it removed.
fn remove_if_unlocked(path: &Path) -> bool {
    let Ok(file) = std::fs::OpenOptions::new().read(true).write(true).open(path) else {
        return false; // renamed into place (or removed) since the folder was listed
    };
    fs4::FileExt::try_lock(&file).is_ok() && std::fs::remove_file(path).is_ok()
}

/// A grey-level image as PNG bytes.
pub fn encode_gray_png(width: u32, height: u32, pixels: &[u8]) -> std::io::Result<Vec<u8>> {
    let mut out = Vec::new();
    image::codecs::png::PngEncoder::new(&mut out)
        .write_image(pixels, width, height, image::ExtendedColorType::L8)
        .map_err(std::io::Error::other)?;
    Ok(out)
}

/// An RGB image as PNG bytes.
pub fn encode_rgb_png(width: u32, height: u32, pixels: &[u8]) -> std::io::Result<Vec<u8>> {
    let mut out = Vec::new();
    image::codecs::png::PngEncoder::new(&mut out)
        .write_image(pixels, width, height, image::ExtendedColorType::Rgb8)
        .map_err(std::io::Error::other)?;
    Ok(out)
}

use image::ImageEncoder;

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_temp_file_is_a_stray_once_its_writer_is_gone() {
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join(format!("{TEMP_PREFIX}0.x.XyZ789"));
        let file = std::fs::File::create(&path).unwrap();
        fs4::FileExt::lock(&file).unwrap();
        assert_eq!(remove_stray_temp_files(dir.path()).unwrap(), 0);
        drop(file);
        assert_eq!(remove_stray_temp_files(dir.path()).unwrap(), 1);
        assert!(!path.exists());
    }
}
