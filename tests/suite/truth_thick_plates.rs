//! Thick plates in moved frames (issue #12; `fringe fuzz --count 300 --seed 1`, airy scene 159:
//! a 1 m plate, n 10 → 1.5 → 10, 200 nm, transmitted, 0–10°, in a frame tilted by 1°,
//! `tests/fuzz_found/fuzz_airy_s1_159_rotated.json`). Expected values are 50-digit evaluations
//! of the case's own binary64 numbers (`tools/thick_plates_mpmath.py` →
//! `tests/data/thick_plates_mpmath.csv`), at two incident directions: the one the case builds
//! (`written/…`) and that direction normalized once more in f64 (`held/…`), a turn of ~1e-17
//! rad, as the tracer holds a plane wave's direction.
//!
//! What they show (docs/PHYSICS.md §8, "Representation sensitivity"): the tracer is exact for
//! the scene it holds (after `Plane::signed_distance_precise` measured along N/|N|: the f64
//! normal of a rotated plate is unit only to ~1e-16, which held the far face of the metre
//! plate ~1e-16 m off, 1.8e-9 of T); the written and the held scene differ by 6e-9 of T, the
//! scene's own conditioning; `fringe fuzz` judges such a scene at its stated tolerance plus
//! that representation term (`conditioning::direction_sensitivity`), which covers the gap,
//! stays within a small factor of it, and still lets the gate catch an injected error just
//! beyond the band.

use fringe::accumulate::fidelity::Fidelity;
use fringe::harness::case::detection::Floor;
use fringe::harness::case::load;
use fringe::harness::case::run;
use fringe::harness::fuzz::{self, Verdict};
use std::path::PathBuf;

const NAME: &str = "fuzz_airy_s1_159_rotated";

fn file() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR")).join(format!("tests/fuzz_found/{NAME}.json"))
}

fn text() -> String {
    std::fs::read_to_string(file()).unwrap()
}

/// (written, held) 50-digit values, in probe order.
fn truth() -> (Vec<f64>, Vec<f64>) {
    let m = crate::support::mpmath_profiles("thick_plates_mpmath.csv");
    (
        m[&format!("written/{NAME}")].clone(),
        m[&format!("held/{NAME}")].clone(),
    )
}

fn run_text(text: &str, detection: bool) -> run::CaseResult {
    run::run_with(
        &load::parse(&file(), text).expect("a valid case"),
        detection,
    )
    .unwrap()
}

fn scale(v: &[f64]) -> f64 {
    v.iter().fold(0.0f64, |s, x| s.max(x.abs()))
}

/// The traced T equals the exact T of the direction the tracer holds, to 1e-12 of the
/// profile at every angle (3.33°: 1.8e-9 off before the signed distance was measured along
/// N/|N|; 6.67°: 6e-9 off the written direction, 1e-15 off the held one).
#[test]
fn a_rotated_metre_plate_is_exact_for_the_direction_it_holds() {
    let (_, held) = truth();
    let r = run_text(&text(), false);
    let traced = &r.metrics[0].traced[&Fidelity::Vector];
    let s = scale(&held);
    for (i, (t, h)) in traced.iter().zip(&held).enumerate() {
        let e = (t - h).abs() / s;
        println!("point {i}: traced {t:e}, held {h:e}, |dev| {e:.2e}");
        assert!(
            e <= 1e-12,
            "point {i}: traced {t:e} vs 50 digits (held) {h:e}: {e:e}"
        );
    }
}

/// One rounding of the incident direction moves T of this scene by 6e-9 (50 digits, both
/// sides): beyond the stated 1e-9, so no f64 tracer meets that tolerance against the written
/// scene. The representation term covers the gap at every point and is within 100× of it where
/// it is largest (a bound for a turn of 2u, the actual turn is one rounding of ≤ u).
#[test]
fn the_representation_term_covers_one_rounding_of_the_direction_tightly() {
    let (written, held) = truth();
    let s = scale(&written);
    let gaps: Vec<f64> = written
        .iter()
        .zip(&held)
        .map(|(w, h)| (w - h).abs() / s)
        .collect();
    let largest = gaps.iter().fold(0.0f64, |m, g| m.max(*g));
    assert!(
        largest > 1e-9,
        "the written and held scenes differ by {largest:e}"
    );
    let r = run_text(&text(), false);
    let rep: Vec<f64> = r.representation.iter().map(|x| x / s).collect();
    println!("gaps {gaps:?}\nrepresentation {rep:?}");
    for (i, (g, t)) in gaps.iter().zip(&rep).enumerate() {
        assert!(g <= t, "point {i}: gap {g:e} > representation term {t:e}");
    }
    let top = rep.iter().fold(0.0f64, |m, t| m.max(*t));
    assert!(
        top <= 100.0 * largest,
        "representation {top:e} vs gap {largest:e}"
    );
}

/// `fringe fuzz` judges the scene at stated + representation: it passes (it failed at 8.5e-9
/// against 1e-9), and at that band the gate still sees an error: the detection floors, measured at
/// the widened tolerance, catch a phase error on one path and an amplitude error within 10× of
/// the band (the library's rule, docs/PHYSICS.md §8).
#[test]
fn the_fuzz_band_passes_the_scene_and_still_catches_an_injected_error() {
    let value: serde_json::Value = serde_json::from_str(&text()).unwrap();
    let v = fuzz::judge(&value, &file());
    assert!(matches!(v, Verdict::Pass { .. }), "{v:?}");

    let r = run_text(&text(), false);
    let analytic = &r.metrics[0].analytic;
    let rep = r.metrics[0]
        .derived_tolerance(&r.representation, 0.0)
        .unwrap();
    let band = 1e-9 + rep;
    let mut widened = value.clone();
    widened["references"][0]["tolerances"]["vector"] = serde_json::json!(band);
    widened["references"][0]["tolerance_note"] =
        serde_json::json!("stated 1e-9 plus the representation sensitivity of the direction");
    let d = run_text(&widened.to_string(), true)
        .detection
        .expect("detection floors");
    println!(
        "band {band:e} (scale {:e}): phase {:?}, amplitude {:?}",
        scale(analytic),
        d.phase_rad,
        d.amplitude
    );
    assert!(
        matches!(d.phase_rad, Floor::Caught(e) if e < 1e-3),
        "{:?}",
        d.phase_rad
    );
    assert!(
        matches!(d.amplitude, Floor::Caught(e) if e <= 10.0 * band),
        "{:?}",
        d.amplitude
    );
}

// A grazing two-beam plate whose lateral distance is not an f64 (issue #12, `fringe fuzz
// --family two_beam_plate --count 300 --seed 1`, scene 4, shrunk: a 10 cm plate of n = 1.5 in an
// ambient of n = 2, 200 nm, the source 2.5 m off the origin, probes 125 m and 250 m away).
// Expected values: 50 digits of the case's own binary64 numbers, the lateral distance p − s
// exact (`tools/two_beam_plate_held_mpmath.py` → `tests/data/two_beam_plate_held_mpmath.csv`).
// Near grazing the path difference moves by n1 (sin θ1 − sin θexit) ≈ 0.5 m per metre of x, so
// the f64 difference 252.51188643223688 − 2.51188643150958 (off by up to 2.8e-14 m) turned the
// phase by ~4e-7 rad: the reference was 1.7e-9 off while the tracer was exact.

const GRAZING: &str = "fuzz_two_beam_plate_s1_4";

fn grazing_file() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR")).join(format!("tests/fuzz_found/{GRAZING}.json"))
}

fn grazing_truth() -> Vec<f64> {
    crate::support::mpmath_profiles("two_beam_plate_held_mpmath.csv")[GRAZING].clone()
}

/// Tracer and closed form both equal 50 digits of the scene as written, to 1e-14 of the profile
/// (the closed form with heights and lateral distance in double-double, `HeldPoints`; it was
/// 1.7e-9 off at 250 m when it took the f64 difference of the coordinates).
#[test]
fn a_grazing_plate_far_from_its_source_is_exact_in_tracer_and_reference() {
    let truth = grazing_truth();
    let text = std::fs::read_to_string(grazing_file()).unwrap();
    let r = run::run_with(
        &load::parse(&grazing_file(), &text).expect("a valid case"),
        false,
    )
    .unwrap();
    let m = &r.metrics[0];
    let s = scale(&truth);
    for (i, ((t, a), e)) in m.traced[&Fidelity::Vector]
        .iter()
        .zip(&m.analytic)
        .zip(&truth)
        .enumerate()
    {
        let (dt, da) = ((t - e).abs() / s, (a - e).abs() / s);
        println!("point {i}: traced {t:e}, closed form {a:e}, 50 digits {e:e}: {dt:.1e}, {da:.1e}");
        assert!(
            dt <= 1e-14,
            "point {i}: traced {t:e} vs 50 digits {e:e}: {dt:e}"
        );
        assert!(
            da <= 1e-14,
            "point {i}: closed form {a:e} vs 50 digits {e:e}: {da:e}"
        );
    }
    let value: serde_json::Value = serde_json::from_str(&text).unwrap();
    let v = fuzz::judge(&value, &grazing_file());
    assert!(matches!(v, Verdict::Pass { .. }), "{v:?}");
}

/// The same closed form fed the f64-rounded lateral distance of the far probe is off 50 digits by
/// more than the case's 1e-9 (what the gate reported before): the test above can fail, and the
/// double-double lateral distance is what makes the reference exact.
#[test]
fn the_rounded_lateral_distance_alone_puts_the_grazing_reference_beyond_tolerance() {
    use fringe::harness::analytic::plate::TwoBeamPlate;
    let truth = grazing_truth();
    let (hs, ho) = (0.7272943720090697, 1.4545887440181393);
    let plate = TwoBeamPlate {
        n1: 2.0,
        n2: 1.5,
        thickness_m: 100000.0 * 1e-6,
        h_src_m: hs,
        h_obs_m: ho,
    };
    let x = 252.51188643223688 - 2.51188643150958; // rounded to f64
    let rounded = plate.intensity_unpolarized(x, 200.0 * 1e-9);
    let e = (rounded - truth[1]).abs() / scale(&truth);
    println!(
        "rounded x {x:e}: {rounded:e} vs 50 digits {:e}: {e:e}",
        truth[1]
    );
    assert!(e > 1e-9, "{e:e}");
}

// A 0.1 nm film moved away from the origin (issue #12, `fringe fuzz --family airy --count 1000
// --seed 1`, scene 499, shrunk: n = 1.5 in air, 200 nm, s, reflected at 0° and 1°, 100 m out).
// The tracer measured the segments between event points as |b − a|, which adds a point's f64
// rounding δ (~7e-15 m at 100 m) to second order, |δ|²/(2L): with L ~ 1e-10 m inside the film
// that is 5e-19 m per round trip, and R was 3.7e-9 off 50 digits at 100 m, 4e-8 at 1000 m.
// Expected values: `tools/airy_translated_mpmath.py` → `tests/data/airy_translated_mpmath.csv`.

/// The traced R of the film equals 50 digits to 1e-13 of the profile wherever the film is (0 m
/// to 1000 m from the origin), and the gate passes the found scene (segments that end on an event
/// are measured along the ray, `Ray::advance_to_event`, `path::event_segment_length`).
#[test]
fn a_sub_nanometre_film_far_from_the_origin_reflects_as_at_the_origin() {
    const FILM: &str = "fuzz_airy_s1_499";
    let path =
        PathBuf::from(env!("CARGO_MANIFEST_DIR")).join(format!("tests/fuzz_found/{FILM}.json"));
    let text = std::fs::read_to_string(&path).unwrap();
    let truth = crate::support::mpmath_profiles("airy_translated_mpmath.csv")[FILM].clone();
    let s = scale(&truth);
    let value: serde_json::Value = serde_json::from_str(&text).unwrap();
    for y in [0.0, 1.0, 10.0, 100.0, 1000.0] {
        let mut moved = value.clone();
        moved["scene"]["surfaces"][0]["plate"]["top_point_m"] = serde_json::json!([0.0, y, 0.0]);
        moved["scene"]["sources"][0]["emitter"]["plane_wave"]["reference_point_m"] =
            serde_json::json!([0.0, y, 1.0]);
        let r = run_text_at(&path, &moved.to_string());
        for (i, (t, e)) in r.metrics[0].traced[&Fidelity::Vector]
            .iter()
            .zip(&truth)
            .enumerate()
        {
            let dev = (t - e).abs() / s;
            println!("{y} m, point {i}: traced {t:e}, 50 digits {e:e}: {dev:.1e}");
            assert!(
                dev <= 1e-13,
                "{y} m, point {i}: traced {t:e} vs 50 digits {e:e}: {dev:e}"
            );
        }
    }
    let v = fuzz::judge(&value, &path);
    assert!(matches!(v, Verdict::Pass { .. }), "{v:?}");
}

fn run_text_at(path: &std::path::Path, text: &str) -> run::CaseResult {
    run::run_with(&load::parse(path, text).expect("a valid case"), false).unwrap()
}
