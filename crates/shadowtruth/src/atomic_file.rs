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
//!
//! Every output goes through here, and what is at its path decides how it is written
//! (`OutputTarget`): nothing or a regular file is replaced by the rename; a FIFO or a character
//! device (`/dev/stdout`, `/dev/null`, a terminal), or a symbolic link to one, is written into in
//! place, as a shell redirection writes it, and stays what it is; anything else (a folder, a
//! socket, a block device, any other symbolic link) is refused, naming the path and what it is,
//! since a rename would replace what the tool did not write.

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
    match output_target(path)? {
        OutputTarget::Replace => {}
        OutputTarget::Stream => return write_in_place(path, bytes),
        OutputTarget::Refuse(what) => return Err(refusal(path, &what)),
    }
    let mut tmp = temp_file_for(path)?;
    tmp.write_all(bytes)?;
    if sync {
        tmp.as_file().sync_all()?;
    }
    persist(tmp, path)
}

/// Renames a temporary file of `temp_file_for` over `path`, when `path` is still nothing or a
/// regular file: what is there may have changed while the file was written (an animation is
/// written over a whole run).
pub fn persist(tmp: NamedTempFile, path: &Path) -> std::io::Result<()> {
    match output_target(path)? {
        OutputTarget::Replace => {}
        OutputTarget::Stream => return Err(refusal(path, "a stream (FIFO or character device)")),
        OutputTarget::Refuse(what) => return Err(refusal(path, &what)),
    }
    // On failure the temporary file is removed when the returned `NamedTempFile` drops.
    tmp.persist(path).map_err(|e| e.error)?;
    Ok(())
}

/// A new temporary file beside `path` (its folder created), locked by this process until it is
/// persisted to `path` or dropped: for a file written piece by piece (an animation) that must
/// appear whole.
pub fn temp_file_for(path: &Path) -> std::io::Result<NamedTempFile> {
    match output_target(path)? {
        OutputTarget::Replace => {}
        OutputTarget::Stream => return Err(refusal(path, "a stream (FIFO or character device)")),
        OutputTarget::Refuse(what) => return Err(refusal(path, &what)),
    }
    let dir = path.parent().filter(|d| !d.as_os_str().is_empty()).unwrap_or(Path::new("."));
    std::fs::create_dir_all(dir)?;
    let name = path.file_name().map(|n| n.to_string_lossy().into_owned()).unwrap_or_default();
    locked_temp_file(dir, &name)
}

/// How an output path is written, from what is there now (see the module comment).
enum OutputTarget {
    /// Nothing, or a regular file: a temporary file renamed over it.
    Replace,
    /// A FIFO or character device, or a link to one: written into in place.
    Stream,
    /// Anything else, described (`a folder`).
    Refuse(String),
}

fn output_target(path: &Path) -> std::io::Result<OutputTarget> {
    let kind = match std::fs::symlink_metadata(path) {
        Err(e) if e.kind() == std::io::ErrorKind::NotFound => return Ok(OutputTarget::Replace),
        meta => meta?.file_type(),
    };
    if kind.is_file() {
        return Ok(OutputTarget::Replace);
    }
    if is_stream(&kind) {
        return Ok(OutputTarget::Stream);
    }
    if !kind.is_symlink() {
        return Ok(OutputTarget::Refuse(kind_name(&kind).to_string()));
    }
    // `/dev/stdout` is a link to the process's stream; a link to anything else is not ours to
    // replace, nor a place to write through to.
    Ok(match std::fs::metadata(path) {
        Ok(linked) if is_stream(&linked.file_type()) => OutputTarget::Stream,
        Ok(linked) => {
            OutputTarget::Refuse(format!("a symbolic link (to {})", kind_name(&linked.file_type())))
        }
        Err(_) => OutputTarget::Refuse("a symbolic link (to nothing)".to_string()),
    })
}

/// Whether a file of this type is written as a stream: a FIFO or a character device.
fn is_stream(kind: &std::fs::FileType) -> bool {
    #[cfg(unix)]
    {
        use std::os::unix::fs::FileTypeExt;
        kind.is_fifo() || kind.is_char_device()
    }
    #[cfg(not(unix))]
    {
        let _ = kind;
        false
    }
}

/// What a file of this type is, for messages (of outputs here, of inputs in `input_file.rs`).
pub(crate) fn kind_name(kind: &std::fs::FileType) -> &'static str {
    #[cfg(unix)]
    {
        use std::os::unix::fs::FileTypeExt;
        if kind.is_block_device() {
            return "a block device";
        }
        if kind.is_socket() {
            return "a socket";
        }
        if kind.is_fifo() {
            return "a FIFO";
        }
        if kind.is_char_device() {
            return "a character device";
        }
    }
    if kind.is_dir() {
        "a folder"
    } else if kind.is_symlink() {
        "a symbolic link"
    } else if kind.is_file() {
        "a regular file"
    } else {
        "not a regular file"
    }
}

fn refusal(path: &Path, what: &str) -> std::io::Error {
    std::io::Error::new(
        std::io::ErrorKind::AlreadyExists,
        format!("{}: is {what}, not a regular file: refusing to replace it", path.display()),
    )
}

/// Writes `bytes` into the FIFO or character device at `path` (never creating a file), as
/// `> path` in a shell would; errors (`/dev/full`: no space left) name the path.
fn write_in_place(path: &Path, bytes: &[u8]) -> std::io::Result<()> {
    let named = |e: std::io::Error| std::io::Error::new(e.kind(), format!("{}: {e}", path.display()));
    let mut file = std::fs::OpenOptions::new().write(true).open(path).map_err(named)?;
    // What was opened, not what was looked at a moment before, decides.
    let kind = file.metadata().map_err(named)?.file_type();
    if !is_stream(&kind) {
        return Err(refusal(path, kind_name(&kind)));
    }
    file.write_all(bytes).and_then(|()| file.flush()).map_err(named)
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
    fn what_is_not_a_regular_file_is_never_replaced() {
        let dir = tempfile::tempdir().unwrap();
        let (victim, link, folder) = (dir.path().join("v"), dir.path().join("l"), dir.path().join("d"));
        std::fs::write(&victim, "kept").unwrap();
        std::os::unix::fs::symlink(&victim, &link).unwrap();
        std::fs::create_dir(&folder).unwrap();
        let e = write_atomic(&link, b"new").unwrap_err().to_string();
        assert!(e.contains("l: is a symbolic link (to a regular file)"), "{e}");
        assert!(std::fs::symlink_metadata(&link).unwrap().file_type().is_symlink());
        assert!(temp_file_for(&folder).unwrap_err().to_string().contains("d: is a folder"));
        assert_eq!(std::fs::read_to_string(&victim).unwrap(), "kept");
        write_atomic(&victim, b"new").unwrap(); // a regular file is replaced
        assert_eq!(std::fs::read_to_string(&victim).unwrap(), "new");
    }

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
