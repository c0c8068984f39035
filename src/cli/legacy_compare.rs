//! `blastsph legacy compare`: reads the run's frame and case, then hands them to
//! [`crate::migration::compare`].

use super::*;
use crate::migration::compare::{Opts, Snapshot};

/// Group `Step#step` (default: the last) of `run`/particles.h5 as blastsph's particles, in the
/// order of their ids (the program's order); `c` and what the file does not hold are zero.
fn snapshot(run: &Path, step: Option<usize>, dim: usize) -> Result<Snapshot> {
    let path = run.join("particles.h5");
    if !path.is_file() {
        return Err(input(format!("{}: no particles.h5 (not a run folder)", run.display())));
    }
    let (f, names) = crate::output::open_steps(&path)?;
    let (k, name) = match step {
        None => names.last().cloned().ok_or_else(|| input(format!("{}: no frames", path.display())))?,
        Some(s) => names.iter().find(|(k, _)| *k == s).cloned().ok_or_else(|| {
            let (a, b) = (names.first().map_or(0, |x| x.0), names.last().map_or(0, |x| x.0));
            input(format!("--step {s}: {} has Step#{a} to Step#{b}", path.display()))
        })?,
    };
    let fr = crate::output::read_group(&f, &name)?;
    let n = fr.id.len();
    let mut order: Vec<usize> = (0..n).collect();
    order.sort_by_key(|&i| fr.id[i]);
    let pick = |v: &[f64]| -> Vec<f64> { order.iter().map(|&i| v.get(i).copied().unwrap_or(0.0)).collect() };
    let (xs, vs) = ([&fr.x, &fr.y, &fr.z], [&fr.vx, &fr.vy, &fr.vz]);
    let inter = |c: &[&Vec<f64>; 3]| -> Vec<f64> {
        order.iter().flat_map(|&i| (0..dim).map(move |d| c[d].get(i).copied().unwrap_or(0.0))).collect()
    };
    let p = crate::state::Particles {
        dim,
        nreal: n,
        ntotal: n,
        x: inter(&xs),
        v: inter(&vs),
        rho: pick(&fr.rho),
        p: pick(&fr.p),
        c: vec![0.0; n],
        e: pick(&fr.e),
        h: pick(&fr.h),
        mass: pick(&fr.mass),
        mat: order.iter().map(|&i| fr.mat.get(i).copied().unwrap_or(0)).collect(),
        id: order.iter().map(|&i| fr.id[i]).collect(),
        bnd: if fr.bnd.is_empty() { Vec::new() } else { order.iter().map(|&i| fr.bnd[i]).collect() },
        ..Default::default()
    };
    Ok(Snapshot { step: k, time: fr.time, p })
}

/// `blastsph legacy compare RUN --legacy DIR --program-out DIR [--step N] [--out DIR]`.
pub(super) fn compare(
    run: PathBuf,
    legacy: PathBuf,
    program_out: PathBuf,
    step: Option<usize>,
    out: Option<PathBuf>,
) -> Result<i32> {
    let case_toml = run.join("case.toml");
    if !case_toml.is_file() {
        return Err(input(format!("{}: no case.toml (not a run folder)", run.display())));
    }
    let c = case::load(&case_toml, &[])?;
    let snap = snapshot(&run, step, c.dim)?;
    let out = out.unwrap_or_else(|| {
        let name = std::path::absolute(&run)
            .ok()
            .and_then(|p| p.file_name().map(|n| n.to_string_lossy().into_owned()))
            .unwrap_or_else(|| "run".into());
        PathBuf::from("runs").join(format!("{}_compare", crate::rundir::sanitize(&name)))
    });
    own_folder(&out, "compare.json", "legacy compare")?;
    let (existed, ours) = (out.exists(), out.join("compare.json").is_file());
    let o = Opts { run, legacy, program_out, out: out.clone() };
    let (text, _) = crate::migration::compare::compare(&o, &c, &snap).inspect_err(|_| {
        // a compare that failed leaves nothing that would refuse the next one in this folder
        if !ours {
            let _ = std::fs::remove_dir_all(out.join("written"));
            if !existed {
                let _ = std::fs::remove_dir(&out);
            }
        }
    })?;
    print!("{text}");
    println!(
        "written: {} (the run's files in your program's format: {})",
        out.join("compare.json").display(),
        out.join("written").display()
    );
    Ok(0)
}
