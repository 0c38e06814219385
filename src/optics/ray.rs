//! The linear polarized ray of zero thickness (paper §3.5): R = {P0, dir, X, Y, attributes}.
//!
//! The frame (X, Y, dir) is right-handed. The polarization is a Jones vector (J_x, J_y) in that
//! frame; the complex 3D field amplitude is `E = J_x X + J_y Y` and the field at the ray's end is
//! `E·e^{+i 2π Op/λ0}` (time dependence e^{-iωt}, docs/PHYSICS.md §1). Fresnel phases live in the
//! Jones vector; path phase lives in the optical path `Op = Σ n_i L_i` (metres, carried as a
//! [`DoubleDouble`] with each length formed from exact coordinate differences), so that path
//! *differences* can be formed to ~1e-30 m before any phase is taken (docs/PHYSICS.md §1). Intensity = |J_x|² + |J_y|² =
//! trace of the coherence matrix.

use crate::optics::double_double::{DoubleDouble, projection, segment_length};
use crate::optics::trail::Trail;
use glam::DVec3;
use num_complex::Complex64;

/// A complex 3D field vector (x, y, z components).
pub type Field3 = [Complex64; 3];

/// Coherence id 0: coherent with nothing (paper §3.4).
pub const INCOHERENT: u64 = 0;

/// One contribution to a ray's phase, recorded so a report can explain a fringe.
#[derive(Clone, Debug, PartialEq)]
pub enum LedgerEntry {
    /// Propagation over `length_m` metres in a medium of index `index`: phase 2π n L/λ0.
    Path {
        /// Refractive index of the medium.
        index: f64,
        /// Geometric length, m.
        length_m: f64,
    },
    /// A reflection at `surface` with the applied coefficients r_s, r_p (their arguments are
    /// the phase jumps) and whether it was TIR.
    Reflection {
        /// The surface's index in the scene.
        surface: usize,
        /// Applied s coefficient.
        r_s: Complex64,
        /// Applied p coefficient.
        r_p: Complex64,
        /// Whether it was total internal reflection.
        tir: bool,
    },
    /// A refraction at `surface` with the applied coefficients t_s, t_p (real and positive for
    /// lossless media: no phase).
    Refraction {
        /// The surface's index in the scene.
        surface: usize,
        /// Applied s coefficient.
        t_s: Complex64,
        /// Applied p coefficient.
        t_p: Complex64,
    },
    /// A tunnelled (frustrated-TIR) transmission through the layer behind `surface`, lit beyond
    /// that face's critical angle, with the layer's applied t_s, t_p (docs/PHYSICS.md §5): the
    /// ray jumps to the layer's far face with no path of its own (all the layer's phase is in
    /// t).
    Tunnel {
        /// The lit face's index in the scene.
        surface: usize,
        /// Applied s coefficient.
        t_s: Complex64,
        /// Applied p coefficient.
        t_p: Complex64,
    },
    /// A coherence change at `surface` (the child lost coherence, or the coherence length rule).
    CoherenceLost {
        /// The surface's index in the scene (`None`: the coherence length rule).
        surface: Option<usize>,
    },
}

/// The per-ray phase ledger: every contribution to the phase in the order it happened. The
/// rays of a plate's reflected orders share the entries of their common beginning
/// ([`Trail`]).
#[derive(Clone, Debug, Default, PartialEq)]
pub struct PhaseLedger {
    /// The entries, oldest first.
    pub entries: Trail<LedgerEntry>,
}

impl PhaseLedger {
    /// Σ n_i L_i over the recorded path entries (metres).
    pub fn optical_path_m(&self) -> f64 {
        self.entries
            .iter()
            .map(|e| match e {
                LedgerEntry::Path { index, length_m } => index * length_m,
                _ => 0.0,
            })
            .sum()
    }
}

/// The complex 3D field `J_x X + J_y Y` of the Jones vector `[J_x, J_y]` in the frame (X, Y).
pub(crate) fn field_of(jones: [Complex64; 2], x: DVec3, y: DVec3) -> Field3 {
    let [jx, jy] = jones;
    [
        jx * x.x + jy * y.x,
        jx * x.y + jy * y.y,
        jx * x.z + jy * y.z,
    ]
}

/// A linear polarized ray with the attributes of paper §3.5.
#[derive(Clone, Debug, PartialEq)]
pub struct Ray {
    /// P0: where the ray starts (m).
    pub origin: DVec3,
    /// Unit direction of propagation.
    pub dir: DVec3,
    /// Unit X axis of the polarization frame (X × Y = dir).
    pub x: DVec3,
    /// Unit Y axis of the polarization frame.
    pub y: DVec3,
    /// Vacuum wavelength λ0 (m).
    pub wavelength_m: f64,
    /// Which source point emitted the ray; 0 = coherent with nothing.
    pub coherence_id: u64,
    /// Coherence length of the source (m); `f64::INFINITY` for ideal monochromatic light.
    pub coherence_length_m: f64,
    /// Jones vector (complex amplitudes along X and Y); includes Fresnel phases.
    pub jones: [Complex64; 2],
    /// Optical path Σ n_i L_i from the source (m), in double-double: rounding it to f64 costs
    /// ~1e-14 m (1e-7 rad) at 100 m, so differences are formed before rounding
    /// ([`Ray::optical_path_m`] is the rounded value).
    pub optical_path: DoubleDouble,
    /// Refractive index of the medium the ray travels in.
    pub index: f64,
    /// Every phase contribution so far.
    pub ledger: PhaseLedger,
    /// Snell's invariant of the ray about the unit normal of the last face it met, with that
    /// normal; `None` before the first face. It is held as the squared normal wavevector
    /// q² = (n cos θ)² in double-double *in the medium where it was formed*
    /// ([`crate::optics::interaction::SnellInvariant`]): Snell's law conserves n sin θ, so at
    /// every further face *parallel* to that one each medium's q'² = q² + n'² − n² is formed
    /// from it directly (docs/PHYSICS.md §8), never by a chain through the media between. The
    /// cosine leaving a film at near-grazing outside (or into a much lower index) is then
    /// formed without the cancellation of 1 − sin², which from an f64 direction loses all its
    /// digits (cos θ ~ 1e-8 outside needs sin²θ inside to 1e-32), and a wave grazing in the
    /// ambient ((n0 cos θ0)² ~ 1e-32) leaves a denser film with its own q² unchanged.
    pub normal_q2: Option<(DVec3, crate::optics::interaction::SnellInvariant)>,
}

impl Ray {
    /// A linearly polarized ray with real amplitude `amplitude` along `e_dir` (projected
    /// perpendicular to `dir`; if `e_dir` is parallel to `dir` an arbitrary perpendicular is used).
    pub fn linear(
        origin: DVec3,
        dir: DVec3,
        e_dir: DVec3,
        amplitude: f64,
        wavelength_m: f64,
        index: f64,
    ) -> Ray {
        Ray::linear_unit(
            origin,
            dir.normalize(),
            e_dir,
            amplitude,
            wavelength_m,
            index,
        )
    }

    /// [`Ray::linear`] with `dir` already normalized (`dir.normalize()` of the direction
    /// [`Ray::linear`] would be given: one normalization serves several rays).
    pub(crate) fn linear_unit(
        origin: DVec3,
        dir: DVec3,
        e_dir: DVec3,
        amplitude: f64,
        wavelength_m: f64,
        index: f64,
    ) -> Ray {
        let e = e_dir - e_dir.dot(dir) * dir;
        let x = if e.length() > 1e-12 {
            e.normalize()
        } else {
            dir.any_orthonormal_vector()
        };
        let y = dir.cross(x);
        Ray {
            origin,
            dir,
            x,
            y,
            wavelength_m,
            coherence_id: INCOHERENT,
            coherence_length_m: f64::INFINITY,
            jones: [Complex64::from(amplitude), Complex64::from(0.0)],
            optical_path: DoubleDouble::ZERO,
            index,
            ledger: PhaseLedger::default(),
            normal_q2: None,
        }
    }

    /// The complex 3D field amplitude `J_x X + J_y Y` (without the path phase).
    pub fn field(&self) -> Field3 {
        field_of(self.jones, self.x, self.y)
    }

    /// Intensity |J_x|² + |J_y|² (the trace of the coherence matrix).
    pub fn intensity(&self) -> f64 {
        self.jones[0].norm_sqr() + self.jones[1].norm_sqr()
    }

    /// The optical path Σ n_i L_i from the source rounded to f64 (m).
    pub fn optical_path_m(&self) -> f64 {
        self.optical_path.to_f64()
    }

    /// Phase in cycles, Op/λ0 (the path phase divided by 2π), of the rounded path.
    pub fn phase_cycles(&self) -> f64 {
        self.optical_path_m() / self.wavelength_m
    }

    /// [`Ray::advance_to`] an event point: `point` is where the ray meets a surface, rounded
    /// to f64, and L is measured along the ray's direction, d·(point − origin)/|d|
    /// ([`projection`]), as the path solver measures a segment that ends on an event
    /// (`trace::path::event_segment_length`, which says why: |point − origin| adds the
    /// point's rounding to second order, 5e-19 m per round trip in a 0.1 nm film 100 m from
    /// the origin).
    #[inline(always)]
    pub(crate) fn advance_to_event(&mut self, point: DVec3) {
        let length = projection(self.dir, point, self.origin);
        self.optical_path += length.mul_f64(self.index);
        self.ledger.entries.push(LedgerEntry::Path {
            index: self.index,
            length_m: length.to_f64(),
        });
        self.origin = point;
    }

    /// Move the ray's origin to `point` along its direction, adding n·L to the optical path
    /// (L = |point − origin| in double-double from the exact coordinate differences) and a
    /// ledger entry. `point` must lie ahead on the ray.
    #[inline(always)]
    pub(crate) fn advance_to(&mut self, point: DVec3) {
        let length = segment_length(self.origin, point);
        self.optical_path += length.mul_f64(self.index);
        self.ledger.entries.push(LedgerEntry::Path {
            index: self.index,
            length_m: length.to_f64(),
        });
        self.origin = point;
    }

    /// Scale the Jones vector by a real factor (e.g. geometric spreading).
    pub fn scale(&mut self, factor: f64) {
        self.jones = [self.jones[0] * factor, self.jones[1] * factor];
    }
}
