//! `blastsph legacy ...`: build, ledger and host mode of a user's legacy code
//! (docs/howto/migrate.md).

use super::*;

#[derive(Subcommand, Debug)]
pub enum LegacyCmd {
    /// Compile the legacy sources of a manifest, unmodified, with generated shims into
    /// DIR/liblegacy.so; DIR/build.json says what was built, DIR/build.log holds the compiler's output
    Build {
        /// The manifest (legacy.toml) beside the legacy sources
        manifest: PathBuf,
        /// The build folder (default: runs/legacy_<name of the manifest's folder>)
        #[arg(long)]
        out: Option<PathBuf>,
    },
    /// The defect ledger: the case run with your routines, with the compat profile's Rust twins,
    /// then with each compat item switched off in turn; the effect of each on the end state
    /// (max |delta| of rho, v, p, e) and on the case's own errors; DIR/ledger.json
    Ledger {
        /// The case: a .toml file, or the name of one in the case folder (see --case-dir)
        case: PathBuf,
        /// The `legacy build` folder of your code
        #[arg(long, value_name = "DIR")]
        legacy: PathBuf,
        /// The compat profile and items of the reference run (default liu-book)
        #[arg(long, value_name = "PROFILE,ITEM,-ITEM", allow_hyphen_values = true)]
        compat: Option<String>,
        /// Where ledger.json goes (default: runs/<case name>_ledger)
        #[arg(long, value_name = "DIR")]
        out: Option<PathBuf>,
        /// Override a case key: --set time.end_s=0.1
        #[arg(long = "set", value_name = "KEY=VALUE")]
        sets: Vec<String>,
        /// Folder to look a case name up in (default as for `run`)
        #[arg(long = "case-dir", value_name = "DIR")]
        case_dir: Option<PathBuf>,
        /// Worker threads of the Rust modules (default: one per core); the results do not depend on it
        #[arg(long, value_name = "N")]
        threads: Option<usize>,
    },
    /// Host mode: your own program (its main, step loop and output) with each mapped routine
    /// compared against its Rust twins at every call; DIR/host_report.json, the table on stdout
    Host {
        /// The case that configures the Rust twins: a .toml file, or the name of one in the case folder
        case: PathBuf,
        /// The `legacy build` folder of your code
        #[arg(long, value_name = "DIR")]
        legacy: PathBuf,
        /// Compatibility items of the Rust twins (as for `dual --legacy`)
        #[arg(long, value_name = "PROFILE,ITEM,-ITEM", allow_hyphen_values = true)]
        compat: Option<String>,
        /// Go on with the Rust twins' outputs in place of your routines' (default: your routines')
        #[arg(long)]
        rust_outputs: bool,
        /// Where the program runs (DIR/work) and the report goes (default: runs/<case name>_host)
        #[arg(long, value_name = "DIR")]
        out: Option<PathBuf>,
        /// Override a case key: --set time.end_s=0.1
        #[arg(long = "set", value_name = "KEY=VALUE")]
        sets: Vec<String>,
        /// Folder to look a case name up in (default as for `run`)
        #[arg(long = "case-dir", value_name = "DIR")]
        case_dir: Option<PathBuf>,
        /// Your program's own command-line arguments, after `--`
        #[arg(last = true, value_name = "ARGS")]
        args: Vec<String>,
    },
    /// Your program's own output against a run: your output routine (module "output") writes the
    /// run's state in its own format, compared file by file, column by column; DIR/compare.json
    Compare {
        /// The run folder (particles.h5, case.toml) of `run --legacy`
        run: PathBuf,
        /// The `legacy build` folder of your code
        #[arg(long, value_name = "DIR")]
        legacy: PathBuf,
        /// The folder where your program wrote its output files
        #[arg(long = "program-out", value_name = "DIR")]
        program_out: PathBuf,
        /// The particles.h5 group Step#N to compare (default: the last)
        #[arg(long, value_name = "N")]
        step: Option<usize>,
        /// Where compare.json and the run's files in your format go (default: runs/<run folder name>_compare)
        #[arg(long, value_name = "DIR")]
        out: Option<PathBuf>,
    },
}

/// `blastsph legacy build`, `ledger`, `host` and `compare`.
pub(super) fn legacy(cmd: LegacyCmd) -> Result<i32> {
    match cmd {
        LegacyCmd::Build { manifest, out } => {
            let out = out.unwrap_or_else(|| {
                let stem = std::path::absolute(&manifest)
                    .ok()
                    .and_then(|p| p.parent().and_then(|d| d.file_name()).map(|n| n.to_string_lossy().into_owned()))
                    .unwrap_or_else(|| "build".into());
                PathBuf::from("runs").join(format!("legacy_{stem}"))
            });
            out_folder(&out)?;
            let info = crate::migration::build(&manifest, &out)?;
            for w in &info.warnings {
                eprintln!("warning: {w}");
            }
            println!(
                "built {}: {} routines ({}), dim {}, maxn {}, max_interaction {}",
                out.join(&info.library).display(),
                info.routines.len(),
                info.routines.iter().map(|r| r.name.as_str()).collect::<Vec<_>>().join(", "),
                info.dim,
                info.maxn,
                info.max_interaction
            );
            match &info.program {
                Some(p) => println!("the legacy program: {}", out.join(p).display()),
                None => println!("no legacy program: {}", info.program_note.as_deref().unwrap_or("-")),
            }
            println!("written: {}, {}", out.join("build.json").display(), out.join("build.log").display());
            Ok(0)
        }
        LegacyCmd::Compare { run, legacy, program_out, step, out } => {
            super::legacy_compare::compare(run, legacy, program_out, step, out)
        }
        LegacyCmd::Host { case, legacy, compat, rust_outputs, out, sets, case_dir, args } => {
            threads(Some(1))?;
            let case = crate::casedir::resolve(&case, case_dir.as_deref())?;
            let la = LegacyArgs { legacy: Some(legacy.clone()), compat };
            let c = case::load(&case, &la.sets(&sets)?)?;
            let dir = out
                .unwrap_or_else(|| PathBuf::from("runs").join(format!("{}_host", crate::rundir::sanitize(c.name()))));
            own_folder(&dir, "host_report.json", "legacy host")?;
            let opts = crate::migration::legacy::host::HostOpts { rust_outputs, args };
            crate::migration::legacy::host::run(c, &legacy, &dir, opts)
        }
        LegacyCmd::Ledger { case, legacy, compat, out, sets, case_dir, threads: n } => {
            threads(n)?;
            let case = crate::casedir::resolve(&case, case_dir.as_deref())?;
            let la = LegacyArgs { legacy: Some(legacy.clone()), compat };
            let c = case::load(&case, &la.sets(&sets)?)?;
            let dir = out
                .unwrap_or_else(|| PathBuf::from("runs").join(format!("{}_ledger", crate::rundir::sanitize(c.name()))));
            report_folder(&dir, &["ledger.json"], "ledger")?;
            crate::rundir::prepare(&dir, false)?;
            let (rows, text) = on_pool(|| crate::migration::ledger::ledger(&c, &legacy, &dir, runs::ledger_l1))?;
            print!("{text}");
            let same = rows.first().is_some_and(|r| r.particles_differing == 0);
            println!(
                "{}; each row against the profile run; {}",
                if same {
                    "your routines and the profile's Rust twins end in the same state, bit for bit".to_string()
                } else {
                    format!(
                        "your routines end {} particles away from the profile's Rust twins",
                        rows[0].particles_differing
                    )
                },
                dir.join("ledger.json").display()
            );
            Ok(0)
        }
    }
}
