//! Light sources: point, line (slit) and plane wave; linear or unpolarized (paper §3.4).
//!
//! A source emits *polarization channels*, mutually incoherent (each its own coherence id,
//! docs/PHYSICS.md §3): a linearly polarized source one; an unpolarized source, by default,
//! three dipole channels along x, y and z (basis-free: the fields sent in directions k1, k2 are
//! correlated as (I − k1k1ᵀ)(I − k2k2ᵀ)/2 whatever the axes, docs/PHYSICS.md §3 "Unpolarized
//! light"), or, as the paper models it, two orthogonal linear channels of half the intensity
//! built from a reference vector. Sources that share a `coherence_group` (e.g. the two slits of
//! Young's experiment, lit by one point) are mutually coherent.

use crate::optics::double_double::difference;
use glam::DVec3;

/// The geometry of emission.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Emitter {
    /// A point at `position` (m), emitting spherical waves.
    Point {
        /// Where it is, m.
        position: DVec3,
    },
    /// A line through `point` along unit `axis`, emitting cylindrical waves perpendicular to its
    /// axis (the stationary-phase ray of a coherent slit). Exact when the scene's planes
    /// contain the axis direction.
    Line {
        /// A point of the line, m.
        point: DVec3,
        /// The line's unit direction.
        axis: DVec3,
    },
    /// A plane wave travelling along unit `direction`, with phase 0 on the plane through
    /// `reference_point` perpendicular to it.
    PlaneWave {
        /// Unit direction of travel.
        direction: DVec3,
        /// A point of the zero-phase wavefront, m.
        reference_point: DVec3,
    },
}

/// Polarization state of the emitted light.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Polarization {
    /// Linear: the field is `reference` projected perpendicular to the ray, then rotated by
    /// `angle_rad` about the ray direction (right-handed).
    Linear {
        /// The field direction before projection (any non-zero length).
        reference: DVec3,
        /// Rotation about the ray, radians.
        angle_rad: f64,
    },
    /// Unpolarized, basis-free (the default): three incoherent dipole channels along x, y, z,
    /// each of weight 1/2; a ray along unit k carries the field (a − (a·k)k)·√(I/2) of dipole
    /// axis a. Σ_a over the three gives the correlation (I − k1k1ᵀ)(I − k2k2ᵀ)/2 of an
    /// unpolarized point source and |E|² = I in every direction (trace of I − kkᵀ is 2),
    /// docs/PHYSICS.md §3.
    Unpolarized,
    /// The paper's unpolarized model (§3.4): two channels, angle 0 and π/2 from `reference`,
    /// half intensity each. Its intensities depend on `reference` off the plane of incidence;
    /// kept to measure that error.
    UnpolarizedTwoChannel {
        /// The 0° channel's field direction before projection.
        reference: DVec3,
    },
}

/// The channels of one source: at most this many (the basis-free unpolarized model's three
/// dipoles). Coherence ids are `CHANNELS_PER_GROUP·g + 1 + k` for channel k of group g.
pub(crate) const CHANNELS_PER_GROUP: u64 = 3;

/// How a channel's launch field depends on the ray direction.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum ChannelField {
    /// Unit field: `reference` projected perpendicular to the ray, rotated by `angle_rad` about
    /// it (right-handed), see [`Polarization::Linear`].
    Linear {
        /// The field direction before projection.
        reference: DVec3,
        /// Rotation about the ray, radians.
        angle_rad: f64,
    },
    /// A dipole along unit `axis`: field `axis − (axis·k)k` for a ray along unit k, of length
    /// sin(angle between axis and k) ≤ 1 (zero along the axis).
    Dipole {
        /// The dipole's unit axis.
        axis: DVec3,
    },
}

/// A source.
#[derive(Clone, Debug, PartialEq)]
pub struct Source {
    /// The source's name (for messages and reports).
    pub name: String,
    /// Where and how it emits.
    pub emitter: Emitter,
    /// Its polarization.
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
    /// |E|² of the channel for a ray whose launch field has unit length (every ray of a
    /// linear channel; a dipole channel's rays perpendicular to its axis).
    pub intensity: f64,
    /// The launch field as a function of the ray direction.
    pub field: ChannelField,
}

impl Channel {
    /// The launch field per √intensity for a ray leaving along unit `dir`: a unit vector for a
    /// linear channel, `axis − (axis·dir)dir` (length ≤ 1) for a dipole. The ray's |E|² is
    /// `intensity · |launch_field|²`.
    pub fn launch_field(&self, dir: DVec3) -> DVec3 {
        let (e, amplitude) = self.launch(dir);
        e * amplitude
    }

    /// The unit field direction and the amplitude factor (|[`Channel::launch_field`]|) of a
    /// ray leaving along unit `dir`. A dipole's field along its own axis is zero: amplitude 0
    /// with an arbitrary unit direction perpendicular to `dir`.
    pub fn launch(&self, dir: DVec3) -> (DVec3, f64) {
        match self.field {
            ChannelField::Linear { .. } => (self.field_direction(dir), 1.0),
            ChannelField::Dipole { axis } => {
                // a − (a·k)k = k × (a × k): |a × k| = sin θ is formed without cancellation.
                let a_cross_k = axis.cross(dir);
                let perp = dir.cross(a_cross_k);
                let len = perp.length();
                if len > 0.0 {
                    (perp / len, len)
                } else {
                    (dir.any_orthonormal_vector(), 0.0)
                }
            }
        }
    }

    /// The unit field direction of this channel for a ray leaving along unit `dir`.
    pub(crate) fn field_direction(&self, dir: DVec3) -> DVec3 {
        match self.field {
            ChannelField::Linear { reference, .. } => {
                self.field_direction_from(field_reference(reference, dir), dir)
            }
            ChannelField::Dipole { .. } => self.launch(dir).0,
        }
    }

    /// [`Channel::field_direction`] of a linear channel from
    /// `e_ref = field_reference(reference, dir)` (one evaluation serves every channel with the
    /// same reference); `e_ref` itself for a dipole channel.
    pub(crate) fn field_direction_from(&self, e_ref: DVec3, dir: DVec3) -> DVec3 {
        match self.field {
            ChannelField::Linear { angle_rad, .. } => {
                angle_rad.cos() * e_ref + angle_rad.sin() * dir.cross(e_ref)
            }
            ChannelField::Dipole { .. } => e_ref,
        }
    }

    /// The reference vector of a linear channel (`None` for a dipole).
    pub(crate) fn linear_reference(&self) -> Option<DVec3> {
        match self.field {
            ChannelField::Linear { reference, .. } => Some(reference),
            ChannelField::Dipole { .. } => None,
        }
    }
}

/// The unit field direction of angle 0 for a ray leaving along unit `dir`: `reference`
/// projected perpendicular to `dir` (an arbitrary perpendicular if they are nearly parallel).
pub(crate) fn field_reference(reference: DVec3, dir: DVec3) -> DVec3 {
    let r = reference - reference.dot(dir) * dir;
    if r.length() > 1e-9 {
        r.normalize()
    } else {
        dir.any_orthonormal_vector()
    }
}

/// The unit direction in which a line source through `point` along unit `axis` sends its ray
/// toward `x` (m): the perpendicular from the line itself to `x` (docs/PHYSICS.md §5
/// "Young": cylindrical waves leave perpendicular to the axis), from the exact coordinate
/// differences x − point with the product and the rejection of the axis in double-double, so it
/// is unit and perpendicular to the axis to a rounding whatever the distance of the line from
/// the origin. `None` when `x` lies on the line.
///
/// A ray launched from an f64 point near the line is off the line by a rounding of that point's
/// coordinates (5.7e-14 m at 500 m), and its direction toward a point 1e-4 m away turns by up
/// to 6e-10 rad: the field of a channel polarized in the plane perpendicular to the axis turns
/// with it, and the coherent term cos α of two slits 23 µm apart moved Young's intensity by
/// 1.8e-11 of 3.6 (`fringe fuzz --family young_exact --seed 1`, scene 5173,
/// `tests/suite/truth_found_edges.rs`).
pub fn line_launch_direction(point: DVec3, axis: DVec3, x: DVec3) -> Option<DVec3> {
    let v = difference(point, x);
    let along = v[0] * axis.x + v[1] * axis.y + v[2] * axis.z;
    let w = [
        v[0] - along * axis.x,
        v[1] - along * axis.y,
        v[2] - along * axis.z,
    ];
    let length = (w[0] * w[0] + w[1] * w[1] + w[2] * w[2]).sqrt();
    if length.hi <= 0.0 {
        return None;
    }
    let d = DVec3::new(
        (w[0] / length).to_f64(),
        (w[1] / length).to_f64(),
        (w[2] / length).to_f64(),
    );
    d.is_finite().then_some(d)
}

impl Source {
    /// The polarization channels with their coherence ids: channel k of group g has id
    /// 3g + 1 + k (`CHANNELS_PER_GROUP`), so no two channels of different groups, and no two
    /// channels of one source, share an id.
    pub fn channels(&self) -> Vec<Channel> {
        let id = |k: u64| CHANNELS_PER_GROUP * self.coherence_group + 1 + k;
        match self.polarization {
            Polarization::Linear {
                reference,
                angle_rad,
            } => vec![Channel {
                coherence_id: id(0),
                intensity: self.intensity,
                field: ChannelField::Linear {
                    reference,
                    angle_rad,
                },
            }],
            Polarization::Unpolarized => [DVec3::X, DVec3::Y, DVec3::Z]
                .into_iter()
                .zip(0..)
                .map(|(axis, k)| Channel {
                    coherence_id: id(k),
                    intensity: self.intensity / 2.0,
                    field: ChannelField::Dipole { axis },
                })
                .collect(),
            Polarization::UnpolarizedTwoChannel { reference } => (0..2)
                .map(|k| Channel {
                    coherence_id: id(k),
                    intensity: self.intensity / 2.0,
                    field: ChannelField::Linear {
                        reference,
                        angle_rad: k as f64 * std::f64::consts::FRAC_PI_2,
                    },
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
