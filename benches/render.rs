//! Whole cases per second: the case runner (`fringe::harness::case::run::run_with`, every fidelity level
//! from one set of exact paths) on the paper's amplitude-division scene, Young's experiment
//! and the Airy plate (bounce count chosen from the tail bound). Throughput is in probe points.
//! And the picture of the performance target: `fringe::output::render::render` of the amplitude-division
//! scene (`figures/plate_amplitude_division.json`) at `vector` fidelity in white light with 81
//! wavelengths, 300 × 300 pixels (throughput in pixels; the 900 × 900 target is 9× the work):
//! as `fringe render` does it (the parallel-stack kernel, `fringe::output::stack_kernel`) and
//! with every pixel traced exactly (`render::render_with(.., PixelPath::Exact)`, `_exact`)
//! and by the kernel's complex reference (`PixelPath::KernelReference`, `_reference`: complex
//! fields, the sums through `Beats`, the same bits);
//! and the two pictures `fringe figures` renders for `fringe check` (the plate at 240 × 240,
//! 31 wavelengths, six shadings; Fig. 3's slits at 240 × 240), by their kernels and exactly.
//!
//! And where a pixel of that picture goes (`pixel` group, one thread, the middle row of the
//! 900 × 900 screen, 900 pixels): the exact trace of its arrivals (`render::arrivals_at`: plan
//! as the render plans it, path solve, carried rays, one-sided screen) against the 81-wavelength
//! beat-term batch of the traced rays, and the path solves alone (`path::solve` of the two
//! sequences that reach, R0 and T0 R1 T0; the rest of the trace is carrying the rays) (`Beats::set` + `Beats::weighted_sum` with the CIE
//! weights), so the split of a pixel's CPU time between tracing and the spectrum is measured,
//! not guessed.
//!
//! Run: `cargo bench -p fringe-benches --bench render`

use criterion::{Criterion, Throughput, criterion_group, criterion_main};
use fringe::Target;
use fringe::accumulate::fidelity::Fidelity;
use fringe::colour::{Illuminant, SpectralIntegrator, WavelengthGrid};
use fringe::harness::case::{build, load, run};
use fringe::output::render::{self, Request, Screen, Shading, Spectrum};
use fringe::trace::{self, beats, path};
use std::hint::black_box;
use std::path::Path;
use std::time::Duration;

fn bench(c: &mut Criterion) {
    // Case files are named from the repository root; `cargo bench` starts in `benches/`.
    std::env::set_current_dir(concat!(env!("CARGO_MANIFEST_DIR"), "/.."))
        .expect("the repository root");
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
    // The kernel's complex reference (complex fields, sums through `Beats`): what the real
    // arithmetic and the direct beat sums of issue #14 save, same pixels, same bits.
    group.bench_function("amplitude_division_300x300_81_vector_reference", |b| {
        b.iter(|| {
            black_box(
                render::render_with(black_box(&case), &req, render::PixelPath::KernelReference)
                    .expect("renders"),
            )
        })
    });
    group.bench_function("amplitude_division_300x300_81_vector_exact", |b| {
        b.iter(|| {
            black_box(
                render::render_with(black_box(&case), &req, render::PixelPath::Exact)
                    .expect("renders"),
            )
        })
    });
    // What `fringe figures` (and so `fringe check`) renders: the plate at 240 × 240 in white
    // light with 31 wavelengths at the six shadings of Figs. 5–7 (one kernel pass per pixel
    // for all six), and Fig. 3's slits at 240 × 240, monochrome (the kernel of line sources
    // without surfaces); each against every pixel traced exactly (`_exact`).
    let six = Request {
        screen: Screen::from_probe(&case.spec.probe, Some((240, 240))).expect("grid probe"),
        shadings: Fidelity::ALL
            .into_iter()
            .map(Shading::Level)
            .chain([Shading::UnpolarizedScalarJump])
            .collect(),
        spectrum: Spectrum::White(
            SpectralIntegrator::new(
                &WavelengthGrid::uniform(380e-9, 780e-9, 31).expect("31 samples"),
                Illuminant::D65,
            )
            .expect("CIE tables cover 380–780 nm"),
        ),
        progress: false,
    };
    let young = load::load(Path::new("figures/young_fig3.json")).expect("figure");
    let fig3 = Request {
        screen: Screen::from_probe(&young.spec.probe, Some((240, 240))).expect("grid probe"),
        shadings: vec![Shading::Level(Fidelity::Vector)],
        spectrum: Spectrum::CaseLight,
        progress: false,
    };
    group.throughput(Throughput::Elements(240 * 240));
    for (name, case, req) in [
        ("figures_plate_240x240_31_six_shadings", &case, &six),
        ("figures_young_240x240", &young, &fig3),
    ] {
        group.bench_function(name, |b| {
            b.iter(|| black_box(render::render(black_box(case), req).expect("renders")))
        });
        group.bench_function(format!("{name}_exact"), |b| {
            b.iter(|| {
                black_box(
                    render::render_with(black_box(case), req, render::PixelPath::Exact)
                        .expect("renders"),
                )
            })
        });
    }
    group.finish();
    pixel_split(c, &case);
}

/// The `pixel` group (module docs): trace versus spectrum of one row of the 900 × 900 picture.
fn pixel_split(c: &mut Criterion, case: &load::Case) {
    let mut group = c.benchmark_group("pixel");
    group
        .sample_size(10)
        .measurement_time(Duration::from_secs(5));
    let screen = Screen::from_probe(&case.spec.probe, Some((900, 900))).expect("grid probe");
    let g = screen.geometry;
    let integ = SpectralIntegrator::new(
        &WavelengthGrid::uniform(380e-9, 780e-9, 81).expect("81 samples"),
        Illuminant::D65,
    )
    .expect("CIE tables cover 380–780 nm");
    let lambdas = integ.lambdas_m().to_vec();
    let weights: Vec<[f64; 3]> = (0..lambdas.len())
        .map(|i| integ.sample_weights(i))
        .collect();
    let lambda = lambdas[lambdas.len() / 2];
    let built = build::build_scene(&case.spec.scene, &build::Overrides::default()).expect("scene");
    let optics = built.scene.optics(lambda).expect("optics");
    let settings = render::trace_settings(case, &built, lambda).expect("settings");
    // The render's plan targets: a 5 × 5 lattice of the screen's pixels.
    let pick = |n: usize, k: usize| k * (n - 1) / 4;
    let targets: Vec<_> = (0..25)
        .map(|k| g.position(pick(g.columns, k / 5), pick(g.rows, k % 5)))
        .collect();
    let row: Vec<_> = (0..g.columns)
        .map(|col| g.position(col, g.rows / 2))
        .collect();
    let plan = trace::plan(&built.scene, &optics, &targets, &settings.limits);
    let trace_row = || {
        row.iter()
            .map(|&p| {
                render::arrivals_at(
                    &built.scene,
                    &optics,
                    &plan,
                    p,
                    &screen.observer(p),
                    &settings,
                    false,
                )
            })
            .collect::<Vec<_>>()
    };
    let rays: Vec<_> = trace_row().iter().map(|a| beats::vector_rays(a)).collect();
    assert!(
        rays.iter().all(|r| r.len() == 4),
        "two beams × two channels"
    );
    group.throughput(Throughput::Elements(row.len() as u64));
    group.bench_function("trace_row_900_of_900x900", |b| {
        b.iter(|| black_box(trace_row()))
    });
    // The path solves alone (the plan's sequences that reach: R0 and T0 R1 T0; the others are
    // skipped by `cannot_reach` before any solve).
    let source = &built.scene.sources[0];
    let sequences: Vec<_> = plan.sequences[0]
        .sequences()
        .into_iter()
        .filter(|seq| {
            !path::cannot_reach(&built.scene, source.emitter, seq, &Target::Point(row[0]))
        })
        .collect();
    assert_eq!(sequences.len(), 2, "R0 and T0 R1 T0");
    group.bench_function("solve_row_900_of_900x900", |b| {
        b.iter(|| {
            for &p in &row {
                for seq in &sequences {
                    let solved = path::solve(
                        &built.scene,
                        &optics,
                        source.emitter,
                        seq,
                        Target::Point(p),
                        &settings.solve,
                    );
                    black_box(solved.expect("both beams reach every pixel"));
                }
            }
        })
    });
    let mut bt = beats::Beats::default();
    let mut acc = fringe::Accumulator::default();
    group.bench_function("beats_81_row_900_of_900x900", |b| {
        b.iter(|| {
            let mut sum = [0.0; 3];
            for r in &rays {
                bt.set(r);
                let w = bt.weighted_sum(&lambdas, &weights, &mut acc);
                for c in 0..3 {
                    sum[c] += w[c];
                }
            }
            black_box(sum)
        })
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
