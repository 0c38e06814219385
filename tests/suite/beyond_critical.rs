//! Layers lit beyond their top face's critical angle (frustrated total reflection), the Airy
//! closed form near a critical angle, and a wedge whose second beam is totally reflected
//! (issue #12, items 5 and 7; docs/PHYSICS.md §5 "Beyond the critical angle of a layer").
//!
//! Expected values come from 50-digit evaluations (`tools/beyond_critical_mpmath.py` →
//! `tests/data/beyond_critical_mpmath.csv`, `beyond_critical_two_beam_mpmath.csv`) or from
//! closed forms written out here, never from the tracer. Before the fixes: every film beyond its
//! critical angle was refused (`airy` 71/300, `two_beam_plate` 97/300 at `fringe fuzz --seed 1`),
//! the Airy terms took cos θ2 = 0 there, the airy reference's cos θ1 was an f64 |d·N| (R off by up
//! to 5e-5 within 1e-9 of the critical angle), and the wedge generator refused a second beam
//! totally reflected at the top face.

use fringe::accumulate::fidelity::Fidelity;
use fringe::harness::analytic::plate::{FTIR_NEGLIGIBLE, Film, Incidence, Pol};
use fringe::harness::case::{load, run};
use glam::DVec3;
use serde_json::{Value, json};
use std::path::{Path, PathBuf};

fn root() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR"))
}

/// One row of `beyond_critical_mpmath.csv`.
struct Row {
    kind: String,
    film: Film,
    cos1: f64,
    dir: DVec3,
    lambda_m: f64,
    pol: Pol,
    reflectance: f64,
    transmittance: f64,
    one_minus_r: f64,
}

fn rows() -> Vec<Row> {
    let text = std::fs::read_to_string(root().join("tests/data/beyond_critical_mpmath.csv"))
        .expect("tests/data/beyond_critical_mpmath.csv");
    text.lines()
        .skip(1)
        .map(|l| {
            let f: Vec<&str> = l.split(',').collect();
            let x = |k: usize| f[k].parse::<f64>().unwrap();
            Row {
                kind: f[0].to_string(),
                film: Film {
                    n1: x(1),
                    n2: x(2),
                    n3: x(3),
                    thickness_m: x(4),
                },
                cos1: x(5),
                dir: DVec3::new(x(6), 0.0, x(7)),
                lambda_m: x(8),
                pol: if f[9] == "0" { Pol::S } else { Pol::P },
                reflectance: x(10),
                transmittance: x(11),
                one_minus_r: x(12),
            }
        })
        .collect()
}

/// The Airy sum with the imaginary cos θ2 of frustrated total reflection, against 50 digits:
/// R, T and 1 − R (the part the ray model misses) to 1e-15 absolute, over films 1 nm – 10 µm
/// from 1e-9 beyond the critical angle to far beyond it.
#[test]
fn the_airy_sum_beyond_the_critical_angle_matches_50_digits() {
    let mut worst: f64 = 0.0;
    let mut n = 0;
    for r in rows().iter().filter(|r| r.kind == "ftir") {
        let a = r.film.terms(r.cos1, r.lambda_m, r.pol);
        assert!(a.evanescent, "row beyond the critical angle");
        let rr = r.film.reflectance(r.cos1, r.lambda_m, r.pol);
        let tt = r.film.transmittance(r.cos1, r.lambda_m, r.pol);
        let e = (rr - r.reflectance)
            .abs()
            .max((tt - r.transmittance).abs())
            .max(((1.0 - rr) - r.one_minus_r).abs());
        assert!(
            e <= 1e-15,
            "{:?} cos θ1 = {} λ = {} {:?}: R {rr} vs {}, T {tt} vs {}",
            r.film,
            r.cos1,
            r.lambda_m,
            r.pol,
            r.reflectance,
            r.transmittance
        );
        worst = worst.max(e);
        n += 1;
    }
    assert!(n >= 40, "rows: {n}");
    println!("Airy beyond critical vs 50 digits: {worst:.3e} over {n} rows");
}

/// The evanescent coupling the gate neglects ([`Film::frustration`]) is the exact 1 − R and T:
/// at least as large as the 50-digit 1 − R and T of each polarization (it is their maximum
/// over s and p), and zero where the exit medium is beyond its own critical angle.
#[test]
fn the_frustration_bounds_what_the_ray_model_misses() {
    for r in rows().iter().filter(|r| r.kind == "ftir") {
        let fr = r.film.frustration(r.cos1, r.lambda_m).expect("evanescent");
        let tol = 1e-15;
        assert!(fr.reflectance + tol >= r.one_minus_r.abs(), "{:?}", r.film);
        assert!(fr.transmittance + tol >= r.transmittance, "{:?}", r.film);
        if r.transmittance == 0.0 {
            assert!(fr.reflectance <= tol && fr.transmittance == 0.0);
        }
        // κ = (2π/λ) sqrt(n1² sin²θ1 − n2²), written out.
        let s2 = 1.0 - r.cos1 * r.cos1;
        let kappa = std::f64::consts::TAU / r.lambda_m
            * (r.film.n1 * r.film.n1 * s2 - r.film.n2 * r.film.n2).sqrt();
        assert!((fr.kappa_per_m - kappa).abs() <= 1e-6 * kappa, "κ");
    }
}

/// Within 1e-12 … 1e-6 of the critical angle (below it), with cos²θ1 formed from the plane
/// wave's f64 direction as the loader normalizes it: R and T to 1e-14 of the 50-digit values.
/// With cos θ1 = |d·N| rounded to f64 first (the reference before the fix) R is off by up to
/// 2e-11 on these rows (more nearer the critical angle: 5e-5 in fuzz scenes), and the factored
/// Airy form (r12 + r23 e)/(1 + r12 r23 e) lost another 1.5e-12 to cancellation.
#[test]
fn the_airy_reference_holds_cos_squared_theta_1_near_the_critical_angle() {
    let mut worst: f64 = 0.0;
    let mut f64_worst: f64 = 0.0;
    for r in rows().iter().filter(|r| r.kind == "near") {
        let d = r.dir.normalize();
        let inc = Incidence::between(d, DVec3::Z);
        let rr = r.film.reflectance(inc, r.lambda_m, r.pol);
        let tt = r.film.transmittance(inc, r.lambda_m, r.pol);
        let e = (rr - r.reflectance).abs().max((tt - r.transmittance).abs());
        assert!(
            e <= 1e-14,
            "{:?} {:?}: R {rr} vs {}",
            r.film,
            r.dir,
            r.reflectance
        );
        worst = worst.max(e);
        let rounded = r.film.reflectance(d.dot(DVec3::Z).abs(), r.lambda_m, r.pol);
        f64_worst = f64_worst.max((rounded - r.reflectance).abs());
    }
    println!("near critical: {worst:.3e} (cos θ1 rounded first: {f64_worst:.3e})");
    assert!(f64_worst > 1e-12, "the rows probe the cancellation");
}

fn run_json(name: &str, doc: &Value) -> Result<run::CaseResult, load::CaseError> {
    let path = Path::new("tests/beyond_critical").join(format!("{name}.json"));
    let case = load::parse(&path, &doc.to_string()).expect("a valid case");
    run::run_with(&case, false)
}

/// A film of index n2 between two media n1 = n3 = 1.5 lit at θ1 from the (0, 0, −1) side
/// (direction (sin θ1, 0, −cos θ1)), s polarized, observed on `side`.
fn ftir_film(thickness_um: f64, theta_deg: f64, side: &str) -> Value {
    let (s, c) = theta_deg.to_radians().sin_cos();
    json!({
        "name": "ftir_film",
        "description": "a film beyond its top face's critical angle",
        "formula": "airy",
        "fidelities": ["vector"],
        "light": {"monochrome": {"wavelength_nm": 550.0}},
        "scene": {
            "ambient": "ambient",
            "media": {"ambient": {"constant": {"n": 1.5}}, "gap": {"constant": {"n": 1.0}},
                      "substrate": {"constant": {"n": 1.5}}},
            "sources": [{"name": "beam",
                "emitter": {"plane_wave": {"direction": [s, 0.0, -c], "reference_point_m": [0.0, 0.0, 1e-3]}},
                "polarization": {"linear": {"reference": [0.0, 1.0, 0.0], "angle_deg": 0.0}},
                "intensity": 1.0}],
            "surfaces": [{"plate": {"name": "film", "top_point_m": [0.0, 0.0, 0.0], "normal": [0.0, 0.0, 1.0],
                "thickness_um": thickness_um, "medium": "gap", "above": "ambient", "below": "substrate"}}]
        },
        "probe": {"single": {"observe": if side == "reflected" {
            json!({"far_field": {"side": side, "surface_normal": [0.0, 0.0, 1.0]}})
        } else {
            json!({"far_field": {"side": side, "surface_normal": [0.0, 0.0, 1.0], "exit_medium": "substrate"}})
        }}},
        "references": [{"model": {"airy": {"film": "film"}}, "tolerances": {"vector": 1e-12}}],
        "trace": {"airy_tail_epsilon": 1e-13}
    })
}

/// A 5 µm air gap between two glasses (n = 1.5) at 60°, beyond its critical angle 41.8°:
/// κ = (2π/λ) sqrt(1.5² sin²60° − 1) = 9.47e6 /m, e^{−2κd} = 6e-42. The exact R = 1 and T = 0
/// to far below 1e-13, the ray model's total reflection at the top face; both sides are traced
/// and compared (they were refused before) and the traced R is 1, the transmitted probe dark.
#[test]
fn a_thick_gap_beyond_the_critical_angle_is_compared_on_both_sides() {
    for side in ["reflected", "transmitted"] {
        let r = run_json("gap", &ftir_film(5.0, 60.0, side)).unwrap_or_else(|e| {
            panic!("{side}: refused: {}", e.message);
        });
        let m = &r.metrics[0];
        let expected = if side == "reflected" { 1.0 } else { 0.0 };
        assert!(
            (m.analytic[0] - expected).abs() <= 1e-15,
            "{side}: {}",
            m.analytic[0]
        );
        let traced = m.traced[&Fidelity::Vector][0];
        assert!(
            (traced - expected).abs() <= 1e-12,
            "{side}: traced {traced}"
        );
    }
}

/// A 50 nm gap at 60° couples through (T ≈ 0.3). It was refused on the transmitted side
/// ("frustrated total reflection moves T by …"); the tracer now starts the tunnelled wave on the
/// far face (`EventKind::Tunnel`, docs/PHYSICS.md §5), so both sides are compared: each traced
/// value is within its gate of the closed form, the coupling is far above
/// [`FTIR_NEGLIGIBLE`], and the traced R and T carry all the power (R + T = 1; the 50-digit
/// values of such films are in `truth_tunnelling`).
#[test]
fn a_thin_gap_beyond_the_critical_angle_is_traced_on_both_sides() {
    let mut sum = 0.0;
    for side in ["transmitted", "reflected"] {
        let r = run_json("thin_gap", &ftir_film(0.05, 60.0, side))
            .unwrap_or_else(|e| panic!("{side}: refused: {}", e.message));
        let m = &r.metrics[0];
        let traced = m.traced[&Fidelity::Vector][0];
        let tol = m.tolerances[&Fidelity::Vector];
        println!("{side}: traced {traced}, closed form {}", m.analytic[0]);
        assert!(
            (traced - m.analytic[0]).abs() <= tol,
            "{side}: {traced} vs {}",
            m.analytic[0]
        );
        if side == "transmitted" {
            assert!(traced > 1e3 * FTIR_NEGLIGIBLE, "T {traced}");
        }
        sum += traced;
    }
    assert!((sum - 1.0).abs() <= 1e-14, "R + T = {sum}");
}

/// The two-beam plate under a point source with the top beam beyond the critical angle: a dense
/// ambient (1.5) over a 0.2 mm air gap, source 1 cm and probe 2 cm above it, 5 cm apart
/// (θ1 = 59°, critical 41.8°; e^{−2κd} ≈ e^{−4000}). The top beam is totally reflected
/// (|r12| = 1, complex), the beam through the gap enters below the critical angle and runs at
/// tan θt ≈ 58 inside. The traced intensity matches the 50-digit two-beam sum with complex r12
/// (`beyond_critical_two_beam_mpmath.csv`) to 1e-12; the scene was refused before.
#[test]
fn a_point_source_over_a_gap_beyond_the_critical_angle_gives_two_beams() {
    let text =
        std::fs::read_to_string(root().join("tests/data/beyond_critical_two_beam_mpmath.csv"))
            .unwrap();
    let truth: f64 = text
        .lines()
        .find(|l| l.starts_with("air_gap,0,"))
        .and_then(|l| l.split(',').nth(2))
        .and_then(|v| v.parse().ok())
        .unwrap();
    let (hs, ho, x): (f64, f64, f64) = (0.01, 0.02, 0.05);
    // Shield just above the source against the direct ray (as the fuzz generator builds it).
    let eps = 1e-8;
    let w = (x * eps / (ho - hs) * (x * 2.0 * hs / (hs + ho))).sqrt();
    let doc = json!({
        "name": "gap_two_beam",
        "description": "two beams, top one totally reflected",
        "formula": "two_beam_plate",
        "fidelities": ["vector"],
        "light": {"monochrome": {"wavelength_nm": 500.0}},
        "scene": {
            "ambient": "ambient",
            "media": {"ambient": {"constant": {"n": 1.5}}, "gap": {"constant": {"n": 1.0}}},
            "sources": [{"name": "lamp", "emitter": {"point": {"position_m": [0.0, 0.0, hs]}},
                "polarization": {"unpolarized": {"model": "paper_two_channel", "reference": [0, 1, 0]}},
                "intensity": 1.0}],
            "surfaces": [
                {"plate": {"name": "plate", "top_point_m": [0, 0, 0], "normal": [0, 0, 1],
                    "thickness_um": 200.0, "medium": "gap", "above": "ambient", "below": "ambient"}},
                {"shield": {"name": "shield", "point_m": [0.0, 0.0, hs + eps], "normal": [0, 0, 1],
                    "rect": {"size_m": [2.0 * w, 2.0 * w], "u_axis": [1, 0, 0]}}}
            ]
        },
        "probe": {"line": {"from_m": [x, 0.0, ho], "to_m": [x, 0.0, ho], "count": 1}},
        "references": [{"model": {"two_beam_plate": {"plate": "plate"}}, "tolerances": {"vector": 1e-12}}],
        "trace": {}
    });
    let r = run_json("gap_two_beam", &doc).unwrap_or_else(|e| panic!("{}", e.message));
    let m = &r.metrics[0];
    let traced = m.traced[&Fidelity::Vector][0];
    println!(
        "two-beam gap: closed form {} traced {traced} 50 digits {truth}",
        m.analytic[0]
    );
    assert!(
        (m.analytic[0] - truth).abs() <= 1e-14 * truth,
        "closed form"
    );
    assert!((traced - truth).abs() <= 1e-12 * truth, "traced");
    // Two beams, not the top one alone (|r12|² = 1 for unpolarized light).
    assert!((truth - 1.0).abs() > 1e-3);
}

/// A wedge (n = 3.5 in air, α = 10°) whose bottom reflection meets the top face at 2α = 20°,
/// beyond its critical angle asin(1/3.5) = 16.6°: no second beam leaves toward the probe, which
/// sees the top reflection alone, I = ((n − 1)/(n + 1))² of the source at every point (one
/// internal reflection budget: the totally reflected beam would need a second).
#[test]
fn a_wedge_whose_second_beam_is_totally_reflected_shows_the_top_beam_alone() {
    let doc = json!({
        "name": "wedge_tir",
        "description": "second beam totally reflected",
        "formula": "wedge",
        "fidelities": ["vector"],
        "light": {"monochrome": {"wavelength_nm": 600.0}},
        "scene": {
            "ambient": "ambient",
            "media": {"ambient": {"constant": {"n": 1.0}}, "glass": {"constant": {"n": 3.5}}},
            "sources": [{"name": "beam",
                "emitter": {"plane_wave": {"direction": [0, 0, -1], "reference_point_m": [0, 0, 1e-3]}},
                "polarization": {"linear": {"reference": [0, 1, 0], "angle_deg": 0.0}},
                "intensity": 2.0}],
            "surfaces": [{"wedge": {"name": "wedge", "top_point_m": [0, 0, 0], "normal": [0, 0, 1],
                "thickness_um": 1000.0, "angle_deg": 10.0, "hinge_axis": [0, 1, 0],
                "medium": "glass", "above": "ambient", "below": "ambient"}}]
        },
        "probe": {"line": {"from_m": [-1e-3, 0, 1e-4], "to_m": [1e-3, 0, 1e-4], "count": 5,
                           "looks_toward": [0, 0, -1]}},
        "references": [{"model": {"wedge": {"wedge": "wedge"}}, "tolerances": {"vector": 1e-12}}],
        "trace": {}
    });
    let r = run_json("wedge_tir", &doc).unwrap_or_else(|e| panic!("{}", e.message));
    let m = &r.metrics[0];
    let expected = 2.0 * ((3.5f64 - 1.0) / (3.5 + 1.0)).powi(2);
    for (a, t) in m.analytic.iter().zip(&m.traced[&Fidelity::Vector]) {
        assert!((a - expected).abs() <= 1e-15 * expected, "closed form {a}");
        assert!((t - expected).abs() <= 1e-12 * expected, "traced {t}");
    }
}
