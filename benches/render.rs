//! Whole cases per second: the case runner (`fringe::harness::case::run::run_with`, every fidelity level
//! from one set of exact paths) on the paper's amplitude-division scene, Young's experiment
//! and the Airy plate (bounce count chosen from the tail bound). Throughput is in probe points.
//! And the picture of the performance target: `fringe::output::render::render` of the amplitude-division
//! scene (`figures/plate_amplitude_division.json`) at `vector` fidelity in white light with 81
//! wavelengths, 300 × 300 pixels (throughput in pixels; the 900 × 900 target is 9× the work).
//!
//! Run: `cargo bench -p fringe-benches --bench render`

use criterion::{Criterion, Throughput, criterion_group, criterion_main};
use fringe::accumulate::fidelity::Fidelity;
use fringe::colour::{Illuminant, SpectralIntegrator, WavelengthGrid};
use fringe::harness::case::{build, load, run};
use fringe::output::render::{self, Request, Screen, Shading, Spectrum};
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

    let mut group = c.benchmark_group("picture");
    group
        .sample_size(10)
        .measurement_time(Duration::from_secs(15));
    let case = load::load(Path::new("figures/plate_amplitude_division.json")).expect("figure");
    let (w, h) = (300, 300);
    let req = Request {
        screen: Screen::from_probe(&case.spec.probe, Some((w, h))).expect("grid probe"),
        shadings: vec![Shading::Level(Fidelity::Vector)],
        spectrum: Spectrum::White(
            SpectralIntegrator::new(
                &WavelengthGrid::uniform(380e-9, 780e-9, 81).expect("81 samples"),
                Illuminant::D65,
            )
            .expect("CIE tables cover 380–780 nm"),
        ),
        progress: false,
    };
    group.throughput(Throughput::Elements((w * h) as u64));
    group.bench_function("amplitude_division_300x300_81_vector", |b| {
        b.iter(|| black_box(render::render(black_box(&case), &req).expect("renders")))
    });
    group.finish();
}

criterion_group! {
    name = benches;
    // Criterion's own plots need a system font that CI machines lack.
    config = Criterion::default().without_plots();
    targets = bench
}
criterion_main!(benches);
