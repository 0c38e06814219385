//! Pinned Fresnel values at named angles. Every expected number is derived independently of the
//! code, and the comment at each says where it comes from: by hand from P1–P4 (docs/PHYSICS.md §1),
//! or from a one-off high-precision evaluation with Python mpmath (50 digits) of the B&W formulas:
//!
//! ```text
//! python3 - <<'EOF'
//! from mpmath import mp, mpf, sqrt, cos, sin, asin, atan, degrees, radians, mpc, arg
//! mp.dps = 50
//! def fres(n1, n2, th):
//!     ci = cos(th); c2 = 1 - (n1/n2)**2*sin(th)**2
//!     ct = sqrt(c2) if c2 >= 0 else mpc(0, sqrt(-c2))
//!     return ((n1*ci-n2*ct)/(n1*ci+n2*ct), (n2*ci-n1*ct)/(n2*ci+n1*ct),
//!             2*n1*ci/(n1*ci+n2*ct), 2*n1*ci/(n2*ci+n1*ct))
//! n = mpf('1.5')
//! print(degrees(atan(n)), degrees(asin(1/n)))
//! print(fres(mpf(1), n, radians(mpf('89.999'))))
//! for a in ['54.6', '48.6']:
//!     rs, rp, _, _ = fres(mpf('1.51'), mpf(1), radians(mpf(a)))
//!     print(a, arg(rs), arg(rp), arg(rp) - arg(rs))
//! EOF
//! ```
//!
//! Output (pasted below where used):
//! θB = 56.309932474020213086…°, θc = 41.810314895778598065…°;
//! at 89.999°: r_s = −0.99996877908858102702…, r_p = −0.99992975432001615601…,
//! t_s = 3.1220911418972977178e-5, t_p = 4.6830453322562656968e-5;
//! n = 1.51 → air at 54.6°: arg r_s = −1.37411540386229195…, arg r_p = −2.15972455967901610…,
//! Δ = −0.78560915581672415275 rad (−45.01208897513376°);
//! at 48.6°: arg r_s = −0.97888669715553188…, arg r_p = −1.76395622863189798…,
//! Δ = −0.78506953147636609660 rad (−44.98117077790871°).

use crate::common;

use common::*;
use fringe::optics::fresnel::{brewster_angle, critical_angle, fresnel, ideal_mirror};
use num_complex::Complex64;

fn assert_c(what: &str, actual: Complex64, expected: Complex64, tol: f64) {
    let err = cdist(actual, expected);
    assert!(
        err <= tol,
        "{what}: actual {actual:e}, expected {expected:e}, err {err:e} > tol {tol:e}"
    );
}

fn assert_r(what: &str, actual: f64, expected: f64, tol: f64) {
    let err = (actual - expected).abs();
    assert!(
        err <= tol,
        "{what}: actual {actual:e}, expected {expected:e}, err {err:e} > tol {tol:e}"
    );
}

/// Normal incidence air → glass n = 1.5, by hand from P1–P4 with cos θi = cos θt = 1:
/// r_s = (1 − 1.5)/(1 + 1.5) = −0.2, r_p = (1.5 − 1)/(1.5 + 1) = +0.2 (p_r = −p_i in this frame,
/// so the 3D field is −0.2·E either way), t_s = t_p = 2/2.5 = 0.8, R = 0.04, T = 1.5·0.64 = 0.96.
#[test]
fn normal_incidence_air_to_glass() {
    let f = fresnel(1.0, 1.5, 1.0);
    assert_c("r_s", f.r_s, Complex64::from(-0.2), 1e-15);
    assert_c("r_p", f.r_p, Complex64::from(0.2), 1e-15);
    assert_c("t_s", f.t_s, Complex64::from(0.8), 1e-15);
    assert_c("t_p", f.t_p, Complex64::from(0.8), 1e-15);
    assert_c("cos θt", f.cos_theta_t, Complex64::from(1.0), 1e-15);
    assert!(!f.total_internal_reflection);
    let p = f.power(1.0, 1.5, 1.0);
    assert_r("R_s", p.r_s, 0.04, 1e-15);
    assert_r("R_p", p.r_p, 0.04, 1e-15);
    assert_r("T_s", p.t_s, 0.96, 1e-15);
    assert_r("T_p", p.t_p, 0.96, 1e-15);
    // And from the glass side (by hand): r_s = +0.2, r_p = −0.2, t = 2·1.5/2.5 = 1.2.
    let g = fresnel(1.5, 1.0, 1.0);
    assert_c("r_s glass→air", g.r_s, Complex64::from(0.2), 1e-15);
    assert_c("r_p glass→air", g.r_p, Complex64::from(-0.2), 1e-15);
    assert_c("t_s glass→air", g.t_s, Complex64::from(1.2), 1e-15);
    assert_c("t_p glass→air", g.t_p, Complex64::from(1.2), 1e-15);
}

/// Brewster air → 1.5: θB = atan 1.5 = 56.30993247402021° (mpmath above); r_p = 0; with
/// θi + θt = 90°, r_s = −sin(θi − θt) = −(sin²θi − cos²θi) = (1 − n²)/(1 + n²) = −1.25/3.25
/// = −0.384615384615… (by hand); t_s = 1 + r_s = 2/3.25 = 0.615384…; with cos θt = sin θi = n cos θi,
/// t_p = 2 cos θi/(n cos θi + cos θt) = 2 cos θi/(2 n cos θi) = 1/n = 0.6666… (by hand).
#[test]
fn brewster_air_to_glass() {
    let tb = brewster_angle(1.0, 1.5);
    assert_r("θB (deg)", tb.to_degrees(), 56.309_932_474_020_213, 1e-12);
    let f = fresnel(1.0, 1.5, tb.cos());
    assert!(
        f.r_p.norm() < 1e-15,
        "r_p at θB: actual {:e}, expected 0, err {:e}",
        f.r_p,
        f.r_p.norm()
    );
    assert_c("r_s at θB", f.r_s, Complex64::from(-1.25 / 3.25), 1e-15);
    assert_c("t_s at θB", f.t_s, Complex64::from(2.0 / 3.25), 1e-15);
    assert_c("t_p at θB", f.t_p, Complex64::from(1.0 / 1.5), 1e-15);
    // From inside the glass the Brewster angle is atan(1/1.5) = 90° − θB.
    let tb2 = brewster_angle(1.5, 1.0);
    assert_r(
        "θB glass→air (deg)",
        tb2.to_degrees(),
        90.0 - 56.309_932_474_020_213,
        1e-12,
    );
    let g = fresnel(1.5, 1.0, tb2.cos());
    assert!(
        g.r_p.norm() < 1e-15,
        "r_p at internal θB: actual {:e}, expected 0",
        g.r_p
    );
}

/// Critical angle glass 1.5 → air: θc = asin(1/1.5) = 41.810314895778598° (mpmath above).
/// At θc, cos θt = 0, so by hand from P1–P4: r_s = r_p = 1, t_s = 2, t_p = 2 n1/n2 = 3.
/// Tolerance: θc in f64 is off by ~1e-16 rad, which leaves |cos²θt| ~ 1e-16 and so
/// |cos θt| ~ 1e-8; the coefficients are then off by ~2·1.5·1e-8/0.745 ≈ 4e-8 (first-order
/// expansion, see fresnel_props continuity test). Asserted to 1e-7.
#[test]
fn critical_angle_glass_to_air() {
    let tc = critical_angle(1.5, 1.0).expect("critical angle exists for 1.5 → 1");
    assert_r("θc (deg)", tc.to_degrees(), 41.810_314_895_778_598, 1e-12);
    assert!(
        critical_angle(1.0, 1.5).is_none(),
        "no critical angle air → glass"
    );
    let f = fresnel(1.5, 1.0, tc.cos());
    assert_c("r_s at θc", f.r_s, Complex64::from(1.0), 1e-7);
    assert_c("r_p at θc", f.r_p, Complex64::from(1.0), 1e-7);
    assert_c("t_s at θc", f.t_s, Complex64::from(2.0), 1e-7);
    assert_c("t_p at θc", f.t_p, Complex64::from(3.0), 1e-7);
    assert!(
        f.cos_theta_t.norm() < 1e-7,
        "cos θt at θc: actual {:e}, expected 0",
        f.cos_theta_t
    );
    // 1° beyond: TIR with unit modulus; 1° before: not TIR.
    let tir = fresnel(1.5, 1.0, (tc + 1f64.to_radians()).cos());
    assert!(tir.total_internal_reflection);
    let no = fresnel(1.5, 1.0, (tc - 1f64.to_radians()).cos());
    assert!(!no.total_internal_reflection);
}

/// Grazing incidence 89.999° air → 1.5. Expected from mpmath (above):
/// r_s = −0.99996877908858102702, r_p = −0.99992975432001615601,
/// t_s = 3.1220911418972977178e-5, t_p = 4.6830453322562656968e-5.
/// Cross-check by hand: first order in cos θ, r_s ≈ −1 + 2 cos θ/sqrt(n² − 1) = −0.9999687786…,
/// r_p ≈ −1 + 2 n² cos θ/sqrt(n² − 1) = −0.9999297519 (agree with mpmath to ~5e-9 = O(cos²θ)).
/// Tolerance: the f64 angle 89.999° → rad is off by ≤ 1e-16 rad, moving cos θ (1.745e-5) by
/// ≤ 1e-16 and r by ≤ 2e-16·n²; asserted to 1e-14.
#[test]
fn grazing_air_to_glass() {
    let c = 89.999f64.to_radians().cos();
    let f = fresnel(1.0, 1.5, c);
    assert_c(
        "r_s",
        f.r_s,
        Complex64::from(-0.999_968_779_088_581_1),
        1e-14,
    );
    assert_c(
        "r_p",
        f.r_p,
        Complex64::from(-0.999_929_754_320_016_2),
        1e-14,
    );
    assert_c(
        "t_s",
        f.t_s,
        Complex64::from(3.122_091_141_897_298e-5),
        1e-14,
    );
    assert_c(
        "t_p",
        f.t_p,
        Complex64::from(4.683_045_332_256_266e-5),
        1e-14,
    );
    // The first-order expansion (by hand) to its own accuracy O(cos²θ) ≈ 3e-10·…
    let first_s = -1.0 + 2.0 * c / (1.5f64 * 1.5 - 1.0).sqrt();
    let first_p = -1.0 + 2.0 * 2.25 * c / (1.5f64 * 1.5 - 1.0).sqrt();
    assert_r("r_s vs first order", f.r_s.re, first_s, 1e-8);
    assert_r("r_p vs first order", f.r_p.re, first_p, 1e-8);
    // Exactly grazing (cos θ = 0): r_s = r_p = −1, t = 0 (by hand from P1–P4).
    let g = fresnel(1.0, 1.5, 0.0);
    assert_c("r_s at 90°", g.r_s, Complex64::from(-1.0), 1e-15);
    assert_c("r_p at 90°", g.r_p, Complex64::from(-1.0), 1e-15);
    assert_c("t_s at 90°", g.t_s, Complex64::from(0.0), 1e-15);
}

/// Fresnel rhomb, n = 1.51 → air: Δ = arg r_p − arg r_s under TIR. Expected from mpmath (above):
/// 54.6°: Δ = −0.78560915581672415275 rad; 48.6°: Δ = −0.78506953147636609660 rad; both
/// within 0.02° of −45° (docs/PHYSICS.md §1), and arg r_s, arg r_p individually (P5, P6 signs).
#[test]
fn fresnel_rhomb_phase_difference() {
    for (deg, arg_s, arg_p, delta) in [
        (
            54.6f64,
            -1.374_115_403_862_292,
            -2.159_724_559_679_016,
            -0.785_609_155_816_724_2,
        ),
        (
            48.6f64,
            -0.978_886_697_155_531_9,
            -1.763_956_228_631_898,
            -0.785_069_531_476_366,
        ),
    ] {
        let f = fresnel(1.51, 1.0, deg.to_radians().cos());
        assert!(f.total_internal_reflection, "TIR expected at {deg}°");
        assert_r(&format!("arg r_s at {deg}°"), f.r_s.arg(), arg_s, 1e-9);
        assert_r(&format!("arg r_p at {deg}°"), f.r_p.arg(), arg_p, 1e-9);
        let d = wrap(f.r_p.arg() - f.r_s.arg());
        assert_r(&format!("Δ at {deg}°"), d, delta, 1e-9);
        assert_r(
            &format!("|Δ| at {deg}° (deg) vs 45°"),
            d.abs().to_degrees(),
            45.0,
            0.02,
        );
    }
}

/// Ideal mirror: n2 → ∞ limit of P1, P2 (by hand): r_s = −1, r_p = +1, no transmission; and the
/// limit is approached by fresnel(1, n2 → large) at normal incidence ((1 − n)/(1 + n) → −1).
#[test]
fn ideal_mirror_is_the_infinite_index_limit() {
    let m = ideal_mirror();
    assert_c("mirror r_s", m.r_s, Complex64::from(-1.0), 0.0);
    assert_c("mirror r_p", m.r_p, Complex64::from(1.0), 0.0);
    assert_c("mirror t_s", m.t_s, Complex64::from(0.0), 0.0);
    let f = fresnel(1.0, 1e12, 0.6);
    assert_c("r_s, n2 = 1e12", f.r_s, m.r_s, 1e-11);
    assert_c("r_p, n2 = 1e12", f.r_p, m.r_p, 1e-11);
}
