//! Docs that stay true.
//!
//! - Every shell command in the README and the tutorial (fenced ```sh blocks) runs against the
//!   built binary, in a temporary folder, on short end times, and succeeds.
//! - Every relative link in README.md and docs/ resolves to a file (and a heading, for `#anchor`).
//! - No sentence in README.md or docs/ is over 60 words (40 in the README), and the README is at
//!   most 120 lines.
//! - No issue numbers, work-history words or citations of files the repository does not hold, in
//!   README.md, docs/ and the case files.
//!
//! The rule for commands: `blastsph ARGS` and `cargo run --release -- ARGS` run the binary built
//! for this test. A command that installs system packages (`scripts/setup`, `apt-get`), needs
//! ParaView (`pvpython`, `xvfb-run`), builds or tests this crate (`cargo build`, `cargo test`: the test runs
//! inside them), gets the source (`git clone`, `cd`) or sets the shell's `PATH` (`export`) is
//! skipped. Any other command
//! fails the test, so a doc cannot hold a command this test silently ignores. Every `run` gets
//! `--end-time` of at most [`RUN_END_CAP_S`] (the doc's own when shorter), every `dual` at most
//! [`DUAL_STEPS_CAP`] steps, and `validate` and `bench` run only with `--dry-run`.

use std::path::{Path, PathBuf};
use std::process::Command;

/// The longest simulated time a doc's `run` is given here (s).
const RUN_END_CAP_S: f64 = 2.0e-5;
/// The most steps a doc's `dual` is given here.
const DUAL_STEPS_CAP: u64 = 3;

fn root() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR"))
}

fn read(p: &Path) -> String {
    std::fs::read_to_string(p).unwrap_or_else(|e| panic!("cannot read {}: {e}", p.display()))
}

/// README.md and every .md file under docs/, sorted.
fn doc_files() -> Vec<PathBuf> {
    fn walk(d: &Path, out: &mut Vec<PathBuf>) {
        for e in std::fs::read_dir(d).unwrap_or_else(|e| panic!("{}: {e}", d.display())).flatten() {
            let p = e.path();
            if p.is_dir() {
                walk(&p, out);
            } else if p.extension().and_then(|s| s.to_str()) == Some("md") {
                out.push(p);
            }
        }
    }
    let mut v = vec![root().join("README.md")];
    walk(&root().join("docs"), &mut v);
    v.sort();
    v
}

/// The case files, cases/ and its sub-folders.
fn case_files() -> Vec<PathBuf> {
    let mut v = Vec::new();
    for dir in ["cases", "cases/hard", "cases/verify"] {
        for e in std::fs::read_dir(root().join(dir)).expect("cases/").flatten() {
            let p = e.path();
            if p.extension().and_then(|s| s.to_str()) == Some("toml") {
                v.push(p);
            }
        }
    }
    v.sort();
    v
}

fn rel(p: &Path) -> String {
    p.strip_prefix(root()).unwrap_or(p).display().to_string()
}

// ---------------------------------------------------------------------------------------------
// Prose: the text outside code, cut into units (paragraphs, list items, table cells, headings),
// then into sentences.

/// The prose units of a Markdown text: fenced code is dropped; a blank line, a heading, a list
/// item and a table row end a unit; each table cell is a unit of its own.
fn prose_units(text: &str) -> Vec<String> {
    let mut out = Vec::new();
    let mut cur: Vec<&str> = Vec::new();
    let mut fence = false;
    let flush = |cur: &mut Vec<&str>, out: &mut Vec<String>| {
        if !cur.is_empty() {
            out.push(cur.join(" "));
            cur.clear();
        }
    };
    for line in text.lines() {
        let s = line.trim();
        if s.starts_with("```") {
            fence = !fence;
            flush(&mut cur, &mut out);
            continue;
        }
        if fence {
            continue;
        }
        if s.starts_with('|') {
            flush(&mut cur, &mut out);
            out.extend(s.trim_matches('|').split('|').map(str::to_string));
            continue;
        }
        if s.is_empty() || s.starts_with('#') {
            flush(&mut cur, &mut out);
            if !s.is_empty() {
                out.push(s.to_string());
            }
            continue;
        }
        if is_list_item(s) {
            flush(&mut cur, &mut out);
        }
        cur.push(s);
    }
    flush(&mut cur, &mut out);
    out
}

fn is_list_item(s: &str) -> bool {
    if s.starts_with("- ") || s.starts_with("* ") || s.starts_with("+ ") {
        return true;
    }
    let digits = s.bytes().take_while(u8::is_ascii_digit).count();
    digits > 0 && s[digits..].starts_with(". ")
}

/// Sentences of a unit: it ends at `.`, `!` or `?` followed by white space.
fn sentences(unit: &str) -> Vec<String> {
    let mut out = Vec::new();
    let mut cur = String::new();
    let mut chars = unit.chars().peekable();
    while let Some(c) = chars.next() {
        cur.push(c);
        if matches!(c, '.' | '!' | '?') && chars.peek().is_some_and(|n| n.is_whitespace()) {
            out.push(std::mem::take(&mut cur));
        }
    }
    if !cur.trim().is_empty() {
        out.push(cur);
    }
    out
}

/// Words: white-space separated tokens holding a letter or a digit.
fn words(s: &str) -> usize {
    s.split_whitespace().filter(|t| t.chars().any(char::is_alphanumeric)).count()
}

/// Sentences of `text` over `limit` words, each cut to its first words.
fn long_sentences(text: &str, limit: usize) -> Vec<String> {
    let mut v = Vec::new();
    for u in prose_units(text) {
        for s in sentences(&u) {
            let n = words(&s);
            if n > limit {
                let head: Vec<&str> = s.split_whitespace().take(12).collect();
                v.push(format!("{n} words: {} …", head.join(" ")));
            }
        }
    }
    v
}

#[test]
fn sentence_splitter_counts_what_a_reader_sees() {
    let text = "# Title\n\nOne two three. Four five\nsix seven!\n\n- an item\n- another item? Yes.\n\n\
                | a b c | d |\n|---|---|\n\n```sh\nnot prose at all\n```\n";
    let units = prose_units(text);
    assert_eq!(
        units,
        vec![
            "# Title",
            "One two three. Four five six seven!",
            "- an item",
            "- another item? Yes.",
            " a b c ",
            " d ",
            "---",
            "---"
        ]
    );
    assert_eq!(sentences("One two three. Four five six seven!").len(), 2);
    assert_eq!(words("a = b, `c` — 3.5 m"), 5);
    let long = format!("{}.", ["word"; 61].join(" "));
    assert_eq!(long_sentences(&long, 60).len(), 1);
    assert_eq!(long_sentences(&long, 61).len(), 0);
}

/// Files exempt from the prose rules: the legacy reference still has table cells and paragraphs
/// of 60 to 100 words. A listed file that passes every rule fails
/// [`exempt_files_still_need_their_exemption`], so the list only shrinks.
const EXEMPT: &[&str] = &[];

fn exempt(f: &Path) -> bool {
    EXEMPT.iter().any(|e| f.ends_with(e))
}

/// The prose rules' complaints about one file: long sentences and work-history words.
fn prose_faults(f: &Path) -> Vec<String> {
    let text = read(f);
    let limit = if f.ends_with("README.md") { 40 } else { 60 };
    let mut v: Vec<String> = long_sentences(&text, limit).into_iter().map(|s| format!("{}: {s}", rel(f))).collect();
    v.extend(history_words(&text).into_iter().map(|w| format!("{}: {w}", rel(f))));
    v
}

#[test]
fn no_sentence_over_sixty_words() {
    let mut bad = Vec::new();
    for f in doc_files().into_iter().filter(|f| !exempt(f)) {
        let limit = if f.ends_with("README.md") { 40 } else { 60 };
        for s in long_sentences(&read(&f), limit) {
            bad.push(format!("{}: {s}", rel(&f)));
        }
    }
    assert!(bad.is_empty(), "sentences over the limit (60 words; 40 in README.md):\n{}", bad.join("\n"));
}

#[test]
fn exempt_files_still_need_their_exemption() {
    for e in EXEMPT {
        let f = root().join(e);
        assert!(f.exists(), "{e} is exempt but does not exist: remove it from EXEMPT");
        assert!(!prose_faults(&f).is_empty(), "{e} now passes the prose rules: remove it from EXEMPT");
    }
}

#[test]
fn readme_is_at_most_120_lines() {
    let n = read(&root().join("README.md")).lines().count();
    assert!(n <= 120, "README.md has {n} lines, over 120");
}

// ---------------------------------------------------------------------------------------------
// Words a manual does not hold.

/// Work-history words and citations of files outside the repository, as lower-case substrings.
/// (Written in pieces, so that this file does not hold the words it forbids.)
const FORBIDDEN: &[&str] = &[
    concat!("this", " pass"),
    concat!("this", " round"),
    concat!("sess", "ion"),
    concat!("the ", "issue"),
    concat!("issue", "'s"),
];

/// The developers' guidance files outside the repository, as they are spelt (the project's own
/// docs/design.md is lower case and may be cited).
const OUTSIDE_FILES: &[&str] = &[concat!("DESIGN", ".md"), concat!("THESIS", ".md"), concat!("REFERENCES", ".md")];

/// The offending pieces of one text: a forbidden substring, an outside file, an issue number (the word, an optional
/// "s", spaces or "#", then a digit) or a date written YYYY-MM-DD.
fn history_words(text: &str) -> Vec<String> {
    let low = text.to_lowercase();
    let mut v: Vec<String> = FORBIDDEN.iter().filter(|w| low.contains(*w)).map(|w| format!("\"{w}\"")).collect();
    v.extend(OUTSIDE_FILES.iter().filter(|w| text.contains(*w)).map(|w| format!("\"{w}\"")));
    for (i, _) in low.match_indices("issue") {
        let rest = low[i + 5..].trim_start_matches('s').trim_start_matches([' ', '#']);
        if rest.starts_with(|c: char| c.is_ascii_digit()) {
            v.push(format!("\"{}\"", low[i..].chars().take(12).collect::<String>().trim()));
        }
    }
    let b = low.as_bytes();
    for i in 0..b.len().saturating_sub(9) {
        let d = |k: usize| b[i + k].is_ascii_digit();
        let edge = i == 0 || !b[i - 1].is_ascii_digit();
        if edge && d(0) && d(1) && d(2) && d(3) && b[i + 4] == b'-' && d(5) && d(6) && b[i + 7] == b'-' && d(8) && d(9)
        {
            v.push(format!("date {}", &low[i..i + 10]));
        }
    }
    v
}

#[test]
fn history_words_are_found() {
    assert_eq!(history_words(concat!("as iss", "ue 13 says")).len(), 1);
    assert_eq!(history_words(concat!("Iss", "ues #4 and 5")).len(), 1);
    assert_eq!(history_words(concat!("measured on 2026", "-12-06")).len(), 1);
    assert_eq!(history_words(concat!("see DESIGN", ".md")).len(), 1);
    assert!(history_words("see docs/design.md").is_empty());
    assert!(history_words("an issue of scale; 1.5-2.4 times; 10-20-30 cm").is_empty());
}

#[test]
fn no_issue_numbers_history_or_outside_files_in_docs_and_cases() {
    let mut bad = Vec::new();
    for f in doc_files().into_iter().filter(|f| !exempt(f)).chain(case_files()) {
        let text = read(&f);
        // in a case file only the comments are prose
        let text = if f.extension().is_some_and(|e| e == "toml") {
            text.lines().filter_map(|l| l.find('#').map(|i| &l[i..])).collect::<Vec<_>>().join("\n")
        } else {
            text
        };
        for w in history_words(&text) {
            bad.push(format!("{}: {w}", rel(&f)));
        }
    }
    assert!(bad.is_empty(), "work history or outside files named:\n{}", bad.join("\n"));
}

// ---------------------------------------------------------------------------------------------
// Links.

/// The targets of the inline links `[text](target)` of a Markdown text, outside fenced code.
fn link_targets(text: &str) -> Vec<String> {
    let mut v = Vec::new();
    let mut fence = false;
    for line in text.lines() {
        if line.trim_start().starts_with("```") {
            fence = !fence;
            continue;
        }
        if fence {
            continue;
        }
        let mut rest = line;
        while let Some(i) = rest.find("](") {
            let after = &rest[i + 2..];
            match after.find(')') {
                Some(j) => {
                    v.push(after[..j].trim().to_string());
                    rest = &after[j..];
                }
                None => break,
            }
        }
    }
    v
}

/// GitHub's anchor of a heading: lower case, punctuation dropped but `-` and `_`, spaces to `-`.
fn slug(heading: &str) -> String {
    heading
        .trim()
        .to_lowercase()
        .chars()
        .filter_map(|c| match c {
            ' ' => Some('-'),
            c if c.is_alphanumeric() || c == '-' || c == '_' => Some(c),
            _ => None,
        })
        .collect()
}

fn anchors(text: &str) -> Vec<String> {
    let mut fence = false;
    let mut v = Vec::new();
    for line in text.lines() {
        if line.trim_start().starts_with("```") {
            fence = !fence;
        } else if !fence && line.starts_with('#') {
            v.push(slug(line.trim_start_matches('#')));
        }
    }
    v
}

#[test]
fn every_relative_link_resolves() {
    assert_eq!(slug("RZ against 3D: the crater (a) `x`"), "rz-against-3d-the-crater-a-x");
    let mut bad = Vec::new();
    let mut n = 0;
    for f in doc_files() {
        let text = read(&f);
        for t in link_targets(&text) {
            if t.starts_with("http://") || t.starts_with("https://") || t.starts_with("mailto:") {
                continue;
            }
            n += 1;
            let (path, anchor) = match t.split_once('#') {
                Some((p, a)) => (p, Some(a)),
                None => (t.as_str(), None),
            };
            let target = if path.is_empty() { f.clone() } else { f.parent().unwrap().join(path) };
            if !target.exists() {
                bad.push(format!("{}: ({t}) names no file", rel(&f)));
                continue;
            }
            if let Some(a) = anchor
                && target.is_file()
                && !anchors(&read(&target)).iter().any(|h| h == a)
            {
                bad.push(format!("{}: ({t}) names no heading of {}", rel(&f), rel(&target)));
            }
        }
    }
    assert!(n > 20, "only {n} relative links found: is the link parser broken?");
    assert!(bad.is_empty(), "broken links:\n{}", bad.join("\n"));
}

// ---------------------------------------------------------------------------------------------
// Commands.

/// The command lines of the ```sh blocks of a Markdown text: a line ending in `\` joins the next,
/// `#` starts a comment, and `&&` separates commands.
fn sh_commands(text: &str) -> Vec<String> {
    let mut v = Vec::new();
    let mut inside = false;
    let mut pending = String::new();
    for line in text.lines() {
        let t = line.trim();
        if t.starts_with("```") {
            inside = !inside && t == "```sh";
            continue;
        }
        if !inside {
            continue;
        }
        let t = match t.find(" #") {
            Some(i) => &t[..i],
            None if t.starts_with('#') => "",
            None => t,
        };
        if let Some(head) = t.strip_suffix('\\') {
            pending.push_str(head);
            pending.push(' ');
            continue;
        }
        pending.push_str(t);
        for c in pending.split("&&") {
            if !c.trim().is_empty() {
                v.push(c.trim().to_string());
            }
        }
        pending.clear();
    }
    v
}

/// Shell words: white space separates, single and double quotes group.
fn shell_words(s: &str) -> Vec<String> {
    let mut v = Vec::new();
    let mut cur = String::new();
    let mut quote: Option<char> = None;
    let mut any = false;
    for c in s.chars() {
        match quote {
            Some(q) if c == q => quote = None,
            Some(_) => cur.push(c),
            None if c == '\'' || c == '"' => {
                quote = Some(c);
                any = true;
            }
            None if c.is_whitespace() => {
                if any || !cur.is_empty() {
                    v.push(std::mem::take(&mut cur));
                }
                any = false;
            }
            None => cur.push(c),
        }
    }
    if any || !cur.is_empty() {
        v.push(cur);
    }
    v
}

/// What the test does with one command: the blastsph arguments to run, or why it is skipped.
enum Plan {
    Run(Vec<String>),
    Skip(&'static str),
}

fn plan(cmd: &str) -> Plan {
    let w = shell_words(cmd);
    let args: Vec<String> = match w.first().map(String::as_str) {
        Some("blastsph") => w[1..].to_vec(),
        Some("cargo") if w.get(1).map(String::as_str) == Some("run") => match w.iter().position(|a| a == "--") {
            Some(i) => w[i + 1..].to_vec(),
            None => panic!("`{cmd}`: cargo run without `--` runs blastsph with no command"),
        },
        Some("cargo") if matches!(w.get(1).map(String::as_str), Some("test" | "build")) => {
            return Plan::Skip("builds or tests this crate");
        }
        Some("scripts/setup" | "apt-get" | "sudo") => return Plan::Skip("installs system packages"),
        Some("pvpython" | "xvfb-run") => return Plan::Skip("needs ParaView"),
        Some("git" | "cd") => return Plan::Skip("gets the source"),
        Some("export") => return Plan::Skip("sets the shell's PATH: the test runs the built binary by its path"),
        _ => panic!("`{cmd}`: a command this test does not know; add a rule for it"),
    };
    Plan::Run(shorten(args))
}

/// The rule for short runs (module docs).
fn shorten(mut a: Vec<String>) -> Vec<String> {
    let flag_value = |a: &[String], flag: &str| a.iter().position(|x| x == flag).map(|i| i + 1);
    match a.first().map(String::as_str) {
        Some("run") => match flag_value(&a, "--end-time") {
            Some(i) => {
                let t: f64 = a[i].parse().expect("--end-time value");
                a[i] = format!("{}", t.min(RUN_END_CAP_S));
            }
            None => a.extend(["--end-time".to_string(), format!("{RUN_END_CAP_S}")]),
        },
        Some("dual") => match flag_value(&a, "--steps") {
            Some(i) => {
                let n: u64 = a[i].parse().expect("--steps value");
                a[i] = n.min(DUAL_STEPS_CAP).to_string();
            }
            None => a.extend(["--steps".to_string(), DUAL_STEPS_CAP.to_string()]),
        },
        Some("validate" | "bench") if !a.iter().any(|x| x == "--dry-run") => a.push("--dry-run".to_string()),
        _ => {}
    }
    if matches!(a.first().map(String::as_str), Some("run" | "validate")) && !a.iter().any(|x| x == "--quiet") {
        a.push("--quiet".to_string());
    }
    a
}

#[test]
fn command_rules() {
    let c = sh_commands(
        "```sh\nscripts/setup && cargo run --release -- run cases/x.toml --out runs/x \\\n  && blastsph report runs/x  # a comment\n```\n```\nnot sh\n```\n",
    );
    assert_eq!(
        c,
        vec!["scripts/setup", "cargo run --release -- run cases/x.toml --out runs/x", "blastsph report runs/x"]
    );
    assert!(matches!(plan(&c[0]), Plan::Skip(_)));
    match plan(&c[1]) {
        Plan::Run(a) => assert_eq!(a, ["run", "cases/x.toml", "--out", "runs/x", "--end-time", "0.00002", "--quiet"]),
        Plan::Skip(_) => panic!("a run was skipped"),
    }
    match plan("blastsph dual shock_tube --steps 50 --set 'a=[1, 2]'") {
        Plan::Run(a) => assert_eq!(a, ["dual", "shock_tube", "--steps", "3", "--set", "a=[1, 2]"]),
        Plan::Skip(_) => panic!("a dual was skipped"),
    }
}

/// Runs the ```sh commands of one doc, in order, in one fresh folder that sees the repository's
/// cases/ (as a user in a clone does).
fn run_doc_commands(doc: &str) {
    let text = read(&root().join(doc));
    let cmds = sh_commands(&text);
    assert!(!cmds.is_empty(), "{doc} has no ```sh commands");
    let dir = tempfile::tempdir().expect("temp dir");
    std::os::unix::fs::symlink(root().join("cases"), dir.path().join("cases")).expect("link cases/");
    let mut ran = 0;
    for cmd in cmds {
        match plan(&cmd) {
            Plan::Skip(why) => eprintln!("{doc}: skipped ({why}): {cmd}"),
            Plan::Run(args) => {
                eprintln!("{doc}: blastsph {}", args.join(" "));
                let out = Command::new(env!("CARGO_BIN_EXE_blastsph"))
                    .args(&args)
                    .current_dir(dir.path())
                    .output()
                    .expect("cannot start blastsph");
                assert!(
                    out.status.success(),
                    "{doc}: `{cmd}` (run as `blastsph {}`) exited {:?}:\n{}",
                    args.join(" "),
                    out.status.code(),
                    String::from_utf8_lossy(&out.stderr)
                );
                ran += 1;
            }
        }
    }
    assert!(ran > 0, "{doc}: no blastsph command ran");
}

#[test]
fn readme_commands_run() {
    run_doc_commands("README.md");
}

#[test]
fn tutorial_commands_run() {
    run_doc_commands("docs/tutorial.md");
}

// ---------------------------------------------------------------------------------------------
// The command-line reference against the binary's own help.

fn help(args: &[&str]) -> String {
    let out =
        Command::new(env!("CARGO_BIN_EXE_blastsph")).args(args).arg("--help").output().expect("cannot start blastsph");
    assert!(out.status.success(), "blastsph {} --help failed", args.join(" "));
    String::from_utf8(out.stdout).expect("help is UTF-8")
}

/// The sub-commands a help text lists under `Commands:` (without `help`).
fn help_commands(text: &str) -> Vec<String> {
    text.lines()
        .skip_while(|l| !l.starts_with("Commands:"))
        .skip(1)
        .take_while(|l| !l.trim().is_empty())
        .filter_map(|l| l.split_whitespace().next().map(str::to_string))
        .filter(|c| c != "help")
        .collect()
}

/// The long flags a help text lists under `Options:` (without `--help` and `--version`).
fn help_flags(text: &str) -> Vec<String> {
    text.lines()
        .skip_while(|l| !l.starts_with("Options:"))
        .filter_map(|l| l.split_whitespace().find(|w| w.starts_with("--")).map(|w| w.trim_end_matches(',').to_string()))
        .filter(|f| f != "--help" && f != "--version")
        .collect()
}

#[test]
fn cli_reference_covers_every_command_and_flag() {
    let cli = read(&root().join("docs/reference/cli.md"));
    // the section of each command: from its heading to the next `## `
    let section = |cmd: &str| -> String {
        let head = format!("## `blastsph {cmd}`");
        let i = cli.find(&head).unwrap_or_else(|| panic!("docs/reference/cli.md has no section \"{head}\""));
        let rest = &cli[i + head.len()..];
        rest[..rest.find("\n## ").unwrap_or(rest.len())].to_string()
    };
    let mut missing = Vec::new();
    let top = help_commands(&help(&[]));
    assert!(top.len() >= 8, "blastsph --help lists only {top:?}");
    for cmd in &top {
        let sec = section(cmd.as_str());
        let subs = help_commands(&help(&[cmd.as_str()]));
        let mut helps = vec![(cmd.clone(), help(&[cmd.as_str()]))];
        for s in &subs {
            helps.push((format!("{cmd} {s}"), help(&[cmd.as_str(), s.as_str()])));
        }
        for (name, text) in helps {
            if name != *cmd && !sec.contains(&format!("blastsph {name}")) {
                missing.push(format!("`blastsph {name}` is not described in the section of `{cmd}`"));
            }
            for f in help_flags(&text) {
                if !sec.contains(&format!("`{f}")) && !sec.contains(&format!(" {f}")) {
                    missing.push(format!("`blastsph {name}` flag {f}"));
                }
            }
        }
    }
    assert!(missing.is_empty(), "docs/reference/cli.md misses:\n{}", missing.join("\n"));
}
