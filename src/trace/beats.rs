//! One screen point's rays at many wavelengths: the accumulation core (eqs. 5–6, docs/PHYSICS.md §3)
//! expanded into beat terms, for spectral renders.
//!
//! A ray's phase splits into a part that scales with 1/λ and one that does not:
//! φ_k(λ) = Δs_k/λ + e_k (cycles), with Δs_k its optical path minus the point's reference
//! optical path (m) and e_k the λ-independent phase (the half-cycle jumps of `scalar_jump`). The
//! fields E_k do not depend on λ when no medium is dispersive. For one coherence group the
//! identity
//!
//! |Σ_k E_k e^{2πiφ_k}|² = Σ_k |E_k|² + Σ_{k<l} Re[2 (E_k·E_l*) e^{2πi(φ_k − φ_l)}],
//!
//! with E_k·E_l* = Σ_c E_k,c conj(E_l,c), rewrites eq. 5 as a constant plus one *beat term* per
//! pair, of path difference Δs_k − Δs_l (formed in metres before dividing by λ, as everywhere in
//! fringe) and extra phase e_k − e_l; incoherent rays (id 0) add |E_k|² to the constant (eq. 6).
//! Terms with the same path difference and extra phase merge exactly (their complex amplitudes
//! add): the s and p channels of an unpolarized source along the same two paths, or several
//! sources' channels, leave **one** term for a two-beam point, so each wavelength costs one
//! phasor instead of one per ray. With more terms than rays (many beams in one group, e.g. an
//! Airy plate) the pair form would cost more, and [`Beats::intensity`] uses the accumulator.

use crate::accumulate::{Accumulator, phasor_from_cycles, phasors_from_cycles};
use crate::optics::ray::{Field3, INCOHERENT};
use crate::trace::Arrival;
use num_complex::Complex64;

/// A ray at a screen point with its phase split for evaluation at any wavelength.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct SpectralContribution {
    /// Coherence id; 0 adds intensity only.
    pub coherence_id: u64,
    /// Optical path minus the point's reference optical path (m).
    pub delta_s_m: f64,
    /// Phase that does not scale with 1/λ (cycles).
    pub extra_cycles: f64,
    /// Complex 3D field amplitude (λ-independent).
    pub field: Field3,
}

/// One beat term: Re[amplitude · e^{2πi(Δs/λ + e)}].
#[derive(Clone, Copy, Debug, PartialEq)]
struct Beat {
    delta_s_m: f64,
    extra_cycles: f64,
    amplitude: Complex64,
}

/// The rays of one point, reduced to beat terms when that is cheaper (module docs).
#[derive(Clone, Debug, Default)]
pub struct Beats {
    rays: Vec<SpectralContribution>,
    /// Σ |E_k|² over every ray.
    constant: f64,
    terms: Vec<Beat>,
    /// Whether `constant` + `terms` represent the rays (else the accumulator is used).
    paired: bool,
    /// Scratch of [`Beats::weighted_sum`]: one phase and phasor per wavelength.
    cycles: Vec<f64>,
    phasors: Vec<Complex64>,
    /// Scratch of [`Beats::intensities`]: coherence ids in order of first appearance, and
    /// each group's field over one block of wavelengths as six rows (re, im of x, y, z).
    group_ids: Vec<u64>,
    group_fields: Vec<f64>,
    /// Distinct (Δs, extra phase) pairs of the rays, and each coherent ray's phase class,
    /// group and field.
    phase_keys: Vec<(f64, f64)>,
    ray_slots: Vec<(usize, usize, Field3)>,
}

/// Wavelengths per block of [`Beats::intensities`] (accumulator form): 64 wavelengths of a
/// group's field sums are 3 KiB, so several groups stay in L1.
const LAMBDA_BLOCK: usize = 64;

/// The `vector` rays of a point's arrivals, traced at one wavelength, as spectral
/// contributions for any wavelength of a non-dispersive scene: Δs is each optical path minus
/// the first arrival's, formed in double-double and rounded once (docs/PHYSICS.md §1), with no
/// λ-independent phase (the `vector` rung's phases are all in the optical path and the Jones
/// vector). [`Beats::set`] then [`Beats::intensities`] gives the spectrum.
pub fn vector_rays(arrivals: &[Arrival]) -> Vec<SpectralContribution> {
    let Some(first) = arrivals.first() else {
        return Vec::new();
    };
    let reference = first.vector.optical_path;
    arrivals
        .iter()
        .map(|a| SpectralContribution {
            coherence_id: a.vector.coherence_id,
            delta_s_m: (a.vector.optical_path - reference).to_f64(),
            extra_cycles: 0.0,
            field: a.vector.field(),
        })
        .collect()
}

fn dot_conj(a: &Field3, b: &Field3) -> Complex64 {
    a[0] * b[0].conj() + a[1] * b[1].conj() + a[2] * b[2].conj()
}

impl Beats {
    /// Replace the rays (allocation is reused across points).
    pub fn set(&mut self, rays: &[SpectralContribution]) {
        self.rays.clear();
        self.rays.extend_from_slice(rays);
        self.terms.clear();
        self.constant = rays
            .iter()
            .map(|r| r.field.iter().map(|c| c.norm_sqr()).sum::<f64>())
            .sum();
        // Pairs in the same group, counted before any is built.
        let mut pairs = 0;
        for (k, a) in rays.iter().enumerate() {
            if a.coherence_id != INCOHERENT {
                pairs += rays[..k]
                    .iter()
                    .filter(|b| b.coherence_id == a.coherence_id)
                    .count();
            }
        }
        self.paired = pairs <= rays.len();
        if !self.paired {
            return;
        }
        for (k, a) in rays.iter().enumerate() {
            if a.coherence_id == INCOHERENT {
                continue;
            }
            for b in rays[..k]
                .iter()
                .filter(|b| b.coherence_id == a.coherence_id)
            {
                let beat = Beat {
                    delta_s_m: a.delta_s_m - b.delta_s_m,
                    extra_cycles: a.extra_cycles - b.extra_cycles,
                    amplitude: 2.0 * dot_conj(&a.field, &b.field),
                };
                match self
                    .terms
                    .iter_mut()
                    .find(|t| t.delta_s_m == beat.delta_s_m && t.extra_cycles == beat.extra_cycles)
                {
                    Some(t) => t.amplitude += beat.amplitude,
                    None => self.terms.push(beat),
                }
            }
        }
    }

    /// The paired form: the constant Σ_k |E_k|² and each beat term as (Δs (m), λ-independent
    /// phase (cycles), amplitude b), the intensity at λ being the constant plus
    /// Σ_t Re[b_t e^{2πi(Δs_t/λ + e_t)}]; `None` when the accumulator evaluates the rays.
    pub fn paired_terms(&self) -> Option<(f64, impl Iterator<Item = (f64, f64, Complex64)> + '_)> {
        self.paired.then(|| {
            (
                self.constant,
                self.terms
                    .iter()
                    .map(|t| (t.delta_s_m, t.extra_cycles, t.amplitude)),
            )
        })
    }

    /// Number of beat terms, or `None` when the rays are evaluated by the accumulator.
    pub fn term_count(&self) -> Option<usize> {
        self.paired.then_some(self.terms.len())
    }

    /// Intensity at vacuum wavelength `lambda_m` (eqs. 5–6); `acc` is scratch space for the
    /// unpaired case.
    pub fn intensity(&self, lambda_m: f64, acc: &mut Accumulator) -> f64 {
        if self.paired {
            let mut i = self.constant;
            for t in &self.terms {
                let p = phasor_from_cycles(t.delta_s_m / lambda_m + t.extra_cycles);
                i += t.amplitude.re * p.re - t.amplitude.im * p.im;
            }
            i
        } else {
            acc.clear();
            for r in &self.rays {
                acc.add_parts(
                    r.coherence_id,
                    r.delta_s_m / lambda_m + r.extra_cycles,
                    &r.field,
                );
            }
            acc.intensity()
        }
    }

    /// [`Beats::intensity`] at every wavelength of `lambdas_m`, into `out`: a spectrum of a
    /// point whose rays were traced once (non-dispersive media: the same paths, fields and
    /// order structure at every λ, only the phases Δs/λ change). Term by term (paired form:
    /// each term's phasors over the whole grid are one batch, [`phasors_from_cycles`]) or by
    /// blocks of wavelengths (accumulator form: one phasor batch per distinct ray phase and
    /// block, shared by the rays of that phase). The accumulator
    /// form sums each coherence group's field in ray order without compensation: for N rays
    /// of fields |E_k| the rounding is ~N u Σ|E_k|² (u = 2^-53), e.g. < 1e-14 for an Airy plate
    /// of 50 orders, where [`Beats::intensity`] compensates.
    pub fn intensities(&mut self, lambdas_m: &[f64], out: &mut [f64]) {
        assert_eq!(lambdas_m.len(), out.len(), "one output per wavelength");
        let n = lambdas_m.len();
        self.cycles.resize(n, 0.0);
        self.phasors.resize(n, Complex64::new(0.0, 0.0));
        if self.paired {
            out.fill(self.constant);
            for t in &self.terms {
                for (c, &l) in self.cycles.iter_mut().zip(lambdas_m) {
                    *c = t.delta_s_m / l + t.extra_cycles;
                }
                phasors_from_cycles(&self.cycles, &mut self.phasors);
                for (o, p) in out.iter_mut().zip(&self.phasors) {
                    *o += t.amplitude.re * p.re - t.amplitude.im * p.im;
                }
            }
            return;
        }
        #[cfg(target_arch = "x86_64")]
        if std::arch::is_x86_feature_detected!("avx2") {
            // SAFETY: `rays_spectrum_avx2` only requires AVX2, which the running CPU has
            // (checked just above). Measured reason: 4-lane loops (README measured table,
            // `airy/spectrum`); no FMA is enabled, so both copies give the same bits.
            unsafe { self.rays_spectrum_avx2(lambdas_m, out) };
            return;
        }
        self.rays_spectrum(lambdas_m, out);
    }

    /// [`Beats::rays_spectrum`] compiled for AVX2.
    #[cfg(target_arch = "x86_64")]
    #[target_feature(enable = "avx2")]
    fn rays_spectrum_avx2(&mut self, lambdas_m: &[f64], out: &mut [f64]) {
        self.rays_spectrum(lambdas_m, out);
    }

    /// The accumulator form of [`Beats::intensities`]: rays that share a phase (the same Δs
    /// and extra phase, e.g. the s and p channels of one path, which are different coherence
    /// groups) share one phasor batch, and the wavelengths are taken [`LAMBDA_BLOCK`] at a time
    /// so that every group's running field sums stay in L1. A group's rays are summed in the
    /// order of their phase classes' first appearance (ray order whenever a group's rays come
    /// in that order, as for the s and p channels of an Airy plate's orders); the rounding
    /// bound of [`Beats::intensities`] does not depend on the order.
    #[inline(always)]
    fn rays_spectrum(&mut self, lambdas_m: &[f64], out: &mut [f64]) {
        self.group_ids.clear();
        self.phase_keys.clear();
        self.ray_slots.clear();
        let mut incoherent = 0.0;
        for r in &self.rays {
            if r.coherence_id == INCOHERENT {
                incoherent += r.field.iter().map(|c| c.norm_sqr()).sum::<f64>();
                continue;
            }
            let g = match self.group_ids.iter().position(|&id| id == r.coherence_id) {
                Some(g) => g,
                None => {
                    self.group_ids.push(r.coherence_id);
                    self.group_ids.len() - 1
                }
            };
            // Exact equality only: rays merge their phasors when their phases are the same
            // numbers, never approximately.
            let key = (r.delta_s_m, r.extra_cycles);
            let p = match self.phase_keys.iter().position(|&k| k == key) {
                Some(p) => p,
                None => {
                    self.phase_keys.push(key);
                    self.phase_keys.len() - 1
                }
            };
            self.ray_slots.push((p, g, r.field));
        }
        // Rays by phase class (first-appearance order); the stable sort keeps ray order within
        // a class.
        self.ray_slots.sort_by_key(|&(p, _, _)| p);
        let groups = self.group_ids.len();
        // Per group, six rows of LAMBDA_BLOCK: re and im of x, y, z at each wavelength of the
        // block, so the loops over wavelengths run over contiguous rows.
        let row = |g: usize, k: usize| (6 * g + k) * LAMBDA_BLOCK;
        self.group_fields.resize(6 * groups * LAMBDA_BLOCK, 0.0);
        self.cycles.resize(LAMBDA_BLOCK, 0.0);
        self.phasors.resize(LAMBDA_BLOCK, Complex64::new(0.0, 0.0));
        let mut cos = [0.0; LAMBDA_BLOCK];
        let mut sin = [0.0; LAMBDA_BLOCK];
        for (lambdas, out) in lambdas_m
            .chunks(LAMBDA_BLOCK)
            .zip(out.chunks_mut(LAMBDA_BLOCK))
        {
            let n = lambdas.len();
            let fields = &mut self.group_fields[..6 * groups * LAMBDA_BLOCK];
            fields.fill(0.0);
            let mut start = 0;
            while start < self.ray_slots.len() {
                let p = self.ray_slots[start].0;
                let end = start
                    + self.ray_slots[start..]
                        .iter()
                        .take_while(|s| s.0 == p)
                        .count();
                let (ds, extra) = self.phase_keys[p];
                for (c, &l) in self.cycles[..n].iter_mut().zip(lambdas) {
                    *c = ds / l + extra;
                }
                phasors_from_cycles(&self.cycles[..n], &mut self.phasors[..n]);
                for ((c, s), p) in cos[..n].iter_mut().zip(&mut sin[..n]).zip(&self.phasors) {
                    (*c, *s) = (p.re, p.im);
                }
                for &(_, g, f) in &self.ray_slots[start..end] {
                    for (k, fk) in f.iter().enumerate() {
                        let (re, im) =
                            fields[row(g, 2 * k)..row(g, 2 * k + 2)].split_at_mut(LAMBDA_BLOCK);
                        for (((er, ei), &c), &s) in re[..n]
                            .iter_mut()
                            .zip(&mut im[..n])
                            .zip(&cos[..n])
                            .zip(&sin[..n])
                        {
                            *er += fk.re * c - fk.im * s;
                            *ei += fk.re * s + fk.im * c;
                        }
                    }
                }
                start = end;
            }
            out.fill(incoherent);
            for g in 0..groups {
                let rows = &fields[row(g, 0)..row(g + 1, 0)];
                for (i, o) in out.iter_mut().enumerate() {
                    let mut e2 = 0.0;
                    for k in 0..6 {
                        let v = rows[k * LAMBDA_BLOCK + i];
                        e2 += v * v;
                    }
                    *o += e2;
                }
            }
        }
    }

    /// Σ_i w_i I(λ_i) for each of three weight channels (e.g. the CIE weights of X, Y, Z) over
    /// the wavelengths `lambdas_m`: the same sum as adding `w_i ·` [`Beats::intensity`]`(λ_i)`,
    /// with the phasors of each beat term computed as one batch. In the paired form
    /// Σ_i w_i I_i = C Σ_i w_i + Σ_t (Re b_t Σ_i w_i cos 2πφ_ti − Im b_t Σ_i w_i sin 2πφ_ti).
    pub fn weighted_sum(
        &mut self,
        lambdas_m: &[f64],
        weights: &[[f64; 3]],
        acc: &mut Accumulator,
    ) -> [f64; 3] {
        assert_eq!(lambdas_m.len(), weights.len(), "one weight per wavelength");
        let mut out = [0.0; 3];
        if !self.paired {
            for (&l, w) in lambdas_m.iter().zip(weights) {
                let i = self.intensity(l, acc);
                for c in 0..3 {
                    out[c] += w[c] * i;
                }
            }
            return out;
        }
        let constant = self.constant;
        let Some((first, rest)) = self.terms.split_first() else {
            for w in weights {
                for c in 0..3 {
                    out[c] += w[c] * constant;
                }
            }
            return out;
        };
        self.cycles.resize(lambdas_m.len(), 0.0);
        self.phasors
            .resize(lambdas_m.len(), Complex64::new(0.0, 0.0));
        // Σ_i w_i C runs in the loop of the first term: nine independent sums instead of three
        // and then six, each still added in wavelength order, so every value is unchanged.
        for (k, t) in std::iter::once(first).chain(rest).enumerate() {
            for (c, &l) in self.cycles.iter_mut().zip(lambdas_m) {
                *c = t.delta_s_m / l + t.extra_cycles;
            }
            phasors_from_cycles(&self.cycles, &mut self.phasors);
            let (mut re, mut im) = ([0.0; 3], [0.0; 3]);
            if k == 0 {
                for (p, w) in self.phasors.iter().zip(weights) {
                    for c in 0..3 {
                        out[c] += w[c] * constant;
                        re[c] += w[c] * p.re;
                        im[c] += w[c] * p.im;
                    }
                }
            } else {
                for (p, w) in self.phasors.iter().zip(weights) {
                    for c in 0..3 {
                        re[c] += w[c] * p.re;
                        im[c] += w[c] * p.im;
                    }
                }
            }
            for c in 0..3 {
                out[c] += t.amplitude.re * re[c] - t.amplitude.im * im[c];
            }
        }
        out
    }
}
