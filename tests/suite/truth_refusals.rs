//! Refusals that were not justified (issue "truth across every valid scene", done-when:
//! 0 unjustified refusals): valid scenes of `fringe fuzz --family two_beam_plate --seed 1`
//! that the gate refused because a closed form or the tracer could not resolve them.
//!
//! 1. The beam through a plate less dense than its ambient, beyond the top face's critical
//!    angle, enters just below it and runs grazing inside the plate (tan θt up to 3e7 in the
//!    generator's range). The two-beam closed form solved for the entry offset a in f64, which
//!    cannot resolve a_c − a ∝ cos²θt, and refused tan θt > 1e3; it now solves for tan θt in
//!    double-double (`TwoBeamPlate::beam_bottom`). Expected values: 60-digit evaluations of
//!    `tools/steep_plate_mpmath.py` (tests/data/steep_plate_mpmath.csv), never the tracer.
//! 2. The tracer then could not land those paths (`T0 R1 T0`): the launch direction rounded to
//!    f64 carries sin θ0 to ~1e-16, a relative error of ~1e-16/cos²θt of tan θt. The launch now
//!    carries Snell's invariant in double-double (`SolvedPath::launch_normal_q2`), and the path
//!    solver steps between parallel faces along the carried cosine and the faces' own heights.
//! 3. Grazing in a plate of low index under a dense ambient, (n cos θ)² re-based per medium as
//!    q² + n'² − n² lost its digits; the path solver now carries Snell's invariant p².

use crate::support::two_beam_plate_rows;
use fringe::harness::fuzz::{self, Family, Verdict};
use std::path::Path;

/// The two-beam closed form with the beam through the plate at tan θt from 1e2 to 1e10 (the
/// refusal stood at 1e3) against 60 digits: 1e-14 relative, on five plates from n = 1.9 over
/// 1.73 to n = 4.76 over 0.0092.
#[test]
fn steep_plate_beam_closed_form_holds_to_1e_14_up_to_tan_theta_t_1e10() {
    let rows = two_beam_plate_rows("steep_plate_mpmath.csv");
    assert_eq!(rows.len(), 25);
    assert!(rows.iter().any(|r| r.3 >= 1e10));
    let mut bad = Vec::new();
    for (t, x, lambda_m, tan_t, exact) in rows {
        assert!(t.n1 > t.n2);
        let got = t.intensity_unpolarized(x, lambda_m);
        let err = (got - exact).abs() / exact;
        if err.is_nan() || err > 1e-14 {
            bad.push(format!(
                "{t:?} at x = {x} m (tan θt = {tan_t:e}): actual {got:e}, expected {exact:e}, err {err:e}"
            ));
        }
    }
    assert!(bad.is_empty(), "{bad:#?}");
}

/// The beam through the plate is not negligible where the refusal stood: at tan θt = 1e3 it
/// moves I by more than 1e-4 of the top beam's |r12|² = 1 on every plate, so a closed form or a
/// tracer that dropped it would fail by far more than any tolerance.
#[test]
fn the_steep_beam_matters_where_it_was_refused() {
    for (t, _, _, tan_t, exact) in two_beam_plate_rows("steep_plate_mpmath.csv") {
        if tan_t > 999.0 && tan_t < 1001.0 {
            assert!((exact - 1.0).abs() > 1e-4, "{t:?}: I = {exact}");
        }
    }
}

/// Scenes of `fringe fuzz --family two_beam_plate --seed 1` (count 300) that were refused as
/// "runs grazing inside the plate … beyond tan θt = 1e3" (tan θt ≥ 1.2e3 … 2.4e7, plain,
/// rotated and translated): now traced, and within the gate's tolerance of the closed form
/// proven above.
#[test]
fn steep_plate_scenes_are_judged_not_refused() {
    let mut bad = Vec::new();
    for index in [23, 26, 35, 54, 63, 85, 89, 91] {
        let scene = fuzz::scene(Family::TwoBeamPlate, 1, index, None);
        let case = scene.case.expect("a generated case");
        let verdict = fuzz::judge(&case, Path::new(&format!("steep_{index}.json")));
        if !matches!(verdict, Verdict::Pass { .. }) {
            bad.push(format!("scene {index} {:?}: {verdict:?}", scene.tags));
        }
    }
    assert!(bad.is_empty(), "{bad:#?}");
}

/// Scenes of `fringe fuzz --family two_beam_plate --seed 1` (count 1000) that were refused as
/// "could not land the path T0 R1 T0" (scene 25: n = 4.76 over a 3.35 µm plate of n = 0.0092,
/// tan θt = 3e7; the others grazing, n = 0.0011 … 3.2 in plates of 0.18 nm … 3.4 µm): the path
/// solver carried (n cos θ)² across faces as q² + n'² − n² in double-double, which lost
/// ~n1²·1e-32/(n2 cos θt)² (2e-12 of tan θt in scene 25) and the landing stalled at 3.5e-10 m
/// over 200 m. It now carries p² = (n sin θ)² (`stack::step_planes_carried`); they are traced
/// and within the gate's tolerance of the two-beam closed form, proven against 60 digits above.
#[test]
fn grazing_plate_paths_land_and_pass() {
    let mut bad = Vec::new();
    for index in [
        25, 51, 272, 409, 410, 435, 451, 482, 655, 658, 705, 717, 829, 937, 958,
    ] {
        let scene = fuzz::scene(Family::TwoBeamPlate, 1, index, None);
        let case = scene.case.expect("a generated case");
        let verdict = fuzz::judge(&case, Path::new(&format!("land_{index}.json")));
        if !matches!(verdict, Verdict::Pass { .. }) {
            bad.push(format!("scene {index} {:?}: {verdict:?}", scene.tags));
        }
    }
    assert!(bad.is_empty(), "{bad:#?}");
}

/// The thin-plate scenes of `fringe fuzz --family two_beam_plate --seed 1` (count 300) that the
/// path solver could not land ("no convergence … after 1 iterations"): plates of 0.2–14 nm,
/// mostly less dense than their ambient, where the beam through the plate runs grazing inside
/// it (scene 239: n = 0.0046 under 0.081, 0.69 nm, tan θt ≈ 6e8). Diagnosis: the Snell-invariant
/// launch (`stack::parallel_stack_launch`) formed each plane's height as the source's distance
/// from it rounded to f64 and then the plate's thickness as the difference of two such ~0.65 m
/// heights, 1.6e-7 of a 0.69 nm plate off; the plate's lateral run (~0.8 m) was as far off, the
/// launch missed by 4e-8 m, and Newton could not step (a finite-difference launch beyond the
/// critical angle is totally reflected). The heights are now kept in double-double until the
/// segment heights are formed, so a plate's faces differ by its exact thickness.
const THIN_PLATE_SCENES: [usize; 8] = [49, 185, 226, 231, 235, 236, 239, 240];

/// Those scenes are judged, not refused, and pass the gate.
#[test]
fn thin_plate_paths_land_and_pass() {
    let mut bad = Vec::new();
    for index in THIN_PLATE_SCENES {
        let scene = fuzz::scene(Family::TwoBeamPlate, 1, index, None);
        let case = scene.case.expect("a generated case");
        let verdict = fuzz::judge(&case, Path::new(&format!("thin_{index}.json")));
        if !matches!(verdict, Verdict::Pass { .. }) {
            bad.push(format!("scene {index} {:?}: {verdict:?}", scene.tags));
        }
    }
    assert!(bad.is_empty(), "{bad:#?}");
}

/// The traced intensities of those scenes (case files `tests/fuzz_found/
/// fuzz_two_beam_plate_s1_<index>.json`, the generator's own output) against 60-digit
/// evaluations of the two-beam sum from their binary64 inputs
/// (`tools/thin_plate_found_mpmath.py`, tests/data/thin_plate_mpmath.csv), never against the
/// tracer or the f64 closed form: within 1e-10 of each profile's largest value. The six scenes
/// with the paper's two channels (226 and 240 carry basis-free unpolarized light, which the
/// script's two-channel sum does not model; they are judged against the closed form above).
#[test]
fn thin_plate_traced_intensities_hold_against_60_digits() {
    crate::support::assert_traced_within("thin_plate_mpmath.csv", 6, 1e-10);
}
