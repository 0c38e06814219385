//! The accumulation core at `vector` fidelity: phase (cycles) → phasor, 3D complex field,
//! grouped by coherence id, intensity per point.
//!
//! T contributions with random phases (0 … 10^6 cycles, i.e. up to 6·10^6 rad) and random
//! complex 3D fields into G coherence groups at P points (T/P per point, CSR layout); throughput
//! in contributions per second. Variants: the pre-optimisation core (libm `sin_cos` of the full
//! phase, linear group search) as a baseline; the per-point `Accumulator`; the batch API on one
//! thread and on a 2-thread rayon pool; the same on the column layout (`ContributionColumns`:
//! ids, phases and fields as three slices, `columns_*`); plain and compensated summation. Plus
//! a bare streaming read of the same bytes (the memory-bandwidth floor), and the phasor kernel
//! alone against `f64::sin_cos` (scalar calls and the batch `phasors_from_cycles`).
//!
//! The machine is shared (2 cores): run it when nothing else is busy, or the 2-thread numbers
//! measure the other load.
//!
//! Run: `CARGO_TARGET_DIR=/work/target-perf cargo bench -p fringe-benches --bench accumulate`

use criterion::{BenchmarkId, Criterion, Throughput, criterion_group, criterion_main};
use fringe::accumulate::columns::{
    ColumnKernel, ContributionColumns, accumulate_columns, accumulate_columns_par,
    accumulate_columns_using,
};
use fringe::accumulate::{
    Accumulator, Contribution, Summation, accumulate_points, accumulate_points_par,
    phasor_from_cycles, phasors_from_cycles,
};
use num_complex::Complex64;
use std::hint::black_box;
use std::time::Duration;

mod accumulation_data;
use accumulation_data::{SplitMix, data};

/// The core before optimisation (libm sin_cos of 2π·frac after `round`, linear group search,
/// plain sums), kept here as the baseline.
fn baseline_intensity(groups: &mut Vec<(u64, [Complex64; 3])>, cs: &[Contribution]) -> f64 {
    groups.clear();
    let mut incoherent = 0.0;
    for c in cs {
        if c.coherence_id == 0 {
            incoherent += c.field.iter().map(|e| e.norm_sqr()).sum::<f64>();
            continue;
        }
        let frac = c.phase_cycles - c.phase_cycles.round();
        let (s, co) = (std::f64::consts::TAU * frac).sin_cos();
        let ph = Complex64::new(co, s);
        let slot = match groups.iter().position(|(id, _)| *id == c.coherence_id) {
            Some(k) => k,
            None => {
                groups.push((c.coherence_id, [Complex64::default(); 3]));
                groups.len() - 1
            }
        };
        for k in 0..3 {
            groups[slot].1[k] += c.field[k] * ph;
        }
    }
    incoherent
        + groups
            .iter()
            .map(|(_, e)| e.iter().map(|c| c.norm_sqr()).sum::<f64>())
            .sum::<f64>()
}

fn pool(threads: usize) -> rayon::ThreadPool {
    rayon::ThreadPoolBuilder::new()
        .num_threads(threads)
        .build()
        .expect("rayon pool")
}

fn bench_phasor(c: &mut Criterion) {
    let n = 1 << 16;
    let mut r = SplitMix(7);
    let phases: Vec<f64> = (0..n).map(|_| 1e6 * r.unit()).collect();
    let mut grp = c.benchmark_group("phasor");
    grp.throughput(Throughput::Elements(n as u64));
    grp.bench_function("libm_sin_cos", |b| {
        b.iter(|| {
            let mut acc = Complex64::default();
            for &p in black_box(&phases) {
                let (s, co) = (std::f64::consts::TAU * (p - p.round())).sin_cos();
                acc += Complex64::new(co, s);
            }
            acc
        })
    });
    grp.bench_function("poly_cycles", |b| {
        b.iter(|| {
            let mut acc = Complex64::default();
            for &p in black_box(&phases) {
                acc += phasor_from_cycles(p);
            }
            acc
        })
    });
    grp.bench_function("poly_cycles_batch", |b| {
        let mut out = vec![Complex64::default(); n];
        b.iter(|| {
            phasors_from_cycles(black_box(&phases), &mut out);
            black_box(&out);
        })
    });
    grp.finish();
}

fn bench_accumulate(c: &mut Criterion) {
    let pool2 = pool(2);
    // (label, T, P, G): 64 contributions per point into 4 groups; streaming from memory
    // (64 MiB of contributions) and L3-resident (4 MiB).
    for (label, t, p, g) in [
        ("T1M_P16k_G4", 1usize << 20, 1usize << 14, 4u64),
        ("T64k_P1k_G4", 1 << 16, 1 << 10, 4),
    ] {
        let (d, offsets) = data(t, p, g, 1);
        let cols = ContributionColumns::from(&d[..]);
        let mut out = vec![0.0; p];
        let mut grp = c.benchmark_group(format!("accumulate/{label}"));
        grp.throughput(Throughput::Elements(t as u64));
        grp.bench_function("baseline_libm_plain_1t", |b| {
            let mut groups = Vec::new();
            b.iter(|| {
                for k in 0..p {
                    out[k] = baseline_intensity(&mut groups, &d[offsets[k]..offsets[k + 1]]);
                }
                black_box(&out);
            })
        });
        grp.bench_function("accumulator_add_compensated_1t", |b| {
            let mut acc = Accumulator::new();
            b.iter(|| {
                for k in 0..p {
                    acc.clear();
                    for c in &d[offsets[k]..offsets[k + 1]] {
                        acc.add(c);
                    }
                    out[k] = acc.intensity();
                }
                black_box(&out);
            })
        });
        for (name, s) in [
            ("plain", Summation::Plain),
            ("compensated", Summation::Compensated),
        ] {
            grp.bench_function(BenchmarkId::new("batch_1t", name), |b| {
                b.iter(|| {
                    accumulate_points(black_box(&d), &offsets, s, &mut out);
                    black_box(&out);
                })
            });
            grp.bench_function(BenchmarkId::new("batch_2t", name), |b| {
                b.iter(|| {
                    pool2.install(|| accumulate_points_par(black_box(&d), &offsets, s, &mut out));
                    black_box(&out);
                })
            });
            grp.bench_function(BenchmarkId::new("columns_1t", name), |b| {
                b.iter(|| {
                    accumulate_columns(black_box(&cols), &offsets, s, &mut out);
                    black_box(&out);
                })
            });
            // The AVX2 kernel on its own (`columns_1t` runs the AVX-512F one where the CPU has it).
            if ColumnKernel::Avx2.available() {
                grp.bench_function(BenchmarkId::new("columns_avx2_1t", name), |b| {
                    b.iter(|| {
                        let cols = black_box(&cols);
                        accumulate_columns_using(ColumnKernel::Avx2, cols, &offsets, s, &mut out);
                        black_box(&out);
                    })
                });
            }
            grp.bench_function(BenchmarkId::new("columns_2t", name), |b| {
                b.iter(|| {
                    pool2.install(|| {
                        accumulate_columns_par(black_box(&cols), &offsets, s, &mut out)
                    });
                    black_box(&out);
                })
            });
        }
        // The memory floor: read the same 64 bytes per contribution and nothing else.
        let words = accumulation_data::as_words(&d);
        grp.bench_function("stream_read_1t", |b| {
            b.iter(|| black_box(accumulation_data::stream_sum(black_box(words))))
        });
        grp.bench_function("stream_read_2t", |b| {
            b.iter(|| {
                pool2.install(|| black_box(accumulation_data::stream_sum_par(black_box(words))))
            })
        });
        grp.finish();
    }
}

criterion_group! {
    name = benches;
    config = Criterion::default()
        .without_plots()
        .sample_size(10)
        .warm_up_time(Duration::from_secs(1))
        .measurement_time(Duration::from_secs(3));
    targets = bench_phasor, bench_accumulate
}
criterion_main!(benches);
