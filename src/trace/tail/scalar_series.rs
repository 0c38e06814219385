//! The scalar rungs' closed Airy tail for mixed s and p light (docs/PHYSICS.md §5a, eq. T2).
//!
//! In `scalar` and `scalar_jump` order N + k carries the amplitude √I_{N+k} with the phase of
//! its path only, and every round trip multiplies the s and p intensities by x = |A_s|² and
//! y = |A_p|². The tail on order N's √I_N is therefore the factor
//!
//! ```text
//! F = Σ_{k≥1} √(w_s x^k + w_p y^k) e^{2πi k c},   w_σ = |e_σ|²/|e|²,                  (T2)
//! ```
//!
//! c the round trip's cycles. For one polarization it is the geometric series of (T1); for
//! mixed light it is not one, and near grazing incidence (1 − x ~ 1e-9) it cannot be summed term
//! by term. Order the polarizations so that the major one M decays no faster (x_M ≥ x_m), let
//! a = √x_M, b = √x_m, ρ = x_m/x_M = e^{−δ}, u = w_m/w_M and u_k = u ρ^k (decreasing in k), and
//! split at K, the first k ≥ 1 with u_k ≤ 1:
//!
//! ```text
//! k ≥ K:  √(w_M x_M^k + w_m x_m^k) = √w_M a^k √(1 + u_k)
//! k < K:  √(w_M x_M^k + w_m x_m^k) = √w_m b^k √(1 + 1/u_k)
//! ```
//!
//! With √(1 + v) = 1 + Σ_{j≥1} (−1)^{j−1} |β_j| v^j (β_j = binom(1/2, j)) each power of u_k (or
//! 1/u_k) turns the sum over k into a geometric series, closed exactly: Σ_{k≥K} q^k =
//! q^K/(1 − q) and Σ_{k=1}^{n} q^k = q (e^{nλ} − 1)/(e^λ − 1) (q = e^λ), with e^λ − 1 formed as
//! expm1(Re λ) cos θ − 2 sin²(θ/2) + i e^{Re λ} sin θ (no cancellation near a resonance) and the
//! logarithms of x, y from log1p of the 1 − |A|² the tracer holds. The series in j converges
//! only like j^{−3/2} where u_k → 1 (wide when ρ → 1), so it is summed by the alternating-series
//! acceleration of Cohen, Rodriguez Villegas and Zagier (Exp. Math. 9 (2000), Algorithm 1):
//! its terms are moments a_j = ∫_0^1 t^j dμ of a complex measure (|β_{j+1}| = (1/π) ∫_0^1 t^j
//! t^{−1/2}(1 − t)^{1/2} dt, times Σ_k r^k v_k^{j+1} with 0 ≤ v_k ≤ 1), so n terms leave an
//! error of at most 4 |μ| (3 + √8)^{−n}, |μ| ≤ ½ Σ_k |r|^k v_k (~1/(1 − x) near grazing
//! incidence). n is chosen, 40 to 380, to make that at most 1e-18 of the region's first
//! geometric series; the returned bound adds it to the rounding.

use num_complex::Complex64;
use std::f64::consts::TAU;

/// Unit roundoff of f64.
const U: f64 = f64::EPSILON / 2.0;

/// The smallest 1 − |A|² taken (with a positive weight): the acceleration's truncation
/// 4|μ|(3 + √8)^{−n}, |μ| ~ 1/(1 − |A|), stays below 1e-12 of F within 380 terms
/// ((3 + √8)^{−380} ≈ 1e-291; at 1e-294 the bound was 3e2 against |F| = 0.33, at 3e-244
/// 5e-12 of F). Physical round
/// trips are many orders above it (1e-9 at cos θ = 1e-9).
pub const MIN_ONE_MINUS_ABS2: f64 = 1e-200;

/// Fewest terms of the accelerated series (module docs): truncation ≤ 4 |μ| (3 + √8)^{−40}.
const TERMS: usize = 40;

/// Most terms: (3 + √8)^{380} ≈ 1e291 stays an f64.
const MAX_TERMS: usize = 380;

/// Terms for a truncation 4 |μ| (3 + √8)^{−n} ≤ 1e-18 `scale` (|μ| ~ 1/(1 − x) near grazing
/// incidence, F off a resonance ~ 1: 40 terms suffice while 1 − x ≥ 1e-12).
fn terms_for(mu: f64, scale: f64) -> usize {
    let want = (4.0 * mu / (1e-18 * scale.max(f64::MIN_POSITIVE))).ln() / (3.0 + 8f64.sqrt()).ln();
    if want.is_finite() {
        (want.ceil().max(TERMS as f64) as usize).min(MAX_TERMS)
    } else {
        MAX_TERMS
    }
}

/// F (eq. T2) and a bound on the absolute error of its evaluation from the given inputs
/// (rounding and truncation; the sensitivity of F to errors in those inputs is not included).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ScalarTail {
    /// Σ_{k≥1} √(w_s x^k + w_p y^k) e^{2πi k c} (dimensionless, on √I_N).
    pub sum: Complex64,
    /// Bound on |computed − exact| (same units as `sum`).
    pub error_bound: f64,
}

/// The scalar rungs' tail factor F of eq. (T2) (module docs): `weights` = (|e_s|², |e_p|²) of
/// order N's field (any common scale; normalized here), `one_minus_abs2` = (1 − x, 1 − y) as
/// the tracer holds them (no cancellation), `cycles` = c, the round trip's phase in cycles.
/// `None` for input with no finite sum: a weight negative or not finite, a weighted 1 − |A|²
/// outside [1e-200, 1] (1 − |A|² ≤ 0: the orders do not decay; below 1e-200 the series cannot
/// certify F to 1e-12 within its terms, and F may leave the
/// f64 range), or c not finite.
pub fn scalar_tail(weights: [f64; 2], one_minus_abs2: [f64; 2], cycles: f64) -> Option<ScalarTail> {
    let [ws, wp] = weights;
    let total = ws + wp;
    if !(ws >= 0.0 && wp >= 0.0 && total.is_finite() && cycles.is_finite()) {
        return None;
    }
    for (w, d) in weights.iter().zip(one_minus_abs2) {
        if *w > 0.0 && !(MIN_ONE_MINUS_ABS2..=1.0).contains(&d) {
            return None;
        }
    }
    if total == 0.0 {
        return Some(ScalarTail {
            sum: Complex64::default(),
            error_bound: 0.0,
        });
    }
    // c in [−1/2, 1/2] (exact: Sterbenz).
    let c = cycles - cycles.round();
    let [ds, dp] = one_minus_abs2;
    // M decays no faster than m; a zero weight leaves the other alone.
    let ((w_maj, d_maj), (w_min, d_min)) = if wp == 0.0 || (ws > 0.0 && ds <= dp) {
        ((ws / total, ds), (wp / total, dp))
    } else {
        ((wp / total, dp), (ws / total, ds))
    };
    if d_maj == 1.0 {
        // x_M = 0, hence x_m = 0 too: every order beyond N is dark.
        return Some(ScalarTail {
            sum: Complex64::default(),
            error_bound: 0.0,
        });
    }
    let alpha = -(-d_maj).ln_1p(); // −ln x_M > 0
    let lam0 = -0.5 * alpha; // ln a
    let pure = |w: f64| {
        let s = w.sqrt() * cdiv(cexp(lam0, c), -cexpm1(lam0, c));
        ScalarTail {
            sum: s,
            error_bound: 16.0 * U * s.norm(),
        }
    };
    if w_min == 0.0 || d_min == 1.0 {
        return Some(pure(w_maj));
    }
    let beta = -(-d_min).ln_1p(); // −ln x_m ≥ α
    // δ = ln(x_M/x_m) ≥ 0, without cancellation when the two are close.
    let delta = if beta > 2.0 * alpha {
        beta - alpha
    } else {
        ((d_min - d_maj) / (1.0 - d_min)).ln_1p()
    };
    if delta <= 0.0 {
        // x_M = x_m: √(w_M + w_m) a^k = a^k.
        return Some(pure(w_maj + w_min));
    }
    let log_u = (w_min / w_maj).ln();
    // K: the first k ≥ 1 with ln u_k = ln u − kδ ≤ 0 (an f64 above 2^52 is an integer).
    let mut k_split = if log_u <= 0.0 {
        1.0
    } else {
        (log_u / delta).ceil().max(1.0)
    };
    if (-k_split).mul_add(delta, log_u) > 0.0 {
        k_split += 1.0;
    }
    let beta_abs = binomial_half_abs();
    // Region k ≥ K about M: √w_M Σ_k r0^k (1 + Σ_j (−1)^{j−1}|β_j| u_k^j), r0 = a e^{2πic}.
    let log_uk = (-k_split).mul_add(delta, log_u); // ln u_K ≤ 0
    let q0 = cexp(-0.5 * alpha * k_split, frac_mul(k_split, c)); // r0^K
    let head = cdiv(q0, -cexpm1(lam0, c));
    // |μ| ≤ ½ Σ_{k≥K} a^k u_k = ½ a^K u_K/(1 − aρ).
    let mu_a = 0.5 * q0.norm() * log_uk.exp() / -(lam0 - delta).exp_m1();
    let n_a = terms_for(mu_a, head.norm());
    let mut a_terms = vec![Complex64::default(); n_a];
    let mut a_abs = (n_a as f64 + 16.0) * head.norm();
    for (j, t) in a_terms.iter_mut().enumerate() {
        let m = (j + 1) as f64;
        *t = beta_abs[j] * (m * log_uk).exp() * cdiv(q0, -cexpm1(m.mul_add(-delta, lam0), c));
        // ln u_k to 4u (|ln u| + δ + 1) (ln u and δ each to a few u; K δ ≈ ln u), m times.
        a_abs += t.norm() * (n_a as f64 + 16.0 + 4.0 * m * (log_u.abs() + delta + 1.0));
    }
    let region_a = w_maj.sqrt() * (head + accelerated(&a_terms));
    let mut err = w_maj.sqrt() * (4.0 * mu_a * truncation(n_a) + U * a_abs);
    let mut sum = region_a;
    if k_split > 1.0 {
        // Region 1 ≤ k < K about m: √w_m Σ_k r1^k (1 + Σ_j (−1)^{j−1}|β_j| u_k^{−j}),
        // r1 = b e^{2πic}; the j-th sum is u^{−j} Σ_{k=1}^{n} (r1 ρ^{−j})^k.
        // n = K − 1 terms. Above 2^53 the f64 K − 1 rounds to K (ρ within 2^-53 of 1, ln u
        // ≥ δ 2^53), so there the phase of r1^n is frac(K c) − c, one round trip less than
        // r0^K's (one rounding of the difference); its modulus e^{n ln b} cannot see the one
        // round trip (|ln b| < 2^-53 when n ln b is of order 1). The n = K term taken for
        // K − 1 made F wrong by about one term (F = −0.02 for −0.5 at 1 − x = 3e-183,
        // 1 − y = 1e-126: `scalar_tail::limit_of_vanishing_decay_is_the_abel_sum`).
        let n = k_split - 1.0;
        let lam1 = -0.5 * beta; // ln b
        let nc = if k_split <= 9_007_199_254_740_992.0 {
            // K ≤ 2^53: K − 1 is exact.
            frac_mul(n, c)
        } else {
            let f = frac_mul(k_split, c) - c;
            f - f.round()
        };
        let head = finite_geometric(n, lam1, c, nc, 0.0);
        // |μ| ≤ ½ Σ_{k<K} b^k/u_k.
        let mu_c = 0.5 * finite_geometric(n, lam1 + delta, 0.0, 0.0, log_u).norm();
        let n_c = terms_for(mu_c, head.norm());
        let mut b_terms = vec![Complex64::default(); n_c];
        let mut b_abs = (n_c as f64 + 16.0) * head.norm();
        for (j, t) in b_terms.iter_mut().enumerate() {
            let m = (j + 1) as f64;
            *t = beta_abs[j] * finite_geometric(n, m.mul_add(delta, lam1), c, nc, m * log_u);
            // ln u_k to 4u (|ln u| + δ + 1) (ln u and δ each to a few u; K δ ≈ ln u), m times.
            b_abs += t.norm() * (n_c as f64 + 16.0 + 4.0 * m * (log_u.abs() + delta + 1.0));
        }
        sum += w_min.sqrt() * (head + accelerated(&b_terms));
        err += w_min.sqrt() * (4.0 * mu_c * truncation(n_c) + U * b_abs);
    }
    Some(
        ScalarTail {
            sum,
            error_bound: err + 4.0 * U * sum.norm(),
        }
        .finite_or_bounded(),
    )
}

impl ScalarTail {
    /// Every path above yields finite values for valid input; this keeps that a checked fact.
    fn finite_or_bounded(self) -> Self {
        debug_assert!(self.sum.re.is_finite() && self.sum.im.is_finite());
        self
    }
}

/// (3 + √8)^{−n}: the accelerated series' truncation per unit of |μ|.
fn truncation(n: usize) -> f64 {
    (3.0 + 8f64.sqrt()).powi(-(n as i32))
}

/// |binom(1/2, j)| for j = 1 … MAX_TERMS: ½, ⅛, 1/16, …
fn binomial_half_abs() -> [f64; MAX_TERMS] {
    let mut b = [0.0; MAX_TERMS];
    b[0] = 0.5;
    for j in 1..MAX_TERMS {
        let m = j as f64; // b[j] = |β_{m+1}| = |β_m| (m − ½)/(m + 1)
        b[j] = b[j - 1] * (m - 0.5) / (m + 1.0);
    }
    b
}

/// Σ_{j≥0} (−1)^j a_j for moments a_j of a measure on [0, 1] (Cohen, Rodriguez Villegas and
/// Zagier, Algorithm 1), with `a.len()` terms; positive weights ≤ 1.
fn accelerated(a: &[Complex64]) -> Complex64 {
    let n = a.len();
    let nf = n as f64;
    let mut d = (3.0 + 8f64.sqrt()).powi(n as i32);
    d = 0.5 * (d + 1.0 / d);
    // The published recurrence with b and c divided by d from the start (it is linear in
    // them): every weight c stays in [0, 1], so no product overflows where a_k is near the top
    // of the f64 range (F ~ 1/(1 − x) at a resonance).
    let (mut b, mut c) = (-1.0 / d, -1.0f64);
    let mut s = Complex64::default();
    for (k, ak) in a.iter().enumerate() {
        let kf = k as f64;
        c = b - c;
        s += c * ak;
        b = (kf + nf) * (kf - nf) * b / ((kf + 0.5) * (kf + 1.0));
    }
    s
}

/// The fraction of a cycle of k·c (k an integer-valued f64, c in cycles), in [−1/2, 1/2]:
/// the product's rounding error is recovered exactly (fma), so the phase of r^K keeps the
/// accuracy of c however large K is.
fn frac_mul(k: f64, c: f64) -> f64 {
    let p = k * c;
    let e = k.mul_add(c, -p);
    let f = (p - p.round()) + e;
    f - f.round()
}

/// e^{re + 2πi cyc}.
fn cexp(re: f64, cyc: f64) -> Complex64 {
    let (s, co) = (TAU * cyc).sin_cos();
    let m = re.exp();
    Complex64::new(m * co, m * s)
}

/// e^{re + 2πi cyc} − 1 for cyc in [−1/2, 1/2], without cancellation near 0.
fn cexpm1(re: f64, cyc: f64) -> Complex64 {
    let th = TAU * cyc;
    let h = (0.5 * th).sin();
    Complex64::new(re.exp_m1() * th.cos() - 2.0 * h * h, re.exp() * th.sin())
}

/// e^{−shift} Σ_{k=1}^{n} e^{kλ}, λ = re + 2πi c (`nc` = frac(n c)), as
/// e^λ (e^{nλ − shift} − e^{−shift})/(e^λ − 1) without overflow (shift ≥ nRe λ when that is
/// large, which the callers ensure) and without cancellation near λ = 0.
fn finite_geometric(n: f64, re: f64, c: f64, nc: f64, shift: f64) -> Complex64 {
    let big = n * re;
    let top = if big <= 1.0 {
        (-shift).exp() * cexpm1(big, nc)
    } else {
        cexp(big - shift, nc) - (-shift).exp()
    };
    let den = cexpm1(re, c);
    if den == Complex64::default() {
        return Complex64::from(n * (-shift).exp());
    }
    cexp(re, c) * cdiv(top, den)
}

/// p/q by Smith's algorithm: num_complex divides by |q|², which underflows for |q| < 1e-154
/// (1 − |A| that small at a resonance gives F ~ 1e154 and more, still an f64).
fn cdiv(p: Complex64, q: Complex64) -> Complex64 {
    if q.re.abs() >= q.im.abs() {
        let r = q.im / q.re;
        let d = q.re + q.im * r;
        Complex64::new((p.re + p.im * r) / d, (p.im - p.re * r) / d)
    } else {
        let r = q.re / q.im;
        let d = q.re * r + q.im;
        Complex64::new((p.re * r + p.im) / d, (p.im * r - p.re) / d)
    }
}
