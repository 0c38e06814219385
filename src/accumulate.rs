//! The accumulation core (paper §3.6–3.7, eqs. 5–6).
//!
//! At a screen point, contributions are grouped by coherence id; each group's complex 3D field
//! vectors are summed with their path phasors, `E_g = Σ_j E_j e^{i 2π c_j}` (c_j: phase in
//! cycles, Op/λ0), and the intensity is `I = Σ_g |E_g|² + Σ_{id = 0} |E_j|²`.
//!
//! Phase is carried in *cycles*: the integer part is split off exactly before the phasor is
//! evaluated, so a metre-long path (10^6 cycles) keeps its fractional phase to ~1e-10 cycles.
//! The core owns no allocation per contribution and can be benchmarked alone.

use crate::ray::{Field3, INCOHERENT};
use num_complex::Complex64;

/// One ray arriving at a point.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Contribution {
    /// Coherence id; 0 adds intensity only.
    pub coherence_id: u64,
    /// Path phase in cycles (Op/λ0, plus any half-cycle jumps of the scalar rungs).
    pub phase_cycles: f64,
    /// Complex 3D field amplitude (Fresnel phases included, path phase excluded).
    pub field: Field3,
}

/// e^{i 2π c} with the integer part of `c` removed exactly first.
#[inline]
pub fn phasor_from_cycles(cycles: f64) -> Complex64 {
    let frac = cycles - cycles.round();
    let (s, c) = (std::f64::consts::TAU * frac).sin_cos();
    Complex64::new(c, s)
}

/// Per-point accumulator of coherence groups; reuse it across points with [`Accumulator::clear`].
#[derive(Clone, Debug, Default)]
pub struct Accumulator {
    groups: Vec<(u64, Field3)>,
    incoherent: f64,
}

impl Accumulator {
    pub fn new() -> Self {
        Self::default()
    }

    pub fn clear(&mut self) {
        self.groups.clear();
        self.incoherent = 0.0;
    }

    /// Add one contribution (eq. 5 for its group, or eq. 6's incoherent term for id 0).
    #[inline]
    pub fn add(&mut self, c: &Contribution) {
        if c.coherence_id == INCOHERENT {
            self.incoherent += c.field.iter().map(|e| e.norm_sqr()).sum::<f64>();
            return;
        }
        let ph = phasor_from_cycles(c.phase_cycles);
        let slot = match self.groups.iter().position(|(id, _)| *id == c.coherence_id) {
            Some(k) => k,
            None => {
                self.groups.push((c.coherence_id, [Complex64::default(); 3]));
                self.groups.len() - 1
            }
        };
        let acc = &mut self.groups[slot].1;
        for k in 0..3 {
            acc[k] += c.field[k] * ph;
        }
    }

    /// I = Σ_g |E_g|² + Σ incoherent |E|² (eq. 6).
    pub fn intensity(&self) -> f64 {
        self.incoherent
            + self
                .groups
                .iter()
                .map(|(_, e)| e.iter().map(|c| c.norm_sqr()).sum::<f64>())
                .sum::<f64>()
    }

    /// The summed field of each coherence group.
    pub fn groups(&self) -> &[(u64, Field3)] {
        &self.groups
    }
}

/// Intensity of a set of contributions at one point.
pub fn intensity(contributions: &[Contribution]) -> f64 {
    let mut acc = Accumulator::new();
    for c in contributions {
        acc.add(c);
    }
    acc.intensity()
}
