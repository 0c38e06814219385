//! Tests of `fringe::accumulate` (paper eqs. 4–6, docs/PHYSICS.md §3). Every check asserts and prints
//! actual, expected and error; each expected value says how it was derived, never from the code
//! under test.

use fringe::accumulate::columns::{
    ColumnKernel, ContributionColumns, accumulate_columns, accumulate_columns_par,
    accumulate_columns_using,
};
use fringe::accumulate::{
    Accumulator, Contribution, Summation, accumulate_points, accumulate_points_par, intensity,
    offsets_from_counts, phasor_from_cycles, phasors_from_cycles,
};
use num_complex::Complex64;
use proptest::prelude::*;
use std::f64::consts::TAU;

// ---------------------------------------------------------------------------------------------
// helpers
// ---------------------------------------------------------------------------------------------

/// SplitMix64, seeded.
struct Rng(u64);
impl Rng {
    fn next_u64(&mut self) -> u64 {
        self.0 = self.0.wrapping_add(0x9E37_79B9_7F4A_7C15);
        let mut z = self.0;
        z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
        z ^ (z >> 31)
    }
    /// Uniform in [0, 1).
    fn unit(&mut self) -> f64 {
        (self.next_u64() >> 11) as f64 * (1.0 / (1u64 << 53) as f64)
    }
    /// Uniform in [−1, 1).
    fn sym(&mut self) -> f64 {
        2.0 * self.unit() - 1.0
    }
    fn complex(&mut self) -> Complex64 {
        Complex64::new(self.sym(), self.sym())
    }
    fn field(&mut self) -> [Complex64; 3] {
        [self.complex(), self.complex(), self.complex()]
    }
}

fn assert_close(what: &str, actual: f64, expected: f64, tol: f64) {
    let err = (actual - expected).abs();
    println!(
        "{what}: actual {actual:.17e}, expected {expected:.17e}, err {err:.3e} (tol {tol:.1e})"
    );
    assert!(
        err <= tol,
        "{what}: actual {actual:e}, expected {expected:e}, err {err:e} > tol {tol:e}"
    );
}

fn c(id: u64, phase_cycles: f64, field: [Complex64; 3]) -> Contribution {
    Contribution {
        coherence_id: id,
        phase_cycles,
        field,
    }
}

fn scale(u: [Complex64; 3], a: Complex64) -> [Complex64; 3] {
    [u[0] * a, u[1] * a, u[2] * a]
}

fn norm2(u: &[Complex64; 3]) -> f64 {
    u.iter().map(|e| e.norm_sqr()).sum()
}

const ZERO3: [Complex64; 3] = [Complex64::new(0.0, 0.0); 3];

fn ex(a: f64) -> [Complex64; 3] {
    [
        Complex64::new(a, 0.0),
        Complex64::new(0.0, 0.0),
        Complex64::new(0.0, 0.0),
    ]
}

// ---------------------------------------------------------------------------------------------
// A double-double reference for e^{i 2π c}: independent of the code under test (Taylor series
// in ~106-bit arithmetic), accurate to ~1e-30 before the final rounding to f64.
// ---------------------------------------------------------------------------------------------

#[derive(Clone, Copy, Debug)]
struct Dd(f64, f64);

fn two_sum(a: f64, b: f64) -> Dd {
    let s = a + b;
    let z = s - a;
    Dd(s, (a - (s - z)) + (b - z))
}
fn two_prod(a: f64, b: f64) -> Dd {
    let p = a * b;
    Dd(p, a.mul_add(b, -p)) // fma: the exact error of the product
}
fn dd_add(a: Dd, b: Dd) -> Dd {
    let s = two_sum(a.0, b.0);
    let t = two_sum(a.1, b.1);
    let s = two_sum(s.0, s.1 + t.0);
    two_sum(s.0, s.1 + t.1)
}
fn dd_mul(a: Dd, b: Dd) -> Dd {
    let p = two_prod(a.0, b.0);
    two_sum(p.0, p.1 + (a.0 * b.1 + a.1 * b.0))
}
fn dd_div_f(a: Dd, b: f64) -> Dd {
    let q1 = a.0 / b;
    let r = dd_add(a, Dd(-two_prod(q1, b).0, -two_prod(q1, b).1));
    let q2 = r.0 / b;
    let r = dd_add(r, Dd(-two_prod(q2, b).0, -two_prod(q2, b).1));
    let q3 = r.0 / b;
    dd_add(two_sum(q1, q2), Dd(q3, 0.0))
}
/// 2π to ~2^-160 (three doubles: 6.283185307179586 + 2.4492935982947064e-16 − 5.989539619436679e-33).
const TWO_PI_DD: Dd = Dd(TAU, 2.449_293_598_294_706_4e-16);
const TWO_PI_3: f64 = -5.989_539_619_436_679e-33;

/// (cos 2πc, sin 2πc) from the double-double Taylor series, rounded to f64 at the end.
fn reference_phasor(cycles: f64) -> (f64, f64) {
    if !cycles.is_finite() {
        return (f64::NAN, f64::NAN);
    }
    let f = cycles - cycles.round(); // exact, |f| ≤ ½
    // Quadrant: f = q/4 + r, |r| ≤ 1/8, exact in f64.
    let q = (4.0 * f).round();
    let r = f - q / 4.0;
    let x = dd_add(dd_mul(TWO_PI_DD, Dd(r, 0.0)), Dd(TWO_PI_3 * r, 0.0)); // 2πr, |x| ≤ π/4
    let x2 = dd_mul(x, x);
    let (mut sin, mut cos) = (x, Dd(1.0, 0.0));
    let (mut ts, mut tc) = (x, Dd(1.0, 0.0));
    for k in 1..=15 {
        let k = k as f64;
        ts = dd_div_f(dd_mul(ts, x2), -(2.0 * k) * (2.0 * k + 1.0));
        tc = dd_div_f(dd_mul(tc, x2), -(2.0 * k - 1.0) * (2.0 * k));
        sin = dd_add(sin, ts);
        cos = dd_add(cos, tc);
    }
    let (s, co) = (sin.0 + sin.1, cos.0 + cos.1);
    match (q as i64).rem_euclid(4) {
        0 => (co, s),
        1 => (-s, co),
        2 => (-co, -s),
        _ => (s, -co),
    }
}

/// Max component error of each of `phasors` against the reference over `args`, with the
/// argument where it occurs.
fn max_errors<const K: usize>(
    args: &[f64],
    phasors: [&dyn Fn(f64) -> (f64, f64); K],
) -> [(f64, f64); K] {
    let mut worst = [(0.0, f64::NAN); K];
    for &a in args {
        let (rc, rs) = reference_phasor(a);
        for (w, phasor) in worst.iter_mut().zip(&phasors) {
            let (pc, ps) = phasor(a);
            let e = (pc - rc).abs().max((ps - rs).abs());
            if e > w.0 || e.is_nan() {
                *w = (e, a);
            }
        }
    }
    worst
}

fn libm_frac(c: f64) -> (f64, f64) {
    let (s, co) = (TAU * (c - c.round())).sin_cos();
    (co, s)
}

fn poly(c: f64) -> (f64, f64) {
    let p = phasor_from_cycles(c);
    (p.re, p.im)
}

/// Random and extreme phases: uniform up to 10^7 cycles, both signs, small ones, and every
/// reduction boundary (±½, ±⅜, ±¼, ±⅛, 0) approached to within a few ulps at several magnitudes.
fn test_arguments() -> Vec<f64> {
    let mut r = Rng(2024);
    let mut args = Vec::new();
    for _ in 0..500_000 {
        args.push(1e7 * r.sym());
    }
    for _ in 0..200_000 {
        args.push(r.sym());
    }
    for _ in 0..100_000 {
        args.push(r.sym() * 10f64.powf(-20.0 * r.unit()));
    }
    for _ in 0..200_000 {
        // n + frac with frac drawn near the octant boundaries.
        let n = (r.sym() * 1e7).round();
        let b = [-0.5, -0.375, -0.25, -0.125, 0.0, 0.125, 0.25, 0.375, 0.5]
            [(r.next_u64() % 9) as usize];
        args.push(n + b + r.sym() * 1e-6);
    }
    for &base in &[0.0, 1.0, 17.0, 1e3, 123_456.0, 1e6, 9_999_999.0, 4.5e15] {
        for b in [-0.5, -0.375, -0.25, -0.125, 0.0, 0.125, 0.25, 0.375, 0.5] {
            let x = base + b;
            let mut up = x;
            let mut down = x;
            for _ in 0..20 {
                args.push(up);
                args.push(down);
                args.push(-up);
                args.push(-down);
                up = up.next_up();
                down = down.next_down();
            }
        }
    }
    args.extend([
        f64::MIN_POSITIVE,
        5e-324,
        -5e-324,
        1e-300,
        2f64.powi(47) + 0.25,
        2f64.powi(48) - 0.5,
        2f64.powi(48) + 0.5,
        2f64.powi(50) + 0.75,
        2f64.powi(51) + 0.5,
        2f64.powi(52) - 0.5,
        2f64.powi(52) + 1.0,
        2f64.powi(60),
        1e300,
        -1e300,
    ]);
    args
}

// ---------------------------------------------------------------------------------------------
// phasor
// ---------------------------------------------------------------------------------------------

#[test]
fn reference_phasor_agrees_with_libm_at_small_arguments() {
    // Validates the reference itself: for |c| < 1 libm's sin_cos(2πc) is within ~1 ulp.
    let mut r = Rng(5);
    let args: Vec<f64> = (0..100_000).map(|_| r.sym()).collect();
    let [(err, at)] = max_errors(&args, [&libm_frac]);
    println!("reference vs libm sin_cos(2π·frac): max err {err:.3e} at c = {at:e}");
    assert_close("reference vs libm", err, 0.0, 4.5e-16);
}

#[test]
fn phasor_polynomial_is_as_accurate_as_libm() {
    let args = test_arguments();
    let [(e_poly, at_poly), (e_libm, at_libm)] = max_errors(&args, [&poly, &libm_frac]);
    let mut d_libm: f64 = 0.0;
    for &a in &args {
        let (pc, ps) = poly(a);
        let (lc, ls) = libm_frac(a);
        d_libm = d_libm.max((pc - lc).abs()).max((ps - ls).abs());
    }
    println!(
        "{} arguments (random up to 1e7 cycles, small, boundary ±ulps, ≥ 2^48)",
        args.len()
    );
    println!("polynomial  vs double-double reference: max err {e_poly:.3e} at c = {at_poly:e}");
    println!("libm frac   vs double-double reference: max err {e_libm:.3e} at c = {at_libm:e}");
    println!("polynomial  vs libm sin_cos(2π·frac):   max |diff| {d_libm:.3e}");
    assert!(
        e_poly <= e_libm,
        "polynomial error {e_poly:e} exceeds libm's {e_libm:e}"
    );
    assert_close("polynomial max error vs reference", e_poly, 0.0, 1.2e-16);
    assert_close("polynomial vs libm", d_libm, 0.0, 1e-15);
}

#[test]
fn phasor_of_full_phase_in_radians_loses_digits() {
    // Why phase is kept in cycles: sin_cos(2π·c) on the full phase rounds 2π·c to ulp(2π·c).
    let c0 = 9_999_999.0 + 0.123_456_789;
    let (rc, rs) = reference_phasor(c0);
    let (s, co) = (TAU * c0).sin_cos();
    let err_full = (co - rc).abs().max((s - rs).abs());
    let (pc, ps) = poly(c0);
    let err_poly = (pc - rc).abs().max((ps - rs).abs());
    println!("c = {c0}: full-phase libm err {err_full:.3e}, cycles polynomial err {err_poly:.3e}");
    assert!(
        err_full > 1e-10,
        "expected the full-phase evaluation to lose digits"
    );
    assert_close("cycles polynomial at 1e7 cycles", err_poly, 0.0, 1.2e-16);
}

#[test]
fn phasor_exact_values_and_non_finite() {
    // Exact values: e^{i2πn} = 1, e^{iπ} = −1, e^{±iπ/2} = ±i (multiples of ¼ cycle).
    for (cyc, re, im) in [
        (0.0, 1.0, 0.0),
        (3.0, 1.0, 0.0),
        (-7.0, 1.0, 0.0),
        (0.25, 0.0, 1.0),
        (0.5, -1.0, 0.0),
        (-0.25, 0.0, -1.0),
        (1e6 + 0.75, 0.0, -1.0),
        (2f64.powi(50) + 0.5, -1.0, 0.0),
    ] {
        let p = phasor_from_cycles(cyc);
        assert_close(&format!("re e^(i2π·{cyc})"), p.re, re, 0.0);
        assert_close(&format!("im e^(i2π·{cyc})"), p.im, im, 0.0);
    }
    for bad in [f64::NAN, f64::INFINITY, f64::NEG_INFINITY] {
        let p = phasor_from_cycles(bad);
        println!("phasor({bad}) = {p}");
        assert!(p.re.is_nan() && p.im.is_nan());
    }
}

#[test]
fn batch_phasors_equal_scalar_bit_for_bit() {
    let mut args = test_arguments();
    args.truncate(300_000);
    args.extend(test_arguments().iter().rev().take(2000)); // the extremes
    args.push(f64::NAN);
    let mut out = vec![Complex64::default(); args.len()];
    phasors_from_cycles(&args, &mut out);
    let mut mismatches = 0;
    for (a, o) in args.iter().zip(&out) {
        let p = phasor_from_cycles(*a);
        if p.re.to_bits() != o.re.to_bits() || p.im.to_bits() != o.im.to_bits() {
            mismatches += 1;
        }
    }
    println!(
        "batch vs scalar phasors: {mismatches} mismatches of {}",
        args.len()
    );
    assert_eq!(mismatches, 0);
}

#[test]
fn huge_integer_parts_give_the_same_intensity() {
    // c and N + c describe the same phase for integer N. f is first made exactly representable
    // at N's magnitude ((N + f) − N is exact), so both contributions carry the same phase.
    let mut r = Rng(11);
    let u = r.field();
    for &n in &[
        1e6,
        -1e6,
        12_345_678.0,
        2f64.powi(40),
        1e12,
        2f64.powi(49),
        2f64.powi(51),
    ] {
        for _ in 0..50 {
            let f0 = r.sym();
            let f = (n + f0) - n;
            let m = 3.0 * n.signum(); // another integer offset
            let g = (m + r.sym()) - m; // exact at m's magnitude
            let small = [c(1, 0.1, u), c(1, f, scale(u, r.complex())), c(1, g, u)];
            let mut big = small;
            big[1].phase_cycles = n + f;
            big[2].phase_cycles = m + g;
            let (i_small, i_big) = (intensity(&small), intensity(&big));
            assert!(
                i_small.to_bits() == i_big.to_bits(),
                "N = {n}, f = {f}: I(f) = {i_small:e}, I(N + f) = {i_big:e}, err {:e}",
                (i_small - i_big).abs()
            );
        }
        println!("N = {n:e}: I(N + f) == I(f) bit for bit (50 random cases)");
    }
}

// ---------------------------------------------------------------------------------------------
// the physics of eqs. 4–6
// ---------------------------------------------------------------------------------------------

#[test]
fn two_parallel_fields_follow_p10() {
    // E1 = a1·u, E2 = a2·u with u a unit complex 3-vector and a1, a2 complex: parallel fields.
    // P10: I = I1 + I2 + 2√(I1 I2) cos δ, δ = 2π(c2 − c1) + arg a2 − arg a1, I_k = |a_k|².
    // Expected value from libm cos of δ built from the fractional phase difference.
    let mut r = Rng(3);
    let mut worst: f64 = 0.0;
    for case in 0..2000 {
        let mut u = r.field();
        let n = norm2(&u).sqrt();
        u = scale(u, Complex64::from(1.0 / n));
        let (a1, a2) = (r.complex(), r.complex());
        let (c1, c2) = (1e5 * r.unit(), 1e5 * r.unit());
        let contribs = [c(7, c1, scale(u, a1)), c(7, c2, scale(u, a2))];
        let (i1, i2) = (a1.norm_sqr(), a2.norm_sqr());
        let dfrac = (c2 - c2.round()) - (c1 - c1.round());
        let delta = TAU * dfrac + a2.arg() - a1.arg();
        let expected = i1 + i2 + 2.0 * (i1 * i2).sqrt() * delta.cos();
        let actual = intensity(&contribs);
        let err = (actual - expected).abs() / (i1 + i2);
        worst = worst.max(err);
        if case < 3 {
            println!(
                "P10 case {case}: actual {actual:.15e}, expected {expected:.15e}, rel err {err:.2e}"
            );
        }
        assert!(
            err < 1e-13,
            "case {case}: actual {actual:e}, expected {expected:e}, rel err {err:e}"
        );
    }
    println!("P10: 2000 random cases, max error / (I1 + I2) = {worst:.2e}");
    // The two classic extremes: δ = 0 → (√I1 + √I2)², δ = π → (√I1 − √I2)².
    let u = ex(1.0);
    let bright = intensity(&[c(1, 10.0, scale(u, 2.0.into())), c(1, 1e6 + 3.0, u)]);
    assert_close("P10 δ = 0: (2 + 1)²", bright, 9.0, 1e-14);
    let dark = intensity(&[c(1, 10.0, scale(u, 2.0.into())), c(1, 1e6 + 0.5, u)]);
    assert_close("P10 δ = π: (2 − 1)²", dark, 1.0, 1e-14);
}

#[test]
fn orthogonal_fields_do_not_interfere() {
    // E1·E2* = 0 → |E1 e^{iφ1} + E2 e^{iφ2}|² = |E1|² + |E2|² for every phase difference.
    let mut r = Rng(4);
    for case in 0..1000 {
        // A random complex vector and one orthogonal to it in the Hermitian sense.
        let e1 = r.field();
        let w = r.field();
        let dot: Complex64 = (0..3).map(|k| w[k] * e1[k].conj()).sum();
        let k = dot / norm2(&e1);
        let e2 = [w[0] - k * e1[0], w[1] - k * e1[1], w[2] - k * e1[2]];
        let contribs = [c(3, 1e4 * r.unit(), e1), c(3, 1e4 * r.unit(), e2)];
        let expected = norm2(&e1) + norm2(&e2);
        let actual = intensity(&contribs);
        if case < 3 {
            println!("orthogonal case {case}: actual {actual:.15e}, expected {expected:.15e}");
        }
        assert!(
            (actual - expected).abs() <= 1e-13 * expected,
            "case {case}: actual {actual:e}, expected {expected:e}"
        );
    }
    // x̂ and ŷ at the phases that would give full fringes if they were parallel.
    for d in [0.0, 0.25, 0.5] {
        let i = intensity(&[
            c(1, 0.0, ex(1.0)),
            c(1, d, [ZERO3[0], Complex64::new(1.0, 0.0), ZERO3[0]]),
        ]);
        assert_close(&format!("x̂ + ŷ at δ = {d} cycles"), i, 2.0, 1e-15);
    }
}

#[test]
fn different_ids_add_intensities() {
    // Mutually incoherent groups: I = |E1|² + |E2|² whatever the phases, even for parallel fields.
    let mut r = Rng(6);
    for case in 0..1000 {
        let u = r.field();
        let (a1, a2) = (r.complex(), r.complex());
        let contribs = [
            c(1, 1e5 * r.unit(), scale(u, a1)),
            c(2, 1e5 * r.unit(), scale(u, a2)),
        ];
        let expected = norm2(&u) * (a1.norm_sqr() + a2.norm_sqr());
        let actual = intensity(&contribs);
        if case < 3 {
            println!("ids 1 and 2, case {case}: actual {actual:.15e}, expected {expected:.15e}");
        }
        assert!(
            (actual - expected).abs() <= 1e-13 * expected,
            "case {case}: {actual:e} vs {expected:e}"
        );
    }
}

#[test]
fn id_zero_adds_squared_norms() {
    // id 0 is coherent with nothing, not even another id-0 ray: I = Σ |E_j|².
    let mut r = Rng(8);
    let u = ex(1.0);
    let contribs = [c(0, 0.0, u), c(0, 0.5, u), c(0, 0.3, scale(u, 2.0.into()))];
    assert_close(
        "three id-0 rays 1 + 1 + 4",
        intensity(&contribs),
        6.0,
        1e-15,
    );
    for _ in 0..200 {
        let fs: Vec<[Complex64; 3]> = (0..5).map(|_| r.field()).collect();
        let contribs: Vec<Contribution> = fs.iter().map(|f| c(0, 1e6 * r.sym(), *f)).collect();
        let expected: f64 = fs.iter().map(norm2).sum();
        let actual = intensity(&contribs);
        assert!(
            (actual - expected).abs() <= 1e-14 * expected,
            "{actual:e} vs {expected:e}"
        );
    }
    // Mixed with a coherent pair: the id-0 term adds to the pair's P10 intensity.
    let mixed = [
        c(5, 0.0, u),
        c(0, 0.123, scale(u, 3.0.into())),
        c(5, 2.0, u),
    ];
    assert_close(
        "coherent pair (4) + id-0 ray (9)",
        intensity(&mixed),
        13.0,
        1e-14,
    );
}

#[test]
fn groups_report_summed_fields_in_order_of_first_appearance() {
    let mut acc = Accumulator::new();
    let u = ex(1.0);
    acc.add(&c(9, 0.0, u));
    acc.add(&c(4, 0.25, u)); // i
    acc.add(&c(9, 0.5, scale(u, 3.0.into()))); // −3
    acc.add(&c(0, 0.0, u));
    let g = acc.groups();
    println!("groups: {g:?}");
    assert_eq!(g.len(), 2);
    assert_eq!((g[0].0, g[1].0), (9, 4));
    assert_close("E_9.x.re (1 − 3)", g[0].1[0].re, -2.0, 1e-15);
    assert_close("E_4.x.im (i)", g[1].1[0].im, 1.0, 1e-15);
    assert_close("I = 4 + 1 + 1", acc.intensity(), 6.0, 1e-15);
    // The view follows later additions.
    acc.add(&c(4, 0.75, u)); // −i cancels
    assert_close("E_4.x.im after −i", acc.groups()[1].1[0].im, 0.0, 1e-15);
    acc.clear();
    assert!(acc.groups().is_empty());
    assert_close("cleared", acc.intensity(), 0.0, 0.0);
}

// ---------------------------------------------------------------------------------------------
// batches
// ---------------------------------------------------------------------------------------------

/// Independent reference: libm phasor of the fraction, linear group search, plain sums.
fn naive_intensity(cs: &[Contribution]) -> f64 {
    let mut groups: Vec<(u64, [Complex64; 3])> = Vec::new();
    let mut inc = 0.0;
    for k in cs {
        if k.coherence_id == 0 {
            inc += norm2(&k.field);
            continue;
        }
        let (co, s) = libm_frac(k.phase_cycles);
        let ph = Complex64::new(co, s);
        match groups.iter_mut().find(|(id, _)| *id == k.coherence_id) {
            Some((_, e)) => (0..3).for_each(|i| e[i] += k.field[i] * ph),
            None => groups.push((k.coherence_id, scale(k.field, ph))),
        }
    }
    inc + groups.iter().map(|(_, e)| norm2(e)).sum::<f64>()
}

fn random_points(
    r: &mut Rng,
    points: usize,
    max_per_point: usize,
    ids: u64,
) -> (Vec<Contribution>, Vec<usize>) {
    let counts: Vec<usize> = (0..points)
        .map(|_| (r.next_u64() % (max_per_point as u64 + 1)) as usize)
        .collect();
    let total: usize = counts.iter().sum();
    let contribs = (0..total)
        .map(|_| {
            let id = r.next_u64() % (ids + 1); // includes id 0
            let id = if id > 0 { id * 1_000_003 } else { 0 }; // sparse ids
            c(id, 1e6 * r.sym(), r.field())
        })
        .collect();
    (contribs, offsets_from_counts(&counts))
}

#[test]
fn batch_and_parallel_equal_the_simple_api() {
    let mut r = Rng(9);
    for &(points, max_per, ids) in &[
        (1000usize, 40usize, 3u64),
        (200, 300, 40),
        (50, 2000, 200),
        (3, 0, 1),
    ] {
        let (d, offsets) = random_points(&mut r, points, max_per, ids);
        for s in [Summation::Compensated, Summation::Plain] {
            let mut serial = vec![0.0; points];
            let mut par = vec![0.0; points];
            accumulate_points(&d, &offsets, s, &mut serial);
            accumulate_points_par(&d, &offsets, s, &mut par);
            let mut worst_naive: f64 = 0.0;
            for k in 0..points {
                let cs = &d[offsets[k]..offsets[k + 1]];
                let mut acc = Accumulator::with_summation(s);
                for x in cs {
                    acc.add(x);
                }
                let simple = acc.intensity();
                assert_eq!(
                    serial[k].to_bits(),
                    simple.to_bits(),
                    "point {k}: batch {} vs add {}",
                    serial[k],
                    simple
                );
                assert_eq!(
                    par[k].to_bits(),
                    simple.to_bits(),
                    "point {k}: parallel {} vs add {}",
                    par[k],
                    simple
                );
                if s == Summation::Compensated {
                    assert_eq!(simple.to_bits(), intensity(cs).to_bits());
                }
                let naive = naive_intensity(cs);
                let scale_k: f64 = cs.iter().map(|x| norm2(&x.field)).sum::<f64>().max(1e-300);
                worst_naive = worst_naive.max((simple - naive).abs() / scale_k);
            }
            println!(
                "{points} points, ≤ {max_per} contributions, {ids} ids, {s:?}: batch == parallel == add bit for bit; \
                 max |I − naive libm| / Σ|E|² = {worst_naive:.2e}"
            );
            assert!(worst_naive < 1e-13);
        }
    }
}

#[test]
#[should_panic(expected = "offsets")]
fn batch_rejects_bad_offsets() {
    let d = [c(1, 0.0, ex(1.0))];
    let mut out = [0.0; 1];
    accumulate_points(&d, &[0, 2], Summation::Plain, &mut out);
}

// ---------------------------------------------------------------------------------------------
// compensated summation
// ---------------------------------------------------------------------------------------------

/// Intensity with the given summation.
fn intensity_with(s: Summation, cs: &[Contribution]) -> f64 {
    let mut acc = Accumulator::with_summation(s);
    acc.extend(cs);
    acc.intensity()
}

#[test]
fn one_large_and_a_million_tiny_terms_in_one_group() {
    // E = 1 + 10^6·2^-54 exactly: every tiny term is 2^-54 at an integer phase (e^{i2πn} = 1
    // exactly, checked below). A plain sum rounds 1 + 2^-54 back to 1 every time and ends at
    // exactly 1; the true intensity is (1 + δ)² with δ = 10^6·2^-54 ≈ 5.55e-11.
    let tiny = 2f64.powi(-54);
    let n = 1_000_000;
    let mut cs = vec![c(1, 0.0, ex(1.0))];
    for j in 0..n {
        let phase = (j % 1000) as f64 * 1e3; // integer cycles up to 10^6
        assert_eq!(phasor_from_cycles(phase), Complex64::new(1.0, 0.0));
        cs.push(c(1, phase, ex(tiny)));
    }
    let delta = n as f64 * tiny; // exact
    let expected = 1.0 + 2.0 * delta + delta * delta;
    let tol = 4e-16;
    let plain = intensity_with(Summation::Plain, &cs);
    let comp = intensity_with(Summation::Compensated, &cs);
    println!(
        "plain: actual {plain:.17e}, expected {expected:.17e}, err {:.3e}",
        (plain - expected).abs()
    );
    assert!(
        (plain - expected).abs() > tol,
        "the plain sum was expected to lose the tiny terms"
    );
    assert_close("compensated 1 + 10^6 tiny", comp, expected, tol);
    // Same through the batch API.
    let mut out = [0.0];
    accumulate_points_par(&cs, &[0, cs.len()], Summation::Compensated, &mut out);
    assert_close("compensated batch", out[0], expected, tol);
}

#[test]
fn a_million_unit_phasors_cancelling_to_a_small_field() {
    // N = 2^20 unit contributions at phases j/N (+ random integer offsets, in shuffled order)
    // plus one of amplitude a at phase 0. Σ_j e^{i2πj/N} = 0, and the computed phasors cancel
    // exactly in pairs (phase j/N + ½ gives exactly −phasor(j/N), checked below: j/N and
    // j/N + ½ are exact in f64), so the exact sum of the computed terms is a and I = a².
    let n: usize = 1 << 20;
    let a = 1e-3;
    let mut r = Rng(12);
    let mut cs: Vec<Contribution> = (0..n)
        .map(|j| {
            let offset = (r.next_u64() % 1_000_000) as f64;
            c(77, offset + j as f64 / n as f64, ex(1.0))
        })
        .collect();
    for j in 0..n / 2 {
        let (p, q) = (
            phasor_from_cycles(cs[j].phase_cycles),
            phasor_from_cycles(cs[j + n / 2].phase_cycles),
        );
        assert!(
            p == -q,
            "phasor pair {j} does not cancel exactly: {p} vs {q}"
        );
    }
    cs.push(c(77, 5.0, ex(a)));
    for k in (1..cs.len()).rev() {
        let m = (r.next_u64() % (k as u64 + 1)) as usize;
        cs.swap(k, m);
    }
    let expected = a * a;
    let tol = 1e-12 * expected;
    let plain = intensity_with(Summation::Plain, &cs);
    let comp = intensity_with(Summation::Compensated, &cs);
    println!(
        "plain: actual {plain:.17e}, expected {expected:.17e}, rel err {:.3e}",
        (plain - expected).abs() / expected
    );
    assert!(
        (plain - expected).abs() > tol,
        "the plain sum was expected to lose digits"
    );
    assert_close(
        "compensated 2^20 cancelling phasors + a",
        comp,
        expected,
        tol,
    );
}

#[test]
fn incoherent_sum_is_compensated_too() {
    // 1 + 10^6 × 2^-54 with |E|² = 2^-54 per tiny id-0 ray (E = 2^-27).
    let n = 1_000_000;
    let mut cs = vec![c(0, 0.0, ex(1.0))];
    cs.extend((0..n).map(|_| c(0, 0.0, ex(2f64.powi(-27)))));
    let expected = 1.0 + n as f64 * 2f64.powi(-54);
    let plain = intensity_with(Summation::Plain, &cs);
    let comp = intensity_with(Summation::Compensated, &cs);
    println!(
        "plain: actual {plain:.17e}, expected {expected:.17e}, err {:.3e}",
        (plain - expected).abs()
    );
    assert!((plain - expected).abs() > 2e-16);
    assert_close("compensated incoherent", comp, expected, 2.3e-16);
}

#[test]
fn many_groups_at_one_point() {
    // 5000 distinct ids (the id table grows and rehashes), each with a P10 pair at δ = 0:
    // I = Σ_g (|a_g| + |b_g|)² for parallel real fields at equal phase.
    let mut r = Rng(13);
    let mut cs = Vec::new();
    let mut expected = 0.0;
    for g in 0..5000u64 {
        let (a, b) = (r.unit(), r.unit());
        let id = g.wrapping_mul(0x1000_0000_0001) + 1;
        cs.push(c(id, 3.0 + 0.1, ex(a)));
        cs.push(c(id, 1e6 + 0.1, ex(b)));
        expected += (a + b) * (a + b);
    }
    // Interleave the pairs so the table sees every id twice far apart.
    let (first, second): (Vec<_>, Vec<_>) = cs.chunks(2).map(|p| (p[0], p[1])).unzip();
    let cs: Vec<_> = first.into_iter().chain(second).collect();
    let mut acc = Accumulator::new();
    acc.extend(&cs);
    assert_eq!(acc.groups().len(), 5000);
    assert_close("5000 groups", acc.intensity(), expected, 1e-12 * expected);
}

// ---------------------------------------------------------------------------------------------
// columns (structure of arrays)
// ---------------------------------------------------------------------------------------------

/// The group fields and intensity of `cs` added one by one with [`Accumulator::add`].
fn added_one_by_one(s: Summation, cs: &[Contribution]) -> (f64, Vec<(u64, [Complex64; 3])>) {
    let mut acc = Accumulator::with_summation(s);
    for x in cs {
        acc.add(x);
    }
    (acc.intensity(), acc.groups().to_vec())
}

/// The same through [`Accumulator::extend_columns`].
fn added_as_columns(s: Summation, cs: &[Contribution]) -> (f64, Vec<(u64, [Complex64; 3])>) {
    let cols = ContributionColumns::from(cs);
    let mut acc = Accumulator::with_summation(s);
    acc.extend_columns(&cols.coherence_ids, &cols.phase_cycles, &cols.fields);
    (acc.intensity(), acc.groups().to_vec())
}

/// The same through [`Accumulator::extend_columns_using`] with the given kernel.
fn added_as_columns_using(
    kernel: ColumnKernel,
    s: Summation,
    cs: &[Contribution],
) -> (f64, Vec<(u64, [Complex64; 3])>) {
    let cols = ContributionColumns::from(cs);
    let mut acc = Accumulator::with_summation(s);
    acc.extend_columns_using(
        kernel,
        &cols.coherence_ids,
        &cols.phase_cycles,
        &cols.fields,
    );
    (acc.intensity(), acc.groups().to_vec())
}

/// Every column kernel the running CPU has (the explicit ones, so that on an AVX-512 machine
/// the AVX2 and portable kernels are checked too, not only the one `Auto` picks).
fn column_kernels() -> Vec<ColumnKernel> {
    [
        ColumnKernel::Portable,
        ColumnKernel::Avx2,
        ColumnKernel::Avx512,
    ]
    .into_iter()
    .filter(|k| k.available())
    .collect()
}

/// Bit-for-bit equality of intensities and of every group's id and field components.
fn assert_same_bits(
    what: &str,
    a: &(f64, Vec<(u64, [Complex64; 3])>),
    b: &(f64, Vec<(u64, [Complex64; 3])>),
) {
    assert_eq!(
        a.0.to_bits(),
        b.0.to_bits(),
        "{what}: intensity {:e} vs {:e}",
        a.0,
        b.0
    );
    assert_eq!(a.1.len(), b.1.len(), "{what}: number of groups");
    for ((ia, ea), (ib, eb)) in a.1.iter().zip(&b.1) {
        assert_eq!(ia, ib, "{what}: group order");
        for k in 0..3 {
            assert!(
                ea[k].re.to_bits() == eb[k].re.to_bits()
                    && ea[k].im.to_bits() == eb[k].im.to_bits(),
                "{what}: group {ia} component {k}: {} vs {}",
                ea[k],
                eb[k]
            );
        }
    }
}

#[test]
fn columns_equal_the_rows_bit_for_bit() {
    // Random points with id 0, sparse ids, 1…200 groups per point (the first four go through
    // the kernel's 4-id compare, later ones through the hash table), both summations, serial
    // and parallel; plus the independent libm reference.
    let mut r = Rng(21);
    for &(points, max_per, ids) in &[
        (1000usize, 70usize, 4u64),
        (300, 200, 9),
        (40, 1500, 200),
        (3, 0, 1),
    ] {
        let (d, offsets) = random_points(&mut r, points, max_per, ids);
        let cols = ContributionColumns::from(&d[..]);
        assert_eq!(cols.len(), d.len());
        for s in [Summation::Compensated, Summation::Plain] {
            let (mut rows, mut serial, mut par) =
                (vec![0.0; points], vec![0.0; points], vec![0.0; points]);
            accumulate_points(&d, &offsets, s, &mut rows);
            accumulate_columns(&cols, &offsets, s, &mut serial);
            accumulate_columns_par(&cols, &offsets, s, &mut par);
            for kernel in column_kernels() {
                let mut using = vec![0.0; points];
                accumulate_columns_using(kernel, &cols, &offsets, s, &mut using);
                for k in 0..points {
                    assert_eq!(
                        using[k].to_bits(),
                        rows[k].to_bits(),
                        "point {k} {s:?}: columns {kernel:?} {:e} vs rows {:e}",
                        using[k],
                        rows[k]
                    );
                }
            }
            let mut worst_naive: f64 = 0.0;
            for k in 0..points {
                let cs = &d[offsets[k]..offsets[k + 1]];
                let one = added_one_by_one(s, cs);
                assert_same_bits(&format!("point {k} {s:?}"), &one, &added_as_columns(s, cs));
                for kernel in column_kernels() {
                    assert_same_bits(
                        &format!("point {k} {s:?} {kernel:?}"),
                        &one,
                        &added_as_columns_using(kernel, s, cs),
                    );
                }
                for (name, v) in [
                    ("rows", rows[k]),
                    ("columns", serial[k]),
                    ("columns par", par[k]),
                ] {
                    assert_eq!(
                        v.to_bits(),
                        one.0.to_bits(),
                        "point {k} {s:?}: {name} {v:e} vs add {:e}",
                        one.0
                    );
                }
                let naive = naive_intensity(cs);
                let scale_k: f64 = cs.iter().map(|x| norm2(&x.field)).sum::<f64>().max(1e-300);
                worst_naive = worst_naive.max((one.0 - naive).abs() / scale_k);
            }
            println!(
                "{points} points, ≤ {max_per} contributions, {ids} ids, {s:?}: columns == columns par \
                 == rows == add bit for bit; max |I − naive libm| / Σ|E|² = {worst_naive:.2e}"
            );
            assert!(worst_naive < 1e-13);
        }
    }
}

#[test]
fn columns_take_the_wide_phase_path_like_the_rows() {
    // Phases ≥ 2^48 cycles (and a NaN) send a whole block of the column kernel to
    // `phasor_from_cycles`; the block's other contributions must not change.
    let mut r = Rng(22);
    let mut cs: Vec<Contribution> = (0..200)
        .map(|j| c(1 + j % 6, 1e6 * r.sym(), r.field()))
        .collect();
    cs[70].phase_cycles = 2f64.powi(50) + 0.25;
    cs[71].phase_cycles = -3e15;
    for s in [Summation::Compensated, Summation::Plain] {
        assert_same_bits(
            &format!("wide phases {s:?}"),
            &added_one_by_one(s, &cs),
            &added_as_columns(s, &cs),
        );
        let mut nan = cs.clone();
        nan[5].phase_cycles = f64::NAN;
        let (a, b) = (added_one_by_one(s, &nan).0, added_as_columns(s, &nan).0);
        println!("NaN phase {s:?}: add {a}, columns {b}");
        assert!(a.is_nan() && b.is_nan());
        for kernel in column_kernels() {
            assert_same_bits(
                &format!("wide phases {s:?} {kernel:?}"),
                &added_one_by_one(s, &cs),
                &added_as_columns_using(kernel, s, &cs),
            );
            let b = added_as_columns_using(kernel, s, &nan).0;
            println!("NaN phase {s:?}: {kernel:?} {b}");
            assert!(b.is_nan());
        }
    }
}

/// Ids that walk every branch of the kernels' group search: the ids of one point, 150
/// contributions (blocks of 64, 64 and 22: chunks of eight and a tail of six).
fn crafted_ids() -> Vec<u64> {
    let mut ids: Vec<u64> = (0..150).map(|j| [7, 13][j % 2]).collect();
    ids[3] = 0; // id 0 in the first chunk (two groups exist)
    ids[40] = 11; // a third group first seen in a later chunk of the first block
    ids[66] = 17; // a fourth group first seen in the second block
    ids[70] = 19; // a fifth group (past the 4-id compare), in the second block
    ids[71] = 0; // id 0 next to it
    for j in (72..128).step_by(5) {
        ids[j] = [11, 17, 19][j % 3]; // all five groups mixed in full chunks
    }
    ids[130] = 23; // a sixth group in the third block's chunks
    ids[147] = 29; // a seventh in its six-contribution tail
    ids[148] = 0;
    ids
}

/// Ids whose chunks of eight mix several new ids, repeated, with id 0 and known groups (the
/// AVX-512F kernel's one group lookup per distinct new id of a chunk): 70 contributions.
fn crafted_new_ids_in_chunks() -> Vec<u64> {
    let mut ids = vec![
        3, 5, 3, 0, 9, 5, 0, 9, // three new groups, each twice, id 0 between them
        21, 3, 22, 21, 0, 23, 22,
        5, // a fourth, fifth and sixth group, repeated, in one chunk
        22, 22, 22, 22, 22, 22, 22, 22, // a hashed group only
        24, 24, 0, 0, 3, 25, 24, 25, // two more new ids among known ones
    ];
    ids.extend((0..38).map(|j| [3, 5, 9, 21, 22, 23, 24, 25, 0][j % 9]));
    ids
}

#[test]
fn column_kernels_walk_every_group_search_branch() {
    // Every kernel against `Accumulator::add` one by one, bit for bit (intensity, groups in order
    // of first appearance, their fields), both summations: the crafted point above; the same
    // with only the first four groups (all chunks after the first take the 8-lane compare);
    // several new ids in one chunk of eight (`crafted_new_ids_in_chunks`); one contribution; one of
    // id 0; and a batch of those points with an empty one.
    let mut r = Rng(29);
    let crafted: Vec<Contribution> = crafted_ids()
        .into_iter()
        .map(|id| c(id, 1e6 * r.sym(), r.field()))
        .collect();
    let four: Vec<Contribution> = (0..200)
        .map(|j| {
            c(
                [7, 13, 11, 17][(j * 7 + j / 3) % 4],
                1e6 * r.sym(),
                r.field(),
            )
        })
        .collect();
    let new_in_chunks: Vec<Contribution> = crafted_new_ids_in_chunks()
        .into_iter()
        .map(|id| c(id, 1e6 * r.sym(), r.field()))
        .collect();
    let one = vec![c(5, 0.3, r.field())];
    let zero = vec![c(0, 0.3, r.field())];
    let points: [&[Contribution]; 6] = [&crafted, &four, &new_in_chunks, &one, &zero, &[]];
    for s in [Summation::Compensated, Summation::Plain] {
        for (k, cs) in points.iter().enumerate() {
            let by_add = added_one_by_one(s, cs);
            let groups = by_add.1.len();
            for kernel in column_kernels() {
                assert_same_bits(
                    &format!(
                        "point {k} ({} contributions, {groups} groups) {s:?} {kernel:?}",
                        cs.len()
                    ),
                    &by_add,
                    &added_as_columns_using(kernel, s, cs),
                );
            }
        }
        assert_eq!(added_one_by_one(s, &crafted).1.len(), 7);
        assert_eq!(added_one_by_one(s, &new_in_chunks).1.len(), 8);
        let all: Vec<Contribution> = points.iter().flat_map(|cs| cs.iter().copied()).collect();
        let offsets = offsets_from_counts(&points.map(|cs| cs.len()));
        let cols = ContributionColumns::from(&all[..]);
        for kernel in column_kernels() {
            let mut out = [0.0; 6];
            accumulate_columns_using(kernel, &cols, &offsets, s, &mut out);
            for (k, cs) in points.iter().enumerate() {
                assert_eq!(
                    out[k].to_bits(),
                    added_one_by_one(s, cs).0.to_bits(),
                    "batch point {k} {s:?} {kernel:?}"
                );
            }
        }
    }
}

#[test]
fn columns_ignore_the_next_field_read_with_a_field() {
    // The AVX-512F kernel reads each field but the last of the columns with one 64-byte load,
    // which also holds the next field's x (lanes 6, 7, only ever added to the sums' padding).
    // Points of 1, 7, 64, 65 and 130 contributions (the last of a block, of a point, of the
    // columns; > 4 groups, id 0 mixed in), each followed in the columns by a point whose first
    // field's x is NaN, ±∞ or 1e300: every point but those gives `Accumulator::add`'s bits,
    // whichever kernel, both summations.
    let mut r = Rng(31);
    let mut points: Vec<Vec<Contribution>> = Vec::new();
    for (k, n) in [1usize, 7, 64, 65, 130].into_iter().enumerate() {
        points.push(
            (0..n)
                .map(|j| {
                    c(
                        [0, 3, 5, 8, 13, 21][(j * 5 + k) % 6],
                        1e6 * r.sym(),
                        r.field(),
                    )
                })
                .collect(),
        );
        let mut bad = r.field();
        bad[0] = [
            Complex64::new(f64::NAN, f64::NAN),
            Complex64::new(f64::INFINITY, f64::NEG_INFINITY),
            Complex64::new(1e300, -1e300),
        ][k % 3];
        points.push(vec![c(3, 0.25, bad), c(5, 0.5, r.field())]);
    }
    let all: Vec<Contribution> = points.iter().flatten().copied().collect();
    let offsets = offsets_from_counts(&points.iter().map(Vec::len).collect::<Vec<_>>());
    let cols = ContributionColumns::from(&all[..]);
    for s in [Summation::Compensated, Summation::Plain] {
        for kernel in column_kernels() {
            let mut out = vec![0.0; points.len()];
            accumulate_columns_using(kernel, &cols, &offsets, s, &mut out);
            for (k, cs) in points.iter().enumerate().step_by(2) {
                let expected = added_one_by_one(s, cs).0;
                assert!(expected.is_finite());
                assert_eq!(
                    out[k].to_bits(),
                    expected.to_bits(),
                    "point {k} ({} contributions) {s:?} {kernel:?}: {:e} vs {expected:e}",
                    cs.len(),
                    out[k]
                );
            }
            // Within one point too: the next field of a group's contribution is non-finite.
            let mut acc = Accumulator::with_summation(s);
            let (a, b) = (offsets[2], offsets[4]);
            acc.extend_columns_using(
                kernel,
                &cols.coherence_ids[a..b],
                &cols.phase_cycles[a..b],
                &cols.fields[a..b],
            );
            let mut one = Accumulator::with_summation(s);
            for x in &all[a..b] {
                one.add(x);
            }
            for ((ia, ea), (ib, eb)) in acc.groups().iter().zip(one.groups()) {
                assert_eq!(ia, ib);
                for k in 0..3 {
                    assert!(
                        ea[k].re.to_bits() == eb[k].re.to_bits()
                            && ea[k].im.to_bits() == eb[k].im.to_bits()
                            || ea[k].re.is_nan() && eb[k].re.is_nan()
                            || ea[k].im.is_nan() && eb[k].im.is_nan(),
                        "group {ia} component {k} {s:?} {kernel:?}: {} vs {}",
                        ea[k],
                        eb[k]
                    );
                }
            }
        }
    }
}

#[test]
fn columns_keep_the_compensated_guarantee() {
    // The one-large-and-a-million-tiny-terms case of the rows, through the columns: E = 1 +
    // 10^6·2^-54 exactly (integer phases, e^{i2πn} = 1 exactly), I = (1 + δ)².
    let tiny = 2f64.powi(-54);
    let n = 1_000_000;
    let mut cs = vec![c(1, 0.0, ex(1.0))];
    cs.extend((0..n).map(|j| c(1, (j % 1000) as f64 * 1e3, ex(tiny))));
    let delta = n as f64 * tiny;
    let expected = 1.0 + 2.0 * delta + delta * delta;
    let cols = ContributionColumns::from(&cs[..]);
    let mut out = [0.0];
    accumulate_columns_par(&cols, &[0, cs.len()], Summation::Compensated, &mut out);
    assert_close("columns compensated 1 + 10^6 tiny", out[0], expected, 4e-16);
    accumulate_columns(&cols, &[0, cs.len()], Summation::Plain, &mut out);
    println!("columns plain: {:.17e} (loses the tiny terms)", out[0]);
    assert!((out[0] - expected).abs() > 4e-16);
}

#[test]
fn columns_push_get_and_clear() {
    let mut r = Rng(23);
    let rows: Vec<Contribution> = (0..10).map(|j| c(j % 3, r.sym(), r.field())).collect();
    let mut cols = ContributionColumns::with_capacity(4);
    assert!(cols.is_empty());
    for x in &rows {
        cols.push(x);
    }
    assert_eq!(cols, ContributionColumns::from(&rows[..]));
    assert_eq!(cols.len(), 10);
    for (j, x) in rows.iter().enumerate() {
        assert_eq!(cols.get(j), *x);
    }
    cols.clear();
    assert!(cols.is_empty());
}

#[test]
fn column_kernels_cover_the_cpu() {
    // The explicit kernels the tests above run: on an AVX-512F machine all three, so the bit
    // checks exercise the 8-lane kernel, the 4-lane one and the portable one.
    let ks = column_kernels();
    println!("column kernels available: {ks:?}");
    assert!(ks.contains(&ColumnKernel::Portable));
    #[cfg(target_arch = "x86_64")]
    {
        assert_eq!(
            ks.contains(&ColumnKernel::Avx2),
            std::arch::is_x86_feature_detected!("avx2")
        );
        assert_eq!(
            ks.contains(&ColumnKernel::Avx512),
            std::arch::is_x86_feature_detected!("avx2")
                && std::arch::is_x86_feature_detected!("avx512f")
        );
    }
}

#[test]
#[should_panic(expected = "equal lengths")]
fn columns_of_unequal_lengths_are_rejected() {
    let mut acc = Accumulator::new();
    acc.extend_columns(&[1, 2], &[0.0], &[ex(1.0), ex(1.0)]);
}

#[test]
#[should_panic(expected = "offsets")]
fn columns_reject_bad_offsets() {
    let cols = ContributionColumns::from(&[c(1, 0.0, ex(1.0))][..]);
    let mut out = [0.0; 1];
    accumulate_columns(&cols, &[0, 2], Summation::Plain, &mut out);
}

fn contribution() -> impl Strategy<Value = Contribution> {
    let id = prop_oneof![Just(0u64), 1u64..6, any::<u64>()];
    let phase = prop_oneof![-1e7..1e7f64, -1e16..1e16f64, -1.0..1.0f64];
    let amp = -1e3..1e3f64;
    (id, phase, proptest::array::uniform6(amp)).prop_map(|(id, p, f)| {
        c(
            id,
            p,
            [
                Complex64::new(f[0], f[1]),
                Complex64::new(f[2], f[3]),
                Complex64::new(f[4], f[5]),
            ],
        )
    })
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(256))]

    /// Columns added in two parts equal the rows added one by one (order kept), bit for bit.
    #[test]
    fn columns_split_anywhere_equal_the_rows(
        cs in proptest::collection::vec(contribution(), 0..300),
        cut in 0.0..1.0f64,
        comp in any::<bool>(),
    ) {
        let s = if comp { Summation::Compensated } else { Summation::Plain };
        let cols = ContributionColumns::from(&cs[..]);
        let m = (cut * cs.len() as f64) as usize;
        let mut acc = Accumulator::with_summation(s);
        acc.extend_columns(&cols.coherence_ids[..m], &cols.phase_cycles[..m], &cols.fields[..m]);
        acc.extend_columns(&cols.coherence_ids[m..], &cols.phase_cycles[m..], &cols.fields[m..]);
        let one = added_one_by_one(s, &cs);
        assert_same_bits("split columns", &one, &(acc.intensity(), acc.groups().to_vec()));
        for kernel in column_kernels() {
            let mut acc = Accumulator::with_summation(s);
            acc.extend_columns_using(kernel, &cols.coherence_ids[..m], &cols.phase_cycles[..m], &cols.fields[..m]);
            acc.extend_columns_using(kernel, &cols.coherence_ids[m..], &cols.phase_cycles[m..], &cols.fields[m..]);
            assert_same_bits(&format!("split columns {kernel:?}"), &one, &(acc.intensity(), acc.groups().to_vec()));
        }
    }
}
