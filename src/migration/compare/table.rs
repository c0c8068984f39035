//! The numbers of a file that a legacy output routine writes: tokens by line, read as Fortran
//! writes them (`1.5D+00`, `0.12345678-100` without its `E`), compared column by column.

use crate::error::{Result, input};
use serde_json::{Value, json};
use std::path::Path;

/// A file's tokens, line by line (empty lines left out; their line numbers kept).
pub struct Table {
    /// (line number from 1, tokens).
    pub lines: Vec<(usize, Vec<String>)>,
}

impl Table {
    /// Reads `path`: tokens split at blanks and commas. The lines before the first line of
    /// numbers only are a header (Tecplot's `TITLE=`, `VARIABLES=`, `ZONE`) and are left out.
    pub fn read(path: &Path) -> Result<Table> {
        let text = std::fs::read(path).map_err(|e| input(format!("{}: {e}", path.display())))?;
        let text = String::from_utf8_lossy(&text);
        let lines = text
            .lines()
            .enumerate()
            .map(|(k, l)| (k + 1, l.split([' ', '\t', ',']).filter(|t| !t.is_empty()).map(String::from).collect()))
            .filter(|(_, t): &(usize, Vec<String>)| !t.is_empty())
            .skip_while(|(_, t)| !t.iter().all(|x| number(x).is_some()))
            .collect();
        Ok(Table { lines })
    }

    /// The positions (line index, column) whose token differs from `other`'s, as (column) per
    /// line: the columns a probe changed.
    pub fn changed_columns(&self, other: &Table) -> Vec<usize> {
        let mut cols = std::collections::BTreeSet::new();
        for ((_, a), (_, b)) in self.lines.iter().zip(&other.lines) {
            for (c, (x, y)) in a.iter().zip(b).enumerate() {
                if x != y {
                    cols.insert(c);
                }
            }
        }
        cols.into_iter().collect()
    }

    /// For each line, the particle (from 1) it is the row of: the lines with the token count
    /// that `n` lines have, in order; `None` for the others (a header), or for all when no token
    /// count occurs `n` times.
    pub fn particles(&self, n: usize) -> Vec<Option<usize>> {
        let mut counts = std::collections::BTreeMap::new();
        for (_, t) in &self.lines {
            *counts.entry(t.len()).or_insert(0usize) += 1;
        }
        let width = counts.iter().filter(|(_, c)| **c == n).map(|(w, _)| *w).max();
        let mut k = 0;
        self.lines
            .iter()
            .map(|(_, t)| {
                (Some(t.len()) == width).then(|| {
                    k += 1;
                    k
                })
            })
            .collect()
    }
}

/// A token as a number: Fortran's `D` exponent and its exponent without a letter (`e14.8` of
/// 1e-100 writes `0.10000000-99`) are read too; `NaN` and `Infinity` as themselves.
pub fn number(tok: &str) -> Option<f64> {
    let mut t: String = tok.replace(['D', 'd'], "E");
    if !t.contains(['E', 'e'])
        && let Some(k) = t.char_indices().skip(1).filter(|(_, c)| *c == '+' || *c == '-').map(|(k, _)| k).last()
        && t[..k].chars().last().is_some_and(|c| c.is_ascii_digit() || c == '.')
    {
        t.insert(k, 'E');
    }
    t.parse::<f64>().ok()
}

/// The significant digits a real token is written with (`0.12345678E+01`: 8); `None` for an
/// integer, a zero, or what is not a number.
pub fn digits(tok: &str) -> Option<usize> {
    if !tok.contains(['.', 'E', 'e', 'D', 'd']) {
        return None;
    }
    let mant: String = tok
        .trim_start_matches(['+', '-'])
        .chars()
        .take_while(|c| c.is_ascii_digit() || *c == '.')
        .filter(|c| c.is_ascii_digit())
        .collect();
    let sig = mant.trim_start_matches('0');
    (!sig.is_empty()).then_some(sig.len())
}

/// One column's comparison.
#[derive(Default, Clone)]
pub struct Column {
    pub compared: usize,
    pub max_abs: f64,
    pub max_rel: f64,
    pub differing: usize,
    /// The first differing: (line number, particle, run's value, program's value).
    pub first: Option<(usize, Option<usize>, f64, f64)>,
    /// The fewest significant digits of a real value of the program's in the column.
    pub digits: Option<usize>,
}

impl Column {
    fn add(&mut self, a: f64, b: f64, line: usize, particle: Option<usize>) {
        self.compared += 1;
        let same = a == b || (a.is_nan() && b.is_nan());
        if same {
            return;
        }
        let d = (a - b).abs();
        let scale = a.abs().max(b.abs());
        let rel = if scale > 0.0 { d / scale } else { 0.0 };
        self.max_abs = if d.is_nan() { f64::NAN } else { self.max_abs.max(d) };
        self.max_rel = self.max_rel.max(rel);
        self.differing += 1;
        if self.first.is_none() {
            self.first = Some((line, particle, a, b));
        }
    }

    pub fn json(&self) -> Value {
        json!({
            "compared": self.compared,
            "max_abs": self.max_abs,
            "max_rel": self.max_rel,
            "differing": self.differing,
            "first_differing": self.first.map(|(l, p, a, b)| json!({ "line": l, "particle": p, "run": a, "program": b })),
            "digits": self.digits,
        })
    }
}

/// Compares the run's file `name` (`run`) with the program's (`prog`), number by number, the
/// columns in `skip` left out; `n` particles. The lines and their token counts must agree and
/// every token compared must be a number: else an error naming the file, line and token.
pub fn compare(name: &str, run: &Table, prog: &Table, n: usize, skip: &[usize]) -> Result<Vec<Column>> {
    if run.lines.len() != prog.lines.len() {
        return Err(input(format!(
            "{name}: the program's has {} lines of values, the run's {}: not the same particles (another step, or another case?)",
            prog.lines.len(),
            run.lines.len()
        )));
    }
    let width = run.lines.iter().map(|(_, t)| t.len()).max().unwrap_or(0);
    let mut cols = vec![Column::default(); width];
    let particles = run.particles(n);
    for (((l, a), (lp, b)), part) in run.lines.iter().zip(&prog.lines).zip(particles) {
        if a.len() != b.len() {
            return Err(input(format!(
                "{name}: line {lp} of the program's has {} values, line {l} of the run's {}",
                b.len(),
                a.len()
            )));
        }
        for (c, (x, y)) in a.iter().zip(b).enumerate() {
            if skip.contains(&c) {
                continue;
            }
            let bad = |who: &str, line: usize, t: &str| {
                input(format!("{name}: line {line} of the {who}'s: `{t}` is not a number"))
            };
            let yv = number(y).ok_or_else(|| bad("program", *lp, y))?;
            let xv = number(x).ok_or_else(|| bad("run", *l, x))?;
            cols[c].add(xv, yv, *lp, part);
            if let Some(d) = digits(y) {
                cols[c].digits = Some(cols[c].digits.map_or(d, |k| k.min(d)));
            }
        }
    }
    Ok(cols)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn fortran_numbers_and_their_digits() {
        assert_eq!(number("0.15000000E+01"), Some(1.5));
        assert_eq!(number("1.5D+00"), Some(1.5));
        assert_eq!(number("0.10000000-99"), Some(1e-100));
        assert_eq!(number("-2"), Some(-2.0));
        assert_eq!(number("***"), None);
        assert_eq!(digits("0.12345678E+01"), Some(8));
        assert_eq!(digits("-1.0000000000000000E+000"), Some(17));
        assert_eq!(digits("0.00000000E+00"), None);
        assert_eq!(digits("42"), None);
    }
}
