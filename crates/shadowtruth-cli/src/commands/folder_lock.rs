//! The output folder of a command, locked before the command reads its inputs
//! (`shadowtruth::output_lock`), so that a second process writing there is refused at once.

use anyhow::Result;
use std::path::{Path, PathBuf};

/// The commands that write into a folder, and the argument that names it.
pub(super) const FOLDER_WRITING_COMMANDS: [(&str, &str); 9] = [
    ("run", "out"),
    ("papers", "out"),
    ("tune", "out"),
    ("score", "out"),
    ("merge", "out"),
    ("island", "out"),
    ("view-export", "out"),
    ("generate", "out"),
    ("report", "dir"),
];

/// Locks the output folder of the command in `matches`, if it writes one.
pub(super) fn lock_output_folder(matches: &clap::ArgMatches) -> Result<()> {
    let Some((command, sub)) = matches.subcommand() else { return Ok(()) };
    let Some((_, arg)) = FOLDER_WRITING_COMMANDS.iter().find(|(name, _)| *name == command) else {
        return Ok(());
    };
    let Some(path) = sub.try_get_one::<PathBuf>(arg).ok().flatten() else { return Ok(()) };
    // `report` takes a folder or the report.json in it.
    let dir = match (command == "report" && path.is_file()).then(|| path.parent()).flatten() {
        Some(parent) if parent.as_os_str().is_empty() => Path::new("."),
        Some(parent) => parent,
        None => path.as_path(),
    };
    match shadowtruth::output_lock::lock_output_folder(dir) {
        Err(held) if held.kind() == std::io::ErrorKind::WouldBlock => Err(held.into()),
        // Any other failure (the path is a file, or under one) is the command's to report,
        // naming its option, when it writes there.
        _ => Ok(()),
    }
}
