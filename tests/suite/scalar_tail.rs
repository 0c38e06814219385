//! The scalar rungs' closed Airy tail for mixed s and p light (issue #12, docs/PHYSICS.md §5a
//! eq. T2, `trace::tail::scalar_series`): F = Σ_{k≥1} √(w_s x^k + w_p y^k) e^{2πikc} is finite
//! and accurate over the whole range 0 ≤ x, y < 1, any weights, any c. Checked against 50 digits
//! (`tools/scalar_tail_mpmath.py` → `tests/data/scalar_tail_mpmath.csv`: term-by-term sums,
//! the plain binomial series near grazing incidence, and the geometric limits), against a slow
//! compensated f64 sum, and by the shift identity F(w) = z g₁ (1 + F(w')) over the whole range;
//! and in a scene: the plate whose closed tail made the scalar rungs NaN
//! (`pipeline_props::random_valid_scenes_give_finite_reports`).

use fringe::accumulate::fidelity::Fidelity;
use fringe::harness::case::{load, run};
use fringe::harness::verdict;
use fringe::trace::tail::scalar_series::{MIN_ONE_MINUS_ABS2, scalar_tail};
use num_complex::Complex64;
use proptest::prelude::*;
use serde_json::json;
use std::f64::consts::TAU;
use std::path::Path;

fn parse(l: &str) -> Vec<&str> {
    l.split(',').collect()
}

/// Every 50-digit row: within the returned error bound, and within 1e-12 of |F|.
#[test]
fn mixed_light_agrees_with_50_digits() {
    let mut worst = 0.0f64;
    let text = include_str!("../data/scalar_tail_mpmath.csv");
    let mut rows = 0;
    for l in text.lines().skip(1) {
        let f = parse(l);
        let x = |k: usize| f[k].parse::<f64>().unwrap();
        let (ws, wp, ds, dp, c) = (x(0), x(1), x(2), x(3), x(4));
        let want = Complex64::new(x(6), x(7));
        let got = scalar_tail([ws, wp], [ds, dp], c).expect("valid input");
        let dev = (got.sum - want).norm();
        let rel = dev / want.norm();
        worst = worst.max(rel);
        assert!(
            dev <= got.error_bound,
            "{l}: F = {} vs 50 digits: off {dev:e} > bound {:e}",
            got.sum,
            got.error_bound
        );
        assert!(rel <= 1e-12, "{l}: relative deviation {rel:e}");
        assert!(
            got.error_bound <= 1e-12 * want.norm(),
            "{l}: bound {:e} is vacuous",
            got.error_bound
        );
        rows += 1;
    }
    assert_eq!(rows, 24 + 40 + 12, "rows of the 50-digit table");
    println!("worst relative deviation from 50 digits: {worst:.2e}");
}

/// The slow reference: Σ_k term by term with compensated (Neumaier) sums, the phase of k c
/// reduced exactly; terms until the rest is below 1e-18 of the sum.
fn slow(ws: f64, wp: f64, ds: f64, dp: f64, c: f64) -> Complex64 {
    let t = ws + wp;
    let (ws, wp) = (ws / t, wp / t);
    let (lx, ly) = ((-ds).ln_1p(), (-dp).ln_1p());
    let a = (0.5 * lx.max(ly)).exp();
    let (mut re, mut im) = ((0.0f64, 0.0f64), (0.0f64, 0.0f64));
    let add = |s: &mut (f64, f64), v: f64| {
        let t = s.0 + v;
        s.1 += if s.0.abs() >= v.abs() {
            (s.0 - t) + v
        } else {
            (v - t) + s.0
        };
        s.0 = t;
    };
    let mut k = 1.0f64;
    while k < 1e7 {
        let g = (ws * (k * lx).exp() + wp * (k * ly).exp()).sqrt();
        let p = k * c;
        let ph = TAU * ((p - p.round()) + k.mul_add(c, -p));
        add(&mut re, g * ph.cos());
        add(&mut im, g * ph.sin());
        let rest = a.powf(k) / (1.0 - a);
        if rest < 1e-18 * (re.0 * re.0 + im.0 * im.0).sqrt() || rest < 1e-300 {
            break;
        }
        k += 1.0;
    }
    Complex64::new(re.0 + re.1, im.0 + im.1)
}

fn one_minus_abs2() -> impl Strategy<Value = f64> {
    prop_oneof![
        (MIN_ONE_MINUS_ABS2.log10()..0.0).prop_map(|e| 10f64.powf(e)),
        (-16.0f64..0.0).prop_map(|e| 10f64.powf(e)),
        0.0f64..=1.0,
    ]
    .prop_filter("1 − |A|² ≥ the smallest taken", |d| {
        *d >= MIN_ONE_MINUS_ABS2
    })
}

fn weight() -> impl Strategy<Value = f64> {
    prop_oneof![
        Just(0.0),
        0.0f64..1.0,
        (-300.0f64..0.0).prop_map(|e| 10f64.powf(e))
    ]
}

fn cycles() -> impl Strategy<Value = f64> {
    prop_oneof![
        -1e6f64..1e6,
        (
            prop_oneof![Just(0.0), Just(0.5), Just(3.0)],
            -1.0f64..1.0,
            -18.0f64..0.0
        )
            .prop_map(|(r, s, e)| r + s * 10f64.powf(e)),
    ]
}

proptest! {
    #![proptest_config(ProptestConfig {
        cases: std::env::var("PROPTEST_CASES").ok().and_then(|s| s.parse().ok()).unwrap_or(256),
        failure_persistence: None,
        ..ProptestConfig::default()
    })]

    /// Over the whole range: finite, the bound finite; where the orders decay fast enough to be
    /// summed one by one (1 − |A|² ≥ 1e-3 for both), within the bound of the slow sum (plus its
    /// own rounding, ~1e-15 of Σ|terms|); and everywhere the shift identity
    /// F(w_s, w_p) = z g₁ (1 + F(w_s x, w_p y)) (g₁ = √(w_s x + w_p y), z = e^{2πic}), which moves
    /// the split between the two expansions by one order.
    #[test]
    fn finite_and_consistent_over_the_whole_range(
        ws in weight(), wp in weight(), ds in one_minus_abs2(), dp in one_minus_abs2(), c in cycles(),
    ) {
        let Some(f) = scalar_tail([ws, wp], [ds, dp], c) else {
            prop_assert!(false, "valid input refused");
            unreachable!()
        };
        prop_assert!(f.sum.re.is_finite() && f.sum.im.is_finite() && f.error_bound.is_finite(), "{f:?}");
        let t = ws + wp;
        prop_assume!(t > 0.0);
        prop_assert!(f.error_bound <= 1e-12 * f.sum.norm().max(1e-300) || f.sum.norm() < 1e-200,
            "bound {:e} vs |F| {:e}", f.error_bound, f.sum.norm());
        if ds >= 1e-3 && dp >= 1e-3 {
            let r = slow(ws, wp, ds, dp, c);
            let terms = 1.0 / (1.0 - (0.5 * (-ds.min(dp)).ln_1p()).exp());
            let tol = f.error_bound + 1e-15 * terms;
            prop_assert!((f.sum - r).norm() <= tol, "{f:?} vs slow {r}: off {:e} > {tol:e}", (f.sum - r).norm());
        }
        // Both orders barely decaying, off resonance: the Abel sum r/(1 − r)
        // (`limit_of_vanishing_decay_is_the_abel_sum`).
        let one_minus_r = (Complex64::from_polar(1.0, TAU * c) - 1.0).norm();
        if ds.max(dp) <= 1e-20 && one_minus_r >= 0.06 {
            let want = abel_sum(c);
            let tol = f.error_bound + 1e-14 * want.norm() + 4.0 * ds.max(dp) / (one_minus_r * one_minus_r);
            prop_assert!((f.sum - want).norm() <= tol, "{f:?} vs r/(1 − r) {want}");
        }
        let (x, y) = (1.0 - ds, 1.0 - dp);
        let (ws, wp) = (ws / t, wp / t);
        let g2 = ws * x + wp * y;
        prop_assume!(g2 > 1e-280);
        let g1 = g2.sqrt();
        let shifted = scalar_tail([ws * x / g2, wp * y / g2], [ds, dp], c).unwrap();
        let p = TAU * (c - c.round());
        let z = Complex64::new(p.cos(), p.sin());
        let rhs = z * g1 * (1.0 + shifted.sum);
        // Both sides' evaluation bounds, and the rounding of x, y, the weights and z (a few u of
        // each side's scale). The shifted weights carry u ρ only to a relative u: F moves the
        // split K = ln u/δ with ln u, so that rounding counts 1/δ times (δ = ln(x/y); where δ
        // is below ~1e-12 the identity cannot be checked in f64 and only finiteness is).
        let dl = ((-dp).ln_1p() - (-ds).ln_1p()).abs();
        let cond = if dl == 0.0 { 0.0 } else { 8.0 * f64::EPSILON / dl };
        let scale = f.sum.norm() + g1 * (1.0 + shifted.sum.norm());
        let tol = f.error_bound + g1 * shifted.error_bound + (1e-14 + cond) * scale;
        prop_assert!((f.sum - rhs).norm() <= tol, "F {f:?} vs shifted {rhs}: off {:e} > {tol:e}", (f.sum - rhs).norm());
    }
}

/// The limits: one polarization alone is the geometric series r/(1 − r), and so is mixed light
/// when x = y (with r = √x e^{2πic}); a vanishing second component changes F continuously.
#[test]
fn limits_are_the_geometric_series() {
    for &(d, c) in &[
        (0.3f64, 0.1f64),
        (1e-9, 0.0),
        (1e-9, 3e-10),
        (1e-12, 0.5),
        (0.999, -0.4),
    ] {
        // r/(1 − r), 1 − r = (1 − |r|) + 2|r| sin²(θ/2) − i |r| sin θ (no cancellation).
        let m = (1.0 - d).sqrt();
        let th = TAU * c;
        let r = Complex64::from_polar(m, th);
        let h = (0.5 * th).sin();
        let g = r / Complex64::new(d / (1.0 + m) + 2.0 * m * h * h, -m * th.sin());
        for w in [[1.0, 0.0], [0.0, 1.0], [0.3, 0.7]] {
            let dd = if w == [0.0, 1.0] {
                [0.5, d]
            } else {
                [d, if w[1] == 0.0 { 0.5 } else { d }]
            };
            let f = scalar_tail(w, dd, c).unwrap();
            assert!(
                (f.sum - g).norm() <= 1e-14 * g.norm(),
                "{w:?} {dd:?} {c}: {} vs {g}",
                f.sum
            );
        }
        // w_p → 0 with y < x: F → the s series, O(√w_p) off it.
        for wp in [1e-10, 1e-20, 1e-30] {
            let f = scalar_tail([1.0, wp], [d, (2.0 * d).min(1.0)], c).unwrap();
            assert!(
                (f.sum - g).norm()
                    <= 2.0 * wp.sqrt() * (1.0 / (1.0 - (1.0 - d).sqrt())) + 1e-14 * g.norm()
            );
        }
    }
}

/// The scene that made the scalar rungs NaN: the library's plate_airy_p, its light polarized at
/// 54° (or 15°) to s, at incidences where the tail bound needs more than the cap, so the
/// runner traces 8 orders and closes the rest. Every output is finite, and the `scalar` rung's
/// reflectance agrees with its 50-digit sum over all orders (`tools/scalar_tail_mpmath.py
/// --plate`); the `vector` rung with the Airy formula checks the case's convention. The rows'
/// conditioning: the tracer's round-trip phase is 2π·8u (ΔS/λ + 1) off (§8), which moves R by
/// ≲ 1e-13 of R at these (non-resonant) points, and the closure itself is ≤ 1e-14 off.
#[test]
fn mixed_light_plate_with_a_closed_tail_is_finite_and_exact() {
    for l in include_str!("../data/scalar_tail_plate_mpmath.csv")
        .lines()
        .skip(1)
    {
        let f = parse(l);
        let x = |k: usize| f[k].parse::<f64>().unwrap();
        let (angle, dx, dc, cos1) = (x(0), x(1), x(2), x(3));
        let (scalar, vector) = (x(5), x(6));
        let path = Path::new(env!("CARGO_MANIFEST_DIR")).join("cases/plate_airy_p.json");
        let mut doc: serde_json::Value =
            serde_json::from_str(&std::fs::read_to_string(&path).unwrap()).unwrap();
        doc["scene"]["sources"][0]["polarization"]["linear"]["angle_deg"] = json!(angle);
        doc["scene"]["sources"][0]["emitter"]["plane_wave"]["direction"] = json!([dx, 0, -dc]);
        doc["probe"] = json!({"single": {"observe": {"far_field": {"side": "reflected",
            "surface_normal": [0, 0, 1]}}}});
        doc["fidelities"] = json!([
            "incoherent",
            "scalar",
            "scalar_jump",
            "paper_rules",
            "vector"
        ]);
        let case = load::parse(&path, &doc.to_string()).unwrap();
        let built = fringe::harness::case::build::build_scene(
            &case.spec.scene,
            &fringe::harness::case::build::Overrides::default(),
        )
        .unwrap();
        let (_, c) = fringe::harness::case::reference::airy_film(&built, "plate", 550e-9).unwrap();
        assert_eq!(c.to_bits(), cos1.to_bits(), "cos θ1 of the case");
        run::preflight(&case).unwrap();
        let r = run::run_with(&case, true).unwrap();
        assert_eq!(
            r.internal_reflections,
            2 * run::CLOSED_TAIL_ORDERS + 1,
            "the closure was not used"
        );
        for m in &r.metrics {
            assert!(m.analytic.iter().all(|v| v.is_finite()), "{l}: {m:?}");
            for (level, t) in &m.traced {
                assert!(t.iter().all(|v| v.is_finite()), "{l}: {level:?} {t:?}");
            }
        }
        for row in verdict::rows(&r) {
            assert!(
                row.max_abs_dev.is_finite() && row.rms_dev.is_finite(),
                "{l}: {row:?}"
            );
        }
        let csv = verdict::golden_csv(&r);
        assert!(!csv.contains("NaN") && !csv.contains("inf"), "{l}: {csv}");
        let m = &r.metrics[0];
        let s = m.traced[&Fidelity::Scalar][0];
        let v = m.traced[&Fidelity::Vector][0];
        println!(
            "{l}: scalar {s:e} (off {:.1e}), vector {v:e} (off {:.1e})",
            (s - scalar).abs() / scalar,
            (v - vector).abs() / vector
        );
        assert!(
            (v - vector).abs() <= 1e-12 * vector,
            "{l}: vector {v:e} vs 50 digits {vector:e}"
        );
        assert!(
            (s - scalar).abs() <= 1e-12 * scalar,
            "{l}: scalar {s:e} vs 50 digits {scalar:e}"
        );
    }
}

/// r/(1 − r) for r = e^{2πic}: the Abel sum Σ_{k≥1} r^k, the limit of F (eq. T2) as both
/// 1 − |A|² vanish (the weights normalized, so √(w_s + w_p) = 1), formed without cancellation
/// (1 − r = 2 sin²(πc) − i sin 2πc).
fn abel_sum(c: f64) -> Complex64 {
    let th = TAU * (c - c.round());
    let h = (0.5 * th).sin();
    let r = Complex64::new(th.cos(), th.sin());
    r / Complex64::new(2.0 * h * h, -th.sin())
}

/// Where both orders barely decay (1 − |A|² from 1e-200 to 1e-20) and the round trip is off
/// resonance (|1 − r| ≥ 0.06), F is the Abel sum r/(1 − r) to O(d/|1 − r|²) (summation by
/// parts: the amplitudes √(w_s x^k + w_p y^k) fall from 1 by at most d/2 a round trip). These
/// splits K = ln(w_m/w_M)/δ reach 1e180, far beyond 2^53, where K − 1 is not an f64: the region
/// before the split once summed K terms for K − 1 and gave F = −0.02 for −0.5 (proptest seed
/// at 1 − x = 3e-183, 1 − y = 1e-126, c = −251844.50069914624).
#[test]
fn limit_of_vanishing_decay_is_the_abel_sum() {
    let ds = [
        1e-200,
        3.0691813412697794e-183,
        1e-150,
        1e-126,
        1e-60,
        1e-20,
    ];
    let weights = [
        [0.11137870271438281, 0.8564519424022944],
        [0.5, 0.5],
        [0.9, 0.1],
        [1e-3, 1.0],
        [1.0, 1e-9],
    ];
    let cycles = [-251844.50069914624, 0.4993, -0.25, 0.1, 0.01, 1234.567];
    let mut splits_beyond_2_53 = 0;
    for &a in &ds {
        for &b in &ds {
            for w in weights {
                for &c in &cycles {
                    let f = scalar_tail(w, [a, b], c).expect("valid input");
                    let want = abel_sum(c);
                    let one_minus_r = (Complex64::from_polar(1.0, TAU * c) - 1.0).norm();
                    let tol = f.error_bound
                        + 1e-14 * want.norm()
                        + 4.0 * a.max(b) / (one_minus_r * one_minus_r);
                    let off = (f.sum - want).norm();
                    assert!(
                        off <= tol,
                        "w {w:?}, 1 − |A|² ({a:e}, {b:e}), c {c}: F {} vs r/(1 − r) {want}: off {off:e} > {tol:e}",
                        f.sum
                    );
                    let delta = (a - b).abs();
                    let log_u = (w[0].max(w[1]) / w[0].min(w[1])).ln();
                    if delta > 0.0 && log_u / delta > 9_007_199_254_740_992.0 {
                        splits_beyond_2_53 += 1;
                    }
                }
            }
        }
    }
    assert!(
        splits_beyond_2_53 > 100,
        "{splits_beyond_2_53} splits beyond 2^53"
    );
}
