//! What the bench writes: bench.csv, the tables of bench.md, the plots.

use crate::error::Result;

use std::fmt::Write as _;

use super::analysis::Family;
use super::analysis::Order;
use super::matrix::family_label;
use super::matrix::k_tag;
use super::run::Row;
use super::run::primary_name;
use crate::plot;
use crate::report::L1;
use serde_json::Value;
use std::path::Path;
use std::path::PathBuf;

pub(super) fn f(v: Option<f64>) -> String {
    match v {
        Some(x) if x.is_finite() => format!("{x}"),
        _ => String::new(),
    }
}

pub(super) fn e4(v: Option<f64>) -> String {
    match v {
        Some(x) if x.is_finite() => format!("{x:.4e}"),
        _ => "-".into(),
    }
}

pub(super) fn g2(v: Option<f64>) -> String {
    match v {
        Some(x) if x.is_finite() => format!("{x:.2}"),
        _ => "-".into(),
    }
}

pub(super) fn g3(v: Option<f64>) -> String {
    match v {
        Some(x) if x.is_finite() => format!("{x:.3}"),
        _ => "-".into(),
    }
}

/// The fixed columns of bench.csv; gauge columns follow (`peak_<g>_pa`, `peak_<g>_err_ref`,
/// `peak_time_<g>_s`, and `peak_<g>_vs_thesis`, `peak_time_<g>_vs_thesis` where the thesis gives them).
pub const CSV_COLUMNS: [&str; 33] = [
    "case",
    "analysis",
    "k",
    "dx_m",
    "particles",
    "particles_expected",
    "count_exact",
    "backend",
    "nnps",
    "kernel",
    "threads",
    "end_time_s",
    "steps",
    "wall_s",
    "particle_steps_per_s",
    "particle_steps_per_s_per_thread",
    "cpu_s",
    "load_avg",
    "status",
    "energy_residual_rel",
    "reference_k",
    "pareto",
    "l1_rho",
    "l1_v",
    "l1_p",
    "l1_e",
    "crater_diameter_m",
    "crater_depth_m",
    "crater_diameter_err_ref",
    "crater_depth_err_ref",
    "crater_diameter_vs_thesis",
    "crater_depth_vs_thesis",
    "wall_s_runs",
];

pub(super) fn csv(rows: &[Row]) -> String {
    let mut gauges: Vec<String> = Vec::new();
    for r in rows {
        for g in &r.gauges {
            if !gauges.contains(&g.name) {
                gauges.push(g.name.clone());
            }
        }
    }
    let thesis_peak = |g: &str| rows.iter().any(|r| r.vs_thesis.contains_key(&format!("peak_{g}")));
    let thesis_time = |g: &str| rows.iter().any(|r| r.vs_thesis.contains_key(&format!("peak_time_{g}")));
    let mut head: Vec<String> = CSV_COLUMNS.iter().map(|s| s.to_string()).collect();
    for g in &gauges {
        head.push(format!("peak_{g}_pa"));
        head.push(format!("peak_{g}_err_ref"));
        head.push(format!("peak_time_{g}_s"));
        if thesis_peak(g) {
            head.push(format!("peak_{g}_vs_thesis"));
        }
        if thesis_time(g) {
            head.push(format!("peak_time_{g}_vs_thesis"));
        }
    }
    let mut s = head.join(",") + "\n";
    for r in rows {
        let l1 = |g: fn(&L1) -> f64| f(r.l1.as_ref().map(g));
        let mut v: Vec<String> = vec![
            r.case.clone(),
            r.analysis.clone(),
            format!("{}", r.k),
            f(Some(r.dx_m)),
            r.particles.to_string(),
            f(Some(r.particles_expected)),
            r.count_exact.to_string(),
            r.backend.clone(),
            r.nnps.clone(),
            r.kernel.clone(),
            r.threads.to_string(),
            f(Some(r.end_time_s)),
            r.steps.map(|s| s.to_string()).unwrap_or_default(),
            f(r.wall_s),
            f(r.particle_steps_per_s),
            f(r.particle_steps_per_s_per_thread),
            f(r.cpu_s),
            f(r.load_avg),
            r.status.clone(),
            f(r.energy_residual_rel),
            f(r.reference_k),
            r.pareto.map(|p| p.to_string()).unwrap_or_default(),
            l1(|l| l.rho),
            l1(|l| l.v),
            l1(|l| l.p),
            l1(|l| l.e),
            f(r.crater_diameter_m),
            f(r.crater_depth_m),
            f(r.err_ref.get("crater_diameter").copied()),
            f(r.err_ref.get("crater_depth").copied()),
            f(r.vs_thesis.get("crater_diameter").copied()),
            f(r.vs_thesis.get("crater_depth").copied()),
            r.wall_s_runs.iter().map(|w| f(Some(*w))).collect::<Vec<_>>().join(" "),
        ];
        for g in &gauges {
            let gp = r.gauges.iter().find(|x| &x.name == g);
            v.push(f(gp.map(|x| x.peak_pa)));
            v.push(f(r.err_ref.get(&format!("peak_{g}")).copied()));
            v.push(f(gp.map(|x| x.peak_time_s)));
            if thesis_peak(g) {
                v.push(f(r.vs_thesis.get(&format!("peak_{g}")).copied()));
            }
            if thesis_time(g) {
                v.push(f(r.vs_thesis.get(&format!("peak_time_{g}")).copied()));
            }
        }
        s += &(v.join(",") + "\n");
    }
    s
}

pub(super) fn ord(v: Option<&Vec<Order>>) -> String {
    match v {
        None => "-".into(),
        Some(list) => list
            .iter()
            .map(|o| {
                let ks: Vec<String> = o.ks.iter().map(|k| k_tag(*k)).collect();
                format!("{} ({})", o.p.map_or("undefined".into(), |p| format!("{p:.2}")), ks.join(","))
            })
            .collect::<Vec<_>>()
            .join("; "),
    }
}

pub(super) fn quantity_title(q: &str) -> String {
    match q {
        "l1_rho" => "L1 rho (kg/m3)".into(),
        "l1_v" => "L1 v (m/s)".into(),
        "l1_p" => "L1 p (Pa)".into(),
        "l1_e" => "L1 e (J/kg)".into(),
        "crater_diameter" => "crater diameter".into(),
        "crater_depth" => "crater depth".into(),
        _ => match q.strip_prefix("peak_time_") {
            Some(g) => format!("peak time at gauge {g}"),
            None => match q.strip_prefix("peak_") {
                Some(g) => format!("peak pressure at gauge {g}"),
                None => q.into(),
            },
        },
    }
}

/// The tables: runs per case, gauges, references and orders, the Pareto front.
pub(super) fn tables(rows: &[Row], fams: &[Family], warnings: &[String], meta: &Value) -> String {
    let mut s = String::new();
    let _ = writeln!(
        s,
        "blastsph bench: {} runs, {} (commit {}), {} cores\n",
        rows.len(),
        meta["date_utc"].as_str().unwrap_or("?"),
        meta["commit"].as_str().unwrap_or("unknown"),
        meta["cores"]
    );
    let mut cases: Vec<&str> = Vec::new();
    for r in rows {
        if !cases.contains(&r.case.as_str()) {
            cases.push(&r.case);
        }
    }
    for c in &cases {
        let rs: Vec<&Row> = rows.iter().filter(|r| r.case == *c).collect();
        let an = rs[0].analysis.as_str();
        let _ = writeln!(s, "### {c}\n");
        match an {
            "riemann" => riemann_table(&mut s, &rs),
            _ => crater_table(&mut s, &rs),
        }
        let _ = writeln!(s);
    }
    orders_table(&mut s, fams);
    let _ = writeln!(s, "\n### Pareto front (wall time against the primary error)\n");
    for c in &cases {
        let front: Vec<String> = rows
            .iter()
            .filter(|r| r.case == *c && r.pareto == Some(true))
            .map(|r| format!("k = {} {} ({} s, {})", k_tag(r.k), r.label(), wall(r.wall_s), e3(r.primary())))
            .collect();
        let an = rows.iter().find(|r| r.case == *c).map_or("", |r| r.analysis.as_str());
        let _ = writeln!(
            s,
            "- {c} ({}): {}",
            primary_name(an),
            if front.is_empty() { "-".into() } else { front.join("; ") }
        );
    }
    if !warnings.is_empty() {
        let _ = writeln!(s, "\n### Warnings\n");
        for w in warnings {
            let _ = writeln!(s, "- {w}");
        }
    }
    s
}

/// The shock tube's table: L1 errors against the exact solution, one row per run.
fn riemann_table(s: &mut String, rs: &[&Row]) {
    let w = rs.iter().find_map(|r| r.window_m);
    let _ = writeln!(
        s,
        "L1 errors against the exact solution at the end time, over x in {}:\n",
        w.map_or("-".into(), |w| format!("[{}, {}] m", w[0], w[1]))
    );
    let _ = writeln!(
        s,
        "| k | dx (m) | particles | backend | nnps | kernel | threads | steps | wall (s) | particle-steps/s | per thread | cpu (s) | load | L1 rho | L1 v | L1 p | L1 e | status |"
    );
    let _ = writeln!(s, "|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|");
    for r in rs {
        let l = r.l1;
        let _ = writeln!(
            s,
            "| {} | {:.4e} | {} | {} | {} | {} | {} | {} | {} | {} | {} | {} | {} | {} | {} | {} | {} | {} |",
            k_tag(r.k),
            r.dx_m,
            r.particles,
            r.backend,
            r.nnps,
            r.kernel,
            r.threads,
            r.steps.map_or("-".into(), |x| x.to_string()),
            wall(r.wall_s),
            e3(r.particle_steps_per_s),
            e3(r.particle_steps_per_s_per_thread),
            wall(r.cpu_s),
            g2(r.load_avg),
            e4(l.map(|l| l.rho)),
            e4(l.map(|l| l.v)),
            e4(l.map(|l| l.p)),
            e4(l.map(|l| l.e)),
            status(r)
        );
    }
}

/// A blast's tables: the crater at the end time, one row per run, and the gauges' peaks.
fn crater_table(s: &mut String, rs: &[&Row]) {
    let _ = writeln!(
        s,
        "Crater at the end time (cm); err = |q − q_ref| / |q_ref| against the finest run of the same configuration; thesis = (q − q_thesis) / q_thesis:\n"
    );
    let _ = writeln!(
        s,
        "| k | dx (m) | particles | backend | nnps | kernel | threads | end (s) | steps | wall (s) | particle-steps/s | per thread | cpu (s) | load | D | depth | D err | depth err | D thesis | depth thesis | status |"
    );
    let _ = writeln!(s, "|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|");
    for r in rs {
        let _ = writeln!(
            s,
            "| {} | {:.4e} | {} | {} | {} | {} | {} | {:e} | {} | {} | {} | {} | {} | {} | {} | {} | {} | {} | {} | {} | {} |",
            k_tag(r.k),
            r.dx_m,
            r.particles,
            r.backend,
            r.nnps,
            r.kernel,
            r.threads,
            r.end_time_s,
            r.steps.map_or("-".into(), |x| x.to_string()),
            wall(r.wall_s),
            e3(r.particle_steps_per_s),
            e3(r.particle_steps_per_s_per_thread),
            wall(r.cpu_s),
            g2(r.load_avg),
            cm(r.crater_diameter_m),
            cm(r.crater_depth_m),
            e3(r.err_ref.get("crater_diameter").copied()),
            e3(r.err_ref.get("crater_depth").copied()),
            g3(r.vs_thesis.get("crater_diameter").copied()),
            g3(r.vs_thesis.get("crater_depth").copied()),
            status(r)
        );
    }
    let gnames: Vec<String> =
        rs.iter().flat_map(|r| r.gauges.iter().map(|g| g.name.clone())).fold(Vec::new(), |mut v, g| {
            if !v.contains(&g) {
                v.push(g);
            }
            v
        });
    if !gnames.is_empty() {
        let _ = writeln!(
            s,
            "\nGauge peaks: MPa at µs (err against the reference; thesis = relative difference of the peak, or of its time where the thesis gives only the time):\n"
        );
        let _ = writeln!(s, "| k | configuration | {} |", gnames.join(" | "));
        let _ = writeln!(s, "|---|---|{}", "---|".repeat(gnames.len()));
        for r in rs.iter().filter(|r| r.ok()) {
            let cells: Vec<String> = gnames
                .iter()
                .map(|g| match r.gauges.iter().find(|x| &x.name == g) {
                    None => "-".into(),
                    Some(x) => {
                        let mut c = format!("{:.1} at {:.0}", x.peak_pa / 1e6, x.peak_time_s * 1e6);
                        if let Some(e) = r.err_ref.get(&format!("peak_{g}")) {
                            c += &format!(", err {e:.2e}");
                        }
                        if let Some(t) = r.vs_thesis.get(&format!("peak_{g}")) {
                            c += &format!(", thesis {t:.2}");
                        }
                        if let Some(t) = r.vs_thesis.get(&format!("peak_time_{g}")) {
                            c += &format!(", thesis time {t:.2}");
                        }
                        c
                    }
                })
                .collect();
            let _ = writeln!(s, "| {} | {} | {} |", k_tag(r.k), r.label(), cells.join(" | "));
        }
    }
}

/// The references of each configuration and the observed orders of convergence.
fn orders_table(s: &mut String, fams: &[Family]) {
    let _ = writeln!(
        s,
        "### References and observed orders\n\nReference of a blast = the finest run of each configuration that finished; change = |q_finest − q_second| / |q_finest| (how converged the reference is). The shock tube's reference is the exact solution. Self-convergence order p = ln(|q_k − q_rk| / |q_rk − q_r²k|) / ln r over three resolutions (r = 2: log2); for the shock tube also p = ln(E_k / E_rk) / ln r from the exact errors E. The resolutions used are in brackets.\n"
    );
    let _ = writeln!(
        s,
        "| case | configuration | reference k | second k | quantity | change | self-convergence p | p from exact errors |"
    );
    let _ = writeln!(s, "|---|---|---|---|---|---|---|---|");
    for fm in fams {
        let names: Vec<String> = {
            let mut n: Vec<String> = fm.reference_change.keys().cloned().collect();
            for k in fm.self_orders.keys().chain(fm.exact_orders.keys()) {
                if !n.contains(k) {
                    n.push(k.clone());
                }
            }
            n.sort_by_key(|q| quantity_rank(q));
            n
        };
        if names.is_empty() {
            let _ = writeln!(
                s,
                "| {} | {} | {} | {} | - | - | - | - |",
                fm.case,
                family_label(&fm.backend, &fm.nnps, &fm.kernel, fm.threads),
                reference(fm),
                fm.second_k.map_or("-".into(), k_tag)
            );
        }
        for q in names {
            let _ = writeln!(
                s,
                "| {} | {} | {} | {} | {} | {} | {} | {} |",
                fm.case,
                family_label(&fm.backend, &fm.nnps, &fm.kernel, fm.threads),
                reference(fm),
                fm.second_k.map_or("-".into(), k_tag),
                q,
                e3(fm.reference_change.get(&q).copied()),
                ord(fm.self_orders.get(&q)),
                ord(fm.exact_orders.get(&q))
            );
        }
    }
}

/// Order of quantities in the tables: L1 errors, crater, then the gauges by name.
pub(super) fn quantity_rank(q: &str) -> (u8, String) {
    let r = match q {
        "l1_rho" => 0,
        "l1_v" => 1,
        "l1_p" => 2,
        "l1_e" => 3,
        "crater_diameter" => 4,
        "crater_depth" => 5,
        _ => 6,
    };
    (r, q.to_string())
}

pub(super) fn reference(fm: &Family) -> String {
    match (fm.analysis.as_str(), fm.reference_k) {
        ("riemann", _) => "exact solution".into(),
        (_, Some(k)) => k_tag(k),
        (_, None) => "-".into(),
    }
}

pub(super) fn wall(v: Option<f64>) -> String {
    match v {
        Some(x) if x >= 100.0 => format!("{x:.0}"),
        Some(x) if x >= 1.0 => format!("{x:.2}"),
        Some(x) => format!("{x:.3}"),
        None => "-".into(),
    }
}

pub(super) fn e3(v: Option<f64>) -> String {
    match v {
        Some(x) if x.is_finite() => format!("{x:.3e}"),
        _ => "-".into(),
    }
}

pub(super) fn cm(v: Option<f64>) -> String {
    match v {
        Some(x) if x.is_finite() => format!("{:.1}", 100.0 * x),
        _ => "-".into(),
    }
}

pub(super) fn status(r: &Row) -> String {
    match (&r.note, r.status.as_str()) {
        (Some(n), "skipped") => format!("skipped: {n}"),
        (Some(_), st) => st.to_string(),
        (None, st) => st.to_string(),
    }
}

/// An error measure of a run, for a plot.
type ErrOf = Box<dyn Fn(&Row) -> Option<f64>>;

/// Error-against-time plots: `error_vs_time.png` (one panel per case, its primary error) and
/// `error_vs_time_<case>.png` (one panel per quantity of the case).
pub(super) fn plots(out: &Path, rows: &[Row]) -> Result<Vec<PathBuf>> {
    let mut files = Vec::new();
    let mut cases: Vec<&str> = Vec::new();
    for r in rows {
        if !cases.contains(&r.case.as_str()) {
            cases.push(&r.case);
        }
    }
    let series = |case: &str, err: &dyn Fn(&Row) -> Option<f64>| -> Vec<plot::LogSeries> {
        let mut fams: Vec<plot::LogSeries> = Vec::new();
        for r in rows.iter().filter(|r| r.case == case && r.ok()) {
            let (Some(t), Some(e)) = (r.wall_s, err(r)) else { continue };
            let pt = (t, e, format!("k={}", k_tag(r.k)));
            match fams.iter_mut().find(|f| f.0 == r.label()) {
                Some(f) => f.1.push(pt),
                None => fams.push((r.label(), vec![pt])),
            }
        }
        for f in &mut fams {
            f.1.sort_by(|a, b| a.0.total_cmp(&b.0));
        }
        fams
    };
    let mut summary = Vec::new();
    for c in &cases {
        let an = rows.iter().find(|r| r.case == *c).map_or("", |r| r.analysis.as_str());
        if an == "none" {
            continue;
        }
        summary.push(plot::LogPanel {
            title: format!("{c}: {}", primary_name(an)),
            xlabel: "wall time (s)".into(),
            ylabel: "error".into(),
            series: series(c, &|r: &Row| r.primary()),
        });
        let mut qs: Vec<(String, String)> = Vec::new();
        let mut panels = Vec::new();
        for r in rows.iter().filter(|r| r.case == *c) {
            for (q, _) in r.quantities() {
                let key = (q.clone(), "ref".to_string());
                if an == "crater" && !qs.contains(&key) {
                    qs.push(key);
                }
                if an == "riemann" && !qs.contains(&(q.clone(), "exact".into())) {
                    qs.push((q, "exact".into()));
                }
            }
            for q in r.vs_thesis.keys() {
                let key = (q.clone(), "thesis".to_string());
                if !qs.contains(&key) {
                    qs.push(key);
                }
            }
        }
        qs.sort_by_key(|(q, how)| (how == "thesis", quantity_rank(q)));
        for (q, how) in &qs {
            let (title, err): (String, ErrOf) = match how.as_str() {
                "exact" => (format!("{} against the exact solution", quantity_title(q)), {
                    let q = q.clone();
                    Box::new(move |r: &Row| r.quantity(&q))
                }),
                "ref" => (format!("{}: relative error against the finest run", quantity_title(q)), {
                    let q = q.clone();
                    Box::new(move |r: &Row| r.err_ref.get(&q).copied())
                }),
                _ => (format!("{}: |relative difference| from the thesis", quantity_title(q)), {
                    let q = q.clone();
                    Box::new(move |r: &Row| r.vs_thesis.get(&q).map(|v| v.abs()))
                }),
            };
            panels.push(plot::LogPanel {
                title,
                xlabel: "wall time (s)".into(),
                ylabel: "error".into(),
                series: series(c, &*err),
            });
        }
        if !panels.is_empty() {
            let cols = panels.len().min(3);
            let nrows = panels.len().div_ceil(cols);
            let path = out.join(format!("error_vs_time_{c}.png"));
            plot::loglog_panels(&path, &panels, cols, (560 * cols as u32, 420 * nrows as u32))?;
            files.push(path);
        }
    }
    if !summary.is_empty() {
        let cols = summary.len().min(2);
        let nrows = summary.len().div_ceil(cols);
        let path = out.join("error_vs_time.png");
        plot::loglog_panels(&path, &summary, cols, (720 * cols as u32, 520 * nrows as u32))?;
        files.insert(0, path);
    }
    Ok(files)
}
