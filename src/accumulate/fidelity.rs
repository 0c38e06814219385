//! The fidelity ladder (docs/PHYSICS.md §4), cheapest first, and the `auto` choice.
//!
//! Every rung starts from the same exact path; they differ in what they keep of the physics:
//!
//! 1. `incoherent`: I = Σ I_j (paper Fig. 5).
//! 2. `scalar`: scalar amplitudes √I_j with phase from the optical path only (P10; Fig. 6 left).
//! 3. `scalar_jump`: + π for every reflection from the denser side (Fig. 6 right).
//! 4. `paper_rules`: s and p with |Fresnel| and the π rules P7/P8, the paper's TIR phases
//!    (Fig. 7 right), in 3D frames.
//! 5. `vector`: complex Fresnel (P1–P6) in 3D frames, full vector sums: the reference.
//!
//! In the scalar rungs I_j is the ray's exact (vector) intensity, so a rung differs from
//! `vector` only by the phase and polarization physics it drops.

#![warn(missing_docs)]

use serde::{Deserialize, Serialize};
use std::fmt;

/// A rung of the fidelity ladder (docs/PHYSICS.md §4), cheapest first.
#[derive(
    Clone,
    Copy,
    Debug,
    PartialEq,
    Eq,
    Hash,
    PartialOrd,
    Ord,
    Serialize,
    Deserialize,
    schemars::JsonSchema,
)]
#[serde(rename_all = "snake_case")]
pub enum Fidelity {
    /// I = Σ I_j: intensities add, no phase (paper Fig. 5).
    Incoherent,
    /// Scalar amplitudes √I_j with the phase of the optical path only (P10; Fig. 6 left).
    Scalar,
    /// As `Scalar`, plus π for every reflection from the denser side (Fig. 6 right).
    ScalarJump,
    /// s and p with |Fresnel|, the π rules P7/P8 and the paper's TIR phases (Fig. 7 right).
    PaperRules,
    /// Complex Fresnel (P1–P6) in 3D frames, full vector sums: the reference.
    Vector,
}

impl Fidelity {
    /// Every rung, cheapest first.
    pub const ALL: [Fidelity; 5] = [
        Fidelity::Incoherent,
        Fidelity::Scalar,
        Fidelity::ScalarJump,
        Fidelity::PaperRules,
        Fidelity::Vector,
    ];

    /// The rung's name in case files and on the command line (`scalar_jump`, …).
    pub fn name(self) -> &'static str {
        match self {
            Fidelity::Incoherent => "incoherent",
            Fidelity::Scalar => "scalar",
            Fidelity::ScalarJump => "scalar_jump",
            Fidelity::PaperRules => "paper_rules",
            Fidelity::Vector => "vector",
        }
    }

    /// The rung named `s` ([`Fidelity::name`]), if any.
    pub fn parse(s: &str) -> Option<Fidelity> {
        Fidelity::ALL.into_iter().find(|f| f.name() == s)
    }
}

/// Writes [`Fidelity::name`].
impl fmt::Display for Fidelity {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(self.name())
    }
}

/// What a scene needs, summarised from its traced paths (see [`auto_select`]).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct SceneNeeds {
    /// Some coherence group receives two or more rays at some point.
    pub interference: bool,
    /// Some path has a reflection or refraction event.
    pub interfaces: bool,
    /// Within every group, all fields are parallel and real-proportional (linear, same axis).
    pub parallel_fields: bool,
    /// Some path is totally internally reflected.
    pub tir: bool,
    /// The quantity measured is a ray's polarization state (e.g. a retardance), not only an
    /// intensity: the scalar rungs cannot represent it.
    pub polarization_state: bool,
}

/// The `auto` choice: the cheapest rung of the ladder that is exact for a scene, and why.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct AutoChoice {
    /// The rung chosen.
    pub level: Fidelity,
    /// Why this rung is exact for the scene and the cheaper ones are not (one sentence).
    pub reason: String,
}

impl AutoChoice {
    fn new(level: Fidelity, reason: &str) -> AutoChoice {
        AutoChoice {
            level,
            reason: reason.to_string(),
        }
    }
}

/// Writes `level: reason`.
impl fmt::Display for AutoChoice {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "{}: {}", self.level, self.reason)
    }
}

/// `auto`: the cheapest rung that is exact for a scene with these needs, and why.
pub fn auto_select(needs: &SceneNeeds) -> AutoChoice {
    if needs.polarization_state {
        return if needs.tir {
            AutoChoice::new(
                Fidelity::Vector,
                "a polarization state is measured and light is totally reflected: only complex Fresnel (P5, P6) gets the retardance right",
            )
        } else {
            AutoChoice::new(
                Fidelity::PaperRules,
                "a polarization state is measured: s and p must be carried separately (no TIR, so the paper's rules are exact)",
            )
        };
    }
    if !needs.interference {
        return AutoChoice::new(
            Fidelity::Incoherent,
            "no two mutually coherent rays meet at any probe point: intensities add",
        );
    }
    if !needs.interfaces && needs.parallel_fields {
        return AutoChoice::new(
            Fidelity::Scalar,
            "no reflections or refractions and parallel fields in every coherence group: path phase is the only phase",
        );
    }
    if !needs.tir {
        return AutoChoice::new(
            Fidelity::PaperRules,
            "interfaces without total internal reflection: |Fresnel| with the π rules P7/P8 equals complex Fresnel exactly",
        );
    }
    AutoChoice::new(
        Fidelity::Vector,
        "total internal reflection: only complex Fresnel (P5, P6) gets the phase right",
    )
}
