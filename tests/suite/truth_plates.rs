//! Plates and films outside the library's corner (issue "truth across every valid scene", the
//! `two_beam_plate` classes of `fringe fuzz --seed 7`): an ambient far thinner than the plate
//! (n = 0.001 over n = 1), where the closed form must stay at ~1e-14 of a 50-digit evaluation and
//! the tracer must either trace both beams or refuse the scene with its reason, never drop a
//! beam silently. Expected values come from `tools/two_beam_plate_found_mpmath.py` (the formulas
//! of `tools/two_beam_mpmath.py` at 50 digits for these exact f64 inputs), never from the
//! tracer.

// The 50-digit values are written with the digits mpmath printed; f64 keeps the nearest.
#![allow(clippy::excessive_precision)]

use fringe::accumulate::fidelity::Fidelity;
use fringe::harness::analytic::plate::TwoBeamPlate;
use fringe::harness::case::{build, load, run};
use fringe::trace;
use fringe::trace::path::Target;
use std::path::{Path, PathBuf};

fn found(name: &str) -> load::Case {
    let path = PathBuf::from(env!("CARGO_MANIFEST_DIR")).join(format!("tests/fuzz_found/{name}"));
    load::load(Path::new(&path)).expect("a valid case file")
}

/// The traced `vector` intensity at probe point `k` of `case` and the number of arrivals
/// (channels × paths), traced as `fringe check` traces it.
fn traced(case: &load::Case, k: usize) -> (f64, usize) {
    let pt = &build::probe_points(&case.spec.probe)[k];
    let built = build::build_scene(&case.spec.scene, &pt.overrides).unwrap();
    let lambda_m = build::spectrum(&case.spec.light, &pt.overrides)[0].0;
    let optics = built.scene.optics(lambda_m).unwrap();
    let target = build::target(&pt.observer, &built, lambda_m).unwrap();
    let st = run::trace_settings(case, &built, lambda_m).unwrap();
    let Target::Point(p) = target else {
        panic!("a point probe")
    };
    let plan = trace::plan(&built.scene, &optics, &[p], &st.limits);
    let (arr, _) = trace::arrivals(&built.scene, &optics, &plan, &target, &st);
    (trace::intensity(&arr, Fidelity::Vector), arr.len())
}

/// The scene of `fuzz_two_beam_plate_s7_5` (ambient n = 0.001, plate n = 1.0, 1 µm, 200 nm,
/// source 0.769 m and probe 1.538 m above the top face, 125 m and 250 m away: 88.9°–89.5°).
fn dense_plate() -> TwoBeamPlate {
    TwoBeamPlate {
        n1: 0.001,
        n2: 1.0,
        thickness_m: 1e-6,
        h_src_m: 0.7689744611748701,
        h_obs_m: 1.5379489223497402,
    }
}

/// 50-digit two-beam intensities of [`dense_plate`] at x = 125 m and x = 250.00000000076898 m.
const DENSE_PLATE_50_DIGITS: [(f64, f64); 2] = [
    (125.0, 0.760_660_463_141_624_816_1),
    (250.000_000_000_768_98, 0.635_447_468_356_172_688_9),
];

/// The beam through the plate leaves it into the ambient at the angle it entered. The closed
/// form took the outside cosine of the bottom reflection and the exit from cos θt by Snell's law,
/// cos²θ = 1 − (n2/n1)² sin²θt: with n2/n1 = 1000 and cos θt ≈ 1 − 2e-7, one rounding of cos θt
/// moved cos²θ by 6e-7 of itself, and I was 1.2e-8 off the 50-digit value (more than the
/// tracer's own error there). Now both cosines of every face come from the entry's double-double.
#[test]
fn two_beam_closed_form_holds_over_a_plate_1000_times_denser_than_its_ambient() {
    let t = dense_plate();
    for (x, exact) in DENSE_PLATE_50_DIGITS {
        let got = t.intensity_unpolarized(x, 200.0 * 1e-9);
        let err = (got - exact).abs() / exact;
        assert!(
            err <= 1e-14,
            "x = {x} m: actual {got:e}, expected {exact:e}, err {err:e}"
        );
    }
}

/// `fuzz_two_beam_plate_s7_84`: the same extreme contrast at 1500 nm, the plate tilted by 1°, the
/// probe 1 m above the source. The beam through the plate exists (Snell's invariant has its
/// root), but f64 ray directions leaving a plate 1000× denser than its ambient carry their
/// rounding ×1000 to the target, so Newton's landing stalled at 7e-12 m, above 1e-12 of the
/// scene, and the path was dropped: the second point was traced with one beam, 4e-3 off. A path
/// through parallel planes launched from the invariant is now accepted when its landing error
/// changes its optical path by at most 1e-18 m (second order, Fermat). Both points must carry
/// both beams (two channels × two paths) and agree with the 50-digit intensity (heights and
/// lateral distance taken along the exactly normalized plate normal); the tracer is within
/// 7.2e-13 there, so 1e-11 is a hundredfold tighter than the case's 1e-9.
#[test]
fn a_stalled_landing_through_a_dense_plate_keeps_its_beam() {
    let case = found("fuzz_two_beam_plate_s7_84.json");
    let exact = [0.999_999_936_373_866_488_8, 0.999_999_936_347_440_084_1];
    for (k, exact) in exact.into_iter().enumerate() {
        let (got, arrivals) = traced(&case, k);
        assert_eq!(arrivals, 4, "point {k}: both beams in both channels");
        let err = (got - exact).abs() / exact;
        assert!(
            err <= 1e-11,
            "point {k}: actual {got:e}, expected {exact:e}, err {err:e}"
        );
    }
    // And `fringe check`'s verdict on the case is a pass.
    let r = run::run_with(&case, false).expect("the case runs");
    let m = &r.metrics[0];
    let dev = m.stats(Fidelity::Vector).unwrap().max_abs_dev;
    assert!(dev <= 1e-9, "two_beam_plate: max|dev| {dev:e}");
}

/// `fuzz_two_beam_plate_s7_5`: at the first point (88.9°) the beam through the plate is found
/// and traced; at the second (89.5°) f64 directions land 7.6e-7 m off the target, which would
/// cost the path 1.7e-18 m at second order, above what is accepted. The tracer dropped that
/// path silently and `fringe check` reported 0.25 off (traced 0.824, two-beam 0.635). Now the
/// case is either refused with the reason, or, once the tracer lands the path (better
/// conditioned exit directions), traced with both beams: every traced value then within 1e-7 of
/// the 50-digit one. The traced first point is within 2e-8 of the 50-digit value today: the
/// tracer's own Fresnel coefficients at the exit take cos θ from the inner ray's f64 cosine (the
/// conditioning the closed form no longer has), an open tracer limit the README names.
#[test]
fn a_path_the_solver_cannot_land_is_refused_not_dropped() {
    let case = found("fuzz_two_beam_plate_s7_5.json");
    match run::run_with(&case, false) {
        Err(e) => {
            let msg = e.to_string();
            assert!(
                msg.contains("$.probe") && msg.contains("could not land the path T0 R1 T0"),
                "{msg}"
            );
        }
        Ok(r) => {
            let traced = &r.metrics[0].traced[&Fidelity::Vector];
            for (got, (x, exact)) in traced.iter().zip(DENSE_PLATE_50_DIGITS) {
                let err = (got - exact).abs() / exact;
                assert!(
                    err <= 1e-7,
                    "x = {x} m: traced {got:e}, 50 digits {exact:e}, err {err:e}"
                );
            }
        }
    }
    let (got, arrivals) = traced(&case, 0);
    let exact = DENSE_PLATE_50_DIGITS[0].1;
    assert_eq!(arrivals, 4, "both beams in both channels");
    let e = (got - exact).abs() / exact;
    assert!(e <= 5e-8, "actual {got:e}, expected {exact:e}, err {e:e}");
}
