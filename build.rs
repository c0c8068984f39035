//! Builds the legacy Fortran core (`fortran/`) into a static library with the `cmake` crate and
//! generates the Rust bindings of its C prototypes (`fortran/include/blastsph_legacy.h`) with
//! `bindgen`: one file per module, named from the Fortran file (`sph_<module>.f90` →
//! `$OUT_DIR/ffi_<module>.rs`, the prototypes `sph_<module>_*`), which the module's own FFI file
//! (`src/modules/<module>/ffi.rs`) includes; the named constants (`SPH_*`) go to
//! `$OUT_DIR/param.rs`. A new module needs nothing here: its `.f90` file names it.
//!
//! Flags that matter for bit-for-bit parity with the Rust twins are set here:
//! `-O2 -ffp-contract=off`, no `-ffast-math`, no `-march=native`.

use std::env;
use std::path::PathBuf;

fn main() {
    println!("cargo:rerun-if-changed=fortran");
    println!("cargo:rerun-if-changed=build.rs");

    let flags = "-O2 -ffp-contract=off -fno-fast-math -std=f2008 -fimplicit-none -Wall -Wno-unused-dummy-argument -Wno-compare-reals";
    let dst = cmake::Config::new("fortran")
        .profile("Release")
        .define("CMAKE_Fortran_FLAGS_RELEASE", flags)
        .define("CMAKE_Fortran_FLAGS_DEBUG", flags)
        .define("CMAKE_POSITION_INDEPENDENT_CODE", "ON")
        .build();
    println!("cargo:rustc-link-search=native={}/lib", dst.display());
    println!("cargo:rustc-link-lib=static=blastsph_legacy");
    println!("cargo:rustc-link-lib=dylib=gfortran");

    let header = "fortran/include/blastsph_legacy.h";
    let out = PathBuf::from(env::var("OUT_DIR").expect("OUT_DIR"));
    let base = || bindgen::Builder::default().header(header).parse_callbacks(Box::new(bindgen::CargoCallbacks::new()));
    base()
        .allowlist_var("SPH_.*")
        .generate()
        .expect("bindgen could not read fortran/include/blastsph_legacy.h")
        .write_to_file(out.join("param.rs"))
        .expect("could not write the generated constants");
    let mut modules: Vec<String> = std::fs::read_dir("fortran/src")
        .expect("fortran/src")
        .filter_map(|e| e.ok())
        .filter_map(|e| e.file_name().into_string().ok())
        .filter_map(|f| f.strip_prefix("sph_").and_then(|f| f.strip_suffix(".f90")).map(str::to_string))
        .filter(|m| m != "param")
        .collect();
    modules.sort();
    for m in &modules {
        base()
            .allowlist_function(format!("sph_{m}_.*"))
            .generate()
            .unwrap_or_else(|e| panic!("bindgen, module {m}: {e}"))
            .write_to_file(out.join(format!("ffi_{m}.rs")))
            .expect("could not write the generated bindings");
    }
}
