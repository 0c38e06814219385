//! The beam through a plate less dense than its ambient, landed (issue #12): `fringe fuzz
//! --family two_beam_plate --count 10000 --seed 1` (main 3550238) refused 80 scenes with "the
//! path solver could not land the path T0 R1 T0 on a probe point". Each is a plate of n2 < n1
//! seen near grazing: the beam through it enters below the top face's critical angle, close to
//! the source, and crosses most of the lateral distance grazing inside the plate (scene 271: a
//! 1.19 nm plate of n = 0.0065 in air, probe 248 m away, tan θt = 1.0e11).
//!
//! The launch came from Snell's invariant p solved in double-double (`parallel_stack_launch`),
//! and the plate's (n2 cos θt)² was formed as n2² − p²: with p within 1e-22 of n2 that keeps
//! ~1e-32/cos²θt = 1e-10 of tan θt, so the 248 m run inside the plate was ~5e-9 m off and the
//! landing stalled at 5.4e-9 m (the tolerance is 1e-12 of the scene, 2.5e-10 m). The solver now
//! holds the invariant as the grazing medium's own (n cos θ)² (`path::stack::Invariant`), refined
//! by Newton's method on that square, so the run and the landing keep ~1e-16 of themselves.
//!
//! Six of the scenes, their probe lines cut to the two end points, are
//! `tests/fuzz_found/fuzz_two_beam_plate_s1_{271,1128,2105,4795,6899,9551}.json`; the 50-digit
//! values are `tools/plate_landing_mpmath.py` → `tests/data/plate_landing_mpmath.csv` (the
//! intensity) and `tests/data/plate_landing_paths_mpmath.csv` (the beam through the plate).
//!
//! What the observable sees: in all 80 scenes the beam through the plate carries an amplitude
//! ∝ cos θt (≤ 6e-9 of the top beam's in scene 271), so the two-beam intensity does not see
//! it at the gate's tolerance (`fringe check` of these cases: an error of 1 in that beam's phase
//! or amplitude does not fail the case). A landing miss δ changes that beam's optical path by
//! at most n δ²/(2 L3) (Fermat: the exit bundle of parallel planes diverges) and its amplitude
//! by ~δ/run: the refusal was not justified, and the path itself is what is checked here.

use fringe::harness::case::build::{Overrides, build_scene};
use fringe::harness::case::load;
use fringe::harness::fuzz::{self, Family, Verdict};
use fringe::trace::path::{Event, EventKind, SolveOptions, Target, solve};
use glam::DVec3;
use std::path::PathBuf;

const FOUND: [u32; 6] = [271, 1128, 2105, 4795, 6899, 9551];

/// Every scene `fringe fuzz --family two_beam_plate --count 10000 --seed 1` refused on main
/// 3550238 because T0 R1 T0 did not land.
const REFUSED: [usize; 80] = [
    271, 309, 346, 459, 537, 585, 604, 846, 849, 1128, 1511, 1581, 1632, 1650, 1788, 1803, 1831,
    1928, 1982, 2105, 2106, 2405, 2529, 2644, 2734, 2758, 2899, 2910, 3118, 3147, 3188, 3384, 3585,
    3707, 3772, 3797, 3876, 3893, 4016, 4157, 4188, 4415, 4472, 4532, 4711, 4778, 4795, 4945, 4957,
    5073, 5513, 5831, 5974, 6040, 6531, 6713, 6899, 7161, 7175, 7288, 7293, 7419, 7428, 7650, 7693,
    7815, 8301, 8613, 8669, 8705, 8818, 9196, 9225, 9279, 9551, 9586, 9662, 9742, 9749, 9864,
];

fn found(n: u32) -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR"))
        .join(format!("tests/fuzz_found/fuzz_two_beam_plate_s1_{n}.json"))
}

/// The beam through the plate of case `n`, solved to each of its two probe points, with the
/// ambient and plate indices and the plate's top point (m).
fn beams_through(n: u32) -> (Vec<fringe::trace::path::SolvedPath>, f64, f64, DVec3) {
    let path = found(n);
    let case = load::parse(&path, &std::fs::read_to_string(&path).unwrap()).unwrap();
    let built = build_scene(&case.spec.scene, &Overrides::default()).unwrap();
    let json: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(&path).unwrap()).unwrap();
    let lambda_m = json["light"]["monochrome"]["wavelength_nm"]
        .as_f64()
        .unwrap()
        * 1e-9;
    let optics = built.scene.optics(lambda_m).unwrap();
    let (top, bottom) = (
        built.surface("plate.top").unwrap(),
        built.surface("plate.bottom").unwrap(),
    );
    let ev = |surface, kind| Event { surface, kind };
    let seq = [
        ev(top, EventKind::Refract),
        ev(bottom, EventKind::Reflect),
        ev(top, EventKind::Refract),
    ];
    let emitter = built.scene.sources[0].emitter;
    let line = &json["probe"]["line"];
    let point = |k: &str| {
        let v: Vec<f64> = line[k]
            .as_array()
            .unwrap()
            .iter()
            .map(|x| x.as_f64().unwrap())
            .collect();
        DVec3::new(v[0], v[1], v[2])
    };
    let paths = [point("from_m"), point("to_m")]
        .iter()
        .map(|&p| {
            solve(
                &built.scene,
                &optics,
                emitter,
                &seq,
                Target::Point(p),
                &SolveOptions::default(),
            )
            .unwrap_or_else(|e| panic!("scene {n}: T0 R1 T0 to {p}: {e}"))
        })
        .collect();
    let n_plate = optics.surfaces[top]
        .map(|o| match o {
            fringe::optics::interaction::SurfaceOptics::Dielectric { n_front, n_back } => {
                n_front.min(n_back)
            }
            _ => unreachable!(),
        })
        .unwrap();
    let top_point = built.scene.surfaces[top].plane.point;
    (paths, optics.ambient_index, n_plate, top_point)
}

/// The beam through the plate lands on both probe points to 1e-12 of the scene (it stalled at
/// 7.6e-11 … 5.8e-7 m), and its lateral run inside the plate, its optical path and its cos θt
/// are those of 50 digits: the run to 1e-14 of itself (main's stalled launch was 2e-11 of it
/// off in scene 271, 5.4e-9 m at 248 m); cos θt, which the traced ray forms from the launch's
/// Snell invariant as carried (`SolvedPath::launch_normal_q2`, held as the plate's own
/// (n2 cos θt)², refined by Newton to ~1e-31 of itself), to 1e-15 relative (main 3eb0153 carried
/// the ambient's (n0 cos θ0)² and re-formed the plate's from it, 4·2⁻¹⁰⁴ n0²/q_t² relative: up
/// to 5e-4 in scene 6899, where cos θt = 8.5e-13; the beam's amplitude, ∝ cos θt, was that far
/// off, `the_beam_through_a_grazing_plate_carries_its_exact_amplitude`); and the optical path
/// to the scene's representation:
/// a rotated plate's unit normal is held in f64, which tilts the plate by ~2⁻⁵³ rad about its
/// top point against the written scene the 50 digits evaluate, and moves the heights of source
/// and probe, and the steep outer legs with them, by ≤ u |x − top| (u = 2⁻⁵²): bound
/// 4u (n0 (|s − top| + |p − top|) + path). A flat 1e-15 of the path, tried first, failed scene
/// 9551 (rotated: 3.8e-15 m, 3.2e-15 of its 1.2 m path); the unrotated scenes are exact.
#[test]
fn the_beam_through_a_grazing_plate_lands_on_the_exact_path() {
    let truth = crate::support::mpmath_profiles("plate_landing_paths_mpmath.csv");
    for n in FOUND {
        let name = format!("fuzz_two_beam_plate_s1_{n}");
        let (paths, n0, n2, top) = beams_through(n);
        for (k, path) in paths.iter().enumerate() {
            let (source, target) = (path.points[0], *path.points.last().unwrap());
            let scale = (target - source).length();
            let run = (path.points[3] - path.points[1]).length();
            let run_true = truth[&format!("{name}/run")][k];
            let op_true = truth[&format!("{name}/path")][k];
            let cos_true = truth[&format!("{name}/cos_t")][k];
            let (_, invariant) = path.launch_normal_q2.expect("a stack launch");
            let q_t2 = invariant.q2_in(n2).to_f64();
            let cos_t = q_t2.sqrt() / n2;
            let run_err = (run - run_true).abs() / run_true;
            let op_err = (path.optical_path_m() - op_true).abs();
            let op_bound = 4.0
                * f64::EPSILON
                * (n0 * ((source - top).length() + (target - top).length()) + op_true);
            let cos_err = (cos_t - cos_true).abs() / cos_true;
            // √ and the division by n2 in f64 (2u), q_t² rounded to f64 (u/2): ≤ 4u.
            let cos_bound = 4.0 * f64::EPSILON / 2.0;
            println!(
                "{name} point {k}: landing {:e} m (tolerance {:e}), run {run:e} m err {run_err:.1e}, \
                 optical path err {op_err:.1e} m (bound {op_bound:.1e}), cos θt {cos_t:e} err {cos_err:.1e} (bound {cos_bound:.1e})",
                path.landing_error,
                1e-12 * scale
            );
            assert!(path.landing_error <= 1e-12 * scale, "{name} {k}");
            assert!(run_err <= 1e-14, "{name} {k}: run {run_err:e}");
            assert!(op_err <= op_bound, "{name} {k}: optical path {op_err:e} m");
            assert!(cos_err <= cos_bound, "{name} {k}: cos θt {cos_err:e}");
        }
    }
}

/// The amplitude of the beam through the plate, traced to each probe point as `fringe check`
/// traces it, against 50 digits (`tools/plate_landing_mpmath.py paths`, `<name>/amp_s`,
/// `amp_p`): the magnitude of the Fresnel product t12 r21 t21 the ray's ledger applied, per
/// polarization. Near grazing inside the plate t12 t21 ∝ cos θt, so the amplitude is as good
/// as the cos θt the tracer forms its coefficients from. Bound: the three coefficients each to
/// a few roundings of their f64 inputs (cos θi, cos²θt from the carried invariant, the indices),
/// 8u apiece, and their product: 32u = 7.1e-15 relative. Main 3eb0153 formed the plate's
/// (n2 cos θt)² from the ambient's (n0 cos θ0)², 4·2⁻¹⁰⁴ n0²/q_t² off, and this beam's
/// amplitude was 1e-9 … 5e-4 off (scene 6899, cos θt = 8.5e-13).
#[test]
fn the_beam_through_a_grazing_plate_carries_its_exact_amplitude() {
    use fringe::harness::case::{build, run};
    use fringe::optics::ray::LedgerEntry;
    use fringe::trace;
    let truth = crate::support::mpmath_profiles("plate_landing_paths_mpmath.csv");
    let bound = 32.0 * f64::EPSILON / 2.0;
    let mut worst = 0.0f64;
    for n in FOUND {
        let name = format!("fuzz_two_beam_plate_s1_{n}");
        let case = load::load(&found(n)).expect("a valid case file");
        for (k, pt) in build::probe_points(&case.spec.probe).iter().enumerate() {
            let built = build::build_scene(&case.spec.scene, &pt.overrides).unwrap();
            let lambda_m = build::spectrum(&case.spec.light, &pt.overrides)[0].0;
            let optics = built.scene.optics(lambda_m).unwrap();
            let target = build::target(&pt.observer, &built, lambda_m).unwrap();
            let st = run::trace_settings(&case, &built, lambda_m).unwrap();
            let fringe::trace::path::Target::Point(p) = target else {
                panic!("a point probe")
            };
            let plan = trace::plan(&built.scene, &optics, &[p], &st.limits);
            let (arrivals, _) = trace::arrivals(&built.scene, &optics, &plan, &target, &st);
            let through: Vec<_> = arrivals
                .iter()
                .filter(|a| {
                    a.path.sequence.iter().map(|e| e.kind).eq([
                        EventKind::Refract,
                        EventKind::Reflect,
                        EventKind::Refract,
                    ])
                })
                .collect();
            assert!(
                !through.is_empty(),
                "{name} {k}: the beam through the plate"
            );
            for a in through {
                let mut amp = [1.0f64; 2];
                for e in a.vector.ledger.entries.iter() {
                    match e {
                        LedgerEntry::Reflection { r_s, r_p, .. } => {
                            amp[0] *= r_s.norm();
                            amp[1] *= r_p.norm();
                        }
                        LedgerEntry::Refraction { t_s, t_p, .. } => {
                            amp[0] *= t_s.norm();
                            amp[1] *= t_p.norm();
                        }
                        _ => {}
                    }
                }
                for (sigma, got) in ["amp_s", "amp_p"].iter().zip(amp) {
                    let want = truth[&format!("{name}/{sigma}")][k];
                    let err = (got - want).abs() / want;
                    println!("{name} point {k} {sigma}: {got:e} vs {want:e}, rel {err:.1e}");
                    worst = worst.max(err);
                    assert!(err <= bound, "{name} {k} {sigma}: {err:e} > {bound:e}");
                }
            }
        }
    }
    println!("worst {worst:.1e} (bound {bound:.1e})");
}

/// The two-beam intensity of the six scenes, traced, against 50 digits: within 1e-14 of the
/// profile.
#[test]
fn the_landed_scenes_trace_to_50_digits() {
    crate::support::assert_traced_within("plate_landing_mpmath.csv", FOUND.len(), 1e-14);
}

/// All 80 scenes as drawn (five probe points, rotated and translated) now pass the fuzz gate
/// at their derived tolerance: none is refused, none fails.
#[test]
fn every_formerly_unlanded_scene_passes_the_fuzz_gate() {
    crate::support::assert_drawn_scenes_pass(REFUSED.iter().map(|&i| (Family::TwoBeamPlate, 1, i)));
}

/// Scenes 5672, 6363 and 6541 of `fringe fuzz --family two_beam_plate --seed 1` (micrometre
/// plates translated hundreds of metres) hold the probe 0.9e-9 … 1.35e-9 rad out of the source's
/// plane of incidence by rounding alone; the `two_beam_plate` reference refused anything beyond
/// 1e-9. The two channels then mix s and p by that angle ε, which moves the channel sum by
/// O(ε²) (≤ 2ε² = 8e-14 at the reference's bound of 2e-7): they are judged, and pass.
const OFF_PLANE_BY_ROUNDING: [usize; 3] = [5672, 6363, 6541];

/// The case of two_beam_plate scene `index` (seed 1) with its polarization reference turned by
/// `eps` rad toward n × reference (in the plate's plane, out of the plane of incidence).
fn with_reference_turned(index: usize, eps: f64) -> serde_json::Value {
    let sc = fuzz::scene(Family::TwoBeamPlate, 1, index, None);
    let mut case = sc.case.expect("the generator builds it");
    let vec3 = |v: &serde_json::Value| {
        let a = v.as_array().expect("a 3-vector");
        DVec3::new(
            a[0].as_f64().unwrap(),
            a[1].as_f64().unwrap(),
            a[2].as_f64().unwrap(),
        )
    };
    let n = vec3(
        &case["scene"]["surfaces"]
            .as_array()
            .unwrap()
            .iter()
            .find_map(|s| s.get("plate"))
            .expect("a plate")["normal"],
    );
    let pol = &mut case["scene"]["sources"][0]["polarization"]["unpolarized"]["reference"];
    let r = vec3(pol);
    let turned = (r + eps * n.cross(r).normalize()).normalize();
    *pol = serde_json::json!([turned.x, turned.y, turned.z]);
    case
}

#[test]
fn references_off_the_plane_by_rounding_are_judged_and_pass() {
    let mut bad = Vec::new();
    for &i in &OFF_PLANE_BY_ROUNDING {
        for eps in [0.0, 1e-8] {
            let v = fuzz::judge(
                &with_reference_turned(i, eps),
                &PathBuf::from(format!("fuzz_two_beam_plate_s1_{i}.json")),
            );
            if !matches!(v, Verdict::Pass { .. }) {
                bad.push(format!("scene {i}, turned {eps}: {v:?}"));
            }
        }
    }
    assert!(bad.is_empty(), "{bad:#?}");
}

/// A reference turned 1e-5 rad out of the plane of incidence (beyond the 2e-7 bound) is
/// still refused with the reason, never judged.
#[test]
fn a_reference_visibly_off_the_plane_of_incidence_is_refused() {
    let v = fuzz::judge(
        &with_reference_turned(OFF_PLANE_BY_ROUNDING[0], 1e-5),
        &PathBuf::from("off_plane.json"),
    );
    match v {
        Verdict::Refused { reason } => assert!(
            reason.contains("perpendicular to every plane of incidence"),
            "{reason}"
        ),
        other => panic!("not refused: {other:?}"),
    }
}
