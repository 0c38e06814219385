//! A ray meets an interface: the reflected and refracted children (paper §3.3–3.5).
//!
//! The parent is advanced to the hit point (adding n·L to its optical path), its 3D field is
//! split into s and p in the frame of docs/PHYSICS.md §1, each component is multiplied by its Fresnel
//! coefficient, and each child carries the frame (X, Y) = (s, p_child), so (X, Y, dir) stays
//! right-handed. Children inherit or lose the coherence id according to the surface's
//! [`CoherenceRules`].

use crate::optics::double_double::{DoubleDouble, two_prod};
use crate::optics::fresnel::{self, FresnelCoefficients};
use crate::optics::material::CoherenceRules;
use crate::optics::ray::{Field3, INCOHERENT, LedgerEntry, Ray};
use glam::DVec3;
use num_complex::Complex64;

/// Which amplitude coefficients an interaction applies (the two polarized rungs of the
/// fidelity ladder, docs/PHYSICS.md §4).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum CoefficientModel {
    /// Complex Fresnel (P1)–(P6).
    Vector,
    /// The paper's |r|, |t| with π-jump rules (P7, P8) and its TIR phases.
    PaperRules,
}

/// Which child of an encounter a path follows.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Child {
    /// The reflected wave.
    Reflected,
    /// The refracted (transmitted) wave; none under total internal reflection.
    Refracted,
    /// The tunnelled wave of frustrated total reflection (docs/PHYSICS.md §5): at a face lit
    /// beyond its critical angle with a [`Layer`] behind it, the wave the evanescent field
    /// launches from the layer's far face into the medium beyond, with the layer's t_layer
    /// (s, p) of [`fresnel::frustrated_layer`]. None where the face is not lit beyond its
    /// critical angle, has no layer behind it, or the medium beyond is beyond its own critical
    /// angle too. The child leaves from the hit point: moving it to the far face (the foot of
    /// the normal through the hit point, with no optical path) is the caller's, who knows the
    /// scene (`trace::path::tunnel_exit`).
    Tunnelled,
}

impl From<bool> for Child {
    /// `true`: [`Child::Reflected`], `false`: [`Child::Refracted`].
    fn from(reflect: bool) -> Self {
        if reflect {
            Child::Reflected
        } else {
            Child::Refracted
        }
    }
}

/// What is on the two sides of the surface.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum SurfaceOptics {
    /// An interface between two lossless media; `n_front` on the side the normal points to.
    Dielectric {
        /// Index on the normal's side.
        n_front: f64,
        /// Index behind.
        n_back: f64,
    },
    /// A perfectly conducting mirror (reflects from either side, transmits nothing).
    IdealMirror,
    /// An ideal thin beam splitter of power reflectance R in a uniform medium of index `n`.
    Splitter {
        /// Power reflectance R in [0, 1].
        reflectance: f64,
        /// Index on both sides.
        n: f64,
    },
}

/// A layer behind a face: the slab between the face and a parallel interface (its
/// `partner`, a plate's or film's other face) at distance `thickness_m`, with index `n_beyond`
/// past the partner, at vacuum wavelength `lambda_m` ([`crate::scene::Scene::layer_behind`]).
/// Beyond the face's critical angle the evanescent field in it couples to the far face
/// (frustrated total reflection, docs/PHYSICS.md §5).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Layer {
    /// Index of the layer's far face in its scene.
    pub partner: usize,
    /// Thickness of the layer along the normal (m).
    pub thickness_m: f64,
    /// Index of the medium beyond the far face.
    pub n_beyond: f64,
    /// Vacuum wavelength (m) the indices are taken at.
    pub lambda_m: f64,
}

/// The local description of one ray–surface encounter.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct InterfaceHit {
    /// Index of the surface in its scene (for the ledger).
    pub surface: usize,
    /// Where the ray meets the surface (m).
    pub point: DVec3,
    /// Unit normal of the surface, pointing to its front side.
    pub normal: DVec3,
    /// What is on the two sides.
    pub optics: SurfaceOptics,
    /// What the children keep of the parent's coherence.
    pub coherence: CoherenceRules,
    /// The layer behind the face for light arriving from its front (`[0]`) and from its back
    /// (`[1]`), if any ([`Layer`]): under total internal reflection into it the reflected child
    /// takes the layer's frustrated coefficients ([`fresnel::frustrated_layer`]).
    pub layers: [Option<Layer>; 2],
}

/// The result of an interaction.
#[derive(Clone, Debug)]
pub struct Children {
    /// The reflected ray.
    pub reflected: Ray,
    /// `None` under total internal reflection and for mirrors.
    pub refracted: Option<Ray>,
    /// The coefficients that were applied.
    pub coefficients: FresnelCoefficients,
    /// |d_i·N|.
    pub cos_theta_i: f64,
    /// Index on the incident side.
    pub n1: f64,
    /// Index on the far side.
    pub n2: f64,
}

fn dot(e: &Field3, v: DVec3) -> Complex64 {
    e[0] * v.x + e[1] * v.y + e[2] * v.z
}

/// The (incident-side, far-side) indices for a ray travelling along `dir` in a medium of index
/// `current` (a mirror has the ray's medium on both sides as far as the ray is concerned).
pub(crate) fn indices_for(
    optics: SurfaceOptics,
    normal: DVec3,
    dir: DVec3,
    current: f64,
) -> (f64, f64) {
    match optics {
        SurfaceOptics::Dielectric { n_front, n_back } => {
            if dir.dot(normal) < 0.0 {
                (n_front, n_back)
            } else {
                (n_back, n_front)
            }
        }
        SurfaceOptics::IdealMirror => (current, current),
        SurfaceOptics::Splitter { n, .. } => (n, n),
    }
}

/// What every ray of direction `d_i` in a medium of index `index` meets at a hit, whatever its
/// polarization: the indices, the coefficients of the model and the s vector.
struct Encounter {
    d_i: DVec3,
    /// The s unit vector (docs/PHYSICS.md §1), `None` at normal incidence, where each ray's own X
    /// decides ([`fresnel::s_direction`]).
    s: Option<DVec3>,
    n1: f64,
    n2: f64,
    cos_theta_i: f64,
    coefficients: FresnelCoefficients,
    /// (n2 cos θt)² (negative under TIR) in double-double, from `invariant`.
    q2_t: DoubleDouble,
    /// Snell's invariant at the face: what every child carries to the next parallel face
    /// ([`Ray::normal_q2`]).
    invariant: SnellInvariant,
    /// The tunnelled wave's coefficients, if the face is lit beyond its critical angle with a
    /// layer behind it and a wave can leave the far face ([`Child::Tunnelled`]).
    tunnel: Option<Tunnelling>,
}

/// The tunnelled wave of an [`Encounter`]: the layer's t (s, p) under the model, the index
/// beyond the layer and (n3 cos θ3)² (double-double, from Snell's invariant).
#[derive(Clone, Copy)]
struct Tunnelling {
    t: [Complex64; 2],
    n3: f64,
    q2_3: DoubleDouble,
}

/// Snell's invariant p² = (n sin θ)² about a face's normal, held as the squared normal
/// wavevector q²_ref = (n_ref cos θ_ref)² (double-double) in the medium of index `n_ref` where it
/// was formed (docs/PHYSICS.md §8). In any index n the normal wavevector square is then
/// (n cos θ)² = (n² − n_ref²) + q²_ref, with n² − n_ref² from exact products, and exactly
/// q²_ref in n_ref itself. Carried between parallel faces ([`Ray::normal_q2`]) it is never
/// re-formed in the next medium and chained back: q²_film = q²_amb + n_f² − n_a² rounds at
/// ~1e-32 n_f², so a wave grazing in the ambient ((n0 cos θ0)² ~ 1e-32) lost its cosine inside a
/// denser film and came out of it at another angle (issue #12: Airy tails that could not be
/// closed, `tests/suite/truth_carried_invariant.rs`). `n_ref = 0` holds p² itself
/// (q²_ref = −p²).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct SnellInvariant {
    /// The reference index n_ref (0: `q2_ref` is −p²).
    pub n_ref: f64,
    /// (n_ref cos θ_ref)², double-double.
    pub q2_ref: DoubleDouble,
}

impl SnellInvariant {
    /// The invariant as (n cos θ)² = `q2` in index `n`.
    pub fn in_medium(n: f64, q2: DoubleDouble) -> Self {
        SnellInvariant {
            n_ref: n,
            q2_ref: q2,
        }
    }

    /// p² itself (`n_ref` = 0).
    pub fn from_p2(p2: DoubleDouble) -> Self {
        SnellInvariant {
            n_ref: 0.0,
            q2_ref: -p2,
        }
    }

    /// (n cos θ)² in index `n` (double-double; negative beyond the critical angle).
    #[inline]
    pub fn q2_in(self, n: f64) -> DoubleDouble {
        if n == self.n_ref {
            self.q2_ref
        } else {
            two_prod(n, n) - two_prod(self.n_ref, self.n_ref) + self.q2_ref
        }
    }
}

/// Snell's invariant of a ray of direction `d_i` in index `n1` at a face of unit normal
/// `normal`: `carried` (the ray's [`Ray::normal_q2`]) when `normal` is the same line (bitwise
/// ±), since Snell's law conserves the tangential wavevector between parallel faces
/// (docs/PHYSICS.md §8); otherwise (n1 cos θi)² in n1 from cos²θi = (d_i·N)²/(|d_i|²|N|²) of the
/// f64 vectors in double-double: the direction as given, whichever of cos θi and sin θi is the
/// small one.
#[inline]
pub fn snell_invariant(
    d_i: DVec3,
    normal: DVec3,
    n1: f64,
    carried: Option<(DVec3, SnellInvariant)>,
) -> SnellInvariant {
    match carried {
        Some((m, inv)) if m == normal || m == -normal => inv,
        _ => {
            let c = DoubleDouble::dot(d_i, normal);
            let cos2 = (c * c) / (DoubleDouble::dot(d_i, d_i) * DoubleDouble::dot(normal, normal));
            SnellInvariant::in_medium(n1, cos2 * two_prod(n1, n1))
        }
    }
}

/// The squared normal wavevector components (n1 cos θi)² and (n2 cos θt)² (the second
/// negative under total internal reflection) of a ray of direction `d_i` in index `n1` meeting
/// a face of unit normal `normal` into index `n2`, in double-double, each formed directly from
/// the ray's Snell invariant ([`snell_invariant`]), never one from the other.
///
/// The tracer ([`interact`]) and the path solver (`path::step_planes`) both call this, so they
/// agree on every total internal reflection.
pub fn normal_wavevector_squares(
    d_i: DVec3,
    normal: DVec3,
    (n1, n2): (f64, f64),
    carried: Option<(DVec3, SnellInvariant)>,
) -> (DoubleDouble, DoubleDouble) {
    let inv = snell_invariant(d_i, normal, n1, carried);
    (inv.q2_in(n1), inv.q2_in(n2))
}

/// The refracted direction sin θt t̂ − cos θt N_o for a given cos θt ≥ 0, normalized: Snell's
/// law in vector form (docs/PHYSICS.md §1), t̂ the unit tangential part of d_i, d_i − (d_i·N_o)
/// N_o, N_o the normal facing the incident side, and sin θt = √((1 − cos θt)(1 + cos θt)) from
/// the same cos θt (Snell's invariant) where θt > 45° (η·|t|, η = n1/n2, nearer the normal).
///
/// In a rotated frame the f64 tangential part d_i − (d_i·N_o) N_o keeps a normal component of
/// ~1e-16 absolute (the rounding of (d_i·N_o) N_o), i.e. ~1e-16/sin θi of its length; scaled
/// up to the exit's sin θt it was ~1e-16·sin θt/sin θi, which on leaving a dense film into a
/// thin ambient at grazing (film n = 2, ambient n = 0.001, sin θi = 5e-4, cos θt = 1.7e-14)
/// outweighed cos θt itself (−5.6e-14 against 1.7e-14): the exit direction pointed back into
/// the film and every order through it missed its far-field direction (`fringe fuzz --family
/// airy --seed 1`, scene 6567 rotated). The tangential part is re-orthogonalized once more.
pub(crate) fn snell_direction(
    d_i: DVec3,
    normal: DVec3,
    (n1, n2): (f64, f64),
    cos_t: f64,
) -> DVec3 {
    let n_o = if d_i.dot(normal) < 0.0 {
        normal
    } else {
        -normal
    };
    // Twice (Gram–Schmidt re-orthogonalization): once, its normal part is left at the
    // ~1e-16 absolute rounding of (d_i·N_o) N_o, which near the normal is ~1e-16/sin θi of
    // the tangential part; the second pass leaves ~1e-16 of the tangential part itself.
    let tangential = d_i - d_i.dot(n_o) * n_o;
    let tangential = tangential - tangential.dot(n_o) * n_o;
    let length = tangential.length();
    if length == 0.0 || !length.is_finite() {
        // Normal incidence: no tangential direction (and η·0 = 0 as before).
        return ((n1 / n2) * tangential - cos_t * n_o).normalize();
    }
    // Near the normal (cos θt > 1/√2) sin θt is η·|t| itself: √(1 − cos²θt) would lose it.
    let sin_t = if cos_t < std::f64::consts::FRAC_1_SQRT_2 {
        ((1.0 - cos_t) * (1.0 + cos_t)).sqrt()
    } else {
        (n1 / n2) * length
    };
    ((sin_t / length) * tangential - cos_t * n_o).normalize()
}

impl Encounter {
    /// `carried`: the ray's [`Ray::normal_q2`]; used when `hit`'s normal is the same line
    /// (bitwise ±), else q² is formed from d_i·N of the f64 vectors (exact products).
    fn new(
        d_i: DVec3,
        index: f64,
        carried: Option<(DVec3, SnellInvariant)>,
        hit: &InterfaceHit,
        model: CoefficientModel,
    ) -> Self {
        let (n1, n2) = indices_for(hit.optics, hit.normal, d_i, index);
        // Snell's law as conservation of the tangential wavevector: the normal components obey
        // (n2 cos θt)² = (n1 cos θi)² + (n2 − n1)(n2 + n1), formed exactly in double-double
        // (docs/PHYSICS.md §8), so a cosine that is a small difference of large squares (light
        // leaving a film at near-grazing outside) keeps its digits.
        let invariant = snell_invariant(d_i, hit.normal, n1, carried);
        let (q2_i, q2_t) = (invariant.q2_in(n1), invariant.q2_in(n2));
        let cos_theta_i = (q2_i.sqrt().to_f64() / n1).min(1.0);
        let mut coefficients = match (hit.optics, model) {
            (SurfaceOptics::IdealMirror, _) => fresnel::ideal_mirror(),
            (SurfaceOptics::Splitter { reflectance, .. }, _) => {
                fresnel::ideal_splitter(reflectance, d_i.dot(hit.normal) < 0.0)
            }
            (SurfaceOptics::Dielectric { .. }, CoefficientModel::Vector) => {
                if n1 == n2 {
                    fresnel::fresnel(n1, n2, cos_theta_i)
                } else {
                    fresnel::fresnel_with_cos2_t(n1, n2, cos_theta_i, q2_t.to_f64() / (n2 * n2))
                }
            }
            (SurfaceOptics::Dielectric { .. }, CoefficientModel::PaperRules) => {
                fresnel::paper_rules(n1, n2, cos_theta_i)
            }
        };
        // Total internal reflection into a layer: the Airy sum with imaginary cos θ2
        // (docs/PHYSICS.md §5, frustrated total reflection). The paper's rung writes its TIR
        // phases in the opposite time convention (the complex conjugates of P5, P6,
        // [`fresnel::paper_rules`]), so it takes the conjugate of the coupling's term.
        let layer = hit.layers[usize::from(d_i.dot(hit.normal) >= 0.0)];
        let mut tunnel = None;
        if let (Some(l), SurfaceOptics::Dielectric { .. }) = (layer, hit.optics)
            && q2_t.hi < 0.0
        {
            let q2_3 = invariant.q2_in(l.n_beyond);
            let f = fresnel::frustrated_layer(
                (n1, n2, l.n_beyond),
                (q2_i, q2_t, q2_3),
                l.thickness_m,
                l.lambda_m,
            );
            let (dr_s, dr_p) = match model {
                CoefficientModel::Vector => (f.dr[0], f.dr[1]),
                CoefficientModel::PaperRules => (f.dr[0].conj(), f.dr[1].conj()),
            };
            coefficients.r_s += dr_s;
            coefficients.r_p += dr_p;
            // The tunnelled wave (a wave leaves the far face only where (n3 cos θ3)² > 0); the
            // paper's rung takes the conjugate as for the reflected coupling, so every rung
            // keeps R + T = 1.
            if q2_3.hi > 0.0 {
                let t = match model {
                    CoefficientModel::Vector => f.t,
                    CoefficientModel::PaperRules => f.t.map(|t| t.conj()),
                };
                tunnel = Some(Tunnelling {
                    t,
                    n3: l.n_beyond,
                    q2_3,
                });
            }
        }
        Encounter {
            d_i,
            s: fresnel::s_of_plane_of_incidence(d_i, hit.normal),
            n1,
            n2,
            cos_theta_i,
            coefficients,
            q2_t,
            invariant,
            tunnel,
        }
    }

    /// The s vector for a ray whose frame has X axis `x`: `fresnel::s_direction(d_i, N, x)`.
    fn s_for(&self, x: DVec3) -> DVec3 {
        self.s
            .unwrap_or_else(|| fresnel::s_at_normal_incidence(self.d_i, x))
    }

    /// The components (a_s, a_p) of the field `e` along s and p_i = d_i × s.
    fn amplitudes(&self, e: &Field3, s: DVec3) -> (Complex64, Complex64) {
        let p_i = self.d_i.cross(s);
        (dot(e, s), dot(e, p_i))
    }
}

/// The parent ray at the hit point, split into s and p, with the coefficients of the model.
struct Split {
    encounter: Encounter,
    /// The s unit vector of this ray (docs/PHYSICS.md §1).
    s: DVec3,
    /// The parent's field components along s and p_i.
    a_s: Complex64,
    a_p: Complex64,
}

/// Advances `parent` to the hit point and splits its field.
fn split(parent: &mut Ray, hit: &InterfaceHit, model: CoefficientModel) -> Split {
    parent.advance_to_event(hit.point);
    // Step 1: the coefficients and the s/p frame of the incident ray.
    let encounter = Encounter::new(parent.dir, parent.index, parent.normal_q2, hit, model);
    let s = encounter.s_for(parent.x);
    // Step 2: the field along s and p_i.
    let (a_s, a_p) = encounter.amplitudes(&parent.field(), s);
    Split {
        encounter,
        s,
        a_s,
        a_p,
    }
}

/// One child of an encounter, apart from the parent's field: its direction, the coefficients
/// (c_s, c_p) it applies, its medium, whether it keeps coherence and its ledger entry.
struct Branch {
    dir: DVec3,
    c: [Complex64; 2],
    index: f64,
    keep: bool,
    entry: LedgerEntry,
}

/// Step 3: the reflected branch.
fn reflected(en: &Encounter, hit: &InterfaceHit) -> Branch {
    let c = &en.coefficients;
    Branch {
        // Normalized: d − 2(d·N)N keeps |d| only if |N| = 1, and an f64 normal in a rotated
        // frame is unit to ~u, so |d|² drifted by 4(d·N)²(|N|² − 1) per reflection — 8e-13
        // after the ~900 internal reflections of an Airy sum — and the p axis d × s of the
        // child's frame with it: the p amplitude grew by that at every event, 1e-12 of R (`fringe
        // fuzz --family airy --seed 1`, scene 5779, `tests/suite/truth_found_edges.rs`).
        dir: fresnel::reflect(en.d_i, hit.normal).normalize(),
        c: [c.r_s, c.r_p],
        index: en.n1,
        keep: hit.coherence.reflected_keeps,
        entry: LedgerEntry::Reflection {
            surface: hit.surface,
            r_s: c.r_s,
            r_p: c.r_p,
            tir: c.total_internal_reflection,
        },
    }
}

/// Step 4: the refracted branch, unless TIR or a mirror.
fn refracted(en: &Encounter, hit: &InterfaceHit) -> Option<Branch> {
    if matches!(hit.optics, SurfaceOptics::IdealMirror) {
        return None;
    }
    let c = &en.coefficients;
    let dir = if matches!(hit.optics, SurfaceOptics::Dielectric { .. }) && en.n1 != en.n2 {
        // Snell's law in vector form with cos θt from the double-double (n2 cos θt)² (the
        // path solver's TIR verdict and direction, `path::step_planes`).
        if en.q2_t.hi < 0.0 {
            return None;
        }
        snell_direction(
            en.d_i,
            hit.normal,
            (en.n1, en.n2),
            en.q2_t.sqrt().to_f64() / en.n2,
        )
    } else {
        fresnel::refract(en.d_i, hit.normal, en.n1, en.n2)?
    };
    Some(Branch {
        dir,
        c: [c.t_s, c.t_p],
        index: en.n2,
        keep: hit.coherence.refracted_keeps,
        entry: LedgerEntry::Refraction {
            surface: hit.surface,
            t_s: c.t_s,
            t_p: c.t_p,
        },
    })
}

/// Step 5: the tunnelled branch ([`Child::Tunnelled`]), leaving from the hit point along the
/// direction Snell's law gives from n1 to n3 (cos θ3 from the double-double (n3 cos θ3)²), with
/// the layer's t (s, p) in the (s, p) frames of the face.
fn tunnelled(en: &Encounter, hit: &InterfaceHit) -> Option<Branch> {
    let tu = en.tunnel?;
    Some(Branch {
        dir: snell_direction(
            en.d_i,
            hit.normal,
            (en.n1, tu.n3),
            tu.q2_3.sqrt().to_f64() / tu.n3,
        ),
        c: tu.t,
        index: tu.n3,
        keep: hit.coherence.refracted_keeps,
        entry: LedgerEntry::Tunnel {
            surface: hit.surface,
            t_s: tu.t[0],
            t_p: tu.t[1],
        },
    })
}

/// The branch a path follows.
fn followed(en: &Encounter, hit: &InterfaceHit, which: Child) -> Option<Branch> {
    match which {
        Child::Reflected => Some(reflected(en, hit)),
        Child::Refracted => refracted(en, hit),
        Child::Tunnelled => tunnelled(en, hit),
    }
}

/// The polarization of a child: direction `b.dir`, frame (s, dir × s), Jones (c_s a_s, c_p a_p).
fn child_frame(b: &Branch, s: DVec3, a_s: Complex64, a_p: Complex64) -> JonesFrame {
    JonesFrame {
        x: s,
        y: b.dir.cross(s),
        jones: [b.c[0] * a_s, b.c[1] * a_p],
    }
}

/// Turns the split parent `ray` into its child along `b`.
fn child(ray: &mut Ray, sp: &Split, hit: &InterfaceHit, b: Branch) {
    ray.dir = b.dir;
    // Every child carries the face's invariant as formed (not re-formed in its own medium).
    ray.normal_q2 = Some((hit.normal, sp.encounter.invariant));
    child_frame(&b, sp.s, sp.a_s, sp.a_p).apply_to(ray);
    ray.index = b.index;
    if !b.keep && ray.coherence_id != INCOHERENT {
        ray.coherence_id = INCOHERENT;
        ray.ledger
            .entries
            .push(LedgerEntry::CoherenceLost { surface: None });
    }
    ray.ledger.entries.push(b.entry);
}

/// Split `ray` at `hit` into its reflected and refracted children using `model`.
pub fn interact(ray: &Ray, hit: &InterfaceHit, model: CoefficientModel) -> Children {
    let mut parent = ray.clone();
    let sp = split(&mut parent, hit, model);
    let refracted = refracted(&sp.encounter, hit).map(|b| {
        let mut r = parent.clone();
        child(&mut r, &sp, hit, b);
        r
    });
    child(&mut parent, &sp, hit, reflected(&sp.encounter, hit));
    let en = &sp.encounter;
    Children {
        reflected: parent,
        refracted,
        coefficients: en.coefficients,
        cos_theta_i: en.cos_theta_i,
        n1: en.n1,
        n2: en.n2,
    }
}

/// The one child of `ray` at `hit` that a path follows (`which`: a [`Child`], or `true` for the
/// reflected one and `false` for the refracted one, `None` under TIR or at a mirror): the same
/// ray [`interact`] returns, without building the other child. A [`Child::Tunnelled`] ray
/// leaves from the hit point ([`Child`] says who moves it to the far face).
pub fn interact_along(
    mut ray: Ray,
    hit: &InterfaceHit,
    model: CoefficientModel,
    which: impl Into<Child>,
) -> Option<Ray> {
    interact_along_in_place(&mut ray, hit, model, which).then_some(ray)
}

/// [`interact_along`] on the ray in place: false, with the ray partly updated, where
/// [`interact_along`] gives `None`.
pub(crate) fn interact_along_in_place(
    ray: &mut Ray,
    hit: &InterfaceHit,
    model: CoefficientModel,
    which: impl Into<Child>,
) -> bool {
    let sp = split(ray, hit, model);
    let Some(b) = followed(&sp.encounter, hit, which.into()) else {
        return false;
    };
    child(ray, &sp, hit, b);
    true
}

/// The polarization of a ray: its frame axes X, Y and its Jones vector (see [`Ray`]).
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct JonesFrame {
    /// Unit frame axis X (⊥ the ray).
    pub x: DVec3,
    /// Unit frame axis Y (so that (X, Y, dir) is right-handed).
    pub y: DVec3,
    /// The Jones vector (J_x, J_y): the field is J_x X + J_y Y.
    pub jones: [Complex64; 2],
}

impl JonesFrame {
    /// The polarization of `ray`.
    pub fn of(ray: &Ray) -> Self {
        JonesFrame {
            x: ray.x,
            y: ray.y,
            jones: ray.jones,
        }
    }

    /// Gives `ray` this polarization.
    pub fn apply_to(&self, ray: &mut Ray) {
        ray.x = self.x;
        ray.y = self.y;
        ray.jones = self.jones;
    }

    /// The complex 3D field `J_x X + J_y Y` ([`Ray::field`]).
    pub fn field(&self) -> Field3 {
        crate::optics::ray::field_of(self.jones, self.x, self.y)
    }
}

/// [`interact_along`] for rays that differ only in polarization (the channels of one source
/// along one path): `lead`, and one more ray per entry of `others` that equals `lead` except for
/// its [`JonesFrame`]. The encounter (indices, coefficients, s vector, child direction, ledger
/// entry) is computed once; `lead` and each entry of `others` end up bitwise as
/// [`interact_along`] leaves its own ray, including at normal incidence, where each ray's X
/// picks its s. Returns false, with the rays partly updated, where [`interact_along`] gives
/// `None`.
pub fn interact_along_shared(
    lead: &mut Ray,
    others: &mut [JonesFrame],
    hit: &InterfaceHit,
    model: CoefficientModel,
    which: impl Into<Child>,
) -> bool {
    lead.advance_to_event(hit.point);
    let encounter = Encounter::new(lead.dir, lead.index, lead.normal_q2, hit, model);
    let Some(b) = followed(&encounter, hit, which.into()) else {
        return false;
    };
    for o in others.iter_mut() {
        let s = encounter.s_for(o.x);
        let (a_s, a_p) = encounter.amplitudes(&o.field(), s);
        *o = child_frame(&b, s, a_s, a_p);
    }
    let s = encounter.s_for(lead.x);
    let (a_s, a_p) = encounter.amplitudes(&lead.field(), s);
    let sp = Split {
        encounter,
        s,
        a_s,
        a_p,
    };
    child(lead, &sp, hit, b);
    true
}
