//! One writer per output folder: a command that writes a folder (a report, a scene, an export)
//! first takes an exclusive advisory lock (flock, through `fs4`, as `atomic_file.rs`) on
//! `LOCK_FILE_NAME` in it, and a second process that finds the folder locked is refused before it
//! removes or writes anything there. Without it two runs into one folder both succeed while the
//! second's removal of earlier outputs deletes the first's figures and the last report written
//! wins.
//!
//! The system releases the lock when its process dies, so a killed run never leaves a stale lock:
//! the next run into its folder (`run --resume` among them) takes the lock as usual. The lock is
//! held until [`release_output_folders`] (the command's end), not only while report.json is open:
//! `tune` writes its own files after its report. A process takes each folder once; asking again
//! for a folder it holds is a no-op, so the command line and the report writer may both ask.
//!
//! The lock file holds its holder's PID, for the refusal's message only. It is removed when the
//! lock is released; a process that opened it just before then finds, once it holds the lock,
//! that the path no longer names its file, and starts over with the new one.

use fs4::FileExt;
use std::fs::File;
use std::io::{Read, Seek, Write};
use std::path::{Path, PathBuf};
use std::sync::Mutex;

/// The lock file in every folder being written.
pub const LOCK_FILE_NAME: &str = ".shadowtruth.lock";

/// How often a lock is taken again when its file keeps being replaced under it.
const LOCK_ATTEMPTS: usize = 8;

/// A folder this process holds.
struct HeldFolder {
    /// The folder, canonical.
    folder: PathBuf,
    /// Its lock file, open and locked.
    file: File,
    /// The folders created to lock it (it and missing parents), deepest first: removed again
    /// on release when they are still empty, so that a refused command leaves no folder.
    created: Vec<PathBuf>,
}

/// The folders this process holds.
static HELD: Mutex<Vec<HeldFolder>> = Mutex::new(Vec::new());

/// Locks the output folder `dir` (created if missing) for this process until
/// [`release_output_folders`]. Another live process writing it is an error naming the folder
/// (and that process's PID), returned before anything in the folder is touched.
pub fn lock_output_folder(dir: &Path) -> std::io::Result<()> {
    let missing = missing_folders(dir);
    std::fs::create_dir_all(dir).map_err(|e| named(dir, "cannot create the folder", e))?;
    let canonical = dir.canonicalize().map_err(|e| named(dir, "cannot resolve the folder", e))?;
    let created = missing.iter().filter_map(|d| d.canonicalize().ok()).collect();
    let mut held = HELD.lock().unwrap_or_else(|poisoned| poisoned.into_inner());
    if held.iter().any(|h| h.folder == canonical) {
        return Ok(());
    }
    let file = take_lock(dir, &canonical.join(LOCK_FILE_NAME))?;
    held.push(HeldFolder { folder: canonical, file, created });
    Ok(())
}

/// Releases every folder this process locked, removing their lock files (see the module
/// comment) and the folders created for them that stayed empty: called when a command ends.
pub fn release_output_folders() {
    let mut held = HELD.lock().unwrap_or_else(|poisoned| poisoned.into_inner());
    for HeldFolder { folder, file, created } in held.drain(..) {
        // Removed while still locked, so that no other process can take this file's lock.
        let _ = std::fs::remove_file(folder.join(LOCK_FILE_NAME));
        drop(file);
        for dir in created {
            if std::fs::remove_dir(&dir).is_err() {
                break; // holds files (or is gone): so do its parents
            }
        }
    }
}

/// `dir` and those of its parents that do not exist, deepest first.
fn missing_folders(dir: &Path) -> Vec<PathBuf> {
    dir.ancestors()
        .filter(|d| !d.as_os_str().is_empty())
        .take_while(|d| std::fs::symlink_metadata(d).is_err())
        .map(Path::to_path_buf)
        .collect()
}

/// The locked lock file at `path`, with this process's PID written into it.
fn take_lock(dir: &Path, path: &Path) -> std::io::Result<File> {
    for _ in 0..LOCK_ATTEMPTS {
        // A releaser may have removed the folder it had created.
        std::fs::create_dir_all(dir).map_err(|e| named(dir, "cannot create the folder", e))?;
        let mut file = open_lock_file(path).map_err(|e| named(path, "cannot open the lock file", e))?;
        match FileExt::try_lock(&file) {
            Ok(()) => {}
            Err(fs4::TryLockError::WouldBlock) => return Err(held_elsewhere(dir, &mut file)),
            // A file system without locks: no process can lock the folder, so none is refused.
            Err(fs4::TryLockError::Error(_)) => return Ok(file),
        }
        if !still_at(&file, path) {
            continue; // its holder removed it as it released it: lock the new one
        }
        file.set_len(0)?;
        write!(file, "{}", std::process::id())?;
        return Ok(file);
    }
    Err(named(path, "the lock file kept being replaced", std::io::Error::other("try again")))
}

/// Opens (or creates) a lock file for reading and writing, never through a symbolic link: a
/// folder that arrived from elsewhere may hold a lock file that links to a file of the user's,
/// which the PID written into it would overwrite. Anything but a regular file is refused.
pub(crate) fn open_lock_file(path: &Path) -> std::io::Result<File> {
    let mut options = std::fs::OpenOptions::new();
    options.read(true).write(true).create(true).truncate(false);
    #[cfg(unix)]
    std::os::unix::fs::OpenOptionsExt::custom_flags(&mut options, libc::O_NOFOLLOW | libc::O_NONBLOCK);
    let file = options.open(path)?;
    if !file.metadata()?.is_file() {
        return Err(std::io::Error::other("not a regular file"));
    }
    Ok(file)
}

/// Whether `path` still names the open `file` (same device and inode).
#[cfg(unix)]
fn still_at(file: &File, path: &Path) -> bool {
    use std::os::unix::fs::MetadataExt;
    match (file.metadata(), std::fs::metadata(path)) {
        (Ok(open), Ok(named)) => open.dev() == named.dev() && open.ino() == named.ino(),
        _ => false,
    }
}

#[cfg(not(unix))]
fn still_at(_file: &File, path: &Path) -> bool {
    path.is_file()
}

/// The refusal of a folder that another live process holds, naming it and that process.
fn held_elsewhere(dir: &Path, file: &mut File) -> std::io::Error {
    let mut pid = String::new();
    let _ = file.rewind().and_then(|()| Read::by_ref(file).take(32).read_to_string(&mut pid));
    let pid = pid.trim();
    let who = if pid.chars().all(|c| c.is_ascii_digit()) && !pid.is_empty() {
        format!("another shadowtruth process (PID {pid})")
    } else {
        "another shadowtruth process".to_string()
    };
    std::io::Error::new(
        std::io::ErrorKind::WouldBlock,
        format!(
            "{}: {who} is writing into this output folder; wait for it to end or write into another folder",
            dir.display()
        ),
    )
}

fn named(path: &Path, what: &str, e: std::io::Error) -> std::io::Error {
    std::io::Error::new(e.kind(), format!("{}: {what}: {e}", path.display()))
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A lock file that links elsewhere is refused and what it links to stays as it was.
    #[cfg(unix)]
    #[test]
    fn a_lock_file_that_is_a_link_is_never_written_through() {
        let dir = tempfile::tempdir().unwrap();
        let theirs = dir.path().join("theirs.txt");
        std::fs::write(&theirs, b"keep me").unwrap();
        let out = dir.path().join("out");
        std::fs::create_dir(&out).unwrap();
        std::os::unix::fs::symlink(&theirs, out.join(LOCK_FILE_NAME)).unwrap();
        assert!(lock_output_folder(&out).is_err());
        assert!(open_lock_file(&out.join(LOCK_FILE_NAME)).is_err());
        assert_eq!(std::fs::read(&theirs).unwrap(), b"keep me");
        // A dangling link creates nothing where it points.
        let dangling = dir.path().join("dangling");
        std::fs::create_dir(&dangling).unwrap();
        std::os::unix::fs::symlink(dir.path().join("nowhere"), dangling.join(LOCK_FILE_NAME)).unwrap();
        assert!(open_lock_file(&dangling.join(LOCK_FILE_NAME)).is_err());
        assert!(!dir.path().join("nowhere").exists());
    }

    #[test]
    fn a_folder_locked_by_another_open_file_is_refused_with_its_pid() {
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join(LOCK_FILE_NAME);
        let mut other = File::create(&path).unwrap();
        FileExt::lock(&other).unwrap();
        write!(other, "4242").unwrap();
        let e = lock_output_folder(dir.path()).unwrap_err();
        assert!(e.to_string().contains(&dir.path().display().to_string()), "{e}");
        assert!(e.to_string().contains("PID 4242"), "{e}");
        drop(other); // as when its process dies
        lock_output_folder(dir.path()).unwrap();
        lock_output_folder(dir.path()).unwrap(); // held by this process already
        assert_eq!(std::fs::read_to_string(&path).unwrap(), std::process::id().to_string());
    }
}
