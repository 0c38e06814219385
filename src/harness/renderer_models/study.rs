//! `fringe models`: every production model of [`super`] against the exact Airy sum over angle ×
//! thickness × wavelength, for plates (0.1–10 µm) and films (0–1.5 µm), in air, on a substrate
//! and seen from a denser medium (where the back face totally reflects), and the colour of each
//! under D65 against the exact colour as CIEDE2000 ΔE00.
//!
//! Quantities: R is the unpolarized power reflectance ½(R_s + R_p) (dimensionless, docs/PHYSICS.md
//! §3a); |ΔR| is the largest difference over the wavelengths 360–830 nm at 1 nm; colours are CIE
//! 1931 XYZ of R(λ) under D65 with Y = 1 for a perfect reflector (`src/colour/spectrum.rs`, C1), ΔE00
//! relative to the D65 white; retardance is arg r_p − arg r_s of the reflected wave at 550 nm.
//! Every comparison is a grid of points (stack, angle, thickness); [`summarize`] reduces it to
//! where ΔE00 < 1 holds and the worst errors.

use super::{Film, Model, belcour_barla, exact_reflectance, incoherent, tir_phase_zero};
use crate::colour::{self, Illuminant, SpectralIntegrator, WavelengthGrid};
use rayon::prelude::*;
use std::fmt::Write as _;

/// One medium stack n1 | n2 (thickness range) | n3 of the study.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Stack {
    pub name: &'static str,
    pub n1: f64,
    pub n2: f64,
    pub n3: f64,
    /// Thickness range (µm) and the number of thicknesses.
    pub thickness_um: (f64, f64),
    pub thickness_count: usize,
    /// Logarithmic thickness spacing (plates) or linear (films).
    pub log_spaced: bool,
    pub what: &'static str,
}

/// The stacks of the study.
pub const STACKS: [Stack; 5] = [
    Stack {
        name: "plate_in_air",
        n1: 1.0,
        n2: 1.5,
        n3: 1.0,
        thickness_um: (0.1, 10.0),
        thickness_count: 41,
        log_spaced: true,
        what: "glass plate n = 1.5 in air, 0.1–10 µm (log-spaced)",
    },
    Stack {
        name: "plate_on_substrate",
        n1: 1.0,
        n2: 1.3,
        n3: 1.5,
        thickness_um: (0.1, 10.0),
        thickness_count: 41,
        log_spaced: true,
        what: "layer n = 1.3 on glass n = 1.5 (glTF iridescence defaults), 0.1–10 µm",
    },
    Stack {
        name: "film_in_air",
        n1: 1.0,
        n2: 1.33,
        n3: 1.0,
        thickness_um: (0.0, 1.5),
        thickness_count: 61,
        log_spaced: false,
        what: "soap film n = 1.33 in air, 0–1.5 µm",
    },
    Stack {
        name: "film_on_substrate",
        n1: 1.0,
        n2: 1.3,
        n3: 1.5,
        thickness_um: (0.0, 1.5),
        thickness_count: 61,
        log_spaced: false,
        what: "film n = 1.3 on glass n = 1.5 (glTF iridescence defaults), 0–1.5 µm",
    },
    Stack {
        name: "film_glass_to_air",
        n1: 1.5,
        n2: 2.0,
        n3: 1.0,
        thickness_um: (0.0, 1.5),
        thickness_count: 61,
        log_spaced: false,
        what: "film n = 2.0 between glass n = 1.5 (lit from the glass) and air: TIR at the back face beyond 41.81°",
    },
];

/// Angles of incidence of the study (degrees): 0, 2, …, 88.
pub(crate) fn angles_deg() -> Vec<f64> {
    (0..=44).map(|k| 2.0 * k as f64).collect()
}

impl Stack {
    /// The thicknesses of the stack (m).
    pub fn thicknesses_m(&self) -> Vec<f64> {
        let (a, b) = self.thickness_um;
        let n = self.thickness_count;
        (0..n)
            .map(|k| {
                let t = k as f64 / (n - 1) as f64;
                1e-6 * if self.log_spaced {
                    a * (b / a).powf(t)
                } else {
                    a + (b - a) * t
                }
            })
            .collect()
    }
}

/// A model or one simplification, compared with its reference at every grid point.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Comparison {
    /// A production model against the exact Airy sum.
    Model(Model),
    /// pbrt/Mitsuba (averaged) against the per-polarization incoherent plate: the cost of
    /// averaging s and p before summing.
    Averaging,
    /// The per-polarization incoherent plate against exact: the cost of dropping the phase.
    DroppedPhase,
    /// Belcour–Barla's series cut at m ≤ 3, integrated exactly, against exact: the cost of
    /// the truncation.
    FourierTruncation,
    /// Belcour–Barla's fitted sensitivities against the exact CIE integral of the same
    /// truncated series: the cost of the fitted spectral integration.
    FittedSensitivities,
}

impl Comparison {
    pub const ALL: [Comparison; 8] = [
        Comparison::Model(Model::ThinDielectricAveraged),
        Comparison::Model(Model::IncoherentPerPolarization),
        Comparison::Model(Model::BelcourBarla),
        Comparison::Model(Model::TirPhaseZero),
        Comparison::Averaging,
        Comparison::DroppedPhase,
        Comparison::FourierTruncation,
        Comparison::FittedSensitivities,
    ];

    /// The comparisons of the table: the four models, then the four simplifications (the cost
    /// of the TIR phase is the `tir_phase_zero` model's own row).
    pub fn table() -> &'static [Comparison] {
        &Self::ALL
    }

    pub fn name(self) -> String {
        match self {
            Comparison::Model(m) => m.name().to_string(),
            Comparison::Averaging => "cost:average_s_p_first".into(),
            Comparison::DroppedPhase => "cost:drop_phase".into(),
            Comparison::FourierTruncation => "cost:fourier_orders_le_3".into(),
            Comparison::FittedSensitivities => "cost:fitted_sensitivities".into(),
        }
    }
}

/// One comparison at one grid point.
#[derive(Clone, Debug, PartialEq)]
pub struct GridRow {
    pub stack: &'static str,
    pub comparison: String,
    pub theta_deg: f64,
    pub thickness_um: f64,
    /// max over λ of |R_test − R_reference| (dimensionless); NaN for colour-only comparisons.
    pub max_abs_dr: f64,
    /// The wavelength of that maximum (nm).
    pub at_nm: f64,
    /// CIEDE2000 between the two colours under D65.
    pub de00: f64,
    /// |Δ retardance| at 550 nm (degrees), where the model has a phase (else NaN).
    pub retardance_err_deg: f64,
}

/// The spectra and colours of every model at one grid point.
struct Point {
    exact: Vec<f64>,
    averaged: f64,
    per_pol: f64,
    bb_series: Vec<f64>,
    tir_zero: Vec<f64>,
    xyz_exact: [f64; 3],
    xyz_averaged: [f64; 3],
    xyz_per_pol: [f64; 3],
    xyz_bb_series: [f64; 3],
    xyz_bb_fit: [f64; 3],
    xyz_tir_zero: [f64; 3],
    retardance_err_tir_zero_deg: f64,
}

fn evaluate(film: &Film, cos1: f64, integ: &SpectralIntegrator) -> Point {
    let l = integ.lambdas_m();
    let exact: Vec<f64> = l
        .iter()
        .map(|&x| exact_reflectance(film, cos1, x))
        .collect();
    let averaged = incoherent::averaged(film, cos1);
    let per_pol = incoherent::per_polarization(film, cos1);
    let bb_series: Vec<f64> = l
        .iter()
        .map(|&x| belcour_barla::reflectance(film, cos1, x, belcour_barla::ORDERS))
        .collect();
    let tir_zero: Vec<f64> = l
        .iter()
        .map(|&x| tir_phase_zero::reflectance(film, cos1, x))
        .collect();
    let flat = |r: f64| integ.xyz(&vec![r; l.len()]);
    let lambda = 550e-9;
    let ret = tir_phase_zero::wrap(
        tir_phase_zero::retardance(film, cos1, lambda)
            - tir_phase_zero::exact_retardance(film, cos1, lambda),
    )
    .abs()
    .to_degrees();
    Point {
        xyz_exact: integ.xyz(&exact),
        xyz_averaged: flat(averaged),
        xyz_per_pol: flat(per_pol),
        xyz_bb_series: integ.xyz(&bb_series),
        xyz_bb_fit: belcour_barla::colour_xyz(film, cos1, belcour_barla::ORDERS),
        xyz_tir_zero: integ.xyz(&tir_zero),
        exact,
        averaged,
        per_pol,
        bb_series,
        tir_zero,
        retardance_err_tir_zero_deg: ret,
    }
}

/// ΔE00 of two XYZ colours (D65, Y = 1 white) relative to `white`.
pub fn delta_e00(a: [f64; 3], b: [f64; 3], white: [f64; 3]) -> f64 {
    colour::delta_e_2000(colour::xyz_to_lab(a, white), colour::xyz_to_lab(b, white))
}

fn max_diff(a: &[f64], b: &[f64], lambdas: &[f64]) -> (f64, f64) {
    a.iter()
        .zip(b)
        .zip(lambdas)
        .fold((0.0f64, lambdas[0] * 1e9), |(m, at), ((x, y), l)| {
            let d = (x - y).abs();
            if d > m { (d, l * 1e9) } else { (m, at) }
        })
}

/// Every comparison of the table at every point of `stacks` × `angles_deg` × thicknesses.
pub fn run(stacks: &[Stack]) -> Vec<GridRow> {
    let grid = WavelengthGrid::cie_1nm();
    let integ = SpectralIntegrator::new(&grid, Illuminant::D65).expect("the CIE grid is valid");
    let white = integ.white_xyz();
    let lambdas = integ.lambdas_m().to_vec();
    let jobs: Vec<(Stack, f64, f64)> = stacks
        .iter()
        .flat_map(|s| {
            let ts = s.thicknesses_m();
            angles_deg()
                .into_iter()
                .flat_map(move |a| ts.clone().into_iter().map(move |d| (*s, a, d)))
        })
        .collect();
    jobs.par_iter()
        .flat_map_iter(|&(s, theta, d)| {
            let film = Film {
                n1: s.n1,
                n2: s.n2,
                n3: s.n3,
                thickness_m: d,
            };
            let p = evaluate(&film, theta.to_radians().cos(), &integ);
            let n = lambdas.len();
            let row = |c: Comparison, test: &[f64], refr: &[f64], xt, xr, ret: f64| {
                let (dr, at) = max_diff(test, refr, &lambdas);
                GridRow {
                    stack: s.name,
                    comparison: c.name(),
                    theta_deg: theta,
                    thickness_um: d * 1e6,
                    max_abs_dr: dr,
                    at_nm: at,
                    de00: delta_e00(xt, xr, white),
                    retardance_err_deg: ret,
                }
            };
            let averaged = vec![p.averaged; n];
            let per_pol = vec![p.per_pol; n];
            vec![
                row(
                    Comparison::Model(Model::ThinDielectricAveraged),
                    &averaged,
                    &p.exact,
                    p.xyz_averaged,
                    p.xyz_exact,
                    f64::NAN,
                ),
                row(
                    Comparison::Model(Model::IncoherentPerPolarization),
                    &per_pol,
                    &p.exact,
                    p.xyz_per_pol,
                    p.xyz_exact,
                    f64::NAN,
                ),
                row(
                    Comparison::Model(Model::BelcourBarla),
                    &p.bb_series,
                    &p.exact,
                    p.xyz_bb_fit,
                    p.xyz_exact,
                    f64::NAN,
                ),
                row(
                    Comparison::Model(Model::TirPhaseZero),
                    &p.tir_zero,
                    &p.exact,
                    p.xyz_tir_zero,
                    p.xyz_exact,
                    p.retardance_err_tir_zero_deg,
                ),
                row(
                    Comparison::Averaging,
                    &averaged,
                    &per_pol,
                    p.xyz_averaged,
                    p.xyz_per_pol,
                    f64::NAN,
                ),
                row(
                    Comparison::DroppedPhase,
                    &per_pol,
                    &p.exact,
                    p.xyz_per_pol,
                    p.xyz_exact,
                    f64::NAN,
                ),
                row(
                    Comparison::FourierTruncation,
                    &p.bb_series,
                    &p.exact,
                    p.xyz_bb_series,
                    p.xyz_exact,
                    f64::NAN,
                ),
                // Colours only: both sides have the same spectrum, so no ΔR (NaN).
                GridRow {
                    max_abs_dr: f64::NAN,
                    ..row(
                        Comparison::FittedSensitivities,
                        &p.bb_series,
                        &p.bb_series,
                        p.xyz_bb_fit,
                        p.xyz_bb_series,
                        f64::NAN,
                    )
                },
            ]
        })
        .collect()
}

/// One line of the error table: a comparison over one stack's grid.
#[derive(Clone, Debug, PartialEq)]
pub struct Summary {
    pub stack: &'static str,
    pub comparison: String,
    /// Worst |ΔR| and where (θ deg, d µm, λ nm).
    pub worst_dr: f64,
    pub worst_dr_at: (f64, f64, f64),
    /// Worst ΔE00 and where (θ deg, d µm).
    pub worst_de: f64,
    pub worst_de_at: (f64, f64),
    /// Fraction of the grid points with ΔE00 < 1.
    pub fraction_de_below_1: f64,
    /// The smallest thickness (µm) from which ΔE00 < 1 at every angle and every thicker
    /// layer; `None` if the thickest layer fails.
    pub de_below_1_from_um: Option<f64>,
    /// The largest angle (deg) up to which ΔE00 < 1 at every thickness; `None` if normal
    /// incidence fails.
    pub de_below_1_up_to_deg: Option<f64>,
    /// Worst |Δ retardance| (deg), NaN where the comparison has no phase.
    pub worst_retardance_deg: f64,
}

/// Reduce the grid to one [`Summary`] per stack and comparison, in table order.
pub fn summarize(rows: &[GridRow]) -> Vec<Summary> {
    let mut out = Vec::new();
    for s in STACKS.iter() {
        for c in Comparison::table() {
            let name = c.name();
            let r: Vec<&GridRow> = rows
                .iter()
                .filter(|x| x.stack == s.name && x.comparison == name)
                .collect();
            if r.is_empty() {
                continue;
            }
            // NaN |ΔR| (colour-only comparisons) is skipped; all NaN reports NaN.
            let wdr = r
                .iter()
                .filter(|x| !x.max_abs_dr.is_nan())
                .max_by(|a, b| a.max_abs_dr.total_cmp(&b.max_abs_dr))
                .unwrap_or(&r[0]);
            let wde = r.iter().max_by(|a, b| a.de00.total_cmp(&b.de00)).unwrap();
            let ok = |x: &&GridRow| x.de00 < 1.0;
            let mut ds: Vec<f64> = r.iter().map(|x| x.thickness_um).collect();
            ds.sort_by(f64::total_cmp);
            ds.dedup();
            let mut from = None;
            for d in ds.iter().rev() {
                if r.iter().filter(|x| x.thickness_um == *d).all(ok) {
                    from = Some(*d);
                } else {
                    break;
                }
            }
            let mut up_to = None;
            for a in angles_deg() {
                if r.iter().filter(|x| x.theta_deg == a).all(ok) {
                    up_to = Some(a);
                } else {
                    break;
                }
            }
            let ret = r
                .iter()
                .map(|x| x.retardance_err_deg)
                .filter(|x| !x.is_nan())
                .fold(f64::NAN, f64::max);
            out.push(Summary {
                stack: s.name,
                comparison: name,
                worst_dr: wdr.max_abs_dr,
                worst_dr_at: (wdr.theta_deg, wdr.thickness_um, wdr.at_nm),
                worst_de: wde.de00,
                worst_de_at: (wde.theta_deg, wde.thickness_um),
                fraction_de_below_1: r.iter().filter(|x| x.de00 < 1.0).count() as f64
                    / r.len() as f64,
                de_below_1_from_um: from,
                de_below_1_up_to_deg: up_to,
                worst_retardance_deg: ret,
            });
        }
    }
    out
}

/// `models.csv`: every grid row.
pub(crate) fn grid_csv(rows: &[GridRow]) -> String {
    crate::io::csv_text(
        &[
            "stack",
            "comparison",
            "theta_deg",
            "thickness_um",
            "max_abs_dR",
            "at_lambda_nm",
            "dE00",
            "retardance_err_deg",
        ],
        rows.iter().map(|r| {
            vec![
                r.stack.to_string(),
                r.comparison.to_string(),
                r.theta_deg.to_string(),
                format!("{:.6}", r.thickness_um),
                format!("{:.6e}", r.max_abs_dr),
                r.at_nm.to_string(),
                format!("{:.6}", r.de00),
                format!("{:.6}", r.retardance_err_deg),
            ]
        }),
    )
}

fn opt(x: Option<f64>, unit: &str) -> String {
    x.map(|v| format!("{v:.3} {unit}"))
        .unwrap_or_else(|| "never".into())
}

/// `summary.csv`: the error table.
pub(crate) fn summary_csv(rows: &[Summary]) -> String {
    let o = |x: Option<f64>| x.map(|v| format!("{v}")).unwrap_or_default();
    crate::io::csv_text(
        &[
            "stack",
            "comparison",
            "worst_abs_dR",
            "dR_theta_deg",
            "dR_thickness_um",
            "dR_lambda_nm",
            "worst_dE00",
            "dE_theta_deg",
            "dE_thickness_um",
            "fraction_dE00_below_1",
            "dE00_below_1_from_thickness_um",
            "dE00_below_1_up_to_deg",
            "worst_retardance_err_deg",
        ],
        rows.iter().map(|r| {
            vec![
                r.stack.to_string(),
                r.comparison.to_string(),
                format!("{:.3e}", r.worst_dr),
                r.worst_dr_at.0.to_string(),
                format!("{:.4}", r.worst_dr_at.1),
                r.worst_dr_at.2.to_string(),
                format!("{:.3}", r.worst_de),
                r.worst_de_at.0.to_string(),
                format!("{:.4}", r.worst_de_at.1),
                format!("{:.4}", r.fraction_de_below_1),
                o(r.de_below_1_from_um),
                o(r.de_below_1_up_to_deg),
                format!("{:.3}", r.worst_retardance_deg),
            ]
        }),
    )
}

/// The error table as Markdown (the README's table is this output).
pub(crate) fn summary_markdown(rows: &[Summary]) -> String {
    let mut s = String::from(
        "| stack | model / simplification | worst \\|ΔR\\| (θ, d, λ) | worst ΔE00 (θ, d) | ΔE00 < 1 on | ΔE00 < 1 at all angles from d = | ΔE00 < 1 at all d up to θ = | worst Δretardance |\n| --- | --- | --- | --- | --- | --- | --- | --- |\n",
    );
    for r in rows {
        let ret = if r.worst_retardance_deg.is_nan() {
            "-".to_string()
        } else {
            format!("{:.1}°", r.worst_retardance_deg)
        };
        let dr = if r.worst_dr.is_nan() {
            "- (colour only)".to_string()
        } else {
            format!(
                "{:.2e} ({}°, {:.3} µm, {} nm)",
                r.worst_dr, r.worst_dr_at.0, r.worst_dr_at.1, r.worst_dr_at.2
            )
        };
        let _ = writeln!(
            s,
            "| {} | {} | {dr} | {:.2} ({}°, {:.3} µm) | {:.0}% | {} | {} | {} |",
            r.stack,
            r.comparison,
            r.worst_de,
            r.worst_de_at.0,
            r.worst_de_at.1,
            100.0 * r.fraction_de_below_1,
            opt(r.de_below_1_from_um, "µm"),
            opt(r.de_below_1_up_to_deg, "°"),
            ret
        );
    }
    s
}

/// Run the whole study and write `OUT/models/models.csv` (every grid row), `summary.csv` and
/// `summary.md` (the error table); returns the table as Markdown. The command
/// (`fringe::cli::models`) then refreshes the report page, which shows the table.
pub fn write(out: &std::path::Path) -> Result<String, String> {
    let rows = run(&STACKS);
    let sums = summarize(&rows);
    let md = summary_markdown(&sums);
    let dir = out.join("models");
    for (name, text) in [
        ("models.csv", grid_csv(&rows)),
        ("summary.csv", summary_csv(&sums)),
        ("summary.md", md.clone()),
    ] {
        let p = dir.join(name);
        crate::io::write_atomic(&p, text.as_bytes())
            .map_err(|e| format!("{}: cannot write: {e}", p.display()))?;
    }
    Ok(md)
}
