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
//! Run: `cargo bench --bench airy`

#[path = "../tests/suite/support/airy_plate.rs"]
mod airy_plate;

use airy_plate::airy_plate;
use criterion::{BenchmarkId, Criterion, Throughput, criterion_group, criterion_main};
use fringe::analytic::plate::{Film, Pol};
use fringe::path::{EnumerationLimits, Target};
use fringe::scene::Scene;
use fringe::trace::{self, TraceSettings};
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
        // Orders 0..=N + 1 arrive (m = 2N + 1 admits one more), two channels each.
        let arrived = point(&scene, &target, &st);
        assert_eq!(
            arrived,
            2 * (orders + 2),
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

criterion_group! {
    name = benches;
    // No plots: criterion's plotting needs system fonts this machine does not have.
    config = Criterion::default().without_plots();
    targets = bench
}
criterion_main!(benches);
