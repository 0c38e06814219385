//! Numerical stability at the extremes (robustness issue): named angles ± 1e-12, nearly equal
//! indices, optical paths from 1 nm to 10 m, films from 0.1 nm to 1 mm, high finesse, and no
//! NaN or infinity anywhere for random valid scenes. Every expected value is a closed form
//! evaluated independently (how is said at each test).

use fringe::accumulate::fidelity::Fidelity;
use fringe::harness::analytic::plate::{Film, Pol};
use fringe::optics::fresnel::{brewster_angle, critical_angle, fresnel};
use fringe::trace::path::{EnumerationLimits, Target};
use fringe::trace::{self, TraceSettings};
use glam::DVec3;
use proptest::prelude::*;

/// The traced far-field film reflectance/transmittance (the tracer's own scene set-up, shared
/// with the report's stability sweep).
use fringe::harness::stability::traced_film;

#[test]
fn named_angles_plus_minus_1e_12() {
    let (n1, n2) = (1.0, 1.5);
    // Normal incidence and 1e-12 rad: r = (n1 − n2)/(n1 + n2) + O(θ²) (P1 at θ = 0).
    for theta in [0.0, 1e-12] {
        let f = fresnel(n1, n2, f64::cos(theta));
        let r0 = (n1 - n2) / (n1 + n2);
        assert!(
            (f.r_s.re - r0).abs() < 1e-15,
            "θ = {theta:e}: r_s {:e}, expected {r0:e}",
            f.r_s.re
        );
        assert!(
            (f.r_p.re + r0).abs() < 1e-15,
            "θ = {theta:e}: r_p {:e}, expected {:e}",
            f.r_p.re,
            -r0
        );
    }
    // Brewster ± 1e-12: r_p changes sign and |r_p| ≤ |dr_p/dθ|·1e-12 (|dr_p/dθ| < 2 here, from
    // differentiating (P2): at θB it equals (1 − n²)/(n²+1)^{...}; bounded by 2 for n ≤ 4).
    let tb = brewster_angle(n1, n2);
    let below = fresnel(n1, n2, (tb - 1e-12).cos()).r_p.re;
    let above = fresnel(n1, n2, (tb + 1e-12).cos()).r_p.re;
    assert!(
        below > 0.0 && above < 0.0,
        "r_p at θB ∓ 1e-12: {below:e}, {above:e}"
    );
    assert!(
        below.abs() < 2e-12 && above.abs() < 2e-12,
        "|r_p| near θB: {below:e}, {above:e}"
    );
    // Critical angle ± 1e-12 (glass → air): |r| = 1 above; below, 1 − |r_s| ~ sqrt(ε) small;
    // no NaN on either side.
    let tc = critical_angle(1.5, 1.0).unwrap();
    for (theta, tir) in [(tc - 1e-12, false), (tc + 1e-12, true)] {
        let f = fresnel(1.5, 1.0, theta.cos());
        assert_eq!(
            f.total_internal_reflection,
            tir,
            "θc {}",
            if tir { "+ ε" } else { "− ε" }
        );
        for r in [f.r_s, f.r_p, f.t_s, f.t_p] {
            assert!(
                r.re.is_finite() && r.im.is_finite(),
                "non-finite coefficient at θc ± ε"
            );
        }
        assert!(
            (f.r_s.norm() - 1.0).abs() < 1e-5,
            "|r_s| at θc ± ε: {}",
            f.r_s.norm()
        );
    }
    // 89.9999° and exactly grazing: r_s → −1 linearly, r_s ≈ −1 + 2 cos θ/sqrt(n² − 1)
    // (first-order expansion of P1 in cos θ for n1 = 1).
    let c = (89.9999f64).to_radians().cos();
    let f = fresnel(1.0, 1.5, c);
    let expected = -1.0 + 2.0 * c / (1.5f64 * 1.5 - 1.0).sqrt();
    assert!(
        (f.r_s.re - expected).abs() < 1e-10,
        "r_s at 89.9999°: {:e}, expected {expected:e}",
        f.r_s.re
    );
    let g = fresnel(1.0, 1.5, 0.0);
    assert_eq!((g.r_s.re, g.r_p.re), (-1.0, -1.0), "exactly grazing");
    let p = g.power(1.0, 1.5, 0.0);
    assert_eq!((p.r_s, p.t_s), (1.0, 0.0), "grazing: all reflected");
}

#[test]
fn nearly_equal_and_large_indices() {
    // n1 = n2: no interface at every angle including grazing.
    for c in [0.0, 0.3, 1.0] {
        let f = fresnel(1.5, 1.5, c);
        assert!(
            f.r_s.norm() == 0.0 && f.r_p.norm() == 0.0 && (f.t_s.re - 1.0).abs() == 0.0,
            "n1 = n2 at cos θ = {c}"
        );
    }
    // n2 − n1 = 1e-12 at normal incidence: r = −Δn/(2n + Δn) exactly (P1); the cosine form keeps
    // the digits because cos²θt is formed from (n2 − n1)(n2 + n1).
    let (n1, dn) = (1.5, 1e-12);
    let f = fresnel(n1, n1 + dn, 1.0);
    let exact = -dn / (2.0 * n1 + dn);
    assert!(
        (f.r_s.re / exact - 1.0).abs() < 1e-3,
        "r_s {:e}, expected {exact:e}",
        f.r_s.re
    );
    // ... and at 60°: first order in Δn, r_s ≈ −Δn/(2 n cos²θ) (derivative of P1 with Snell).
    let c = 0.5;
    let f = fresnel(n1, n1 + dn, c);
    let approx = -dn / (2.0 * n1 * c * c);
    assert!(
        (f.r_s.re / approx - 1.0).abs() < 1e-3,
        "r_s at 60°: {:e}, expected {approx:e}",
        f.r_s.re
    );
    // n up to 4: R + T = 1.
    for n2 in [3.0, 4.0] {
        for c in [1.0, 0.5, 0.01] {
            let f = fresnel(1.0, n2, c);
            let p = f.power(1.0, n2, c);
            assert!(
                (p.r_s + p.t_s - 1.0).abs() < 1e-14 && (p.r_p + p.t_p - 1.0).abs() < 1e-14,
                "n = {n2}, cos θ = {c}"
            );
        }
    }
}

/// Path differences are formed in metres before phases: two coherent point sources at distances
/// from 1 nm to 10 m. The exact path difference is computed without cancellation as
/// (r1² − r2²)/(r1 + r2) with r1² − r2² = (x1 − x2)(x1 + x2) in exact arithmetic of the offsets.
#[test]
fn path_differences_from_1_nm_to_10_m() {
    let lambda = 550e-9;
    for distance in [1e-9f64, 1e-6, 1e-3, 1.0, 10.0] {
        let dx = 1e-7 * distance.max(1e-6); // source offset along the line of sight
        let scene = fringe::harness::stability::collinear_sources(dx);
        let p = DVec3::new(distance, 0.0, 0.0);
        let optics = scene.optics(lambda).unwrap();
        let limits = EnumerationLimits::default();
        let plan = trace::plan(&scene, &optics, &[p], &limits);
        let (arr, _) = trace::arrivals(
            &scene,
            &optics,
            &plan,
            &Target::Point(p),
            &TraceSettings::default(),
        );
        assert_eq!(arr.len(), 2);
        // Formed in double-double before rounding (issue #13: no 1e-9 rad floor at 1 m).
        let traced = (arr[1].path.optical_path - arr[0].path.optical_path).to_f64();
        let exact = dx; // collinear: r2 − r1 = dx exactly
        let phase_err = std::f64::consts::TAU * (traced - exact).abs() / lambda;
        let allowed = 1e-12;
        assert!(
            phase_err <= allowed,
            "distance {distance} m: phase error {phase_err:e} rad (traced Δs {traced:e}, exact {exact:e})"
        );
        let i = trace::intensity(&arr, Fidelity::Vector);
        let expected = 2.0 + 2.0 * (std::f64::consts::TAU * exact / lambda).cos();
        assert!(
            (i - expected).abs() < 4.0 * phase_err.max(1e-12) + 1e-12,
            "I = {i}, expected {expected}"
        );
    }
}

/// Films from 0.1 nm to 1 mm against the Airy sum (docs/PHYSICS.md §5, evaluated by
/// analytic::plate::Film from the Fresnel coefficients alone).
#[test]
fn films_from_a_tenth_of_a_nanometre_to_a_millimetre() {
    let lambda = 550e-9;
    for d in [1e-10, 1e-8, 1e-6, 1e-3] {
        for theta in [0.0f64, 1.0] {
            let film = Film {
                n1: 1.0,
                n2: 1.5,
                n3: 1.33,
                thickness_m: d,
            };
            let exact = film.reflectance(theta.cos(), lambda, Pol::S);
            let traced = traced_film([1.0, 1.5, 1.33], d, theta, lambda, 0.0, 15, true);
            assert!(
                (traced - exact).abs() < 1e-9 * exact.max(1e-3),
                "d = {d:e}, θ = {theta}: traced {traced:e}, Airy {exact:e}"
            );
        }
    }
}

/// High finesse (grazing incidence, |r21 r23| → 1): the bounce count chosen from the tail bound
/// keeps the error honest — the traced truncated sum never deviates from Airy by more than the
/// bound (2|r|τ + τ², τ the amplitude tail).
#[test]
fn high_finesse_bound_is_honest() {
    let lambda = 550e-9;
    let film = Film {
        n1: 1.0,
        n2: 1.5,
        n3: 1.0,
        thickness_m: 1e-6,
    };
    let theta = 85f64.to_radians();
    let c = theta.cos();
    let r_exact = film.r(c, lambda, Pol::S).norm();
    let exact = r_exact * r_exact;
    for orders in [2usize, 5, 10, 20, 40] {
        let tau = film.r_tail_bound(c, lambda, Pol::S, orders);
        let bound = 2.0 * r_exact * tau + tau * tau;
        let traced = traced_film(
            [1.0, 1.5, 1.0],
            1e-6,
            theta,
            lambda,
            0.0,
            2 * orders - 1,
            true,
        );
        assert!(
            (traced - exact).abs() <= bound * (1.0 + 1e-9) + 1e-15,
            "{orders} orders: |R_N − R| = {:e} > bound {bound:e}",
            (traced - exact).abs()
        );
    }
    let n = film.orders_for_bound(c, lambda, Pol::S, 1e-12);
    let traced = traced_film([1.0, 1.5, 1.0], 1e-6, theta, lambda, 0.0, 2 * n - 1, true);
    assert!(
        (traced - exact).abs() < 1e-11,
        "auto orders {n}: traced {traced:e}, Airy {exact:e}"
    );
}

proptest! {
    #![proptest_config(ProptestConfig { cases: 64, failure_persistence: None, ..ProptestConfig::default() })]

    /// Random valid film scenes through the whole pipeline: every number finite, and with the
    /// bounce count chosen from the Airy tail bound (ε = 1e-12), R + T = 1 (lossless).
    #[test]
    fn no_nan_or_infinity_for_valid_scenes(
        n2 in 1.0f64..4.0, n3 in 1.0f64..4.0, d in 1e-10f64..1e-3,
        theta in 0.0f64..1.55, lambda in 380e-9f64..780e-9, pol in 0.0f64..3.2,
    ) {
        let film = Film { n1: 1.0, n2, n3, thickness_m: d };
        let orders = [Pol::S, Pol::P].into_iter().map(|p| film.orders_for_bound(theta.cos(), lambda, p, 1e-12)).max().unwrap();
        let internal = (2 * orders + 1).min(2001);
        let r = traced_film([1.0, n2, n3], d, theta, lambda, pol, internal, true);
        prop_assert!(r.is_finite() && r >= 0.0, "R = {r}");
        let t_dir_exists = fringe::optics::fresnel::refract(DVec3::new(theta.sin(), 0.0, -theta.cos()), DVec3::Z, 1.0, n3).is_some();
        if t_dir_exists {
            let t = traced_film([1.0, n2, n3], d, theta, lambda, pol, internal, false);
            prop_assert!(t.is_finite() && t >= 0.0, "T = {t}");
            prop_assert!((r + t - 1.0).abs() < 1e-9, "R + T = {} with {internal} internal reflections", r + t);
        }
    }
}
