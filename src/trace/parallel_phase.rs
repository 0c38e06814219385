//! The far-field optical path of a plane wave whose every event lies on planes with one line
//! of normals (a film, a plate, a stack of parallel plates), formed from Snell's invariant
//! instead of summed along the traced segments (docs/PHYSICS.md §8).
//!
//! Every wave of such a path is a plane wave with the same tangential wavevector k_t (Snell's
//! law conserves it), so its phase at the far-field wavefront through `r_t` is
//!
//! Φ = k_t·(r_t − r_pw) + κ_0 h_0(r_pw) + Σ_e κ_{e+1} (h_{e+1} − h_e) − κ_m h_{m−1}(r_t),
//!
//! with κ_i = n_i d̂_i·N̂ = ±√q²_i the normal wavevector of segment i ((n cos θ)², from the
//! launch's q²_0 and the indices in double-double as the tracer carries it), h_e(r) = N̂·(x_e − r)
//! the height of event e's plane (its anchor and height, not the rounded point) and r_pw the
//! plane wave's reference point: the tangential parts of all segments telescope to the first
//! term exactly. Summed along the segments instead, each tangential part is the rounded f64
//! direction times a lateral run that near grazing incidence reaches metres, and the far-field
//! projection is along the *target's* f64 direction: both first-order errors, ~1e-16 rad times
//! the run, that grow linearly with the order. A film 1e-10° below the critical angle of its
//! top face (n = 1 in n = 3, 1 µm, 200 nm; `fuzz_airy_s1_203`) runs 0.64 m sideways per round
//! trip, and its orders' phases were 8e-17 m of path per round trip off (2.5e-9 rad, ninth
//! order), which its closed tail (|1 − q| ~ 2e-4) turned into 7e-9 of the reflectance. A 10 mm
//! plate (2.6468 → 2.62 → 10, 81.74°, 0.89 m sideways per round trip; `fuzz_airy_s2_7972`)
//! whose ~90 orders were all traced, no tail closed, had T 4.5e-9 off 50 digits from the same
//! walk (each round trip's f64 path ~2e-15 m off, growing with the order).
//!
//! So every arrival of a plane wave into the far field along such a path carries Φ as its
//! optical path (`trace::arrivals_with`), traced order by order or walked: [`PlaneWavePhase`]
//! adds one term per event ([`PlaneWavePhase::step`]), so the far-field walk, which shares each
//! beginning among the sequences through it, keeps its O(1) per order, and the one-by-one trace
//! ([`PlaneWavePhase::of_path`], O(m) per order as its own trace is) gets the same bits. Paths
//! that meet a plane off the line of normals, or tunnel, keep the traced sum.

use crate::optics::double_double::{DoubleDouble, difference, two_prod};
use crate::optics::interaction::normal_wavevector_squares;
use crate::scene::Scene;
use crate::scene::source::Emitter;
use crate::trace::path::{Event, EventKind, SolvedPath, Target};
use glam::DVec3;

/// The exact far-field optical path of every path of one plane-wave source into one far-field
/// direction (module docs), built event by event.
pub(crate) struct PlaneWavePhase<'a> {
    scene: &'a Scene,
    /// r_pw, the plane wave's reference point (m).
    reference_point: DVec3,
    /// r_t, the far-field wavefront's reference point (m).
    reference: DVec3,
    /// Per surface, the signed distance of r_pw from its plane (m), formed once.
    from_reference_point: Vec<DoubleDouble>,
}

/// Φ of a path's beginning (module docs, without its last two terms), after its last event.
#[derive(Clone, Copy, Debug)]
pub(crate) struct Partial {
    /// N̂ as held by the first event's plane: every further plane's is ±N̂ bitwise.
    normal: DVec3,
    /// (n0 cos θ0)² about N̂ of the launch direction (m⁰), as the tracer forms it at the first
    /// face.
    q2_0: DoubleDouble,
    /// The launch direction and index.
    d0: DVec3,
    n0: f64,
    /// The last event's surface.
    last: usize,
    /// κ_0 h_0(r_pw) + Σ κ_{e+1} (h_{e+1} − h_e) so far (m).
    phi: DoubleDouble,
}

impl<'a> PlaneWavePhase<'a> {
    /// For the paths of the source `emitter` into `target`; `None` (the traced sums stand)
    /// unless the source is a plane wave and the target a far-field direction.
    pub(crate) fn new(scene: &'a Scene, emitter: Emitter, target: &Target) -> Option<Self> {
        let Emitter::PlaneWave {
            reference_point, ..
        } = emitter
        else {
            return None;
        };
        let Target::Direction { reference, .. } = *target else {
            return None;
        };
        let from_reference_point = scene
            .surfaces
            .iter()
            .map(|s| s.plane.signed_distance_dd(reference_point))
            .collect();
        Some(PlaneWavePhase {
            scene,
            reference_point,
            reference,
            from_reference_point,
        })
    }

    /// κ = ±√q² of a segment along `d` in index `n` (+ where d·N̂ ≥ 0), q² = q²_0 + n² − n0²;
    /// `None` for an evanescent segment.
    fn kappa(p: &Partial, n: f64, d: DVec3) -> Option<DoubleDouble> {
        let q2 = if n == p.n0 {
            p.q2_0
        } else {
            p.q2_0 + two_prod(n, n) - two_prod(p.n0, p.n0)
        };
        if q2.hi < 0.0 {
            return None;
        }
        let k = q2.sqrt();
        Some(if d.dot(p.normal) >= 0.0 { k } else { -k })
    }

    /// h(r) = N̂·(x − r) of `surface`'s plane: −σ times r's signed distance from it (σ = ±1 as
    /// its normal is ±N̂); `None` where the plane is off the line of normals.
    fn height(&self, normal: DVec3, surface: usize, r: DVec3) -> Option<DoubleDouble> {
        let plane = &self.scene.surfaces[surface].plane;
        let sd = if r == self.reference_point {
            self.from_reference_point[surface]
        } else {
            plane.signed_distance_dd(r)
        };
        if plane.normal == normal {
            Some(-sd)
        } else if plane.normal == -normal {
            Some(sd)
        } else {
            None
        }
    }

    /// Φ after the first event `ev`, met along the launch direction `d0` in index `n0`:
    /// κ_0 h_0(r_pw). `None` for a tunnel event or an evanescent launch.
    pub(crate) fn first(&self, ev: Event, d0: DVec3, n0: f64) -> Option<Partial> {
        if ev.kind == EventKind::Tunnel {
            return None;
        }
        let normal = self.scene.surfaces[ev.surface].plane.normal;
        let (q2_0, _) = normal_wavevector_squares(d0, normal, (n0, n0), None);
        let mut p = Partial {
            normal,
            q2_0,
            d0,
            n0,
            last: ev.surface,
            phi: DoubleDouble::ZERO,
        };
        p.phi = Self::kappa(&p, n0, d0)? * self.height(normal, ev.surface, self.reference_point)?;
        Some(p)
    }

    /// Φ after one more event `ev`, met along the segment `d` in index `n` from the last one:
    /// Φ + κ (h_ev − h_last). `None` for a tunnel event, a plane off the line of normals or an
    /// evanescent segment.
    pub(crate) fn step(&self, p: Option<Partial>, ev: Event, d: DVec3, n: f64) -> Option<Partial> {
        let p = p?;
        if ev.kind == EventKind::Tunnel {
            return None;
        }
        let r = self.reference_point;
        let dh = self.height(p.normal, ev.surface, r)? - self.height(p.normal, p.last, r)?;
        Some(Partial {
            last: ev.surface,
            phi: p.phi + Self::kappa(&p, n, d)? * dh,
            ..p
        })
    }

    /// Φ of the whole path whose beginning is `p`, leaving along `d` in index `n` (m): − κ_m
    /// h_{m−1}(r_t) + k_t·(r_t − r_pw), relative to the wavefront through r_pw as the traced
    /// paths are.
    pub(crate) fn finish(&self, p: Option<Partial>, d: DVec3, n: f64) -> Option<DoubleDouble> {
        let p = p?;
        let mut phi =
            p.phi - Self::kappa(&p, n, d)? * self.height(p.normal, p.last, self.reference)?;
        // k_t·(r_t − r_pw) = n0 [d̂0·v − (d̂0·N̂)(N̂·v)]: the same for every path into the target.
        if self.reference != self.reference_point {
            let (d0, normal) = (p.d0, p.normal);
            let v = difference(self.reference_point, self.reference);
            let dot = |a: DVec3| v[0].mul_f64(a.x) + v[1].mul_f64(a.y) + v[2].mul_f64(a.z);
            let (dd, nn) = (DoubleDouble::dot(d0, d0), DoubleDouble::dot(normal, normal));
            let along = DoubleDouble::dot(d0, normal) * dot(normal) / nn;
            phi += (dot(d0) - along).mul_f64(p.n0) / dd.sqrt();
        }
        Some(phi)
    }

    /// Φ of `path` (m): [`Self::first`], [`Self::step`] per further event and [`Self::finish`],
    /// the same bits as the far-field walk forms them; `None` where the traced sum stands.
    pub(crate) fn of_path(&self, path: &SolvedPath) -> Option<DoubleDouble> {
        let mut segments = path.dirs.iter().copied().zip(path.indices.iter().copied());
        let mut p = None;
        for (k, ev) in path.sequence.iter().copied().enumerate() {
            let (d, n) = segments.next()?;
            p = if k == 0 {
                self.first(ev, d, n)
            } else {
                self.step(p, ev, d, n)
            };
        }
        let (d, n) = segments.next()?;
        self.finish(p, d, n)
    }
}
