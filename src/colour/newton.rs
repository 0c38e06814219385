//! Newton's interference colours of a thin film (Airy reflectance, docs/PHYSICS.md §5).

use super::*;

/// Checks the film parameters fringe accepts, naming the offending field.
fn validate_film(n_film: f64, thickness_m: f64) -> Result<(), String> {
    if !(n_film.is_finite() && n_film > 0.0) {
        return Err(format!("n_film = {n_film}: must be real, finite and > 0"));
    }
    if !(thickness_m.is_finite() && thickness_m >= 0.0) {
        return Err(format!(
            "thickness_m = {thickness_m:e}: must be finite and >= 0 (metres)"
        ));
    }
    Ok(())
}

/// Reflectance R = |r|² (dimensionless) at normal incidence of a non-absorbing film of index
/// `n_film` and thickness `thickness_m` (metres) in air (n = 1 on both sides), for vacuum
/// wavelength `lambda_m` (metres). Exact multi-beam (Airy) sum, B&W §7.6.1, docs/PHYSICS.md §5:
///
/// ```text
/// r = (r12 + r23 e^{iβ}) / (1 + r12 r23 e^{iβ}),   β = 4π n d / λ
/// r12 = (1 − n)/(1 + n),   r23 = (n − 1)/(n + 1)
/// ```
///
/// (time convention e^{-iωt}; at normal incidence R does not depend on the sign of β).
/// d = 0 gives R = 0 exactly (r23 = −r12). The maximum ((n²−1)/(n²+1))² occurs at
/// d = λ/(4n) (quarter-wave film).
///
/// # Panics
/// If `n_film` is not finite and > 0, `thickness_m` is not finite and ≥ 0, or `lambda_m` is not
/// finite and > 0.
pub fn soap_film_reflectance(n_film: f64, thickness_m: f64, lambda_m: f64) -> f64 {
    if let Err(e) = validate_film(n_film, thickness_m) {
        panic!("soap_film_reflectance: {e}");
    }
    assert!(
        lambda_m.is_finite() && lambda_m > 0.0,
        "soap_film_reflectance: lambda_m = {lambda_m:e} must be finite and > 0 (metres)"
    );
    let r12 = (1.0 - n_film) / (1.0 + n_film);
    let r23 = (n_film - 1.0) / (n_film + 1.0);
    let beta = 4.0 * std::f64::consts::PI * n_film * thickness_m / lambda_m;
    let (sin_beta, cos_beta) = beta.sin_cos();
    // Numerator and denominator as (re, im).
    let num = (r12 + r23 * cos_beta, r23 * sin_beta);
    let den = (1.0 + r12 * r23 * cos_beta, r12 * r23 * sin_beta);
    (num.0 * num.0 + num.1 * num.1) / (den.0 * den.0 + den.1 * den.1)
}

/// One film thickness of Newton's colour sequence.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct NewtonRow {
    /// Film thickness in metres.
    pub thickness_m: f64,
    /// XYZ of the reflected light under the chosen illuminant (Y = 1 for a perfect reflector).
    pub xyz: [f64; 3],
    /// Linear sRGB after adaptation, before clipping.
    pub linear_srgb: [f64; 3],
    /// 8-bit sRGB after clipping and the transfer curve.
    pub srgb8: [u8; 3],
    /// How far the furthest linear channel lay outside [0, 1] (0 = in gamut).
    pub clip_excess: f64,
}

/// Newton's interference colours in reflection: for each thickness (metres), the reflectance
/// spectrum [`soap_film_reflectance`] on `grid` is integrated to XYZ under `illuminant` (C1)
/// and shown in sRGB with `adaptation` ([`xyz_to_srgb8`]).
///
/// Errors: invalid `n_film`, thickness or grid.
pub fn newton_sequence(
    n_film: f64,
    thicknesses_m: &[f64],
    grid: &WavelengthGrid,
    illuminant: Illuminant,
    adaptation: Adaptation,
) -> Result<Vec<NewtonRow>, String> {
    let mut rows = newton_sequences(n_film, thicknesses_m, grid, &[(illuminant, adaptation)])?;
    Ok(rows.pop().unwrap_or_default())
}

/// [`newton_sequence`] under several (illuminant, adaptation) pairs, one row list per pair in
/// their order: each thickness's reflectance spectrum (which does not depend on the light) is
/// evaluated once and integrated under every pair, so each list is bit for bit the one
/// [`newton_sequence`] gives for its pair. Thicknesses run in parallel (rayon).
///
/// Errors: invalid `n_film`, thickness or grid.
pub fn newton_sequences(
    n_film: f64,
    thicknesses_m: &[f64],
    grid: &WavelengthGrid,
    lights: &[(Illuminant, Adaptation)],
) -> Result<Vec<Vec<NewtonRow>>, String> {
    use rayon::prelude::*;
    for &d in thicknesses_m {
        validate_film(n_film, d)?;
    }
    grid.validate()?;
    let integrators = lights
        .iter()
        .map(|&(illuminant, adaptation)| {
            Ok((
                SpectralIntegrator::new(grid, illuminant)?,
                illuminant,
                adaptation,
            ))
        })
        .collect::<Result<Vec<_>, String>>()?;
    // Per thickness, the row under each light.
    let per_thickness: Vec<Vec<NewtonRow>> = thicknesses_m
        .par_iter()
        .map_init(
            || vec![0.0; grid.len()],
            |spectrum, &thickness_m| {
                for (r, &lambda) in spectrum.iter_mut().zip(&grid.lambdas_m) {
                    *r = soap_film_reflectance(n_film, thickness_m, lambda);
                }
                integrators
                    .iter()
                    .map(|(integrator, illuminant, adaptation)| {
                        let xyz = integrator.xyz(spectrum);
                        let pixel = xyz_to_srgb8(xyz, *illuminant, *adaptation);
                        NewtonRow {
                            thickness_m,
                            xyz,
                            linear_srgb: pixel.linear_srgb,
                            srgb8: pixel.srgb8,
                            clip_excess: pixel.clip_excess,
                        }
                    })
                    .collect()
            },
        )
        .collect();
    Ok((0..lights.len())
        .map(|k| per_thickness.iter().map(|rows| rows[k]).collect())
        .collect())
}

/// [`newton_sequence`] as CSV text: one '#' comment line stating n, illuminant, adaptation and
/// grid, then the header `thickness_nm,X,Y,Z,R_lin,G_lin,B_lin,R8,G8,B8` and one row per
/// thickness (thickness in nm; XYZ with Y = 1 for white; linear sRGB before clipping).
pub fn write_newton_csv(
    n_film: f64,
    thicknesses_m: &[f64],
    grid: &WavelengthGrid,
    illuminant: Illuminant,
    adaptation: Adaptation,
) -> Result<String, String> {
    let rows = newton_sequence(n_film, thicknesses_m, grid, illuminant, adaptation)?;
    Ok(newton_csv(&rows, n_film, grid, illuminant, adaptation))
}

/// [`write_newton_csv`] of rows already computed by [`newton_sequence`] with these arguments
/// (so a caller that needs the rows too computes them once).
pub fn newton_csv(
    rows: &[NewtonRow],
    n_film: f64,
    grid: &WavelengthGrid,
    illuminant: Illuminant,
    adaptation: Adaptation,
) -> String {
    let comment = format!(
        "# fringe::colour::newton_sequence: soap film n_film={n_film} in air, normal incidence, \
         Airy reflectance; illuminant={}, adaptation={}, CIE 1931 2deg, {} samples {:.3}..{:.3} nm\n",
        illuminant.name(),
        adaptation.name(),
        grid.len(),
        grid.lambdas_m[0] * NM_PER_M,
        grid.lambdas_m[grid.len() - 1] * NM_PER_M,
    );
    let table = crate::io::csv_text(
        &[
            "thickness_nm",
            "X",
            "Y",
            "Z",
            "R_lin",
            "G_lin",
            "B_lin",
            "R8",
            "G8",
            "B8",
        ],
        rows.iter().map(|row| {
            let e = |v: f64| format!("{v:.10e}");
            // Rounded to 1e-6 nm so that 1e-7 m prints as 100, not 100.00000000000001.
            let mut fields = vec![((row.thickness_m * NM_PER_M * 1e6).round() / 1e6).to_string()];
            fields.extend(row.xyz.map(e));
            fields.extend(row.linear_srgb.map(e));
            fields.extend(row.srgb8.map(|c| c.to_string()));
            fields
        }),
    );
    comment + &table
}
