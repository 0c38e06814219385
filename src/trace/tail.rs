//! The Airy tail closed exactly: the sum of every reflected order of a plane wave between two
//! parallel faces beyond the last one traced (docs/PHYSICS.md §5a, eq. T1).
//!
//! Between two parallel faces X and Y every further round trip multiplies the s and p
//! amplitudes of the last traced order a_N by the same factor q_σ = A_σ e^{2πi ΔS/λ}, with
//! A_σ = r_σ(X) r_σ(Y) the two internal Fresnel coefficients the tracer applied (its own ledger)
//! and ΔS = 2 n d cos θ the optical path of one round trip (in double-double from the faces'
//! distance and the carried (n cos θ)², not the difference of two traced paths: see `close`).
//! Orders N + 1, N + 2, … sum to a_N q_σ/(1 − q_σ) per σ: one extra arrival ([`TailClosure`]
//! on [`Arrival::tail`]) that stands for infinitely many.
//!
//! Conditioning: near grazing incidence 1 − |q| ~ 1e-9, so 1 − q is never formed from q. It is
//! (1 − |A|) + |A|(1 − e^{iψ}), with 1 − |A|² from Stokes' relations (4 Re(x ȳ)/|x + y|² for
//! r = (x − y)/(x + y), no cancellation; the normal wavevectors x, y from the squared normal
//! components the tracer carries in double-double, [`crate::optics::ray::Ray::normal_q2`]),
//! 1 − e^{iψ} = 2 sin²(ψ/2) − i sin ψ, and ψ = arg A + 2π·frac(ΔS/λ) with the fraction of a
//! cycle reduced in double-double ([`super::phase_cycles`]).
//!
//! Where it applies (anything else is refused with the reason, never closed approximately):
//! a plane-wave source observed in the far field, with an infinite coherence length; a scene of
//! exactly two unbounded dielectric interfaces whose normals are the same line (bitwise ±, the
//! tracer's own test for carrying q² between faces); the deepest traced sequence ends in a run
//! of internal reflections alternating between them followed only by refractions, and the
//! sequence with one round trip fewer was traced too, with the same coherence id.

pub mod scalar_series;

use super::{Arrival, phase_cycles};
use crate::accumulate::fidelity::Fidelity;
use crate::optics::double_double::DoubleDouble;
use crate::optics::interaction::indices_for;
use crate::optics::ray::{Field3, INCOHERENT, LedgerEntry, Ray};
use crate::scene::geometry::Extent;
use crate::scene::source::Emitter;
use crate::scene::{Scene, SceneOptics, SurfaceKind};
use crate::trace::path::EventKind;
use glam::DVec3;
use num_complex::Complex64;
use std::f64::consts::TAU;
use std::sync::Arc;

/// Unit roundoff of f64.
const U: f64 = f64::EPSILON / 2.0;

/// A light whose field along one of s, p is below this fraction of the other, and decays no
/// slower, is taken as pure s or p light by the scalar rungs (`scalar_factor`).
const PURE_POLARIZATION: f64 = 1e-15;

/// One round trip between the faces under one coefficient model, per σ = (s, p).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct RoundTrip {
    /// A_σ = r_σ(X) r_σ(Y), as the tracer applied them (dimensionless, complex).
    pub a: [Complex64; 2],
    /// 1 − |A_σ|², from Stokes' relations (no cancellation).
    pub one_minus_abs2: [f64; 2],
}

/// The closure of the orders beyond the last traced one (module docs): the arrival it rides on
/// is that order's, and its contribution is the sum of all further orders.
#[derive(Clone, Debug, PartialEq)]
pub struct TailClosure {
    /// Optical path of one round trip, ΔS (m), in double-double.
    pub round_trip_path: DoubleDouble,
    /// The s and p unit vectors of the exit direction (p = d × s).
    pub s: DVec3,
    /// See `s`.
    pub p: DVec3,
    /// Under complex Fresnel (`vector`).
    pub vector: RoundTrip,
    /// Under the paper's rules (`paper_rules`), when traced.
    pub paper: Option<RoundTrip>,
    /// Reflections from the denser side per round trip (the half cycles of `scalar_jump`).
    pub denser_per_round_trip: usize,
    /// N, the index of the deepest order traced explicitly (information): the closure adds
    /// orders N + 1, N + 2, … (order 0 is the top reflection, or the direct pass through).
    pub traced_orders: usize,
}

/// q/(1 − q) for q = |a| e^{iψ}, ψ = arg a + 2π `cycles` (docs/PHYSICS.md eq. T1), with 1 − q
/// formed without cancellation from `one_minus_abs2` = 1 − |a|², and a bound on its relative
/// rounding error given the error `dpsi` (rad) of ψ. `None` when |a| = 1 (no decay: the series
/// diverges).
pub(crate) fn geometric_sum(
    a: Complex64,
    one_minus_abs2: f64,
    cycles: f64,
    dpsi: f64,
) -> Option<(Complex64, f64)> {
    if one_minus_abs2 <= 0.0 {
        return None;
    }
    let m = (1.0 - one_minus_abs2).max(0.0).sqrt();
    let one_minus_m = one_minus_abs2 / (1.0 + m);
    // ψ in cycles: arg a/2π is exactly 0 or ±0.5 for a real a (π/τ is exact), so the sum
    // with the path's fraction of a cycle near a resonance is exact (Sterbenz).
    let c = a.im.atan2(a.re) / TAU + cycles;
    let psi = TAU * (c - c.round());
    let (sin, cos) = psi.sin_cos();
    let half = (0.5 * psi).sin();
    let q = Complex64::new(m * cos, m * sin);
    let one_minus_q = Complex64::new(one_minus_m + 2.0 * m * half * half, -m * sin);
    let w = one_minus_q.norm();
    // δq ≤ (a few u)(1 − |a|) + u + |a| δψ; F = q/(1 − q): δF/F ≤ δq/|q| + δ(1 − q)/|1 − q|.
    let dq = 4.0 * U * (one_minus_m + 1.0) + m * (dpsi + 4.0 * U);
    let rel = if m > 0.0 { dq / m } else { 0.0 } + (dq + 4.0 * U * w) / w;
    Some((q / one_minus_q, rel))
}

impl TailClosure {
    fn round_trip(&self, level: Fidelity) -> Option<&RoundTrip> {
        match level {
            Fidelity::PaperRules => self.paper.as_ref(),
            _ => Some(&self.vector),
        }
    }

    /// The phase error (rad) of ψ at `lambda_m`: the round trip's path known to a few u
    /// relative (docs/PHYSICS.md §8), plus the rounding of arg A and of the reduction.
    fn dpsi(&self, lambda_m: f64) -> f64 {
        let cu = 8.0 * U;
        TAU * cu * (self.round_trip_path.to_f64().abs() / lambda_m + 1.0)
    }

    fn cycles(&self, lambda_m: f64) -> f64 {
        phase_cycles(self.round_trip_path, DoubleDouble::ZERO, lambda_m)
    }

    /// The field of orders N + 1, N + 2, … given order N's field `e` (its own path phase
    /// excluded, as in a contribution) at vacuum wavelength `lambda_m`, under the model of
    /// `level` (`vector` or `paper_rules`), and a bound on its relative rounding error.
    pub fn field(&self, e: &Field3, level: Fidelity, lambda_m: f64) -> (Field3, f64) {
        let rt = self
            .round_trip(level)
            .expect("a paper_rules tail is closed where the paper's rules were traced");
        let c = self.cycles(lambda_m);
        let dpsi = self.dpsi(lambda_m);
        let dot = |v: DVec3| e[0] * v.x + e[1] * v.y + e[2] * v.z;
        let (es, ep) = (dot(self.s), dot(self.p));
        let mut out = [Complex64::default(); 3];
        let mut rel = 0.0f64;
        for (k, (amp, v)) in [(es, self.s), (ep, self.p)].into_iter().enumerate() {
            if amp == Complex64::default() {
                continue;
            }
            let Some((f, r)) = geometric_sum(rt.a[k], rt.one_minus_abs2[k], c, dpsi) else {
                return ([Complex64::new(f64::NAN, f64::NAN); 3], f64::NAN);
            };
            rel = rel.max(r);
            let x = amp * f;
            out[0] += x * v.x;
            out[1] += x * v.y;
            out[2] += x * v.z;
        }
        (out, rel)
    }

    /// The intensity of orders N + 1, N + 2, … added without phase (`incoherent`), given order
    /// N's field `e`: Σ_σ |e_σ|² |A_σ|²/(1 − |A_σ|²).
    pub(crate) fn incoherent_intensity(&self, e: &Field3) -> f64 {
        let dot = |v: DVec3| e[0] * v.x + e[1] * v.y + e[2] * v.z;
        let rt = &self.vector;
        [dot(self.s), dot(self.p)]
            .iter()
            .zip(rt.one_minus_abs2)
            .map(|(x, d)| {
                if x.norm_sqr() == 0.0 {
                    0.0
                } else {
                    x.norm_sqr() * (1.0 - d) / d
                }
            })
            .sum()
    }

    /// The scalar rungs' sum of orders N + 1, … as a factor on order N's scalar amplitude √I_N:
    /// Σ_k √(w_s |A_s|^{2k} + w_p |A_p|^{2k}) e^{2πi k (ΔS/λ + j/2)}, w_σ = |e_σ|²/|e|² (j the
    /// denser-side reflections per round trip when `jump`), docs/PHYSICS.md §5a eq. (T2). For s
    /// or p light it is the geometric series of (T1) (as before, bit for bit, also where the
    /// other component is below 1e-15 of it and decays no slower, so that its share of every
    /// order stays below 1e-30); for mixed light it is [`scalar_series::scalar_tail`].
    /// `close` refuses 1 − |A_σ|² < [`scalar_series::MIN_ONE_MINUS_ABS2`], below which the sum
    /// cannot be certified (the NaN arms are unreachable).
    pub(crate) fn scalar_factor(&self, e: &Field3, jump: bool, lambda_m: f64) -> Complex64 {
        let dot = |v: DVec3| e[0] * v.x + e[1] * v.y + e[2] * v.z;
        let (es, ep) = (dot(self.s).norm(), dot(self.p).norm());
        let d = self.vector.one_minus_abs2;
        let mut c = self.cycles(lambda_m);
        if jump {
            c += 0.5 * (self.denser_per_round_trip % 2) as f64;
        }
        let pure = if ep <= PURE_POLARIZATION * es && d[1] >= d[0] {
            Some(0)
        } else if es <= PURE_POLARIZATION * ep && d[0] >= d[1] {
            Some(1)
        } else {
            None
        };
        let nan = Complex64::new(f64::NAN, f64::NAN);
        match pure {
            Some(k) => {
                let m = Complex64::from((1.0 - d[k]).max(0.0).sqrt());
                geometric_sum(m, d[k], c, self.dpsi(lambda_m)).map_or(nan, |(f, _)| f)
            }
            None => scalar_series::scalar_tail([es * es, ep * ep], d, c).map_or(nan, |t| t.sum),
        }
    }
}

/// Why a tail could not be closed exactly.
#[derive(Clone, Debug, PartialEq)]
pub struct NotClosable(pub String);

impl std::fmt::Display for NotClosable {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(&self.0)
    }
}

fn refuse<T>(msg: impl Into<String>) -> Result<T, NotClosable> {
    Err(NotClosable(msg.into()))
}

/// The last two reflection coefficients (r_s, r_p) a ray's ledger records, in order (the
/// round trip's A_σ = r_σ(X) r_σ(Y); also [`super::round_trips`]).
pub(crate) fn last_two_reflections(ray: &Ray) -> Option<[(Complex64, Complex64); 2]> {
    let mut last = None;
    let mut before = None;
    for e in ray.ledger.entries.iter() {
        if let LedgerEntry::Reflection { r_s, r_p, .. } = e {
            before = last;
            last = Some((*r_s, *r_p));
        }
    }
    Some([before?, last?])
}

/// 1 − |r|² for r = (x − y)/(x + y) with x real: 4 x Re(y)/|x + y|² (Stokes; 0 under TIR).
fn stokes(x: f64, y: Complex64) -> f64 {
    4.0 * x * y.re / (Complex64::from(x) + y).norm_sqr()
}

/// Close the tail of every plane-wave source's Airy orders in `arrivals` (traced by
/// [`super::arrivals`] into the far field): append, per channel, one arrival whose
/// [`Arrival::tail`] stands for all orders beyond the deepest traced one (module docs). Returns
/// the number of arrivals appended, or why the closure would not be exact.
pub fn close(
    scene: &Scene,
    optics: &SceneOptics,
    arrivals: &mut Vec<Arrival>,
) -> Result<usize, NotClosable> {
    // The scene: two unbounded dielectric interfaces on one line of normals.
    let nx = one_film(scene, "the Airy tail is closed").map_err(NotClosable)?;
    let mut added = Vec::new();
    for (si, src) in scene.sources.iter().enumerate() {
        if !matches!(src.emitter, Emitter::PlaneWave { .. }) {
            return refuse("the Airy tail is closed only for plane-wave sources");
        }
        if src.coherence_length_m.is_finite() {
            return refuse(
                "the Airy tail is closed only for light of infinite coherence length (finite: \
                 far orders lose coherence by the paper's rule)",
            );
        }
        // The traced orders arrive with their optical paths from Snell's invariant
        // (`trace::parallel_phase`, every far-field walk): the closure multiplies the deepest
        // one by 1/(1 − q), so a phase error growing with the order, as the sum along f64
        // segments over a lateral run of metres has, is what it amplifies most
        // (`fuzz_airy_s1_203`: 2.5e-9 rad at the ninth order was 7.1e-9 of R).
        let own: Vec<&Arrival> = arrivals.iter().filter(|a| a.source == si).collect();
        let Some(deep) = own.iter().max_by_key(|a| a.path.sequence.len()).copied() else {
            continue;
        };
        let seq: Vec<_> = deep.path.sequence.iter().copied().collect();
        if entry_reflects_totally(scene, optics, &deep.path) {
            // The film carries no propagating wave here by the tracer's own verdict at the
            // face the wave meets first: its reflection and tunnelled wave are the frustrated
            // layer's whole Airy sum (docs/PHYSICS.md §5), no order enters the film and no tail
            // is left out. The budget's rule for such points keeps a margin of 1e-12 n1² in
            // (n2 cos θ2)² (`case::run::budget`); inside it the tracer still reflects totally,
            // and these points were refused as "no order with an internal reflection reached
            // the probe" or "the deepest traced sequence (1 events) …" (fuzz `airy` seed 1
            // count 10^4: 23 scenes 1e-9°…1e-7° beyond the critical angle, e.g. 183, 1658).
            continue;
        }
        let len = seq.len();
        // Exit: refractions only after the run of internal reflections.
        let mut end = len;
        while end > 0 && seq[end - 1].kind == EventKind::Refract {
            end -= 1;
        }
        let mut start = end;
        while start > 0 && seq[start - 1].kind == EventKind::Reflect {
            start -= 1;
        }
        let run = &seq[start..end];
        if run.is_empty() {
            return refuse(format!(
                "no order with an internal reflection reached the probe (the deepest traced \
                 sequence has {len} event(s)): the path solver did not land the orders through \
                 the film here"
            ));
        }
        if run.len() < 2
            || end == len
            || run.windows(2).any(|w| w[0].surface == w[1].surface)
            || seq[..start].iter().any(|e| e.kind == EventKind::Reflect)
        {
            return refuse(format!(
                "the deepest traced sequence ({} events) does not end in a round trip between \
                 the faces followed by refractions out",
                len
            ));
        }
        let mut shorter = seq.clone();
        shorter.drain(start..start + 2);
        let group = |s: &[crate::trace::path::Event]| -> Vec<&Arrival> {
            own.iter()
                .filter(|a| a.path.sequence.iter().eq(s.iter()))
                .copied()
                .collect()
        };
        let (deep_group, prev_group) = (group(&seq), group(&shorter));
        if prev_group.len() != deep_group.len() {
            return refuse("the order before the deepest one was not traced");
        }
        // The inside index and the indices beyond X (= run[0]'s face) and Y.
        let path = &deep.path;
        let n_in = path.indices[start + 1];
        let faces = [run[0].surface, run[1].surface];
        let mut beyond = [0.0; 2];
        for (k, &f) in faces.iter().enumerate() {
            let d_in = path.dirs[start + k];
            let Some(o) = optics.surfaces[f] else {
                return refuse("a face of the film is opaque");
            };
            let (a, b) = indices_for(o, scene.surfaces[f].plane.normal, d_in, n_in);
            if a != n_in || path.indices[start + k] != n_in {
                return refuse("the round trip does not stay in one medium");
            }
            beyond[k] = b;
        }
        for (d, p) in deep_group.iter().zip(&prev_group) {
            let v = &d.vector;
            if v.coherence_id == INCOHERENT || v.coherence_id != p.vector.coherence_id {
                return refuse("the orders do not stay coherent with each other");
            }
            // The squared normal wavevector on the exit side, as the tracer carried it.
            let Some((m, invariant)) = v.normal_q2 else {
                return refuse("the exit ray carries no normal wavevector");
            };
            if m != nx && m != -nx {
                return refuse("the exit face is not parallel to the film");
            }
            // Every medium's (n cos θ)² from the invariant as the ray carried it (formed in
            // one medium, never chained through the others).
            let q2_at = |n: f64| invariant.q2_in(n);
            let k_of = |n: f64| {
                let q2 = q2_at(n);
                if q2.hi >= 0.0 {
                    Complex64::from(q2.sqrt().to_f64())
                } else {
                    Complex64::new(0.0, (-q2).sqrt().to_f64())
                }
            };
            let k_in = k_of(n_in).re;
            // Per face and σ: 1 − |r|² (Stokes), then 1 − |A|² = D_X + |r_X|² D_Y.
            let d_face = |nb: f64| {
                let kb = k_of(nb);
                [stokes(k_in, kb), stokes(nb * nb * k_in, kb * (n_in * n_in))]
            };
            let (dx, dy) = (d_face(beyond[0]), d_face(beyond[1]));
            let d_a = [0, 1].map(|k| dx[k] + (1.0 - dx[k]) * dy[k]);
            let vector = |ray: &Ray| -> Result<RoundTrip, NotClosable> {
                let Some([(sx, px), (sy, py)]) = last_two_reflections(ray) else {
                    return refuse("the ledger holds no round trip");
                };
                let a = [sx * sy, px * py];
                for k in 0..2 {
                    // The tracer's coefficients and Stokes' relations must describe one face pair.
                    if ((1.0 - a[k].norm_sqr()) - d_a[k]).abs() > 1e-12 {
                        return refuse(format!(
                            "the traced round trip (|A|² = {}) does not match the faces' \
                             Fresnel coefficients (1 − |A|² = {:e})",
                            a[k].norm_sqr(),
                            d_a[k]
                        ));
                    }
                }
                if d_a.iter().any(|x| *x <= 0.0) {
                    return refuse(
                        "both faces reflect totally (|r21 r23| = 1): the orders do not decay and \
                         their sum does not converge",
                    );
                }
                // The scalar rungs' sum for mixed light (eq. T2) is certified down to this
                // 1 − |A|²; below it no rung's closure is offered rather than a NaN one.
                if d_a.iter().any(|x| *x < scalar_series::MIN_ONE_MINUS_ABS2) {
                    return refuse(format!(
                        "a round trip keeps all but {:e} of its power (1 − |A|² below {:e}): \
                         the scalar rungs' closed sum cannot be certified there",
                        d_a[0].min(d_a[1]),
                        scalar_series::MIN_ONE_MINUS_ABS2
                    ));
                }
                Ok(RoundTrip {
                    a,
                    one_minus_abs2: d_a,
                })
            };
            let vector = vector(v)?;
            // The paper's rules keep |r| of (P1)–(P4) and change only phases: their round trip
            // is closed with their own phases and 1 − |A|² from Stokes' relations (they form
            // |r| from an f64 cos θ, which at grazing incidence rounds |A| to 1).
            let paper =
                d.paper
                    .as_ref()
                    .and_then(last_two_reflections)
                    .map(|[(sx, px), (sy, py)]| RoundTrip {
                        a: [sx * sy, px * py],
                        one_minus_abs2: d_a,
                    });
            let dir = v.dir;
            let s = crate::optics::fresnel::s_of_plane_of_incidence(dir, nx)
                .unwrap_or_else(|| dir.any_orthonormal_vector());
            // One round trip's optical path: 2 d n cos θ inside (d the film's thickness, n cos θ
            // from the carried q², both double-double), the difference of the traced paths of
            // orders N and N − 1 without its rounding. That difference is of two paths of
            // metres near grazing incidence, each a few u of its own length off, and the sum
            // divides its error by |1 − q|: films 1e-10° below the critical angle of their top
            // face (|1 − q| ~ 1e-4, round-trip segments of 0.3 m in a 1 µm film) were closed
            // 7.5e-7 off 50 digits (`fringe fuzz --family airy --seed 1`, scenes 77, 203).
            let round_trip_path = film_thickness(scene) * q2_at(n_in).sqrt() * 2.0;
            let closure = TailClosure {
                round_trip_path,
                s,
                p: dir.cross(s),
                vector,
                paper,
                denser_per_round_trip: d
                    .path
                    .denser_reflections
                    .saturating_sub(p.path.denser_reflections),
                traced_orders: run.len().div_ceil(2),
            };
            let mut a = (*d).clone();
            a.tail = Some(Arc::new(closure));
            added.push(a);
        }
    }
    let n = added.len();
    arrivals.extend(added);
    Ok(n)
}

/// Whether the tracer reflects `path`'s light totally at the first face it meets (the wave
/// launched along `dirs[0]` in `indices[0]`): the verdict of the tracer's own interaction,
/// (n2 cos θt)² < 0 in double-double from the same direction, normal and carried launch q²
/// (`interaction::normal_wavevector_squares`), so the two cannot disagree.
fn entry_reflects_totally(
    scene: &Scene,
    optics: &SceneOptics,
    path: &crate::trace::path::SolvedPath,
) -> bool {
    let (Some(ev), Some(&d), Some(&n1)) = (
        path.sequence.first(),
        path.dirs.first(),
        path.indices.first(),
    ) else {
        return false;
    };
    let Some(o) = optics.surfaces[ev.surface] else {
        return false;
    };
    let normal = scene.surfaces[ev.surface].plane.normal;
    let (a, b) = indices_for(o, normal, d, n1);
    let (_, q2_t) = crate::optics::interaction::normal_wavevector_squares(
        d,
        normal,
        (a, b),
        path.launch_normal_q2,
    );
    a != b && q2_t.hi < 0.0
}

/// The normal of the first face if `scene` is one film: exactly two unbounded dielectric
/// interfaces whose normals lie on one line, so that every further order is the one before
/// it after the same round trip. Otherwise why not, each reason beginning with `what` ("the
/// Airy tail is closed", [`super::round_trips`]' "round trips are traced").
pub(crate) fn one_film(scene: &Scene, what: &str) -> Result<DVec3, String> {
    if scene.surfaces.len() != 2 {
        return Err(format!(
            "{what} only between the two faces of one film, and this scene has {} surfaces",
            scene.surfaces.len()
        ));
    }
    for s in &scene.surfaces {
        if !matches!(s.extent, Extent::Unbounded)
            || !matches!(s.kind, SurfaceKind::Interface { .. })
        {
            return Err(format!(
                "{what} only between unbounded dielectric faces; {:?} is not one",
                s.name
            ));
        }
    }
    let (nx, ny) = (
        scene.surfaces[0].plane.normal,
        scene.surfaces[1].plane.normal,
    );
    if nx != ny && nx != -ny {
        return Err(format!(
            "{what} only between parallel faces (the film's faces are not parallel: further \
             orders are not the same round trip)"
        ));
    }
    Ok(nx)
}

/// The distance (m) between the two parallel faces of the scene (`close` has checked there are
/// exactly two, with normals on one line), in double-double from the planes as held: the
/// signed distances of one point from both, along each plane's own N/|N| (also
/// [`super::round_trips`]).
pub(crate) fn film_thickness(scene: &Scene) -> DoubleDouble {
    let (x, y) = (&scene.surfaces[0].plane, &scene.surfaces[1].plane);
    let o = x.anchor;
    let (sx, sy) = (x.signed_distance_dd(o), y.signed_distance_dd(o));
    if x.normal == y.normal {
        (sy - sx).abs()
    } else {
        (sy + sx).abs()
    }
}
