//! Complex Fresnel coefficients (P1–P6) per second: `fringe::optics::fresnel::fresnel` over a sweep of
//! incidence angles, outside TIR (air → glass), fully inside TIR (glass → air beyond the
//! critical angle) and a 0–90° sweep from glass that crosses the critical angle.
//!
//! Run: `cargo bench -p fringe-benches --bench fresnel`

use criterion::{Criterion, Throughput, criterion_group, criterion_main};
use fringe::optics::fresnel::{critical_angle, fresnel};
use std::hint::black_box;
use std::time::Duration;

const N: usize = 4096;

/// cos θi for N angles evenly spread over [lo, hi] (radians).
fn sweep(lo: f64, hi: f64) -> Vec<f64> {
    (0..N)
        .map(|k| (lo + (hi - lo) * k as f64 / (N - 1) as f64).cos())
        .collect()
}

fn bench(c: &mut Criterion) {
    let (glass, air) = (1.5, 1.0);
    let theta_c = critical_angle(glass, air).expect("glass → air has a critical angle");
    let half_pi = std::f64::consts::FRAC_PI_2;
    let cases = [
        (
            "air_to_glass_0_90deg_no_tir",
            air,
            glass,
            sweep(0.0, half_pi),
        ),
        (
            "glass_to_air_tir_only",
            glass,
            air,
            sweep(theta_c + 1e-9, half_pi),
        ),
        (
            "glass_to_air_0_90deg_mixed",
            glass,
            air,
            sweep(0.0, half_pi),
        ),
    ];
    let mut grp = c.benchmark_group("fresnel");
    grp.throughput(Throughput::Elements(N as u64));
    for (name, n1, n2, cosines) in &cases {
        let tir = cosines
            .iter()
            .filter(|&&ci| fresnel(*n1, *n2, ci).total_internal_reflection)
            .count();
        println!("{name}: {tir} of {N} angles under TIR");
        grp.bench_function(*name, |b| {
            b.iter(|| {
                let mut acc = num_complex::Complex64::default();
                for &ci in black_box(cosines) {
                    let f = fresnel(black_box(*n1), black_box(*n2), ci);
                    acc += f.r_s + f.r_p + f.t_s + f.t_p;
                }
                acc
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
