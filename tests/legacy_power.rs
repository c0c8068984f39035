//! A legacy kernel that writes the cubic's q³ as a real power (`q**3.d0`, as codes in `real(rk)`
//! write `q**3._rk`): gfortran calls libm's pow for it, where it multiplies `q**3` out. The
//! compatibility item `real_power` makes the kernel's Rust twin do the same.

mod legacy_kit;
use legacy_kit::*;

/// The dual run of the variant's build with `--compat COMPAT` for 10 steps: its kernel's W row.
fn kernel_w(b: &std::path::Path, compat: &str, out: &str) -> serde_json::Value {
    let out = scratch(out);
    let args = ["dual", "shock_tube", "--legacy", b.to_str().unwrap(), "--compat", compat, "--steps", "10", "--out"];
    let o = blastsph(&[&args[..], &[out.to_str().unwrap()]].concat());
    let se = String::from_utf8_lossy(&o.stderr);
    assert!(matches!(o.status.code(), Some(0 | 4)), "dual --compat {compat}: {se}");
    let (_, rows) = report_rows(&out.join("dual_report.json"));
    row(&rows, "legacy.kernel", "w").clone()
}

#[test]
fn a_kernel_with_a_real_power_is_matched_by_the_item_real_power() {
    let d = variant_built("real_power", "kernel.f", |t| t.replace("q**3/2.", "q**3.d0/2."));
    let b = d.join("build");
    // the book's profile multiplies q³ out: W differs in the last bits for some pairs
    let book = kernel_w(&b, "liu-book", "real_power_book");
    assert!(book["out_of_tolerance"].as_u64().unwrap() > 0, "{book}");
    let ulp = book["max_ulp"].as_f64().unwrap();
    assert!(ulp > 0.0 && ulp < 16.0, "{book}");
    // with the item, every W at 0 ULP
    let pow = kernel_w(&b, "liu-book,real_power", "real_power_pow");
    assert!(pow["compared"].as_u64().unwrap() > 0, "{pow}");
    assert_eq!(pow["out_of_tolerance"].as_u64(), Some(0), "{pow}");
    assert_eq!(pow["max_ulp"].as_f64(), Some(0.0), "{pow}");
}
