//! Rotated plane-wave scenes near grazing, Brewster's and critical angles (issue #12; `fringe
//! fuzz --count 10000 --seed 1`: 90 of the 91 `airy` failures and all 4 `rhomb_retardance` ones
//! were in rotated frames). Expected values are 50-digit evaluations of the found scenes' own
//! binary64 numbers (`tools/representation_mpmath.py` →
//! `tests/data/representation_mpmath.csv`).
//!
//! What they show (docs/PHYSICS.md §3a, §8):
//! * the grazing and near-Brewster transmitted scenes were a harness error on the traced side:
//!   the far-field power factor (n3 cos θ3)/(n1 cos θ1) took cos θ1 = d·N in f64, u/cos θ1 off
//!   in a rotated frame (6.5e-8 of T at 89.9999999°, 6 % at 89.9999999999999°); from the
//!   double-double normal wavevectors the traced T equals 50 digits of the direction the tracer
//!   holds;
//! * the rest is the scene's representation: a direction and a normal each held one rounding
//!   off move the exact incidence cosine by up to 2u Σ|d_i N_i| (`conditioning::cosine_rounding`),
//!   which near grazing moves T by u/cos θ of itself and near a critical angle moves the rhomb's
//!   retardance through its square-root singularity. The representation term (amplitudes:
//!   `conditioning::amplitude_sensitivity`, `power_factor_sensitivity`; the rhomb's phase:
//!   `tir::rhomb_retardance_representation`) covers a 50-digit finite difference of that turn,
//!   stays within a small factor of it, and the gate at the widened band still catches an
//!   injected error.

use fringe::accumulate::fidelity::Fidelity;
use fringe::harness::case::detection::{FLOOR_FACTOR, Floor};
use fringe::harness::case::load;
use fringe::harness::case::run;
use fringe::harness::fuzz::{self, Verdict};
use std::path::PathBuf;

/// Rotated films near grazing (89.99999° … 89.9999999999999°) whose direction
/// `tools/representation_mpmath.py` rebuilds bit for bit in binary64.
const GRAZING: [&str; 5] = [
    "fuzz_airy_s1_8928",
    "fuzz_airy_s1_8724",
    "fuzz_airy_s1_1225",
    "fuzz_airy_s1_4064",
    "fuzz_airy_s1_3321",
];

/// Also found, judged only: 7341 (89.9999999°, 1.4e-8 off before; now 1.2e-16 off the closed
/// form) and 9549 (89.999999°; 1.3e-10 off the closed form, inside its representation band of
/// 4e-9): Python's binary64 rebuild of their directions is not the one the tracer holds (the
/// traced value is 1.4e-8 and 1.3e-10 off it), so they have no 50-digit row here.
const ALSO_FOUND: [&str; 2] = ["fuzz_airy_s1_7341", "fuzz_airy_s1_9549"];

const RHOMB: [&str; 4] = [
    "fuzz_rhomb_retardance_s1_2773",
    "fuzz_rhomb_retardance_s1_4425",
    "fuzz_rhomb_retardance_s1_4569",
    "fuzz_rhomb_retardance_s1_7597",
];

fn file(name: &str) -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR")).join(format!("tests/fuzz_found/{name}.json"))
}

fn text(name: &str) -> String {
    std::fs::read_to_string(file(name)).unwrap()
}

fn truth(key: &str) -> Vec<f64> {
    crate::support::mpmath_profiles("representation_mpmath.csv")[key].clone()
}

fn run_text(name: &str, text: &str, detection: bool) -> run::CaseResult {
    run::run_with(
        &load::parse(&file(name), text).expect("a valid case"),
        detection,
    )
    .unwrap()
}

fn scale(v: &[f64]) -> f64 {
    v.iter().fold(0.0f64, |s, x| s.max(x.abs()))
}

/// The traced T of rotated films at 89.99999°–89.9999999999999° equals 50 digits of the
/// direction the tracer holds within the rounding bound the arithmetic allows the scene
/// (`conditioning::intensity_rounding`, at least 1e-12 of the value; measured 4e-16 … 1.2e-12;
/// before: 6.5e-9 … 2.5e-2 off, the f64 power factor).
#[test]
fn rotated_grazing_transmittance_is_exact_for_the_direction_the_tracer_holds() {
    for name in GRAZING {
        let held = truth(&format!("held/{name}"));
        let r = run_text(name, &text(name), false);
        let traced = &r.metrics[0].traced[&Fidelity::Vector];
        let s = scale(&held);
        let bound = r.metrics[0].derived_tolerance(&r.rounding, 1e-12).unwrap();
        for (i, (t, h)) in traced.iter().zip(&held).enumerate() {
            let e = (t - h).abs() / s;
            println!(
                "{name} point {i}: traced {t:e}, 50 digits {h:e}, |dev| {e:.2e}, bound {bound:.2e}"
            );
            assert!(
                e <= bound,
                "{name} point {i}: traced {t:e} vs {h:e}: {e:e} > {bound:e}"
            );
        }
    }
}

/// The representation term covers the 50-digit change of T under one representation rounding
/// of the incidence cosine, and is within 100× of it (measured: 3.0× where the Fresnel
/// coefficients' and the power factor's motions, of opposite sign, are added in magnitude;
/// 30× at 89.9999999999999°, where the phase term adds to it).
#[test]
fn the_amplitude_term_covers_a_turn_of_one_rounding_tightly() {
    for name in GRAZING {
        let turn = truth(&format!("turn/{name}"));
        let r = run_text(name, &text(name), false);
        for (i, (g, t)) in turn.iter().zip(&r.representation).enumerate() {
            println!("{name} point {i}: 50-digit turn {g:e}, representation term {t:e}");
            assert!(
                *g <= *t && *t <= 100.0 * g,
                "{name} point {i}: turn {g:e}, term {t:e}"
            );
        }
    }
}

/// The rhomb's representation term is the 50-digit change of the retardance under the same
/// rounding of sin θ at the TIR face, to first order (within 10 %), and covers what the tracer
/// and the closed form differ by (2e-9 … 1.1e-6 rad near the critical angle) within 100×.
#[test]
fn the_rhomb_retardance_term_is_the_derivative_times_one_rounding() {
    for name in RHOMB {
        let turn = truth(&format!("turn/{name}"))[0];
        let r = run_text(name, &text(name), false);
        let term = r.phase_representation[0];
        let m = &r.metrics[0];
        let dev = (m.traced[&Fidelity::Vector][0] - m.analytic[0]).abs();
        println!("{name}: 50-digit turn {turn:e}, term {term:e}, traced − closed form {dev:e}");
        assert!(
            (term - turn).abs() <= 0.1 * turn,
            "{name}: term {term:e} vs 50-digit turn {turn:e}"
        );
        assert!(dev <= term, "{name}: deviation {dev:e} > term {term:e}");
        // Tight: the actual turn is a fraction of a rounding, but not far below it.
        assert!(
            term <= 100.0 * dev,
            "{name}: term {term:e} ≫ deviation {dev:e}"
        );
        assert_eq!(r.representation_tolerance(), term);
    }
}

/// Every found scene above passes `fringe fuzz`'s judgement now (they failed at 6.5e-9 …
/// 2.5e-2 of T and 2e-9 … 1.1e-6 rad of retardance).
#[test]
fn the_found_rotated_scenes_pass_the_fuzz_judgement() {
    for name in GRAZING.iter().chain(&ALSO_FOUND).chain(&RHOMB) {
        let value: serde_json::Value = serde_json::from_str(&text(name)).unwrap();
        let v = fuzz::judge(&value, &file(name));
        println!("{name}: {v:?}");
        assert!(matches!(v, Verdict::Pass { .. }), "{name}: {v:?}");
    }
}

/// At the widened band the gate still sees an error: for the rotated film at 89.99999°
/// (band = derived + representation, 3.9e-9 of T) the detection floors, measured at that
/// band, catch a phase and an amplitude error on one path within the library's 10× of the band
/// (`detection::FLOOR_FACTOR`; measured 8.7× for the amplitude on the weaker path).
#[test]
fn the_widened_band_still_catches_an_injected_error() {
    let name = "fuzz_airy_s1_3321";
    let value: serde_json::Value = serde_json::from_str(&text(name)).unwrap();
    let r = run_text(name, &text(name), false);
    let m = &r.metrics[0];
    let derived = m.derived_tolerance(&r.rounding, 1e-12).unwrap().min(1e-9);
    let band = derived + r.representation_tolerance();
    let mut widened = value.clone();
    widened["references"][0]["tolerances"]["vector"] = serde_json::json!(band);
    widened["references"][0]["tolerance_note"] =
        serde_json::json!("derived plus the representation sensitivity of the direction");
    let d = run_text(name, &widened.to_string(), true)
        .detection
        .expect("detection floors");
    println!(
        "{name}: band {band:e}: phase {:?}, amplitude {:?}",
        d.phase_rad, d.amplitude
    );
    assert!(
        matches!(d.phase_rad, Floor::Caught(e) if e <= FLOOR_FACTOR * band),
        "{:?}",
        d.phase_rad
    );
    assert!(
        matches!(d.amplitude, Floor::Caught(e) if e <= FLOOR_FACTOR * band),
        "{:?}",
        d.amplitude
    );
}
