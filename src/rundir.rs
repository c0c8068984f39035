//! Run directories (docs/reference/output.md): what a run may write where.
//!
//! - A run writes into an empty or new folder; a folder that holds anything else is refused
//!   unless it is the run's own restart (the same case, an unfinished run with a checkpoint) or
//!   `--force` is given, which clears it first — and clears only what blastsph writes (a folder
//!   holding other files is refused even then: `--force` never deletes a user's files).
//! - Files are created without following symbolic links: new files with `O_CREAT | O_EXCL`
//!   (which never follows a link), files appended to with `O_NOFOLLOW`, and rewritten files
//!   through a new temporary file renamed over the old (a rename replaces a link, it does not
//!   write through it). A run directory holds no links; `report` and `resume` refuse one that
//!   does.
//! - The default folder `runs/<name>` takes the case's name sanitised: letters, digits, `-`,
//!   `_` and inner `.` kept, everything else `_` (so "../../x" and "/tmp/x" stay inside `runs/`).

use crate::error::{IoAt, Result, SphError, input};
use std::fs::{File, OpenOptions};
use std::path::{Path, PathBuf};

use crate::files::nofollow;
pub use crate::files::open_rw;
pub(crate) use crate::files::{create_new, open_append, write_atomic, write_atomic_with};

/// The files blastsph writes into a run directory (and their temporaries).
pub(crate) fn is_ours(name: &str) -> bool {
    let base = name.strip_suffix(".tmp").unwrap_or(name);
    matches!(
        base,
        "particles.h5"
            | "particles.xmf"
            | "summary.json"
            | "gauges.csv"
            | "case.toml"
            | "checkpoint.bin"
            | "report.json"
            | "animation.gif"
            | "dual_report.json"
            | "dual_free.json"
            | "ledger.json"
            | "revolved.h5"
            | "revolved.h5.part"
            | "revolved.xmf"
            | LOCK
    ) || (base.ends_with(".png") && !base.contains('/'))
}

/// The file a run locks (flock) in its run directory while it writes it.
pub(crate) const LOCK: &str = "run.lock";

/// A lock on a run directory, held until it is dropped (or the process ends, however it ends).
pub struct DirLock(#[allow(dead_code)] File);

/// Takes the run directory `dir` (which exists) for a run or a resume: an exclusive lock on
/// `dir/run.lock`; refused with one line when another process holds it (a run writing the
/// folder). A file system without locks is not refused (nothing to lock with).
pub(crate) fn lock_run(dir: &Path, what: &str) -> Result<DirLock> {
    let path = dir.join(LOCK);
    let mut o = OpenOptions::new();
    o.read(true).write(true).create(true).truncate(false);
    nofollow(&mut o);
    let f = o.open(&path).map_err(|e| input(format!("{what} {}: cannot open {LOCK} ({e})", dir.display())))?;
    match f.try_lock() {
        Ok(()) => Ok(DirLock(f)),
        Err(std::fs::TryLockError::WouldBlock) => Err(input(format!(
            "{what} {}: a run is writing it now (another blastsph process holds its {LOCK}): wait for it to end, or stop it (Ctrl-C, kill -TERM) first",
            dir.display()
        ))),
        Err(std::fs::TryLockError::Error(_)) => Ok(DirLock(f)),
    }
}

/// For a reader of a run directory (`report`, `revolve`): refused with one line while a run
/// holds the folder's lock (its particles.h5 is open for writing and its summary not final);
/// `None` where the folder has no lock file.
pub(crate) fn lock_read(dir: &Path, what: &str) -> Result<Option<DirLock>> {
    let path = dir.join(LOCK);
    let mut o = OpenOptions::new();
    o.read(true);
    nofollow(&mut o);
    let Ok(f) = o.open(&path) else { return Ok(None) };
    match f.try_lock_shared() {
        Ok(()) => Ok(Some(DirLock(f))),
        Err(std::fs::TryLockError::WouldBlock) => Err(input(format!(
            "{what} {}: a run is writing it now (another blastsph process holds its {LOCK}): {what} it when the run has ended or stopped, or {what} a copy of the folder",
            dir.display()
        ))),
        Err(std::fs::TryLockError::Error(_)) => Ok(None),
    }
}

/// A folder name from a case name: at most 100 characters of `[A-Za-z0-9._-]`, others `_`, no
/// leading `.`; "case" when nothing is left.
pub(crate) fn sanitize(name: &str) -> String {
    let mut s: String = name
        .chars()
        .take(100)
        .map(|c| if c.is_ascii_alphanumeric() || matches!(c, '-' | '_' | '.') { c } else { '_' })
        .collect();
    while s.starts_with('.') {
        s.replace_range(..1, "_");
    }
    if s.is_empty() || s.chars().all(|c| c == '_') { "case".to_string() } else { s }
}

/// The default run directory of a case: `runs/<sanitised name>`.
pub(crate) fn default_dir(case_name: &str) -> PathBuf {
    PathBuf::from("runs").join(sanitize(case_name))
}

/// What a run directory holds now.
#[derive(Debug, Clone, PartialEq, Eq)]
pub enum Found {
    /// Nothing there yet (its nearest existing ancestor is a folder).
    Missing,
    /// An empty folder.
    Empty,
    /// A folder with entries, all of them blastsph's: `case.toml`'s text, whether a
    /// checkpoint is there, and the entries' names (sorted).
    Run { case_toml: Option<String>, checkpoint: bool, names: Vec<String> },
    /// A folder with something blastsph did not write (its name).
    Other(String),
}

fn io(dir: &Path, e: std::io::Error) -> SphError {
    input(format!("{}: {e}", dir.display()))
}

/// The plots `blastsph report` writes into a run directory, by name (the snapshots' names carry
/// their times); every PNG a report writes is one of them (tests/engineer.rs).
pub fn is_report_plot(name: &str) -> bool {
    const FIXED: [&str; 12] = [
        "bubble_growth.png",
        "crater_growth.png",
        "crater_map.png",
        "crater_profile.png",
        "density_map.png",
        "ejecta_height.png",
        "gauges.png",
        "gauges_velocity.png",
        "peaks.png",
        "ppv_map.png",
        "profiles.png",
        "animation.gif",
    ];
    FIXED.contains(&name)
        || (name.ends_with(".png")
            && ["snap_material_", "snap_pressure_", "snap_velocity_"].iter().any(|p| name.starts_with(p)))
}

/// Removes what `blastsph revolve` wrote into a run directory (revolved.h5, revolved.xmf, and a
/// revolve's unfinished `revolved.h5.part`): when a run is resumed, since they hold the frames of
/// the run as it was.
pub(crate) fn remove_revolved(dir: &Path) -> Result<()> {
    for name in ["revolved.h5", "revolved.h5.part", "revolved.xmf", "revolved.xmf.tmp"] {
        remove_stale(&dir.join(name))?;
    }
    Ok(())
}

/// Removes what `blastsph report` wrote into a run directory (report.json, its plots by name,
/// animation.gif, and their `.tmp`; a PNG of another name is left): before a new report (its
/// snapshot names follow its times, so an earlier report's would stay beside it) and when a run
/// is resumed.
pub(crate) fn remove_report(dir: &Path) -> Result<()> {
    for e in std::fs::read_dir(dir).map_err(|e| io(dir, e))? {
        let e = e.map_err(|e| io(dir, e))?;
        let name = e.file_name().to_string_lossy().into_owned();
        let base = name.strip_suffix(".tmp").unwrap_or(&name);
        let ft = e.file_type().map_err(|e| io(dir, e))?;
        if ft.is_file() && (base == "report.json" || is_report_plot(base)) {
            std::fs::remove_file(e.path()).io_at(name)?;
        }
    }
    Ok(())
}

/// Looks at `dir` without writing: refuses a path that is a link, a file, or lies under a file.
pub(crate) fn inspect(dir: &Path, flag: &str) -> Result<Found> {
    let shown = dir.display();
    // a new folder's name with a control character (a newline from a shell's $(...)) is a
    // mistake, and breaks every line that names it
    if let Some(c) = dir.to_string_lossy().chars().find(|c| c.is_control()) {
        return Err(input(format!("{flag} {:?}: the path holds the control character {c:?}", dir.to_string_lossy())));
    }
    match std::fs::symlink_metadata(dir) {
        Err(e) if e.kind() == std::io::ErrorKind::NotFound => {
            // the nearest ancestor that exists must be a folder
            let mut a = dir.parent();
            while let Some(p) = a {
                if p.as_os_str().is_empty() {
                    break;
                }
                match std::fs::metadata(p) {
                    Ok(m) if m.is_dir() => break,
                    Ok(_) => return Err(input(format!("{flag} {shown}: {} is not a folder", p.display()))),
                    Err(_) => a = p.parent(),
                }
            }
            Ok(Found::Missing)
        }
        Err(e) => Err(input(format!("{flag} {shown}: {e}"))),
        Ok(m) if m.file_type().is_symlink() => {
            Err(input(format!("{flag} {shown}: a symbolic link (give the folder it points to)")))
        }
        Ok(m) if !m.is_dir() => Err(input(format!("{flag} {shown}: exists and is not a folder"))),
        Ok(_) => {
            let mut entries = Vec::new();
            for e in std::fs::read_dir(dir).map_err(|e| input(format!("{flag} {shown}: {e}")))? {
                let e = e.map_err(|e| io(dir, e))?;
                let name = e.file_name().to_string_lossy().into_owned();
                let ft = e.file_type().map_err(|e| io(dir, e))?;
                if ft.is_symlink() || ft.is_dir() || !is_ours(&name) {
                    return Ok(Found::Other(name));
                }
                // the lock alone is no run
                if name != LOCK {
                    entries.push(name);
                }
            }
            if entries.is_empty() {
                return Ok(Found::Empty);
            }
            let case_toml = if entries.iter().any(|n| n == "case.toml") {
                crate::case::read_text(&dir.join("case.toml")).ok()
            } else {
                None
            };
            let checkpoint = entries.iter().any(|n| n == "checkpoint.bin");
            entries.sort();
            Ok(Found::Run { case_toml, checkpoint, names: entries })
        }
    }
}

/// Makes `dir` (and its parents); with `clear`, removes blastsph's files from it first (links
/// are removed, never followed). Call after [`inspect`] accepted it.
pub(crate) fn prepare(dir: &Path, clear: bool) -> Result<()> {
    std::fs::create_dir_all(dir).map_err(|e| input(format!("cannot make the run directory {}: {e}", dir.display())))?;
    if clear {
        // every entry is looked at before any is removed: a refusal leaves the folder whole
        let mut gone = Vec::new();
        for e in std::fs::read_dir(dir).map_err(|e| io(dir, e))? {
            let e = e.map_err(|e| io(dir, e))?;
            let name = e.file_name().to_string_lossy().into_owned();
            let ft = e.file_type().map_err(|e| io(dir, e))?;
            // (the lock stays: the run clearing the folder holds it)
            if name == LOCK && ft.is_file() {
                continue;
            }
            if ft.is_dir() || !(is_ours(&name) || ft.is_symlink()) {
                return Err(input(format!(
                    "--force {}: it holds `{name}`, which blastsph did not write (--force clears only run directories)",
                    dir.display()
                )));
            }
            gone.push(e.path());
        }
        for p in gone {
            std::fs::remove_file(&p).map_err(|e| io(dir, e))?;
        }
    }
    Ok(())
}

/// Refuses a run directory given to `report` or `resume` that is not one: missing, not a folder,
/// a link, or holding a link.
pub(crate) fn check_existing(dir: &Path, what: &str) -> Result<()> {
    let shown = dir.display();
    let m = std::fs::symlink_metadata(dir).map_err(|e| input(format!("{what} {shown}: {e}")))?;
    if m.file_type().is_symlink() {
        return Err(input(format!("{what} {shown}: a symbolic link (give the run directory itself)")));
    }
    if !m.is_dir() {
        return Err(input(format!("{what} {shown}: not a run directory (not a folder)")));
    }
    for e in std::fs::read_dir(dir).map_err(|e| input(format!("{what} {shown}: {e}")))? {
        let e = e.map_err(|e| io(dir, e))?;
        if e.file_type().map_err(|e| io(dir, e))?.is_symlink() {
            return Err(input(format!(
                "{what} {shown}: it holds a symbolic link, {} (a run directory holds none; nothing written)",
                e.file_name().to_string_lossy()
            )));
        }
    }
    Ok(())
}

/// Removes a temporary file a killed writer may have left (none is no error).
pub(crate) fn remove_stale(tmp: &Path) -> Result<()> {
    match std::fs::remove_file(tmp) {
        Ok(()) => Ok(()),
        Err(e) if e.kind() == std::io::ErrorKind::NotFound => Ok(()),
        Err(e) => Err(SphError::Io(format!("{}: {e}", tmp.display()))),
    }
}

/// The SHA-256 digest of `bytes` in lower-case hexadecimal (the case files' fingerprints).
pub(crate) fn sha256_hex(bytes: &[u8]) -> String {
    use sha2::{Digest, Sha256};
    let d = Sha256::digest(bytes);
    d.iter().map(|b| format!("{b:02x}")).collect()
}
