//! The command line of `blastsph converge`.

use super::ConvergeOptions;
use crate::error::Result;
use crate::sim::Overrides;
use std::path::PathBuf;

#[derive(clap::Args, Debug, Clone)]
pub struct ConvergeArgs {
    /// The case: a .toml file, or the name of one in the case folder (see --case-dir)
    pub case: PathBuf,
    /// Levels of the ladder, 2 to 4: k = b, 2b, 4b (, 8b), b from --base; every spacing Δx becomes Δx/k
    #[arg(long, default_value_t = 3)]
    pub levels: usize,
    /// The first level's k (0.25: a ladder from four times as coarse as the case, k = 0.25, 0.5, 1)
    #[arg(long, default_value_t = 1.0, allow_hyphen_values = true)]
    pub base: f64,
    /// Where converge.json, the plots and the level runs (level_K/) go (default: `runs/<case name>_converge`)
    #[arg(long, value_name = "DIR")]
    pub out: Option<PathBuf>,
    /// Override a case key at every level, before its refinement: --set time.end_s=0.1
    #[arg(long = "set", value_name = "KEY=VALUE")]
    pub sets: Vec<String>,
    /// Folder to look a case name up in (default as for `run`)
    #[arg(long = "case-dir", value_name = "DIR")]
    pub case_dir: Option<PathBuf>,
    /// Worker threads of the Rust modules (default: one per core); the results do not depend on it
    #[arg(long, value_name = "N")]
    pub threads: Option<usize>,
}

impl ConvergeArgs {
    /// The case file and the options; the default folder from the case's name.
    pub fn options(&self) -> Result<(PathBuf, ConvergeOptions)> {
        let case = crate::casedir::resolve(&self.case, self.case_dir.as_deref())?;
        let out = match &self.out {
            Some(o) => o.clone(),
            None => {
                let c = crate::case::load(&case, &self.sets)?;
                PathBuf::from("runs").join(format!("{}_converge", crate::rundir::sanitize(c.name())))
            }
        };
        Ok((
            case,
            ConvergeOptions {
                levels: self.levels,
                base: self.base,
                out,
                sets: self.sets.clone(),
                ov: Overrides::default(),
            },
        ))
    }
}
