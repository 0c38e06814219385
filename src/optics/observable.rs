//! What a probe measures: one definition per observable (docs/PHYSICS.md §3a).
//!
//! - **Field intensity** I = |E|² summed over coherence groups (paper eq. 6): what a screen point
//!   in the ambient medium records, in units of the source's |E|².
//! - **Power reflectance R / transmittance T** of a plane wave: the fraction of the incident
//!   power crossing a plane of unit normal N that leaves in the observed far-field direction,
//!   `R = |r|²`, `T = (n_out |d_out·N|)/(n_in |d_in·N|)·|t|²` per polarization, so that R + T = 1
//!   for a lossless scene (B&W §1.5.3, eq. 21–22). A `far_field` probe measures R or T.
//!
//! A traced value and a closed form are compared only when they are the same observable:
//! every probe declares what it measures ([`Observable`]), every closed form what it returns
//! ([`Returns`]), and `check_match` refuses a mismatch before anything is traced.

use serde::Serialize;

/// A measured quantity.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize)]
#[serde(rename_all = "snake_case")]
pub enum Observable {
    /// |E|², in units of the source's |E|² (the paper's intensity I, eq. 6).
    FieldIntensity,
    /// Power reflectance R of a plane wave (dimensionless).
    Reflectance,
    /// Power transmittance T of a plane wave (dimensionless), with the
    /// (n_out cos θ_out)/(n_in cos θ_in) factor of `power_factor`.
    Transmittance,
}

impl Observable {
    /// The observable with its unit, for table headers and plot axes.
    pub fn label(self) -> &'static str {
        match self {
            Observable::FieldIntensity => "field intensity |E|² (source |E|² = 1)",
            Observable::Reflectance => "power reflectance R",
            Observable::Transmittance => "power transmittance T",
        }
    }

    /// Whether this is a power fraction of a plane wave (R or T).
    pub(crate) fn is_power(self) -> bool {
        !matches!(self, Observable::FieldIntensity)
    }
}

/// What a closed form returns.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Returns {
    /// Field intensity |E|² at a screen point.
    FieldIntensity,
    /// A power fraction R or T of a plane wave (which one follows from the probe's side).
    Power,
    /// The field of each beam, turned into whatever the probe measures (the conversion of
    /// `power_factor` applied to the closed form's |E|², independently of the trace).
    AsProbe,
}

/// Whether a closed form returning `returns` may be compared with a probe measuring `measured`;
/// the error says what to change.
pub fn check_match(model: &str, returns: Returns, measured: Observable) -> Result<(), String> {
    match (returns, measured.is_power()) {
        (Returns::AsProbe, _) | (Returns::FieldIntensity, false) | (Returns::Power, true) => Ok(()),
        (Returns::FieldIntensity, true) => Err(format!(
            "{model} returns the field intensity |E|² at screen points, but the probe measures \
             the {} of a plane wave (a far_field observer): observe it at points",
            measured.label()
        )),
        (Returns::Power, false) => Err(format!(
            "{model} returns a power reflectance or transmittance (R or T of a plane wave), but \
             the probe measures the {}: observe it with a far_field observer",
            measured.label()
        )),
    }
}

/// The factor that turns the far-field |E_out|² of a plane wave (unit incident |E|²) into the
/// power fraction crossing a plane of unit normal `normal`:
/// `(n_out |d_out·N|)/(n_in |d_in·N|)` (B&W §1.5.3: the energy flux through the boundary is
/// n cos θ |E|² up to a constant common to both waves). It is 1 for a reflected wave.
pub fn power_factor(
    n_in: f64,
    d_in: glam::DVec3,
    n_out: f64,
    d_out: glam::DVec3,
    normal: glam::DVec3,
) -> f64 {
    let n = normal.normalize();
    (n_out * d_out.normalize().dot(n).abs()) / (n_in * d_in.normalize().dot(n).abs())
}
