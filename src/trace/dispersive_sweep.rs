//! The round-trip spectrum of a dispersive film (Sellmeier, Cauchy, …) without a trace per
//! wavelength: the orders' structure is traced once, and at every further wavelength only the
//! indices, the Fresnel coefficients and the round trip's phase are formed again
//! (docs/PHYSICS.md §5a, eq. T1; §8 for the carried invariant).
//!
//! Between two parallel faces the traced orders of a plane wave differ from wavelength to
//! wavelength only in numbers, not in structure, unless a critical angle is crossed: the
//! same sequences (which face, reflect or refract, from which side), the same channels, the
//! same further orders. A [`Sweep`] is that structure, taken from one trace by round trips
//! ([`super::round_trips::rays`]) at a reference wavelength λ0. At a wavelength λ it forms:
//!
//! - the index on each side of each face met (n(λ) of its media);
//! - Snell's invariant of the launch at the first face, (n1 cos θ1)² in double-double from the
//!   launch direction ([`snell_invariant`], as the tracer forms it at that face), and from it
//!   (n cos θ)² in every medium ([`SnellInvariant::q2_in`]);
//! - each face's Fresnel coefficients from them, by the tracer's own formula
//!   ([`fresnel::fresnel_with_cos2_t`] with cos θi and cos²θt as `interaction` forms them):
//!   at λ0 they are checked bit for bit against the coefficients the traced rays' ledgers hold;
//! - per σ ∈ {s, p} the sum over the orders F_σ = Σ_k C_σ,k e^{2πi j_k ΔS/λ}, with C_σ,k the
//!   product of order k's coefficients, j_k its round trips beyond the source's shallowest
//!   order and ΔS = 2 d n cos θ inside (double-double from the faces' distance and the carried
//!   q², as [`super::tail`] forms it; its fraction of a cycle reduced in double-double,
//!   [`super::phase_cycles`]). The orders beyond the traced ones follow the deepest traced
//!   one, each after one more round trip A_σ e^{2πi ΔS/λ} (A_σ = r_σ(X) r_σ(Y) of the last
//!   two reflections), as many as the limits allow: the orders of [`super::round_trips::rays`];
//! - the intensity I = W_s |F_s|² + W_p |F_p|², W_σ = Σ_groups |Σ_channels a_σ|² over the
//!   source's coherence groups, a_σ the channel's launch field along s and p = d × s of the
//!   launch direction (the s and p of every order are the same line: every face is parallel,
//!   so each event multiplies a_s by c_s and a_p by c_p, docs/PHYSICS.md §1).
//!
//! The path difference of two orders of one source that enter and leave by the same faces in
//! the same directions is the optical path of the film segments they do not share: each film
//! segment between the two faces is κ d (κ = n cos θ inside, the plane-wave phase of
//! `trace::parallel_phase`), so order k is the shallowest order's path plus j_k ΔS. The walk
//! sums the same path along its segments; the two agree to its rounding
//! (`tests/suite/round_trips.rs`, `dispersive_sweep_equals_per_wavelength_traces`).
//!
//! Where the structure holds (anything else is refused at λ0 with the reason, and at λ
//! [`Sweep::intensity`] answers `None`, the caller then traces λ by round trips or by the
//! general walk): what [`super::round_trips::rays`] needs, one source, every channel coherent
//! (no coherence id 0, none lost on the way), not at normal incidence (s from the plane of
//! incidence), no event tunnelling, no face reflecting totally into a layer (frustrated
//! reflection), every face at λ reflecting totally where it did at λ0 and nowhere else (no
//! critical angle crossed: (n cos θ)² keeps its sign on both sides), and the indices of the
//! launch and exit media at λ those at λ0 (then the exit direction is λ0's, the target's).

use super::round_trips::{NotApplicable, check_scene, extension, traced_orders};
use super::{TraceSettings, phase_cycles};
use crate::optics::double_double::DoubleDouble;
use crate::optics::fresnel;
use crate::optics::interaction::{SnellInvariant, SurfaceOptics, snell_invariant};
use crate::optics::material::IndexError;
use crate::optics::ray::{INCOHERENT, LedgerEntry};
use crate::scene::{Scene, SceneOptics};
use crate::trace::path::{EventKind, Target};
use glam::DVec3;
use num_complex::Complex64;
use std::f64::consts::TAU;

/// At most this many distinct (face, side) encounters: two faces, each from either side.
const MAX_FACES: usize = 4;

/// At most this many events per traced order (the short trace has at most
/// [`super::round_trips::TRACED_INTERNAL_REFLECTIONS`] internal reflections, plus the
/// refractions in and out and the external reflection).
const MAX_EVENTS: usize = 16;

fn refuse<T>(msg: impl Into<String>) -> Result<T, NotApplicable> {
    Err(NotApplicable(msg.into()))
}

/// One face met from one side.
#[derive(Clone, Copy, Debug, PartialEq)]
struct Face {
    /// The surface's index in the scene.
    surface: usize,
    /// Met from the side its normal points to (d_i·N < 0): incident index n_front.
    from_front: bool,
}

/// One traced order: its events as (face, reflect) and its round trips beyond the source's
/// shallowest order.
#[derive(Clone, Debug)]
struct Order {
    events: Vec<(usize, bool)>,
    round_trips: u32,
}

/// Reflection and transmission coefficients (s, p) of each face at one wavelength.
#[derive(Clone, Copy, Debug, Default)]
struct FaceCoefficients {
    r: [Complex64; 2],
    t: [Complex64; 2],
}

/// The structure of a dispersive film's round-trip spectrum toward one far-field direction
/// (module docs), taken at λ0 and evaluated at any wavelength where it holds.
#[derive(Clone, Debug)]
pub struct Sweep {
    /// The reference wavelength (m).
    lambda0_m: f64,
    /// The unit launch direction.
    dir0: DVec3,
    /// The faces met, at most [`MAX_FACES`].
    faces: Vec<Face>,
    /// The traced orders (distinct paths), in the trace's order.
    orders: Vec<Order>,
    /// The deepest traced order (index into `orders`) and the faces (X, Y) of its last two
    /// reflections, when further orders follow.
    deepest: Option<(usize, usize, usize)>,
    /// How many further orders the limits allow.
    further: usize,
    /// The face whose incident side is the film (its n1 is the film's index).
    film_face: usize,
    /// The first face met (the invariant is formed there) and the launch index at λ0.
    launch: (usize, f64),
    /// The last face met, whether the last event reflects, and the exit index at λ0.
    exit: (usize, bool, f64),
    /// Per face, whether it reflects totally at λ0 (and must at every swept wavelength).
    tir: [bool; MAX_FACES],
    /// The distance between the faces (m), double-double.
    thickness: DoubleDouble,
    /// W_σ = Σ_groups |Σ_channels a_σ|² (σ = s, p): the intensity per |F_σ|².
    weights: [f64; 2],
}

/// (n1, n2) of `face` given its surface's optics.
fn sides(optics: Option<SurfaceOptics>, face: Face) -> Option<(f64, f64)> {
    match optics? {
        SurfaceOptics::Dielectric { n_front, n_back } => Some(if face.from_front {
            (n_front, n_back)
        } else {
            (n_back, n_front)
        }),
        _ => None,
    }
}

/// The coefficients of `face` with indices (n1, n2) for a wave of Snell invariant `inv`, as
/// `interaction` forms them for a dielectric face under the `vector` model (with no layer
/// behind it, [`Sweep::new`] checks), and whether it reflects totally ((n2 cos θt)² < 0);
/// `None` at grazing incidence or at the critical angle ((n cos θ)² = 0 on a side) or where no
/// wave propagates on the incident side.
#[inline]
fn coefficients(inv: SnellInvariant, (n1, n2): (f64, f64)) -> Option<(FaceCoefficients, bool)> {
    let (q2_i, q2_t) = (inv.q2_in(n1), inv.q2_in(n2));
    if q2_i.hi <= 0.0 || q2_t.hi == 0.0 {
        return None;
    }
    let cos_i = (q2_i.sqrt().to_f64() / n1).min(1.0);
    let c = if n1 == n2 {
        fresnel::fresnel(n1, n2, cos_i)
    } else {
        fresnel::fresnel_with_cos2_t(n1, n2, cos_i, q2_t.to_f64() / (n2 * n2))
    };
    Some((
        FaceCoefficients {
            r: [c.r_s, c.r_p],
            t: [c.t_s, c.t_p],
        },
        q2_t.hi < 0.0,
    ))
}

impl Sweep {
    /// The structure of the spectrum toward the far-field `target` from one trace by round
    /// trips at the wavelength of `optics` (sequences discovered with `probe_targets`, as
    /// [`super::round_trips::rays`]), or why it does not hold (module docs).
    pub fn new(
        scene: &Scene,
        optics: &SceneOptics,
        probe_targets: &[DVec3],
        target: &Target,
        settings: &TraceSettings,
    ) -> Result<Sweep, NotApplicable> {
        let normal = check_scene(scene, target)?;
        if scene.sources.len() != 1 {
            return refuse("the sweep takes one source (sources may share coherence groups)");
        }
        let src = &scene.sources[0];
        let arrivals = traced_orders(scene, optics, probe_targets, target, settings);
        if arrivals.is_empty() {
            return refuse("no order reaches the target");
        }
        let own: Vec<usize> = (0..arrivals.len()).collect();
        let ext = extension(scene, optics, normal, &arrivals, &own, &settings.limits)?;
        let channels = src.channels();
        if channels.iter().any(|c| c.coherence_id == INCOHERENT)
            || arrivals.iter().any(|a| a.vector.coherence_id == INCOHERENT)
        {
            return refuse("a channel is incoherent (its orders add intensity only)");
        }
        // The distinct paths: the walk records the channels of one path one after another.
        let mut paths = Vec::new();
        let mut k = 0;
        while k < arrivals.len() {
            let path = &arrivals[k].path;
            let n = arrivals[k..]
                .iter()
                .take_while(|a| std::sync::Arc::ptr_eq(&a.path, path))
                .count();
            if n != channels.len()
                || arrivals[k..k + n]
                    .iter()
                    .zip(&channels)
                    .any(|(a, c)| a.vector.coherence_id != c.coherence_id)
            {
                return refuse("an order does not carry every channel of the source");
            }
            paths.push(k);
            k += n;
        }
        let first = &arrivals[paths[0]];
        let (seq0, dirs0, idx0) = (&first.path.sequence, &first.path.dirs, &first.path.indices);
        let exit_of = |a: &super::Arrival| {
            let p = &a.path;
            let m = p.sequence.len();
            (
                p.sequence[0].surface,
                p.sequence[m - 1].surface,
                p.indices[m].to_bits(),
                p.indices[0].to_bits(),
                p.dirs[m],
            )
        };
        // The same faces and media in and out, the same exit direction to its rounding (each
        // order's is formed by its own chain of reflections and refractions).
        let same_way = |a: &(usize, usize, u64, u64, DVec3),
                        b: &(usize, usize, u64, u64, DVec3)| {
            a.0 == b.0 && a.1 == b.1 && a.2 == b.2 && a.3 == b.3 && (a.4 - b.4).length() <= 1e-12
        };
        if seq0.is_empty() {
            return refuse("an order meets no face");
        }
        let key = exit_of(first);
        let mut faces: Vec<Face> = Vec::with_capacity(MAX_FACES);
        let mut orders = Vec::with_capacity(paths.len());
        let mut film_index: Option<f64> = None;
        let mut film_face = None;
        let mut segments = Vec::with_capacity(paths.len());
        for &i in &paths {
            let a = &arrivals[i];
            if !same_way(&exit_of(a), &key) {
                return refuse(
                    "the orders do not all enter and leave by the same faces in the same directions",
                );
            }
            let p = &a.path;
            let m = p.sequence.len();
            if m > MAX_EVENTS {
                return refuse("an order has too many events for the sweep");
            }
            let mut events = Vec::with_capacity(m);
            let mut film_segments = 0u32;
            for (e, ev) in p.sequence.iter().enumerate() {
                let reflect = match ev.kind {
                    EventKind::Reflect => true,
                    EventKind::Refract => false,
                    EventKind::Tunnel => return refuse("an order tunnels through a layer"),
                };
                let surface = &scene.surfaces[ev.surface];
                let face = Face {
                    surface: ev.surface,
                    from_front: p.dirs[e].dot(surface.plane.normal) < 0.0,
                };
                let f = match faces.iter().position(|&x| x == face) {
                    Some(f) => f,
                    None if faces.len() < MAX_FACES => {
                        faces.push(face);
                        faces.len() - 1
                    }
                    None => return refuse("more than four face encounters"),
                };
                if e > 0 {
                    // A segment between two events: between the two faces, in the film.
                    if p.sequence[e - 1].surface == ev.surface {
                        return refuse("an order meets one face twice in a row");
                    }
                    if film_index.is_some_and(|n| n != p.indices[e]) {
                        return refuse("the orders cross more than one medium between the faces");
                    }
                    film_index = Some(p.indices[e]);
                    film_face = Some(f);
                    film_segments += 1;
                }
                events.push((f, reflect));
            }
            segments.push(film_segments);
            orders.push(Order {
                events,
                round_trips: 0,
            });
        }
        let fewest = *segments.iter().min().expect("an order");
        for (o, &s) in orders.iter_mut().zip(&segments) {
            if (s - fewest) % 2 != 0 {
                return refuse("two orders differ by an odd number of film segments");
            }
            o.round_trips = (s - fewest) / 2;
        }
        // The launch field of every channel along s and p of the launch direction.
        let dir0 = dirs0[0].normalize();
        let n_first = scene.surfaces[seq0[0].surface].plane.normal;
        let Some(s) = fresnel::s_of_plane_of_incidence(dir0, n_first) else {
            return refuse("normal incidence (each channel's own frame picks s)");
        };
        let p = dir0.cross(s);
        let mut groups: Vec<(u64, [Complex64; 2])> = Vec::with_capacity(channels.len());
        for c in &channels {
            let e = super::launch_ray(optics, c, src.coherence_length_m, &first.path).field();
            let dot = |v: DVec3| e[0] * v.x + e[1] * v.y + e[2] * v.z;
            let a = [dot(s), dot(p)];
            match groups.iter_mut().find(|g| g.0 == c.coherence_id) {
                Some(g) => {
                    g.1[0] += a[0];
                    g.1[1] += a[1];
                }
                None => groups.push((c.coherence_id, a)),
            }
        }
        let weights = [0, 1].map(|k| groups.iter().map(|g| g.1[k].norm_sqr()).sum::<f64>());
        let m = seq0.len();
        let exit_face = orders[0].events[m - 1];
        let mut sweep = Sweep {
            lambda0_m: optics.lambda_m,
            dir0,
            launch: (orders[0].events[0].0, idx0[0]),
            exit: (exit_face.0, exit_face.1, idx0[m]),
            faces,
            film_face: film_face.unwrap_or(0),
            deepest: None,
            further: 0,
            orders,
            tir: [false; MAX_FACES],
            thickness: super::tail::film_thickness(scene),
            weights,
        };
        if let Some(ext) = ext {
            let deep = paths
                .iter()
                .position(|&i| i == ext.deepest[0])
                .expect("the deepest order is a traced path");
            let reflections: Vec<usize> = sweep.orders[deep]
                .events
                .iter()
                .filter(|e| e.1)
                .map(|e| e.0)
                .collect();
            let &[.., x, y] = &reflections[..] else {
                return refuse("the deepest order holds no round trip");
            };
            sweep.deepest = Some((deep, x, y));
            sweep.further = ext.further;
        }
        // The coefficients the sweep forms at λ0 must be those the tracer applied, bit for bit.
        let mut table = [FaceCoefficients::default(); MAX_FACES];
        let mut tir = [false; MAX_FACES];
        if !matches!(
            sweep.face_coefficients(scene, optics.lambda_m, &mut table, &mut tir),
            Ok(Some(_))
        ) {
            return refuse(
                "a face is met at its critical angle or is not dielectric at the reference \
                 wavelength",
            );
        }
        for (f, _) in sweep.faces.iter().zip(tir).filter(|x| x.1) {
            // Total reflection into a layer adds the layer's frustrated coupling to r.
            if optics.layers[f.surface][usize::from(!f.from_front)].is_some() {
                return refuse("a face reflects totally into a layer (frustrated reflection)");
            }
        }
        sweep.tir = tir;
        for (o, &i) in sweep.orders.iter().zip(&paths) {
            let applied = arrivals[i]
                .vector
                .ledger
                .entries
                .iter()
                .filter_map(|e| match e {
                    LedgerEntry::Reflection { r_s, r_p, .. } => Some([*r_s, *r_p]),
                    LedgerEntry::Refraction { t_s, t_p, .. } => Some([*t_s, *t_p]),
                    _ => None,
                });
            let formed = o.events.iter().map(
                |&(f, reflect)| {
                    if reflect { table[f].r } else { table[f].t }
                },
            );
            if !applied.eq(formed) {
                return refuse("the sweep's Fresnel coefficients are not the tracer's");
            }
        }
        Ok(sweep)
    }

    /// The reference wavelength λ0 (m) the structure was traced at.
    pub fn reference_wavelength_m(&self) -> f64 {
        self.lambda0_m
    }

    /// Every face's coefficients at `lambda_m` into `table` and whether it reflects totally
    /// into `tir`, and the film's (n cos θ)² (double-double); `Ok(None)` where the structure
    /// does not hold there (a critical angle met, launch or exit index not λ0's).
    fn face_coefficients(
        &self,
        scene: &Scene,
        lambda_m: f64,
        table: &mut [FaceCoefficients; MAX_FACES],
        tir: &mut [bool; MAX_FACES],
    ) -> Result<Option<DoubleDouble>, IndexError> {
        // The same indices and errors as `Scene::optics`.
        scene.ambient.index(lambda_m)?;
        let mut optics = [None; 2];
        for (o, s) in optics.iter_mut().zip(&scene.surfaces) {
            *o = s.optics(lambda_m)?;
        }
        let mut n = [(0.0, 0.0); MAX_FACES];
        for (k, f) in self.faces.iter().enumerate() {
            let Some(x) = sides(optics[f.surface], *f) else {
                return Ok(None);
            };
            n[k] = x;
        }
        let (lf, n_launch) = self.launch;
        let (xf, xr, n_exit) = self.exit;
        let exit = if xr { n[xf].0 } else { n[xf].1 };
        if n[lf].0 != n_launch || exit != n_exit {
            return Ok(None);
        }
        // Snell's invariant as the tracer forms it at the first face (nothing carried yet).
        let normal = scene.surfaces[self.faces[lf].surface].plane.normal;
        let inv = snell_invariant(self.dir0, normal, n[lf].0, None);
        for k in 0..self.faces.len() {
            let Some((c, t)) = coefficients(inv, n[k]) else {
                return Ok(None);
            };
            table[k] = c;
            tir[k] = t;
        }
        Ok(Some(inv.q2_in(n[self.film_face].0)))
    }

    /// The traced intensity |E|² (`vector`) at vacuum wavelength `lambda_m` (module docs), or
    /// `None` where the structure traced at λ0 does not hold at `lambda_m` (then trace it).
    /// Errors where an index cannot be formed there (as [`Scene::optics`]).
    pub fn intensity(&self, scene: &Scene, lambda_m: f64) -> Result<Option<f64>, IndexError> {
        let mut table = [FaceCoefficients::default(); MAX_FACES];
        let mut tir = [false; MAX_FACES];
        let Some(q2) = self.face_coefficients(scene, lambda_m, &mut table, &mut tir)? else {
            return Ok(None);
        };
        // Which faces reflect totally is part of the structure (a critical angle crossed
        // changes the sequences).
        if tir != self.tir {
            return Ok(None);
        }
        // One round trip: ΔS = 2 d n cos θ inside, its fraction of a cycle in double-double.
        let round_trip = self.thickness * q2.sqrt() * 2.0;
        let c = phase_cycles(round_trip, DoubleDouble::ZERO, lambda_m);
        let (sin, cos) = (TAU * c).sin_cos();
        let w = Complex64::new(cos, sin);
        let mut f = [Complex64::default(); 2];
        let mut deepest = [Complex64::default(); 2];
        for (k, o) in self.orders.iter().enumerate() {
            let mut amp = [Complex64::from(1.0); 2];
            for &(face, reflect) in &o.events {
                let cf = if reflect {
                    table[face].r
                } else {
                    table[face].t
                };
                amp[0] *= cf[0];
                amp[1] *= cf[1];
            }
            let phase = w.powu(o.round_trips);
            for (a, sum) in amp.iter_mut().zip(f.iter_mut()) {
                *a *= phase;
                *sum += *a;
            }
            if self.deepest.is_some_and(|d| d.0 == k) {
                deepest = amp;
            }
        }
        if let Some((_, x, y)) = self.deepest {
            for (s, (sum, mut amp)) in f.iter_mut().zip(deepest).enumerate() {
                let q = table[x].r[s] * table[y].r[s] * w;
                for _ in 0..self.further {
                    amp *= q;
                    *sum += amp;
                }
            }
        }
        Ok(Some(
            self.weights[0] * f[0].norm_sqr() + self.weights[1] * f[1].norm_sqr(),
        ))
    }
}
