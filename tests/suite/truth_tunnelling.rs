//! Layers lit beyond their top face's critical angle, traced (issue #12; docs/PHYSICS.md §5,
//! "Beyond the critical angle of a layer"): at a face whose far side is a layer (a plate's or
//! film's other face a distance d behind it) the totally reflected child takes the layer's
//! frustrated reflection r_layer (the Airy sum with imaginary cos θ2,
//! `fresnel::frustrated_layer`) instead of the face's r12.
//!
//! Expected values come from 50-digit evaluations of the case files' own binary64 numbers
//! (`tools/tunnelling_mpmath.py` → `tests/data/tunnelling_mpmath.csv`, and the "ftir" rows of
//! `tools/beyond_critical_mpmath.py` → `tests/data/beyond_critical_mpmath.csv`) or from
//! identities of the Airy sum (R + T = 1, d → 0, d → ∞), never from the tracer. Before this,
//! every such scene with a coupling above 1e-13 of the source was refused
//! (`fringe fuzz --count 300 --seed 1`: 46 `two_beam_plate`, 22 `airy`).

use fringe::accumulate::fidelity::Fidelity;
use fringe::harness::analytic::plate::{Film, Incidence, Pol};
use fringe::harness::case::{load, run};
use fringe::optics::double_double::{DoubleDouble, two_prod};
use fringe::optics::fresnel::{self, frustrated_layer};
use fringe::optics::interaction::{CoefficientModel, InterfaceHit, Layer, SurfaceOptics, interact};
use fringe::optics::material::CoherenceRules;
use fringe::optics::ray::Ray;
use glam::DVec3;
use num_complex::Complex64;
use serde_json::json;
use std::path::{Path, PathBuf};

fn root() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR"))
}

/// (n1 cos θ1)², (n2 cos θ2)², (n3 cos θ3)² in double-double from cos θ1, as the tracer forms
/// them (`interaction::normal_wavevector_squares`).
fn q2s(n: (f64, f64, f64), cos1: f64) -> (DoubleDouble, DoubleDouble, DoubleDouble) {
    let q1 = two_prod(cos1, cos1) * two_prod(n.0, n.0);
    let sq = |m: f64| q1 + two_prod(m, m) - two_prod(n.0, n.0);
    (q1, sq(n.1), sq(n.2))
}

/// r_layer (s, p) = r12 + (r − r12) and t_layer (s, p) of [`frustrated_layer`].
fn layer(n: (f64, f64, f64), d: f64, lambda: f64, cos1: f64) -> ([Complex64; 2], [Complex64; 2]) {
    let q = q2s(n, cos1);
    let f = frustrated_layer(n, q, d, lambda);
    let r12 = fresnel::fresnel_with_cos2_t(n.0, n.1, cos1, q.1.to_f64() / (n.1 * n.1));
    assert!(r12.total_internal_reflection);
    ([r12.r_s + f.dr[0], r12.r_p + f.dr[1]], f.t)
}

/// T = n3 cos θ3/(n1 cos θ1)·|t|² (0 when cos θ3 is imaginary).
fn power_t(n: (f64, f64, f64), cos1: f64, t: Complex64) -> f64 {
    let q = q2s(n, cos1);
    if q.2.hi <= 0.0 {
        return 0.0;
    }
    q.2.sqrt().to_f64() / (n.0 * cos1) * t.norm_sqr()
}

/// The "ftir" rows of `beyond_critical_mpmath.csv`: films of 1 nm – 10 µm from 1e-9 of the
/// critical angle to far beyond it, substrates denser and rarer than n1 sin θ1, s and p; R, T and
/// |r − r12| of the 50-digit Airy sum. The layer coefficients the tracer applies match them.
#[test]
fn the_frustrated_coefficients_are_the_50_digit_airy_sum() {
    let text = std::fs::read_to_string(root().join("tests/data/beyond_critical_mpmath.csv"))
        .expect("tests/data/beyond_critical_mpmath.csv");
    let mut rows = 0;
    let (mut worst_r, mut worst_t, mut worst_dr) = (0.0f64, 0.0f64, 0.0f64);
    for l in text.lines().skip(1).filter(|l| l.starts_with("ftir,")) {
        let f: Vec<f64> = l.split(',').skip(1).map(|x| x.parse().unwrap()).collect();
        let n = (f[0], f[1], f[2]);
        let (d, cos1, lambda, k) = (f[3], f[4], f[7], f[8] as usize);
        let (r, t) = layer(n, d, lambda, cos1);
        let (big_r, big_t, dr) = (f[9], f[10], f[12]);
        let coupling = frustrated_layer(n, q2s(n, cos1), d, lambda).dr[k];
        worst_r = worst_r.max((r[k].norm_sqr() - big_r).abs());
        worst_t = worst_t.max((power_t(n, cos1, t[k]) - big_t).abs());
        if dr > 1e-40 {
            worst_dr = worst_dr.max((coupling.norm() - dr).abs() / dr);
        } else {
            // The 50-digit |r − r12| is a difference of two O(1) numbers: below ~1e-48 it is 0.
            assert!(coupling.norm() < 1e-40, "{l}: {}", coupling.norm());
        }
        rows += 1;
    }
    println!("ftir rows {rows}: R {worst_r:.3e}, T {worst_t:.3e}, |r − r12| rel {worst_dr:.3e}");
    assert!(rows >= 40, "rows {rows}");
    assert!(worst_r <= 1e-14, "R {worst_r:e}");
    assert!(worst_t <= 1e-14, "T {worst_t:e}");
    // r − r12 is formed directly (never as a difference), so it keeps its relative digits
    // however small the coupling.
    assert!(worst_dr <= 1e-12, "|r − r12| {worst_dr:e}");
}

/// A lossless layer conserves power: R + T = 1 wherever the exit medium takes a propagating
/// wave, and R = 1 (with T = 0) where it does not; over indices 1.0–4.0, thicknesses
/// 0.1 nm – 10 µm, angles from 1e-10 of the critical angle to grazing, s and p.
#[test]
fn a_lossless_layer_reflects_and_transmits_all_the_power() {
    let mut worst = 0.0f64;
    let mut seed = 0x2545_f491_4f6c_dd1du64;
    let mut uniform = || {
        seed ^= seed << 13;
        seed ^= seed >> 7;
        seed ^= seed << 17;
        (seed >> 11) as f64 / (1u64 << 53) as f64
    };
    for _ in 0..2000 {
        let n1 = 1.2 + 2.8 * uniform();
        let n2 = 1.0 + (n1 - 1.0) * 0.9 * uniform();
        let n3 = 1.0 + 3.0 * uniform();
        let d = 10f64.powf(-10.0 + 5.0 * uniform());
        let sin_c = n2 / n1;
        let sin1 = sin_c + (1.0 - sin_c) * 10f64.powf(-10.0 * uniform());
        let cos1 = (1.0 - sin1 * sin1).sqrt();
        if cos1 <= 1e-6 || (n1 * n1 * (1.0 - cos1 * cos1)) <= n2 * n2 {
            continue;
        }
        let n = (n1, n2, n3);
        let (r, t) = layer(n, d, 550e-9, cos1);
        for k in 0..2 {
            let sum = r[k].norm_sqr() + power_t(n, cos1, t[k]);
            worst = worst.max((sum - 1.0).abs());
        }
    }
    println!("|R + T − 1| ≤ {worst:.3e}");
    assert!(worst <= 1e-14, "{worst:e}");
}

/// A layer of zero thickness is no layer: r_layer and t_layer are the bare n1 → n3 interface's
/// (P1)–(P4) (n3 taking a propagating wave), and as d grows the coupling dies as e^{−2κd}: the
/// ratio of |r − r12| at d and d + Δ is e^{−2κΔ} (κ = (2π/λ) sqrt(n1² sin²θ1 − n2²)).
#[test]
fn a_vanishing_layer_is_the_bare_interface_and_a_thick_one_decays_as_exp_minus_2_kappa_d() {
    let lambda = 633e-9;
    for (n, cos1) in [
        ((1.5, 1.0, 1.5), 0.6),
        ((2.0, 1.2, 2.4), 0.3),
        ((1.7, 1.33, 1.6), 0.5),
    ] {
        let (r, t) = layer(n, 0.0, lambda, cos1);
        let bare = fresnel::fresnel(n.0, n.2, cos1);
        assert!(!bare.total_internal_reflection);
        for (got, want) in [
            (r[0], bare.r_s),
            (r[1], bare.r_p),
            (t[0], bare.t_s),
            (t[1], bare.t_p),
        ] {
            assert!((got - want).norm() <= 4e-16, "{n:?}: {got} vs {want}");
        }
        let kappa =
            std::f64::consts::TAU / lambda * (n.0 * n.0 * (1.0 - cos1 * cos1) - n.1 * n.1).sqrt();
        let q = q2s(n, cos1);
        for d in [2e-6, 4e-6] {
            let a = frustrated_layer(n, q, d, lambda);
            let b = frustrated_layer(n, q, d + 1e-7, lambda);
            for k in 0..2 {
                let ratio = b.dr[k].norm() / a.dr[k].norm();
                let want = (-2.0 * kappa * 1e-7).exp();
                assert!(
                    (ratio / want - 1.0).abs() <= 1e-6,
                    "{n:?} d {d}: {ratio} vs {want}"
                );
            }
        }
    }
}

/// Where the coupling is below the f64 resolution of r12 (a 1 mm layer, e^{−2κd} underflows)
/// the traced reflection is today's total reflection bit for bit; through a 100 nm layer it is
/// r_layer, and a face with no layer behind it (a half-space) keeps r12 whatever is beyond.
#[test]
fn the_reflected_child_takes_the_layer_coefficient_and_reduces_to_tir() {
    let (n1, n2, n3, lambda) = (1.5, 1.0, 1.5, 550e-9);
    let theta = 60f64.to_radians();
    let d_i = DVec3::new(theta.sin(), 0.0, -theta.cos());
    let ray = Ray::linear(
        DVec3::new(-theta.tan(), 0.0, 1.0),
        d_i,
        DVec3::new(0.6, 0.8, 0.0),
        1.0,
        lambda,
        n1,
    );
    let hit = |d: Option<f64>| InterfaceHit {
        surface: 0,
        point: DVec3::ZERO,
        normal: DVec3::Z,
        optics: SurfaceOptics::Dielectric {
            n_front: n1,
            n_back: n2,
        },
        coherence: CoherenceRules::default(),
        layers: [
            d.map(|thickness_m| Layer {
                partner: 1,
                thickness_m,
                n_beyond: n3,
                lambda_m: lambda,
            }),
            None,
        ],
    };
    let bare = interact(&ray, &hit(None), CoefficientModel::Vector).coefficients;
    assert!(bare.total_internal_reflection);
    let thick = interact(&ray, &hit(Some(1e-3)), CoefficientModel::Vector).coefficients;
    assert_eq!(
        (thick.r_s, thick.r_p),
        (bare.r_s, bare.r_p),
        "1 mm: TIR bit for bit"
    );
    let thin = interact(&ray, &hit(Some(1e-7)), CoefficientModel::Vector);
    let film = Film {
        n1,
        n2,
        n3,
        thickness_m: 1e-7,
    };
    let inc = Incidence::between(d_i, DVec3::Z);
    for (got, pol) in [
        (thin.coefficients.r_s, Pol::S),
        (thin.coefficients.r_p, Pol::P),
    ] {
        let want = film.r(inc, lambda, pol);
        assert!((got - want).norm() <= 1e-15, "{pol:?}: {got} vs {want}");
        assert!(got.norm() < 0.99, "{pol:?}: the coupling matters here");
    }
    // The child carries it: E_r·s = r_s (E·s).
    let s = d_i.cross(DVec3::Z).normalize();
    let e_in = ray.field();
    let e_out = thin.reflected.field();
    let along = |e: [Complex64; 3]| e[0] * s.x + e[1] * s.y + e[2] * s.z;
    assert!((along(e_out) - thin.coefficients.r_s * along(e_in)).norm() <= 1e-15);
    // The paper's rung (opposite time convention) takes the conjugate coupling: same |r|.
    let paper = interact(&ray, &hit(Some(1e-7)), CoefficientModel::PaperRules).coefficients;
    assert!((paper.r_s - thin.coefficients.r_s.conj()).norm() <= 1e-15);
    assert!((paper.r_p - thin.coefficients.r_p.conj()).norm() <= 1e-15);
}

fn run_file(path: &Path) -> run::CaseResult {
    let text = std::fs::read_to_string(path).unwrap();
    let case = load::parse(path, &text).expect("a valid case");
    run::run_with(&case, false).unwrap_or_else(|e| panic!("{}: {}", path.display(), e.message))
}

/// Films beyond the critical angle of their top face, traced on the reflected side and compared
/// point by point with 50 digits (`tests/tunnelling/*.json`): a 50 nm gap (strong coupling, s),
/// a 0.3 µm layer on a denser substrate (p), a 1.5 µm gap (weak coupling, unpolarized), a
/// rotated frame with mixed polarization on a substrate, and a sweep across the critical angle.
/// Each was refused before ("the film carries an evanescent wave"); each passes its gate and is
/// within 1e-12 of the 50-digit values, as its closed form is within 1e-13.
#[test]
fn films_beyond_the_critical_angle_reflect_as_50_digits() {
    let truth = crate::support::mpmath_profiles("tunnelling_mpmath.csv");
    let mut names = Vec::new();
    for entry in std::fs::read_dir(root().join("tests/tunnelling")).unwrap() {
        let path = entry.unwrap().path();
        let name = path.file_stem().unwrap().to_str().unwrap().to_string();
        let r = run_file(&path);
        let m = &r.metrics[0];
        let want = &truth[&name];
        let traced = &m.traced[&Fidelity::Vector];
        assert_eq!(traced.len(), want.len(), "{name}");
        let scale = want.iter().fold(0.0f64, |s, x| s.max(x.abs()));
        let dev = |v: &[f64]| {
            v.iter()
                .zip(want)
                .map(|(a, b)| (a - b).abs() / scale)
                .fold(0.0, f64::max)
        };
        let (e_traced, e_closed) = (dev(traced), dev(&m.analytic));
        println!("{name}: traced {e_traced:.3e}, closed form {e_closed:.3e} off 50 digits");
        assert_exact_and_passed(&name, m, e_traced, e_closed);
        names.push(name);
    }
    assert!(names.len() >= 5, "{names:?}");
}

/// The two-beam plate with the top beam beyond the critical angle of a thin gap (a dense ambient
/// 1.5 over a 2 µm air gap, source 1 cm and probe 2 cm above it, the top beam 1 mm beyond the
/// lateral distance of the critical angle: e^{−2κd} ≈ 1e-4, the beam through the gap at
/// tan θt ≈ 250): refused before as frustrated total reflection, now traced with r_layer on the
/// top beam and compared; matches the 50-digit two-beam sum with r_layer
/// (`tools/tunnelling_mpmath.py`) to 1e-12.
#[test]
fn a_point_source_over_a_thin_gap_beyond_the_critical_angle_is_traced() {
    let truth = crate::support::mpmath_profiles("tunnelling_mpmath.csv")["two_beam_gap"][0];
    let (hs, ho, x): (f64, f64, f64) = (0.01, 0.02, 0.027_832_815_729_997_48);
    let eps = 1e-8;
    let w = (x * eps / (ho - hs) * (x * 2.0 * hs / (hs + ho))).sqrt();
    let doc = json!({
        "name": "gap_two_beam_frustrated",
        "description": "two beams, the top one frustrated by a thin gap",
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
                    "thickness_um": 2.0, "medium": "gap", "above": "ambient", "below": "ambient"}},
                {"shield": {"name": "shield", "point_m": [0.0, 0.0, hs + eps], "normal": [0, 0, 1],
                    "rect": {"size_m": [2.0 * w, 2.0 * w], "u_axis": [1, 0, 0]}}}
            ]
        },
        "probe": {"line": {"from_m": [x, 0.0, ho], "to_m": [x, 0.0, ho], "count": 1}},
        "references": [{"model": {"two_beam_plate": {"plate": "plate"}}, "tolerances": {"vector": 1e-12}}],
        "trace": {}
    });
    let path = Path::new("tests/tunnelling/gap_two_beam_frustrated.json");
    let case = load::parse(path, &doc.to_string()).expect("a valid case");
    let r = run::run_with(&case, false).unwrap_or_else(|e| panic!("{}", e.message));
    let m = &r.metrics[0];
    let traced = m.traced[&Fidelity::Vector][0];
    println!(
        "two-beam frustrated gap: closed form {} traced {traced} 50 digits {truth}",
        m.analytic[0]
    );
    assert!(
        (m.analytic[0] - truth).abs() <= 1e-14 * truth,
        "closed form"
    );
    assert!((traced - truth).abs() <= 1e-12 * truth, "traced");
    // The coupling matters here: the top beam's |r − r12| at its angle.
    let h = hs + ho;
    let film = Film {
        n1: 1.5,
        n2: 1.0,
        n3: 1.5,
        thickness_m: 2e-6,
    };
    let fr = film
        .frustration(h / x.hypot(h), 500e-9)
        .expect("beyond the critical angle");
    assert!(fr.amplitude > 1e-6, "{}", fr.amplitude);
}

/// The traced transmitted side of the films beyond the critical angle of their top face
/// (`tests/tunnelling_transmitted/*.json`, issue #12): the tunnelled wave the tracer starts on the
/// far face (`EventKind::Tunnel`, docs/PHYSICS.md §5) against the 50-digit T of each case's own
/// binary64 numbers (`tools/tunnelling_mpmath.py`): a 50 nm gap (strong coupling, s), a 0.3 µm
/// layer on a denser substrate (p), a 1.5 µm gap on n = 4 (weak coupling, T down to 7e-17,
/// unpolarized), a rotated frame with mixed polarization on a substrate, a sweep across the
/// critical angle (orders inside the film below it, the tunnelled wave beyond), and a substrate
/// that is beyond its own critical angle over most of the sweep (T = 0 exactly there: no wave
/// leaves). Each was refused before ("this frustrated total reflection moves T by …").
#[test]
fn films_beyond_the_critical_angle_transmit_the_tunnelled_wave_as_50_digits() {
    let truth = crate::support::mpmath_profiles("tunnelling_mpmath.csv");
    let mut names = Vec::new();
    let mut dark = 0;
    for entry in std::fs::read_dir(root().join("tests/tunnelling_transmitted")).unwrap() {
        let path = entry.unwrap().path();
        let name = path.file_stem().unwrap().to_str().unwrap().to_string();
        let r = run_file(&path);
        let m = &r.metrics[0];
        let want = &truth[&name];
        let traced = &m.traced[&Fidelity::Vector];
        assert_eq!(traced.len(), want.len(), "{name}");
        let (mut e_traced, mut e_closed) = (0.0f64, 0.0f64);
        for (k, ((t, c), w)) in traced.iter().zip(&m.analytic).zip(want).enumerate() {
            if *w == 0.0 {
                // No wave leaves the far face: nothing is traced there, and T is 0 exactly.
                assert_eq!((*t, *c), (0.0, 0.0), "{name} point {k}");
                dark += 1;
                continue;
            }
            e_traced = e_traced.max((t - w).abs() / w);
            e_closed = e_closed.max((c - w).abs() / w);
            println!("{name} {k}: traced {t:e}, closed form {c:e}, 50 digits {w:e}");
        }
        println!("{name}: traced {e_traced:.3e}, closed form {e_closed:.3e} relative to 50 digits");
        assert_exact_and_passed(&name, m, e_traced, e_closed);
        names.push(name);
    }
    assert!(names.len() >= 6, "{names:?}");
    assert!(
        dark >= 5,
        "points beyond the substrate's critical angle: {dark}"
    );
}

/// Power is conserved by the traced waves: at every probe angle the traced reflected R
/// (`tests/tunnelling/X.json`) and the traced transmitted T (`tests/tunnelling_transmitted/X_t.json`,
/// the same scene observed below) of a lossless film beyond the critical angle sum to 1, from
/// the reflected child's r_layer and the tunnelled child's t_layer, each carried through the
/// tracer's own frames and power factor.
#[test]
fn the_traced_reflected_and_tunnelled_waves_carry_all_the_power() {
    let mut pairs = 0;
    let mut worst = 0.0f64;
    for entry in std::fs::read_dir(root().join("tests/tunnelling")).unwrap() {
        let path = entry.unwrap().path();
        let name = path.file_stem().unwrap().to_str().unwrap().to_string();
        let below = root().join(format!("tests/tunnelling_transmitted/{name}_t.json"));
        let (r, t) = (run_file(&path), run_file(&below));
        let (r, t) = (
            &r.metrics[0].traced[&Fidelity::Vector],
            &t.metrics[0].traced[&Fidelity::Vector],
        );
        assert_eq!(r.len(), t.len(), "{name}");
        for (k, (a, b)) in r.iter().zip(t).enumerate() {
            let dev = (a + b - 1.0).abs();
            println!("{name} {k}: R {a:e} + T {b:e} − 1 = {dev:e}");
            worst = worst.max(dev);
        }
        pairs += 1;
    }
    println!("|R + T − 1| ≤ {worst:.3e} over {pairs} films");
    assert!(pairs >= 5, "{pairs}");
    assert!(worst <= 1e-14, "{worst:e}");
}

/// The tunnelled child at one face (`interaction::Child::Tunnelled`): a 100 nm air gap between
/// n = 1.5 and a substrate n = 1.7 lit at 60° (beyond the critical angle 41.8°). The child
/// travels in n3 along Snell's direction from n1 to n3 (n1 sin θ1 = n3 sin θ3, in the plane of
/// incidence), carries E·s = t_s (E_in·s) and E·p = t_p (E_in·p_in) with the layer's t of the
/// independent Airy sum (`Film::t`), its ledger records them, and the paper's rung takes their
/// conjugates (the opposite time convention, as for r_layer: same |t|). There is no tunnelled
/// child without a layer, below the critical angle, or where the substrate (n3 = 1.2 here) is
/// beyond its own critical angle.
#[test]
fn the_tunnelled_child_leaves_along_snell_with_the_layer_transmission() {
    use fringe::optics::interaction::{Child, interact_along};
    use fringe::optics::ray::LedgerEntry;
    let (n1, n2, n3, lambda, d) = (1.5, 1.0, 1.7, 550e-9, 1e-7);
    let ray_at = |deg: f64| {
        let theta = deg.to_radians();
        let d_i = DVec3::new(theta.sin(), 0.0, -theta.cos());
        let ray = Ray::linear(
            DVec3::new(-theta.tan(), 0.0, 1.0),
            d_i,
            DVec3::new(0.6, 0.8, 0.0).normalize(),
            1.0,
            lambda,
            n1,
        );
        (ray, d_i)
    };
    let hit = |layer: Option<f64>, beyond: f64| InterfaceHit {
        surface: 0,
        point: DVec3::ZERO,
        normal: DVec3::Z,
        optics: SurfaceOptics::Dielectric {
            n_front: n1,
            n_back: n2,
        },
        coherence: CoherenceRules::default(),
        layers: [
            layer.map(|thickness_m| Layer {
                partner: 1,
                thickness_m,
                n_beyond: beyond,
                lambda_m: lambda,
            }),
            None,
        ],
    };
    let (ray, d_i) = ray_at(60.0);
    let child = interact_along(
        ray.clone(),
        &hit(Some(d), n3),
        CoefficientModel::Vector,
        Child::Tunnelled,
    )
    .expect("a tunnelled wave");
    // Snell from n1 to n3, in the plane of incidence (y = 0), going down.
    let sin3 = n1 * 60f64.to_radians().sin() / n3;
    let want_dir = DVec3::new(sin3, 0.0, -(1.0 - sin3 * sin3).sqrt());
    assert!((child.dir - want_dir).length() <= 4e-16, "{}", child.dir);
    assert_eq!(child.index, n3);
    let film = Film {
        n1,
        n2,
        n3,
        thickness_m: d,
    };
    let inc = Incidence::between(d_i, DVec3::Z);
    let s = DVec3::Y * -1.0; // d_i × N normalized: (sin θ, 0, −cos θ) × z = (0, −sin θ, 0)
    let p_in = d_i.cross(s);
    let p_out = child.dir.cross(s);
    let along = |e: [Complex64; 3], v: DVec3| e[0] * v.x + e[1] * v.y + e[2] * v.z;
    let (e_in, e_out) = (ray.field(), child.field());
    let t_s = film.t(inc, lambda, Pol::S);
    let t_p = film.t(inc, lambda, Pol::P);
    let got_s = along(e_out, s) / along(e_in, s);
    let got_p = along(e_out, p_out) / along(e_in, p_in);
    println!("t_s {got_s} vs {t_s}, t_p {got_p} vs {t_p}");
    assert!((got_s - t_s).norm() <= 1e-15 * t_s.norm(), "s");
    assert!((got_p - t_p).norm() <= 1e-15 * t_p.norm(), "p");
    assert!(
        t_s.norm() > 0.1 && t_p.norm() > 0.1,
        "the coupling matters here"
    );
    match child.ledger.entries.iter().last() {
        Some(LedgerEntry::Tunnel {
            surface: 0,
            t_s: a,
            t_p: b,
        }) => {
            assert!((*a - t_s).norm() <= 1e-15 && (*b - t_p).norm() <= 1e-15);
        }
        other => panic!("last ledger entry {other:?}"),
    }
    let paper = interact_along(
        ray.clone(),
        &hit(Some(d), n3),
        CoefficientModel::PaperRules,
        Child::Tunnelled,
    )
    .expect("a tunnelled wave under the paper's rules");
    let paper_s = along(paper.field(), s) / along(e_in, s);
    assert!((paper_s - got_s.conj()).norm() <= 1e-15, "paper: {paper_s}");
    // No tunnelled wave: no layer, below the critical angle, a substrate beyond its own.
    let none = |ray: &Ray, h: &InterfaceHit| {
        interact_along(ray.clone(), h, CoefficientModel::Vector, Child::Tunnelled).is_none()
    };
    assert!(none(&ray, &hit(None, n3)), "no layer");
    assert!(
        none(&ray_at(30.0).0, &hit(Some(d), n3)),
        "below the critical angle"
    );
    assert!(
        none(&ray, &hit(Some(d), 1.2)),
        "n3 beyond its critical angle too"
    );
}

/// A traced case against 50 digits: the closed form within 1e-13 and the tracer within 1e-12
/// of them (`e_closed`, `e_traced`), and the case's own gate passed at `vector`.
fn assert_exact_and_passed(name: &str, m: &run::MetricResult, e_traced: f64, e_closed: f64) {
    assert!(e_closed <= 1e-13, "{name}: closed form {e_closed:e}");
    assert!(e_traced <= 1e-12, "{name}: traced {e_traced:e}");
    let tol = m.tolerances[&Fidelity::Vector];
    let gate = m.stats(Fidelity::Vector).expect("vector stats").max_abs_dev;
    assert!(gate <= tol, "{name}: the gate, {gate:e} > {tol:e}");
}
