//! Convergence: references, errors against them, observed orders.

use serde::Serialize;

use super::run::Row;
use std::collections::BTreeMap;

/// An observed order of convergence from the runs at `ks`.
#[derive(Debug, Clone, Serialize)]
pub struct Order {
    pub ks: Vec<f64>,
    /// None where it is undefined (a difference or an error of zero, or not finite).
    pub p: Option<f64>,
}

/// One configuration (case, backend, search, kernel) across its resolutions.
#[derive(Debug, Clone, Serialize)]
pub struct Family {
    pub case: String,
    /// The case's analysis: "riemann" (errors against the exact solution), "crater" (against
    /// the reference run), "none".
    pub analysis: String,
    pub backend: String,
    pub nnps: String,
    pub kernel: String,
    /// The thread count, when it is an axis of the matrix (`--threads` as a list).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub threads: Option<usize>,
    /// Resolutions that finished.
    pub ks: Vec<f64>,
    /// Blast: the reference, the finest run that finished (a Riemann case's reference is the
    /// exact solution).
    pub reference_k: Option<f64>,
    /// The second finest run that finished.
    pub second_k: Option<f64>,
    /// How converged the reference is: |q_finest − q_second| / |q_finest| per quantity.
    pub reference_change: BTreeMap<String, f64>,
    /// Observed order from three resolutions k, rk, r²k without a reference:
    /// p = ln(|q_k − q_rk| / |q_rk − q_r²k|) / ln r (r = 2: log2).
    pub self_orders: BTreeMap<String, Vec<Order>>,
    /// Riemann: observed order from the exact errors of two resolutions, p = ln(E_k / E_rk) / ln r.
    pub exact_orders: BTreeMap<String, Vec<Order>>,
}

pub(super) fn finite(x: f64) -> Option<f64> {
    x.is_finite().then_some(x)
}

/// Observed order from three values at resolutions in a constant ratio r.
pub fn self_order(q: [f64; 3], r: f64) -> Option<f64> {
    let (a, b) = ((q[0] - q[1]).abs(), (q[1] - q[2]).abs());
    if a > 0.0 && b > 0.0 && r > 1.0 { finite((a / b).ln() / r.ln()) } else { None }
}

/// Observed order from the errors at two resolutions in the ratio r.
pub fn exact_order(e: [f64; 2], r: f64) -> Option<f64> {
    if e[0] > 0.0 && e[1] > 0.0 && r > 1.0 { finite((e[0] / e[1]).ln() / r.ln()) } else { None }
}

/// Groups the rows into configurations, fills each row's reference errors, and returns the
/// configurations with their references and orders.
pub(super) fn analyse(rows: &mut [Row]) -> Vec<Family> {
    let mut keys: Vec<super::run::Key> = Vec::new();
    for r in rows.iter() {
        if !keys.contains(&r.family()) {
            keys.push(r.family());
        }
    }
    let mut fams = Vec::new();
    for key in keys {
        let idx: Vec<usize> = (0..rows.len()).filter(|&i| rows[i].family() == key && rows[i].ok()).collect();
        let mut idx = idx;
        idx.sort_by(|&a, &b| rows[a].k.total_cmp(&rows[b].k));
        let ks: Vec<f64> = idx.iter().map(|&i| rows[i].k).collect();
        let crater = idx.first().is_some_and(|&i| rows[i].analysis == "crater");
        let mut fam = Family {
            case: key.0.clone(),
            analysis: idx.first().map_or(String::new(), |&i| rows[i].analysis.clone()),
            backend: key.1.clone(),
            nnps: key.2.clone(),
            kernel: key.3.clone(),
            threads: key.4,
            ks: ks.clone(),
            reference_k: if crater { ks.last().copied() } else { None },
            second_k: if crater && ks.len() >= 2 { Some(ks[ks.len() - 2]) } else { None },
            reference_change: BTreeMap::new(),
            self_orders: BTreeMap::new(),
            exact_orders: BTreeMap::new(),
        };
        let names: Vec<String> =
            idx.last().map(|&i| rows[i].quantities().into_iter().map(|q| q.0).collect()).unwrap_or_default();
        if let Some(&iref) = idx.last().filter(|_| crater) {
            let refrow = rows[iref].clone();
            for &i in &idx {
                rows[i].reference_k = Some(refrow.k);
                if i == iref {
                    continue;
                }
                for (q, v) in rows[i].quantities() {
                    if let Some(r) = refrow.quantity(&q)
                        && r != 0.0
                        && let Some(e) = finite((v - r).abs() / r.abs())
                    {
                        rows[i].err_ref.insert(q, e);
                    }
                }
            }
            if idx.len() >= 2 {
                let sec = &rows[idx[idx.len() - 2]];
                for q in &names {
                    if let (Some(a), Some(b)) = (refrow.quantity(q), sec.quantity(q))
                        && a != 0.0
                        && let Some(c) = finite((a - b).abs() / a.abs())
                    {
                        fam.reference_change.insert(q.clone(), c);
                    }
                }
            }
        }
        for q in &names {
            let vals: Vec<Option<f64>> = idx.iter().map(|&i| rows[i].quantity(q)).collect();
            let mut so = Vec::new();
            for w in 0..idx.len().saturating_sub(2) {
                let (k0, k1, k2) = (ks[w], ks[w + 1], ks[w + 2]);
                let r = k1 / k0;
                if ((k2 / k1) / r - 1.0).abs() > 1e-9 {
                    continue;
                }
                if let (Some(a), Some(b), Some(c)) = (vals[w], vals[w + 1], vals[w + 2]) {
                    so.push(Order { ks: vec![k0, k1, k2], p: self_order([a, b, c], r) });
                }
            }
            if !so.is_empty() {
                fam.self_orders.insert(q.clone(), so);
            }
            if q.starts_with("l1_") {
                let mut eo = Vec::new();
                for w in 0..idx.len().saturating_sub(1) {
                    if let (Some(a), Some(b)) = (vals[w], vals[w + 1]) {
                        eo.push(Order { ks: vec![ks[w], ks[w + 1]], p: exact_order([a, b], ks[w + 1] / ks[w]) });
                    }
                }
                if !eo.is_empty() {
                    fam.exact_orders.insert(q.clone(), eo);
                }
            }
        }
        fams.push(fam);
    }
    // the Pareto front of each case: no other run is at least as fast and at least as accurate
    let cases: Vec<String> = rows.iter().map(|r| r.case.clone()).fold(Vec::new(), |mut v, c| {
        if !v.contains(&c) {
            v.push(c);
        }
        v
    });
    for c in cases {
        let pts: Vec<(usize, f64, f64)> = rows
            .iter()
            .enumerate()
            .filter(|(_, r)| r.case == c && r.ok())
            .filter_map(|(i, r)| Some((i, r.wall_s?, r.primary().filter(|e| *e > 0.0)?)))
            .collect();
        for &(i, t, e) in &pts {
            let dominated = pts.iter().any(|&(j, t2, e2)| j != i && t2 <= t && e2 <= e && (t2 < t || e2 < e));
            rows[i].pareto = Some(!dominated);
        }
    }
    fams
}
