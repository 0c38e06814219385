//! The airy scenes `fringe fuzz` still failed at 3eb0153 (issue #12): films on substrates lit
//! at 89.999999999999° from an ambient of n = 0.001 (Brewster's angle of the top face is
//! atan(n_film/0.001), 89.97°), and a 10 mm plate near the critical angle of its top face.
//! Shrunk into `tests/fuzz_found/`; every verdict is against a 50-digit Airy sum of the
//! scene's own binary64 numbers (`tools/grazing_brewster_mpmath.py` →
//! `tests/data/grazing_brewster_mpmath.csv`), never against the tracer's output.
//!
//! Deviations are measured as the gate measures them: divided by the largest 50-digit value of
//! the profile, or by 1e-15 of the source's power where that is larger (the gate's
//! `VANISHING_SCALE`, src/harness/case/run/mod.rs).

use crate::support::{closed_form_error, mpmath_profiles, traced_error};

/// The gate's floor under the scale of a vanishing intensity profile (`VANISHING_SCALE`).
const VANISHING_SCALE: f64 = 1e-15;

/// The gate's base tolerance of the `airy` family at `vector` without representation terms
/// (`fringe fuzz` printed "> 1.0000000000000309e-12" for the shrunk scene 6567).
const GATE: f64 = 1e-12;

/// How far a closed form may be from 50 digits (issue #12: "every closed form's own error
/// ≤ 1e-14 relative").
const CLOSED_FORM: f64 = 1e-14;

/// (traced, closed form) deviation of the case `name` from its 50-digit profile, on the gate's
/// scale.
fn deviations(name: &str) -> (f64, f64) {
    let truth = &mpmath_profiles("grazing_brewster_mpmath.csv")[name];
    let peak = truth.iter().fold(0.0f64, |m, v| m.max(v.abs()));
    let to_gate = peak / peak.max(VANISHING_SCALE);
    let traced = traced_error(name, truth) * to_gate;
    let closed = closed_form_error(name, truth) * to_gate;
    println!("{name}: traced {traced:.3e}, closed form {closed:.3e} off 50 digits");
    (traced, closed)
}

/// Seed 1 scene 7304, shrunk: n 0.001 → 1.5 (1 µm) → 1, plate rotated 1° about y, 200 nm,
/// s polarized, transmitted. Traced T was 4.45e-17 against 6.95e-17: ×0.64 = |1 − r21 r23|²
/// with r21 r23 ≈ +0.2 for s, and for p (`_p`, r21 r23 ≈ −0.2) ×1.44 = |1 + 0.2|²; only the
/// order T0 T1 arrived, none of the multiply reflected ones. After the fix the s scenes are
/// 9.1e-13 off on the gate's scale (T = 7e-17 is below its 1e-15 floor): the orders the case's
/// tail bound leaves out, as for the p variant (below).
///
/// Cause: the sequence enumeration launched its plane-wave probe ray from the wavefront through
/// the reference point, 1 m above the film, so it met the film ~h/cos θ = 5.7e13 m out, where
/// a coordinate rounds by ~1e-2 m. In the rotated frame (unlike the axis-aligned one, whose
/// z coordinates stay exact) the 1 µm film's faces were not resolved there: the ray reflected
/// at the lower face was already above the upper one, and no sequence with an internal
/// reflection was planned. The enumeration now probes from the solver's own stack launch
/// (`path::plane_wave_launch`, a local anchor before the first plane).
#[test]
fn a_rotated_grazing_film_plans_its_internal_reflections() {
    let mut bad = Vec::new();
    for name in ["fuzz_airy_s1_7304", "fuzz_airy_s1_7304_unrotated"] {
        let (traced, closed) = deviations(name);
        if !(traced <= GATE && closed <= CLOSED_FORM) {
            bad.push(format!("{name}: traced {traced:e}, closed form {closed:e}"));
        }
    }
    assert!(bad.is_empty(), "{bad:#?}");
}

/// Seed 1 scene 6567 (film 2.0) and seed 2 scene 2213 (film 1.5), shrunk: n 0.001 → film
/// (1 µm) → 1, 200 nm, reflected, linear at ±300°. The film is 20 and 15 half-waves thick, an
/// absentee layer, so 50 digits give the same R = 1 − 5.2142e-11 for both; the closed form is
/// within 1e-14 of it (asserted here), so the tracer is the side that is wrong.
#[test]
fn the_airy_closed_form_holds_at_grazing_near_brewster() {
    for name in ["fuzz_airy_s1_6567", "fuzz_airy_s2_2213"] {
        let (_, closed) = deviations(name);
        assert!(closed <= CLOSED_FORM, "{name}: closed form {closed:e}");
    }
}

/// The tracer on 6567 and 2213. Before the carried invariant (`interaction::SnellInvariant`)
/// traced 1 − R was 1.0428e-10 and 7.8213e-11: exactly (to 1e-6 of it) 1 − |r12|² of the bare
/// top face 0.001 → film (50 digits: 1.04284e-10 and 7.82132e-11), i.e. no order that crossed
/// the film came back out.
///
/// Cause: the tracer carried (n cos θ)² from medium to medium in double-double, q²_film =
/// q²_amb + n_f² − n_a², and back out q²_amb' = q²_film + n_a² − n_f². Here q²_amb = (0.001 ·
/// 1.738e-14)² = 3.02e-34, below the double-double resolution of q²_film ≈ 4 (~5e-32), and
/// q²_amb' came back as −4.04e-33: the exit through the top face was judged total internal
/// reflection, so every T0 R1 … T0 order was missing. Now every medium's square is formed from
/// the ambient's directly, and the exit gets q²_amb back exactly.
///
/// Rotated (`_rotated`, shrunk again after that fix) the orders through the film still missed
/// their far-field direction: leaving the film (sin θi = 5e-4) for the ambient at cos θt =
/// 1.7e-14, the exit direction's normal part was −5.6e-14 instead of +1.7e-14 (the f64
/// tangential part's ~1e-16 normal residue scaled up by sin θt/sin θi), so the exit pointed
/// back into the film; `interaction::snell_direction` now re-orthogonalizes it.
#[test]
fn a_grazing_absentee_film_reflects_as_50_digits() {
    for name in [
        "fuzz_airy_s1_6567",
        "fuzz_airy_s2_2213",
        "fuzz_airy_s1_6567_rotated",
        "fuzz_airy_s2_2213_rotated",
    ] {
        let (traced, _) = deviations(name);
        assert!(traced <= GATE, "{name}: traced {traced:e}");
    }
}

/// The p-polarized variant of 7304 (`fuzz_airy_s1_7304_p`, rotated, transmitted, T ≈ 7e-11)
/// and 7304 itself (s, T ≈ 7e-17) are both −1.3107e-11 of their T off the 50-digit Airy sum,
/// which looked like a tracer error (it was 3.0e-11 with the chained q², before the carried
/// invariant). It is not one: the case asks for the sum its tail bound cuts
/// (`airy_tail_epsilon` = 1e-15 of the source's amplitude, the smallest the loader takes), the
/// budget traces orders 0–15 (31 internal reflections), and with |r21 r23| = 0.2 for s and p
/// alike the orders left out are −1.3107e-11 of T for both. The traced T equals the 50-digit
/// sum of those 16 orders (`tools/grazing_brewster_mpmath.py`, `<name>/orders_0_15`) to
/// ~1e-16, and the full sum within the case's own tail bound 2√T ε √I0 + ε² I0
/// (2.4e-10 of T here), which the gate's derived tolerance adds (`run::budget`,
/// docs/PHYSICS.md §8): `fringe check` passes the case, rightly.
#[test]
fn a_rotated_grazing_film_transmits_the_orders_its_tail_bound_asks_for() {
    let truth = mpmath_profiles("grazing_brewster_mpmath.csv");
    for name in ["fuzz_airy_s1_7304_p", "fuzz_airy_s1_7304"] {
        let cut = truth[&format!("{name}/orders_0_15")][0];
        crate::support::assert_traced_cut_sum(name, truth[name][0], cut, 31, 1e-15);
    }
}

/// Seed 2 scene 7972, shrunk: n 2.6468 → 2.62 (10 mm) → 10, 786 nm, 81.7396° (cos θ2 = 0.0224,
/// 1496 cycles per round trip), s polarized, transmitted. The closed form is within 1e-14 of
/// 50 digits (asserted); the tracer's per-order amplitudes |t12 r23 r21 … t23|² agree with 50
/// digits to ~1e-15 (orders 0–2 checked).
#[test]
fn the_airy_closed_form_holds_for_a_thick_plate_near_critical() {
    let (_, closed) = deviations("fuzz_airy_s2_7972");
    assert!(
        closed <= CLOSED_FORM,
        "fuzz_airy_s2_7972: closed form {closed:e}"
    );
}

/// The tracer on 7972: T was 4.5e-9 off 50 digits on the gate's scale (3.9e-8 as drawn). Its
/// ~90 orders are all traced (|r21 r23| = 0.72, no tail closed), each round trip running
/// 0.89 m sideways, and the optical path summed along the f64 segments was ~2e-15 m per round
/// trip off (each segment's f64 length varied by 1.8e-15 m between orders), a phase error
/// growing with the order. Every far-field arrival of a plane wave between parallel planes
/// now carries its optical path from Snell's invariant (`trace::parallel_phase`,
/// docs/PHYSICS.md §8), walked or traced one by one: 4.3e-13 off 50 digits.
#[test]
fn a_thick_plate_near_critical_transmits_as_50_digits() {
    let (traced, _) = deviations("fuzz_airy_s2_7972");
    assert!(traced <= GATE, "fuzz_airy_s2_7972: traced {traced:e}");
}
