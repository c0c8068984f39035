//! The manifest key `adds` of a routine: the arrays it adds into without zeroing them first
//! (`dvxdt(d,i) = dvxdt(d,i) + ...`, as many genuine codes write their artificial viscosity or
//! external force). blastsph gives every routine its own rate term and sums the terms itself, so
//! the generated shim zeroes these arrays before each call ([`zero`]): the routine then adds
//! into zeros, as it would inside a wrapper that zeroes the arrays and calls it.
//!
//! ```toml
//! [[routine]]
//! name = "art_visc"
//! module = "viscosity"
//! args = ["ntotal", ..., "dvxdt", "dedt"]
//! adds = ["dvxdt", "dedt"]       # vocabulary names of its arguments or globals
//! ```
//!
//! A name is refused (one line, exit status 2) when it is not an argument or global of the
//! routine, when it is one value (a scalar), when the routine reads it (the vocabulary's role
//! `in` or `in/out`: zeroing it would take its input away), when it is a total the program sums
//! (`dvx`, `du`: blastsph sums the terms itself), and on a routine that is not called at each
//! step (`setup`, `init`, `output`).

use super::bind::Buf;
use super::manifest::{Arg, Global};
use super::vocab::{self, CallMode, Kind, Role, Shape, Term};
use crate::error::{Result, SphError};
use std::fmt::Write;

/// The vocabulary names (canonical) of the arrays listed in `adds` (`written`, as the manifest
/// gives them) of a routine of call mode `call` and modules `modules`, checked against its
/// arguments and globals. `key` names the routine in messages.
pub fn of(
    written: &[String],
    (call, modules): (CallMode, &[String]),
    (args, globals): (&[Arg], &[Global]),
    key: &str,
    err: &dyn Fn(&str, String) -> SphError,
) -> Result<Vec<&'static str>> {
    let key = format!("{key}.adds");
    if let Some(m) = modules.iter().find(|m| matches!(m.as_str(), "setup" | "init" | "output"))
        && !written.is_empty()
    {
        return Err(err(
            &key,
            format!("a routine of module \"{m}\" is not called at each step: it has no term to add into"),
        ));
    }
    let mut out: Vec<&'static str> = Vec::new();
    for w in written {
        let n = w.trim().to_ascii_lowercase();
        let term: Option<&'static Term> = match call {
            CallMode::EachPair => vocab::lookup_pair(&n).or_else(|| vocab::lookup(&n)),
            _ => vocab::lookup(&n),
        };
        let Some(term) = term else {
            return Err(err(
                &key,
                format!("unknown name \"{w}\" (see the argument table of docs/reference/legacy.md)"),
            ));
        };
        let bound = args.iter().map(|a| a.term).chain(globals.iter().map(|g| g.term)).find(|t| t.name == term.name);
        let Some(term) = bound else {
            return Err(err(&key, format!("\"{w}\" is not among the routine's args or globals")));
        };
        if matches!(term.name, "dvx" | "du") {
            let own = if term.name == "dvx" { "dvxdt" } else { "dedt" };
            return Err(err(
                &key,
                format!(
                    "\"{w}\" is the total of every term, which blastsph sums itself: map the routine's own term as \"{own}\""
                ),
            ));
        }
        if term.shape == Shape::Scalar {
            return Err(err(&key, format!("\"{w}\" is one value, not an array: only arrays are zeroed")));
        }
        if term.role != Role::Out {
            return Err(err(
                &key,
                format!(
                    "the routine reads \"{w}\" (role {}): zeroing it before the call would take its input away",
                    term.role.name()
                ),
            ));
        }
        if out.contains(&term.name) {
            return Err(err(&key, format!("\"{w}\" given twice")));
        }
        out.push(term.name);
    }
    Ok(out)
}

/// Shim text: zeroes, before the call, the buffers of the bindings `b` (0-based `k`, Fortran
/// `v{k+1}`) that `adds` names, over the values the copy in filled: `sizes(k)` values (the rows
/// 1..ntotal of a per-particle array), or the `niac` pairs in use of a per-pair one. An array
/// declared with a leading extent `l` above dim (`leads`) has its rows zeroed whole, `l` values
/// each. The rows past them keep what they held, as a wrapper's loop over 1..ntotal leaves them.
pub fn zero(f: &mut String, adds: &[&str], b: &[&'static Term], niac: Option<usize>, leads: &[Option<usize>]) {
    for (k, t) in b.iter().enumerate().filter(|(_, t)| adds.contains(&t.name)) {
        let k1 = k + 1;
        let zero = if t.kind == Kind::Real { "0.0d0" } else { "0" };
        let _ = writeln!(f, "  ! adds: the routine adds into {}: its rows in use start at 0", t.name);
        let _ = writeln!(f, "  ncopy = sizes({k1})");
        if t.shape.per_pair()
            && let Some(n) = niac
        {
            let stride = if t.shape == Shape::PairVec { "bs_dim" } else { "1" };
            let _ = writeln!(f, "  ncopy = min(ncopy, max(0_c_int64_t, int(v{n}, c_int64_t)*{stride}))");
        }
        match leads.get(k).copied().flatten() {
            Some(l) => {
                let _ = writeln!(f, "  if (ncopy > 0) v{k1}(1:(ncopy/bs_dim)*{l}) = {zero}");
            }
            None => {
                let _ = writeln!(f, "  if (ncopy > 0) v{k1}(1:ncopy) = {zero}");
            }
        }
    }
}

/// Host mode: what a call added into the arrays `adds` names, its values after the call less
/// those before (`args`: the routine's argument names, in the order of `after` and `before`).
/// One subtraction per value: where an array held 0 before the call it is what the routine
/// summed, bit for bit; elsewhere it carries the rounding of the program's sum.
pub fn added(adds: &[String], args: &[&str], after: Vec<Option<Buf>>, before: &[Option<Buf>]) -> Vec<Option<Buf>> {
    after
        .into_iter()
        .zip(args.iter().zip(before))
        .map(|(a, (name, b))| match (a, b) {
            (Some(Buf::R(a)), Some(Buf::R(b))) if adds.iter().any(|n| n == name) => {
                Some(Buf::R(a.iter().zip(b.iter().chain(std::iter::repeat(&0.0))).map(|(x, y)| x - y).collect()))
            }
            (Some(Buf::I(a)), Some(Buf::I(b))) if adds.iter().any(|n| n == name) => Some(Buf::I(
                a.iter().zip(b.iter().chain(std::iter::repeat(&0))).map(|(x, y)| x.wrapping_sub(*y)).collect(),
            )),
            (a, _) => a,
        })
        .collect()
}

/// Host mode with the twins' outputs: the twin's term `t` added to what the program's array held
/// before the call (`before`), as the routine would have added its own.
pub fn onto(before: Option<&Buf>, t: Buf) -> Buf {
    match (before, t) {
        (Some(Buf::R(b)), Buf::R(t)) => {
            Buf::R(t.iter().zip(b.iter().chain(std::iter::repeat(&0.0))).map(|(x, y)| y + x).collect())
        }
        (Some(Buf::I(b)), Buf::I(t)) => {
            Buf::I(t.iter().zip(b.iter().chain(std::iter::repeat(&0))).map(|(x, y)| y.wrapping_add(*x)).collect())
        }
        (_, t) => t,
    }
}

/// The line host mode's table gives a routine with `adds` (`{}`: the arrays).
pub const HOST_NOTE: &str = "adds into {}: compared as the array after the call less before it, bit for bit only where the array held 0 before the call";
