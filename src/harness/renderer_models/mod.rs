//! The thin-layer models production renderers ship, written from their published formulas and
//! measured against the exact Airy sum of [`crate::harness::analytic::plate`] (docs/PHYSICS.md §5).
//!
//! Every model here takes the same three-medium stack as the exact closed form, a
//! [`Film`] n1 | n2 (thickness d) | n3 lit from n1 at cos θ1, and returns the **power
//! reflectance** R (dimensionless, the observable of docs/PHYSICS.md §3a for a plane wave observed in
//! the far field) of unpolarized light, or its colour. Conventions are the crate's (docs/PHYSICS.md
//! §1): time dependence e^{-iωt}, phase e^{+iβ} for the round trip β = (4π/λ) n2 d cos θ2,
//! Fresnel amplitudes (P1)–(P6) in the s/p frame of `src/optics/fresnel.rs`; wavelengths in metres.
//!
//! | model | module | what it drops |
//! | --- | --- | --- |
//! | [`Model::ThinDielectricAveraged`] | [`incoherent`] | the phase, and s/p (pbrt-v4 `ThinDielectricBxDF`, Mitsuba 3 `thindielectric`) |
//! | [`Model::IncoherentPerPolarization`] | [`incoherent`] | the phase only |
//! | [`Model::BelcourBarla`] | [`belcour_barla`] | the exact spectral integral (fitted sensitivities, 3 Fourier orders) |
//! | [`Model::TirPhaseZero`] | [`tir_phase_zero`] | the phase of total internal reflection at the film's back face |
//!
//! [`study`] sweeps them over angle × thickness × wavelength (`fringe models`).

pub mod belcour_barla;
pub mod incoherent;
pub mod study;
pub mod tir_phase_zero;

pub use crate::harness::analytic::plate::{Film, Pol};

/// A production model of a thin layer, by the name the error table uses.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub enum Model {
    /// pbrt-v4 `ThinDielectricBxDF` / Mitsuba 3 `thindielectric`: the incoherent plate on the
    /// polarization-averaged Fresnel reflectance ([`incoherent::averaged`]).
    ThinDielectricAveraged,
    /// The same incoherent plate done per polarization, then averaged
    /// ([`incoherent::per_polarization`]).
    IncoherentPerPolarization,
    /// Belcour & Barla 2017, the model behind glTF `KHR_materials_iridescence`
    /// ([`belcour_barla`]).
    BelcourBarla,
    /// The exact Airy amplitude with the phase of total internal reflection at the 2→3 face
    /// set to zero ([`tir_phase_zero`]).
    TirPhaseZero,
}

impl Model {
    /// Every model, in the order of the error table.
    pub const ALL: [Model; 4] = [
        Model::ThinDielectricAveraged,
        Model::IncoherentPerPolarization,
        Model::BelcourBarla,
        Model::TirPhaseZero,
    ];

    /// The model's name in tables and files.
    pub fn name(self) -> &'static str {
        match self {
            Model::ThinDielectricAveraged => "pbrt_mitsuba_thin_dielectric",
            Model::IncoherentPerPolarization => "incoherent_per_polarization",
            Model::BelcourBarla => "belcour_barla_2017",
            Model::TirPhaseZero => "tir_phase_zero",
        }
    }

    /// Unpolarized power reflectance R(λ) of the model (dimensionless). For Belcour–Barla this
    /// is its Fourier series at one wavelength with the orders it ships
    /// ([`belcour_barla::ORDERS`]), i.e. its Airy sum with the spectral integration bypassed.
    pub fn reflectance(self, film: &Film, cos_theta_1: f64, lambda_m: f64) -> f64 {
        match self {
            Model::ThinDielectricAveraged => incoherent::averaged(film, cos_theta_1),
            Model::IncoherentPerPolarization => incoherent::per_polarization(film, cos_theta_1),
            Model::BelcourBarla => {
                belcour_barla::reflectance(film, cos_theta_1, lambda_m, belcour_barla::ORDERS)
            }
            Model::TirPhaseZero => tir_phase_zero::reflectance(film, cos_theta_1, lambda_m),
        }
    }
}

/// Exact unpolarized reflectance ½(R_s + R_p) of the Airy sum (docs/PHYSICS.md §5).
pub fn exact_reflectance(film: &Film, cos_theta_1: f64, lambda_m: f64) -> f64 {
    0.5 * (film.reflectance(cos_theta_1, lambda_m, Pol::S)
        + film.reflectance(cos_theta_1, lambda_m, Pol::P))
}
