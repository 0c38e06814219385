//! Light sources: point, line (slit) and plane wave; linear or unpolarized (paper §3.4).
//!
//! A source emits *polarization channels*: a linearly polarized source one, an unpolarized
//! source two orthogonal linear channels of half the intensity each, with different coherence
//! ids (they are mutually incoherent, docs/PHYSICS.md §3). Sources that share a `coherence_group`
//! (e.g. the two slits of Young's experiment, lit by one point) are mutually coherent.

use glam::DVec3;

/// The geometry of emission.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Emitter {
    /// A point at `position` (m), emitting spherical waves.
    Point { position: DVec3 },
    /// A line through `point` along unit `axis`, emitting cylindrical waves perpendicular to its
    /// axis (the stationary-phase ray of a coherent slit). Exact when the scene's planes
    /// contain the axis direction.
    Line { point: DVec3, axis: DVec3 },
    /// A plane wave travelling along unit `direction`, with phase 0 on the plane through
    /// `reference_point` perpendicular to it.
    PlaneWave {
        direction: DVec3,
        reference_point: DVec3,
    },
}

/// Polarization state of the emitted light.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Polarization {
    /// Linear: the field is `reference` projected perpendicular to the ray, then rotated by
    /// `angle_rad` about the ray direction (right-handed).
    Linear { reference: DVec3, angle_rad: f64 },
    /// Unpolarized: two channels, angle 0 and π/2 from `reference`, half intensity each.
    Unpolarized { reference: DVec3 },
}

/// A source.
#[derive(Clone, Debug, PartialEq)]
pub struct Source {
    pub name: String,
    pub emitter: Emitter,
    pub polarization: Polarization,
    /// |E|² of the emitted light (of all channels together): at unit distance for point and
    /// line sources with geometric spreading on, and everywhere when spreading is off.
    pub intensity: f64,
    /// Sources with the same group are mutually coherent; every group gets its own ids.
    pub coherence_group: u64,
    /// Coherence length (m) used by the paper's rule (P9); `f64::INFINITY` for none.
    pub coherence_length_m: f64,
}

/// One polarization channel of a source.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Channel {
    /// Coherence id (never 0: emitted light is coherent with itself).
    pub coherence_id: u64,
    /// |E|² of the channel.
    pub intensity: f64,
    /// The field reference vector and rotation angle, see [`Polarization::Linear`].
    pub reference: DVec3,
    pub angle_rad: f64,
}

impl Channel {
    /// The unit field direction of this channel for a ray leaving along unit `dir`.
    pub fn field_direction(&self, dir: DVec3) -> DVec3 {
        self.field_direction_from(field_reference(self.reference, dir), dir)
    }

    /// [`Channel::field_direction`] from `e_ref = field_reference(self.reference, dir)` (one
    /// evaluation serves every channel with the same reference).
    pub fn field_direction_from(&self, e_ref: DVec3, dir: DVec3) -> DVec3 {
        self.angle_rad.cos() * e_ref + self.angle_rad.sin() * dir.cross(e_ref)
    }
}

/// The unit field direction of angle 0 for a ray leaving along unit `dir`: `reference`
/// projected perpendicular to `dir` (an arbitrary perpendicular if they are nearly parallel).
pub fn field_reference(reference: DVec3, dir: DVec3) -> DVec3 {
    let r = reference - reference.dot(dir) * dir;
    if r.length() > 1e-9 {
        r.normalize()
    } else {
        dir.any_orthonormal_vector()
    }
}

impl Source {
    /// The polarization channels with their coherence ids: 2g+1 and 2g+2 for group g.
    pub fn channels(&self) -> Vec<Channel> {
        let id = |k: u64| 2 * self.coherence_group + 1 + k;
        match self.polarization {
            Polarization::Linear {
                reference,
                angle_rad,
            } => vec![Channel {
                coherence_id: id(0),
                intensity: self.intensity,
                reference,
                angle_rad,
            }],
            Polarization::Unpolarized { reference } => (0..2)
                .map(|k| Channel {
                    coherence_id: id(k),
                    intensity: self.intensity / 2.0,
                    reference,
                    angle_rad: k as f64 * std::f64::consts::FRAC_PI_2,
                })
                .collect(),
        }
    }

    /// A representative point of the source (for probe rays and initial guesses).
    pub fn anchor(&self) -> DVec3 {
        match self.emitter {
            Emitter::Point { position } => position,
            Emitter::Line { point, .. } => point,
            Emitter::PlaneWave {
                reference_point, ..
            } => reference_point,
        }
    }
}
