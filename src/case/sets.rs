//! Loading a case: reading the file, applying the `--set KEY=VALUE` overrides to its text, and
//! attributing an error to the file or to the override that caused it.

use super::Case;
use crate::error::{Result, input};
use std::path::Path;

/// Reads a case file, applies `key=value` overrides, and parses it.
pub fn load(path: &Path, sets: &[String]) -> Result<Case> {
    let text = std::fs::read_to_string(path)
        .map_err(|e| input(format!("{}: cannot read the case file: {e}", path.display())))?;
    parse(&text, &path.display().to_string(), sets, path.file_stem().and_then(|s| s.to_str()))
}

/// Parses case text; `origin` names it in error messages. The `--set` overrides are applied to
/// the text ([`apply_sets`]); an error they cause names the override, not a line of the edited
/// text.
pub fn parse(text: &str, origin: &str, sets: &[String], stem: Option<&str>) -> Result<Case> {
    text.parse::<toml::Table>().map_err(|e| toml_error(origin, text, &e))?;
    let attempt = |k: usize| -> Result<Case> {
        let edited = apply_sets(text, &sets[..k])?;
        let mut case: Case = toml::from_str(&edited).map_err(|e| toml_error(origin, &edited, &e))?;
        if case.name.is_none() {
            case.name = Some(stem.unwrap_or("case").to_string());
        }
        case.validate()?;
        Ok(case)
    };
    match attempt(sets.len()) {
        Ok(c) => Ok(c),
        Err(e) if sets.is_empty() => Err(e),
        Err(e) => Err(blame(&e, sets, &attempt)),
    }
}

/// The error of a case with overrides, attributed: to the file when the file alone gives the same
/// error, else to the first override after which it appears.
fn blame(
    e: &crate::error::SphError,
    sets: &[String],
    attempt: &dyn Fn(usize) -> Result<Case>,
) -> crate::error::SphError {
    let msg = |e: &crate::error::SphError| -> String {
        // the message without a leading `origin:line: `
        let s = e.to_string();
        match s.split_once(": ") {
            Some((head, rest)) if head.rsplit(':').next().is_some_and(|l| l.parse::<usize>().is_ok()) => {
                rest.to_string()
            }
            _ => s,
        }
    };
    let want = msg(e);
    if let Err(e0) = attempt(0)
        && msg(&e0) == want
    {
        return e0;
    }
    for k in 1..=sets.len() {
        if let Err(ek) = attempt(k)
            && msg(&ek) == want
        {
            if want.starts_with("--set ") {
                return input(want);
            }
            return input(format!("--set {}: {want}", sets[k - 1]));
        }
    }
    input(format!("--set {}: {want}", sets.join(" --set ")))
}

fn toml_error(origin: &str, text: &str, e: &toml::de::Error) -> crate::error::SphError {
    let line = e.span().map(|s| text[..s.start.min(text.len())].matches('\n').count() + 1);
    let msg = e.message().replace('\n', " ");
    match line {
        Some(l) => input(format!("{origin}:{l}: {msg}")),
        None => input(format!("{origin}: {msg}")),
    }
}

/// The case text with `--set a.b.c=value` overrides applied (value parsed as TOML, else taken as
/// a string), keeping the file's layout and comments; a changed value is marked with a comment
/// `# set by --set (was …)`. Arrays of tables are indexed by number or by their `name`:
/// `material.loose_sand.pmin_pa=0`.
pub fn apply_sets(text: &str, sets: &[String]) -> Result<String> {
    if sets.is_empty() {
        return Ok(text.to_string());
    }
    let mut doc: toml_edit::DocumentMut = text.parse().map_err(|e| input(format!("{e}")))?;
    for s in sets {
        apply_set(&mut doc, s)?;
    }
    Ok(doc.to_string())
}

fn apply_set(doc: &mut toml_edit::DocumentMut, s: &str) -> Result<()> {
    use toml_edit::Item;
    let (key, val) = s.split_once('=').ok_or_else(|| input(format!("--set {s}: expected key=value")))?;
    let key = key.trim();
    let mut parsed: toml_edit::Value = match format!("v = {val}").parse::<toml_edit::DocumentMut>() {
        Ok(d) => match d.get("v").and_then(|v| v.as_value()) {
            Some(v) => v.clone(),
            None => toml_edit::Value::from(val),
        },
        Err(_) => toml_edit::Value::from(val),
    };
    if key.is_empty() || key.split('.').any(|p| p.is_empty()) {
        return Err(input(format!("--set {s}: an empty key")));
    }
    let parts: Vec<&str> = key.split('.').collect();
    let mut cur: &mut Item = doc.as_item_mut();
    for part in parts {
        let array_len = match &*cur {
            Item::ArrayOfTables(a) => Some(a.len()),
            Item::Value(toml_edit::Value::Array(a)) => Some(a.len()),
            _ => None,
        };
        cur = if let Some(len) = array_len {
            let idx = match part.parse::<usize>() {
                Ok(i) => i,
                Err(_) => {
                    let named = |t: Option<&str>| t == Some(part);
                    let pos = match &*cur {
                        Item::ArrayOfTables(a) => a.iter().position(|t| named(t.get("name").and_then(|n| n.as_str()))),
                        Item::Value(toml_edit::Value::Array(a)) => a.iter().position(|v| {
                            named(v.as_inline_table().and_then(|t| t.get("name")).and_then(|n| n.as_str()))
                        }),
                        _ => None,
                    };
                    pos.ok_or_else(|| input(format!("--set {key}: no entry named `{part}`")))?
                }
            };
            if idx >= len {
                return Err(input(format!("--set {key}: index {idx} out of range ({len} entries)")));
            }
            cur.get_mut(idx).ok_or_else(|| input(format!("--set {key}: index {idx} out of range")))?
        } else if cur.is_table_like() || cur.is_none() {
            cur.get_mut(part).ok_or_else(|| input(format!("--set {key}: `{part}` is not inside a table")))?
        } else {
            return Err(input(format!("--set {key}: `{part}` is not inside a table")));
        };
    }
    if let Some(old) = cur.as_value() {
        let mut was = old.clone();
        was.decor_mut().clear();
        let prefix = old.decor().prefix().and_then(|p| p.as_str()).unwrap_or(" ").to_string();
        parsed.decor_mut().set_prefix(prefix);
        parsed.decor_mut().set_suffix(format!("  # set by --set (was {})", was.to_string().trim()));
    } else if !cur.is_none() && !matches!(parsed, toml_edit::Value::InlineTable(_)) {
        return Err(input(format!("--set {key}: replaces a table with a value")));
    }
    *cur = Item::Value(parsed);
    Ok(())
}
