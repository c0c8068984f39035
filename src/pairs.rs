//! Pair lists compared as sets in the dual run. A legacy search may return the same pairs as
//! blastsph's in another order (the book's `link_list` walks cells and runs each cell's list from
//! the highest particle down), or a pair as (j, i). The dual run then lines the Rust side's
//! per-pair values up with the other side's pairs — a pair found as (j, i) is compared with ∇W
//! negated and its ends swapped — and reports how the orders differ; pairs only one side found
//! are differences (counted out of tolerance).

use crate::state::{Field, Particles, Per, Snap, Work};
use serde::Serialize;
use std::collections::HashMap;

/// How two pair lists differed, summed over the steps compared.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq, Serialize)]
pub struct OrderStat {
    /// Steps at which the lists differed in order or content.
    pub steps: u64,
    /// Pairs found by both sides at another position.
    pub moved: u64,
    /// Pairs found by both sides, as (j, i) on one and (i, j) on the other.
    pub reversed: u64,
    /// Pairs only the other side (Fortran or legacy) found.
    pub only_counterpart: u64,
    /// Pairs only the Rust side found.
    pub only_rust: u64,
}

impl OrderStat {
    pub fn add(&mut self, o: &OrderStat) {
        self.steps += o.steps;
        self.moved += o.moved;
        self.reversed += o.reversed;
        self.only_counterpart += o.only_counterpart;
        self.only_rust += o.only_rust;
    }
    /// One line for the report; `other` names the other side ("legacy", "fortran").
    pub fn text(&self, other: &str) -> String {
        format!(
            "{} steps in another order or with other pairs: {} pairs at other places, {} reversed, {} only in the {other} list, {} only in the Rust list",
            self.steps, self.moved, self.reversed, self.only_counterpart, self.only_rust
        )
    }
}

/// The Rust side's outputs lined up with the other side's pair order.
pub struct Aligned {
    pub snaps: Vec<Snap>,
    pub stat: OrderStat,
}

/// Lines the Rust outputs `rust` (one per field of `writes`) up with the pair list now in `w`
/// (the other side's). `None` when the stage writes no pair list or both lists are the same.
pub fn align(writes: &[Field], rust: &[Snap], _p: &Particles, w: &Work, dim: usize) -> Option<Aligned> {
    let at = |f: Field| writes.iter().position(|&x| x == f);
    let (ki, kj) = (at(Field::PairI)?, at(Field::PairJ)?);
    let (ri, rj) = match (&rust[ki], &rust[kj]) {
        (Snap::I(a), Snap::I(b)) => (a, b),
        _ => return None,
    };
    let (fi, fj) = (&w.pairs.i, &w.pairs.j);
    if ri == fi && rj == fj {
        return None;
    }
    let mut index: HashMap<(i32, i32), (usize, bool)> = HashMap::with_capacity(ri.len());
    for (k, (&a, &b)) in ri.iter().zip(rj).enumerate() {
        index.entry((a.min(b), a.max(b))).or_insert((k, a > b));
    }
    let mut stat = OrderStat { steps: 1, ..Default::default() };
    let mut used = vec![false; ri.len()];
    // for each pair of the other side: its Rust index and whether it is reversed
    let map: Vec<Option<(usize, bool)>> = fi
        .iter()
        .zip(fj)
        .enumerate()
        .map(|(k, (&a, &b))| {
            let (kr, rev_r) = *index.get(&(a.min(b), a.max(b)))?;
            if used[kr] {
                return None;
            }
            used[kr] = true;
            let rev = rev_r != (a > b);
            if rev {
                stat.reversed += 1;
            }
            if kr != k {
                stat.moved += 1;
            }
            Some((kr, rev))
        })
        .collect();
    stat.only_counterpart = map.iter().filter(|m| m.is_none()).count() as u64;
    stat.only_rust = used.iter().filter(|u| !**u).count() as u64;
    let nf = fi.len();
    let snaps = writes
        .iter()
        .zip(rust)
        .map(|(&f, s)| {
            let (per, width) = f.layout(dim);
            if per != Per::Pair {
                return s.clone();
            }
            match s {
                Snap::I(v) => {
                    if f != Field::PairI && f != Field::PairJ {
                        return Snap::I(v.clone());
                    }
                    let src = if f == Field::PairI { (ri, rj) } else { (rj, ri) };
                    Snap::I(
                        map.iter()
                            .map(|m| match *m {
                                Some((kr, false)) => src.0[kr],
                                Some((kr, true)) => src.1[kr],
                                None => -1,
                            })
                            .collect(),
                    )
                }
                Snap::F(v) => {
                    let mut out = vec![f64::NAN; nf * width];
                    for (k, m) in map.iter().enumerate() {
                        if let Some((kr, rev)) = *m
                            && (kr + 1) * width <= v.len()
                        {
                            for d in 0..width {
                                let x = v[kr * width + d];
                                out[k * width + d] = if rev && f == Field::Dwdx { -x } else { x };
                            }
                        }
                    }
                    Snap::F(out)
                }
            }
        })
        .collect();
    Some(Aligned { snaps, stat })
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::modules::nnps::PairList;

    #[test]
    fn a_list_in_another_order_lines_up_and_counts() {
        // Rust: (0,1) (1,2) (1,3); the other side: (1,3) (0,1) (2,1) — every pair at another
        // position, (2,1) reversed
        let mut w = Work { pairs: PairList::new(vec![1, 0, 2], vec![3, 1, 1]), ..Default::default() };
        w.w = vec![0.5, 0.25, 0.125];
        let rust = vec![
            Snap::I(vec![0, 1, 1]),
            Snap::I(vec![1, 2, 3]),
            Snap::F(vec![1.0, 2.0, 3.0]),
            Snap::F(vec![10.0, 20.0, 30.0]),
        ];
        let writes = [Field::PairI, Field::PairJ, Field::W, Field::Dwdx];
        let a = align(&writes, &rust, &Particles::default(), &w, 1).expect("differs");
        assert_eq!(a.stat, OrderStat { steps: 1, moved: 3, reversed: 1, only_counterpart: 0, only_rust: 0 });
        match (&a.snaps[0], &a.snaps[1], &a.snaps[2], &a.snaps[3]) {
            (Snap::I(i), Snap::I(j), Snap::F(wv), Snap::F(g)) => {
                assert_eq!(i, &vec![1, 0, 2]);
                assert_eq!(j, &vec![3, 1, 1]);
                assert_eq!(wv, &vec![3.0, 1.0, 2.0]);
                assert_eq!(g, &vec![30.0, 10.0, -20.0]);
            }
            _ => panic!("kinds"),
        }
        // a pair reversed in place: not moved
        let w2 = Work { pairs: PairList::new(vec![0, 2, 1], vec![1, 1, 3]), ..Default::default() };
        let a = align(&writes, &rust, &Particles::default(), &w2, 1).expect("differs");
        assert_eq!(a.stat, OrderStat { steps: 1, moved: 0, reversed: 1, only_counterpart: 0, only_rust: 0 });
        // the same list: nothing to align
        let same = vec![Snap::I(vec![1, 0, 2]), Snap::I(vec![3, 1, 1]), Snap::F(vec![0.0; 3]), Snap::F(vec![0.0; 3])];
        assert!(align(&writes, &same, &Particles::default(), &w, 1).is_none());
    }

    #[test]
    fn missing_and_extra_pairs_are_counted() {
        let w = Work { pairs: PairList::new(vec![0, 0], vec![1, 2]), ..Default::default() };
        let rust = vec![Snap::I(vec![0, 1]), Snap::I(vec![1, 2])];
        let a = align(&[Field::PairI, Field::PairJ], &rust, &Particles::default(), &w, 1).expect("differs");
        assert_eq!((a.stat.only_counterpart, a.stat.only_rust), (1, 1));
        match &a.snaps[0] {
            Snap::I(i) => assert_eq!(i, &vec![0, -1]),
            _ => panic!(),
        }
    }
}
