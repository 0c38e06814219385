//! The random contributions of the accumulation benches (`accumulate.rs`, `cpu_rates.rs`): one
//! generator, so both measure the same data.

use fringe::accumulate::Contribution;
use num_complex::Complex64;
use rayon::prelude::*;

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

/// The bytes of the contributions as 64-bit words (8 per contribution: id, phase, 6 field
/// components), for the streaming-read floor.
pub fn as_words(d: &[Contribution]) -> &[u64] {
    // Contribution is a u64, an f64 and three Complex64 (#[repr(C)] pairs of f64): 64 bytes,
    // 8-byte aligned, no padding (checked here); every bit pattern is a valid u64.
    assert_eq!(std::mem::size_of::<Contribution>(), 64);
    // SAFETY: the slice covers exactly the bytes of `d` (len·64), aligned for u64, and lives as
    // long as `d`.
    unsafe { std::slice::from_raw_parts(d.as_ptr().cast::<u64>(), d.len() * 8) }
}

/// A bare streaming read: the wrapping sum of every word (8 independent lanes, which the
/// compiler vectorizes), i.e. what reading the bytes costs without any arithmetic on them.
pub fn stream_sum(words: &[u64]) -> u64 {
    let mut acc = [0u64; 8];
    for w in words.chunks_exact(8) {
        for (a, x) in acc.iter_mut().zip(w) {
            *a = a.wrapping_add(*x);
        }
    }
    acc.iter().fold(0, |s, v| s.wrapping_add(*v))
}

/// [`stream_sum`] split in halves over rayon's current pool.
pub fn stream_sum_par(words: &[u64]) -> u64 {
    let h = (words.len() / 16) * 8;
    let (a, b) = words.split_at(h);
    [a, b]
        .par_iter()
        .map(|w| stream_sum(w))
        .reduce(|| 0, u64::wrapping_add)
}
