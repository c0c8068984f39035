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

mod sim;

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

#[cfg(test)]
mod tests;
