//! Spectral colour: per-wavelength intensities → CIE 1931 XYZ → sRGB, CIELAB and CIEDE2000
//! colour differences, and Newton's interference colours of a thin film (docs/PHYSICS.md §6).
//!
//! # Conventions (stated once, used by every function here)
//!
//! - **Units**: wavelengths and thicknesses are in **metres** (vacuum wavelength), as everywhere
//!   in fringe. The CIE tables are tabulated in nanometres; the conversion happens only inside
//!   the table look-up. Spectral weights of a [`WavelengthGrid`] are in metres.
//! - **Observer**: CIE 1931 2° standard observer, x̄, ȳ, z̄ at 1 nm from 360 nm to 830 nm
//!   (CIE 15:2004, Table T.4; `data/cie1931_2deg.csv`), linearly interpolated between table
//!   rows and zero outside 360–830 nm.
//! - **Illuminants**: E (equal energy, S(λ) = 1) and D65 (CIE 15:2004, Table T.1, tabulated
//!   every 5 nm to 780 nm, linearly interpolated to 1 nm and held constant above 780 nm;
//!   `data/cie_d65.csv`, column `S_D65`).
//! - **Tristimulus values** of a reflectance or transmittance spectrum ρ(λ) (dimensionless)
//!   under illuminant S (CIE 15:2004 §7.1, with the integral replaced by a quadrature on the
//!   grid with weights w_i):
//!
//!   ```text
//!   X = k Σ_i w_i S(λ_i) x̄(λ_i) ρ(λ_i),  Y = k Σ_i w_i S(λ_i) ȳ(λ_i) ρ(λ_i),  Z = …z̄…
//!   k = 1 / Σ_i w_i S(λ_i) ȳ(λ_i)                                                   (C1)
//!   ```
//!
//!   so a perfect reflector (ρ ≡ 1) has Y = 1 exactly **on every grid** (relative colorimetry,
//!   Y in [0, 1] rather than CIE's [0, 100]).
//! - **Display**: XYZ → linear sRGB with the IEC 61966-2-1:1999 matrix (D65 white), clip each
//!   channel to [0, 1], then the IEC piecewise transfer curve, then 8 bits. Under illuminant E a
//!   perfect reflector is (X, Y, Z) = (1, 1, 1), which is not sRGB white (linear ≈ (1.205,
//!   0.948, 0.909)); [`Adaptation::Bradford`] maps the E white onto the D65 white first
//!   (the default for E, see [`Illuminant::default_adaptation`]), [`Adaptation::None`] does not.
//!   Every display result ([`SrgbPixel`]) records the illuminant and adaptation it used.
//! - **Thin film**: time dependence e^{-iωt}; a wave that travelled optical path s carries
//!   e^{+i 2π s/λ} (docs/PHYSICS.md §1).

use std::sync::OnceLock;

// ---------------------------------------------------------------------------------------------
// Tabulated data
// ---------------------------------------------------------------------------------------------

/// CIE 1931 2° colour matching functions, 360–830 nm at 1 nm (CIE 15:2004 Table T.4).
const CIE1931_2DEG_CSV: &str = include_str!("../../data/cie1931_2deg.csv");
/// CIE standard illuminant D65 relative SPD, 360–830 nm at 1 nm (CIE 15:2004 Table T.1).
const CIE_D65_CSV: &str = include_str!("../../data/cie_d65.csv");

/// First wavelength of the shipped tables, in nanometres.
const TABLE_START_NM: f64 = 360.0;
/// Last wavelength of the shipped tables, in nanometres.
const TABLE_END_NM: f64 = 830.0;
/// Number of 1 nm rows in each shipped table (360..=830 nm).
const TABLE_ROWS: usize = 471;
/// Nanometres per metre.
const NM_PER_M: f64 = 1e9;

/// A table sampled every 1 nm from [`TABLE_START_NM`] to [`TABLE_END_NM`], `N` values per row.
struct Table1nm<const N: usize> {
    rows: Vec<[f64; N]>,
}

impl<const N: usize> Table1nm<N> {
    /// Parses the columns `columns` (by header name) of a CSV whose first column is
    /// `lambda_nm`; lines starting with '#' are comments. Panics on malformed shipped data
    /// (the data is compiled in, and a test reads every table).
    fn parse(csv: &str, columns: [&str; N]) -> Self {
        let mut reader = csv::ReaderBuilder::new()
            .comment(Some(b'#'))
            .from_reader(csv.as_bytes());
        let header = reader.headers().expect("table has a header").clone();
        assert_eq!(&header[0], "lambda_nm", "first column must be lambda_nm");
        let index = columns.map(|name| {
            header
                .iter()
                .position(|h| h == name)
                .unwrap_or_else(|| panic!("table has no column {name}"))
        });
        let rows: Vec<[f64; N]> = reader
            .records()
            .enumerate()
            .map(|(row, record)| {
                let fields = record.expect("table rows are CSV records of one length");
                let lambda_nm: f64 = fields[0].parse().expect("lambda_nm is a number");
                assert_eq!(
                    lambda_nm,
                    TABLE_START_NM + row as f64,
                    "table must be 1 nm steps"
                );
                index.map(|c| fields[c].parse().expect("table value is a number"))
            })
            .collect();
        assert_eq!(rows.len(), TABLE_ROWS, "table must cover 360..=830 nm");
        Table1nm { rows }
    }

    /// Linear interpolation at `lambda_m` (metres); zero outside 360–830 nm.
    fn at(&self, lambda_m: f64) -> [f64; N] {
        // Positions within 1e-6 nm of the table ends count as the ends (metre→nm rounding).
        const END_SLACK_NM: f64 = 1e-6;
        let x = lambda_m * NM_PER_M - TABLE_START_NM;
        let span = TABLE_END_NM - TABLE_START_NM;
        if !(x >= -END_SLACK_NM && x <= span + END_SLACK_NM) {
            return [0.0; N];
        }
        let x = x.clamp(0.0, span);
        let i = (x.floor() as usize).min(TABLE_ROWS - 2);
        let t = x - i as f64;
        let (a, b) = (self.rows[i], self.rows[i + 1]);
        std::array::from_fn(|c| (1.0 - t) * a[c] + t * b[c])
    }
}

/// The CIE 1931 2° standard observer colour matching functions x̄, ȳ, z̄ (dimensionless,
/// ȳ(555 nm) = 1), from CIE 15:2004 Table T.4 at 1 nm, 360–830 nm.
///
/// Values between table rows are linearly interpolated; outside 360–830 nm they are zero.
pub struct Cmf {
    table: Table1nm<3>,
}

impl Cmf {
    /// The shared, parsed CIE 1931 2° table (parsed once on first use).
    pub fn cie1931_2deg() -> &'static Cmf {
        static CMF: OnceLock<Cmf> = OnceLock::new();
        CMF.get_or_init(|| Cmf {
            table: Table1nm::parse(CIE1931_2DEG_CSV, ["xbar", "ybar", "zbar"]),
        })
    }

    /// [x̄, ȳ, z̄] at the vacuum wavelength `lambda_m` (metres).
    pub fn xyz_bar(&self, lambda_m: f64) -> [f64; 3] {
        self.table.at(lambda_m)
    }

    /// x̄ at `lambda_m` (metres).
    pub fn xbar(&self, lambda_m: f64) -> f64 {
        self.xyz_bar(lambda_m)[0]
    }

    /// ȳ (the photopic luminous efficiency V(λ)) at `lambda_m` (metres).
    pub fn ybar(&self, lambda_m: f64) -> f64 {
        self.xyz_bar(lambda_m)[1]
    }

    /// z̄ at `lambda_m` (metres).
    pub fn zbar(&self, lambda_m: f64) -> f64 {
        self.xyz_bar(lambda_m)[2]
    }
}

/// A CIE illuminant: the spectral power distribution lighting the scene.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Illuminant {
    /// Equal-energy illuminant E: S(λ) = 1 at every wavelength; white point (1, 1, 1).
    E,
    /// CIE standard illuminant D65 (average daylight, CCT ≈ 6504 K), S(560 nm) = 100
    /// (CIE 15:2004 Table T.1); the white point of sRGB.
    D65,
}

impl Illuminant {
    /// XYZ of a perfect reflector under this illuminant, Y = 1: [`WHITE_E`] or [`WHITE_D65`].
    pub fn white_xyz(self) -> [f64; 3] {
        match self {
            Illuminant::E => WHITE_E,
            Illuminant::D65 => WHITE_D65,
        }
    }

    /// The adaptation fringe uses unless told otherwise: Bradford for E (so a white object
    /// looks white on an sRGB display), none for D65 (already the sRGB white).
    pub fn default_adaptation(self) -> Adaptation {
        match self {
            Illuminant::E => Adaptation::Bradford,
            Illuminant::D65 => Adaptation::None,
        }
    }

    /// Short name for reports and CSV comments: "E" or "D65".
    pub fn name(self) -> &'static str {
        match self {
            Illuminant::E => "E",
            Illuminant::D65 => "D65",
        }
    }
}

/// Relative spectral power S(λ) of `illuminant` at `lambda_m` (metres), dimensionless.
///
/// E: 1 everywhere. D65: CIE 15:2004 Table T.1 normalised to S(560 nm) = 100, linearly
/// interpolated, held at its 780 nm value up to 830 nm (as in `data/cie_d65.csv`), and zero
/// outside 360–830 nm (where the colour matching functions are zero anyway).
pub fn illuminant_spd(illuminant: Illuminant, lambda_m: f64) -> f64 {
    match illuminant {
        Illuminant::E => 1.0,
        Illuminant::D65 => {
            static D65: OnceLock<Table1nm<1>> = OnceLock::new();
            D65.get_or_init(|| Table1nm::parse(CIE_D65_CSV, ["S_D65"]))
                .at(lambda_m)[0]
        }
    }
}

// ---------------------------------------------------------------------------------------------
// Wavelength grids and spectral integration
// ---------------------------------------------------------------------------------------------

/// Sample wavelengths λ_i (metres, strictly increasing) and quadrature weights w_i (metres)
/// such that ∫ f(λ) dλ ≈ Σ_i w_i f(λ_i).
#[derive(Clone, Debug, PartialEq)]
pub struct WavelengthGrid {
    /// Vacuum wavelengths in metres, finite, positive and strictly increasing.
    pub lambdas_m: Vec<f64>,
    /// Quadrature weights in metres, one per wavelength.
    pub weights: Vec<f64>,
}

impl WavelengthGrid {
    /// `count` equally spaced wavelengths from `min_m` to `max_m` inclusive (metres), with
    /// **trapezoid** weights: h = (max − min)/(count − 1), w = h/2 at both ends and h inside.
    ///
    /// Errors: `count` < 2 (the trapezoid rule needs two points; use [`Self::from_list`] for
    /// one wavelength), `min_m`/`max_m` not finite, not positive, or `min_m` ≥ `max_m`.
    pub fn uniform(min_m: f64, max_m: f64, count: usize) -> Result<Self, String> {
        if count < 2 {
            return Err(format!(
                "WavelengthGrid::uniform: count = {count}, need at least 2 samples \
                 (trapezoid weights); use from_list for a single wavelength"
            ));
        }
        if !(min_m.is_finite() && max_m.is_finite() && min_m > 0.0 && min_m < max_m) {
            return Err(format!(
                "WavelengthGrid::uniform: need finite 0 < min_m < max_m (metres), \
                 got min_m = {min_m:e}, max_m = {max_m:e}"
            ));
        }
        let h = (max_m - min_m) / (count - 1) as f64;
        let lambdas_m: Vec<f64> = (0..count).map(|i| min_m + h * i as f64).collect();
        let weights = (0..count)
            .map(|i| if i == 0 || i == count - 1 { 0.5 * h } else { h })
            .collect();
        let grid = WavelengthGrid { lambdas_m, weights };
        grid.validate()?;
        Ok(grid)
    }

    /// The full 1 nm grid of the CIE tables: 360–830 nm, 471 samples, trapezoid weights.
    pub fn cie_1nm() -> Self {
        Self::uniform(
            TABLE_START_NM / NM_PER_M,
            TABLE_END_NM / NM_PER_M,
            TABLE_ROWS,
        )
        .expect("the CIE 1 nm grid is valid")
    }

    /// A grid on the given wavelengths (metres, strictly increasing) with **trapezoid**
    /// weights for uneven spacing: w_i = (λ_{i+1} − λ_{i−1})/2 inside, (λ_1 − λ_0)/2 and
    /// (λ_{n−1} − λ_{n−2})/2 at the ends. A single wavelength gets weight 1 m (after the
    /// Y normalisation (C1) it is a monochrome observation and the weight cancels).
    ///
    /// Errors: empty list, a wavelength that is not finite or not positive, or a list that is
    /// not strictly increasing (the offending index is named).
    pub fn from_list(lambdas_m: Vec<f64>) -> Result<Self, String> {
        let n = lambdas_m.len();
        let weights = match n {
            0 => Vec::new(), // rejected by validate() below
            1 => vec![1.0],
            _ => (0..n)
                .map(|i| {
                    let lo = lambdas_m[i.saturating_sub(1)];
                    let hi = lambdas_m[(i + 1).min(n - 1)];
                    0.5 * (hi - lo)
                })
                .collect(),
        };
        let grid = WavelengthGrid { lambdas_m, weights };
        grid.validate()?;
        Ok(grid)
    }

    /// Checks the invariants (the fields are public, so a grid may be built by hand):
    /// at least one sample, equal lengths, wavelengths finite, positive, strictly
    /// increasing, weights finite and non-negative.
    pub fn validate(&self) -> Result<(), String> {
        let n = self.lambdas_m.len();
        if n == 0 {
            return Err("WavelengthGrid: no wavelengths (count = 0)".to_string());
        }
        if self.weights.len() != n {
            return Err(format!(
                "WavelengthGrid: {} weights for {n} wavelengths",
                self.weights.len()
            ));
        }
        for (i, &lambda) in self.lambdas_m.iter().enumerate() {
            if !(lambda.is_finite() && lambda > 0.0) {
                return Err(format!(
                    "WavelengthGrid: lambdas_m[{i}] = {lambda:e} m, must be finite and > 0"
                ));
            }
            if i > 0 && lambda <= self.lambdas_m[i - 1] {
                return Err(format!(
                    "WavelengthGrid: lambdas_m[{i}] = {lambda:e} m is not greater than \
                     lambdas_m[{}] = {:e} m (must be strictly increasing)",
                    i - 1,
                    self.lambdas_m[i - 1]
                ));
            }
        }
        if let Some(i) = self
            .weights
            .iter()
            .position(|w| !(w.is_finite() && *w >= 0.0))
        {
            return Err(format!(
                "WavelengthGrid: weights[{i}] = {:e} m, must be finite and >= 0",
                self.weights[i]
            ));
        }
        Ok(())
    }

    /// Number of samples.
    pub fn len(&self) -> usize {
        self.lambdas_m.len()
    }

    /// True if the grid has no samples (never true for a validated grid).
    pub fn is_empty(&self) -> bool {
        self.lambdas_m.is_empty()
    }
}

/// Precomputed tristimulus weights of a wavelength grid under one illuminant, equation (C1):
///
/// ```text
/// W_i = k · w_i · S(λ_i) · [x̄(λ_i), ȳ(λ_i), z̄(λ_i)],   k = 1 / Σ_i w_i S(λ_i) ȳ(λ_i)
/// XYZ = Σ_i W_i ρ(λ_i)
/// ```
///
/// k is computed on the grid itself, so a spectrum of ones gives Y = 1 exactly even on a
/// coarse grid.
#[derive(Clone, Debug)]
pub struct SpectralIntegrator {
    illuminant: Illuminant,
    lambdas_m: Vec<f64>,
    weights_xyz: Vec<[f64; 3]>,
}

impl SpectralIntegrator {
    /// Builds the weights (C1) for `grid` under `illuminant`.
    ///
    /// Errors: an invalid grid, or a grid on which Σ w_i S(λ_i) ȳ(λ_i) = 0 (no sample
    /// inside 360–830 nm where ȳ > 0), where Y cannot be normalised.
    pub fn new(grid: &WavelengthGrid, illuminant: Illuminant) -> Result<Self, String> {
        grid.validate()?;
        let cmf = Cmf::cie1931_2deg();
        let unnormalised: Vec<[f64; 3]> = grid
            .lambdas_m
            .iter()
            .zip(&grid.weights)
            .map(|(&lambda, &w)| {
                let s = w * illuminant_spd(illuminant, lambda);
                cmf.xyz_bar(lambda).map(|bar| s * bar)
            })
            .collect();
        let y_white: f64 = unnormalised.iter().map(|w| w[1]).sum();
        if y_white.is_nan() || y_white <= 0.0 {
            return Err(format!(
                "SpectralIntegrator: the grid ({} samples, {:e}..{:e} m) sees no luminance \
                 (sum of w S ybar = {y_white:e}); it needs samples inside 360-830 nm",
                grid.len(),
                grid.lambdas_m[0],
                grid.lambdas_m[grid.len() - 1]
            ));
        }
        let k = 1.0 / y_white;
        Ok(SpectralIntegrator {
            illuminant,
            lambdas_m: grid.lambdas_m.clone(),
            weights_xyz: unnormalised.iter().map(|w| w.map(|c| k * c)).collect(),
        })
    }

    /// The illuminant the weights include.
    pub fn illuminant(&self) -> Illuminant {
        self.illuminant
    }

    /// Sample wavelengths in metres.
    pub fn lambdas_m(&self) -> &[f64] {
        &self.lambdas_m
    }

    /// Number of samples.
    pub fn len(&self) -> usize {
        self.weights_xyz.len()
    }

    /// True if there are no samples (never, for a constructed integrator).
    pub fn is_empty(&self) -> bool {
        self.weights_xyz.is_empty()
    }

    /// The normalised weights W_i = k w_i S(λ_i) (x̄, ȳ, z̄)(λ_i) of sample `i` (C1).
    pub fn sample_weights(&self, i: usize) -> [f64; 3] {
        self.weights_xyz[i]
    }

    /// XYZ (Y = 1 for a perfect reflector) of a reflectance/transmittance spectrum given at the
    /// grid's wavelengths (dimensionless, one value per sample): XYZ = Σ_i W_i ρ_i.
    ///
    /// # Panics
    /// If `spectrum.len()` differs from the number of samples.
    pub fn xyz(&self, spectrum: &[f64]) -> [f64; 3] {
        assert_eq!(
            spectrum.len(),
            self.len(),
            "SpectralIntegrator::xyz: spectrum has {} values, grid has {} samples",
            spectrum.len(),
            self.len()
        );
        let mut xyz = [0.0; 3];
        for (w, &rho) in self.weights_xyz.iter().zip(spectrum) {
            for c in 0..3 {
                xyz[c] += w[c] * rho;
            }
        }
        xyz
    }

    /// XYZ of a perfect reflector on this grid: Σ_i W_i, with Y = 1 by construction.
    pub fn white_xyz(&self) -> [f64; 3] {
        self.weights_xyz
            .iter()
            .fold([0.0; 3], |sum, w| std::array::from_fn(|c| sum[c] + w[c]))
    }

    /// A zeroed XYZ image of `pixel_count` pixels to stream per-wavelength images into.
    pub fn accumulator(&self, pixel_count: usize) -> XyzAccumulator<'_> {
        XyzAccumulator {
            integrator: self,
            xyz: vec![[0.0; 3]; pixel_count],
            sample_seen: vec![false; self.len()],
        }
    }
}

/// An XYZ image built one wavelength at a time, so a renderer never holds all
/// per-wavelength images: pixel p receives Σ_i W_i I_i(p) (C1), where I_i is the monochrome
/// image (relative intensity: 1 = the illuminant's own level) at sample i.
#[derive(Clone, Debug)]
pub struct XyzAccumulator<'a> {
    integrator: &'a SpectralIntegrator,
    xyz: Vec<[f64; 3]>,
    sample_seen: Vec<bool>,
}

impl XyzAccumulator<'_> {
    /// Adds the monochrome image of sample `sample_index` (one relative intensity per pixel).
    ///
    /// Errors: `sample_index` out of range or an image of the wrong size (nothing is added).
    pub fn add_image(&mut self, sample_index: usize, image: &[f64]) -> Result<(), String> {
        if sample_index >= self.sample_seen.len() {
            return Err(format!(
                "XyzAccumulator::add_image: sample_index {sample_index} out of range \
                 (grid has {} samples)",
                self.sample_seen.len()
            ));
        }
        if image.len() != self.xyz.len() {
            return Err(format!(
                "XyzAccumulator::add_image: image has {} pixels, accumulator has {}",
                image.len(),
                self.xyz.len()
            ));
        }
        let w = self.integrator.weights_xyz[sample_index];
        for (pixel, &intensity) in self.xyz.iter_mut().zip(image) {
            for c in 0..3 {
                pixel[c] += w[c] * intensity;
            }
        }
        self.sample_seen[sample_index] = true;
        Ok(())
    }

    /// Adds one pixel's relative intensity at sample `sample_index`.
    ///
    /// # Panics
    /// If `sample_index` or `pixel` is out of range.
    pub fn add_sample(&mut self, sample_index: usize, pixel: usize, intensity: f64) {
        let w = self.integrator.weights_xyz[sample_index];
        for (sum, weight) in self.xyz[pixel].iter_mut().zip(w) {
            *sum += weight * intensity;
        }
        self.sample_seen[sample_index] = true;
    }

    /// The XYZ image so far (complete only once every sample has been added).
    pub fn xyz_image(&self) -> &[[f64; 3]] {
        &self.xyz
    }

    /// Sample indices to which nothing has been added yet.
    pub fn missing_samples(&self) -> Vec<usize> {
        (0..self.sample_seen.len())
            .filter(|&i| !self.sample_seen[i])
            .collect()
    }

    /// The finished XYZ image. Errors if some sample never received a contribution (a
    /// forgotten wavelength would silently shift every colour).
    pub fn finish(self) -> Result<Vec<[f64; 3]>, String> {
        let missing = self.missing_samples();
        if missing.is_empty() {
            Ok(self.xyz)
        } else {
            Err(format!(
                "XyzAccumulator::finish: {} of {} samples never added (indices {:?})",
                missing.len(),
                self.sample_seen.len(),
                missing
            ))
        }
    }
}

// ---------------------------------------------------------------------------------------------
// XYZ → sRGB
// ---------------------------------------------------------------------------------------------

/// White point of illuminant E, Y = 1: (1, 1, 1).
pub const WHITE_E: [f64; 3] = [1.0, 1.0, 1.0];

/// White point of D65 for the CIE 1931 2° observer, Y = 1: (0.95047, 1, 1.08883)
/// (ASTM E308, from the CIE D65 table; CIE 15:2004 Table T.3 rounds it to 95.04, 100, 108.88).
pub const WHITE_D65: [f64; 3] = [0.95047, 1.0, 1.08883];

/// XYZ (D65, Y = 1) → linear sRGB, IEC 61966-2-1:1999 §5.2 (the standard's 4-decimal matrix,
/// also used by colour-science).
pub const XYZ_TO_LINEAR_SRGB: [[f64; 3]; 3] = [
    [3.2406, -1.5372, -0.4986],
    [-0.9689, 1.8758, 0.0415],
    [0.0557, -0.2040, 1.0570],
];

/// Bradford cone-response matrix M_BFD (Lam 1985; Hunt, *The Reproduction of Colour*, and
/// CIE 160:2004 use the same numbers).
pub const BRADFORD: [[f64; 3]; 3] = [
    [0.8951, 0.2664, -0.1614],
    [-0.7502, 1.7135, 0.0367],
    [0.0389, -0.0685, 1.0296],
];

/// Inverse of [`BRADFORD`] to 7 decimals (as tabulated by B. Lindbloom, "Chromatic Adaptation").
pub const BRADFORD_INVERSE: [[f64; 3]; 3] = [
    [0.9869929, -0.1470543, 0.1599627],
    [0.4323053, 0.5183603, 0.0492912],
    [-0.0085287, 0.0400428, 0.9684867],
];

/// Chromatic adaptation applied before the XYZ → sRGB matrix.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Adaptation {
    /// Bradford von Kries transform from the illuminant's white to the D65 white
    /// ([`bradford_adapt`]); the identity under D65.
    Bradford,
    /// No adaptation: XYZ goes straight into the sRGB matrix (an E white shows pinkish).
    None,
}

impl Adaptation {
    /// Short name for reports and CSV comments: "Bradford" or "none".
    pub fn name(self) -> &'static str {
        match self {
            Adaptation::Bradford => "Bradford",
            Adaptation::None => "none",
        }
    }
}

/// m · v for a 3×3 matrix.
fn mat3_mul_vec(m: &[[f64; 3]; 3], v: [f64; 3]) -> [f64; 3] {
    std::array::from_fn(|r| m[r][0] * v[0] + m[r][1] * v[1] + m[r][2] * v[2])
}

/// XYZ (D65-referred, Y = 1 for white) → linear sRGB, IEC 61966-2-1:1999 eq. (5.2) with
/// [`XYZ_TO_LINEAR_SRGB`]. Not clipped: out-of-gamut colours give components < 0 or > 1.
pub fn xyz_to_linear_srgb(xyz: [f64; 3]) -> [f64; 3] {
    mat3_mul_vec(&XYZ_TO_LINEAR_SRGB, xyz)
}

/// Bradford chromatic adaptation (von Kries scaling in the Bradford cone space):
///
/// ```text
/// XYZ_out = M⁻¹ · diag(ρ_to / ρ_from) · M · XYZ,   ρ = M · XYZ_white,   M = BRADFORD
/// ```
///
/// `from_white`, `to_white`: XYZ of the source and destination whites (any common scale).
/// Maps `from_white` onto `to_white`.
pub fn bradford_adapt(xyz: [f64; 3], from_white: [f64; 3], to_white: [f64; 3]) -> [f64; 3] {
    let rho_from = mat3_mul_vec(&BRADFORD, from_white);
    let rho_to = mat3_mul_vec(&BRADFORD, to_white);
    let cone = mat3_mul_vec(&BRADFORD, xyz);
    let scaled = std::array::from_fn(|c| cone[c] * rho_to[c] / rho_from[c]);
    mat3_mul_vec(&BRADFORD_INVERSE, scaled)
}

/// XYZ seen under `illuminant` → D65-referred XYZ ready for the sRGB matrix, using
/// `adaptation` (Bradford from the illuminant's white point to [`WHITE_D65`], or none).
pub fn adapt_to_d65(xyz: [f64; 3], illuminant: Illuminant, adaptation: Adaptation) -> [f64; 3] {
    match (illuminant, adaptation) {
        (Illuminant::D65, _) | (_, Adaptation::None) => xyz,
        (Illuminant::E, Adaptation::Bradford) => bradford_adapt(xyz, WHITE_E, WHITE_D65),
    }
}

/// The sRGB transfer curve (IEC 61966-2-1:1999 eq. (5.3)) of a linear value, after clipping it
/// to [0, 1]:
///
/// ```text
/// V = 12.92 L                    for L ≤ 0.0031308
/// V = 1.055 L^(1/2.4) − 0.055    otherwise
/// ```
pub fn srgb_encode(linear: f64) -> f64 {
    let l = linear.clamp(0.0, 1.0);
    if l <= 0.0031308 {
        12.92 * l
    } else {
        1.055 * l.powf(1.0 / 2.4) - 0.055
    }
}

/// Inverse of [`srgb_encode`] on [0, 1] (IEC 61966-2-1:1999 eq. (5.1)): V ≤ 0.04045 → V/12.92,
/// else ((V + 0.055)/1.055)^2.4. The input is clipped to [0, 1].
pub fn srgb_decode(encoded: f64) -> f64 {
    let v = encoded.clamp(0.0, 1.0);
    if v <= 0.04045 {
        v / 12.92
    } else {
        ((v + 0.055) / 1.055).powf(2.4)
    }
}

/// Linear sRGB → 8-bit sRGB: clip to [0, 1], [`srgb_encode`], round(255 V).
pub fn to_srgb8(linear_srgb: [f64; 3]) -> [u8; 3] {
    linear_srgb.map(|l| (255.0 * srgb_encode(l)).round() as u8)
}

/// An XYZ colour on an sRGB display, with the choices that produced it.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct SrgbPixel {
    /// Linear sRGB after adaptation, **before** clipping (may lie outside [0, 1]).
    pub linear_srgb: [f64; 3],
    /// 8-bit sRGB after clipping and the transfer curve.
    pub srgb8: [u8; 3],
    /// How far the furthest channel lay outside [0, 1] before clipping (0 = in gamut).
    pub clip_excess: f64,
    /// Illuminant the XYZ was computed under.
    pub illuminant: Illuminant,
    /// Adaptation applied before the sRGB matrix.
    pub adaptation: Adaptation,
}

impl SrgbPixel {
    /// True if any channel had to be clipped (strictly outside [0, 1]). Strict on purpose:
    /// even the perfect reflector under D65 exceeds 1 by 7.5e-5 in G (4-decimal IEC matrix),
    /// so compare [`Self::clip_excess`](SrgbPixel::clip_excess) with a tolerance where that matters.
    pub fn clipped(&self) -> bool {
        self.clip_excess > 0.0
    }
}

/// How far the furthest component of `linear` lies outside [0, 1] (0 if none does).
fn clip_excess(linear: [f64; 3]) -> f64 {
    linear
        .iter()
        .map(|&l| (-l).max(l - 1.0).max(0.0))
        .fold(0.0, f64::max)
}

/// XYZ under `illuminant` (Y = 1 for the perfect reflector) → 8-bit sRGB: [`adapt_to_d65`],
/// [`xyz_to_linear_srgb`], clip, [`srgb_encode`]. The result says whether it clipped and which
/// illuminant and adaptation were used.
pub fn xyz_to_srgb8(xyz: [f64; 3], illuminant: Illuminant, adaptation: Adaptation) -> SrgbPixel {
    let linear_srgb = xyz_to_linear_srgb(adapt_to_d65(xyz, illuminant, adaptation));
    SrgbPixel {
        linear_srgb,
        srgb8: to_srgb8(linear_srgb),
        clip_excess: clip_excess(linear_srgb),
        illuminant,
        adaptation,
    }
}

/// Display colour (linear sRGB, brightest channel = 1) of monochromatic light of vacuum
/// wavelength `lambda_m` (metres), to tint a monochrome image "in the hue of its wavelength".
///
/// Method: XYZ = (x̄, ȳ, z̄)(λ) (CIE 1931 2°, no illuminant: the light is the source),
/// linear sRGB by the IEC 61966-2-1 matrix, negative components (spectral colours lie outside
/// the sRGB gamut) set to 0, then divided by the largest component. This keeps the dominant
/// hue but desaturates towards the gamut edge; it is a display convention, not colorimetry.
/// Returns [0, 0, 0] where no channel is positive (outside 360–830 nm).
pub fn wavelength_to_srgb_hue(lambda_m: f64) -> [f64; 3] {
    let linear = xyz_to_linear_srgb(Cmf::cie1931_2deg().xyz_bar(lambda_m)).map(|c| c.max(0.0));
    let peak = linear.iter().copied().fold(0.0, f64::max);
    if peak > 0.0 {
        linear.map(|c| c / peak)
    } else {
        [0.0; 3]
    }
}

// ---------------------------------------------------------------------------------------------
// CIELAB and CIEDE2000
// ---------------------------------------------------------------------------------------------

/// XYZ → CIE 1976 L*a*b* relative to `white` (XYZ of the reference white, same scale as
/// `xyz`), CIE 15:2004 §8.2.1, with the exact CIE constants ε = 216/24389, κ = 24389/27:
///
/// ```text
/// f(t) = t^(1/3) if t > ε, else (κ t + 16)/116
/// L* = 116 f(Y/Yn) − 16,  a* = 500 (f(X/Xn) − f(Y/Yn)),  b* = 200 (f(Y/Yn) − f(Z/Zn))
/// ```
pub fn xyz_to_lab(xyz: [f64; 3], white: [f64; 3]) -> [f64; 3] {
    const EPSILON: f64 = 216.0 / 24389.0;
    const KAPPA: f64 = 24389.0 / 27.0;
    let f = |t: f64| {
        if t > EPSILON {
            t.cbrt()
        } else {
            (KAPPA * t + 16.0) / 116.0
        }
    };
    let [fx, fy, fz] = std::array::from_fn(|c| f(xyz[c] / white[c]));
    [116.0 * fy - 16.0, 500.0 * (fx - fy), 200.0 * (fy - fz)]
}

/// Hue angle atan2(b, a) in degrees in [0, 360), and 0 for a = b = 0 (Sharma et al. eq. 4).
fn hue_deg(a: f64, b: f64) -> f64 {
    if a == 0.0 && b == 0.0 {
        0.0
    } else {
        b.atan2(a).to_degrees().rem_euclid(360.0)
    }
}

/// CIEDE2000 colour difference ΔE00 between two CIELAB colours (kL = kC = kH = 1), following
/// G. Sharma, W. Wu, E. N. Dalal, "The CIEDE2000 color-difference formula: implementation
/// notes, supplementary test data, and mathematical observations", Color Res. Appl. 30(1),
/// 21–30 (2005), equations (1)–(22); CIE 142-2001. Angles in degrees as in the paper.
pub fn delta_e_2000(lab1: [f64; 3], lab2: [f64; 3]) -> f64 {
    let [l1, a1, b1] = lab1;
    let [l2, a2, b2] = lab2;
    const POW25_7: f64 = 6_103_515_625.0; // 25^7

    // Step 1: a' (eq. 2–3), C' and h' (eq. 4–6).
    let c_mean_ab = 0.5 * (a1.hypot(b1) + a2.hypot(b2));
    let c7 = c_mean_ab.powi(7);
    let g = 0.5 * (1.0 - (c7 / (c7 + POW25_7)).sqrt());
    let (a1p, a2p) = ((1.0 + g) * a1, (1.0 + g) * a2);
    let (c1p, c2p) = (a1p.hypot(b1), a2p.hypot(b2));
    let (h1p, h2p) = (hue_deg(a1p, b1), hue_deg(a2p, b2));

    // Step 2: ΔL', ΔC', Δh', ΔH' (eq. 8–11).
    let delta_lp = l2 - l1;
    let delta_cp = c2p - c1p;
    let chroma_product = c1p * c2p;
    let delta_hp = if chroma_product == 0.0 {
        0.0
    } else {
        let d = h2p - h1p;
        if d > 180.0 {
            d - 360.0
        } else if d < -180.0 {
            d + 360.0
        } else {
            d
        }
    };
    let delta_big_hp = 2.0 * chroma_product.sqrt() * (0.5 * delta_hp).to_radians().sin();

    // Step 3: means, weighting functions and rotation term (eq. 12–22).
    let l_mean = 0.5 * (l1 + l2);
    let c_mean = 0.5 * (c1p + c2p);
    let h_mean = if chroma_product == 0.0 {
        h1p + h2p
    } else if (h1p - h2p).abs() <= 180.0 {
        0.5 * (h1p + h2p)
    } else if h1p + h2p < 360.0 {
        0.5 * (h1p + h2p + 360.0)
    } else {
        0.5 * (h1p + h2p - 360.0)
    };
    let cos_deg = |x: f64| x.to_radians().cos();
    let t = 1.0 - 0.17 * cos_deg(h_mean - 30.0)
        + 0.24 * cos_deg(2.0 * h_mean)
        + 0.32 * cos_deg(3.0 * h_mean + 6.0)
        - 0.20 * cos_deg(4.0 * h_mean - 63.0);
    let delta_theta = 30.0 * (-((h_mean - 275.0) / 25.0).powi(2)).exp();
    let cm7 = c_mean.powi(7);
    let r_c = 2.0 * (cm7 / (cm7 + POW25_7)).sqrt();
    let l50 = (l_mean - 50.0).powi(2);
    let s_l = 1.0 + 0.015 * l50 / (20.0 + l50).sqrt();
    let s_c = 1.0 + 0.045 * c_mean;
    let s_h = 1.0 + 0.015 * c_mean * t;
    let r_t = -(2.0 * delta_theta).to_radians().sin() * r_c;

    let (dl, dc, dh) = (delta_lp / s_l, delta_cp / s_c, delta_big_hp / s_h);
    (dl * dl + dc * dc + dh * dh + r_t * dc * dh).sqrt()
}

// ---------------------------------------------------------------------------------------------
// Newton's interference colours
// ---------------------------------------------------------------------------------------------

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
    for &d in thicknesses_m {
        validate_film(n_film, d)?;
    }
    let integrator = SpectralIntegrator::new(grid, illuminant)?;
    let mut spectrum = vec![0.0; integrator.len()];
    let rows = thicknesses_m
        .iter()
        .map(|&thickness_m| {
            for (r, &lambda) in spectrum.iter_mut().zip(integrator.lambdas_m()) {
                *r = soap_film_reflectance(n_film, thickness_m, lambda);
            }
            let xyz = integrator.xyz(&spectrum);
            let pixel = xyz_to_srgb8(xyz, illuminant, adaptation);
            NewtonRow {
                thickness_m,
                xyz,
                linear_srgb: pixel.linear_srgb,
                srgb8: pixel.srgb8,
                clip_excess: pixel.clip_excess,
            }
        })
        .collect();
    Ok(rows)
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
    let comment = format!(
        "# fringe::output::colour::newton_sequence: soap film n_film={n_film} in air, normal incidence, \
         Airy reflectance; illuminant={}, adaptation={}, CIE 1931 2deg, {} samples {:.3}..{:.3} nm\n",
        illuminant.name(),
        adaptation.name(),
        grid.len(),
        grid.lambdas_m[0] * NM_PER_M,
        grid.lambdas_m[grid.len() - 1] * NM_PER_M,
    );
    let table = crate::output::report::csv_text(
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
    Ok(comment + &table)
}
