//! Optically isotropic, lossless media: refractive index models (dispersion) and the
//! coherence rules a surface applies to the rays it creates (paper §3.4).
//!
//! Wavelengths are vacuum wavelengths in metres. The dispersion formulas are empirical fits
//! with a stated validity range; evaluating outside it is an error, never a silent
//! extrapolation. Complex (absorbing) indices are out of scope (docs/PHYSICS.md §1) and rejected
//! where a case file is read.

use serde::{Deserialize, Serialize};

/// A refractive-index model n(λ0).
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case", deny_unknown_fields)]
pub enum Dispersion {
    /// n independent of wavelength.
    Constant {
        /// The index.
        n: f64,
    },
    /// Cauchy: n = a + b/λ² + c/λ⁴ with λ in micrometres; valid in `[min_um, max_um]`.
    Cauchy {
        /// Constant term.
        a: f64,
        /// b, µm².
        b_um2: f64,
        /// c, µm⁴.
        c_um4: f64,
        /// Shortest valid vacuum wavelength, µm.
        min_um: f64,
        /// Longest valid vacuum wavelength, µm.
        max_um: f64,
    },
    /// Sellmeier: n² = 1 + Σ B_k λ²/(λ² − C_k) with λ in micrometres (C_k in µm²);
    /// valid in `[min_um, max_um]`.
    Sellmeier {
        /// B_1..B_3 (dimensionless).
        b: [f64; 3],
        /// C_1..C_3, µm².
        c_um2: [f64; 3],
        /// Shortest valid vacuum wavelength, µm.
        min_um: f64,
        /// Longest valid vacuum wavelength, µm.
        max_um: f64,
    },
}

/// Errors of index evaluation.
#[derive(Clone, Debug, PartialEq, thiserror::Error)]
pub enum IndexError {
    /// The wavelength is outside the formula's validity range.
    #[error(
        "wavelength {lambda_nm} nm is outside the validity range {min_nm}–{max_nm} nm of the dispersion formula"
    )]
    OutOfRange {
        /// The vacuum wavelength asked for, nm.
        lambda_nm: f64,
        /// Shortest valid vacuum wavelength, nm.
        min_nm: f64,
        /// Longest valid vacuum wavelength, nm.
        max_nm: f64,
    },
    /// The formula gives an index that is not finite or not > 0 there.
    #[error(
        "the dispersion formula gives a non-physical index {n} at {lambda_nm} nm (must be finite and > 0)"
    )]
    NonPhysical {
        /// The index the formula gives.
        n: f64,
        /// The vacuum wavelength, nm.
        lambda_nm: f64,
    },
}

impl Dispersion {
    /// Schott N-BK7 Sellmeier coefficients (Schott data sheet, valid 0.3–2.5 µm;
    /// n(587.6 nm) = 1.5168).
    pub fn bk7() -> Self {
        Dispersion::Sellmeier {
            b: [1.039_612_12, 0.231_792_344, 1.010_469_45],
            c_um2: [0.006_000_698_67, 0.020_017_914_4, 103.560_653],
            min_um: 0.3,
            max_um: 2.5,
        }
    }

    /// Refractive index at vacuum wavelength `lambda_m` (metres).
    pub fn index(&self, lambda_m: f64) -> Result<f64, IndexError> {
        let l_um = lambda_m * 1e6;
        let check = |min_um: f64, max_um: f64| {
            if !(l_um >= min_um && l_um <= max_um) {
                Err(IndexError::OutOfRange {
                    lambda_nm: l_um * 1e3,
                    min_nm: min_um * 1e3,
                    max_nm: max_um * 1e3,
                })
            } else {
                Ok(())
            }
        };
        let n = match self {
            Dispersion::Constant { n } => *n,
            Dispersion::Cauchy {
                a,
                b_um2,
                c_um4,
                min_um,
                max_um,
            } => {
                check(*min_um, *max_um)?;
                let l2 = l_um * l_um;
                a + b_um2 / l2 + c_um4 / (l2 * l2)
            }
            Dispersion::Sellmeier {
                b,
                c_um2,
                min_um,
                max_um,
            } => {
                check(*min_um, *max_um)?;
                let l2 = l_um * l_um;
                let n2 = 1.0 + (0..3).map(|k| b[k] * l2 / (l2 - c_um2[k])).sum::<f64>();
                n2.sqrt()
            }
        };
        if n.is_finite() && n > 0.0 {
            Ok(n)
        } else {
            Err(IndexError::NonPhysical {
                n,
                lambda_nm: l_um * 1e3,
            })
        }
    }
}

/// A named medium.
#[derive(Clone, Debug, PartialEq)]
pub struct Medium {
    /// The medium's name (as in the case file; for messages).
    pub name: String,
    /// Its refractive index n(λ0).
    pub dispersion: Dispersion,
}

impl Medium {
    /// A medium of constant index `n`.
    pub fn constant(name: &str, n: f64) -> Self {
        Medium {
            name: name.to_string(),
            dispersion: Dispersion::Constant { n },
        }
    }
    /// Vacuum, n = 1.
    pub fn vacuum() -> Self {
        Self::constant("vacuum", 1.0)
    }
    /// The refractive index at vacuum wavelength `lambda_m` (metres), or why there is none.
    pub fn index(&self, lambda_m: f64) -> Result<f64, IndexError> {
        self.dispersion.index(lambda_m)
    }
}

/// What a surface does to the coherence id of the rays it creates (paper §3.4): each child
/// either inherits the parent's id or loses coherence (id := 0, coherent with nothing).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct CoherenceRules {
    /// The reflected child keeps the parent's coherence id.
    pub reflected_keeps: bool,
    /// The refracted child keeps the parent's coherence id.
    pub refracted_keeps: bool,
}

impl Default for CoherenceRules {
    fn default() -> Self {
        CoherenceRules {
            reflected_keeps: true,
            refracted_keeps: true,
        }
    }
}
