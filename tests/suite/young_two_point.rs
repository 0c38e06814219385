//! Young's two-point interference (docs/PHYSICS.md §3 P10, §5 "Young", "Coherence").
//!
//! Two point sources S1 = (−h, 0, 0), S2 = (+h, 0, 0) in vacuum, screen points P = (x, 0, L) on a
//! line: sources and screen points lie in the plane y = 0, and both sources are polarized along
//! y (perpendicular to that plane), so both fields at P are parallel to ŷ with unit amplitude
//! (spreading off). Expected (P10 with I1 = I2 = 1, by hand): I = 2 + 2 cos(2π(r1 − r2)/λ), with
//! the exact distances; r1 − r2 is formed without cancellation as
//! (r1² − r2²)/(r1 + r2) = 4 h x/(r1 + r2). Different coherence groups: I = I1 + I2 = 2.
//! With spreading on (unit intensity at unit distance): amplitudes 1/r1, 1/r2, so
//! I = 1/r1² + 1/r2² + 2 cos δ/(r1 r2).
//!
//! Tolerance: 1e-12 relative to the fringe maximum, plus the phase-rounding budget of the
//! tracer's f64 representation: a path of r/λ cycles carries phase rounding of a few ulp of
//! r/λ, δφ ≈ 2π·4ε·(r1 + r2)/λ, which moves I by ≤ 2√(I1 I2)·|sin δ|·δφ ≤ 2δφ. In the µm-scale
//! geometry below δφ ≈ 1e-12, so the test holds the code to ~1e-12; the paper's geometry
//! (r ≈ 0.275 m = 5·10⁵ λ) is checked with the same formula, where the budget is ~2e-9.

use crate::common;

use common::EPS;
use fringe::accumulate::fidelity::Fidelity;
use fringe::optics::material::Medium;
use fringe::scene::Scene;
use fringe::scene::source::{Emitter, Polarization, Source};
use fringe::trace::path::{EnumerationLimits, Sequence, SolveOptions, Target};
use fringe::trace::{self, TraceSettings};
use glam::DVec3;
use std::f64::consts::TAU;

fn scene(h: f64, groups: (u64, u64)) -> Scene {
    let mut scene = Scene::new(Medium::vacuum());
    for (x, g) in [(-h, groups.0), (h, groups.1)] {
        scene.sources.push(Source {
            name: format!("S{x}"),
            emitter: Emitter::Point {
                position: DVec3::new(x, 0.0, 0.0),
            },
            polarization: Polarization::Linear {
                reference: DVec3::Y,
                angle_rad: 0.0,
            },
            intensity: 1.0,
            coherence_group: g,
            coherence_length_m: f64::INFINITY,
        });
    }
    scene
}

/// Intensity at every screen point, with (r1, r2) for each.
fn screen(
    scene: &Scene,
    lambda: f64,
    xs: &[f64],
    l: f64,
    spreading: bool,
) -> Vec<(f64, f64, f64, f64)> {
    let optics = scene.optics(lambda).unwrap();
    let limits = EnumerationLimits::default();
    let plan = trace::plan(scene, &optics, &[DVec3::new(0.0, 0.0, l)], &limits);
    let listed: Vec<Vec<Sequence>> = plan.sequences.iter().map(|t| t.sequences()).collect();
    assert_eq!(
        listed,
        vec![vec![vec![]], vec![vec![]]],
        "no surfaces: only the direct sequence per source"
    );
    let settings = TraceSettings {
        limits,
        solve: SolveOptions {
            spreading,
            ..SolveOptions::default()
        },
        ..TraceSettings::default()
    };
    let h = scene.sources[1].anchor().x;
    xs.iter()
        .map(|&x| {
            let p = DVec3::new(x, 0.0, l);
            let (found, failed) =
                trace::arrivals(scene, &optics, &plan, &Target::Point(p), &settings);
            assert!(
                failed.is_empty() && found.len() == 2,
                "two direct arrivals expected at x = {x}: {failed:?}"
            );
            let r1 = (p - DVec3::new(-h, 0.0, 0.0)).length();
            let r2 = (p - DVec3::new(h, 0.0, 0.0)).length();
            (x, trace::intensity(&found, Fidelity::Vector), r1, r2)
        })
        .collect()
}

fn check_fringes(lambda: f64, h: f64, l: f64, xs: &[f64]) {
    let sc = scene(h, (0, 0));
    for (x, i, r1, r2) in screen(&sc, lambda, xs, l, false) {
        let delta = TAU * (4.0 * h * x / (r1 + r2)) / lambda;
        let expected = 2.0 + 2.0 * delta.cos();
        let dphi = TAU * 4.0 * EPS * (r1 + r2) / lambda;
        let tol = 1e-12 * 4.0 + 2.0 * dphi;
        let err = (i - expected).abs();
        assert!(
            err <= tol,
            "λ {lambda:e}, x {x:e}: I actual {i:e}, expected 2 + 2cos δ = {expected:e}, err {err:e} > tol {tol:e}"
        );
    }
}

/// µm-scale Young: λ = 550 nm, d = 2h = 20 µm, L = 100 µm (fringe spacing λL/d ≈ 2.75 µm),
/// 81 screen points over ±20 µm (several fringes, bright and dark).
#[test]
fn coherent_sources_give_p10_fringes() {
    let xs: Vec<f64> = (-40..=40).map(|k| k as f64 * 0.5e-6).collect();
    check_fringes(550e-9, 10e-6, 100e-6, &xs);
}

/// The paper's geometry (§4.1): λ = 550 nm, d = 500λ, l = 1000 d, over ±3 fringe spacings
/// (λ l/d = 0.55 mm), with the rounding budget stated in the module docs.
#[test]
fn paper_geometry_fringes() {
    let lambda = 550e-9;
    let d = 500.0 * lambda;
    let l = 1000.0 * d;
    let xs: Vec<f64> = (-30..=30).map(|k| k as f64 * 0.055e-3).collect();
    check_fringes(lambda, d / 2.0, l, &xs);
}

/// Mutually incoherent sources (different coherence groups): I = I1 + I2 = 2 everywhere.
#[test]
fn incoherent_sources_add_intensities() {
    let sc = scene(10e-6, (0, 1));
    let xs: Vec<f64> = (-20..=20).map(|k| k as f64 * 0.7e-6).collect();
    for (x, i, _, _) in screen(&sc, 550e-9, &xs, 100e-6, false) {
        let err = (i - 2.0).abs();
        assert!(
            err <= 1e-14,
            "x {x:e}: I actual {i:e}, expected I1 + I2 = 2, err {err:e}"
        );
    }
}

/// Spreading on: I = 1/r1² + 1/r2² + 2 cos δ/(r1 r2), to 1e-9 relative to (1/r1 + 1/r2)²
/// (the spreading factors come from central differences, accurate to ~1e-10).
#[test]
fn spreading_weights_the_fringes() {
    let (lambda, h, l) = (550e-9, 10e-6, 100e-6);
    let sc = scene(h, (3, 3));
    let xs: Vec<f64> = (-40..=40).map(|k| k as f64 * 0.5e-6).collect();
    for (x, i, r1, r2) in screen(&sc, lambda, &xs, l, true) {
        let delta = TAU * (4.0 * h * x / (r1 + r2)) / lambda;
        let expected = 1.0 / (r1 * r1) + 1.0 / (r2 * r2) + 2.0 * delta.cos() / (r1 * r2);
        let scale = (1.0 / r1 + 1.0 / r2).powi(2);
        let err = (i - expected).abs();
        assert!(
            err <= 1e-9 * scale,
            "x {x:e}: I actual {i:e}, expected {expected:e}, err {err:e} > {:e}",
            1e-9 * scale
        );
    }
}

/// Two beams in glass (n = 1.5) above a glass/air face z = 0: the direct one S → P and one
/// totally internally reflected at the face (incidence ≈ 68° > θc = 41.8°). The TIR phase
/// (P5/P6) and the path phase e^{+i2πs/λ} must use the same time convention, so the fringes are
/// I = |E1 + E2 e^{iδ}|², δ = 2π n (|P − S'| − |P − S|)/λ (image method, S' the mirror image),
/// with E2 built here from my own B&W coefficients (`common::ref_fresnel`) in the frame of
/// docs/PHYSICS.md §1: E2 = r_s (E0·s) s + r_p (E0·p_i) p_r. For s light (field ∥ y) this is
/// 2 + 2 cos(δ + arg r_s). The paper's rule (conjugate TIR phase, docs/PHYSICS.md §1) must give
/// 2 + 2 cos(δ − arg r_s) instead: the fringe shift the harness is meant to show.
#[test]
fn tir_two_beam_fringes_use_one_time_convention() {
    use common::{field_norm, ref_fresnel};
    use fringe::scene::geometry::Plane;
    use fringe::trace::Plan;
    use fringe::trace::path::{Event, EventKind};
    use num_complex::Complex64;
    let (lambda, n) = (550e-9, 1.5);
    for (s_pol, reference) in [(true, DVec3::Y), (false, DVec3::Z)] {
        let mut scene = Scene::new(Medium::constant("glass", n));
        let face = scene.add_interface(
            "face",
            Plane::new(DVec3::ZERO, DVec3::Z),
            Medium::constant("glass", n),
            Medium::vacuum(),
        );
        let s = DVec3::new(-50e-6, 0.0, 20e-6);
        scene.sources.push(Source {
            name: "S".into(),
            emitter: Emitter::Point { position: s },
            polarization: Polarization::Linear {
                reference,
                angle_rad: 0.0,
            },
            intensity: 1.0,
            coherence_group: 0,
            coherence_length_m: f64::INFINITY,
        });
        let optics = scene.optics(lambda).unwrap();
        let plan = Plan::from_sequences(vec![vec![
            vec![],
            vec![Event {
                surface: face,
                kind: EventKind::Reflect,
            }],
        ]]);
        let s_img = DVec3::new(s.x, s.y, -s.z);
        let e_of = |d: DVec3| (reference - reference.dot(d) * d).normalize();
        for k in 0..=40 {
            let p = DVec3::new(50e-6 + k as f64 * 0.3e-6, 0.0, 20e-6 + k as f64 * 0.1e-6);
            let (found, failed) = trace::arrivals(
                &scene,
                &optics,
                &plan,
                &Target::Point(p),
                &TraceSettings::default(),
            );
            assert!(
                failed.is_empty() && found.len() == 2,
                "two arrivals expected: {failed:?}"
            );
            // Expected field sum, built independently.
            let d1 = (p - s).normalize();
            let x = s_img + (s.z / (s.z + p.z)) * (p - s_img);
            let d2 = (x - s).normalize();
            let cos_i = -d2.z;
            let f = ref_fresnel(n, 1.0, cos_i);
            assert!(f.cos_t.im > 0.0, "TIR expected at the face");
            let sv = d2.cross(DVec3::Z).normalize();
            let p_i = d2.cross(sv);
            let d_r = DVec3::new(d2.x, d2.y, -d2.z);
            let p_r = d_r.cross(sv);
            let e0 = e_of(d2);
            let delta =
                std::f64::consts::TAU * n * ((p - s_img).length() - (p - s).length()) / lambda;
            let ph = Complex64::from_polar(1.0, delta);
            let e1 = e_of(d1);
            let a_s = f.r_s * e0.dot(sv);
            let a_p = f.r_p * e0.dot(p_i);
            let comp =
                |e1c: f64, sc: f64, pc: f64| Complex64::from(e1c) + (a_s * sc + a_p * pc) * ph;
            let total = [
                comp(e1.x, sv.x, p_r.x),
                comp(e1.y, sv.y, p_r.y),
                comp(e1.z, sv.z, p_r.z),
            ];
            let expected = field_norm(&total).powi(2);
            let i = trace::intensity(&found, Fidelity::Vector);
            let dphi =
                std::f64::consts::TAU * 4.0 * EPS * n * ((p - s_img).length() + (p - s).length())
                    / lambda;
            let tol = 4e-12 + 2.0 * dphi;
            let err = (i - expected).abs();
            assert!(
                err <= tol,
                "{} k {k}: vector I actual {i:e}, expected {expected:e}, err {err:e} > {tol:e}",
                if s_pol { "s" } else { "p" }
            );
            if s_pol {
                let by_hand = 2.0 + 2.0 * (delta + f.r_s.arg()).cos();
                let err = (i - by_hand).abs();
                assert!(
                    err <= tol,
                    "s k {k}: vector I actual {i:e}, expected 2 + 2cos(δ + arg r_s) {by_hand:e}, err {err:e}"
                );
                let ip = trace::intensity(&found, Fidelity::PaperRules);
                let paper = 2.0 + 2.0 * (delta - f.r_s.arg()).cos();
                let err = (ip - paper).abs();
                assert!(
                    err <= tol,
                    "s k {k}: paper_rules I actual {ip:e}, expected 2 + 2cos(δ − arg r_s) {paper:e}, err {err:e}"
                );
            }
        }
    }
}
