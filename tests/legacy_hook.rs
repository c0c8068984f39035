//! The legacy-code bridge attaches to the core through one hook (`sim::Bridge`, `sim::Hook`):
//! the core's sources name no part of the bridge, a `[compat]` table without a bridge is refused
//! in one line, and with the bridge the compat stages enter the plan.

use blastsph::sim::{Overrides, Sim};
use std::path::Path;

/// Every `.rs` file under `dir`.
fn sources(dir: &Path, out: &mut Vec<std::path::PathBuf>) {
    for e in std::fs::read_dir(dir).unwrap() {
        let p = e.unwrap().path();
        if p.is_dir() {
            sources(&p, out);
        } else if p.extension().is_some_and(|x| x == "rs") {
            out.push(p);
        }
    }
}

#[test]
fn the_core_sources_name_no_part_of_the_bridge() {
    let root = Path::new(env!("CARGO_MANIFEST_DIR")).join("src");
    let mut files = Vec::new();
    for d in ["sim", "modules", "case", "state", "setup"] {
        sources(&root.join(d), &mut files);
    }
    files.push(root.join("param.rs"));
    files.push(root.join("dual.rs"));
    files.push(root.join("pairs.rs"));
    assert!(files.len() > 40, "{files:?}");
    let mut bad = Vec::new();
    for f in &files {
        let text = std::fs::read_to_string(f).unwrap();
        for (k, line) in text.lines().enumerate() {
            if line.contains("migration::") || line.contains("mod compat") {
                bad.push(format!("{}:{}: {line}", f.display(), k + 1));
            }
        }
    }
    assert!(bad.is_empty(), "the core names the bridge:\n{}", bad.join("\n"));
}

fn shock_tube_with(compat: &str) -> blastsph::case::Case {
    let path = Path::new(env!("CARGO_MANIFEST_DIR")).join("cases/shock_tube.toml");
    let text = std::fs::read_to_string(&path).unwrap();
    blastsph::case::parse(&format!("{text}\n{compat}\n"), "shock_tube.toml", &[], Some("shock_tube")).unwrap()
}

#[test]
fn a_compat_table_without_the_bridge_is_refused_in_one_line() {
    let c = shock_tube_with("[compat]\nprofile = \"liu-book\"");
    let e = Sim::new(c, &Overrides::default()).err().expect("refused").to_string();
    assert!(e.contains("[compat]") && e.contains("legacy bridge") && !e.contains('\n'), "{e}");
    // the same case without the table runs without the bridge
    assert!(Sim::new(shock_tube_with(""), &Overrides::default()).is_ok());
}

#[test]
fn with_the_bridge_the_compat_stages_enter_the_plan_and_bad_items_are_refused() {
    let ov = Overrides { bridge: Some(blastsph::migration::bridge(None, false)), ..Default::default() };
    let sim = Sim::new(shock_tube_with("[compat]\nprofile = \"liu-book\""), &ov).unwrap();
    let text = sim.plan.text();
    assert!(text.contains("[compat liu-book]"), "{text}");
    assert!(text.contains("compat"), "{text}");
    let plain = Sim::new(shock_tube_with(""), &ov).unwrap();
    assert!(!plain.plan.text().contains("[compat"));
    let e = Sim::new(shock_tube_with("[compat]\nkernal = true"), &ov).err().unwrap().to_string();
    assert!(e.contains("compat.kernal: no such compatibility item"), "{e}");
}
