//! The random contributions of the accumulation benches (`accumulate.rs`, `cpu_rates.rs`): one
//! generator, so both measure the same data.

use fringe::accumulate::Contribution;
use num_complex::Complex64;

/// SplitMix64: a tiny seeded generator (no dependency needed).
pub struct SplitMix(pub u64);
impl SplitMix {
    pub fn next_u64(&mut self) -> u64 {
        self.0 = self.0.wrapping_add(0x9E37_79B9_7F4A_7C15);
        let mut z = self.0;
        z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
        z ^ (z >> 31)
    }
    /// Uniform in [0, 1).
    pub fn unit(&mut self) -> f64 {
        (self.next_u64() >> 11) as f64 * (1.0 / (1u64 << 53) as f64)
    }
}

/// T random contributions into groups 1..=G, and CSR offsets for P equal points.
pub fn data(t: usize, p: usize, g: u64, seed: u64) -> (Vec<Contribution>, Vec<usize>) {
    let mut r = SplitMix(seed);
    let contribs = (0..t)
        .map(|_| {
            let id = 1 + r.next_u64() % g;
            let phase = 1e6 * r.unit();
            let mut f = [Complex64::default(); 3];
            for c in &mut f {
                *c = Complex64::new(2.0 * r.unit() - 1.0, 2.0 * r.unit() - 1.0);
            }
            Contribution {
                coherence_id: id,
                phase_cycles: phase,
                field: f,
            }
        })
        .collect();
    let offsets = (0..=p).map(|k| k * t / p).collect();
    (contribs, offsets)
}
