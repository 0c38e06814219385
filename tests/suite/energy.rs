//! Energy conservation of the traced multi-beam sums on a lossless plate (docs/PHYSICS.md §5
//! "Energy", "Plate / film, multi-beam (Airy)").
//!
//! A plane wave (unit intensity) meets a plate of index n2 = 1.5, thickness 1 µm, between air
//! (n1 = 1) and a substrate n3 (1.0 or 1.33), at several angles including Brewster's and
//! near-grazing ones, s and p. The reflected orders [R top], [T top, R bot, (R top, R bot)^(m−1),
//! T top] and the transmitted orders [T top, (R bot, R top)^k, T bot] are traced with
//! `trace::arrivals` into the far field (`Target::Direction`, specular and transmitted
//! directions) and summed coherently (`Fidelity::Vector`) and incoherently (`Fidelity::Incoherent`).
//!
//! Expected values, derived by hand from P1–P4 with my own coefficients (`common::ref_fresnel`):
//! with ρ = r21 r23 and β = (4π/λ) n2 d cos θ2 the orders are
//! a_0 = r12, a_m = t12 t21 r23 ρ^(m−1) e^{imβ} (2m − 1 internal reflections) and
//! b_k = t12 t23 ρ^k e^{i(k+½)β} (2k internal reflections); R + T = 1 for the infinite sums
//! (Airy, B&W §7.6.1), with T = η|Σb|², η = n3 cos θ3/(n1 cos θ1).
//! Truncating at N internal reflections keeps m ≤ M_r = ⌊(N+1)/2⌋, k ≤ M_t = ⌊N/2⌋; the dropped
//! amplitudes are bounded by the geometric tails ε_r = |t12 t21 r23| |ρ|^{M_r}/(1 − |ρ|),
//! ε_t = |t12 t23| |ρ|^{M_t+1}/(1 − |ρ|), and since ||a+e|² − |a|²| ≤ |e|(2|a| + |e|) with
//! |Σa| ≤ 1, |Σb| ≤ 1/√η: |R_N + T_N − 1| ≤ ε_r(2 + ε_r) + η ε_t(2/√η + ε_t).
//! Incoherently, power bookkeeping gives exactly Σ|a_m|² + η Σ|b_k|² = 1 − P_left with
//! P_left = T12 · R23^{⌈(N+1)/2⌉} · R21^{⌊(N+1)/2⌋} (the beam still inside the plate after N
//! internal reflections: it alternately meets the bottom and the top, starting at the bottom).

use crate::common;

use common::*;
use fringe::accumulate::fidelity::Fidelity;
use fringe::optics::material::Medium;
use fringe::scene::source::{Emitter, Polarization, Source};
use fringe::scene::{Scene, SceneOptics};
use fringe::trace::path::{EnumerationLimits, Event, EventKind, Sequence, Target};
use fringe::trace::{self, Plan, TraceSettings};
use glam::DVec3;
use num_complex::Complex64;

const LAMBDA: f64 = 550e-9;
const D: f64 = 1e-6;
const N2: f64 = 1.5;

fn ev(surface: usize, kind: EventKind) -> Event {
    Event { surface, kind }
}

fn reflected_order(m: usize) -> Sequence {
    if m == 0 {
        return vec![ev(0, EventKind::Reflect)];
    }
    let mut s = vec![ev(0, EventKind::Refract), ev(1, EventKind::Reflect)];
    for _ in 1..m {
        s.push(ev(0, EventKind::Reflect));
        s.push(ev(1, EventKind::Reflect));
    }
    s.push(ev(0, EventKind::Refract));
    s
}

fn transmitted_order(k: usize) -> Sequence {
    let mut s = vec![ev(0, EventKind::Refract)];
    for _ in 0..k {
        s.push(ev(1, EventKind::Reflect));
        s.push(ev(0, EventKind::Reflect));
    }
    s.push(ev(1, EventKind::Refract));
    s
}

struct Setup {
    scene: Scene,
    optics: SceneOptics,
    refl_target: Target,
    trans_target: Target,
    n3: f64,
    cos1: f64,
    cos3: f64,
}

/// Plate with top face z = 0 (normal +z), bottom z = −1 µm; plane wave at `theta` in the xz
/// plane, polarized s (field along y) or p (in the plane of incidence).
fn setup(theta: f64, n3: f64, s_pol: bool) -> Setup {
    let mut scene = Scene::new(Medium::vacuum());
    let (top, bottom) = scene.add_plate(
        "plate",
        DVec3::ZERO,
        DVec3::Z,
        D,
        Medium::vacuum(),
        Medium::constant("glass", N2),
        Medium::constant("substrate", n3),
    );
    assert_eq!((top, bottom), (0, 1));
    let (s1, c1) = theta.sin_cos();
    let dir = DVec3::new(s1, 0.0, -c1);
    let reference = if s_pol {
        DVec3::Y
    } else {
        DVec3::new(c1, 0.0, s1)
    };
    scene.sources.push(Source {
        name: "plane wave".into(),
        emitter: Emitter::PlaneWave {
            direction: dir,
            reference_point: DVec3::new(0.0, 0.0, 1e-6),
        },
        polarization: Polarization::Linear {
            reference,
            angle_rad: 0.0,
        },
        intensity: 1.0,
        coherence_group: 0,
        coherence_length_m: f64::INFINITY,
    });
    let optics = scene.optics(LAMBDA).unwrap();
    let s3 = s1 / n3;
    let c3 = ((1.0 - s3) * (1.0 + s3)).sqrt();
    Setup {
        scene,
        optics,
        refl_target: Target::Direction {
            dir: DVec3::new(s1, 0.0, c1),
            reference: DVec3::ZERO,
        },
        trans_target: Target::Direction {
            dir: DVec3::new(s3, 0.0, -c3),
            reference: DVec3::new(0.0, 0.0, -D),
        },
        n3,
        cos1: c1,
        cos3: c3,
    }
}

/// My closed-form amplitudes for one polarization: (r12, t12, r21, t21, r23, t23, β).
struct Airy {
    r12: Complex64,
    t12: Complex64,
    r21: Complex64,
    t21: Complex64,
    r23: Complex64,
    t23: Complex64,
    beta: f64,
    eta: f64,
}

fn airy(theta: f64, n3: f64, s_pol: bool) -> Airy {
    let c1 = theta.cos();
    let f12 = ref_fresnel(1.0, N2, c1);
    let c2 = f12.cos_t.re;
    let f21 = ref_fresnel(N2, 1.0, c2);
    let f23 = ref_fresnel(N2, n3, c2);
    let c3 = f23.cos_t.re;
    let pick = |f: &RefFresnel| {
        if s_pol {
            (f.r_s, f.t_s)
        } else {
            (f.r_p, f.t_p)
        }
    };
    let (r12, t12) = pick(&f12);
    let (r21, t21) = pick(&f21);
    let (r23, t23) = pick(&f23);
    Airy {
        r12,
        t12,
        r21,
        t21,
        r23,
        t23,
        beta: 4.0 * std::f64::consts::PI / LAMBDA * N2 * D * c2,
        eta: n3 * c3 / c1,
    }
}

impl Airy {
    fn rho(&self) -> Complex64 {
        self.r21 * self.r23
    }
    fn refl_order(&self, m: usize) -> Complex64 {
        if m == 0 {
            return self.r12;
        }
        let e = Complex64::from_polar(1.0, self.beta);
        self.t12 * self.t21 * self.r23 * (self.rho() * e).powu(m as u32 - 1) * e
    }
    fn trans_order(&self, k: usize) -> Complex64 {
        let e = Complex64::from_polar(1.0, self.beta);
        self.t12
            * self.t23
            * (self.rho() * e).powu(k as u32)
            * Complex64::from_polar(1.0, 0.5 * self.beta)
    }
    /// Orders kept with at most N internal reflections.
    fn counts(n: usize) -> (usize, usize) {
        (n.div_ceil(2), n / 2)
    }
    fn tail_bound(&self, n: usize) -> f64 {
        let (mr, mt) = Self::counts(n);
        let q = self.rho().norm();
        let er = (self.t12 * self.t21 * self.r23).norm() * q.powi(mr as i32) / (1.0 - q);
        let et = (self.t12 * self.t23).norm() * q.powi(mt as i32 + 1) / (1.0 - q);
        er * (2.0 + er) + self.eta * et * (2.0 / self.eta.sqrt() + et)
    }
    /// Exact coherent partial sums (R_N, T_N).
    fn partial(&self, n: usize) -> (f64, f64) {
        let (mr, mt) = Self::counts(n);
        let r: Complex64 = (0..=mr).map(|m| self.refl_order(m)).sum();
        let t: Complex64 = (0..=mt).map(|k| self.trans_order(k)).sum();
        (r.norm_sqr(), self.eta * t.norm_sqr())
    }
    /// The closed-form Airy R and T (docs/PHYSICS.md §5).
    fn closed(&self) -> (f64, f64) {
        let e = Complex64::from_polar(1.0, self.beta);
        let den = Complex64::from(1.0) - self.rho() * e;
        let r = self.r12 + self.t12 * self.t21 * self.r23 * e / den;
        let t = self.t12 * self.t23 * Complex64::from_polar(1.0, 0.5 * self.beta) / den;
        (r.norm_sqr(), self.eta * t.norm_sqr())
    }
    /// 1 − P_left for the incoherent sum (see module docs).
    fn incoherent_expected(&self, n: usize) -> f64 {
        let t12 = 1.0 - self.r12.norm_sqr();
        let up = n.div_ceil(2); // reflections at the top from inside among the first N+1
        let down = n + 1 - up; // at the bottom
        1.0 - t12 * self.r23.norm_sqr().powi(down as i32) * self.r21.norm_sqr().powi(up as i32)
    }
}

/// Trace `seqs` to `target` and return (coherent vector intensity, incoherent intensity,
/// number of arrivals). Also checks every arrival's far-field optical path, both the solver's
/// (`SolvedPath::optical_path_m`) and the propagated ray's, against `expected_op(order)`.
fn traced(
    su: &Setup,
    seqs: Vec<Sequence>,
    target: &Target,
    expected_op: impl Fn(usize) -> f64,
) -> (f64, f64, usize) {
    let expected = seqs.len();
    let plan = Plan::from_sequences(vec![seqs.clone()]);
    let (found, failed) = trace::arrivals(
        &su.scene,
        &su.optics,
        &plan,
        target,
        &TraceSettings::default(),
    );
    assert!(
        failed.is_empty(),
        "sequences that failed: {:?}",
        failed
            .iter()
            .map(|f| (&f.sequence, &f.error))
            .collect::<Vec<_>>()
    );
    assert_eq!(found.len(), expected);
    for a in &found {
        // The plan walks sequences sorted; `seqs` lists them by order.
        let order = seqs
            .iter()
            .position(|s| a.path.sequence == *s)
            .expect("every arrival follows a listed sequence");
        let op = expected_op(order);
        for (what, got) in [
            ("solver", a.path.optical_path_m()),
            ("ray", a.vector.optical_path_m()),
        ] {
            let err = (got - op).abs();
            assert!(
                err <= 1e-12 * op.abs().max(1e-6),
                "order {order} ({what}): far-field optical path actual {got:e}, expected {op:e}, err {err:e}"
            );
        }
    }
    (
        trace::intensity(&found, Fidelity::Vector),
        trace::intensity(&found, Fidelity::Incoherent),
        found.len(),
    )
}

/// Far-field optical paths, by hand: the launch point is (0, 0, h0), h0 = 1 µm above the top face;
/// the m-th reflected order leaves the top face at x_m = h0 tan θ1 + 2 m d tan θ2 after
/// h0/cos θ1 in air and 2m·d/cos θ2 in the plate, and is referred to the wavefront through the
/// origin perpendicular to (sin θ1, 0, cos θ1): OP_m = h0/cos θ1 + 2 m n2 d/cos θ2 − sin θ1·x_m
/// (OP_m − OP_0 = 2 m n2 d cos θ2, the Airy step). The k-th transmitted order leaves the bottom
/// at x = h0 tan θ1 + (2k+1) d tan θ2, referred to the wavefront through (0, 0, −d)
/// perpendicular to (sin θ3, 0, −cos θ3): OP_k = h0/cos θ1 + (2k+1) n2 d/cos θ2 − n3 sin θ3·x
/// (n3 sin θ3 = sin θ1).
fn far_field_ops(theta: f64) -> (impl Fn(usize) -> f64, impl Fn(usize) -> f64) {
    let h0 = 1e-6;
    let (s1, c1) = theta.sin_cos();
    let s2 = s1 / N2;
    let c2 = ((1.0 - s2) * (1.0 + s2)).sqrt();
    let refl = move |m: usize| {
        let m = m as f64;
        h0 / c1 + 2.0 * m * N2 * D / c2 - s1 * (h0 * s1 / c1 + 2.0 * m * D * s2 / c2)
    };
    let trans = move |k: usize| {
        let j = 2.0 * k as f64 + 1.0;
        h0 / c1 + j * N2 * D / c2 - s1 * (h0 * s1 / c1 + j * D * s2 / c2)
    };
    (refl, trans)
}

fn traced_rt(su: &Setup, theta: f64, n: usize) -> ((f64, f64), (f64, f64)) {
    let (mr, mt) = Airy::counts(n);
    let (op_r, op_t) = far_field_ops(theta);
    let (rc, ri, _) = traced(
        su,
        (0..=mr).map(reflected_order).collect(),
        &su.refl_target,
        op_r,
    );
    let (tc, ti, _) = traced(
        su,
        (0..=mt).map(transmitted_order).collect(),
        &su.trans_target,
        op_t,
    );
    let eta = su.n3 * su.cos3 / su.cos1;
    ((rc, eta * tc), (ri, eta * ti))
}

const BREWSTER: f64 = 56.309_932_474_020_21; // atan(1.5) in degrees (see fresnel_pinned.rs)

/// Coherent sums reach R + T = 1 to 1e-12 once N is large enough that the geometric tail bound
/// is below 1e-13; they also equal the closed-form Airy R and T to 1e-12.
#[test]
fn coherent_sums_conserve_energy() {
    for n3 in [1.0, 1.33] {
        for theta_deg in [0.0, 30.0, BREWSTER, 80.0] {
            for s_pol in [true, false] {
                let theta = f64::to_radians(theta_deg);
                let a = airy(theta, n3, s_pol);
                let n = (1..400).find(|&n| a.tail_bound(n) < 1e-13).unwrap();
                let su = setup(theta, n3, s_pol);
                let ((r, t), _) = traced_rt(&su, theta, n);
                let what = format!(
                    "θ {theta_deg}°, n3 {n3}, {}, N = {n}",
                    if s_pol { "s" } else { "p" }
                );
                let err = (r + t - 1.0).abs();
                assert!(
                    err <= 1e-12,
                    "{what}: R + T actual {:e}, expected 1, err {err:e}",
                    r + t
                );
                let (ra, ta) = a.closed();
                let err = (r - ra).abs().max((t - ta).abs());
                assert!(
                    err <= 1e-12,
                    "{what}: (R, T) actual ({r:e}, {t:e}), expected Airy ({ra:e}, {ta:e}), err {err:e}"
                );
            }
        }
    }
}

/// For finite N the coherent energy deficit is bounded by the geometric tail (module docs) and
/// the traced partial sums equal the exact partial sums of the closed-form orders to 1e-12;
/// includes near-grazing 89° (slow convergence, |ρ| ≈ 0.94 for s) and Brewster (r12,p = 0).
#[test]
fn truncated_sums_are_bounded_by_the_geometric_tail() {
    for n3 in [1.0, 1.33] {
        for theta_deg in [0.0, BREWSTER, 75.0, 89.0] {
            for s_pol in [true, false] {
                let theta = f64::to_radians(theta_deg);
                let a = airy(theta, n3, s_pol);
                let su = setup(theta, n3, s_pol);
                for n in [0usize, 1, 2, 5, 12] {
                    let ((r, t), _) = traced_rt(&su, theta, n);
                    let what = format!(
                        "θ {theta_deg}°, n3 {n3}, {}, N = {n}",
                        if s_pol { "s" } else { "p" }
                    );
                    let (rp, tp) = a.partial(n);
                    let err = (r - rp).abs().max((t - tp).abs());
                    assert!(
                        err <= 1e-12,
                        "{what}: (R_N, T_N) actual ({r:e}, {t:e}), expected partial sums ({rp:e}, {tp:e}), err {err:e}"
                    );
                    let deficit = (r + t - 1.0).abs();
                    let bound = a.tail_bound(n) * (1.0 + 1e-9) + 1e-13;
                    assert!(
                        deficit <= bound,
                        "{what}: |R_N + T_N − 1| actual {deficit:e}, expected ≤ tail bound {bound:e}"
                    );
                }
            }
        }
    }
}

/// Incoherent (power) sums: Σ|a_m|² + η Σ|b_k|² = 1 − P_left exactly (module docs), to 1e-12,
/// through the `incoherent` rung of the ladder.
#[test]
fn incoherent_power_sum_is_one_minus_tail() {
    for n3 in [1.0, 1.33] {
        for theta_deg in [0.0, 30.0, BREWSTER, 89.0] {
            for s_pol in [true, false] {
                let theta = f64::to_radians(theta_deg);
                let a = airy(theta, n3, s_pol);
                let su = setup(theta, n3, s_pol);
                for n in [0usize, 1, 2, 3, 8, 15] {
                    let (_, (ri, ti)) = traced_rt(&su, theta, n);
                    let expected = a.incoherent_expected(n);
                    let err = (ri + ti - expected).abs();
                    assert!(
                        err <= 1e-12,
                        "θ {theta_deg}°, n3 {n3}, {}, N = {n}: Σ R_m + Σ T_k actual {:e}, expected 1 − P_left {expected:e}, err {err:e}",
                        if s_pol { "s" } else { "p" },
                        ri + ti
                    );
                }
            }
        }
    }
}

/// `trace::plan` with `EnumerationLimits { max_internal_reflections: N, .. }` discovers every
/// order that the hand-built list contains: the sequences that reach the specular and the
/// transmitted directions are exactly the reflected orders m ≤ ⌊(N+1)/2⌋ and transmitted k ≤ ⌊N/2⌋.
#[test]
fn plan_discovers_every_order() {
    let theta = 30f64.to_radians();
    for n in [1usize, 4, 7] {
        let su = setup(theta, 1.33, true);
        let limits = EnumerationLimits {
            max_internal_reflections: n,
            max_events: 64,
        };
        let plan = trace::plan(
            &su.scene,
            &su.optics,
            &[DVec3::ZERO, DVec3::new(1e-5, 0.0, 0.0)],
            &limits,
        );
        let settings = TraceSettings {
            limits,
            ..TraceSettings::default()
        };
        let (mr, mt) = Airy::counts(n);
        for (target, want) in [
            (
                &su.refl_target,
                (0..=mr).map(reflected_order).collect::<Vec<_>>(),
            ),
            (
                &su.trans_target,
                (0..=mt).map(transmitted_order).collect::<Vec<_>>(),
            ),
        ] {
            let (found, _) = trace::arrivals(&su.scene, &su.optics, &plan, target, &settings);
            let mut got: Vec<Sequence> = found.iter().map(|a| a.path.sequence.to_vec()).collect();
            got.sort();
            let mut want = want;
            want.sort();
            assert_eq!(got, want, "N = {n}: sequences reaching {target:?}");
        }
    }
}
