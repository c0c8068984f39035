//! `--set KEY=VALUE` overrides, applied to the case's text (its layout and comments kept), so an
//! override is validated exactly like the file (`docs/reference/cases.md`).

use crate::error::{Result, input};

/// The case text with `--set a.b.c=value` overrides applied (value parsed as TOML, else taken as
/// a string), keeping the file's layout and comments; a changed value is marked with a comment
/// `# set by --set (was …)`. Arrays of tables are indexed by number or by their `name`:
/// `material.loose_sand.pmin_pa=0`.
pub fn apply_sets(text: &str, sets: &[String]) -> Result<String> {
    apply_sets_by(text, sets, "--set")
}

/// [`apply_sets`] with the mark naming the flag that made the change (`# set by --end-time (was
/// …)`, `# set by resume --end-time (was …)`); errors still name the override as `--set`.
pub fn apply_sets_by(text: &str, sets: &[String], by: &str) -> Result<String> {
    if sets.is_empty() {
        return Ok(text.to_string());
    }
    let mut doc: toml_edit::DocumentMut = text.parse().map_err(|e| input(format!("{e}")))?;
    for s in sets {
        apply_set(&mut doc, s, by)?;
    }
    Ok(doc.to_string())
}

fn apply_set(doc: &mut toml_edit::DocumentMut, s: &str, by: &str) -> Result<()> {
    use toml_edit::Item;
    let (key, val) = s.split_once('=').ok_or_else(|| input(format!("--set {}: expected key=value", shown(s))))?;
    let key = key.trim();
    let ks = shown(key);
    let mut parsed: toml_edit::Value = match format!("v = {val}").parse::<toml_edit::DocumentMut>() {
        Ok(d) => match d.get("v").and_then(|v| v.as_value()) {
            Some(v) => v.clone(),
            None => toml_edit::Value::from(val),
        },
        Err(_) => toml_edit::Value::from(val),
    };
    if key.is_empty() || key.split('.').any(|p| p.is_empty()) {
        return Err(input(format!("--set {}: an empty key", shown(s))));
    }
    let parts: Vec<&str> = key.split('.').collect();
    let mut cur: &mut Item = doc.as_item_mut();
    // inside an inline table or an array (`eos = { c_ms = 1440.0 }`) a comment cannot follow the
    // value: it is replaced unmarked (case.toml's header lists every override)
    let mut inline = false;
    for part in parts {
        inline |= matches!(&*cur, Item::Value(_));
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
                    pos.ok_or_else(|| input(format!("--set {ks}: no entry named `{}`", shown(part))))?
                }
            };
            if idx >= len {
                return Err(input(format!("--set {ks}: index {idx} out of range ({len} entries)")));
            }
            cur.get_mut(idx).ok_or_else(|| input(format!("--set {ks}: index {idx} out of range")))?
        } else if cur.is_table_like() || cur.is_none() {
            cur.get_mut(part).ok_or_else(|| input(format!("--set {ks}: `{}` is not inside a table", shown(part))))?
        } else {
            return Err(input(format!("--set {ks}: `{}` is not inside a table", shown(part))));
        };
    }
    if let Some(old) = cur.as_value() {
        let mut was = old.clone();
        was.decor_mut().clear();
        let prefix = old.decor().prefix().and_then(|p| p.as_str()).unwrap_or(" ").to_string();
        parsed.decor_mut().set_prefix(prefix);
        if inline {
            let suffix = old.decor().suffix().and_then(|p| p.as_str()).unwrap_or("").to_string();
            parsed.decor_mut().set_suffix(suffix);
        } else {
            parsed.decor_mut().set_suffix(format!("  # set by {by} (was {})", shown(was.to_string().trim())));
        }
    } else if !cur.is_none() && !matches!(parsed, toml_edit::Value::InlineTable(_)) {
        return Err(input(format!("--set {ks}: replaces a table with a value")));
    } else if matches!(&*cur, Item::ArrayOfTables(_)) {
        return Err(input(format!(
            "--set {ks}: would replace every [[{ks}]] entry with one table: set an entry's keys (`{ks}.NAME.KEY=VALUE`, or `{ks}.0.KEY=VALUE`)"
        )));
    } else if matches!(&*cur, Item::Table(_)) {
        // a table given for a table (`region.soil={rho_kgm3=1500.0}`): its keys are set one by
        // one, the others kept (replacing the table would drop them, and an entry of an array
        // of tables cannot hold an inline value: it vanished from the case)
        let toml_edit::Value::InlineTable(t) = parsed else { unreachable!("checked above") };
        if t.is_empty() {
            return Err(input(format!("--set {ks}: an empty table sets nothing")));
        }
        for (k, v) in t.iter() {
            if k.contains(['.', '=']) || k.trim() != k || k.is_empty() {
                return Err(input(format!("--set {ks}: the key `{}` inside the table cannot be set", shown(k))));
            }
            let mut v = v.clone();
            v.decor_mut().clear();
            apply_set(doc, &format!("{key}.{k}={v}"), by)?;
        }
        return Ok(());
    }
    *cur = Item::Value(parsed);
    Ok(())
}

/// An override as error messages show it: on one line, cut to 120 characters.
pub(super) fn shown(s: &str) -> String {
    let one: String = s.chars().map(|c| if c.is_control() || super::validate::is_bidi(c) { ' ' } else { c }).collect();
    if one.chars().count() > 120 { format!("{}…", one.chars().take(120).collect::<String>()) } else { one }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A value inside an inline table (an EOS's constants) is replaced without a comment, which
    /// TOML does not allow there; a value of a table gets its `# set by --set` mark.
    #[test]
    fn a_value_inside_an_inline_table_is_replaced_and_the_text_still_parses() {
        let t =
            "[[material]]\nname = \"s\"\neos = { kind = \"soil\", c_ms = 1440.0, s = [1, 2] }\n[time]\nend_s = 1.0\n";
        let sets: Vec<String> = ["material.s.eos.c_ms=1500.0", "material.s.eos.s.1=3", "time.end_s=2.0"]
            .iter()
            .map(|s| s.to_string())
            .collect();
        let out = apply_sets(t, &sets).unwrap();
        let v: toml::Table = out.parse().unwrap_or_else(|e| panic!("{out}\n{e}"));
        assert_eq!(v["material"][0]["eos"]["c_ms"].as_float(), Some(1500.0));
        assert_eq!(v["material"][0]["eos"]["s"][1].as_integer(), Some(3));
        assert_eq!(v["time"]["end_s"].as_float(), Some(2.0));
        assert!(out.contains("end_s = 2.0  # set by --set (was 1.0)"), "{out}");
    }

    /// A table given for a table sets its keys and keeps the others (it used to replace the
    /// table: an entry of an array of tables vanished from the case); a table for a whole array
    /// of tables is refused.
    #[test]
    fn a_table_given_for_a_table_sets_its_keys() {
        let t = "[[region]]\nname = \"soil\"\nrho_kgm3 = 1450.0\nspacing_m = 0.01\n[[region]]\nname = \"charge\"\nrho_kgm3 = 1630.0\n[time]\nend_s = 1.0\n";
        let out = apply_sets(t, &["region.soil={rho_kgm3=1500.0, e_jkg=2.0}".to_string()]).unwrap();
        let v: toml::Table = out.parse().unwrap_or_else(|e| panic!("{out}\n{e}"));
        let r = v["region"].as_array().unwrap();
        assert_eq!(r.len(), 2, "{out}");
        assert_eq!(r[0]["rho_kgm3"].as_float(), Some(1500.0));
        assert_eq!(r[0]["e_jkg"].as_float(), Some(2.0));
        assert_eq!(r[0]["spacing_m"].as_float(), Some(0.01), "the other keys kept: {out}");
        let out = apply_sets(t, &["time={end_s=2.0}".to_string()]).unwrap();
        assert!(out.contains("end_s = 2.0  # set by --set (was 1.0)"), "{out}");
        let e = apply_sets(t, &["region={name=\"x\"}".to_string()]).unwrap_err().to_string();
        assert!(e.contains("would replace every [[region]] entry"), "{e}");
        assert!(apply_sets(t, &["region.soil={}".to_string()]).is_err());
    }
}
