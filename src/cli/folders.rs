//! The folders a command writes into: a new or empty one, or one of its own kind.

use super::*;

/// Refuses an `--out` of `bench`, `validate` or `legacy build` that cannot be a folder (a file, a
/// link, a path under a file) before anything is computed. (Their folders are their own: what
/// they hold is replaced.)
pub(super) fn out_folder(dir: &Path) -> Result<()> {
    crate::rundir::inspect(dir, "--out").map(|_| ())
}

/// Refuses an `--out` of `bench` or `validate` that is not new, empty or the command's own
/// earlier output (`marker`, the file it always writes there): a run directory or a folder of
/// other files is not written into.
pub(super) fn own_folder(dir: &Path, marker: &str, what: &str) -> Result<()> {
    match crate::rundir::inspect(dir, "--out")? {
        crate::rundir::Found::Missing | crate::rundir::Found::Empty => Ok(()),
        _ if dir.join(marker).is_file() => Ok(()),
        crate::rundir::Found::Run { .. } => Err(input(format!(
            "--out {}: a run directory: give {what} a new or empty folder (or one of its own, with {marker})",
            dir.display()
        ))),
        crate::rundir::Found::Other(name) => Err(input(format!(
            "--out {}: it holds `{name}`, which no {what} wrote there: give a new or empty folder (or one of its own, with {marker})",
            dir.display()
        ))),
    }
}

/// Refuses an `--out` of `dual` or `legacy ledger` that holds files blastsph did not write or
/// another of its outputs (a run's files): its own earlier report (`ours`) is replaced, a run
/// directory is not mixed with it.
pub(super) fn report_folder(dir: &Path, ours: &[&str], what: &str) -> Result<()> {
    match crate::rundir::inspect(dir, "--out")? {
        crate::rundir::Found::Other(name) => Err(input(format!(
            "--out {}: holds `{name}`, which blastsph did not write: give an empty or new folder",
            dir.display()
        ))),
        // a `.tmp` of one of ours counts as it
        crate::rundir::Found::Run { names, .. } => {
            match names.iter().find(|n| !ours.contains(&n.strip_suffix(".tmp").unwrap_or(n))) {
                Some(name) => Err(input(format!(
                    "--out {}: holds another blastsph output (`{name}`): give the {what} an empty or new folder, or an earlier {what}'s",
                    dir.display()
                ))),
                None => Ok(()),
            }
        }
        _ => Ok(()),
    }
}

/// Checks the --progress-every value and sets it.
pub(super) fn progress_every(s: f64) -> Result<()> {
    if !(s.is_finite() && (0.0..=1e9).contains(&s)) {
        return Err(input(format!("--progress-every {s}: must be 0 to 1e9 seconds")));
    }
    crate::progress::set_every(s);
    Ok(())
}
