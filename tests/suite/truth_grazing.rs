//! Point-source scenes that failed `fringe fuzz --family two_beam_plate,lloyd --seed 1`
//! (issue #12, helper "grazing"), each traced and compared point by point with a 50-digit
//! evaluation of the same binary64 inputs (`tools/grazing_mpmath.py` →
//! `tests/data/grazing_mpmath.csv`), never with the tracer's own output:
//!
//! * a point source grazing a plate (1e-7 … 1e-8 rad above it): the Snell invariant p of the
//!   launch lies within a rounding of the ambient index, so in f64 it rounded to n0 and the
//!   launch ran parallel to the plate (the beam through the plate lost: `_59` traced 0, `_129`
//!   4.3e-8 off) or one ulp off (`_106`, 1.1e-6). `path::parallel_stack_launch` now solves for p
//!   in double-double and forms cos θ0 from it;
//! * Lloyd's mirror 100 m from the origin, 1 µm source height, 1 cm screen (`fuzz_lloyd_s1_218`):
//!   the f64 hit point on the mirror is a rounding (1.4e-14 m) off the exact path, so the launch
//!   that lands the path tilts by ~1e-12 and r_s moves by ~1e-12: the tracer is 1.2e-11 off 50
//!   digits, which no f64 hit point avoids; the derived tolerance now includes that term
//!   (`conditioning::fresnel_sensitivity`, docs/PHYSICS.md §8), and the gate still sees an error
//!   of that size (detection floor ≤ 10× the derived tolerance).

use fringe::accumulate::fidelity::Fidelity;
use fringe::harness::case::{detection, load, run};
use fringe::harness::conditioning::fresnel_sensitivity;
use fringe::harness::fuzz::{self, DERIVED_FLOOR};
use fringe::optics::interaction::SurfaceOptics;
use fringe::trace::path::EventKind;
use glam::DVec3;
use std::collections::BTreeMap;
use std::path::{Path, PathBuf};

fn root() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR"))
}

fn found(name: &str) -> PathBuf {
    root().join(format!("tests/fuzz_found/{name}.json"))
}

/// The 50-digit values by case name, in probe order.
fn mpmath_values() -> BTreeMap<String, Vec<f64>> {
    crate::support::mpmath_profiles("grazing_mpmath.csv")
}

fn load_case(path: &Path) -> load::Case {
    let text = std::fs::read_to_string(path).unwrap();
    load::parse(path, &text).expect("a valid case")
}

fn run_case(case: &load::Case) -> run::CaseResult {
    run::run_with(case, false).unwrap()
}

/// Largest deviation of `values` from `truth`, relative to the largest 50-digit value (as the
/// gate measures).
fn relative_error(values: &[f64], truth: &[f64]) -> f64 {
    assert_eq!(values.len(), truth.len());
    let scale = truth.iter().fold(0.0f64, |s, x| s.max(x.abs()));
    values
        .iter()
        .zip(truth)
        .map(|(t, m)| (t - m).abs() / scale)
        .fold(0.0, f64::max)
}

/// The traced `vector` values of a fuzz-found case, its closed form, and its derived tolerance.
fn traced(name: &str) -> (Vec<f64>, Vec<f64>, f64) {
    let r = run_case(&load_case(&found(name)));
    let m = &r.metrics[0];
    let derived = m.derived_tolerance(&r.rounding, DERIVED_FLOOR).unwrap();
    (
        m.traced[&Fidelity::Vector].clone(),
        m.analytic.clone(),
        derived,
    )
}

/// A point source 1e-7–1e-8 rad above a plate (in air, and in an ambient of n = 0.0063 and
/// 0.126 over plates of n = 1 and 1.5): both beams found, the tracer within 1e-12 of 50 digits
/// (before: the beam through the plate lost, 1.0 / 4.3e-8 / 1.1e-6 off), the closed form within
/// 1e-14.
#[test]
fn a_point_source_grazing_a_plate_keeps_the_beam_through_it() {
    let truth = mpmath_values();
    for name in [
        "fuzz_two_beam_plate_s1_59",
        "fuzz_two_beam_plate_s1_106",
        "fuzz_two_beam_plate_s1_129",
    ] {
        let (tr, cf, _) = traced(name);
        let e = relative_error(&tr, &truth[name]);
        let c = relative_error(&cf, &truth[name]);
        println!("{name}: traced vs 50 digits {e:.3e}, closed form {c:.3e}");
        assert!(e <= 1e-12, "{name}: traced vs 50 digits {e:e}");
        assert!(c <= 1e-14, "{name}: closed form vs 50 digits {c:e}");
    }
}

/// Lloyd's mirror 100 m from the origin: the tracer is off 50 digits by what its f64 hit point
/// allows (1.2e-11, above the flat 1e-12) and within the derived tolerance (2.9e-10), which
/// stays below the library's cap of 1e-9; the closed form is within 1e-14.
#[test]
fn lloyd_far_from_the_origin_is_within_what_its_hit_points_allow() {
    let name = "fuzz_lloyd_s1_218";
    let truth = &mpmath_values()[name];
    let (tr, cf, derived) = traced(name);
    let e = relative_error(&tr, truth);
    let c = relative_error(&cf, truth);
    println!("{name}: traced vs 50 digits {e:.3e}, derived tolerance {derived:.3e}");
    assert!(c <= 1e-14, "closed form vs 50 digits {c:e}");
    assert!(
        e <= derived,
        "traced vs 50 digits {e:e} > derived {derived:e}"
    );
    assert!(derived <= 1e-9, "derived tolerance {derived:e}");
    // The fuzz gate's verdict on the file as found.
    let text = std::fs::read_to_string(found(name)).unwrap();
    let v = fuzz::judge(&serde_json::from_str(&text).unwrap(), &found(name));
    assert!(matches!(v, fuzz::Verdict::Pass { .. }), "{v:?}");
}

/// The event-point term scales with X/ℓ, the largest coordinate over the path's length: the
/// same Lloyd scene moved back to the origin (every z − 100, exact in binary64 here) keeps its
/// derived tolerance at the floor, 100 m out it is above it.
#[test]
fn the_hit_point_term_vanishes_for_a_scene_at_the_origin() {
    let text = std::fs::read_to_string(found("fuzz_lloyd_s1_218")).unwrap();
    let mut v: serde_json::Value = serde_json::from_str(&text).unwrap();
    let shift = |p: &mut serde_json::Value| {
        let z = p[2].as_f64().unwrap();
        let moved = z - 100.0;
        assert_eq!(moved + 100.0, z, "the shift is exact");
        p[2] = moved.into();
    };
    shift(&mut v["scene"]["sources"][0]["emitter"]["line"]["point_m"]);
    shift(&mut v["scene"]["surfaces"][0]["interface"]["point_m"]);
    shift(&mut v["probe"]["line"]["from_m"]);
    shift(&mut v["probe"]["line"]["to_m"]);
    let dir = std::env::temp_dir().join("fringe_truth_grazing");
    std::fs::create_dir_all(&dir).unwrap();
    let path = dir.join("lloyd_at_origin.json");
    std::fs::write(&path, serde_json::to_string_pretty(&v).unwrap()).unwrap();
    let r = run_case(&load_case(&path));
    let at_origin = r.metrics[0]
        .derived_tolerance(&r.rounding, DERIVED_FLOOR)
        .unwrap();
    let (_, _, far) = traced("fuzz_lloyd_s1_218");
    println!("derived tolerance: at the origin {at_origin:.3e}, 100 m out {far:.3e}");
    assert_eq!(at_origin, DERIVED_FLOOR);
    assert!(far > 10.0 * DERIVED_FLOOR, "{far:e}");
}

/// At its derived tolerance the far Lloyd scene still catches an injected error: a phase offset
/// or an amplitude error on the reflected path just above the tolerance fails it (detection
/// floors ≤ 10× the tolerance, `detection::FLOOR_FACTOR`).
#[test]
fn the_far_lloyd_scene_sees_errors_at_its_derived_tolerance() {
    let (_, _, derived) = traced("fuzz_lloyd_s1_218");
    let text = std::fs::read_to_string(found("fuzz_lloyd_s1_218")).unwrap();
    let mut v: serde_json::Value = serde_json::from_str(&text).unwrap();
    v["references"][0]["tolerances"]["vector"] = derived.into();
    let dir = std::env::temp_dir().join("fringe_truth_grazing");
    std::fs::create_dir_all(&dir).unwrap();
    let path = dir.join("lloyd_at_derived.json");
    std::fs::write(&path, serde_json::to_string_pretty(&v).unwrap()).unwrap();
    let case = load_case(&path);
    let r = run_case(&case);
    let floors = detection::detection_floors(&case, &r).unwrap().unwrap();
    println!("derived {derived:.3e}: {floors:?}");
    for (what, f) in [("phase", floors.phase_rad), ("amplitude", floors.amplitude)] {
        match f {
            detection::Floor::Caught(e) => assert!(
                e <= detection::FLOOR_FACTOR * derived,
                "{what}: floor {e:e} > 10 × {derived:e}"
            ),
            other => panic!("{what}: {other:?}"),
        }
    }
}

/// `fresnel_sensitivity` against the closed-form derivatives of (P1), (P2) in q = n cos θ
/// (dq2/dq1 = q1/q2; d ln r_s/dq1 = −2/q2): κ = max(|r_s'|, |r_p'|)/max(|r_s|, |r_p|) per unit
/// cos θi, to 1e-6 (the central difference), for 1 → 1.5 at cos θi = 0.0996 (Lloyd's angle),
/// 0.5 and 0.9; 0 for an ideal mirror.
#[test]
fn fresnel_sensitivity_is_the_derivative_of_the_coefficients() {
    let (n1, n2) = (1.0f64, 1.5f64);
    let optics = SurfaceOptics::Dielectric {
        n_front: n1,
        n_back: n2,
    };
    let normal = DVec3::Z;
    for c in [0.0996f64, 0.5, 0.9] {
        let d_in = DVec3::new((1.0 - c * c).sqrt(), 0.0, -c);
        let q1 = n1 * c;
        let q2 = (n2 * n2 - n1 * n1 + q1 * q1).sqrt();
        let dq2 = q1 / q2;
        let rs = (q1 - q2) / (q1 + q2);
        let drs = ((1.0 - dq2) * (q1 + q2) - (q1 - q2) * (1.0 + dq2)) / (q1 + q2).powi(2);
        let (a, b) = (n2 * n2, n1 * n1);
        let rp = (a * q1 - b * q2) / (a * q1 + b * q2);
        let drp = ((a - b * dq2) * (a * q1 + b * q2) - (a * q1 - b * q2) * (a + b * dq2))
            / (a * q1 + b * q2).powi(2);
        let expect = n1 * drs.abs().max(drp.abs()) / rs.abs().max(rp.abs());
        let got = fresnel_sensitivity(optics, EventKind::Reflect, normal, d_in, n1);
        println!("cos {c}: κ {got:.9e}, closed form {expect:.9e}");
        assert!(
            (got - expect).abs() <= 1e-6 * expect,
            "cos {c}: {got:e} vs {expect:e}"
        );
    }
    let d_in = DVec3::new(0.6, 0.0, -0.8);
    let mirror = fresnel_sensitivity(
        SurfaceOptics::IdealMirror,
        EventKind::Reflect,
        normal,
        d_in,
        1.0,
    );
    assert_eq!(mirror, 0.0);
}
