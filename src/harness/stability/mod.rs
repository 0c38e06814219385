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
//! emulated on f64 bits by `paths::round_to_binary32` (no single-precision type is used); the phases
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

mod film;
mod interface;
mod paths;

use film::{film_rows, finesse_rows, random_film_rows};
pub use film::{traced_film, traced_film_with};
use interface::{critical_rows, incidence_rows, index_rows};
use paths::path_rows;
pub use paths::round_to_binary32;
pub use paths::{collinear_sources, path_points};
pub(crate) use paths::{path_grid, path_points_with};

/// Vacuum wavelength of the whole sweep (m).
pub const WAVELENGTH_M: f64 = 550e-9;

/// The bound on fringe's two-beam phase error from 1 nm to 10 m (rad): optical paths held in
/// double-double keep the exact path difference of the collinear sources to ~1e-30 m, so the
/// phase is the exact one rounded once; absolute paths rounded to f64 err by ~1e-9 rad at 1 m
/// and fail this bound from about 1 mm on ([`PathArithmetic::AbsoluteF64`]).
pub const PATH_PHASE_TOLERANCE_RAD: f64 = 1e-12;

/// The bound on the relative deviation of a traced film reflectance from the Airy sum (and of a
/// truncated traced sum from the truncated closed form): issue #13's 1e-12.
pub(crate) const FILM_TOLERANCE: f64 = 1e-12;

/// The relative deviation of a traced film reflectance from the Airy sum that the f64 inputs
/// allow: `FILM_TOLERANCE` plus the conditioning of R on its inputs. The round-trip phase
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
pub(crate) const PATH_OFFSETS: usize = 8;

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
    /// A row of the sweep: the verdict is `deviation ≤ tolerance` (none for an illustration row).
    pub fn new(
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

/// The phase errors of one path length (worst over `PATH_OFFSETS` path differences).
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
    crate::io::csv_text(
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
