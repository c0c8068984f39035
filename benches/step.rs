//! Criterion benchmarks of one rate evaluation (Liu's single_step: mirrors, search, kernel,
//! density rate, EOS, strength, forces, viscosity, penalty, smoothing) of the thesis's surface
//! blast S1 (`cases/surface_loose_tnt6.toml`, 10 000 particles) 50 steps after the charge is lit,
//! with every module in Rust and with every module in Fortran (both with the cell search).
//!
//! `cargo bench --bench step`. The whole-run comparison, with errors, is `blastsph bench`
//! (docs/performance.md); this isolates the per-step cost without output or time stepping.

use blastsph::case;
use blastsph::modules::Backend;
use blastsph::sim::{Overrides, Sim};
use criterion::{Criterion, criterion_group, criterion_main};
use std::path::Path;
use std::time::Duration;

fn blast(backend: Backend) -> Sim {
    let path = Path::new(env!("CARGO_MANIFEST_DIR")).join("cases/surface_loose_tnt6.toml");
    let c = case::load(&path, &[]).expect("the surface blast case loads");
    let ov = Overrides { backend: Some(backend), ..Overrides::default() };
    let mut sim = Sim::new(c, &ov).expect("the surface blast case builds");
    // the rates at t = 0 come first, as in the runner
    sim.rates();
    for _ in 0..50 {
        sim.step().expect("the first 50 steps of the surface blast are stable");
    }
    sim
}

fn rates(cr: &mut Criterion) {
    let mut g = cr.benchmark_group("surface_loose_tnt6 rates, 10k particles");
    g.sample_size(20).measurement_time(Duration::from_secs(5));
    for (name, b) in [("rust", Backend::Rust), ("fortran", Backend::Fortran)] {
        let mut sim = blast(b);
        g.bench_function(name, |bn| bn.iter(|| sim.rates()));
    }
    g.finish();
}

criterion_group!(benches, rates);
criterion_main!(benches);
