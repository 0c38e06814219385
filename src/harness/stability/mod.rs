//! The stability sweep (robustness, issue #6): the tracer at the numerical extremes that
//! `tests/suite/stability.rs` asserts, each traced value next to a closed form evaluated independently
//! of the tracer, with its deviation, tolerance and verdict; and the optical-path sweep from
//! 1 nm to 10 m, which also shows what single-precision (binary32) absolute phases would cost.
//!
//! # What is traced, and against what
//!
//! Everything traced goes through the library's tracer as a user's scene does
//! ([`trace::plan`], [`trace::arrivals`], `vector` fidelity), built like the tests build it:
//!
//! * **incidence**, **critical angle**, **indices**: a plane wave on one unbounded interface,
//!   observed in the far field of the reflection. The amplitude r = (E_r·e_r)/(E_i·e_i) is read
//!   from the traced 3D field in the s/p frame of docs/PHYSICS.md §1 (e = s, or p_i = d_i × s and
//!   p_r = d_r × s). Closed forms are *not* the cosine forms (P1)–(P4) the tracer evaluates:
//!   the sine and tangent forms −sin(θi−θt)/sin(θi+θt), tan(θi−θt)/tan(θi+θt) where they are well
//!   conditioned, first-order expansions at Brewster's angle and for n2 − n1 = 1e-12, and the
//!   half-angle retardance tan(|Δ|/2) = cos θ·sqrt(sin²θ − n21²)/sin²θ under total internal
//!   reflection (with sin²θ − n21² = sin(θ−θc)·sin(θ+θc), free of cancellation).
//! * **films**: the far-field reflectance of a film (1 pm to 1 mm, at 0, 1 rad and 89.9°) summed
//!   bounce by bounce by the tracer, with bounce counts from the Airy tail bound (< 1e-15),
//!   against the Airy sum of [`Film`] (the same Fresnel kernels, an independent summation) at
//!   1e-12 relative plus the conditioning of R on f64 inputs ([`film_tolerance`]); the same film
//!   with the wave's phase referred to a point 100 m away (a global phase); and R(1 pm) − R(bare
//!   interface) against the Airy difference (the film does not vanish as d → 0).
//! * **finesse**: the traced sum truncated after N reflected orders against the closed-form
//!   truncated sum (`Film::r_truncated`) at 1e-12, the geometric tail bound checked for honesty
//!   on the closed forms, and the full sum against Airy.
//! * **random films**: seeded pseudo-random valid films, every number finite and R + T = 1.
//! * **paths**: two coherent point sources on one line with a point beyond them, as in the
//!   tests: the exact path difference is the source offset Δs itself (collinear), so the exact
//!   two-beam phase is 2πΔs/λ. fringe carries optical paths in double-double and forms their
//!   difference before rounding ([`trace::contribution_from`]): the phase is the exact one to
//!   1e-12 rad from 1 nm to 10 m.
//!
//! Every judged row can fail: [`sweep_with`]`(`[`PathArithmetic::AbsoluteF64`]`)` holds the
//! traced paths as a naive tracer would (absolute, rounded to f64) and fails the path rows from
//! ~1 mm on and the 100 m reference row (a test keeps it so).
//!
//! Near a singular angle the offset "1e-12 rad" is itself known only to the rounding of the
//! angle (~1e-16 rad, 1e-4 of the offset) in the tracer and in the closed form alike, so
//! quantities that vanish there are compared relative to their size with tolerance 1e-3.
//!
//! # The single-precision illustration
//!
//! For the same path lengths the sweep evaluates, without tracing, the phase a program would get
//! if it formed phases from absolute optical paths (φ_k = 2π s_k/λ per beam, then φ2 − φ1): with
//! the paths stored in f64, and with the paths stored in IEEE binary32. The binary32 store is
//! emulated on f64 bits by [`round_to_binary32`] (no single-precision type is used); the phases
//! are then formed in f64, so the curve shows the cost of the storage alone. Storing a path of
//! 1 m moves it by up to half a binary32 spacing (the spacing is 6e-8 m just below 1 m and
//! 1.2e-7 m just above), up to 6e-8 m or 0.7 rad of phase at 550 nm; forming the phases
//! (1.1e7 rad at 1 m) in binary32 too would add a rounding of up to 0.5 rad (their spacing is
//! 1 rad). Errors are not reduced modulo 2π: beyond π the fringe
//! can be anywhere. In f64 both ways of forming the phase err by ~1e-9 rad at 1 m (the spacing
//! of f64 at 1 m, 2.2e-16 m, is 2.5e-9 rad); fringe's double-double paths, differenced before
//! rounding, keep the phase within 1e-12 rad up to 10 m. This
//! illustration is reported for information; only fringe's own method is judged.
//!
//! # When it runs
//!
//! `fringe check` runs the sweep on every run, with or without CASE arguments (it takes well
//! under a second and checks the tracer itself, which every case relies on), and writes
//! `stability.csv`, `stability_paths.png` and the `stability` section of `index.html`.

use crate::accumulate::fidelity::Fidelity;
use crate::harness::analytic::plate::{Film, Pol};
use crate::harness::analytic::tir;
use crate::optics::double_double::DoubleDouble;
use crate::optics::fresnel::{self, brewster_angle, critical_angle};
use crate::optics::material::Medium;
use crate::scene::Scene;
use crate::scene::source::{Emitter, Polarization, Source};
use crate::trace::path::{EnumerationLimits, Event, EventKind, Target};
use crate::trace::{self, TraceSettings};
use glam::DVec3;
use num_complex::Complex64;
use serde::{Deserialize, Serialize};
use std::f64::consts::{FRAC_PI_2, TAU};

/// Vacuum wavelength of the whole sweep (m).
pub const WAVELENGTH_M: f64 = 550e-9;

/// The bound on fringe's two-beam phase error from 1 nm to 10 m (rad): optical paths held in
/// double-double keep the exact path difference of the collinear sources to ~1e-30 m, so the
/// phase is the exact one rounded once; absolute paths rounded to f64 err by ~1e-9 rad at 1 m
/// and fail this bound from about 1 mm on ([`PathArithmetic::AbsoluteF64`]).
pub const PATH_PHASE_TOLERANCE_RAD: f64 = 1e-12;

/// The bound on the relative deviation of a traced film reflectance from the Airy sum (and of a
/// truncated traced sum from the truncated closed form): issue #13's 1e-12.
pub const FILM_TOLERANCE: f64 = 1e-12;

/// The relative deviation of a traced film reflectance from the Airy sum that the f64 inputs
/// allow: [`FILM_TOLERANCE`] plus the conditioning of R on its inputs. The round-trip phase
/// β = 4π n2 d cos θ2/λ of a scene given in f64 (direction components, indices, thickness) is
/// itself known only to a few ε·β, and the tracer carries phases in f64 cycles of the same
/// relative rounding, which moves R by |∂R/∂β|·β·ε = |d ∂R/∂d|·ε; 16ε bounds the few roundings.
/// Negligible for thin films, it matters for a 1 mm film near a minimum of R (β ~ 3e4 rad:
/// ~1e-11 of R). ∂R/∂d by a central difference of the Airy sum.
pub fn film_tolerance(film: &Film, cos_theta: f64, lambda_m: f64, pol: Pol) -> f64 {
    let r = film.reflectance(cos_theta, lambda_m, pol);
    let h = 1e-6;
    let at = |s: f64| {
        Film {
            thickness_m: film.thickness_m * s,
            ..*film
        }
        .reflectance(cos_theta, lambda_m, pol)
    };
    let d_dr_dd = (at(1.0 + h) - at(1.0 - h)) / (2.0 * h);
    FILM_TOLERANCE + 16.0 * f64::EPSILON * d_dr_dd.abs() / r
}

/// How the sweep holds the traced optical paths before phases are formed.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum PathArithmetic {
    /// fringe's: paths in double-double, differences formed before rounding.
    DoubleDouble,
    /// A deliberately naive build: every traced optical path rounded to f64 (absolute, from the
    /// source or the wave's reference) before phases are formed, as a tracer that stores
    /// absolute paths in f64 does. The sweep must fail it (a test keeps that true).
    AbsoluteF64,
}

/// The arrivals as `arithmetic` holds them (rounded to absolute f64 paths for the naive build).
fn hold(mut arr: Vec<trace::Arrival>, arithmetic: PathArithmetic) -> Vec<trace::Arrival> {
    if arithmetic == PathArithmetic::AbsoluteF64 {
        let round = |r: &mut crate::optics::ray::Ray| {
            r.optical_path = DoubleDouble::from(r.optical_path_m());
        };
        for a in &mut arr {
            round(&mut a.vector);
            if let Some(p) = &mut a.paper {
                round(p);
            }
        }
    }
    arr
}

/// Path differences per path length in the path sweep (the worst one is reported).
pub const PATH_OFFSETS: usize = 8;

/// How a row's deviation is measured.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum DeviationKind {
    /// |traced − closed form|.
    Absolute,
    /// |traced − closed form| / |closed form|.
    Relative,
}

impl DeviationKind {
    pub fn name(self) -> &'static str {
        match self {
            DeviationKind::Absolute => "absolute",
            DeviationKind::Relative => "relative",
        }
    }
}

/// One line of the stability table.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct StabilityRow {
    /// The family of extremes (incidence, critical angle, indices, films, finesse, random films,
    /// paths, or the precision illustration).
    pub group: String,
    /// The condition, human-readable (e.g. "θ = θB + 1e-12 rad, p").
    pub condition: String,
    /// What is compared, with its unit.
    pub quantity: String,
    /// The traced value (for the illustration rows: the value the named method computes).
    pub traced: f64,
    /// The closed-form (exact) value.
    pub closed_form: f64,
    /// |traced − closed form|, absolute or relative as `deviation_kind` says.
    pub deviation: f64,
    pub deviation_kind: DeviationKind,
    /// `None`: an illustration row, reported without a verdict.
    pub tolerance: Option<f64>,
    /// `None` for illustration rows; `Some(false)` also when any number is not finite.
    pub pass: Option<bool>,
}

impl StabilityRow {
    fn new(
        group: &str,
        condition: String,
        quantity: &str,
        traced: f64,
        closed_form: f64,
        kind: DeviationKind,
        tolerance: Option<f64>,
    ) -> Self {
        let diff = (traced - closed_form).abs();
        let deviation = match kind {
            DeviationKind::Absolute => diff,
            DeviationKind::Relative => diff / closed_form.abs(),
        };
        // NaN compares false with every tolerance: a non-finite number fails explicitly.
        let finite = traced.is_finite() && closed_form.is_finite() && deviation.is_finite();
        StabilityRow {
            group: group.into(),
            condition,
            quantity: quantity.into(),
            traced,
            closed_form,
            deviation,
            deviation_kind: kind,
            tolerance,
            pass: tolerance.map(|t| finite && deviation <= t),
        }
    }
}

/// The phase errors of one path length (worst over [`PATH_OFFSETS`] path differences).
#[derive(Clone, Copy, Debug, PartialEq, Serialize)]
pub struct PathPoint {
    /// Optical path of the nearer beam, s (m).
    pub path_m: f64,
    /// fringe: traced paths, differenced in double-double, then 2πΔs/λ (rad).
    pub fringe_rad: f64,
    /// Phases from absolute f64 paths, 2πs2/λ − 2πs1/λ (rad).
    pub f64_absolute_rad: f64,
    /// Phases from absolute paths stored in binary32 (rad).
    pub binary32_absolute_rad: f64,
    /// The worst case of each method: (computed two-beam phase, exact phase) in rad.
    pub fringe_worst: (f64, f64),
    pub f64_absolute_worst: (f64, f64),
    pub binary32_absolute_worst: (f64, f64),
}

/// The whole sweep.
#[derive(Clone, Debug, PartialEq)]
pub struct Sweep {
    pub rows: Vec<StabilityRow>,
    /// The path sweep on the plot's grid (1, 2, 5 per decade from 1 nm to 10 m).
    pub paths: Vec<PathPoint>,
    pub seconds: f64,
}

impl Sweep {
    /// The judged rows that fail.
    pub fn failures(&self) -> impl Iterator<Item = &StabilityRow> {
        self.rows.iter().filter(|r| r.pass == Some(false))
    }
}

/// Round an f64 to the nearest IEEE 754 binary32 value (round to nearest, ties to even), on f64
/// bits: the significand is rounded to 24 bits (to the fixed spacing 2^-149 below 2^-126, where
/// binary32 is subnormal), and magnitudes that round to 2^128 or beyond become infinite. NaN and
/// infinities pass through.
///
/// Rounding an exactly computed f64 value to 24 bits is what storing it in binary32 does.
/// Moreover, for +, −, ×, ÷ of two binary32 values, the f64 result rounded here is exactly the
/// binary32 result (53 ≥ 2·24 + 2: double rounding is innocuous; Figueroa, "When is double
/// rounding innocuous?", SIGNUM Newsl. 30(3), 1995).
///
/// Method: with e = ⌊log2 |x|⌋ (from the exponent bits; at least −126), the spacing of binary32
/// values near x is q = 2^(e−23); x/q and the product by q are exact power-of-two scalings, so
/// `(x/q).round_ties_even()·q` is the correctly rounded value (a carry to 2^(e+1) included).
pub fn round_to_binary32(x: f64) -> f64 {
    if !x.is_finite() || x == 0.0 {
        return x;
    }
    let biased = ((x.to_bits() >> 52) & 0x7ff) as i32;
    // f64 subnormals (biased 0) are far below binary32's smallest subnormal: e = −126 suffices.
    let e = (biased - 1023).max(-126);
    let q = f64::from_bits(((e - 23 + 1023) as u64) << 52);
    let r = (x / q).round_ties_even() * q;
    if r.abs() >= 2f64.powi(128) {
        f64::INFINITY.copysign(x)
    } else {
        r
    }
}

/// The path lengths of the plot: 1, 2, 5 per decade from 1 nm to 10 m.
pub fn path_grid() -> Vec<f64> {
    let mut g = Vec::new();
    for e in -9..=0 {
        for m in [1.0, 2.0, 5.0] {
            g.push(m * 10f64.powi(e));
        }
    }
    g.push(10.0);
    g
}

/// The path differences Δs_j = 1e-7·max(s, 1 µm)·(1 + j/K), j < K (the offsets of the tests,
/// spread over a factor 2 so the rounding of s + Δs samples a whole spacing of binary32).
fn path_offsets(path_m: f64) -> Vec<f64> {
    let base = 1e-7 * path_m.max(1e-6);
    (0..PATH_OFFSETS)
        .map(|j| base * (1.0 + j as f64 / PATH_OFFSETS as f64))
        .collect()
}

/// Two coherent, linearly polarized unit point sources in vacuum on the x axis, at 0 and at
/// −`offset_m`: at a point (s, 0, 0) their optical paths differ by exactly `offset_m`.
pub fn collinear_sources(offset_m: f64) -> Scene {
    let mut scene = Scene::new(Medium::vacuum());
    for (k, x) in [0.0, offset_m].into_iter().enumerate() {
        scene.sources.push(Source {
            name: format!("s{k}"),
            emitter: Emitter::Point {
                position: DVec3::new(-x, 0.0, 0.0),
            },
            polarization: Polarization::Linear {
                reference: DVec3::Z,
                angle_rad: 0.0,
            },
            intensity: 1.0,
            coherence_group: 0,
            coherence_length_m: f64::INFINITY,
        });
    }
    scene
}

/// fringe's traced path difference for [`collinear_sources`] at the point (s, 0, 0): the exact
/// difference is Δs (collinear). Formed in double-double, rounded once; with
/// [`PathArithmetic::AbsoluteF64`] from the two paths rounded to f64 first.
fn traced_path_difference(path_m: f64, offset_m: f64, arithmetic: PathArithmetic) -> f64 {
    let scene = collinear_sources(offset_m);
    let p = DVec3::new(path_m, 0.0, 0.0);
    let Ok(optics) = scene.optics(WAVELENGTH_M) else {
        return f64::NAN;
    };
    let limits = EnumerationLimits::default();
    let plan = trace::plan(&scene, &optics, &[p], &limits);
    let (arr, _) = trace::arrivals(
        &scene,
        &optics,
        &plan,
        &Target::Point(p),
        &TraceSettings::default(),
    );
    let arr = hold(arr, arithmetic);
    let path_of = |source: usize| {
        arr.iter()
            .find(|a| a.source == source)
            .map(|a| a.vector.optical_path)
    };
    match (path_of(1), path_of(0)) {
        (Some(a), Some(b)) => (a - b).to_f64(),
        _ => f64::NAN,
    }
}

/// Two-beam phase from absolute paths: each path as `store` keeps it, φ_k = (2π/λ)·s_k in f64,
/// then φ2 − φ1. The second path is s + Δs as an f64 program computes it.
fn absolute_phase_difference(path_m: f64, offset_m: f64, store: impl Fn(f64) -> f64) -> f64 {
    let k = TAU / WAVELENGTH_M;
    let s1 = store(path_m);
    let s2 = store(path_m + offset_m);
    k * s2 - k * s1
}

/// The three methods' phase errors at each path length (worst over [`PATH_OFFSETS`]). The exact
/// phase 2πΔs/λ is rounded once (relative 1e-16), orders of magnitude below every error shown.
pub fn path_points(paths_m: &[f64]) -> Vec<PathPoint> {
    path_points_with(paths_m, PathArithmetic::DoubleDouble)
}

/// [`path_points`] with the traced paths held as `arithmetic` says.
pub fn path_points_with(paths_m: &[f64], arithmetic: PathArithmetic) -> Vec<PathPoint> {
    paths_m
        .iter()
        .map(|&s| {
            let mut worst = [(f64::NEG_INFINITY, 0.0, 0.0); 3];
            for ds in path_offsets(s) {
                let exact = TAU * ds / WAVELENGTH_M;
                let traced = traced_path_difference(s, ds, arithmetic);
                // Differences in metres first: |Δs_traced − Δs| is exact for nearby values.
                let fringe_err = TAU * (traced - ds).abs() / WAVELENGTH_M;
                let fringe_phase = TAU * traced / WAVELENGTH_M;
                let f64_phase = absolute_phase_difference(s, ds, |x| x);
                let b32_phase = absolute_phase_difference(s, ds, round_to_binary32);
                let errs = [
                    (fringe_err, fringe_phase),
                    ((f64_phase - exact).abs(), f64_phase),
                    ((b32_phase - exact).abs(), b32_phase),
                ];
                for (w, (err, phase)) in worst.iter_mut().zip(errs) {
                    // NaN is the worst value and stays.
                    if !w.0.is_nan() && (err.is_nan() || err > w.0) {
                        *w = (err, phase, exact);
                    }
                }
            }
            PathPoint {
                path_m: s,
                fringe_rad: worst[0].0,
                f64_absolute_rad: worst[1].0,
                binary32_absolute_rad: worst[2].0,
                fringe_worst: (worst[0].1, worst[0].2),
                f64_absolute_worst: (worst[1].1, worst[1].2),
                binary32_absolute_worst: (worst[2].1, worst[2].2),
            }
        })
        .collect()
}

/// s or p input, as a source polarization angle about the reference Y (docs/PHYSICS.md §1: for the
/// plane of incidence xz, s ∥ Y and p = d × s).
fn pol_angle(pol: Pol) -> f64 {
    match pol {
        Pol::S => 0.0,
        Pol::P => FRAC_PI_2,
    }
}

/// The plane wave of the sweep at `theta` in the xz plane, phase referred to `reference`.
fn plane_wave_at(theta: f64, angle_rad: f64, reference: DVec3) -> Source {
    Source {
        name: "beam".into(),
        emitter: Emitter::PlaneWave {
            direction: DVec3::new(theta.sin(), 0.0, -theta.cos()),
            reference_point: reference,
        },
        polarization: Polarization::Linear {
            reference: DVec3::Y,
            angle_rad,
        },
        intensity: 1.0,
        coherence_group: 0,
        coherence_length_m: f64::INFINITY,
    }
}

/// [`plane_wave_at`] with the reference 1 mm above the interface.
fn plane_wave(theta: f64, angle_rad: f64) -> Source {
    plane_wave_at(theta, angle_rad, DEFAULT_REFERENCE)
}

/// The sweep's default phase reference of a plane wave: 1 mm above the film.
const DEFAULT_REFERENCE: DVec3 = DVec3::new(0.0, 0.0, 1e-3);

/// The traced reflection amplitude r_s or r_p of one unbounded interface n1 | n2 (the plane
/// z = 0, n1 above) for a plane wave at angle θ, read from the traced 3D field in the frame of
/// docs/PHYSICS.md §1. NaN if the tracer finds no reflected ray.
fn traced_r(n1: f64, n2: f64, theta: f64, pol: Pol) -> Complex64 {
    let nan = Complex64::new(f64::NAN, f64::NAN);
    let mut scene = Scene::new(Medium::constant("n1", n1));
    scene.add_interface(
        "interface",
        crate::scene::geometry::Plane::new(DVec3::ZERO, DVec3::Z),
        Medium::constant("n1", n1),
        Medium::constant("n2", n2),
    );
    let source = plane_wave(theta, pol_angle(pol));
    let d_i = match source.emitter {
        Emitter::PlaneWave { direction, .. } => direction.normalize(),
        _ => return nan,
    };
    let e_i = source.channels()[0].field_direction(d_i);
    scene.sources.push(source);
    let Ok(optics) = scene.optics(WAVELENGTH_M) else {
        return nan;
    };
    let d_r = fresnel::reflect(d_i, DVec3::Z);
    let reference = DVec3::new(0.0, 0.0, 1e-3);
    let target = Target::Direction {
        dir: d_r,
        reference,
    };
    let limits = EnumerationLimits {
        max_internal_reflections: 0,
        max_events: 1,
    };
    let plan = trace::plan(&scene, &optics, &[reference], &limits);
    let (arr, _) = trace::arrivals(&scene, &optics, &plan, &target, &TraceSettings::default());
    let reflect = [Event {
        surface: 0,
        kind: EventKind::Reflect,
    }];
    let Some(a) = arr.iter().find(|a| a.path.sequence == reflect[..]) else {
        return nan;
    };
    let s = fresnel::s_direction(d_i, DVec3::Z, DVec3::Y);
    let (e_in, e_out) = match pol {
        Pol::S => (s, s),
        Pol::P => (d_i.cross(s), a.vector.dir.cross(s)),
    };
    let field = a.vector.field();
    let along = |v: DVec3| field[0] * v.x + field[1] * v.y + field[2] * v.z;
    along(e_out) / e_i.dot(e_in)
}

/// θt from Snell's law (outside total internal reflection).
fn theta_t(n1: f64, n2: f64, theta: f64) -> f64 {
    (n1 / n2 * theta.sin()).asin()
}

/// r_s by the sine form −sin(θi − θt)/sin(θi + θt) (B&W §1.5.2), independent of (P1).
fn r_s_sine(n1: f64, n2: f64, theta: f64) -> f64 {
    let t = theta_t(n1, n2, theta);
    -(theta - t).sin() / (theta + t).sin()
}

/// r_p by the tangent form tan(θi − θt)/tan(θi + θt) (B&W §1.5.2), independent of (P2).
fn r_p_tangent(n1: f64, n2: f64, theta: f64) -> f64 {
    let t = theta_t(n1, n2, theta);
    (theta - t).tan() / (theta + t).tan()
}

/// The far-field reflectance (or transmittance) of a film n1 | n2 (thickness d, m) | n3 lit by
/// a plane wave at `theta` (rad) of vacuum wavelength `lambda_m`, traced at `vector` fidelity
/// with `internal` internal reflections, for linear polarization at `pol_angle` (rad) from s;
/// NaN when the scene has no optics at `lambda_m` or the transmitted direction does not exist.
pub fn traced_film(
    n: [f64; 3],
    d: f64,
    theta: f64,
    lambda_m: f64,
    pol_angle: f64,
    internal: usize,
    reflected: bool,
) -> f64 {
    traced_film_with(
        n,
        d,
        theta,
        (lambda_m, pol_angle),
        internal,
        reflected,
        DEFAULT_REFERENCE,
        PathArithmetic::DoubleDouble,
    )
}

/// [`traced_film`] with the plane wave's phase (and far-field wavefront) referred to
/// `reference` and the traced paths held as `arithmetic` says; `(λ, polarization angle)`.
#[allow(clippy::too_many_arguments)]
pub fn traced_film_with(
    n: [f64; 3],
    d: f64,
    theta: f64,
    (lambda_m, pol_angle): (f64, f64),
    internal: usize,
    reflected: bool,
    reference: DVec3,
    arithmetic: PathArithmetic,
) -> f64 {
    let mut scene = Scene::new(Medium::constant("n1", n[0]));
    scene.add_plate(
        "film",
        DVec3::ZERO,
        DVec3::Z,
        d,
        Medium::constant("n1", n[0]),
        Medium::constant("n2", n[1]),
        Medium::constant("n3", n[2]),
    );
    scene
        .sources
        .push(plane_wave_at(theta, pol_angle, reference));
    let Ok(optics) = scene.optics(lambda_m) else {
        return f64::NAN;
    };
    let d_in = DVec3::new(theta.sin(), 0.0, -theta.cos());
    let dir = if reflected {
        DVec3::new(theta.sin(), 0.0, theta.cos())
    } else {
        match fresnel::refract(d_in, DVec3::Z, n[0], n[2]) {
            Some(d) => d,
            None => return f64::NAN,
        }
    };
    let target = Target::Direction { dir, reference };
    let limits = EnumerationLimits {
        max_internal_reflections: internal,
        max_events: 2 * internal + 4,
    };
    let plan = trace::plan(&scene, &optics, &[reference], &limits);
    let st = TraceSettings {
        limits,
        ..Default::default()
    };
    let (arr, _) = trace::arrivals(&scene, &optics, &plan, &target, &st);
    let i = trace::intensity(&hold(arr, arithmetic), Fidelity::Vector);
    if reflected {
        i
    } else {
        // Far-field |E|² of the transmitted plane wave → power ratio (n3 cos θ3)/(n1 cos θ1).
        i * n[2] * dir.z.abs() / (n[0] * theta.cos())
    }
}

/// θ in a condition: degrees with enough digits.
fn deg(theta: f64) -> String {
    format!("{:.4}°", theta.to_degrees())
}

fn pol_name(pol: Pol) -> &'static str {
    match pol {
        Pol::S => "s",
        Pol::P => "p",
    }
}

/// Normal, 1e-12 rad, Brewster ± 1e-12, 89.9999° and exactly grazing, air → glass 1.5.
fn incidence_rows(rows: &mut Vec<StabilityRow>) {
    use DeviationKind::*;
    let g = "incidence";
    let (n1, n2) = (1.0, 1.5);
    let r0 = (n1 - n2) / (n1 + n2);
    // Normal and near-normal incidence: r_s = (n1 − n2)/(n1 + n2), r_p = −r_s in this frame
    // (P1, P2 at θ = 0; the O(θ²) terms are 1e-24 at 1e-12 rad).
    for (theta, label) in [(0.0, "θ = 0"), (1e-12, "θ = 1e-12 rad")] {
        for (pol, exact) in [(Pol::S, r0), (Pol::P, -r0)] {
            rows.push(StabilityRow::new(
                g,
                format!("{label}, {}, n 1 → 1.5", pol_name(pol)),
                &format!("r_{} (real)", pol_name(pol)),
                traced_r(n1, n2, theta, pol).re,
                exact,
                Absolute,
                Some(1e-14),
            ));
        }
    }
    // Brewster ± 1e-12: first order in ε = θ − θB, r_p = −(n⁴ − 1)/(2n³)·ε (n = n2/n1): from
    // the tangent form, tan(θ + θt) ≈ −1/((1 + 1/n²)ε) and tan(θB − θtB) = (n² − 1)/(2n).
    // ε is formed from the f64 angles (exact subtraction); its O(ε²) remainder is 1e-24.
    let tb = brewster_angle(n1, n2);
    let n = n2 / n1;
    for (theta, label) in [(tb - 1e-12, "θB − 1e-12"), (tb + 1e-12, "θB + 1e-12")] {
        let eps = theta - tb;
        rows.push(StabilityRow::new(
            g,
            format!("θ = {label} rad, p, n 1 → 1.5"),
            "r_p (real)",
            traced_r(n1, n2, theta, Pol::P).re,
            -(n.powi(4) - 1.0) / (2.0 * n.powi(3)) * eps,
            Relative,
            Some(1e-3),
        ));
    }
    // 89.9999°: sine and tangent forms, well conditioned there.
    let theta = 89.9999f64.to_radians();
    rows.push(StabilityRow::new(
        g,
        format!("θ = {}, s, n 1 → 1.5", deg(theta)),
        "r_s (real)",
        traced_r(n1, n2, theta, Pol::S).re,
        r_s_sine(n1, n2, theta),
        Absolute,
        Some(1e-14),
    ));
    rows.push(StabilityRow::new(
        g,
        format!("θ = {}, p, n 1 → 1.5", deg(theta)),
        "r_p (real)",
        traced_r(n1, n2, theta, Pol::P).re,
        r_p_tangent(n1, n2, theta),
        Absolute,
        Some(1e-14),
    ));
    // Exactly grazing: no ray meets a plane at 90°, so the Fresnel kernel the tracer calls is
    // evaluated directly; the limit of (P1), (P2) is r_s = r_p = −1 (all light reflected).
    let f = fresnel::fresnel(n1, n2, 0.0);
    for (pol, r) in [(Pol::S, f.r_s), (Pol::P, f.r_p)] {
        rows.push(StabilityRow::new(
            g,
            format!(
                "θ = 90° exactly, {} (Fresnel kernel: no ray meets the plane)",
                pol_name(pol)
            ),
            &format!("r_{} (real)", pol_name(pol)),
            r.re,
            -1.0,
            Absolute,
            Some(0.0),
        ));
    }
}

/// Glass 1.5 → air at θc ± 1e-12, the Fresnel rhomb angle and 89.9999°.
fn critical_rows(rows: &mut Vec<StabilityRow>) {
    use DeviationKind::*;
    let g = "critical angle";
    let (n1, n2) = (1.5, 1.0);
    let Some(tc) = critical_angle(n1, n2) else {
        return;
    };
    // Just below θc: 1 − r_s = 2 n2 cos θt/(n1 cos θ + n2 cos θt) (from the cosine form, but with
    // cos θt = (n1/n2)·sqrt(sin(θc − θ)·sin(θc + θ)) in place of Snell's cancelling difference).
    let theta = tc - 1e-12;
    let cos_t = n1 / n2 * ((tc - theta).sin() * (tc + theta).sin()).sqrt();
    let one_minus = 2.0 * n2 * cos_t / (n1 * theta.cos() + n2 * cos_t);
    rows.push(StabilityRow::new(
        g,
        "θ = θc − 1e-12 rad, s, n 1.5 → 1".into(),
        "1 − r_s",
        1.0 - traced_r(n1, n2, theta, Pol::S).re,
        one_minus,
        Relative,
        Some(1e-3),
    ));
    // Total internal reflection: |r| = 1 and the retardance |Δ| = |arg r_p − arg r_s| from
    // tan(|Δ|/2) = cos θ·sqrt(sin²θ − n21²)/sin²θ (docs/PHYSICS.md §1).
    let retardance = |theta: f64| {
        let s2 = theta.sin().powi(2);
        let root = ((theta - tc).sin() * (theta + tc).sin()).sqrt();
        2.0 * (theta.cos() * root / s2).atan()
    };
    let rhomb = 54.6f64.to_radians();
    for (theta, label, tol) in [
        (tc + 1e-12, "θ = θc + 1e-12 rad".to_string(), 1e-3),
        (rhomb, format!("θ = {} (Fresnel rhomb)", deg(rhomb)), 1e-12),
        (
            89.9999f64.to_radians(),
            format!("θ = {}", deg(89.9999f64.to_radians())),
            1e-9,
        ),
    ] {
        let rs = traced_r(n1, n2, theta, Pol::S);
        let rp = traced_r(n1, n2, theta, Pol::P);
        for (pol, r) in [(Pol::S, rs), (Pol::P, rp)] {
            rows.push(StabilityRow::new(
                g,
                format!("{label}, {}, TIR n 1.5 → 1", pol_name(pol)),
                &format!("|r_{}|", pol_name(pol)),
                r.norm(),
                1.0,
                Absolute,
                Some(1e-14),
            ));
        }
        // At the rhomb angle the closed form is analytic::tir's half-angle formula.
        let exact = if theta == rhomb {
            tir::retardance_magnitude(n1, n2, theta)
        } else {
            retardance(theta)
        };
        rows.push(StabilityRow::new(
            g,
            format!("{label}, TIR n 1.5 → 1"),
            "retardance |arg r_p − arg r_s| (rad)",
            (rp * rs.conj()).arg().abs(),
            exact,
            Relative,
            Some(tol),
        ));
    }
}

/// n1 = n2, n2 − n1 = 1e-12, and n = 4.
fn index_rows(rows: &mut Vec<StabilityRow>) {
    use DeviationKind::*;
    let g = "indices";
    // No interface: r = 0 at every angle.
    for theta in [0.0, 60f64.to_radians()] {
        for pol in [Pol::S, Pol::P] {
            rows.push(StabilityRow::new(
                g,
                format!("n1 = n2 = 1.5, θ = {}, {}", deg(theta), pol_name(pol)),
                &format!("r_{} (real)", pol_name(pol)),
                traced_r(1.5, 1.5, theta, pol).re,
                0.0,
                Absolute,
                Some(1e-14),
            ));
        }
    }
    // n2 − n1 = 1e-12: r_s = −Δn/(2n + Δn) exactly at θ = 0 (P1), −Δn/(2 n cos²θ) to first order
    // at 60° (derivative of the sine form with Snell); Δn is the exact f64 difference.
    let n1 = 1.5;
    let n2 = n1 + 1e-12;
    let dn = n2 - n1;
    let c60 = 60f64.to_radians().cos();
    for (theta, exact) in [
        (0.0, -dn / (2.0 * n1 + dn)),
        (60f64.to_radians(), -dn / (2.0 * n1 * c60 * c60)),
    ] {
        rows.push(StabilityRow::new(
            g,
            format!("n2 − n1 = 1e-12 (n1 = 1.5), θ = {}, s", deg(theta)),
            "r_s (real)",
            traced_r(n1, n2, theta, Pol::S).re,
            exact,
            Relative,
            Some(1e-3),
        ));
    }
    // A large index: sine and tangent forms (cos θ = 1 uses (1 − n)/(1 + n)).
    for theta in [0.0, 60f64.to_radians(), 0.01f64.acos()] {
        for pol in [Pol::S, Pol::P] {
            let exact = match (pol, theta == 0.0) {
                (Pol::S, true) => (1.0 - 4.0) / (1.0 + 4.0),
                (Pol::P, true) => -(1.0 - 4.0) / (1.0 + 4.0),
                (Pol::S, false) => r_s_sine(1.0, 4.0, theta),
                (Pol::P, false) => r_p_tangent(1.0, 4.0, theta),
            };
            rows.push(StabilityRow::new(
                g,
                format!("n 1 → 4, θ = {}, {}", deg(theta), pol_name(pol)),
                &format!("r_{} (real)", pol_name(pol)),
                traced_r(1.0, 4.0, theta, pol).re,
                exact,
                Absolute,
                Some(1e-14),
            ));
        }
    }
}

/// The internal reflections that bring the Airy tail of `film` at `theta` below 1e-15 for
/// both polarizations (2 per reflected order, plus one), at most the case cap 2000 + 1.
fn internal_for(film: &Film, theta: f64) -> usize {
    let orders = [Pol::S, Pol::P]
        .into_iter()
        .map(|p| film.orders_for_bound(theta.cos(), WAVELENGTH_M, p, 1e-15))
        .max()
        .unwrap_or(1);
    (2 * orders + 1).min(2001)
}

/// Films 1 pm … 1 mm (air | 1.5 | 1.33) at 0, 1 rad and 89.9° (grazing) against Airy, bounce
/// counts from the tail bound; the 1 µm film with the wave's phase reference 100 m away (a
/// global phase, it must cancel); and R → the bare interface's value as d → 0.
fn film_rows(rows: &mut Vec<StabilityRow>, arithmetic: PathArithmetic) {
    let g = "films";
    let n = [1.0, 1.5, 1.33];
    let film_of = |d: f64| Film {
        n1: n[0],
        n2: n[1],
        n3: n[2],
        thickness_m: d,
    };
    let grazing = 89.9f64.to_radians();
    for d in [1e-12, 1e-10, 1e-8, 1e-6, 1e-3] {
        let film = film_of(d);
        for (theta, angle) in [(0.0f64, "0"), (1.0, "1 rad"), (grazing, "89.9°")] {
            let internal = internal_for(&film, theta);
            for pol in [Pol::S, Pol::P] {
                rows.push(StabilityRow::new(
                    g,
                    format!(
                        "d = {d:.0e} m, θ = {angle}, {}, 1 | 1.5 | 1.33, {internal} internal reflections (tail < 1e-15)",
                        pol_name(pol)
                    ),
                    "R (Airy)",
                    traced_film_with(
                        n,
                        d,
                        theta,
                        (WAVELENGTH_M, pol_angle(pol)),
                        internal,
                        true,
                        DEFAULT_REFERENCE,
                        arithmetic,
                    ),
                    film.reflectance(theta.cos(), WAVELENGTH_M, pol),
                    DeviationKind::Relative,
                    Some(film_tolerance(&film, theta.cos(), WAVELENGTH_M, pol)),
                ));
            }
        }
    }
    // A global phase: the wave's reference point 100 m above the film.
    let (d, theta) = (1e-6, 80f64.to_radians());
    let film = film_of(d);
    let internal = internal_for(&film, theta);
    for (z, label) in [(1e-3, "1 mm"), (100.0, "100 m")] {
        rows.push(StabilityRow::new(
            g,
            format!(
                "d = 1 µm, θ = 80°, s, reference point of the wave {label} above the film (a global phase)"
            ),
            "R (Airy)",
            traced_film_with(
                n,
                d,
                theta,
                (WAVELENGTH_M, pol_angle(Pol::S)),
                internal,
                true,
                DVec3::new(0.0, 0.0, z),
                arithmetic,
            ),
            film.reflectance(theta.cos(), WAVELENGTH_M, Pol::S),
            DeviationKind::Relative,
            Some(film_tolerance(&film, theta.cos(), WAVELENGTH_M, Pol::S)),
        ));
    }
    // d → 0: the 1 pm film's R tends to the bare 1 | 1.33 interface's, with the first-order
    // slope of the Airy sum: |R(1 pm) − R(0)| is O(d/λ), far above rounding, and
    // R(1 pm) − R_bare agrees with the Airy difference (continuity, no film that vanishes).
    let theta: f64 = 0.5;
    let bare = {
        let r0 = Film {
            n1: n[0],
            n2: n[2],
            n3: n[2],
            thickness_m: 0.0,
        };
        r0.reflectance(theta.cos(), WAVELENGTH_M, Pol::S)
    };
    let film = film_of(1e-12);
    let traced = traced_film_with(
        n,
        1e-12,
        theta,
        (WAVELENGTH_M, pol_angle(Pol::S)),
        internal_for(&film, theta),
        true,
        DEFAULT_REFERENCE,
        arithmetic,
    );
    rows.push(StabilityRow::new(
        g,
        "d = 1 pm vs d = 0, θ = 0.5 rad, s: R(1 pm) − R(bare 1 | 1.33 interface)".to_string(),
        "ΔR (Airy)",
        traced - bare,
        film.reflectance(theta.cos(), WAVELENGTH_M, Pol::S) - bare,
        DeviationKind::Relative,
        // 1e-6 plus the rounding of the traced R itself, 16ε·R (the sum of ~20 beams, as in
        // `film_tolerance`), relative to ΔR ~ 2e-11: the tracer's R(1 pm) is ~5e-17 off a
        // 50-digit Airy sum, which the Stokes-form closed form meets to 2e-18 (a closed form
        // that summed the series as the tracer does shared its rounding and hid it).
        Some(
            1e-6 + 16.0 * f64::EPSILON * bare
                / (film.reflectance(theta.cos(), WAVELENGTH_M, Pol::S) - bare).abs(),
        ),
    ));
}

/// High finesse: 1 | 1.5 | 1 film, 1 µm, 85°, s: the traced sum truncated after N reflected
/// orders against the closed-form truncated sum (`Film::r_truncated`, the geometric series
/// summed independently) at 1e-12 relative, and the tail bound checked for honesty: the
/// truncated closed form's distance to the full Airy sum never exceeds 2|r|τ + τ².
fn finesse_rows(rows: &mut Vec<StabilityRow>, arithmetic: PathArithmetic) {
    let g = "finesse";
    let film = Film {
        n1: 1.0,
        n2: 1.5,
        n3: 1.0,
        thickness_m: 1e-6,
    };
    let theta = 85f64.to_radians();
    let c = theta.cos();
    let r = film.r(c, WAVELENGTH_M, Pol::S).norm();
    let exact = r * r;
    let auto = film.orders_for_bound(c, WAVELENGTH_M, Pol::S, 1e-15);
    for orders in [2usize, 5, 10, 20, 40, auto] {
        // 2N − 1 internal reflections reach reflected order N (N round trips): N + 1 beams
        // with order 0, the top face's reflection.
        let beams = orders + 1;
        let truncated = film.r_truncated(c, WAVELENGTH_M, Pol::S, beams).norm_sqr();
        let traced = traced_film_with(
            [1.0, 1.5, 1.0],
            1e-6,
            theta,
            (WAVELENGTH_M, 0.0),
            2 * orders - 1,
            true,
            DEFAULT_REFERENCE,
            arithmetic,
        );
        rows.push(StabilityRow::new(
            g,
            format!("1 | 1.5 | 1, d = 1 µm, θ = 85°, s, orders 0 to N = {orders}"),
            "R truncated (closed-form partial sum)",
            traced,
            truncated,
            DeviationKind::Relative,
            Some(FILM_TOLERANCE),
        ));
        let tau = film.r_tail_bound(c, WAVELENGTH_M, Pol::S, beams);
        let bound = 2.0 * r * tau + tau * tau;
        rows.push(StabilityRow::new(
            g,
            format!(
                "orders 0 to N = {orders}: |R_N − R| ≤ tail bound 2|r|τ + τ² = {bound:.3e} (closed forms)"
            ),
            "R_N − R vs tail bound",
            (truncated - exact).abs(),
            0.0,
            DeviationKind::Absolute,
            Some(bound * (1.0 + 1e-9) + 1e-16),
        ));
    }
    rows.push(StabilityRow::new(
        g,
        format!("N = {auto} orders (tail bound < 1e-15): traced R against the full Airy sum"),
        "R (Airy)",
        traced_film_with(
            [1.0, 1.5, 1.0],
            1e-6,
            theta,
            (WAVELENGTH_M, 0.0),
            2 * auto - 1,
            true,
            DEFAULT_REFERENCE,
            arithmetic,
        ),
        exact,
        DeviationKind::Relative,
        Some(FILM_TOLERANCE),
    ));
}

/// A small deterministic generator (SplitMix64) for the random films.
struct SplitMix(u64);

impl SplitMix {
    fn next_unit(&mut self) -> f64 {
        self.0 = self.0.wrapping_add(0x9e37_79b9_7f4a_7c15);
        let mut z = self.0;
        z = (z ^ (z >> 30)).wrapping_mul(0xbf58_476d_1ce4_e5b9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94d0_49bb_1331_11eb);
        z ^= z >> 31;
        (z >> 11) as f64 / (1u64 << 53) as f64
    }
    fn range(&mut self, a: f64, b: f64) -> f64 {
        a + (b - a) * self.next_unit()
    }
}

/// Seeded random valid films: every traced R, T finite and R + T = 1 with the bounce count
/// from the Airy tail bound (the proptest of tests/suite/stability.rs, as one row).
fn random_film_rows(rows: &mut Vec<StabilityRow>, arithmetic: PathArithmetic) {
    const SCENES: usize = 32;
    let mut rng = SplitMix(6);
    let mut worst = 0.0f64;
    let mut worst_at = String::new();
    for _ in 0..SCENES {
        let n2 = rng.range(1.0, 4.0);
        let n3 = rng.range(1.0, 4.0);
        let d = 10f64.powf(rng.range(-10.0, -3.0));
        let theta = rng.range(0.0, 1.55);
        let pol = rng.range(0.0, 3.2);
        let film = Film {
            n1: 1.0,
            n2,
            n3,
            thickness_m: d,
        };
        let orders = [Pol::S, Pol::P]
            .into_iter()
            .map(|p| film.orders_for_bound(theta.cos(), WAVELENGTH_M, p, 1e-12))
            .max()
            .unwrap_or(1);
        let internal = (2 * orders + 1).min(2001);
        let trace = |reflected| {
            traced_film_with(
                [1.0, n2, n3],
                d,
                theta,
                (WAVELENGTH_M, pol),
                internal,
                reflected,
                DEFAULT_REFERENCE,
                arithmetic,
            )
        };
        let r = trace(true);
        let transmits = fresnel::refract(
            DVec3::new(theta.sin(), 0.0, -theta.cos()),
            DVec3::Z,
            1.0,
            n3,
        )
        .is_some();
        let t = if transmits { trace(false) } else { 0.0 };
        // A NaN anywhere makes the sum NaN, and NaN is the worst value.
        let dev = (r + t - 1.0).abs();
        if dev.is_nan() || dev > worst || worst_at.is_empty() {
            worst_at = format!(
                "n2 {n2:.3}, n3 {n3:.3}, d {d:.2e} m, θ {theta:.3} rad, R {r:.6}, T {t:.6}"
            );
            if dev.is_nan() {
                worst = f64::NAN;
                break;
            }
            worst = dev;
        }
    }
    rows.push(StabilityRow::new(
        "random films",
        format!(
            "{SCENES} seeded films 1 | n2 | n3, n ∈ [1, 4), d ∈ [0.1 nm, 1 mm), θ ∈ [0, 1.55] rad, \
             any linear polarization, orders from ε = 1e-12; worst: {worst_at}"
        ),
        "R + T (finite, lossless)",
        1.0 + worst,
        1.0,
        DeviationKind::Absolute,
        Some(1e-9),
    ));
}

/// A length with a readable unit: 1 nm, 100 µm, 10 mm, 1 m.
fn length_label(m: f64) -> String {
    let (v, unit) = if m < 1e-6 {
        (m * 1e9, "nm")
    } else if m < 1e-3 {
        (m * 1e6, "µm")
    } else if m < 1.0 {
        (m * 1e3, "mm")
    } else {
        (m, "m")
    };
    format!("{} {unit}", (v * 1e6).round() / 1e6)
}

/// Rows of the path sweep at whole decades: fringe judged, the two absolute-phase variants
/// for information.
fn path_rows(rows: &mut Vec<StabilityRow>, points: &[PathPoint], arithmetic: PathArithmetic) {
    for p in points {
        let mantissa = p.path_m / 10f64.powf(p.path_m.log10().round());
        if (mantissa - 1.0).abs() > 1e-9 {
            continue;
        }
        let offsets = path_offsets(p.path_m);
        let cond = |what: &str| {
            format!(
                "s = {}, Δs from {:.0e} to {:.1e} m; {what}",
                length_label(p.path_m),
                offsets[0],
                offsets[PATH_OFFSETS - 1],
            )
        };
        let q = format!("two-beam phase 2πΔs/λ (rad), worst of {PATH_OFFSETS} Δs");
        rows.push(StabilityRow::new(
            "paths",
            cond(match arithmetic {
                PathArithmetic::DoubleDouble => {
                    "fringe: traced, paths differenced in double-double"
                }
                PathArithmetic::AbsoluteF64 => "naive build: traced, absolute paths rounded to f64",
            }),
            &q,
            p.fringe_worst.0,
            p.fringe_worst.1,
            DeviationKind::Absolute,
            Some(PATH_PHASE_TOLERANCE_RAD),
        ));
        for (what, (phase, exact)) in [
            ("absolute phases from f64 paths", p.f64_absolute_worst),
            (
                "absolute phases from binary32 paths",
                p.binary32_absolute_worst,
            ),
        ] {
            rows.push(StabilityRow::new(
                "precision illustration",
                cond(what),
                &q,
                phase,
                exact,
                DeviationKind::Absolute,
                None,
            ));
        }
    }
}

/// Run the whole sweep.
pub fn sweep() -> Sweep {
    sweep_with(PathArithmetic::DoubleDouble)
}

/// The sweep with the traced paths held as `arithmetic` says: fringe's double-double, or the
/// deliberately naive absolute f64 paths that it must fail.
pub fn sweep_with(arithmetic: PathArithmetic) -> Sweep {
    let start = std::time::Instant::now();
    let mut rows = Vec::new();
    incidence_rows(&mut rows);
    critical_rows(&mut rows);
    index_rows(&mut rows);
    film_rows(&mut rows, arithmetic);
    finesse_rows(&mut rows, arithmetic);
    random_film_rows(&mut rows, arithmetic);
    let paths = path_points_with(&path_grid(), arithmetic);
    path_rows(&mut rows, &paths, arithmetic);
    Sweep {
        rows,
        paths,
        seconds: start.elapsed().as_secs_f64(),
    }
}

/// The CSV header of `stability.csv`.
pub const CSV_HEADER: &str =
    "group,condition,quantity,traced,closed_form,deviation,deviation_kind,tolerance,verdict";

/// Verdict text of a row: pass, FAIL or info.
pub fn verdict(pass: Option<bool>) -> &'static str {
    match pass {
        Some(true) => "pass",
        Some(false) => "FAIL",
        None => "info",
    }
}

/// `stability.csv`: one line per row, values to 17 significant digits, an empty tolerance for
/// illustration rows.
pub fn csv(rows: &[StabilityRow]) -> String {
    // Written by the `csv` crate (a field with a comma, a quote or a line break is quoted).
    crate::output::report::csv_text(
        &CSV_HEADER.split(',').collect::<Vec<_>>(),
        rows.iter().map(|r| {
            vec![
                r.group.clone(),
                r.condition.clone(),
                r.quantity.clone(),
                format!("{:.16e}", r.traced),
                format!("{:.16e}", r.closed_form),
                format!("{:.6e}", r.deviation),
                r.deviation_kind.name().to_string(),
                r.tolerance.map(|t| format!("{t:e}")).unwrap_or_default(),
                verdict(r.pass).to_string(),
            ]
        }),
    )
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn binary32_rounding_of_hand_checked_values() {
        let p = |k: i32| 2f64.powi(k);
        // Ties go to the even significand.
        assert_eq!(round_to_binary32(1.0 + p(-24)), 1.0);
        assert_eq!(round_to_binary32(1.0 + 3.0 * p(-24)), 1.0 + p(-22));
        assert_eq!(round_to_binary32(16_777_217.0), 16_777_216.0);
        assert_eq!(round_to_binary32(16_777_219.0), 16_777_220.0);
        // Just above a tie rounds up; representable values stay.
        assert_eq!(round_to_binary32(1.0 + p(-24) + p(-40)), 1.0 + p(-23));
        assert_eq!(round_to_binary32(1.0 + p(-23)), 1.0 + p(-23));
        // 0.1 in binary32 is 13421773·2^-27 = 0.100000001490116119384765625.
        assert_eq!(round_to_binary32(0.1), 13_421_773.0 * p(-27));
        assert_eq!(round_to_binary32(-0.1), -13_421_773.0 * p(-27));
        // A carry into the exponent: 2 − 2^-25 rounds to 2.
        assert_eq!(round_to_binary32(2.0 - p(-25)), 2.0);
        // Largest finite binary32, overflow, subnormals, zero, NaN.
        let max = (2.0 - p(-23)) * p(127);
        assert_eq!(round_to_binary32(max), max);
        assert_eq!(round_to_binary32(p(128)), f64::INFINITY);
        assert_eq!(round_to_binary32(-p(128)), f64::NEG_INFINITY);
        assert_eq!(round_to_binary32(p(-149)), p(-149));
        assert_eq!(round_to_binary32(p(-150)), 0.0);
        assert_eq!(round_to_binary32(1.5 * p(-149)), p(-148));
        assert_eq!(round_to_binary32(3.0 * p(-130)), 3.0 * p(-130));
        assert_eq!(round_to_binary32(0.0), 0.0);
        assert!(round_to_binary32(f64::NAN).is_nan());
        // The spacing of binary32 at 1 m: 2^-23 above 1, 2^-24 below.
        assert_eq!(round_to_binary32(1.0 + 0.6 * p(-23)), 1.0 + p(-23));
        assert_eq!(round_to_binary32(1.0 - 0.6 * p(-24)), 1.0 - p(-24));
    }

    #[test]
    fn binary32_rounding_is_idempotent_and_monotone() {
        let mut x = 1e-30;
        let mut prev = 0.0;
        while x < 1e30 {
            let r = round_to_binary32(x);
            assert_eq!(round_to_binary32(r), r, "{x:e}");
            assert!(r >= prev, "{x:e}");
            assert!((r - x).abs() <= x * 2f64.powi(-24), "{x:e} → {r:e}");
            prev = r;
            x *= 1.0 + 1e-3;
        }
    }

    #[test]
    fn csv_quotes_fields_with_commas() {
        let r = StabilityRow::new(
            "incidence",
            "θ = 0, s".into(),
            "r_s",
            -0.2,
            -0.2,
            DeviationKind::Absolute,
            Some(1e-14),
        );
        let text = csv(&[r]);
        let line = text.lines().nth(1).unwrap();
        assert!(line.starts_with("incidence,\"θ = 0, s\",r_s,"), "{line}");
        assert!(line.ends_with(",absolute,1e-14,pass"), "{line}");
    }
}
