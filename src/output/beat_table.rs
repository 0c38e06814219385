//! The spectral sum of a beat term from a table: for weights w_ci (channel c, e.g. the CIE
//! X, Y, Z weights of [`crate::colour::SpectralIntegrator`]) on the wavelengths λ_i,
//!
//!   Σ_i w_ci [C + Re(b e^{2πi(Δ/λ_i + e)})] = C W_c + Re(b e^{2πi e} G_c(Δ)),
//!   W_c = Σ_i w_ci,   G_c(Δ) = Σ_i w_ci e^{2πiΔ/λ_i},
//!
//! so a pixel's colour needs G at its beat terms' path differences Δ (m) only, not one phasor
//! per wavelength ([`crate::trace::beats`] evaluates the left side directly).
//!
//! G is tabulated at the nodes Δ_k = k h with its value and derivative
//! G'_c(Δ) = Σ_i w_ci (2πi/λ_i) e^{2πiΔ/λ_i}, and read by cubic Hermite interpolation between
//! two nodes. The interpolation error of each of Re G, Im G is at most
//! h⁴/384 · max|G⁽⁴⁾| ≤ h⁴/384 · Σ_i |w_ci| (2π/λ_i)⁴ (the cubic Hermite remainder), and h is
//! chosen so that this bound is [`RELATIVE_BOUND`] of Σ_i |w_ci| for every channel: a beat
//! term's sum is off by at most 2 |b| · RELATIVE_BOUND · Σ_i |w_ci|, with |b| ≤ 2|E_k||E_l|
//! ≤ the pixel's constant C. (For the visible grid, 380–780 nm, h ≈ 0.27 nm.)
//!
//! The nodes are computed on demand into a per-thread direct-mapped cache (a node's value is a
//! function of k alone, so the picture does not depend on the thread count or on the order in
//! which pixels are visited). The cache is thread-local and kept for the table's lifetime
//! (rayon calls a render's scratch initializer once per job split, and a fresh cache per split
//! recomputed its ~2000 nodes each time).

use crate::accumulate::phasor_from_cycles;
use crate::trace::beats::Beats;
use num_complex::Complex64;
use std::cell::RefCell;
use std::sync::atomic::{AtomicU64, Ordering};

/// Identities of tables, so a thread's cache knows whose nodes it holds.
static NEXT_TABLE: AtomicU64 = AtomicU64::new(1);

thread_local! {
    static CACHE: RefCell<TableCache> = RefCell::new(TableCache::default());
}

/// The interpolation error bound per unit of Σ_i |w_ci| (module docs).
pub(crate) const RELATIVE_BOUND: f64 = 1e-12;

/// Cache slots per thread (a power of two): 4096 nodes span 1.1 µm of path difference at the
/// visible grid's h.
const SLOTS: usize = 4096;

/// One node: per channel, G and h·G'.
type Node = [[Complex64; 2]; 3];

/// The table of one wavelength grid and its weights (module docs).
#[derive(Clone, Debug)]
pub(crate) struct BeatTable {
    lambdas: Vec<f64>,
    weights: Vec<[f64; 3]>,
    /// Σ_i w_ci.
    weight_sums: [f64; 3],
    /// Node spacing (m).
    h: f64,
    /// This table's identity (`NEXT_TABLE`).
    id: u64,
}

/// Per-thread node cache.
#[derive(Clone, Debug, Default)]
pub(crate) struct TableCache {
    /// The table whose nodes the slots hold (0: none).
    owner: u64,
    slots: Vec<Option<(i64, Node)>>,
}

impl BeatTable {
    /// The table of `weights` on `lambdas_m`, or `None` for an empty grid or a non-finite
    /// spacing.
    pub(crate) fn new(lambdas_m: &[f64], weights: &[[f64; 3]]) -> Option<BeatTable> {
        if lambdas_m.is_empty() || lambdas_m.len() != weights.len() {
            return None;
        }
        // h⁴/384 · Σ|w|(2π/λ)⁴ ≤ RELATIVE_BOUND · Σ|w| for every channel.
        let mut worst: f64 = 0.0;
        for c in 0..3 {
            let (mut s4, mut s0) = (0.0, 0.0);
            for (&l, w) in lambdas_m.iter().zip(weights) {
                s4 += w[c].abs() * (std::f64::consts::TAU / l).powi(4);
                s0 += w[c].abs();
            }
            if s0 > 0.0 {
                worst = worst.max(s4 / s0);
            }
        }
        let h = (384.0 * RELATIVE_BOUND / worst).powf(0.25);
        if !(h.is_finite() && h > 0.0) {
            return None;
        }
        let mut weight_sums = [0.0; 3];
        for w in weights {
            for c in 0..3 {
                weight_sums[c] += w[c];
            }
        }
        Some(BeatTable {
            lambdas: lambdas_m.to_vec(),
            weights: weights.to_vec(),
            weight_sums,
            h,
            id: NEXT_TABLE.fetch_add(1, Ordering::Relaxed),
        })
    }

    /// G and h·G' at Δ = k h (out of line: a cache miss is rare, and `cached` stays small
    /// enough to inline).
    #[cold]
    #[inline(never)]
    fn node(&self, k: i64) -> Node {
        let delta = k as f64 * self.h;
        let mut n = [[Complex64::new(0.0, 0.0); 2]; 3];
        for (&l, w) in self.lambdas.iter().zip(&self.weights) {
            let p = phasor_from_cycles(delta / l);
            // h · d/dΔ e^{2πiΔ/λ} = (2πh/λ) i e^{2πiΔ/λ}.
            let dp = Complex64::new(-p.im, p.re) * (std::f64::consts::TAU * self.h / l);
            for c in 0..3 {
                n[c][0] += w[c] * p;
                n[c][1] += w[c] * dp;
            }
        }
        n
    }

    #[inline]
    fn cached<'a>(&self, cache: &'a mut TableCache, k: i64) -> &'a Node {
        if cache.owner != self.id || cache.slots.len() != SLOTS {
            cache.owner = self.id;
            cache.slots.clear();
            cache.slots.resize(SLOTS, None);
        }
        let slot = &mut cache.slots[(k as u64 as usize) & (SLOTS - 1)];
        if !matches!(slot, Some((kk, _)) if *kk == k) {
            *slot = Some((k, self.node(k)));
        }
        &slot.as_ref().expect("just filled").1
    }

    /// The node index k and the cubic Hermite basis (h00, h10, h01, h11) at Δ = (k + t) h.
    #[inline]
    fn hermite(&self, delta: f64) -> (i64, [f64; 4]) {
        let x = delta / self.h;
        let k = x.floor();
        let t = x - k;
        let (t2, t3) = (t * t, t * t * t);
        (
            k as i64,
            [
                2.0 * t3 - 3.0 * t2 + 1.0,
                t3 - 2.0 * t2 + t,
                -2.0 * t3 + 3.0 * t2,
                t3 - t2,
            ],
        )
    }

    /// G_c(Δ) for the three channels (cubic Hermite between the nodes around Δ).
    fn g(&self, delta: f64, cache: &mut TableCache) -> [Complex64; 3] {
        let (k, [h00, h10, h01, h11]) = self.hermite(delta);
        let a = *self.cached(cache, k);
        let b = *self.cached(cache, k + 1);
        let mut g = [Complex64::new(0.0, 0.0); 3];
        for c in 0..3 {
            g[c] = a[c][0] * h00 + a[c][1] * h10 + b[c][0] * h01 + b[c][1] * h11;
        }
        g
    }

    /// Re G_c(Δ): the real parts of [`BeatTable::g`] alone, by the same operations (a complex
    /// times a real scales each part apart, and the sum's real part is the sum of the real
    /// parts in the same order): bit for bit `g`'s real parts, for a beat term without a
    /// λ-independent phase, whose sum needs no imaginary part.
    #[inline]
    fn g_re(&self, delta: f64, cache: &mut TableCache) -> [f64; 3] {
        let (k, [h00, h10, h01, h11]) = self.hermite(delta);
        let mut a = [[0.0; 2]; 3];
        for (ac, n) in a.iter_mut().zip(self.cached(cache, k)) {
            *ac = [n[0].re, n[1].re];
        }
        let b = self.cached(cache, k + 1);
        let mut g = [0.0; 3];
        for c in 0..3 {
            g[c] = a[c][0] * h00 + a[c][1] * h10 + b[c][0].re * h01 + b[c][1].re * h11;
        }
        g
    }

    /// Σ_i w_i I(λ_i) of `beats` (the same sum as [`Beats::weighted_sum`] on this table's grid,
    /// to the bound of the module docs), or `None` where the beats are not in the paired form
    /// or a path difference is beyond 2^52 nodes.
    pub(crate) fn weighted_sum(&self, beats: &Beats) -> Option<[f64; 3]> {
        CACHE.with(|c| self.weighted_sum_with(beats, &mut c.borrow_mut()))
    }

    /// [`BeatTable::weighted_sum`] of the paired form given directly: the constant and the
    /// terms (Δ (m), λ-independent phase e (cycles), real amplitude b), as
    /// [`crate::output::stack_kernel::shade_terms`] forms them from real fields. The same
    /// operations as [`BeatTable::weighted_sum`] on the complex amplitude b + 0i, less the
    /// products of the zero imaginary part: bit for bit the same sums (up to the sign of a
    /// zero). `None` where a path difference is beyond 2^52 nodes.
    pub(crate) fn weighted_sum_real(
        &self,
        constant: f64,
        terms: &[(f64, f64, f64)],
    ) -> Option<[f64; 3]> {
        CACHE.with(|c| {
            let cache = &mut c.borrow_mut();
            let mut out = self.weight_sums.map(|w| constant * w);
            for &(delta, extra, b) in terms {
                // Also refuses a NaN.
                if (delta / self.h).abs().partial_cmp(&4.5e15) != Some(std::cmp::Ordering::Less) {
                    return None;
                }
                if extra == 0.0 {
                    let g = self.g_re(delta, cache);
                    for c in 0..3 {
                        out[c] += b * g[c];
                    }
                } else {
                    let g = self.g(delta, cache);
                    // (b + 0i) e^{2πie} = b cos + i b sin.
                    let ph = phasor_from_cycles(extra);
                    let (re, im) = (b * ph.re, b * ph.im);
                    for c in 0..3 {
                        out[c] += re * g[c].re - im * g[c].im;
                    }
                }
            }
            Some(out)
        })
    }

    /// [`BeatTable::weighted_sum`] with the node cache `cache`.
    fn weighted_sum_with(&self, beats: &Beats, cache: &mut TableCache) -> Option<[f64; 3]> {
        let (constant, terms) = beats.paired_terms()?;
        let mut out = self.weight_sums.map(|w| constant * w);
        for (delta, extra, b) in terms {
            // Also refuses a NaN.
            if (delta / self.h).abs().partial_cmp(&4.5e15) != Some(std::cmp::Ordering::Less) {
                return None;
            }
            let b = if extra == 0.0 {
                b
            } else {
                b * phasor_from_cycles(extra)
            };
            let g = self.g(delta, cache);
            for c in 0..3 {
                out[c] += b.re * g[c].re - b.im * g[c].im;
            }
        }
        Some(out)
    }
}
