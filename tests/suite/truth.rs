//! The gate's verdicts hold outside the library's comfortable corner (issue "truth across every
//! valid scene"): closed forms take their media from the scene, traced values and closed forms
//! are the same observable, and a rigid motion of a scene changes neither values nor verdicts.

use fringe::accumulate::fidelity::Fidelity;
use fringe::harness::case::load::{self, Case};
use fringe::harness::case::run::{self, CaseResult};
use serde_json::{Value, json};
use std::path::{Path, PathBuf};

fn library(name: &str) -> Value {
    let path = PathBuf::from(env!("CARGO_MANIFEST_DIR")).join(format!("cases/{name}.json"));
    serde_json::from_str(&std::fs::read_to_string(path).unwrap()).unwrap()
}

fn parse(v: &Value) -> Case {
    load::parse(Path::new("edited.json"), &v.to_string()).expect("a valid case")
}

/// Every metric with a `vector` tolerance: (metric, max deviation, tolerance).
fn vector_rows(r: &CaseResult) -> Vec<(String, f64, f64)> {
    r.metrics
        .iter()
        .filter_map(|m| {
            let tol = *m.tolerances.get(&Fidelity::Vector)?;
            let s = m.stats(Fidelity::Vector)?;
            Some((m.name.clone(), s.max_abs_dev, tol))
        })
        .collect()
}

fn assert_passes(name: &str, r: &CaseResult) {
    for (metric, dev, tol) in vector_rows(r) {
        assert!(
            dev <= tol,
            "{name}: {metric}: traced vs closed form {dev:e} > tolerance {tol:e}"
        );
    }
}

/// Young, the wedge, the Michelson and the paper's coherence rule in water (n = 1.333) instead
/// of air: the tracer is right there, so every closed form must agree with it. Before the
/// closed forms read the ambient index, each of these failed by O(1) (the phase 2π(r1 − r2)/λ
/// misses the factor n). The values must also differ from the case in air, so the test cannot
/// pass by ignoring the medium on both sides.
#[test]
fn closed_forms_take_their_media_from_the_scene() {
    for name in [
        "young_paper",
        "wedge_fizeau",
        "michelson",
        "coherence_length_paper_rule",
    ] {
        let mut doc = library(name);
        let in_air = run::run_with(&parse(&doc), false).unwrap();
        doc["scene"]["media"]["air"] = json!({ "constant": { "n": 1.333 } });
        let in_water = run::run_with(&parse(&doc), false).unwrap();
        assert_passes(name, &in_water);
        let primary = |r: &CaseResult| r.metrics[0].analytic.clone();
        let moved = primary(&in_air)
            .iter()
            .zip(primary(&in_water))
            .map(|(a, w)| (a - w).abs())
            .fold(0.0, f64::max);
        assert!(moved > 1e-3, "{name}: the closed form ignores the medium");
    }
}

/// The oil film on water observed in transmission: the closed form returns the power
/// transmittance T = (n3 cos θ3)/(n1 cos θ1)|t|², and the far-field probe now measures the same
/// (before, the trace reported |t|² and every such scene failed by n3 cos θ3/(n1 cos θ1)).
/// Independently of any closed form, the traced R and T of the lossless film add up to 1.
#[test]
fn a_film_on_a_substrate_is_compared_as_power_transmittance() {
    let reflected = library("thin_film_on_substrate");
    let mut transmitted = reflected.clone();
    let observe = &mut transmitted["probe"]["sweep"]["observe"]["far_field"];
    observe["side"] = json!("transmitted");
    observe["exit_medium"] = json!("water");
    let r = run::run_with(&parse(&reflected), false).unwrap();
    let t = run::run_with(&parse(&transmitted), false).unwrap();
    assert_passes("transmitted", &t);
    assert_eq!(
        t.observable,
        fringe::optics::observable::Observable::Transmittance
    );
    let (rv, tv) = (
        &r.metrics[0].traced[&Fidelity::Vector],
        &t.metrics[0].traced[&Fidelity::Vector],
    );
    for (k, (a, b)) in rv.iter().zip(tv).enumerate() {
        assert!(
            (a + b - 1.0).abs() < 1e-12,
            "point {k}: traced R + T = {} + {} = {}",
            a,
            b,
            a + b
        );
    }
}

/// A single face 1 → 1.5 at normal incidence traced as one plane-wave beam into the glass:
/// T = 4n/(1 + n)² = 0.96, not |t|² = 0.64 (B&W §1.5.3).
#[test]
fn one_face_transmits_four_n_over_one_plus_n_squared() {
    let doc = json!({
        "name": "one_face",
        "description": "one face",
        "formula": "T = 4n/(1+n)^2",
        "light": { "monochrome": { "wavelength_nm": 550 } },
        "scene": {
            "ambient": "air",
            "media": { "air": { "constant": { "n": 1.0 } }, "glass": { "constant": { "n": 1.5 } } },
            "surfaces": [ { "interface": { "name": "face", "point_m": [0, 0, 0], "normal": [0, 0, 1],
                                           "front": "air", "back": "glass" } } ],
            "sources": [ { "name": "beam",
                "emitter": { "plane_wave": { "direction": [0, 0, -1], "reference_point_m": [0, 0, 0.001] } },
                "polarization": { "linear": { "reference": [0, 1, 0], "angle_deg": 0 } } } ]
        },
        "probe": { "single": { "observe": { "far_field": {
            "side": "transmitted", "surface_normal": [0, 0, 1], "exit_medium": "glass" } } } },
        "references": [ { "model": { "plane_wave_beams": { "beams": [
            { "source": "beam", "events": [ { "surface": "face", "reflect": false } ] } ] } },
            "tolerances": { "vector": 1e-12 } } ],
        "fidelities": ["vector"]
    });
    let r = run::run_with(&parse(&doc), false).unwrap();
    let expected = 4.0 * 1.5 / (2.5f64 * 2.5);
    for v in [
        r.metrics[0].analytic[0],
        r.metrics[0].traced[&Fidelity::Vector][0],
    ] {
        assert!(
            (v - expected).abs() < 1e-14,
            "actual {v:e}, expected {expected:e}"
        );
    }
}

/// A closed form and a probe that measure different things cannot be compared: the Airy power
/// reflectance at a screen point, and an `exit_medium` on the reflected side (where the wave
/// leaves into the ambient), are bad input naming the key.
#[test]
fn a_mismatched_observable_is_refused() {
    let mut doc = library("plate_airy_s");
    doc["probe"] = json!({ "single": { "observe": { "point": { "position_m": [0, 0, 0.01] } } } });
    doc["trace"] = json!({});
    let e = run::run_with(&parse(&doc), false).unwrap_err();
    assert_eq!(e.json_path, "$.references[0].model", "{e}");
    assert!(e.message.contains("power reflectance"), "{e}");

    let mut doc = library("plate_airy_s");
    doc["probe"]["sweep"]["observe"]["far_field"]["exit_medium"] = json!("glass");
    let e = run::run_with(&parse(&doc), false).unwrap_err();
    assert_eq!(
        e.json_path, "$.probe.sweep.observe.far_field.exit_medium",
        "{e}"
    );
}

/// Keys whose 3-vectors are directions (rotated); other 3-vectors with a `_m` key are points
/// (rotated and translated). Sellmeier coefficients (`b`, `c_um2`) are not vectors.
const DIRECTION_KEYS: [&str; 10] = [
    "normal",
    "axis",
    "direction",
    "reference",
    "u_axis",
    "v_axis",
    "hinge_axis",
    "in_plane_axis",
    "surface_normal",
    "looks_toward",
];

/// The case `doc` moved rigidly: every point p ↦ q·p + shift, every direction d ↦ q·d.
fn moved(doc: &Value, q: glam::DQuat, shift: glam::DVec3) -> Value {
    fn walk(v: &mut Value, key: &str, q: glam::DQuat, shift: glam::DVec3) {
        match v {
            Value::Object(map) => {
                for (k, x) in map.iter_mut() {
                    walk(x, k, q, shift);
                }
            }
            Value::Array(items) => {
                let nums: Option<Vec<f64>> = items.iter().map(Value::as_f64).collect();
                match nums {
                    Some(n)
                        if n.len() == 3
                            && (key.ends_with("_m") || DIRECTION_KEYS.contains(&key)) =>
                    {
                        let p = glam::DVec3::from_slice(&n);
                        let r = if key.ends_with("_m") {
                            q * p + shift
                        } else {
                            q * p
                        };
                        *v = json!([r.x, r.y, r.z]);
                    }
                    _ => items.iter_mut().for_each(|x| walk(x, key, q, shift)),
                }
            }
            _ => {}
        }
    }
    let mut out = doc.clone();
    walk(&mut out, "", q, shift);
    out
}

/// A rigid rotation (about axes no case is aligned with) and a 1 cm translation of every library
/// case: every `vector` row still passes its tolerance and the traced primary profile is the
/// same to within that tolerance (relative to its largest value). Before, rotated TIR and rhomb
/// scenes were refused ("needs every event in one plane of incidence": at a normal-incidence
/// face s fell back to a fixed axis), and a rotated small-angle wedge was refused as "needs s
/// polarization" by a 1e-12 test on a hinge known only to ~1e-16/α.
#[test]
fn a_rigid_motion_changes_neither_values_nor_verdicts() {
    let motions = [
        (
            glam::DVec3::new(1.0, 2.0, 3.0),
            0.7,
            glam::DVec3::new(0.01, -0.004, 0.002),
        ),
        (
            glam::DVec3::new(-2.0, 0.5, 1.0),
            2.9,
            glam::DVec3::new(-0.003, 0.008, 0.005),
        ),
    ];
    for file in crate::support::library::case_files() {
        let name = file.file_stem().unwrap().to_string_lossy().to_string();
        let doc = library(&name);
        let base = run::run_with(&parse(&doc), false).unwrap();
        for (axis, angle, shift) in motions {
            let q = glam::DQuat::from_axis_angle(axis.normalize(), angle);
            let r = run::run_with(&parse(&moved(&doc, q, shift)), false)
                .unwrap_or_else(|e| panic!("{name} rotated by {angle} about {axis}: {e}"));
            assert_passes(&format!("{name} rotated by {angle} about {axis}"), &r);
            for (m0, m1) in base.metrics.iter().zip(&r.metrics) {
                let (Some(tol), Some(a), Some(b)) = (
                    m0.tolerances.get(&Fidelity::Vector),
                    m0.traced.get(&Fidelity::Vector),
                    m1.traced.get(&Fidelity::Vector),
                ) else {
                    continue;
                };
                let scale = a.iter().fold(1e-15f64, |s, x| s.max(x.abs()));
                // The moved scene is the scene only up to the rounding of its rotated
                // coordinates, which moves a value by the scene's own conditioning (5e-12 in
                // bk7_dispersion: its 5 µm plate's faces, moved by 1 cm, are ~2e-18 m off, the
                // thickness by 3.5e-13 of itself, β = 171 rad by 6e-11 rad). The closed form on
                // each scene reads the same faces and carries that change, so the
                // tracer's *error* must be the same to the case's tolerance, and the values to
                // 1e-9 (or the tolerance, if looser).
                let (u0, u1) = (&m0.analytic, &m1.analytic);
                for (k, (x, y)) in a.iter().zip(b).enumerate() {
                    assert!(
                        (x - y).abs() <= tol.max(1e-9) * scale,
                        "{name} {}: point {k}: {x:e} before, {y:e} after the motion",
                        m0.name
                    );
                    if let (Some(u), Some(v)) = (u0.get(k), u1.get(k)) {
                        assert!(
                            ((x - u) - (y - v)).abs() <= tol * scale,
                            "{name} {}: point {k}: error {:e} before, {:e} after the motion",
                            m0.name,
                            x - u,
                            y - v
                        );
                    }
                }
            }
        }
    }
}

/// A reference wired to a surface of the wrong kind, or an Airy film observed about another
/// normal, is bad input at the key that names it (before: NaN rows or deviations of 1).
#[test]
fn references_must_match_their_scene() {
    // The wedge reference naming a plate.
    let mut doc = library("wedge_fizeau");
    let wedge = doc["scene"]["surfaces"][0]["wedge"].clone();
    doc["scene"]["surfaces"][0] = json!({ "plate": {
        "name": wedge["name"], "top_point_m": wedge["top_point_m"], "normal": wedge["normal"],
        "thickness_um": wedge["thickness_um"], "medium": wedge["medium"],
        "above": wedge["above"], "below": wedge["below"] } });
    let e = run::run_with(&parse(&doc), false).unwrap_err();
    assert_eq!(e.json_path, "$.references[0].model.wedge.wedge", "{e}");
    assert!(e.message.contains("is a plate"), "{e}");

    // A Michelson "mirror" that is a splitter.
    let mut doc = library("michelson");
    let k = doc["scene"]["surfaces"]
        .as_array()
        .unwrap()
        .iter()
        .position(|s| s.get("mirror").is_some())
        .unwrap();
    let m = doc["scene"]["surfaces"][k]["mirror"].clone();
    doc["scene"]["surfaces"][k] = json!({ "splitter": {
        "name": m["name"], "point_m": m["point_m"], "normal": m["normal"], "reflectance": 0.5 } });
    let e = run::run_with(&parse(&doc), false).unwrap_err();
    assert!(
        e.json_path
            .starts_with("$.references[0].model.michelson.mirrors["),
        "{e}"
    );

    // The Airy film observed about a normal that is not the film's.
    let mut doc = library("plate_airy_s");
    doc["probe"]["sweep"]["observe"]["far_field"]["surface_normal"] = json!([0, 1, 1]);
    let e = run::run_with(&parse(&doc), false).unwrap_err();
    assert_eq!(
        e.json_path, "$.probe.sweep.observe.far_field.surface_normal",
        "{e}"
    );
}

/// Every library case can see errors of the size of its tolerance: a phase offset or an
/// amplitude error on one path of at most 10× the `vector` tolerance fails it (where the
/// error changes the observable at all). A case that could not see them would pass a wrong
/// tracer. The floors are bounded below too: an error far smaller than the tolerance must
/// not fail a passing case.
#[test]
fn every_library_case_sees_errors_of_its_tolerance() {
    use fringe::harness::case::detection::Floor;
    for file in crate::support::library::case_files() {
        let case = load::load(&file).unwrap();
        let r = run::run(&case).unwrap();
        let Some(d) = r.detection else { continue };
        for (what, floor) in [("phase", d.phase_rad), ("amplitude", d.amplitude)] {
            match floor {
                Floor::Caught(f) => assert!(
                    f <= 10.0 * d.tolerance && f >= 1e-3 * d.tolerance,
                    "{}: {what} floor {f:e} against tolerance {:e}",
                    r.name,
                    d.tolerance
                ),
                Floor::Blind => panic!("{}: blind to a {what} error", r.name),
                Floor::NotApplicable(_) => {}
            }
        }
    }
}

/// Gaussian light is traced as a finite sum over its spectral samples (incoherent across
/// wavelength), so `coherence_gaussian` judges the tracer against that same sum,
/// Σ w_i (a1² + a2² + 2 a1 a2 cos(2π·2nd/λ_i)), evaluated here independently from the
/// documented sampling (k_i = k0 + x_i σ_k over ±sigmas, trapezoid weights). With three
/// samples over ±3σ the continuous-spectrum form |γ(Δs)| differs from it by O(1e-2) (the
/// sampling error, a property of the case): before the reference became the sampled sum, such
/// cases failed although the tracer was right.
#[test]
fn a_gaussian_spectrum_is_judged_by_its_own_sampled_sum() {
    let mut doc = library("coherence_length");
    doc["light"]["gaussian"]["samples"] = json!(3);
    doc["light"]["gaussian"]["sigmas"] = json!(3.0);
    doc["probe"]["sweep"]["count"] = json!(7);
    doc["probe"]["sweep"]["to"] = json!(20000);
    let r = run::run_with(&parse(&doc), false).expect("runs");
    let m = &r.metrics[0];
    let (n, lambda0, fwhm) = (1.5f64, 550e-9f64, 10e-9f64);
    let tau = std::f64::consts::TAU;
    let k0 = tau / lambda0;
    let sigma = tau * fwhm / (lambda0 * lambda0) / (2.0 * (2.0 * 2f64.ln()).sqrt());
    let samples: Vec<(f64, f64)> = [(-3.0, 0.5), (0.0, 1.0), (3.0, 0.5)]
        .iter()
        .map(|&(x, t): &(f64, f64)| (k0 + x * sigma, t * (-0.5 * x * x).exp()))
        .collect();
    let total: f64 = samples.iter().map(|s| s.1).sum();
    let (a1, a2) = (
        (1.0 - n) / (1.0 + n),
        2.0 / (1.0 + n) * (n - 1.0) / (n + 1.0) * 2.0 * n / (n + 1.0),
    );
    let mut sampling_error = 0.0f64;
    for (k, &t_nm) in m.coordinates.iter().enumerate() {
        let ds = 2.0 * n * t_nm * 1e-9;
        let sum: f64 = samples
            .iter()
            .map(|&(kk, w)| w / total * (a1 * a1 + a2 * a2 + 2.0 * a1 * a2 * (kk * ds).cos()))
            .sum();
        let peak = (a1.abs() + a2.abs()).powi(2);
        assert!(
            (m.analytic[k] - sum).abs() <= 1e-12 * peak,
            "thickness {t_nm} nm: reference {:e}, the sampled sum {sum:e}",
            m.analytic[k]
        );
        let gamma = fringe::harness::analytic::coherence::gaussian_visibility(ds, lambda0, fwhm);
        let continuous = a1 * a1 + a2 * a2 + 2.0 * a1 * a2 * gamma * (k0 * ds).cos();
        sampling_error = sampling_error.max((continuous - sum).abs() / peak);
    }
    assert!(
        sampling_error > 1e-3,
        "the case must be undersampled for this test to mean anything: {sampling_error:e}"
    );
    assert_passes("coherence_length, 3 samples", &r);
}

/// An ambient denser than the plate, light beyond the top face's critical angle (the fuzzer's
/// `tests/fuzz_found/fuzz_two_beam_plate_s1_11.json`: n = 2 over n = 1.5, 50°–67°, a 1 µm
/// plate). It was a NaN row, then a refusal; since issue #12's eighth-session work the tracer
/// reflects the top beam with the plate's frustrated r_layer (`truth_tunnelling.rs`) and lands the
/// beam through the plate at tan θt ≈ 9e4 and 1.9e6 inside, and the closed form solves for tan θt
/// in double-double (`truth_refusals.rs`): the scene is judged and passes. The expected values are
/// 50-digit evaluations (tools/steep_plate_mpmath.py's formulas: `intensity` of
/// tools/beyond_critical_plate_mpmath.py with `r_top` from tools/tunnelling_mpmath.py's `r_layer`).
#[test]
fn a_plate_beyond_its_critical_angle_is_judged_against_the_frustrated_two_beam_sum() {
    let path = PathBuf::from(env!("CARGO_MANIFEST_DIR"))
        .join("tests/fuzz_found/fuzz_two_beam_plate_s1_11.json");
    let doc: Value = serde_json::from_str(&std::fs::read_to_string(path).unwrap()).unwrap();
    let r = run::run_with(&parse(&doc), false).expect("judged, not refused");
    assert_passes("fuzz_two_beam_plate_s1_11", &r);
    let exact = [0.9998591682563975, 1.000005831541269];
    let m = &r.metrics[0];
    for (k, want) in exact.iter().enumerate() {
        let traced = m.traced[&Fidelity::Vector][k];
        assert!(
            (traced - want).abs() <= 1e-12 && (m.analytic[k] - want).abs() <= 1e-14,
            "point {k}: traced {traced:e}, closed form {:e}, 50 digits {want:e}",
            m.analytic[k]
        );
    }
}

/// The numbers of a case file are the numbers traced and judged: a coordinate is read as the
/// f64 nearest its decimal text (serde_json's `float_roundtrip`; its default fast path can be
/// one ulp off). Young's slits 183 m from the origin (`tests/fuzz_found/fuzz_young_exact_s1_5`,
/// n = 2, 200 nm): one ulp of a coordinate there is 2.8e-14 m, 0.3 mrad of phase, 3e-8 of
/// the intensity. The closed form at the first probe point against a 50-digit evaluation
/// (mpmath: perpendicular distances to the exactly normalized slit axis, δ = 2π n (r1 − r2)/λ,
/// I = 2 + (1 + cos α) cos δ for unpolarized light) of the file's decimal numbers.
///
/// The tracer on the same scene: a line source's rays start at an f64 point near the line (off
/// it by ~ulp(183 m)), a first-order path error of ~1e-14 m (1.4e-8 of the intensity here);
/// the first segment is now measured from the line itself (`path::solve`).
#[test]
fn young_far_from_the_origin_is_read_and_traced_exactly() {
    let path = PathBuf::from(env!("CARGO_MANIFEST_DIR"))
        .join("tests/fuzz_found/fuzz_young_exact_s1_5.json");
    let doc: Value = serde_json::from_str(&std::fs::read_to_string(path).unwrap()).unwrap();
    let x = doc["scene"]["sources"][0]["emitter"]["line"]["point_m"][2]
        .as_f64()
        .unwrap();
    assert_eq!(x, 183.3124144416023, "serde_json read {x:e}");
    let r = run::run_with(&parse(&doc), false).expect("runs");
    let m = &r.metrics[0];
    let exact = 3.996_003_607_272_290_6; // mpmath, 50 digits: 3.9960036072722906309
    assert!(
        (m.analytic[0] - exact).abs() <= 1e-13,
        "closed form {:.17e}, 50 digits {exact:.17e}",
        m.analytic[0]
    );
    assert_passes("fuzz_young_exact_s1_5", &r);
}

/// Mutually incoherent point sources 500 m from the origin (`tests/fuzz_found/
/// fuzz_incoherent_sum_s1_92.json`, spreading on): the traced intensity is Σ I_k/r_k², which
/// the closed form evaluates directly. The tracer's spreading comes from the Jacobian of the
/// landing residual by finite differences; the residual was formed from absolute coordinates
/// (o + t d − p), so at 500 m it carried ~1e-13 m of rounding against a launch step of ~1e-6 r,
/// and the spreading was 1.8e-5 off.
#[test]
fn spreading_far_from_the_origin_is_exact() {
    let path = PathBuf::from(env!("CARGO_MANIFEST_DIR"))
        .join("tests/fuzz_found/fuzz_incoherent_sum_s1_92.json");
    let doc: Value = serde_json::from_str(&std::fs::read_to_string(path).unwrap()).unwrap();
    let r = run::run_with(&parse(&doc), false).expect("runs");
    assert_passes("fuzz_incoherent_sum_s1_92", &r);
}

/// A Michelson scene whose first mirror is large enough to be lit directly by the source: light
/// also reaches the probe along source → m1 → splitter (transmitted) → probe, through the
/// pinhole (`tests/fuzz_found/fuzz_michelson_s1_4.json`; the tracer finds it, traced 0.686
/// against the two-arm closed form's 0.123). The two-arm closed form does not describe that
/// scene, so the case is refused naming the unmodelled path, never compared.
#[test]
fn a_michelson_scene_with_a_path_outside_the_two_arms_is_refused() {
    let path =
        PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("tests/fuzz_found/fuzz_michelson_s1_4.json");
    let doc: Value = serde_json::from_str(&std::fs::read_to_string(path).unwrap()).unwrap();
    let err = run::run_with(&parse(&doc), false).expect_err("refused");
    assert!(
        err.json_path == "$.references[0].model"
            && err.message.contains("does not model")
            && err
                .message
                .contains("reflected by \"m1\", through \"splitter\""),
        "{}: {}",
        err.json_path,
        err.message
    );
}

/// A transmitted far-field sweep across the critical angle (glass n = 1.5 into air, s light,
/// 0°–80° in 5° steps; θc = 41.81°) is traced point by point: below θc the power transmittance
/// is 1 − |r_s|² of the Fresnel coefficient evaluated here, beyond it no transmitted wave
/// propagates and T = 0 exactly, traced and closed form alike (issue #12 item 5; the sweep used
/// to be refused whole with "no transmitted wave").
#[test]
fn a_transmitted_sweep_across_the_critical_angle_is_zero_beyond_it() {
    let doc = json!({
        "name": "tir_sweep",
        "description": "transmission out of glass across the critical angle",
        "formula": "T = 1 - |r_s|^2 below the critical angle, 0 beyond",
        "light": { "monochrome": { "wavelength_nm": 550 } },
        "scene": {
            "ambient": "glass",
            "media": { "air": { "constant": { "n": 1.0 } }, "glass": { "constant": { "n": 1.5 } } },
            "surfaces": [ { "interface": { "name": "face", "point_m": [0, 0, 0], "normal": [0, 0, 1],
                                           "front": "glass", "back": "air" } } ],
            "sources": [ { "name": "beam",
                "emitter": { "plane_wave": { "direction": [0, 0, -1], "reference_point_m": [0, 0, 0.001] } },
                "polarization": { "linear": { "reference": [0, 1, 0], "angle_deg": 0 } } } ]
        },
        "probe": { "sweep": {
            "parameter": { "incidence_angle_deg": { "surface_normal": [0, 0, 1], "in_plane_axis": [1, 0, 0] } },
            "from": 0, "to": 80, "count": 17,
            "observe": { "far_field": { "side": "transmitted", "surface_normal": [0, 0, 1],
                                        "exit_medium": "air" } } } },
        "references": [ { "model": { "plane_wave_beams": { "beams": [
            { "source": "beam", "events": [ { "surface": "face", "reflect": false } ] } ] } },
            "tolerances": { "vector": 1e-12 } } ],
        "fidelities": ["vector"]
    });
    let r = run::run_with(&parse(&doc), false).expect("the sweep runs");
    let m = &r.metrics[0];
    assert_eq!(m.analytic.len(), 17);
    let (n1, n2) = (1.5f64, 1.0f64);
    for (k, (&exact, &traced)) in m
        .analytic
        .iter()
        .zip(&m.traced[&Fidelity::Vector])
        .enumerate()
    {
        let theta = (5.0 * k as f64).to_radians();
        let sin2 = n1 / n2 * theta.sin();
        let expected = if sin2 >= 1.0 {
            0.0
        } else {
            let (c1, c2) = (theta.cos(), (1.0 - sin2 * sin2).sqrt());
            let rs = (n1 * c1 - n2 * c2) / (n1 * c1 + n2 * c2);
            1.0 - rs * rs
        };
        for (what, v) in [("closed form", exact), ("traced", traced)] {
            assert!(
                (v - expected).abs() <= 1e-12,
                "{what} at {}°: {v:e}, expected {expected:e}",
                5 * k
            );
        }
    }
    assert_passes("tir_sweep", &r);
    // A sweep wholly beyond θc is dark by physics, not a misplaced probe: T = 0 everywhere.
    let mut beyond = doc.clone();
    beyond["probe"]["sweep"]["from"] = json!(45);
    let r = run::run_with(&parse(&beyond), false).expect("a dark sweep beyond θc runs");
    assert!(r.metrics[0].analytic.iter().all(|&v| v == 0.0));
    assert!(
        r.metrics[0].traced[&Fidelity::Vector]
            .iter()
            .all(|&v| v == 0.0)
    );
    assert_passes("tir_sweep beyond θc", &r);
}
