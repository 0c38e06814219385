//! Conformance packs and grading of another tracer's values.
//!
//! `fringe export [CASE…] --out DIR` ([`export`]) writes, per case, what another tracer needs to
//! reproduce it: the case file, the probe points and wavelengths, the observable of every
//! quantity with its definition and unit, the conventions, the expected values (closed form and
//! exact traced at every fidelity level) and the tolerances. `fringe grade CASE --values FILE`
//! ([`grading`]) reads that tracer's values ([`values`]) and judges them like `fringe check`
//! judges the traced values: the same deviation metric, tolerances, verdict rows and exit codes,
//! plus which fidelity rung they match best.
//!
//! A case's values are grouped into **quantities**: every intensity-like reference of a case
//! compares the same traced observable (the one its probe declares: [`Observable`]), so the
//! other tracer supplies it once per probe point; each retardance, visibility or fringe-spacing
//! reference is a quantity of its own.

pub mod export;
pub mod grading;
pub mod values;

use crate::harness::case::reference::MetricKind;
use crate::harness::case::run::CaseResult;
use crate::harness::case::spec::{FarSide, Observer, Probe, SweepParameter};

/// What a probe measures (docs/PHYSICS.md §3a), named once for packs, value files and reports.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Observable {
    /// Power reflectance R = |r|² of a plane wave, observed in the reflected far field.
    Reflectance,
    /// Power transmittance T = (n_out cos θ_out)/(n_in cos θ_in)·|t|², transmitted far field.
    Transmittance,
    /// Field intensity |E|² at a screen point or along a far-field direction, in units of the
    /// source's |E|² (summed over coherence groups, paper eq. 6).
    FieldIntensity,
    /// Retardance arg E_p − arg E_s of the arriving field (rad, wrapped to (−π, π]).
    Retardance,
    /// Two-beam fringe visibility 2√(I1 I2)/(I1 + I2) (dimensionless).
    Visibility,
    /// Fringe spacing at the probe centre (m).
    FringeSpacing,
}

impl Observable {
    /// The observable of an intensity-like reference, from the probe kind: far-field probes of
    /// a plane wave measure power R or T; screen points and far-field directions |E|².
    pub(crate) fn of_probe(probe: &Probe) -> Observable {
        let observer = match probe {
            Probe::Sweep { observe, .. } | Probe::Single { observe } => Some(observe),
            Probe::Line { .. } | Probe::Grid { .. } => None,
        };
        match observer {
            Some(Observer::FarField {
                side: FarSide::Reflected,
                ..
            }) => Observable::Reflectance,
            Some(Observer::FarField {
                side: FarSide::Transmitted,
                ..
            }) => Observable::Transmittance,
            _ => Observable::FieldIntensity,
        }
    }

    /// The observable of a metric of a case with this probe.
    pub(crate) fn of_metric(kind: MetricKind, probe: &Probe) -> Observable {
        match kind {
            MetricKind::Intensity => Observable::of_probe(probe),
            MetricKind::Retardance => Observable::Retardance,
            MetricKind::Visibility => Observable::Visibility,
            MetricKind::FringeSpacing => Observable::FringeSpacing,
        }
    }

    pub fn name(self) -> &'static str {
        match self {
            Observable::Reflectance => "reflectance",
            Observable::Transmittance => "transmittance",
            Observable::FieldIntensity => "field_intensity",
            Observable::Retardance => "retardance_rad",
            Observable::Visibility => "visibility",
            Observable::FringeSpacing => "fringe_spacing_m",
        }
    }

    pub fn unit(self) -> &'static str {
        match self {
            Observable::Reflectance | Observable::Transmittance | Observable::Visibility => {
                "dimensionless fraction in [0, 1]"
            }
            Observable::FieldIntensity => "|E|² in units of the source's |E|² (≥ 0)",
            Observable::Retardance => "radians in (−π, π]",
            Observable::FringeSpacing => "metres",
        }
    }

    pub fn definition(self) -> &'static str {
        match self {
            Observable::Reflectance => {
                "power reflectance R = |r|² of the plane wave (docs/PHYSICS.md §3a), every reflected order summed coherently, weighted over the spectral samples"
            }
            Observable::Transmittance => {
                "power transmittance T = (n_out cos θ_out)/(n_in cos θ_in)·|t|² of the plane wave (docs/PHYSICS.md §3a), weighted over the spectral samples"
            }
            Observable::FieldIntensity => {
                "field intensity I = Σ_groups |Σ_j E_j e^{iφ_j}|² (paper eqs. 5–6), φ = 2π s/λ for optical path s, in units of the source's |E|², weighted over the spectral samples"
            }
            Observable::Retardance => {
                "arg E_p − arg E_s of the summed field, s = d_in × N normalised at the named surface, p = d_out × s (docs/PHYSICS.md §1)"
            }
            Observable::Visibility => {
                "two-beam visibility 2√(I1 I2)/(I1 + I2) of the two mutually coherent arrivals"
            }
            Observable::FringeSpacing => {
                "local fringe spacing along the probe line at its centre, from the phase gradient of the two strongest coherent beams"
            }
        }
    }

    /// The range a value of this observable must lie in, with a margin for rounding; a value
    /// outside it is in the wrong units (percent, degrees, micrometres…). `None`: no bound.
    pub fn allowed(self) -> (f64, Option<f64>) {
        const M: f64 = 1e-9;
        match self {
            Observable::Reflectance | Observable::Transmittance | Observable::Visibility => {
                (-M, Some(1.0 + M))
            }
            Observable::FieldIntensity => (-M, None),
            Observable::Retardance => (-std::f64::consts::PI - M, Some(std::f64::consts::PI + M)),
            Observable::FringeSpacing => (0.0, Some(1.0)),
        }
    }
}

/// The probe coordinate: its name and unit.
pub(crate) fn coordinate_name(probe: &Probe) -> (&'static str, &'static str) {
    match probe {
        Probe::Line { .. } => (
            "distance_m",
            "metres along the probe line from origin_m (default from_m)",
        ),
        Probe::Sweep { parameter, .. } => match parameter {
            SweepParameter::IncidenceAngleDeg { .. } => ("incidence_angle_deg", "degrees"),
            SweepParameter::WavelengthNm {} => ("wavelength_nm", "nanometres (vacuum)"),
            SweepParameter::ThicknessNm { .. } => ("thickness_nm", "nanometres"),
        },
        Probe::Single { .. } => ("single", "always 0"),
        Probe::Grid { .. } => ("pixel_index", "row-major pixel index, row 0 at the top"),
    }
}

/// One quantity another tracer supplies: its name in value files, its observable, the probe
/// coordinates, and the metrics (indices into [`CaseResult::metrics`]) it is judged by.
#[derive(Clone, Debug, PartialEq)]
pub struct Quantity {
    pub name: String,
    pub observable: Observable,
    pub coordinates: Vec<f64>,
    pub metrics: Vec<usize>,
}

/// The quantities of a case run: one for all intensity-like references (named after the
/// observable), one per other reference (named after its label).
pub fn quantities(result: &CaseResult, probe: &Probe) -> Vec<Quantity> {
    let mut out: Vec<Quantity> = Vec::new();
    for (i, m) in result.metrics.iter().enumerate() {
        let observable = Observable::of_metric(m.kind, probe);
        if m.kind == MetricKind::Intensity {
            if let Some(q) = out.iter_mut().find(|q| q.observable == observable) {
                q.metrics.push(i);
                continue;
            }
            out.push(Quantity {
                name: observable.name().into(),
                observable,
                coordinates: m.coordinates.clone(),
                metrics: vec![i],
            });
        } else {
            out.push(Quantity {
                name: m.name.clone(),
                observable,
                coordinates: m.coordinates.clone(),
                metrics: vec![i],
            });
        }
    }
    out
}
