//! Exact point-to-point paths per second (`fringe::trace::path::solve`) through a plane-parallel
//! plate (n = 1.5, 1 mm, in air) from a point source 10 cm above it to screen points 10 cm
//! above it, along `[T top, R bottom, (R top, R bottom)^(k−1), T top]` for k = 1, 3, 9 bottom
//! reflections (2k − 1 internal reflections, 2k + 1 events). Each iteration solves the path to
//! a row of 16 screen points; throughput is in paths.
//!
//! Run: `cargo bench -p fringe-benches --bench path`

use criterion::{BenchmarkId, Criterion, Throughput, criterion_group, criterion_main};
use fringe::optics::material::Medium;
use fringe::scene::Scene;
use fringe::scene::source::{Emitter, Polarization, Source};
use fringe::trace::path::{Event, EventKind, SolveOptions, Target, solve};
use glam::DVec3;
use std::hint::black_box;
use std::time::Duration;

fn bench(c: &mut Criterion) {
    let mut scene = Scene::new(Medium::vacuum());
    let (top, bottom) = scene.add_plate(
        "plate",
        DVec3::ZERO,
        DVec3::Z,
        1e-3,
        Medium::vacuum(),
        Medium::constant("glass", 1.5),
        Medium::vacuum(),
    );
    let emitter = Emitter::Point {
        position: DVec3::new(0.0, 0.0, 0.1),
    };
    scene.sources.push(Source {
        name: "point".into(),
        emitter,
        polarization: Polarization::Linear {
            reference: DVec3::X,
            angle_rad: 0.0,
        },
        intensity: 1.0,
        coherence_group: 0,
        coherence_length_m: f64::INFINITY,
    });
    let optics = scene.optics(550e-9).expect("constant indices");
    let targets: Vec<Target> = (0..16)
        .map(|i| Target::Point(DVec3::new(0.01 + 0.005 * i as f64, 0.002 * i as f64, 0.1)))
        .collect();
    let opts = SolveOptions::default();
    let ev = |surface, kind| Event { surface, kind };
    let mut grp = c.benchmark_group("path/plate");
    grp.throughput(Throughput::Elements(targets.len() as u64));
    for k in [1usize, 3, 9] {
        let mut seq = vec![ev(top, EventKind::Refract), ev(bottom, EventKind::Reflect)];
        for _ in 1..k {
            seq.push(ev(top, EventKind::Reflect));
            seq.push(ev(bottom, EventKind::Reflect));
        }
        seq.push(ev(top, EventKind::Refract));
        // Every path must exist (a failing solve would make the bench meaningless).
        let mut iterations = 0;
        for t in &targets {
            let p = solve(&scene, &optics, emitter, &seq, *t, &opts)
                .unwrap_or_else(|e| panic!("k = {k}: no path to {t:?}: {e}"));
            iterations += p.iterations;
        }
        println!(
            "k = {k}: {} events, mean {:.1} Newton iterations per path",
            seq.len(),
            iterations as f64 / targets.len() as f64
        );
        grp.bench_function(BenchmarkId::new("bottom_reflections", k), |b| {
            b.iter(|| {
                let mut s = 0.0;
                for t in &targets {
                    let p = solve(&scene, &optics, emitter, black_box(&seq), *t, &opts).unwrap();
                    s += p.optical_path_m();
                }
                s
            })
        });
    }
    grp.finish();
}

criterion_group! {
    name = benches;
    config = Criterion::default()
        .without_plots()
        .sample_size(10)
        .warm_up_time(Duration::from_secs(1))
        .measurement_time(Duration::from_secs(3));
    targets = bench
}
criterion_main!(benches);
