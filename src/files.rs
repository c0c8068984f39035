//! Files written safely: created new without following a link, opened without following one,
//! or replaced whole through a temporary file beside them.

use crate::error::{IoAt, Result, SphError, input};
use std::fs::{File, OpenOptions};
use std::path::{Path, PathBuf};

/// Makes `o` refuse to open a symbolic link.
#[cfg(unix)]
pub(crate) fn nofollow(o: &mut OpenOptions) {
    use std::os::unix::fs::OpenOptionsExt;
    o.custom_flags(libc::O_NOFOLLOW);
}

/// Makes `o` refuse to open a symbolic link (nothing to do here).
#[cfg(not(unix))]
pub(crate) fn nofollow(_o: &mut OpenOptions) {}

/// Creates a new file (refused when the name exists, as a file or a link: never follows one).
pub(crate) fn create_new(path: &Path) -> Result<File> {
    let mut o = OpenOptions::new();
    o.write(true).create_new(true);
    nofollow(&mut o);
    o.open(path).io_at(path.display())
}

/// Opens an existing file to append to, refusing a link.
pub(crate) fn open_append(path: &Path) -> Result<File> {
    let mut o = OpenOptions::new();
    o.append(true);
    nofollow(&mut o);
    o.open(path).map_err(|e| input(format!("{}: {e}", path.display())))
}

/// Opens an existing file to read and write, refusing a link.
pub fn open_rw(path: &Path) -> Result<File> {
    let mut o = OpenOptions::new();
    o.read(true).write(true);
    nofollow(&mut o);
    o.open(path).map_err(|e| input(format!("{}: {e}", path.display())))
}

/// Writes `bytes` as `path` through a new temporary file beside it, synced, then renamed over
/// `path`: a reader sees the old file or the new one, and a link at either name is replaced,
/// never written through.
pub(crate) fn write_atomic(path: &Path, bytes: &[u8]) -> Result<()> {
    write_atomic_with(path, |w| w.write_all(bytes))
}

/// As [`write_atomic`], with the bytes written by `fill` into a buffered writer (a large file is
/// streamed, never held in memory whole).
pub(crate) fn write_atomic_with(
    path: &Path,
    fill: impl FnOnce(&mut dyn std::io::Write) -> std::io::Result<()>,
) -> Result<()> {
    use std::io::Write;
    let mut tmp = path.as_os_str().to_owned();
    tmp.push(".tmp");
    let tmp = PathBuf::from(tmp);
    match std::fs::remove_file(&tmp) {
        Ok(()) => {}
        Err(e) if e.kind() == std::io::ErrorKind::NotFound => {}
        Err(e) => return Err(SphError::Io(format!("{}: {e}", tmp.display()))),
    }
    let f = create_new(&tmp)?;
    let mut bw = std::io::BufWriter::with_capacity(1 << 20, f);
    fill(&mut bw).and_then(|_| bw.flush()).and_then(|_| bw.get_ref().sync_all()).io_at(tmp.display())?;
    drop(bw);
    std::fs::rename(&tmp, path).io_at(path.display())
}
