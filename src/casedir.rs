//! Where `run`, `check`, `dual`, `validate` and `bench` find a case given by name: `--case-dir
//! DIR` when given; else the `cases/` folder of the repository the current directory is in
//! (the nearest ancestor holding `cases/` beside a `Cargo.toml`); else the `cases/` folder of the
//! source tree this binary was built from, when it still exists. A name that is found nowhere is
//! refused with one line that says where it looked.

use crate::error::{Result, input};
use std::path::{Path, PathBuf};

/// The folders to look in, in order (existing ones only).
pub fn candidates(case_dir: Option<&Path>) -> Vec<PathBuf> {
    if let Some(d) = case_dir {
        return vec![d.to_path_buf()];
    }
    let mut out = Vec::new();
    if let Ok(cwd) = std::env::current_dir() {
        for a in cwd.ancestors() {
            if a.join("cases").is_dir() && a.join("Cargo.toml").is_file() {
                out.push(a.join("cases"));
                break;
            }
        }
    }
    let built = Path::new(env!("CARGO_MANIFEST_DIR")).join("cases");
    if built.is_dir() && !out.contains(&built) {
        out.push(built);
    }
    out
}

/// The case folder: `--case-dir`, or the first candidate; an error saying where it looked.
pub fn folder(case_dir: Option<&Path>) -> Result<PathBuf> {
    if let Some(d) = case_dir {
        if d.is_dir() {
            return Ok(d.to_path_buf());
        }
        return Err(input(format!("--case-dir {}: no such folder", d.display())));
    }
    candidates(None).into_iter().next().ok_or_else(|| {
        input(format!(
            "no case folder: give --case-dir DIR (looked for cases/ beside a Cargo.toml from {} upwards, and in {})",
            std::env::current_dir().map(|p| p.display().to_string()).unwrap_or_else(|_| "?".into()),
            Path::new(env!("CARGO_MANIFEST_DIR")).join("cases").display()
        ))
    })
}

/// A case given as a path (kept as it is when it names a file, or holds a `/` or ends in
/// `.toml`) or as a name (`surface_loose_tnt6`, `hard/coarse_25`) looked up in the case folders.
pub fn resolve(case: &Path, case_dir: Option<&Path>) -> Result<PathBuf> {
    let s = case.to_string_lossy();
    let not_a_file = || input(format!("{s}: not a regular file (a case is a .toml file)"));
    let looks_like_path = s.ends_with(".toml") || case.is_file() || (case_dir.is_none() && s.starts_with('.'));
    if looks_like_path {
        if case.exists() && !case.is_file() {
            return Err(not_a_file());
        }
        return Ok(case.to_path_buf());
    }
    let dirs = candidates(case_dir);
    for d in &dirs {
        let p = d.join(format!("{s}.toml"));
        if p.is_file() {
            return Ok(p);
        }
    }
    if case.exists() {
        return Err(not_a_file());
    }
    if dirs.is_empty() {
        return Err(input(format!(
            "{s}: no such case file, and no case folder to look it up in (give --case-dir DIR)"
        )));
    }
    Err(input(format!(
        "{s}: no such case file, and no {s}.toml in {}",
        dirs.iter().map(|d| d.display().to_string()).collect::<Vec<_>>().join(" or ")
    )))
}
