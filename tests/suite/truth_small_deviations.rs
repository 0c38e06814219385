//! The fuzz failures of 1e-12 … 4e-11 (issue #12; `fringe fuzz --count 300 --seed 1`, shrunk
//! into `tests/fuzz_found/`), each decided against a 50-digit evaluation of the case file's own
//! binary64 numbers (`tools/small_deviations_mpmath.py` → `tests/data/small_deviations_mpmath.csv`),
//! never against the tracer or the closed form the gate uses:
//!
//! * airy on a substrate, transmitted (#230 at normal incidence in air, #253 and #283 near
//!   grazing, #1 in a medium): the tracer cut the Airy sum where the tail bound of the
//!   *reflected* wave fell below `airy_tail_epsilon`; the transmitted orders can be far larger
//!   (t23 = 0.77 against t21 = 0.0125 in #230; √(n3 cos θ3/(n1 cos θ1)) = 870 at 89.9999° in
//!   #283). The budget now bounds both sides (`Film::tail_bound`), and the derived tolerance
//!   counts the truncation the case asks for (`run::budget::tail_truncation`).
//! * two_beam_plate #181 (a 0.1 nm plate at a dark fringe, I = 9.8e-12 of the source): the
//!   closed form, not the tracer, was 1.5e-10 off: its p channel summed |a1|² + |a2|² +
//!   2 Re(a1 a2* e^{iφ}) cos Δθ, terms 1e6 times the result.
//! * airy #207 (1 nm film 500 m from the origin): the tracer equals 50 digits at the origin; moved,
//!   the bottom face is an f64 plane 500 m out, 1e-13 m off the written 1 nm thickness: the
//!   scene's own representation (helper "cond"'s policy), recorded here, not judged.
//! * wedge #109, #291 (and #538, #638, #866 of `--family wedge --count 1000 --seed 1`): the
//!   tracer was 3e-12 … 1.2e-11 off 50 digits, the closed form within 8e-16: the path solver
//!   landed a plane wave's beam 1.5e-11 m off a target 1e-4 m above the wedge and drew the last
//!   segment to the target, a kink of m²/(2L) = 1.1e-18 m of path, now subtracted; ≤ 8e-16.

use fringe::accumulate::fidelity::Fidelity;
use fringe::harness::analytic::plate::{Film, Pol, TwoBeamPlate};
use fringe::harness::case::{load, run};
use fringe::harness::fuzz::{Verdict, judge};
use num_complex::Complex64;
use std::collections::BTreeMap;
use std::path::PathBuf;

fn found(name: &str) -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR")).join(format!("tests/fuzz_found/{name}.json"))
}

fn truth() -> BTreeMap<String, Vec<f64>> {
    crate::support::mpmath_profiles("small_deviations_mpmath.csv")
}

fn case_json(name: &str) -> serde_json::Value {
    serde_json::from_str(&std::fs::read_to_string(found(name)).unwrap()).unwrap()
}

fn run_case(name: &str) -> run::CaseResult {
    let path = found(name);
    let text = std::fs::read_to_string(&path).unwrap();
    run::run_with(&load::parse(&path, &text).expect("a valid case"), false).unwrap()
}

/// The traced `vector` values of the primary reference.
fn traced(name: &str) -> Vec<f64> {
    run_case(name).metrics[0].traced[&Fidelity::Vector].clone()
}

/// Largest |a − b| relative to the largest |b| (as the gate measures).
fn relative(a: &[f64], b: &[f64]) -> f64 {
    assert_eq!(a.len(), b.len());
    let scale = b.iter().fold(0.0f64, |s, x| s.max(x.abs()));
    a.iter()
        .zip(b)
        .map(|(x, y)| (x - y).abs() / scale)
        .fold(0.0, f64::max)
}

fn epsilon(name: &str) -> f64 {
    case_json(name)["trace"]["airy_tail_epsilon"]
        .as_f64()
        .unwrap()
}

/// The transmitted Airy scenes on substrates: the traced T is within what the case's own tail
/// bound ε leaves out, 2√T ε + ε² (unit source), plus 1e-13 of T for the arithmetic, of the 50-digit
/// T. #283 (ε = 1e-15, 89.9999°) was 3.2e-11 of T off, 36 times that, because the budget bounded
/// only the reflected tail; #230 and #1 were 2.5e-12 and 1.9e-11 off.
#[test]
fn transmitted_airy_sums_are_cut_where_the_transmitted_tail_is_below_epsilon() {
    let truth = truth();
    for name in [
        "fuzz_airy_s1_230",
        "fuzz_airy_s1_253",
        "fuzz_airy_s1_283",
        "fuzz_airy_s1_1",
    ] {
        let eps = epsilon(name);
        let t = traced(name);
        for (x, m) in t.iter().zip(&truth[name]) {
            let allowed = 2.0 * m.sqrt() * eps + eps * eps + 1e-13 * m;
            println!(
                "{name}: traced {x:e}, 50 digits {m:e}, |dev| {:.3e}, allowed {allowed:.3e}",
                (x - m).abs()
            );
            assert!(
                (x - m).abs() <= allowed,
                "{name}: traced {x:e} vs 50 digits {m:e}: {:e} > {allowed:e}",
                (x - m).abs()
            );
        }
    }
}

/// The found scenes through the fuzz gate itself (derived tolerance, at least 1e-12): pass.
#[test]
fn the_fuzz_gate_passes_the_found_scenes() {
    for name in [
        "fuzz_airy_s1_230",
        "fuzz_airy_s1_253",
        "fuzz_airy_s1_283",
        "fuzz_airy_s1_1",
        "fuzz_two_beam_plate_s1_181",
        "fuzz_wedge_s1_109",
        "fuzz_wedge_s1_291",
        "fuzz_wedge_s1_538",
        "fuzz_wedge_s1_638",
        "fuzz_wedge_s1_866",
    ] {
        let v = judge(&case_json(name), &found(name));
        assert!(matches!(v, Verdict::Pass { .. }), "{name}: {v:?}");
    }
}

/// The transmitted orders of an Airy sum, summed one by one (order m: t12 t23 e^{iβ/2} q^m,
/// q = r21 r23 e^{iβ}), scaled to √T: √(n3 cos θ3/(n1 cos θ1)) |t − Σ_{m<N}| is the tail that
/// [`Film::t_tail_bound`] must bound, with t the closed-form amplitude. The film of #230
/// (air | n 0.0063, 1 µm | n 0.01, 200 nm, normal incidence): the reflected bound misses that
/// tail by orders of magnitude; the transmitted bound holds, for s and p, at several angles.
#[test]
fn the_transmitted_tail_bound_bounds_the_transmitted_tail() {
    let films = [
        Film {
            n1: 1.0,
            n2: 0.006_309_573_444_801_93,
            n3: 0.01,
            thickness_m: 1e-6,
        },
        Film {
            n1: 1.0,
            n2: 1.1,
            n3: 1.33,
            thickness_m: 3e-7,
        },
        Film {
            n1: 0.1,
            n2: 1.0,
            n3: 1.33,
            thickness_m: 2e-6,
        },
    ];
    let lambda = 200e-9;
    // The largest ratio of a transmitted tail to the reflected bound at the same N.
    let mut missed_by = 0.0f64;
    for f in films {
        for theta_deg in [0.0f64, 30.0, 60.0, 85.0] {
            let c = theta_deg.to_radians().cos();
            for pol in [Pol::S, Pol::P] {
                let a = f.terms(c, lambda, pol);
                if a.cos3 == 0.0 {
                    continue;
                }
                let scale = (f.n3 * a.cos3 / (f.n1 * a.cos1)).sqrt();
                let t = f.t(c, lambda, pol);
                let q = a.r21 * a.r23 * a.round_trip;
                let mut partial = Complex64::default();
                let mut order = a.t12 * a.t23 * a.half_trip;
                for n in 1..=12usize {
                    partial += order;
                    order *= q;
                    let tail = scale * (t - partial).norm();
                    let bound = f.t_tail_bound(c, lambda, pol, n);
                    assert!(
                        tail <= bound * (1.0 + 1e-9) + 1e-15,
                        "{f:?} {theta_deg}° {pol:?} N = {n}: tail {tail:e} > bound {bound:e}"
                    );
                    assert!(f.tail_bound(c, lambda, pol, n) >= bound);
                    if tail > 1e-14 {
                        missed_by = missed_by.max(tail / f.r_tail_bound(c, lambda, pol, n));
                    }
                }
            }
        }
    }
    println!("the reflected bound misses a transmitted tail by up to {missed_by:.2}×");
    assert!(
        missed_by > 3.0,
        "the reflected bound alone should miss a transmitted tail here ({missed_by})"
    );
}

/// #181: a 0.1 nm plate (n 1.5 in n 1.51) under an unpolarized point source, 2000 nm, at a
/// dark fringe (I = 9.8e-12 of the source). The closed form was 1.5e-10 off 50 digits: its p
/// channel cancelled terms 1e6 times the result. Both the closed form and the tracer now stay
/// within what f64 beam amplitudes allow here: each of the two beams (|a| = |r12| = 3.3e-3)
/// rounded by u moves the field E = Σ a_k e^{iφ_k} (|E| = √I = 3.1e-6) by 2u|a|, so I by
/// 4u|a|/|E| of itself = 4.7e-13 (both measure 2.2e-13; the 1e-14 for closed forms
/// would need the amplitudes, or their difference r12 e^{iφ} − r12(1 − r12²), beyond f64: open).
#[test]
fn a_dark_fringe_of_a_sub_nm_plate_against_50_digits() {
    let name = "fuzz_two_beam_plate_s1_181";
    let truth = &truth()[name];
    let plate = TwoBeamPlate {
        n1: 1.51,
        n2: 1.5,
        thickness_m: 0.0001 * 1e-6,
        h_src_m: 1.0,
        h_obs_m: 2.0,
    };
    let xs = [0.052_365_194_784_652_756, 0.104_730_390_569_305_51];
    let closed: Vec<f64> = xs
        .iter()
        .map(|x| plate.intensity_unpolarized(*x, 2000e-9))
        .collect();
    let e_closed = relative(&closed, truth);
    let e_traced = relative(&traced(name), truth);
    // What f64 amplitudes allow (doc above), at the profile's largest point.
    let a = plate.beam_top(xs[0]).amp_s.norm();
    let scale = truth.iter().fold(0.0f64, |s, x| s.max(*x));
    let allowed = 4.0 * f64::EPSILON / 2.0 * a / scale.sqrt();
    println!(
        "{name}: closed form {e_closed:.3e}, tracer {e_traced:.3e} off 50 digits; f64 amplitudes allow {allowed:.3e}"
    );
    assert!(
        e_closed <= allowed,
        "closed form {e_closed:e} off 50 digits"
    );
    assert!(e_traced <= allowed, "tracer {e_traced:e} off 50 digits");
}

/// #207 (air-like n 0.01 | n 1.5, 1 nm | n 0.001, reflected, normal incidence) moved back to the
/// origin: the tracer equals 50 digits to 1e-14. As found (500 m out) it is 6.9e-12 off: the
/// bottom face is then an f64 plane whose offset is rounded at 500 m, 5.5e-14 m of the written
/// 1 nm; that representation term is not a tracer error (recorded, not judged here).
#[test]
fn a_nm_film_at_the_origin_reflects_as_50_digits() {
    let truth = truth();
    let at_origin = relative(
        &traced("fuzz_airy_s1_207_at_origin"),
        &truth["fuzz_airy_s1_207_at_origin"],
    );
    let moved = relative(&traced("fuzz_airy_s1_207"), &truth["fuzz_airy_s1_207"]);
    println!("#207: at the origin {at_origin:.3e}, 500 m out {moved:.3e} off 50 digits");
    assert!(at_origin <= 1e-14, "{at_origin:e}");
}

/// Wedges, all unrotated with the top face through the origin, against 50 digits: #109 (n 1.1 |
/// 3.0 | 1.0, 1e-5°, 2000 nm, 125 m along the wedge), #291 (n 10 | 0.001 | 10, 4e-4°, 200 nm,
/// 57 m), and from `fringe fuzz --family wedge --count 1000 --seed 1` #538 (n 0.89 | 0.50 | 0.89,
/// 1e-5°, 25 m), #638 (air | 0.126 | air, 1e-5°, 4.6 m), #866 (n 3 | 1.5 | 1, 1e-5°, 2.6 m). The
/// tracer was 1e-11, 3e-12, 6.8e-12, 3.4e-12, 1.2e-11 off: the path solver accepted the bottom
/// beam 1.5e-11 m off its target (1e-12 of the 25 m scene) without a Newton step and drew the
/// last segment, 1e-4 m long, to the target: a kink whose m²/(2L) = 1.1e-18 m of optical path
/// is 1e-11 of I. A plane wave between plane faces stays plane, so the path to the target's
/// wavefront is (P − X)·d exactly: the kink is now subtracted (`trace::path::solve`).
#[test]
fn long_wedges_trace_as_50_digits() {
    let truth = truth();
    for name in [
        "fuzz_wedge_s1_109",
        "fuzz_wedge_s1_291",
        "fuzz_wedge_s1_538",
        "fuzz_wedge_s1_638",
        "fuzz_wedge_s1_866",
    ] {
        let e = relative(&traced(name), &truth[name]);
        println!("{name}: tracer {e:.3e} off 50 digits");
        assert!(e <= 1e-14, "{name}: {e:e}");
    }
}

/// The closed form of the same wedges is within 2e-15 of 50 digits (the reference is right).
#[test]
fn long_wedges_closed_form_against_50_digits() {
    let truth = truth();
    for name in [
        "fuzz_wedge_s1_109",
        "fuzz_wedge_s1_291",
        "fuzz_wedge_s1_538",
        "fuzz_wedge_s1_638",
        "fuzz_wedge_s1_866",
    ] {
        let e = relative(&run_case(name).metrics[0].analytic, &truth[name]);
        println!("{name}: closed form {e:.3e} off 50 digits");
        assert!(e <= 1e-14, "{name}: closed form {e:e}");
    }
}
