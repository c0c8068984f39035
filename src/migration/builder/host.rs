//! The host program of a legacy build (`DIR/libhost.so`, run by `blastsph legacy host`): the
//! user's own main program and every object, with each mapped routine interposed.
//!
//! How: the object that defines a mapped routine is copied into `obj/host/`, and in the copy
//! (`objcopy`) the routine's symbol is made weak and given a second name, `bs_real_<symbol>`,
//! at the same address. A generated C wrapper defines the routine's symbol strongly: it hands
//! the argument addresses to blastsph's hook, calls `bs_real_<symbol>` and hands them again.
//! At the link every call of the routine, from another file or from its own file, binds to the
//! wrapper (a weak definition yields to a strong one). The sources and the build's own objects
//! stay as they are.

use super::*;

/// The host library's file name in the build folder.
pub const HOST_LIBRARY: &str = "libhost.so";

/// The C symbol of the hook pointer the wrappers call (set by blastsph before the main program
/// starts; null: the wrappers only call the routine).
pub const HOOK_SYMBOL: &str = "blastsph_host_hook";

/// What the host build made: the library's name, or why there is none; and each routine that
/// cannot be interposed, with why.
pub(super) struct Host {
    pub(super) library: Option<String>,
    pub(super) note: Option<String>,
    pub(super) refused: Vec<String>,
}

/// One symbol of an object, as `objdump -t` lists it: (name, section, value).
fn symbols(text: &str) -> Vec<(String, String, String)> {
    text.lines()
        .filter_map(|l| {
            let f: Vec<&str> = l.split_whitespace().collect();
            // value, flags..., section, size, name
            (f.len() >= 4 && f[0].chars().all(|c| c.is_ascii_hexdigit()) && f[0].len() >= 8).then(|| {
                let n = f.len();
                (f[n - 1].to_string(), f[n - 3].to_string(), f[0].to_string())
            })
        })
        .collect()
}

/// Builds `out/libhost.so` from `objects` (every source's, the main program's included) when
/// the sources hold exactly one main program.
pub(super) fn link_host(
    out: &Path,
    free: &[String],
    objects: &[PathBuf],
    is_program: &[bool],
    routines: &[RoutineInfo],
    log: &mut Log,
) -> Result<Host> {
    let none = |note: String| Ok(Host { library: None, note: Some(note), refused: Vec::new() });
    if is_program.iter().filter(|p| **p).count() != 1 {
        return none("the sources do not hold exactly one main program".into());
    }
    let dir = out.join("obj").join("host");
    std::fs::create_dir_all(&dir).map_err(|e| SphError::Io(format!("{}: {e}", dir.display())))?;
    let _ = std::fs::remove_file(out.join(HOST_LIBRARY));
    let mut refused = Vec::new();
    let mut linked: Vec<PathBuf> = objects.to_vec();
    let mut wrapped: Vec<&RoutineInfo> = Vec::new();
    // the objects that define mapped routines: their symbols
    for (k, o) in objects.iter().enumerate() {
        let (ok, so, _) = log.run(Command::new("objdump").arg("-t").arg(o))?;
        if !ok {
            return none(format!("objdump -t {} failed", o.display()));
        }
        let syms = symbols(&so);
        let mut args: Vec<String> = Vec::new();
        for r in routines {
            let Some((_, sec, val)) = syms.iter().find(|(n, s, _)| *n == r.symbol && s != "*UND*") else { continue };
            // a copy the compiler made of it, which calls in its own file may take instead
            if let Some((clone, _, _)) = syms.iter().find(|(n, _, _)| {
                n.strip_prefix(&r.symbol)
                    .is_some_and(|rest| [".localalias", ".constprop", ".isra"].iter().any(|c| rest.starts_with(c)))
            }) {
                refused.push(format!(
                    "routine {}: its file's calls may take the compiler's copy `{clone}`, which cannot be interposed (a flag such as -fno-semantic-interposition in fflags?)",
                    r.name
                ));
                continue;
            }
            args.push(format!("--weaken-symbol={}", r.symbol));
            args.push("--add-symbol".into());
            args.push(format!("bs_real_{}={sec}:0x{val},global,function", r.symbol));
            wrapped.push(r);
        }
        if args.is_empty() {
            continue;
        }
        let copy = dir.join(o.file_name().unwrap_or_default());
        std::fs::copy(o, &copy).map_err(|e| SphError::Io(format!("{}: {e}", copy.display())))?;
        let (ok, _, se) = log.run(Command::new("objcopy").args(&args).arg(&copy))?;
        if !ok {
            return none(format!("objcopy failed on {}: {}", copy.display(), first_error(&se)));
        }
        linked[k] = copy;
    }
    let text = wrappers(routines, &wrapped);
    let src = dir.join("blastsph_host.c");
    std::fs::write(&src, text).map_err(|e| SphError::Io(format!("{}: {e}", src.display())))?;
    let wobj = dir.join("blastsph_host.o");
    let (ok, _, se) = log.run(Command::new("gfortran").args(["-c", "-fPIC", "-O2"]).arg("-o").arg(&wobj).arg(&src))?;
    if !ok {
        return none(format!("the generated wrappers do not compile: {}", first_error(&se)));
    }
    let lib = out.join(HOST_LIBRARY);
    let (ok, _, se) =
        log.run(Command::new("gfortran").args(LINK_FLAGS).args(free).arg("-o").arg(&lib).args(&linked).arg(&wobj))?;
    if !ok {
        return none(format!("the host program does not link: {}", first_error(&se)));
    }
    Ok(Host { library: Some(HOST_LIBRARY.to_string()), note: None, refused })
}

/// The C source of the wrappers: one per interposed routine, taking the routine's arguments as
/// addresses (every dummy of the vocabulary is a number: no hidden length arguments).
fn wrappers(all: &[RoutineInfo], wrapped: &[&RoutineInfo]) -> String {
    let mut f = String::new();
    let _ = writeln!(f, "/* Generated by `blastsph legacy build`: the wrappers of the host program. */");
    let _ = writeln!(f, "typedef void (*bs_hook_t)(int routine, int phase, void **args);");
    let _ = writeln!(f, "bs_hook_t {HOOK_SYMBOL} = 0;");
    for r in wrapped {
        let k = all.iter().position(|x| x.name == r.name).unwrap_or(0);
        let n = r.args.len();
        let params: Vec<String> = (0..n).map(|i| format!("void *a{i}")).collect();
        let names: Vec<String> = (0..n).map(|i| format!("a{i}")).collect();
        let decl = if n == 0 { "void".to_string() } else { params.join(", ") };
        let list = if n == 0 { "0".to_string() } else { names.join(", ") };
        let _ = writeln!(f, "extern void bs_real_{}({decl});", r.symbol);
        let _ = writeln!(f, "void {}({decl}) {{", r.symbol);
        let _ = writeln!(f, "  void *a[{}] = {{{list}}};", n.max(1));
        let _ = writeln!(f, "  if ({HOOK_SYMBOL}) {HOOK_SYMBOL}({k}, 0, a);");
        let _ = writeln!(f, "  bs_real_{}({});", r.symbol, names.join(", "));
        let _ = writeln!(f, "  if ({HOOK_SYMBOL}) {HOOK_SYMBOL}({k}, 1, a);");
        let _ = writeln!(f, "}}");
    }
    f
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn objdump_symbols_are_read_with_their_section() {
        let t = "a.o:     file format elf64-x86-64\n\nSYMBOL TABLE:\n\
                 0000000000000000 l    df *ABS*\t0000000000000000 a.f\n\
                 0000000000000010 g     F .text\t000000000000000d kern_\n\
                 0000000000000000         *UND*\t0000000000000000 _gfortran_st_write\n";
        let s = symbols(t);
        assert!(s.contains(&("kern_".into(), ".text".into(), "0000000000000010".into())), "{s:?}");
        assert!(s.contains(&("_gfortran_st_write".into(), "*UND*".into(), "0000000000000000".into())), "{s:?}");
    }
}
