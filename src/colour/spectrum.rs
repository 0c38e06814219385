//! Wavelength grids, spectral integration to CIE XYZ (C1), and XYZ images built one
//! wavelength at a time.

use super::*;

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
