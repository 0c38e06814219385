//! Baseline bench (temporary): the plain per-point Accumulator.
use criterion::{Criterion, Throughput, criterion_group, criterion_main};
use fringe::accumulate::{Accumulator, Contribution};
use num_complex::Complex64;
use std::hint::black_box;

struct SplitMix(u64);
impl SplitMix {
    fn next_u64(&mut self) -> u64 {
        self.0 = self.0.wrapping_add(0x9E37_79B9_7F4A_7C15);
        let mut z = self.0;
        z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
        z ^ (z >> 31)
    }
    fn unit(&mut self) -> f64 {
        (self.next_u64() >> 11) as f64 * (1.0 / (1u64 << 53) as f64)
    }
}

fn data(t: usize, g: u64, seed: u64) -> Vec<Contribution> {
    let mut r = SplitMix(seed);
    (0..t)
        .map(|_| {
            let id = 1 + r.next_u64() % g;
            let phase = 1e6 * r.unit();
            let mut f = [Complex64::default(); 3];
            for c in &mut f {
                *c = Complex64::new(2.0 * r.unit() - 1.0, 2.0 * r.unit() - 1.0);
            }
            Contribution { coherence_id: id, phase_cycles: phase, field: f }
        })
        .collect()
}

fn bench(c: &mut Criterion) {
    let (t, p, g) = (1 << 18, 1 << 12, 4u64);
    let d = data(t, g, 1);
    let per = t / p;
    let mut grp = c.benchmark_group("accumulate");
    grp.throughput(Throughput::Elements(t as u64));
    grp.sample_size(10);
    grp.measurement_time(std::time::Duration::from_secs(3));
    grp.bench_function("baseline_accumulator_1t", |b| {
        let mut out = vec![0.0; p];
        b.iter(|| {
            let mut acc = Accumulator::new();
            for (k, chunk) in d.chunks(per).enumerate() {
                acc.clear();
                for c in chunk {
                    acc.add(c);
                }
                out[k] = acc.intensity();
            }
            black_box(&out);
        })
    });
    grp.finish();
}

criterion_group!(benches, bench);
criterion_main!(benches);
