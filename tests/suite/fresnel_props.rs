//! Property tests of the Fresnel kernels (docs/PHYSICS.md §1, P1–P8) for indices in [1, 3] and every
//! angle of incidence in [0, π/2] (ends included).
//!
//! Expected values are identities of the exact physics (energy conservation, Stokes relations,
//! Snell's law, P5/P6, the convention-free rhomb formula) or independent re-evaluations of the
//! B&W formulas in `common::ref_fresnel`; the code's own output is never the expected value.
//! Tolerances are 1e-12 where the quantities are well conditioned and an explicit rounding budget
//! (stated at each place) where the formulas themselves lose digits (near grazing incidence and
//! near the critical angle, where cos θt = sqrt(small)).

use crate::common;

use common::*;
use fringe::optics::fresnel::{
    FresnelCoefficients, brewster_angle, critical_angle, fresnel, paper_rules, reflect, refract,
};
use num_complex::Complex64;
use proptest::prelude::*;
use std::f64::consts::FRAC_PI_2;

/// Rounding budget for a Fresnel coefficient evaluated from a cosine that was itself recomputed
/// from the other side of the interface. A recomputed cos² carries an absolute error
/// δ ≈ 8ε·(n_max/n_min)² (a handful of roundings of O(k²) terms), so the cosine itself is off by
/// min(δ/(2 cos), √δ). With r = (a − b)/(a + b), |∂r/∂a|, |∂r/∂b| ≤ 2/(a + b), hence
/// |δr| ≤ 2·k·(δcos_i + δcos_t)/(cos_i + cos_t) with k = n_max/n_min, doubled for safety.
fn roundtrip_tol(n1: f64, n2: f64, ci: f64, ct: f64) -> f64 {
    let k = n1.max(n2) / n1.min(n2);
    let delta = 8.0 * EPS * k * k;
    let d = |c: f64| {
        if c > 0.0 {
            (delta / (2.0 * c)).min(delta.sqrt())
        } else {
            delta.sqrt()
        }
    };
    1e-12 + 4.0 * k * (d(ci) + d(ct)) / (ci + ct)
}

fn check_close(
    what: &str,
    actual: Complex64,
    expected: Complex64,
    tol: f64,
) -> Result<(), TestCaseError> {
    let err = cdist(actual, expected);
    prop_assert!(
        err <= tol,
        "{what}: actual {actual:e}, expected {expected:e}, err {err:e} > tol {tol:e}"
    );
    Ok(())
}

proptest! {
    #![proptest_config(config(256))]

    /// R + T = 1 for s and p outside TIR; R = 1, T = 0 under TIR (docs/PHYSICS.md §1 "Power").
    /// Expected: 1 (energy conservation at a lossless interface). T is also recomputed here
    /// from t and an independent cos θt, so a wrong `power()` and a wrong `t` are both caught.
    #[test]
    fn power_is_conserved((n1, n2) in index_pair(), theta in angle()) {
        let c = cos_of(theta);
        // n1 = n2 at exactly grazing incidence is pinned separately
        // (`equal_indices_at_grazing_incidence_are_transparent`).
        prop_assume!(!(n1 == n2 && c == 0.0));
        let f = fresnel(n1, n2, c);
        let p = f.power(n1, n2, c);
        let reference = ref_fresnel(n1, n2, c);
        let tir = n1 * (1.0 - c * c).sqrt() > n2;
        let near_critical = (n1 * (1.0 - c * c).sqrt() - n2).abs() < 1e-12;
        if !near_critical {
            prop_assert_eq!(f.total_internal_reflection, tir, "TIR flag for n1 {} n2 {} theta {}", n1, n2, theta);
        }
        for (name, r, t) in [("s", p.r_s, p.t_s), ("p", p.r_p, p.t_p)] {
            if f.total_internal_reflection {
                prop_assert!((r - 1.0).abs() < 1e-13, "R_{name} under TIR: actual {r:e}, expected 1, err {:e}", (r - 1.0).abs());
                prop_assert!(t.abs() < 1e-300, "T_{name} under TIR: actual {t:e}, expected 0");
            } else {
                let sum = r + t;
                let err = (sum - 1.0).abs();
                prop_assert!(err < 1e-12, "R_{name}+T_{name}: actual {sum:e}, expected 1, err {err:e} (n1 {n1} n2 {n2} theta {theta})");
            }
        }
        if !f.total_internal_reflection && c > 0.0 {
            let ratio = n2 * reference.cos_t.re / (n1 * c);
            for (name, t) in [("s", f.t_s), ("p", f.t_p)] {
                let r = if name == "s" { f.r_s } else { f.r_p };
                let sum = r.norm_sqr() + ratio * t.norm_sqr();
                let err = (sum - 1.0).abs();
                prop_assert!(err < 1e-12, "|r_{name}|²+(n2 cosθt/n1 cosθi)|t_{name}|²: actual {sum:e}, expected 1, err {err:e}");
            }
        }
    }

    /// Stokes relations (docs/PHYSICS.md §1): r(2→1, θt) = −r(1→2, θi) and t12·t21 − r12·r21 = 1,
    /// for s and p, outside TIR. Expected values are the identities themselves (B&W §1.6.4).
    #[test]
    fn stokes_relations((n1, n2) in index_pair(), theta in angle()) {
        let c = cos_of(theta);
        prop_assume!(!(n1 == n2 && c == 0.0));
        let reference = ref_fresnel(n1, n2, c);
        prop_assume!(reference.cos_t.im == 0.0); // outside TIR only
        let ct = reference.cos_t.re;
        let fwd = fresnel(n1, n2, c);
        prop_assume!(!fwd.total_internal_reflection);
        let back = fresnel(n2, n1, ct);
        // Reverse incidence at θt is exactly critical when θi is grazing: the recomputed cos² may
        // round to −ε and be flagged TIR; the coefficients are still within the budget.
        prop_assert!(!back.total_internal_reflection || c < 1e-7, "reverse incidence flagged TIR at cos θt {ct}, cos θi {c}");
        let tol = roundtrip_tol(n1, n2, c, ct);
        check_close("r_s(2→1) vs −r_s(1→2)", back.r_s, -fwd.r_s, tol)?;
        check_close("r_p(2→1) vs −r_p(1→2)", back.r_p, -fwd.r_p, tol)?;
        let k = n1.max(n2) / n1.min(n2);
        let one = Complex64::from(1.0);
        check_close("t12 t21 − r12 r21 (s)", fwd.t_s * back.t_s - fwd.r_s * back.r_s, one, (2.0 * k + 2.0) * tol)?;
        check_close("t12 t21 − r12 r21 (p)", fwd.t_p * back.t_p - fwd.r_p * back.r_p, one, (2.0 * k + 2.0) * tol)?;
    }

    /// Snell's law through `refract` (n1 sin θi = n2 sin θt, coplanar, same side as the
    /// transmitted half-space), TIR reported as `None`, and `refract`/`reflect` return unit
    /// vectors; the mirror direction keeps the tangential component and flips the normal one.
    #[test]
    fn snell_and_unit_directions((n1, n2) in index_pair(), inc in incidence()) {
        let d = inc.d_i;
        let nrm = inc.normal; // random orientation
        let sin_i = d.cross(nrm).length();
        let r = reflect(d, nrm);
        let lr = r.length();
        prop_assert!((lr - 1.0).abs() < 1e-14, "|reflect| actual {lr:e}, expected 1, err {:e}", (lr - 1.0).abs());
        let dn = r.dot(nrm) + d.dot(nrm);
        prop_assert!(dn.abs() < 1e-14, "reflect: d_r·N + d_i·N actual {dn:e}, expected 0");
        let tang = (r - r.dot(nrm) * nrm) - (d - d.dot(nrm) * nrm);
        prop_assert!(tang.length() < 1e-14, "reflect: tangential change actual {:e}, expected 0", tang.length());
        let excess = n1 * sin_i - n2;
        match refract(d, nrm, n1, n2) {
            None => prop_assert!(excess > -1e-12, "refract returned TIR but n1 sinθi − n2 = {excess:e} < 0"),
            Some(t) => {
                prop_assert!(excess < 1e-12, "refract returned a ray but n1 sinθi − n2 = {excess:e} > 0");
                let lt = t.length();
                prop_assert!((lt - 1.0).abs() < 1e-14, "|refract| actual {lt:e}, expected 1, err {:e}", (lt - 1.0).abs());
                let sin_t = t.cross(nrm).length();
                let err = (n1 * sin_i - n2 * sin_t).abs();
                prop_assert!(err < 1e-12 * n1.max(n2), "Snell: n1 sinθi {:e}, n2 sinθt {:e}, err {err:e}", n1 * sin_i, n2 * sin_t);
                let plane = d.cross(nrm);
                let off = t.dot(plane);
                prop_assert!(off.abs() < 1e-12, "refracted ray leaves the plane of incidence by {off:e}");
                if inc.cos_i > 1e-9 {
                    prop_assert!(t.dot(inc.n_o) < 0.0, "refracted ray goes back to the incident side: d_t·n_o = {:e}", t.dot(inc.n_o));
                }
            }
        }
    }

    /// Re r_p changes sign exactly once between normal incidence and grazing (or the critical
    /// angle), and the change is at θB = atan(n2/n1) (B&W §1.5.3). Scan of 4000 angles.
    #[test]
    fn r_p_changes_sign_once_at_brewster((n1, n2) in distinct_index_pair()) {
        let theta_b = (n2 / n1).atan();
        let tb_code = brewster_angle(n1, n2);
        prop_assert!((tb_code - theta_b).abs() < 1e-15, "θB actual {tb_code:e}, expected {theta_b:e}");
        let theta_max = if n1 > n2 { (n2 / n1).asin() * (1.0 - 1e-9) } else { FRAC_PI_2 };
        let steps = 4000;
        let mut last_sign = 0.0f64;
        let mut changes = Vec::new();
        for k in 0..=steps {
            let th = theta_max * k as f64 / steps as f64;
            let c = if k == steps && n1 < n2 { 0.0 } else { th.cos() };
            let rp = fresnel(n1, n2, c).r_p.re;
            if rp == 0.0 {
                continue;
            }
            let s = rp.signum();
            if last_sign != 0.0 && s != last_sign {
                changes.push(th);
            }
            last_sign = s;
        }
        prop_assert_eq!(changes.len(), 1, "sign changes of Re r_p at {:?} (expected one, at θB = {})", changes, theta_b);
        let step = theta_max / steps as f64;
        let at = changes[0];
        prop_assert!(at >= theta_b && at - step <= theta_b + 1e-15,
            "sign change between {:e} and {at:e}, expected around θB {theta_b:e}", at - step);
        let rb = fresnel(n1, n2, theta_b.cos()).r_p;
        prop_assert!(rb.norm() < 1e-14, "r_p at θB: actual {rb:e}, expected 0");
    }

    /// Beyond the critical angle |r_s| = |r_p| = 1 (P5, P6 are pure phases).
    #[test]
    fn unit_modulus_under_tir((n1, n2) in distinct_index_pair(), u in 0.0..=1.0f64) {
        let (n1, n2) = (n1.max(n2), n1.min(n2));
        let tc = (n2 / n1).asin();
        let theta = tc + (1e-9 + u * (1.0 - 1e-9)) * (FRAC_PI_2 - tc);
        let c = cos_of(if u == 1.0 { FRAC_PI_2 } else { theta });
        let f = fresnel(n1, n2, c);
        prop_assert!(f.total_internal_reflection, "TIR flag missing at θ {theta} > θc {tc}");
        for (name, r) in [("s", f.r_s), ("p", f.r_p)] {
            let err = (r.norm() - 1.0).abs();
            prop_assert!(err < 1e-14, "|r_{name}| under TIR: actual {:e}, expected 1, err {err:e}", r.norm());
        }
        let tcc = critical_angle(n1, n2).unwrap();
        prop_assert!((tcc - tc).abs() < 1e-15, "θc actual {tcc:e}, expected {tc:e}");
        prop_assert!(critical_angle(n2, n1).is_none(), "critical angle reported for n1 < n2");
    }

    /// r and t are continuous across the critical angle. Near θc, cos²θt ≈ (n1/n2)²·sin 2θc·(θ − θc),
    /// so |cos θt| ≈ κ = (n1/n2)·sqrt(sin 2θc·δ) at θc ± δ (real below, imaginary above):
    /// continuity is only √δ-smooth. To first order r_s = 1 − 2 n2 cosθt/(n1 cosθc),
    /// r_p = 1 − 2 n1 cosθt/(n2 cosθc), t_s = 1 + r_s, t_p = (2n1/n2)(1 − n1 cosθt/(n2 cosθc)),
    /// so |r(θc+δ) − r(θc−δ)| ≤ 2·(2κ)·n_other/(n_this cos θc) (|ct+ − ct−| ≤ 2κ), used with a
    /// factor 1.5 margin for second-order terms. The first-order values themselves are also
    /// checked (this pins the sign of the evanescent branch: Im r_s < 0 just above θc).
    #[test]
    fn continuity_at_the_critical_angle((n1, n2) in distinct_index_pair()) {
        let (n1, n2) = (n1.max(n2), n1.min(n2));
        let tc = (n2 / n1).asin();
        let delta = 1e-9;
        let below = fresnel(n1, n2, (tc - delta).cos());
        let above = fresnel(n1, n2, (tc + delta).cos());
        prop_assert!(!below.total_internal_reflection && above.total_internal_reflection);
        let kappa = (n1 / n2) * ((2.0 * tc).sin() * delta).sqrt();
        let cc = tc.cos();
        let bound_s = 1.5 * 4.0 * kappa * n2 / (n1 * cc) + 1e-12;
        let bound_p = 1.5 * 4.0 * kappa * n1 / (n2 * cc) + 1e-12;
        let bound_tp = 1.5 * (2.0 * n1 / n2) * 2.0 * kappa * n1 / (n2 * cc) + 1e-12;
        for (name, a, b, tol) in [
            ("r_s", below.r_s, above.r_s, bound_s),
            ("r_p", below.r_p, above.r_p, bound_p),
            ("t_s", below.t_s, above.t_s, bound_s),
            ("t_p", below.t_p, above.t_p, bound_tp),
        ] {
            let err = cdist(a, b);
            prop_assert!(err <= tol, "{name} jump across θc: below {a:e}, above {b:e}, err {err:e} > tol {tol:e}");
        }
        // First-order values on both sides (relative accuracy O(κ) + rounding √ε/κ-ish).
        let exp_below = Complex64::new(1.0 - 2.0 * n2 * kappa / (n1 * cc), 0.0);
        let exp_above = Complex64::new(1.0, -2.0 * n2 * kappa / (n1 * cc));
        let scale = 2.0 * n2 * kappa / (n1 * cc);
        for (name, a, e) in [("r_s(θc−δ)", below.r_s, exp_below), ("r_s(θc+δ)", above.r_s, exp_above)] {
            let err = cdist(a, e);
            prop_assert!(err <= 0.02 * scale, "{name}: actual {a:e}, expected (1st order) {e:e}, err {err:e} > {:e}", 0.02 * scale);
        }
    }

    /// `paper_rules` (|r|, |t| with P7/P8) equals complex Fresnel (P1–P4) wherever there is no
    /// TIR (docs/PHYSICS.md §2: "prove that with a test"). Tolerance 1e-12 × max(1, |coefficient|):
    /// at θB r_p crosses zero and the P8 angle comparison may disagree with the sign of a
    /// 1e-16-sized r_p, which an absolute floor absorbs.
    #[test]
    fn paper_rules_equal_fresnel_outside_tir((n1, n2) in index_pair(), theta in angle()) {
        let c = cos_of(theta);
        prop_assume!(!(n1 == n2 && c == 0.0));
        let f = fresnel(n1, n2, c);
        prop_assume!(!f.total_internal_reflection);
        let p = paper_rules(n1, n2, c);
        for (name, a, e) in [("r_s", p.r_s, f.r_s), ("r_p", p.r_p, f.r_p), ("t_s", p.t_s, f.t_s), ("t_p", p.t_p, f.t_p)] {
            let tol = 1e-12 * e.norm().max(1.0);
            let err = cdist(a, e);
            prop_assert!(err <= tol, "{name} paper_rules vs fresnel (n1 {n1} n2 {n2} θ {theta}): actual {a:e}, expected {e:e}, err {err:e}");
        }
        // And fresnel itself against the independent reference evaluation.
        let r = ref_fresnel(n1, n2, c);
        let tol = roundtrip_tol(n1, n2, c.max(1e-300), r.cos_t.re);
        for (name, a, e) in [("r_s", f.r_s, r.r_s), ("r_p", f.r_p, r.r_p), ("t_s", f.t_s, r.t_s), ("t_p", f.t_p, r.t_p)] {
            let err = cdist(a, e);
            prop_assert!(err <= 6.0 * tol, "{name} fresnel vs B&W reference: actual {a:e}, expected {e:e}, err {err:e}");
        }
    }

    /// Under TIR the paper's phases are the negatives of (P5)/(P6) (opposite time convention),
    /// with the same unit moduli; transmission amplitudes are untouched.
    #[test]
    fn paper_rules_tir_phases_are_negated((n1, n2) in distinct_index_pair(), u in 0.0..=1.0f64) {
        let (n1, n2) = (n1.max(n2), n1.min(n2));
        let tc = (n2 / n1).asin();
        let theta = tc + (1e-6 + u * (1.0 - 1e-6)) * (FRAC_PI_2 - tc);
        let c = cos_of(if u == 1.0 { FRAC_PI_2 } else { theta });
        let f = fresnel(n1, n2, c);
        let p = paper_rules(n1, n2, c);
        prop_assert!(f.total_internal_reflection && p.total_internal_reflection);
        for (name, a, e) in [("s", p.r_s, f.r_s), ("p", p.r_p, f.r_p)] {
            let err = wrap(a.arg() + e.arg()).abs();
            prop_assert!(err < 1e-12, "arg r_{name}: paper {:e}, expected −(fresnel {:e}), err {err:e}", a.arg(), e.arg());
            prop_assert!((a.norm() - 1.0).abs() < 1e-14, "|r_{name}| paper actual {:e}, expected 1", a.norm());
        }
    }

    /// (P5), (P6) closed forms equal arg r_s, arg r_p under TIR, and the convention-free check
    /// tan(|Δ|/2) = cos θi·sqrt(sin²θi − n21²)/sin²θi (B&W §1.5.4, eq. 60) with
    /// Δ = arg r_p − arg r_s. Rounding budget: sin²θi − n21² = (1 − n21)(1 + n21) − cos²θi carries
    /// an absolute error of a few ε, so q = sqrt(·) is off by δq = min(4ε/q, 2√ε); the phases
    /// −2 atan(q/(m cos θi)) then move by ≤ 2 δq/(m cos θi) (m = 1 or n21²), capped at 2π.
    #[test]
    fn tir_phases_match_p5_p6((n1, n2) in distinct_index_pair(), u in 0.0..=1.0f64) {
        let (n1, n2) = (n1.max(n2), n1.min(n2));
        let n21 = n2 / n1;
        let tc = n21.asin();
        let theta = tc + u * (FRAC_PI_2 - tc);
        let c = cos_of(if u == 1.0 { FRAC_PI_2 } else { theta });
        prop_assume!(fresnel(n1, n2, c).total_internal_reflection);
        let x = (1.0 - n21) * (1.0 + n21) - c * c;
        prop_assume!(x > 0.0);
        let q = x.sqrt();
        let s2 = 1.0 - c * c;
        let dq = (4.0 * EPS / q).min(2.0 * EPS.sqrt());
        let f: FresnelCoefficients = fresnel(n1, n2, c);
        let p5 = -2.0 * (q / c).atan(); // atan(+inf) = π/2 at c = 0
        let p6 = -2.0 * (q / (n21 * n21 * c)).atan();
        let tol5 = 1e-12 + if c > 0.0 { (2.0 * dq / c).min(7.0) } else { 0.0 };
        let tol6 = 1e-12 + if c > 0.0 { (2.0 * dq / (n21 * n21 * c)).min(7.0) } else { 0.0 };
        let e5 = wrap(f.r_s.arg() - p5).abs();
        let e6 = wrap(f.r_p.arg() - p6).abs();
        prop_assert!(e5 <= tol5, "arg r_s actual {:e}, expected (P5) {p5:e}, err {e5:e} > {tol5:e}", f.r_s.arg());
        prop_assert!(e6 <= tol6, "arg r_p actual {:e}, expected (P6) {p6:e}, err {e6:e} > {tol6:e}", f.r_p.arg());
        let delta = wrap(f.r_p.arg() - f.r_s.arg());
        let lhs = (delta.abs() / 2.0).tan();
        let rhs = c * q / s2;
        let err = (lhs - rhs).abs();
        let tol = 1e-12 + c * dq / s2 + (1.0 + rhs * rhs) * 0.5 * (tol5 + tol6);
        prop_assert!(err <= tol, "tan(|Δ|/2) actual {lhs:e}, expected cosθ·sqrt(sin²θ−n21²)/sin²θ = {rhs:e}, err {err:e} > {tol:e}");
    }
}

/// n1 = n2 at exactly grazing incidence (cos θi = 0): there is no interface, so r = 0 and t = 1
/// (the limit of P1–P4 as θ → π/2 with n1 = n2, where r ≡ 0 and t ≡ 1 for every θ < π/2).
/// The cosine forms are 0/0 there; the module docs promise they "stay finite … for n1 = n2".
#[test]
fn equal_indices_at_grazing_incidence_are_transparent() {
    for n in [1.0, 1.5, 3.0] {
        // Just below grazing the identity holds (checks the limit we expect).
        let near = fresnel(n, n, 1e-9);
        for (name, a, e) in [
            ("r_s", near.r_s, 0.0),
            ("r_p", near.r_p, 0.0),
            ("t_s", near.t_s, 1.0),
            ("t_p", near.t_p, 1.0),
        ] {
            let err = (a - e).norm();
            assert!(
                err < 1e-12,
                "n={n}, cos θ=1e-9, {name}: actual {a:e}, expected {e:e}, err {err:e}"
            );
        }
        let f = fresnel(n, n, 0.0);
        for (name, a, e) in [
            ("r_s", f.r_s, 0.0),
            ("r_p", f.r_p, 0.0),
            ("t_s", f.t_s, 1.0),
            ("t_p", f.t_p, 1.0),
        ] {
            let err = (a - e).norm();
            assert!(
                err < 1e-12,
                "n={n}, cos θ=0, {name}: actual {a:e}, expected {e:e}, err {err:e}"
            );
        }
        let p = f.power(n, n, 0.0);
        let sum = p.r_s + p.t_s;
        // At exact grazing no power crosses the plane (power() sets T = 0); what must not happen
        // is a NaN leaking into an accumulation.
        assert!(
            sum.is_finite(),
            "R_s + T_s at n1 = n2, grazing: actual {sum:e}, expected finite"
        );
    }
}
