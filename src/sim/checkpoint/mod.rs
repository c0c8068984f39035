//! The solver's state as a checkpoint: every array and number a step reads, so that a run
//! restored from it continues bit for bit.
//!
//! What is in it is decided in one place, [`Sim::save_state`] and [`Sim::restore_state`], by
//! destructuring [`Sim`], [`Particles`], [`Work`], [`Book`] and [`Stability`] without `..`: a field
//! added to any of them does not compile until it is saved or its omission is written down here.
//! Left out, with the reason:
//! - `Sim::case`, `Sim::cfg`, `Sim::plan`: rebuilt from the run directory's case.toml, as the run
//!   built them (the plan's per-stage timings are saved);
//! - `Sim::cmp`: the dual run's comparator (dual runs do not checkpoint);
//! - the incidence lists and the scratch buffers of [`crate::modules::nnps::PairList`]: rebuilt
//!   after every search, before anything reads them; the Rust cell search's Verlet candidate
//!   lists change only its speed (the pair list is canonical: tests/restart.rs checks that a
//!   resumed run, which starts with none, is bitwise the uninterrupted one).
//!
//! The file format ([`Blob`]): a magic line, a version, named arrays (f64 as their bits,
//! integers, text) and a SHA-256 of everything before it, so a truncated or damaged checkpoint is
//! refused before anything is read from it.

use super::{Book, Sim, Stability};
use crate::error::{Result, SphError, input};
use crate::state::{Particles, Work};
use std::collections::BTreeMap;

const MAGIC: &[u8; 20] = b"BLASTSPH-CHECKPOINT\n";
/// Version of the format; a checkpoint of another version is refused.
pub const VERSION: u32 = 3;

/// One named array of a checkpoint.
#[derive(Debug, Clone, PartialEq)]
pub enum Item {
    F64(Vec<f64>),
    I32(Vec<i32>),
    I64(Vec<i64>),
    U32(Vec<u32>),
    U64(Vec<u64>),
    Text(String),
}

impl Item {
    /// The array as a borrowed [`Ref`] (what is written to the file).
    fn as_ref(&self) -> Ref<'_> {
        match self {
            Item::F64(v) => Ref::F64(v),
            Item::I32(v) => Ref::I32(v),
            Item::I64(v) => Ref::I64(v),
            Item::U32(v) => Ref::U32(v),
            Item::U64(v) => Ref::U64(v),
            Item::Text(s) => Ref::Text(s),
        }
    }
}

/// One named array of a checkpoint, borrowed from the state being saved (written as the owned
/// [`Item`] of the same kind would be: the file does not tell them apart).
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Ref<'a> {
    F64(&'a [f64]),
    I32(&'a [i32]),
    I64(&'a [i64]),
    U32(&'a [u32]),
    U64(&'a [u64]),
    Text(&'a str),
}

impl Ref<'_> {
    /// The kind's code in the file.
    fn code(&self) -> u8 {
        match self {
            Ref::F64(_) => 0,
            Ref::I32(_) => 1,
            Ref::I64(_) => 2,
            Ref::U32(_) => 3,
            Ref::U64(_) => 4,
            Ref::Text(_) => 5,
        }
    }
    /// An owned copy.
    fn to_item(self) -> Item {
        match self {
            Ref::F64(v) => Item::F64(v.to_vec()),
            Ref::I32(v) => Item::I32(v.to_vec()),
            Ref::I64(v) => Item::I64(v.to_vec()),
            Ref::U32(v) => Item::U32(v.to_vec()),
            Ref::U64(v) => Item::U64(v.to_vec()),
            Ref::Text(s) => Item::Text(s.to_string()),
        }
    }
    /// The array's name, kind, length and values.
    fn write(self, w: &mut impl std::io::Write, name: &str) -> std::io::Result<()> {
        head(w, name, self.code())?;
        match self {
            Ref::F64(v) => words(w, v.iter().map(|x| x.to_bits().to_le_bytes())),
            Ref::I32(v) => words(w, v.iter().map(|x| x.to_le_bytes())),
            Ref::I64(v) => words(w, v.iter().map(|x| x.to_le_bytes())),
            Ref::U32(v) => words(w, v.iter().map(|x| x.to_le_bytes())),
            Ref::U64(v) => words(w, v.iter().map(|x| x.to_le_bytes())),
            Ref::Text(s) => words(w, s.bytes().map(|x| [x])),
        }
    }
}

/// Named arrays, written and read as one checksummed file. The state's large arrays are put as
/// borrowed [`Ref`]s and streamed to the file by [`Blob::encode_to`], so that writing a
/// checkpoint needs no copy of the state in memory.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct Blob<'a> {
    pub items: BTreeMap<String, Item>,
    refs: BTreeMap<String, Ref<'a>>,
}

/// A writer that hashes what goes through it (the checkpoint's SHA-256 of everything before it).
struct Hashing<'w> {
    w: &'w mut dyn std::io::Write,
    sum: sha2::Sha256,
}

impl std::io::Write for Hashing<'_> {
    fn write(&mut self, buf: &[u8]) -> std::io::Result<usize> {
        use sha2::Digest;
        let n = self.w.write(buf)?;
        self.sum.update(&buf[..n]);
        Ok(n)
    }
    fn flush(&mut self) -> std::io::Result<()> {
        self.w.flush()
    }
}

fn bad(what: &str) -> SphError {
    input(format!("checkpoint: {what}"))
}

impl<'a> Blob<'a> {
    pub fn put(&mut self, name: &str, item: Item) {
        self.refs.remove(name);
        self.items.insert(name.to_string(), item);
    }
    /// Puts an array borrowed from the state (no copy; see [`Ref`]).
    pub fn put_ref(&mut self, name: &str, r: Ref<'a>) {
        self.items.remove(name);
        self.refs.insert(name.to_string(), r);
    }
    pub fn put_f64(&mut self, name: &str, v: &[f64]) {
        self.put(name, Item::F64(v.to_vec()));
    }
    pub fn put_text(&mut self, name: &str, s: &str) {
        self.put(name, Item::Text(s.to_string()));
    }

    fn get(&self, name: &str) -> Result<std::borrow::Cow<'_, Item>> {
        use std::borrow::Cow;
        if let Some(it) = self.items.get(name) {
            return Ok(Cow::Borrowed(it));
        }
        match self.refs.get(name) {
            Some(r) => Ok(Cow::Owned(r.to_item())),
            None => Err(bad(&format!("no `{name}` in it (written by another version?)"))),
        }
    }
    pub fn f64(&self, name: &str) -> Result<Vec<f64>> {
        match &*self.get(name)? {
            Item::F64(v) => Ok(v.clone()),
            _ => Err(bad(&format!("`{name}` is not an array of reals"))),
        }
    }
    pub fn i32(&self, name: &str) -> Result<Vec<i32>> {
        match &*self.get(name)? {
            Item::I32(v) => Ok(v.clone()),
            _ => Err(bad(&format!("`{name}` is not an array of 32-bit integers"))),
        }
    }
    pub fn i64(&self, name: &str) -> Result<Vec<i64>> {
        match &*self.get(name)? {
            Item::I64(v) => Ok(v.clone()),
            _ => Err(bad(&format!("`{name}` is not an array of 64-bit integers"))),
        }
    }
    pub fn u32(&self, name: &str) -> Result<Vec<u32>> {
        match &*self.get(name)? {
            Item::U32(v) => Ok(v.clone()),
            _ => Err(bad(&format!("`{name}` is not an array of unsigned 32-bit integers"))),
        }
    }
    pub fn u64(&self, name: &str) -> Result<Vec<u64>> {
        match &*self.get(name)? {
            Item::U64(v) => Ok(v.clone()),
            _ => Err(bad(&format!("`{name}` is not an array of unsigned 64-bit integers"))),
        }
    }
    pub fn text(&self, name: &str) -> Result<String> {
        match &*self.get(name)? {
            Item::Text(s) => Ok(s.clone()),
            _ => Err(bad(&format!("`{name}` is not text"))),
        }
    }
    /// One real (an array of one).
    pub fn scalar(&self, name: &str) -> Result<f64> {
        one(name, self.f64(name)?)
    }
    /// One count (an array of one).
    pub fn count(&self, name: &str) -> Result<u64> {
        one(name, self.u64(name)?)
    }

    /// The file's bytes.
    pub fn encode(&self) -> Vec<u8> {
        let mut b = Vec::new();
        // (writing into a Vec does not fail)
        let _ = self.encode_to(&mut b);
        b
    }

    /// Writes the file's bytes to `w` as they are produced: the arrays in name order (owned and
    /// borrowed alike), then the SHA-256 of everything before it.
    pub fn encode_to(&self, w: &mut dyn std::io::Write) -> std::io::Result<()> {
        use sha2::{Digest, Sha256};
        use std::io::Write;
        let mut h = Hashing { w, sum: Sha256::new() };
        h.write_all(MAGIC)?;
        h.write_all(&VERSION.to_le_bytes())?;
        h.write_all(&((self.items.len() + self.refs.len()) as u64).to_le_bytes())?;
        // both maps in one name order (a name is in one of them only)
        let (mut a, mut r) = (self.items.iter().peekable(), self.refs.iter().peekable());
        loop {
            let own = match (a.peek(), r.peek()) {
                (None, None) => break,
                (Some(_), None) => true,
                (None, Some(_)) => false,
                (Some((na, _)), Some((nr, _))) => na < nr,
            };
            let (name, arr) = if own {
                let Some((name, item)) = a.next() else { break };
                (name, item.as_ref())
            } else {
                let Some((name, arr)) = r.next() else { break };
                (name, *arr)
            };
            arr.write(&mut h, name)?;
        }
        let sum = h.sum.finalize();
        h.w.write_all(&sum)
    }

    /// Reads the file's bytes: the checksum first, then every array, bounds checked.
    pub fn decode(bytes: &[u8]) -> Result<Blob<'static>> {
        use sha2::{Digest, Sha256};
        if bytes.len() < MAGIC.len() + 4 + 8 + 32 || &bytes[..MAGIC.len()] != MAGIC {
            return Err(bad("not a blastsph checkpoint (or truncated)"));
        }
        let (body, sum) = bytes.split_at(bytes.len() - 32);
        if Sha256::digest(body).as_slice() != sum {
            return Err(bad("damaged (its SHA-256 does not match: truncated or changed)"));
        }
        let mut r = Reader { b: body, at: MAGIC.len() };
        let version = u32::from_le_bytes(r.take::<4>()?);
        if version != VERSION {
            return Err(bad(&format!("format version {version}; this blastsph reads version {VERSION}")));
        }
        let n = u64::from_le_bytes(r.take::<8>()?);
        let mut blob = Blob::default();
        for _ in 0..n {
            let len = r.len(1)?;
            let name = String::from_utf8(r.bytes(len)?.to_vec()).map_err(|_| bad("a name that is not UTF-8"))?;
            let code = r.take::<1>()?[0];
            let item = match code {
                0 => Item::F64(r.array::<8, _>(|w| f64::from_bits(u64::from_le_bytes(w)))?),
                1 => Item::I32(r.array::<4, _>(i32::from_le_bytes)?),
                2 => Item::I64(r.array::<8, _>(i64::from_le_bytes)?),
                3 => Item::U32(r.array::<4, _>(u32::from_le_bytes)?),
                4 => Item::U64(r.array::<8, _>(u64::from_le_bytes)?),
                5 => {
                    let len = r.len(1)?;
                    Item::Text(String::from_utf8(r.bytes(len)?.to_vec()).map_err(|_| bad("text that is not UTF-8"))?)
                }
                c => return Err(bad(&format!("unknown array kind {c}"))),
            };
            blob.items.insert(name, item);
        }
        if r.at != body.len() {
            return Err(bad("bytes after the last array"));
        }
        Ok(blob)
    }
}

fn one<T: Copy>(name: &str, v: Vec<T>) -> Result<T> {
    match v.as_slice() {
        [x] => Ok(*x),
        _ => Err(bad(&format!("`{name}` must hold one value"))),
    }
}

/// An array's name and kind.
fn head(w: &mut impl std::io::Write, name: &str, code: u8) -> std::io::Result<()> {
    w.write_all(&(name.len() as u64).to_le_bytes())?;
    w.write_all(name.as_bytes())?;
    w.write_all(&[code])
}

/// An array's length, then its values, through a small buffer.
fn words<const N: usize>(
    w: &mut impl std::io::Write,
    it: impl ExactSizeIterator<Item = [u8; N]>,
) -> std::io::Result<()> {
    w.write_all(&(it.len() as u64).to_le_bytes())?;
    let mut buf = Vec::with_capacity(1 << 16);
    for x in it {
        buf.extend_from_slice(&x);
        if buf.len() >= (1 << 16) {
            w.write_all(&buf)?;
            buf.clear();
        }
    }
    w.write_all(&buf)
}

struct Reader<'a> {
    b: &'a [u8],
    at: usize,
}

impl Reader<'_> {
    fn bytes(&mut self, n: usize) -> Result<&[u8]> {
        let end = self.at.checked_add(n).filter(|&e| e <= self.b.len()).ok_or_else(|| bad("truncated"))?;
        let s = &self.b[self.at..end];
        self.at = end;
        Ok(s)
    }
    fn take<const N: usize>(&mut self) -> Result<[u8; N]> {
        let mut w = [0u8; N];
        w.copy_from_slice(self.bytes(N)?);
        Ok(w)
    }
    /// A length of `width`-byte values that the rest of the file can hold.
    fn len(&mut self, width: usize) -> Result<usize> {
        let n = u64::from_le_bytes(self.take::<8>()?);
        let left = (self.b.len() - self.at) / width;
        usize::try_from(n).ok().filter(|&n| n <= left).ok_or_else(|| bad("an array longer than the file"))
    }
    fn array<const N: usize, T>(&mut self, f: impl Fn([u8; N]) -> T) -> Result<Vec<T>> {
        let n = self.len(N)?;
        let raw = self.bytes(n * N)?;
        Ok(raw
            .chunks_exact(N)
            .map(|c| {
                let mut w = [0u8; N];
                w.copy_from_slice(c);
                f(w)
            })
            .collect())
    }
}

fn usize_of(name: &str, v: u64) -> Result<usize> {
    usize::try_from(v).map_err(|_| bad(&format!("`{name}` = {v} does not fit this machine")))
}

impl Sim {
    /// The state a step and the run loop's solver read, into `b` (names under `sim.`, `p.`, `w.`).
    pub fn save_state<'a>(&'a self, b: &mut Blob<'a>) {
        let Sim {
            case: _,
            cfg: _,
            plan,
            p,
            w,
            t,
            nstep,
            dt_prev,
            book,
            stab,
            h_init,
            region,
            x_init,
            e_initial,
            index_of_id,
            cmp: _,
            timers,
            dt_first,
            pace,
        } = self;
        b.put_f64("sim.t", &[*t]);
        b.put("sim.nstep", Item::U64(vec![*nstep]));
        b.put_f64("sim.dt_prev", &[*dt_prev]);
        let Book { work_wall, work_penalty, work_gravity, work_floor } = book;
        b.put_f64("sim.book", &[*work_wall, *work_penalty, *work_gravity, *work_floor]);
        let Stability {
            max_wall_penetration_m,
            left_domain,
            h_ratio_min,
            h_ratio_max,
            min_interface_gap_dx,
            max_neighbours,
            mean_neighbours,
            nan,
        } = stab;
        b.put_f64(
            "sim.stab.f",
            &[
                *max_wall_penetration_m,
                *h_ratio_min,
                *h_ratio_max,
                min_interface_gap_dx.unwrap_or(f64::NAN),
                *mean_neighbours,
            ],
        );
        b.put(
            "sim.stab.n",
            Item::U64(vec![
                *left_domain as u64,
                *max_neighbours as u64,
                u64::from(*nan),
                u64::from(min_interface_gap_dx.is_some()),
            ]),
        );
        b.put_ref("sim.h_init", Ref::F64(h_init));
        b.put_ref("sim.region", Ref::U32(region));
        b.put_ref("sim.x_init", Ref::F64(x_init));
        b.put_f64("sim.e_initial", &[*e_initial]);
        b.put_ref("sim.index_of_id", Ref::U32(index_of_id));
        let names: Vec<&str> = timers.keys().copied().collect();
        b.put_text("sim.timers.names", &names.join("\n"));
        b.put_f64("sim.timers.seconds", &timers.values().copied().collect::<Vec<_>>());
        b.put_f64("sim.dt_first", &[*dt_first]);
        b.put("sim.pace", Item::U64(vec![pace.0]));
        b.put_f64("sim.pace_t", &[pace.1]);
        let stages: Vec<&str> = plan.entries.iter().map(|e| e.stage.name()).collect();
        b.put_text("sim.plan.stages", &stages.join("\n"));
        b.put_f64("sim.plan.seconds", &plan.entries.iter().map(|e| e.seconds).collect::<Vec<_>>());

        let Particles {
            dim,
            nreal,
            ntotal,
            x,
            v,
            rho,
            p: pr,
            c,
            e,
            h,
            mass,
            mat,
            id,
            tau,
            tlight,
            burn,
            h0,
            rho0,
            alpha,
        } = p;
        b.put("p.sizes", Item::U64(vec![*dim as u64, *nreal as u64, *ntotal as u64]));
        for (name, a) in [
            ("p.x", x),
            ("p.v", v),
            ("p.rho", rho),
            ("p.p", pr),
            ("p.c", c),
            ("p.e", e),
            ("p.h", h),
            ("p.mass", mass),
            ("p.tau", tau),
            ("p.tlight", tlight),
            ("p.burn", burn),
            ("p.h0", h0),
            ("p.rho0", rho0),
            ("p.alpha", alpha),
        ] {
            b.put_ref(name, Ref::F64(a));
        }
        b.put_ref("p.mat", Ref::I32(mat));
        b.put_ref("p.id", Ref::I64(id));

        let Work {
            pairs,
            w: ww,
            dwdx,
            w0,
            drho,
            acc,
            dde,
            dv,
            de,
            eps,
            rot,
            dtau,
            av,
            dhdt,
            rho_min,
            e_min,
            v_min,
            tau_min,
            gsrc,
            gseg,
            dt_cfl,
            rinv,
            pmass,
            mumax,
            efloor,
            divv: _, // the viscosity switch's workspace, recomputed before every use
        } = w;
        b.put_ref("w.pairs.i", Ref::I32(&pairs.i));
        b.put_ref("w.pairs.j", Ref::I32(&pairs.j));
        for (name, a) in [
            ("w.w", ww),
            ("w.dwdx", dwdx),
            ("w.w0", w0),
            ("w.drho", drho),
            ("w.acc", acc),
            ("w.dde", dde),
            ("w.dv", dv),
            ("w.de", de),
            ("w.eps", eps),
            ("w.rot", rot),
            ("w.dtau", dtau),
            ("w.av", av),
            ("w.dhdt", dhdt),
            ("w.rho_min", rho_min),
            ("w.e_min", e_min),
            ("w.v_min", v_min),
            ("w.tau_min", tau_min),
            ("w.dt_cfl", dt_cfl),
            ("w.rinv", rinv),
            ("w.pmass", pmass),
            ("w.mumax", mumax),
            ("w.efloor", efloor),
        ] {
            b.put_ref(name, Ref::F64(a));
        }
        b.put_ref("w.gsrc", Ref::I32(gsrc));
        b.put_ref("w.gseg", Ref::I32(gseg));
    }

    /// Puts the state of `b` into this simulation, built from the same case (or, with
    /// `--allow-changed`, a changed one): refused with one line when the checkpoint cannot be
    /// the state of this simulation (another particle count, another plan).
    pub fn restore_state(&mut self, b: &Blob) -> Result<()> {
        // what must agree before anything is replaced
        let sizes = b.u64("p.sizes")?;
        let [dim, nreal, ntotal] = sizes.as_slice() else { return Err(bad("`p.sizes` must hold 3 values")) };
        let (dim, nreal, ntotal) = (usize_of("dim", *dim)?, usize_of("nreal", *nreal)?, usize_of("ntotal", *ntotal)?);
        if dim != self.p.dim || nreal != self.p.nreal {
            return Err(input(format!(
                "the checkpoint holds {nreal} particles in {dim}D; the case makes {} in {}D: it is not this case's state",
                self.p.nreal, self.p.dim
            )));
        }
        let stages: Vec<&str> = self.plan.entries.iter().map(|e| e.stage.name()).collect();
        let saved = b.text("sim.plan.stages")?;
        if saved != stages.join("\n") {
            return Err(input(format!(
                "the checkpoint's step has the stages {}; the case's has {}: it is not this case's state",
                saved.replace('\n', ", "),
                stages.join(", ")
            )));
        }
        let nmat = self.case.materials.len();
        let self_regions = self.case.regions.len();
        let Sim {
            case: _,
            cfg: _,
            plan,
            p,
            w,
            t,
            nstep,
            dt_prev,
            book,
            stab,
            h_init,
            region,
            x_init,
            e_initial,
            index_of_id,
            cmp: _,
            timers,
            dt_first,
            pace,
        } = self;

        let Particles {
            dim: _,
            nreal: _,
            ntotal: p_ntotal,
            x,
            v,
            rho,
            p: pr,
            c,
            e,
            h,
            mass,
            mat,
            id,
            tau,
            tlight,
            burn,
            h0,
            rho0,
            alpha,
        } = p;
        let sized = |name: &str, got: usize, want: usize| -> Result<()> {
            if got == want { Ok(()) } else { Err(bad(&format!("`{name}` holds {got} values, not {want}"))) }
        };
        let new_mat = b.i32("p.mat")?;
        sized("p.mat", new_mat.len(), ntotal)?;
        if let Some(m) = new_mat.iter().find(|&&m| m < 0 || m as usize >= nmat) {
            return Err(input(format!("the checkpoint has a particle of material {m}; the case has {nmat} materials")));
        }
        let new_id = b.i64("p.id")?;
        sized("p.id", new_id.len(), id.len())?;
        if new_id.iter().any(|&i| i < 0 || i as usize >= nreal) {
            return Err(bad("a particle id out of range"));
        }
        for (name, a, n) in [
            ("p.x", &mut *x, dim * ntotal),
            ("p.v", &mut *v, dim * ntotal),
            ("p.rho", &mut *rho, ntotal),
            ("p.p", &mut *pr, ntotal),
            ("p.c", &mut *c, ntotal),
            ("p.e", &mut *e, ntotal),
            ("p.h", &mut *h, ntotal),
            ("p.mass", &mut *mass, ntotal),
        ] {
            let val = b.f64(name)?;
            sized(name, val.len(), n)?;
            *a = val;
        }
        // allocated by the stages that use them (register): their sizes are the case's
        for (name, a) in
            [("p.tlight", &mut *tlight), ("p.burn", &mut *burn), ("p.h0", &mut *h0), ("p.rho0", &mut *rho0)]
        {
            let val = b.f64(name)?;
            sized(name, val.len(), a.len())?;
            *a = val;
        }
        let new_tau = b.f64("p.tau")?;
        sized("p.tau", new_tau.len(), if tau.is_empty() { 0 } else { crate::modules::param::NSTR * ntotal })?;
        *tau = new_tau;
        let new_alpha = b.f64("p.alpha")?;
        sized("p.alpha", new_alpha.len(), if alpha.is_empty() { 0 } else { ntotal })?;
        *alpha = new_alpha;
        *mat = new_mat;
        *id = new_id;
        *p_ntotal = ntotal;

        let Work {
            pairs,
            w: ww,
            dwdx,
            w0,
            drho,
            acc,
            dde,
            dv,
            de,
            eps,
            rot,
            dtau,
            av,
            dhdt,
            rho_min,
            e_min,
            v_min,
            tau_min,
            gsrc,
            gseg,
            dt_cfl,
            rinv,
            pmass,
            mumax,
            efloor,
            divv: _, // the viscosity switch's workspace, recomputed before every use
        } = w;
        let (pi, pj) = (b.i32("w.pairs.i")?, b.i32("w.pairs.j")?);
        sized("w.pairs.j", pj.len(), pi.len())?;
        if pi.iter().chain(&pj).any(|&k| k < 0 || k as usize >= ntotal) {
            return Err(bad("a pair of particles out of range"));
        }
        *pairs = crate::modules::nnps::PairList::new(pi, pj);
        for (name, a) in [
            ("w.w", ww),
            ("w.dwdx", dwdx),
            ("w.w0", w0),
            ("w.drho", drho),
            ("w.acc", acc),
            ("w.dde", dde),
            ("w.dv", dv),
            ("w.de", de),
            ("w.eps", eps),
            ("w.rot", rot),
            ("w.dtau", dtau),
            ("w.av", av),
            ("w.dhdt", dhdt),
            ("w.rho_min", rho_min),
            ("w.e_min", e_min),
            ("w.v_min", v_min),
            ("w.tau_min", tau_min),
            ("w.dt_cfl", dt_cfl),
            ("w.rinv", rinv),
            ("w.pmass", pmass),
            ("w.mumax", mumax),
            ("w.efloor", efloor),
        ] {
            *a = b.f64(name)?;
        }
        *gsrc = b.i32("w.gsrc")?;
        *gseg = b.i32("w.gseg")?;

        *t = b.scalar("sim.t")?;
        *nstep = b.count("sim.nstep")?;
        *dt_prev = b.scalar("sim.dt_prev")?;
        let bk = b.f64("sim.book")?;
        let [work_wall, work_penalty, work_gravity, work_floor] = bk.as_slice() else {
            return Err(bad("`sim.book` must hold 4 values"));
        };
        *book = Book {
            work_wall: *work_wall,
            work_penalty: *work_penalty,
            work_gravity: *work_gravity,
            work_floor: *work_floor,
        };
        let sf = b.f64("sim.stab.f")?;
        let sn = b.u64("sim.stab.n")?;
        let ([pen, hmin, hmax, gap, mean], [left, maxn, nan, has_gap]) = (sf.as_slice(), sn.as_slice()) else {
            return Err(bad("`sim.stab` must hold 5 reals and 4 counts"));
        };
        *stab = Stability {
            max_wall_penetration_m: *pen,
            left_domain: usize_of("left_domain", *left)?,
            h_ratio_min: *hmin,
            h_ratio_max: *hmax,
            min_interface_gap_dx: (*has_gap != 0).then_some(*gap),
            max_neighbours: usize_of("max_neighbours", *maxn)?,
            mean_neighbours: *mean,
            nan: *nan != 0,
        };
        for (name, a, n) in [("sim.h_init", &mut *h_init, nreal), ("sim.x_init", &mut *x_init, dim * nreal)] {
            let val = b.f64(name)?;
            sized(name, val.len(), n)?;
            *a = val;
        }
        let nregion = self_regions;
        for (name, a, below) in [("sim.region", &mut *region, nregion), ("sim.index_of_id", &mut *index_of_id, nreal)] {
            let val = b.u32(name)?;
            sized(name, val.len(), nreal)?;
            if val.iter().any(|&k| k as usize >= below) {
                return Err(bad(&format!("`{name}` holds an index out of range")));
            }
            *a = val;
        }
        *e_initial = b.scalar("sim.e_initial")?;
        let names = b.text("sim.timers.names")?;
        let secs = b.f64("sim.timers.seconds")?;
        timers.clear();
        for (n, s) in names.split('\n').filter(|n| !n.is_empty()).zip(secs) {
            // the solver's timers are named by string literals; a resumed run names them anew
            // (a handful of bytes, once per resume)
            timers.insert(Box::leak(n.to_string().into_boxed_str()), s);
        }
        *dt_first = b.scalar("sim.dt_first")?;
        *pace = (b.count("sim.pace")?, b.scalar("sim.pace_t")?);
        let secs = b.f64("sim.plan.seconds")?;
        for (e, s) in plan.entries.iter_mut().zip(secs) {
            e.seconds = s;
        }
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Arrays put borrowed are written exactly as the same arrays put owned, in one name order.
    #[test]
    fn borrowed_and_owned_arrays_encode_the_same() {
        let x = vec![1.5, -0.0, f64::MIN_POSITIVE, 3e300];
        let m = vec![3i32, -7];
        let id = vec![1i64 << 40, 2];
        let r = vec![9u32, 0, 4];
        let mut own = Blob::default();
        own.put("b.x", Item::F64(x.clone()));
        own.put("d.m", Item::I32(m.clone()));
        own.put("a.id", Item::I64(id.clone()));
        own.put("c.r", Item::U32(r.clone()));
        own.put("c.n", Item::U64(vec![5]));
        own.put_text("e.t", "text");
        let mut mixed = Blob::default();
        mixed.put_ref("b.x", Ref::F64(&x));
        mixed.put_ref("d.m", Ref::I32(&m));
        mixed.put_ref("a.id", Ref::I64(&id));
        mixed.put_ref("c.r", Ref::U32(&r));
        mixed.put("c.n", Item::U64(vec![5]));
        mixed.put_text("e.t", "text");
        let bytes = own.encode();
        assert_eq!(mixed.encode(), bytes);
        let back = Blob::decode(&bytes).unwrap();
        assert_eq!(back, own);
        assert_eq!(mixed.f64("b.x").unwrap(), x);
        // a name put again replaces the earlier array, borrowed or owned
        mixed.put("b.x", Item::F64(vec![2.0]));
        own.put("b.x", Item::F64(vec![2.0]));
        assert_eq!(mixed.encode(), own.encode());
    }
}
