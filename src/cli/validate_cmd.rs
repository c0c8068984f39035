//! `blastsph validate`: every thesis scene run and compared with the thesis.

use super::folders::own_folder;
use super::{CaseArgs, on_pool, overrides, threads};
use crate::error::{Result, input};
use crate::runner::RunOptions;
use std::path::PathBuf;

/// `blastsph validate`: the thesis scenes run and compared with the thesis.
pub(super) fn validate(
    out: PathBuf,
    cases: Option<PathBuf>,
    only: Vec<String>,
    args: CaseArgs,
    th: Option<usize>,
    quiet: bool,
) -> Result<i32> {
    let cases = crate::casedir::folder(cases.as_deref())?;
    own_folder(&out, "validation.md", "validate")?;
    threads(th)?;
    for o in &only {
        if !crate::validate::SCENES.contains(&o.as_str()) {
            return Err(input(format!("--only {o}: not a thesis scene ({})", crate::validate::SCENES.join(", "))));
        }
    }
    // the scenes' folders are the validation's own: each run replaces its last
    let opts = RunOptions {
        out: None,
        sets: args.sets.clone(),
        ov: overrides(&args)?,
        quiet,
        threads: th,
        force: true,
        ..Default::default()
    };
    let md = on_pool(|| crate::validate::validate(&cases, &out, &opts, &only))?;
    println!("{md}");
    println!("written: {}", out.join("validation.md").display());
    Ok(0)
}
