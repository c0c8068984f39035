//! The house rules of `src/`, read from the source text:
//!
//! - the layer table in the crate documentation (`src/lib.rs`, section "Layers") names every
//!   top-level module of `src/`; a module imports (`crate::x`, `use crate::{x, ..}`, `super::`)
//!   only from its own layer or those below it;
//! - the import graph between top-level modules (a folder or a file of `src/`) has no cycle;
//! - no source file over 800 lines, no function over 150 lines, no
//!   `#[allow(clippy::too_many_arguments)]`.

use std::collections::{BTreeMap, BTreeSet};
use std::path::{Path, PathBuf};

/// Imports from the core to the legacy bridge, one line each (file, module imported): none; the
/// core knows the bridge only through the hook it defines (`sim::hook`).
const CORE_TO_BRIDGE: &[(&str, &str)] = &[];

/// Imports from the legacy bridge upwards: none; the bridge writes files through the core's
/// `files`, and its ledger takes the Riemann L1 errors from its caller.
const BRIDGE_UP: &[(&str, &str)] = &[];

/// Edges between core modules that close a cycle inside the core, allowed as a debt: none. The
/// modules read the case and the state; the case and the state share only `param`, the core's
/// leaf; the set-up checks the generated particles against the case. The list may only shrink.
const CORE_CYCLES: &[(&str, &str)] = &[];

/// Files and functions of the legacy bridge over the size limits; the bridge's own work splits
/// them, and each goes from this list when it does.
const BRIDGE_FILES_OVER: &[&str] = &[];
const BRIDGE_FNS_OVER: &[(&str, &str)] = &[];

const MAX_FILE_LINES: usize = 800;
const MAX_FN_LINES: usize = 150;

fn src() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("src")
}

fn rust_files(dir: &Path, out: &mut Vec<PathBuf>) {
    let mut entries: Vec<PathBuf> = std::fs::read_dir(dir).unwrap().map(|e| e.unwrap().path()).collect();
    entries.sort();
    for p in entries {
        if p.is_dir() {
            rust_files(&p, out);
        } else if p.extension().is_some_and(|e| e == "rs") {
            out.push(p);
        }
    }
}

/// The path of `p` relative to the crate root, with `/` separators (`src/sim/plan.rs`).
fn rel(p: &Path) -> String {
    let root = Path::new(env!("CARGO_MANIFEST_DIR"));
    let r = p.strip_prefix(root).unwrap();
    r.components().map(|c| c.as_os_str().to_string_lossy().into_owned()).collect::<Vec<_>>().join("/")
}

/// The module path of a source file below `src/`: `src/sim/plan.rs` → ["sim", "plan"],
/// `src/sim/mod.rs` → ["sim"], `src/lib.rs` → [].
fn module_path(p: &Path) -> Vec<String> {
    let r = p.strip_prefix(src()).unwrap();
    let mut parts: Vec<String> = r.components().map(|c| c.as_os_str().to_string_lossy().into_owned()).collect();
    let last = parts.pop().unwrap();
    let stem = last.strip_suffix(".rs").unwrap().to_string();
    if !(stem == "mod" || (parts.is_empty() && (stem == "lib" || stem == "main"))) {
        parts.push(stem);
    }
    parts
}

/// Source text with comments, string and character literals blanked (line breaks kept), so that
/// a path in a doc comment or a message is not an import and braces in strings are not counted.
fn code_only(text: &str) -> String {
    let b = text.as_bytes();
    let mut out = String::with_capacity(text.len());
    let mut i = 0;
    let blank = |c: u8, out: &mut String| out.push(if c == b'\n' { '\n' } else { ' ' });
    while i < b.len() {
        let c = b[i];
        if c == b'/' && b.get(i + 1) == Some(&b'/') {
            while i < b.len() && b[i] != b'\n' {
                out.push(' ');
                i += 1;
            }
        } else if c == b'/' && b.get(i + 1) == Some(&b'*') {
            let mut depth = 0;
            while i < b.len() {
                if b[i] == b'/' && b.get(i + 1) == Some(&b'*') {
                    depth += 1;
                    out.push_str("  ");
                    i += 2;
                } else if b[i] == b'*' && b.get(i + 1) == Some(&b'/') {
                    depth -= 1;
                    out.push_str("  ");
                    i += 2;
                    if depth == 0 {
                        break;
                    }
                } else {
                    blank(b[i], &mut out);
                    i += 1;
                }
            }
        } else if c == b'r' && (b.get(i + 1) == Some(&b'"') || b.get(i + 1) == Some(&b'#')) && !ident_byte(b, i) {
            // raw string r"..." or r#"..."#
            let mut j = i + 1;
            let mut hashes = 0;
            while b.get(j) == Some(&b'#') {
                hashes += 1;
                j += 1;
            }
            if b.get(j) != Some(&b'"') {
                out.push(c as char);
                i += 1;
                continue;
            }
            let close: Vec<u8> = std::iter::once(b'"').chain(std::iter::repeat_n(b'#', hashes)).collect();
            out.push(' ');
            i = j + 1;
            while i < b.len() && !b[i..].starts_with(&close) {
                blank(b[i], &mut out);
                i += 1;
            }
            for _ in 0..close.len().min(b.len() - i.min(b.len())) {
                out.push(' ');
            }
            i += close.len();
        } else if c == b'"' {
            out.push(' ');
            i += 1;
            while i < b.len() && b[i] != b'"' {
                if b[i] == b'\\' {
                    blank(b[i], &mut out);
                    i += 1;
                }
                if i < b.len() {
                    blank(b[i], &mut out);
                    i += 1;
                }
            }
            out.push(' ');
            i += 1;
        } else if c == b'\'' {
            // a character literal ('a', '\n', '\''), not a lifetime ('a)
            let lit = if b.get(i + 1) == Some(&b'\\') {
                b[i + 2..].iter().position(|&x| x == b'\'').map(|k| i + 2 + k)
            } else if b.get(i + 2) == Some(&b'\'') {
                Some(i + 2)
            } else {
                std::str::from_utf8(&b[i + 1..]).ok().and_then(|s| {
                    let ch = s.chars().next()?;
                    let n = ch.len_utf8();
                    (b.get(i + 1 + n) == Some(&b'\'') && n > 1).then_some(i + 1 + n)
                })
            };
            match lit {
                Some(end) => {
                    for _ in i..=end {
                        out.push(' ');
                    }
                    i = end + 1;
                }
                None => {
                    out.push('\'');
                    i += 1;
                }
            }
        } else {
            // copy one whole UTF-8 character
            let s = &text[i..];
            let ch = s.chars().next().unwrap();
            out.push(ch);
            i += ch.len_utf8();
        }
    }
    out
}

fn ident_byte(b: &[u8], i: usize) -> bool {
    i > 0 && (b[i - 1].is_ascii_alphanumeric() || b[i - 1] == b'_')
}

/// The first segments that follow a path start at byte `at` of `code` (just after `crate::` or
/// the last `super::`): one name, or every top-level name of a `{..}` group.
fn heads(code: &str, at: usize) -> Vec<String> {
    let rest = &code[at..];
    let rest = rest.trim_start();
    if let Some(group) = rest.strip_prefix('{') {
        let mut depth = 1;
        let mut names = Vec::new();
        let mut cur = String::new();
        let mut at_start = true;
        for ch in group.chars() {
            match ch {
                '{' => depth += 1,
                '}' => {
                    depth -= 1;
                    if depth == 0 {
                        break;
                    }
                }
                ',' if depth == 1 => {
                    at_start = true;
                    cur.clear();
                    continue;
                }
                _ => {}
            }
            if depth == 1 && at_start {
                if ch.is_alphanumeric() || ch == '_' {
                    cur.push(ch);
                } else if !cur.is_empty() {
                    names.push(std::mem::take(&mut cur));
                    at_start = false;
                }
            }
        }
        if at_start && !cur.is_empty() {
            names.push(cur);
        }
        names
    } else {
        let name: String = rest.chars().take_while(|c| c.is_alphanumeric() || *c == '_').collect();
        if name.is_empty() { vec![] } else { vec![name] }
    }
}

/// Every top-level module a file refers to: (line, module).
fn imports(path: &Path, text: &str) -> Vec<(usize, String)> {
    let code = code_only(text);
    let me = module_path(path);
    let line_of = |at: usize| code[..at].matches('\n').count() + 1;
    let mut out = Vec::new();
    let mut i = 0;
    while let Some(k) = code[i..].find("crate::") {
        let at = i + k;
        i = at + "crate::".len();
        if ident_byte(code.as_bytes(), at) {
            continue;
        }
        for h in heads(&code, i) {
            out.push((line_of(at), h));
        }
    }
    // super:: chains
    let mut i = 0;
    while let Some(k) = code[i..].find("super::") {
        let at = i + k;
        if ident_byte(code.as_bytes(), at) {
            i = at + 7;
            continue;
        }
        let mut n = 0;
        let mut j = at;
        while code[j..].starts_with("super::") {
            n += 1;
            j += "super::".len();
            j += code[j..].len() - code[j..].trim_start().len();
        }
        i = j;
        // `super` from a file's own items: src/a/b.rs is module a::b, so super:: is a.
        if n >= me.len() {
            let base = me.len() - n.min(me.len());
            if base == 0 {
                for h in heads(&code, j) {
                    out.push((line_of(at), h));
                }
            }
        }
    }
    out
}

/// The layer table of `src/lib.rs`: module → (layer index, layer name).
fn layer_table() -> BTreeMap<String, (usize, String)> {
    let lib = std::fs::read_to_string(src().join("lib.rs")).unwrap();
    let mut table = BTreeMap::new();
    let mut inside = false;
    let mut layer = 0;
    for line in lib.lines() {
        let Some(doc) = line.strip_prefix("//!") else { continue };
        let doc = doc.trim();
        if doc.starts_with("## ") {
            inside = doc == "## Layers";
            continue;
        }
        if !inside || !doc.starts_with('|') || doc.starts_with("|--") || doc.starts_with("| layer") {
            continue;
        }
        let cells: Vec<&str> = doc.trim_matches('|').split('|').map(str::trim).collect();
        assert!(cells.len() >= 2, "src/lib.rs, layer table: row `{doc}` has no module cell");
        for name in cells[1].split(',') {
            let name = name.trim().trim_matches('`').to_string();
            assert!(
                table.insert(name.clone(), (layer, cells[0].to_string())).is_none(),
                "src/lib.rs, layer table: `{name}` is in two layers"
            );
        }
        layer += 1;
    }
    assert!(layer >= 2, "src/lib.rs has no layer table (a `## Layers` section with a row per layer)");
    table
}

struct Graph {
    /// (from module, to module) → first (file, line) that makes the edge
    edges: BTreeMap<(String, String), (String, usize)>,
}

fn graph() -> (Graph, Vec<String>) {
    let mut files = Vec::new();
    rust_files(&src(), &mut files);
    let mut edges = BTreeMap::new();
    let mut units = BTreeSet::new();
    for f in &files {
        let mp = module_path(f);
        let Some(from) = mp.first().cloned() else { continue };
        if from == "main" {
            continue;
        }
        units.insert(from.clone());
        let text = std::fs::read_to_string(f).unwrap();
        for (line, to) in imports(f, &text) {
            if to == from || to == "self" || to == "super" {
                continue;
            }
            edges.entry((from.clone(), to)).or_insert((rel(f), line));
        }
    }
    (Graph { edges }, units.into_iter().collect())
}

fn allowed(file: &str, to: &str) -> bool {
    CORE_TO_BRIDGE.iter().chain(BRIDGE_UP).any(|&(f, t)| f == file && t == to)
}

#[test]
fn every_module_is_in_the_layer_table() {
    let table = layer_table();
    let (_, units) = graph();
    let missing: Vec<&String> = units.iter().filter(|u| !table.contains_key(*u)).collect();
    assert!(missing.is_empty(), "modules of src/ missing from the layer table in src/lib.rs: {missing:?}");
    let stale: Vec<&String> = table.keys().filter(|k| !units.contains(k)).collect();
    assert!(stale.is_empty(), "the layer table in src/lib.rs names modules src/ does not have: {stale:?}");
}

#[test]
fn no_import_from_a_lower_layer_to_a_higher_one() {
    let table = layer_table();
    let mut files = Vec::new();
    rust_files(&src(), &mut files);
    let mut bad = Vec::new();
    let mut used = BTreeSet::new();
    for f in &files {
        let mp = module_path(f);
        let Some(from) = mp.first() else { continue };
        let Some(&(lf, ref nf)) = table.get(from) else { continue };
        let text = std::fs::read_to_string(f).unwrap();
        for (line, to) in imports(f, &text) {
            let Some(&(lt, ref nt)) = table.get(&to) else { continue };
            if lt > lf {
                if allowed(&rel(f), &to) {
                    used.insert((rel(f), to.clone()));
                } else {
                    bad.push(format!("{}:{line}: `{from}` ({nf}) imports `{to}` ({nt})", rel(f)));
                }
            }
        }
    }
    assert!(bad.is_empty(), "imports from a lower layer to a higher one:\n{}", bad.join("\n"));
    let stale: Vec<_> = CORE_TO_BRIDGE
        .iter()
        .chain(BRIDGE_UP)
        .filter(|&&(f, t)| !used.contains(&(f.to_string(), t.to_string())))
        .collect();
    assert!(stale.is_empty(), "allowed exceptions that no longer occur (remove them): {stale:?}");
}

/// Strongly connected components of more than one module (Tarjan), each sorted.
fn cycles(units: &[String], edges: &BTreeSet<(String, String)>) -> Vec<Vec<String>> {
    struct T<'a> {
        adj: BTreeMap<&'a str, Vec<&'a str>>,
        index: BTreeMap<&'a str, usize>,
        low: BTreeMap<&'a str, usize>,
        stack: Vec<&'a str>,
        on: BTreeSet<&'a str>,
        next: usize,
        out: Vec<Vec<String>>,
    }
    fn visit<'a>(t: &mut T<'a>, v: &'a str) {
        t.index.insert(v, t.next);
        t.low.insert(v, t.next);
        t.next += 1;
        t.stack.push(v);
        t.on.insert(v);
        for w in t.adj.get(v).cloned().unwrap_or_default() {
            if !t.index.contains_key(w) {
                visit(t, w);
                let lw = t.low[w];
                let lv = t.low.get_mut(v).unwrap();
                *lv = (*lv).min(lw);
            } else if t.on.contains(w) {
                let iw = t.index[w];
                let lv = t.low.get_mut(v).unwrap();
                *lv = (*lv).min(iw);
            }
        }
        if t.low[v] == t.index[v] {
            let mut comp = Vec::new();
            loop {
                let w = t.stack.pop().unwrap();
                t.on.remove(w);
                comp.push(w.to_string());
                if w == v {
                    break;
                }
            }
            if comp.len() > 1 {
                comp.sort();
                t.out.push(comp);
            }
        }
    }
    let mut adj: BTreeMap<&str, Vec<&str>> = BTreeMap::new();
    for (a, b) in edges {
        adj.entry(a.as_str()).or_default().push(b.as_str());
    }
    let mut t = T {
        adj,
        index: BTreeMap::new(),
        low: BTreeMap::new(),
        stack: vec![],
        on: BTreeSet::new(),
        next: 0,
        out: vec![],
    };
    for u in units {
        if !t.index.contains_key(u.as_str()) {
            visit(&mut t, u.as_str());
        }
    }
    t.out
}

#[test]
fn no_cycle_between_modules() {
    let (g, units) = graph();
    let mut edges = BTreeSet::new();
    for ((a, b), (file, _)) in &g.edges {
        // The allowed upward imports are checked above; they would close a cycle with every
        // import that runs the right way, so they are left out here.
        if allowed(file, b) || CORE_CYCLES.iter().any(|&(x, y)| x == a && y == b) {
            continue;
        }
        edges.insert((a.clone(), b.clone()));
    }
    // an allowed edge may be made by a second file too
    let mut files = Vec::new();
    rust_files(&src(), &mut files);
    for f in &files {
        let mp = module_path(f);
        let Some(from) = mp.first() else { continue };
        let text = std::fs::read_to_string(f).unwrap();
        for (_, to) in imports(f, &text) {
            if &to != from
                && units.contains(&to)
                && !allowed(&rel(f), &to)
                && !CORE_CYCLES.iter().any(|&(x, y)| x == from && y == to)
            {
                edges.insert((from.clone(), to));
            }
        }
    }
    let stale: Vec<_> =
        CORE_CYCLES.iter().filter(|&&(a, b)| !g.edges.contains_key(&(a.to_string(), b.to_string()))).collect();
    assert!(stale.is_empty(), "CORE_CYCLES entries that no longer occur (remove them): {stale:?}");
    let found = cycles(&units, &edges);
    let mut msg = Vec::new();
    for comp in &found {
        msg.push(format!("cycle among {comp:?}:"));
        for (a, b) in &edges {
            if comp.contains(a) && comp.contains(b) {
                let (file, line) = g.edges.get(&(a.clone(), b.clone())).cloned().unwrap_or_default();
                msg.push(format!("  {a} -> {b}   (e.g. {file}:{line})"));
            }
        }
    }
    assert!(found.is_empty(), "the modules of src/ import each other in a circle:\n{}", msg.join("\n"));
}

#[test]
fn no_file_over_800_lines() {
    let mut files = Vec::new();
    rust_files(&src(), &mut files);
    let over: Vec<String> = files
        .iter()
        .filter_map(|f| {
            let n = std::fs::read_to_string(f).unwrap().lines().count();
            (n > MAX_FILE_LINES && !BRIDGE_FILES_OVER.contains(&rel(f).as_str()))
                .then(|| format!("{} ({n} lines)", rel(f)))
        })
        .collect();
    assert!(over.is_empty(), "source files over {MAX_FILE_LINES} lines:\n{}", over.join("\n"));
}

/// Every `fn` with a body: (name, first line, lines from the signature to the closing brace).
fn functions(text: &str) -> Vec<(String, usize, usize)> {
    let code = code_only(text);
    let b = code.as_bytes();
    let mut out = Vec::new();
    let mut i = 0;
    let line_of = |at: usize| code[..at].matches('\n').count() + 1;
    while let Some(k) = code[i..].find("fn ") {
        let at = i + k;
        i = at + 3;
        if ident_byte(b, at) {
            continue;
        }
        let name: String =
            code[at + 3..].trim_start().chars().take_while(|c| c.is_alphanumeric() || *c == '_').collect();
        if name.is_empty() {
            continue; // `fn(` types
        }
        // the body opens at the first `{` before any `;` (a declaration without a body)
        let mut j = at;
        let mut paren = 0i32;
        let open = loop {
            match b.get(j) {
                None => break None,
                Some(b'(') | Some(b'[') => paren += 1,
                Some(b')') | Some(b']') => paren -= 1,
                Some(b';') if paren == 0 => break None,
                Some(b'{') if paren == 0 => break Some(j),
                _ => {}
            }
            j += 1;
        };
        let Some(open) = open else { continue };
        let mut depth = 0;
        let mut end = open;
        for (q, &c) in b.iter().enumerate().skip(open) {
            if c == b'{' {
                depth += 1;
            } else if c == b'}' {
                depth -= 1;
                if depth == 0 {
                    end = q;
                    break;
                }
            }
        }
        let (l0, l1) = (line_of(at), line_of(end));
        out.push((name, l0, l1 - l0 + 1));
    }
    out
}

#[test]
fn no_function_over_150_lines() {
    let mut files = Vec::new();
    rust_files(&src(), &mut files);
    let mut over = Vec::new();
    for f in &files {
        let text = std::fs::read_to_string(f).unwrap();
        for (name, line, n) in functions(&text) {
            if n > MAX_FN_LINES && !BRIDGE_FNS_OVER.contains(&(rel(f).as_str(), name.as_str())) {
                over.push(format!("{}:{line}: fn {name} ({n} lines)", rel(f)));
            }
        }
    }
    assert!(over.is_empty(), "functions over {MAX_FN_LINES} lines:\n{}", over.join("\n"));
}

#[test]
fn no_too_many_arguments_allow() {
    let mut files = Vec::new();
    rust_files(&src(), &mut files);
    let hits: Vec<String> = files
        .iter()
        .filter(|f| code_only(&std::fs::read_to_string(f).unwrap()).contains("too_many_arguments"))
        .map(|f| rel(f))
        .collect();
    assert!(hits.is_empty(), "`#[allow(clippy::too_many_arguments)]` in: {hits:?}");
}

#[test]
fn the_parsers_see_what_they_should() {
    let p = src().join("a/b.rs");
    let text =
        "use crate::{x::y, z};\n// crate::c\nlet s = \"crate::d\";\nfn f() { super::super::q::r(); crate::w::v(); }\n";
    let got: Vec<String> = imports(&p, text).into_iter().map(|(_, m)| m).collect();
    assert_eq!(got, vec!["x", "z", "w", "q"]);
    let body = "fn a() {\n  let s = \"}\";\n  if x { y }\n}\nfn b();\n";
    assert_eq!(functions(body), vec![("a".to_string(), 1, 4)]);
}
