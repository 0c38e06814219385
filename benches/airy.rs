//! The Airy plate to a requested error bound: the cost of one far-field point (sequence
//! discovery with `fringe::trace::plan`, then every reflected order traced exactly with
//! `fringe::trace::arrivals`, both polarized models and the failure list, as `fringe check`
//! does) for a plane wave on a free-standing plate (n = 1.5, 2 µm, λ = 550 nm, unpolarized) at
//! 85°, where |r21 r23| is large.
//!
//! * `airy/bound/ε`: the bounce count chosen from the tail bound ε (N reflected orders with
//!   |t12 t21 r23| |r21 r23|^{N−1}/(1 − |r21 r23|) ≤ ε, m = 2N + 1 internal reflections), so N
//!   grows like log(1/ε)/log(1/|r21 r23|). Throughput is in reflected orders: constant
//!   orders/s means the cost grows like N.
//! * `airy/walk/m` and `airy/one_by_one/m`: a fixed budget of m internal reflections, the
//!   far-field walk (each shared beginning traced once, O(m)) against tracing every order from
//!   the source (`share_beginnings: false`, O(m²)).
//!
//! * `airy/spectrum/...`: a traced Airy spectrum, 401 wavelengths (400–800 nm) of a plane wave
//!   on a free-standing plate (n = 1.7, 3.217 µm, 35°, unpolarized), orders from the tail
//!   bound ε = 1e-12 at the middle wavelength, `vector`; throughput in spectral points.
//!   `traced_once`: one trace, then `Beats::intensities` (one 401-λ phasor batch per distinct
//!   ray phase, shared by the rays of the source's channels along one order;
//!   the test `beats::spectrum_traced_once_matches_airy_and_per_wavelength_traces` checks it
//!   against Airy to 1e-12). `per_wavelength`: a trace at every wavelength (what a dispersive
//!   plate needs), for the constant plate and for N-BK7 (Sellmeier); `bk7_round_trips`: the
//!   N-BK7 spectrum by `trace::round_trips::spectrum` (traced once by round trips, swept over
//!   the wavelengths by `trace::dispersive_sweep`). `traced_once_2t`: 16
//!   such spectra (angles 20°–50°) on a 2-thread pool.
//!
//! Run: `cargo bench -p fringe-benches --bench airy`

#[path = "../tests/suite/support/airy_plate.rs"]
mod airy_plate;

use airy_plate::{airy_plate, airy_plate_of};
use criterion::{BenchmarkId, Criterion, Throughput, criterion_group, criterion_main};
use fringe::harness::analytic::plate::{Film, Pol};
use fringe::optics::material::{Dispersion, Medium};
use fringe::scene::Scene;
use fringe::trace::beats::{Beats, vector_rays};
use fringe::trace::path::{EnumerationLimits, Target};
use fringe::trace::{self, TraceSettings, round_trips};
use glam::DVec3;
use std::hint::black_box;
use std::time::Duration;

const LAMBDA: f64 = 550e-9;
const THETA_DEG: f64 = 85.0;

/// Settings for `m` internal reflections (the case runner's event budget).
fn settings(m: usize, share_beginnings: bool) -> TraceSettings {
    TraceSettings {
        limits: EnumerationLimits {
            max_internal_reflections: m,
            max_events: 2 * m + 8,
        },
        share_beginnings,
        ..TraceSettings::default()
    }
}

/// One far-field point, as the case runner traces it; returns the number of arrivals.
fn point(scene: &Scene, target: &Target, st: &TraceSettings) -> usize {
    let optics = scene.optics(LAMBDA).expect("constant indices");
    let plan = trace::plan(scene, &optics, &[DVec3::new(0.0, 0.0, 0.001)], &st.limits);
    trace::arrivals(scene, &optics, &plan, target, st).0.len()
}

fn bench(c: &mut Criterion) {
    let (scene, target) = airy_plate(THETA_DEG.to_radians());
    let film = Film {
        n1: 1.0,
        n2: 1.5,
        n3: 1.0,
        thickness_m: 2e-6,
    };
    let cos1 = THETA_DEG.to_radians().cos();
    let mut group = c.benchmark_group("airy/bound");
    group
        .sample_size(20)
        .measurement_time(Duration::from_secs(3));
    for eps in [1e-4, 1e-7, 1e-10, 1e-13] {
        let orders = [Pol::S, Pol::P]
            .map(|p| film.orders_for_bound(cos1, LAMBDA, p, eps))
            .into_iter()
            .max()
            .unwrap();
        let st = settings(2 * orders + 1, true);
        // Orders 0..=N + 1 arrive (m = 2N + 1 admits one more), one ray per channel each (an
        // unpolarized source has three dipole channels).
        let arrived = point(&scene, &target, &st);
        assert_eq!(
            arrived,
            scene.sources[0].channels().len() * (orders + 2),
            "every order within the budget arrives"
        );
        group.throughput(Throughput::Elements(orders as u64));
        eprintln!(
            "airy/bound/{eps:.0e}: {orders} reflected orders, m = {} internal reflections",
            2 * orders + 1
        );
        group.bench_with_input(
            BenchmarkId::from_parameter(format!("{eps:.0e}")),
            &st,
            |b, st| b.iter(|| black_box(point(&scene, &target, black_box(st)))),
        );
    }
    group.finish();

    let mut group = c.benchmark_group("airy");
    group
        .sample_size(10)
        .measurement_time(Duration::from_secs(3));
    for m in [64usize, 256, 1024, 2000] {
        group.throughput(Throughput::Elements(m as u64));
        for (name, share) in [("walk", true), ("one_by_one", false)] {
            if !share && m > 1024 {
                continue; // about a second per point: the trend is clear by then
            }
            let st = settings(m, share);
            group.bench_with_input(BenchmarkId::new(name, m), &st, |b, st| {
                b.iter(|| black_box(point(&scene, &target, black_box(st))))
            });
        }
    }
    group.finish();
}

/// Orders and settings for the tail bound ε = 1e-12 of a plate of index `n` at `theta`.
fn spectrum_settings(theta: f64, n: f64, thickness_m: f64, lambda_m: f64) -> TraceSettings {
    let film = Film {
        n1: 1.0,
        n2: n,
        n3: 1.0,
        thickness_m,
    };
    let orders = [Pol::S, Pol::P]
        .map(|p| film.orders_for_bound(theta.cos(), lambda_m, p, 1e-12))
        .into_iter()
        .max()
        .unwrap();
    settings(2 * orders + 1, true)
}

/// One traced-once spectrum into `out`.
fn spectrum_once(
    scene: &Scene,
    target: &Target,
    st: &TraceSettings,
    lambdas: &[f64],
    beats: &mut Beats,
    out: &mut [f64],
) {
    let optics = scene.optics(lambdas[lambdas.len() / 2]).expect("indices");
    let plan = trace::plan(scene, &optics, &[DVec3::new(0.0, 0.0, 0.001)], &st.limits);
    let arrivals = trace::arrivals(scene, &optics, &plan, target, st).0;
    beats.set(&vector_rays(&arrivals));
    beats.intensities(lambdas, out);
}

fn bench_spectrum(c: &mut Criterion) {
    const D: f64 = 3.217e-6;
    let theta = 35f64.to_radians();
    let lambdas: Vec<f64> = (0..401).map(|i| 400e-9 + 1e-9 * i as f64).collect();
    let mid = lambdas[200];
    let st = spectrum_settings(theta, 1.7, D, mid);
    eprintln!(
        "airy/spectrum: m = {} internal reflections for ε = 1e-12",
        st.limits.max_internal_reflections
    );
    let (scene, target) = airy_plate_of(theta, Medium::constant("glass", 1.7), D);
    let bk7 = Medium {
        name: "N-BK7".into(),
        dispersion: Dispersion::bk7(),
    };
    let n_bk7 = bk7.index(mid).unwrap();
    let st_bk7 = spectrum_settings(theta, n_bk7, D, mid);
    let (scene_bk7, target_bk7) = airy_plate_of(theta, bk7, D);
    let mut group = c.benchmark_group("airy/spectrum");
    group
        .sample_size(10)
        .measurement_time(Duration::from_secs(3));
    group.throughput(Throughput::Elements(lambdas.len() as u64));
    let mut beats = Beats::default();
    let mut out = vec![0.0; lambdas.len()];
    group.bench_function("traced_once", |b| {
        b.iter(|| {
            spectrum_once(&scene, &target, &st, &lambdas, &mut beats, &mut out);
            black_box(&out);
        })
    });
    let per_wavelength = |scene: &Scene, target: &Target, st: &TraceSettings| -> f64 {
        lambdas
            .iter()
            .map(|&l| {
                let optics = scene.optics(l).expect("indices");
                let plan = trace::plan(scene, &optics, &[DVec3::new(0.0, 0.0, 0.001)], &st.limits);
                let arr = trace::arrivals(scene, &optics, &plan, target, st).0;
                trace::intensity(&arr, fringe::accumulate::fidelity::Fidelity::Vector)
            })
            .sum()
    };
    group.bench_function("per_wavelength", |b| {
        b.iter(|| black_box(per_wavelength(&scene, &target, &st)))
    });
    group.bench_function("bk7_per_wavelength", |b| {
        b.iter(|| black_box(per_wavelength(&scene_bk7, &target_bk7, &st_bk7)))
    });
    group.bench_function("bk7_round_trips", |b| {
        b.iter(|| {
            round_trips::spectrum(
                &scene_bk7,
                &[DVec3::new(0.0, 0.0, 0.001)],
                &target_bk7,
                &st_bk7,
                &lambdas,
                &mut beats,
                &mut out,
            )
            .expect("indices");
            black_box(&out);
        })
    });
    // 16 spectra (angles 20°–50°) on two threads.
    let spectra: Vec<(Scene, Target, TraceSettings)> = (0..16)
        .map(|k| {
            let th = (20.0 + 2.0 * k as f64).to_radians();
            let (s, t) = airy_plate_of(th, Medium::constant("glass", 1.7), D);
            (s, t, spectrum_settings(th, 1.7, D, mid))
        })
        .collect();
    let pool = rayon::ThreadPoolBuilder::new()
        .num_threads(2)
        .build()
        .expect("rayon pool");
    group.throughput(Throughput::Elements(16 * lambdas.len() as u64));
    group.bench_function("traced_once_2t_16_spectra", |b| {
        b.iter(|| {
            use rayon::prelude::*;
            pool.install(|| {
                spectra
                    .par_iter()
                    .map_init(
                        || (Beats::default(), vec![0.0; lambdas.len()]),
                        |(beats, out), (s, t, st)| {
                            spectrum_once(s, t, st, &lambdas, beats, out);
                            out[0]
                        },
                    )
                    .sum::<f64>()
            })
        })
    });
    group.finish();
}

criterion_group! {
    name = benches;
    // No plots: criterion's plotting needs system fonts this machine does not have.
    config = Criterion::default().without_plots();
    targets = bench, bench_spectrum
}
criterion_main!(benches);
