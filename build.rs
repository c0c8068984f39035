//! Builds the legacy Fortran core (`fortran/`) into a static library with the `cmake` crate and
//! generates the Rust bindings of its C prototypes (`fortran/include/blastsph_legacy.h`) with
//! `bindgen`. Flags that matter for bit-for-bit parity with the Rust twins are set here:
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
    let bindings = bindgen::Builder::default()
        .header(header)
        .allowlist_function("sph_.*")
        .allowlist_var("SPH_.*")
        .parse_callbacks(Box::new(bindgen::CargoCallbacks::new()))
        .generate()
        .expect("bindgen could not read fortran/include/blastsph_legacy.h");
    let out = PathBuf::from(env::var("OUT_DIR").expect("OUT_DIR"));
    bindings.write_to_file(out.join("legacy_bindings.rs")).expect("could not write the generated bindings");
}
