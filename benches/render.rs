//! Whole cases per second: the case runner (`fringe::case::run::run_with`, every fidelity level
//! from one set of exact paths) on the paper's amplitude-division scene, Young's experiment
//! and the Airy plate (bounce count chosen from the tail bound). Throughput is in probe points.
//!
//! Run: `cargo bench --bench render`

use criterion::{Criterion, Throughput, criterion_group, criterion_main};
use fringe::case::{build, load, run};
use std::hint::black_box;
use std::path::Path;
use std::time::Duration;

fn bench(c: &mut Criterion) {
    let mut group = c.benchmark_group("render");
    group
        .sample_size(10)
        .measurement_time(Duration::from_secs(5));
    for name in ["plate_two_beam_paper", "young_paper", "plate_airy_s"] {
        let case = load::load(Path::new(&format!("cases/{name}.json"))).expect("library case");
        let points = build::probe_points(&case.spec.probe).len();
        group.throughput(Throughput::Elements(points as u64));
        group.bench_function(name, |b| {
            b.iter(|| black_box(run::run_with(black_box(&case), false).expect("case runs")))
        });
    }
    group.finish();
}

criterion_group! {
    name = benches;
    // Criterion's own plots need a system font that CI machines lack.
    config = Criterion::default().without_plots();
    targets = bench
}
criterion_main!(benches);
