//! One run of a renderer's command line: no shell, stdin closed, its output kept in files beside
//! its images, a wall-clock timeout, and every process it started ended with it.

use std::fs::File;
use std::io::{Read, Seek, SeekFrom};
use std::path::Path;
use std::process::{Command, ExitStatus, Stdio};
use std::time::{Duration, Instant};

/// Bytes of a failed command's stderr shown in its error.
const STDERR_TAIL_BYTES: u64 = 2000;
/// How often a running command is looked at: `std` has no timed wait, and 20 ms is nothing
/// beside a render.
const POLL: Duration = Duration::from_millis(20);

/// Why a command gave no images.
#[derive(Debug)]
pub(super) enum CommandFailure {
    Start(std::io::Error),
    Exit { status: ExitStatus, stderr_tail: String },
    Timeout { seconds: f64, stderr_tail: String },
}

impl std::fmt::Display for CommandFailure {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            CommandFailure::Start(e) => write!(f, "cannot start: {e}"),
            CommandFailure::Exit { status, stderr_tail } => write!(f, "{status}{}", tail_text(stderr_tail)),
            CommandFailure::Timeout { seconds, stderr_tail } => {
                write!(f, "still running after its timeout of {seconds} s; ended{}", tail_text(stderr_tail))
            }
        }
    }
}

fn tail_text(tail: &str) -> String {
    if tail.trim().is_empty() { String::new() } else { format!("; its stderr ends:\n{}", tail.trim_end()) }
}

/// Runs `argv` in the current folder, its stdout and stderr written to `log_dir`, and waits at
/// most `timeout_s`. A command that outlives its timeout is killed with everything it started.
pub(super) fn run_command(argv: &[String], log_dir: &Path, timeout_s: f64) -> Result<(), CommandFailure> {
    let stderr_path = log_dir.join("stderr.txt");
    let stdout = File::create(log_dir.join("stdout.txt")).map_err(CommandFailure::Start)?;
    let stderr = File::create(&stderr_path).map_err(CommandFailure::Start)?;
    let mut command = Command::new(&argv[0]);
    command.args(&argv[1..]).stdin(Stdio::null()).stdout(stdout).stderr(stderr);
    #[cfg(unix)]
    std::os::unix::process::CommandExt::process_group(&mut command, 0);
    let mut child = command.spawn().map_err(CommandFailure::Start)?;
    let deadline = Instant::now() + Duration::from_secs_f64(timeout_s);
    let status = loop {
        match child.try_wait() {
            Ok(Some(status)) => break Some(status),
            Ok(None) if Instant::now() >= deadline => break None,
            Ok(None) => std::thread::sleep(POLL),
            Err(e) => {
                end_group(&mut child);
                return Err(CommandFailure::Start(e));
            }
        }
    };
    // A browser the command left behind would outlive the plan.
    end_group(&mut child);
    let stderr_tail = || read_tail(&stderr_path);
    match status {
        Some(status) if status.success() => Ok(()),
        Some(status) => Err(CommandFailure::Exit { status, stderr_tail: stderr_tail() }),
        None => Err(CommandFailure::Timeout { seconds: timeout_s, stderr_tail: stderr_tail() }),
    }
}

/// Kills the command's process group (the command and what it started), then reaps the command.
fn end_group(child: &mut std::process::Child) {
    #[cfg(unix)]
    if let Ok(pid) = i32::try_from(child.id()) {
        // SAFETY: kill(2) with a negative pid signals that process group only: the group the
        // command was started in (`process_group(0)` made its id the command's pid).
        unsafe {
            libc::kill(-pid, libc::SIGKILL);
        }
    }
    #[cfg(not(unix))]
    let _ = child.kill();
    let _ = child.wait();
}

/// The last bytes of a log file, as text.
fn read_tail(path: &Path) -> String {
    let Ok(mut file) = File::open(path) else { return String::new() };
    let len = file.metadata().map(|m| m.len()).unwrap_or(0);
    let _ = file.seek(SeekFrom::Start(len.saturating_sub(STDERR_TAIL_BYTES)));
    let mut bytes = Vec::new();
    let _ = file.take(STDERR_TAIL_BYTES).read_to_end(&mut bytes);
    String::from_utf8_lossy(&bytes).into_owned()
}

#[cfg(all(test, target_os = "linux"))]
mod tests {
    use super::*;

    fn sh(script: &str) -> Vec<String> {
        vec!["sh".into(), "-c".into(), script.into()]
    }

    #[test]
    fn a_failing_command_reports_its_status_and_stderr_tail() {
        let dir = tempfile::tempdir().unwrap();
        assert!(run_command(&sh("echo fine"), dir.path(), 10.0).is_ok());
        let e =
            run_command(&sh("echo first >&2; echo 'no GPU here' >&2; exit 3"), dir.path(), 10.0).unwrap_err();
        let text = e.to_string();
        assert!(text.contains("exit status: 3") && text.ends_with("first\nno GPU here"), "{text}");
        let e = run_command(&["/nonexistent/renderer".to_string()], dir.path(), 10.0).unwrap_err();
        assert!(e.to_string().starts_with("cannot start"), "{e}");
    }

    #[test]
    fn a_command_past_its_timeout_is_ended_with_what_it_started() {
        let dir = tempfile::tempdir().unwrap();
        let marker = dir.path().join("child.pid");
        // The command starts a grandchild that would outlive it, then hangs.
        let script = format!("sleep 30 & echo $! > {}; echo waiting >&2; wait", marker.display());
        let started = Instant::now();
        let e = run_command(&sh(&script), dir.path(), 0.5).unwrap_err();
        assert!(started.elapsed() < Duration::from_secs(10), "ended at its timeout");
        assert!(matches!(e, CommandFailure::Timeout { .. }) && e.to_string().contains("waiting"), "{e}");
        let pid: i32 = std::fs::read_to_string(&marker).unwrap().trim().parse().unwrap();
        std::thread::sleep(Duration::from_millis(100));
        // Gone, or a zombie that no one has reaped yet (its parent was killed too): not running.
        let state = std::fs::read_to_string(format!("/proc/{pid}/stat")).unwrap_or_default();
        let running = state.rsplit_once(')').is_some_and(|(_, rest)| !rest.trim_start().starts_with('Z'));
        assert!(!running, "the grandchild {pid} was ended with the command: {state}");
    }
}
