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

mod cie;
mod difference;
mod newton;
mod spectrum;
mod srgb;

pub use cie::*;
pub use difference::*;
pub use newton::*;
pub use spectrum::*;
pub use srgb::*;
