//! A per-pixel kernel for one class of scene: point sources over a stack of parallel,
//! unbounded dielectric interfaces (plates, films, interfaces), with absorbing rectangular
//! shields, without geometric spreading, at every rung of the fidelity ladder (and the paper's
//! one scalar ray per path). For that class the exact trace ([`crate::trace::arrivals_with`])
//! is replaced, pixel by pixel, by what it computes in closed form; where the kernel cannot
//! vouch for a pixel it says so and the render traces that pixel exactly.
//!
//! # Every rung from one pass
//!
//! Each ray the kernel finds (`KernelRay`) holds what the exact trace's arrival gives the
//! rungs (docs/PHYSICS.md §4; [`crate::trace::contribution_with`]): its coherence id, its path
//! difference, its field under complex Fresnel, its field under the paper's rules (the same
//! frames and cosines, [`fresnel::paper_rules`] for the coefficients, only when a picture
//! asks for `paper_rules`: the paper's ray is launched alike and carries the same optical
//! path and coherence), and the number of reflections from the denser side (n1 < n2, as the
//! path solver counts them). `shade` forms each shading's contributions from these.
//!
//! # What is found once per picture
//!
//! The planes are sorted by their height z along the common normal N; the slabs between them
//! each hold one index. Every candidate sequence of the render's plan is walked through the
//! slabs once: the slab and direction (along ±N) of each segment, the heights of the segments
//! between two events (per slab), the indices n1, n2 of each event and whether it keeps
//! coherence. A sequence the walk cannot follow (an event on a plane the ray does not meet
//! next) never arrives; the exact solver fails it too.
//!
//! # What is solved per pixel
//!
//! With D the lateral distance from the source to the pixel and H_k the total height the path
//! crosses in slab k (the first and last segments depend on the pixel), Snell's invariant
//! p = n_k sin θ_k is the root of the lateral equation (docs/PHYSICS.md §8)
//!
//!   F(p) = Σ_k H_k p / q_k(p) − D = 0,   q_k(p) = √(n_k² − p²) = n_k cos θ_k,
//!
//! increasing and convex on [0, min n_k): Newton in f64, safeguarded by bisection, from the
//! cubic extrapolation of the four previous pixels' roots in the row (fewer at the row's start;
//! the row's first pixel starts from min n_k / 2, so a row's values do not depend on the thread
//! that renders it), until the step's predicted error is below u/4 of p or the step is below
//! half an ulp of p (`solve_p`). On a pixel pitch much below the heights crossed the cubic start
//! is within that error already: one evaluation of F per pixel and sequence (the linear start
//! needed two). Each segment's direction is (p u ± q_k N)/n_k (u: the unit lateral direction),
//! the Fresnel coefficients of each event come from the same cosines the tracer uses
//! (cos θi = q1/n1, cos²θt = q2²/n2², [`fresnel::fresnel_with_cos2_t`]), and each channel's
//! field is carried through the events in the tracer's own frames (s = the plane of incidence's
//! normal, p_i = d_i × s, the child's frame (s, d_o × s); [`crate::optics::interaction`]).
//!
//! # Real arithmetic
//!
//! Every event the kernel vouches for is below its critical angle (cos²θt > 1e-6, below) between
//! the real indices of lossless dielectrics (the crate's only media; the kernel refuses any
//! other surface), and the launch fields are real: every Fresnel coefficient and every field is real. The kernel
//! therefore forms them in f64 (`KernelArithmetic::Real`:
//! [`fresnel::fresnel_real_pair_with_cos2_t`] and a real carry), with the operations of the
//! complex ones on their real parts — a product with an imaginary part of exactly 0 rounds its
//! real part alike, and num-complex's quotient by d + 0i is (a·d)/(d·d) — so the fields are the
//! complex arithmetic's bit for bit (up to the sign of a zero). `render` then sums a pixel's
//! beat terms straight from these real fields (`shade_terms`) instead of through
//! [`SpectralContribution`]s and `Beats`. `KernelArithmetic::Complex` (the render's
//! `PixelPath::KernelReference`) keeps the complex path as the reference the tests hold the real
//! one to, bit for bit (`tests/suite/stack_kernel.rs`); events beyond or near a critical angle,
//! where coefficients are complex, are the exact trace's.
//!
//! # Optical path differences
//!
//! At the root, the optical path is S(p) = p D + Σ_k H_k q_k(p) (n²/q = p²/q + q), stationary
//! in p, so a rounded root moves S only to second order. The beat terms need differences of
//! two beams i, j of one source, each ~ a metre-scale path: formed as
//!
//!   S_j − S_i = (p_j − p_i) [D − Σ_k H_ik (p_i + p_j)/(q_k(p_i) + q_k(p_j))]
//!               + Σ_k (H_jk − H_ik) q_k(p_j),
//!
//! (q(p_j) − q(p_i) = (p_i² − p_j²)/(q(p_i) + q(p_j))) nothing cancels but the bracket, whose
//! rounding u·D is multiplied by the small p_j − p_i, and the heights of slabs both beams cross
//! the same way (the air legs of a plate's two beams) are bitwise equal, so H_jk − H_ik = 0
//! exactly. The rounding of Δ is then ~u·(|Δ| + |p_j − p_i| D) instead of ~u·S.
//!
//! # When a pixel goes to the exact trace
//!
//! The kernel answers `None` (the render then traces the pixel exactly) where its verdicts
//! would hang on a rounding: a pixel or source within `margin` (1e-9 of the scene scale) of a
//! plane, a pixel straight above the source (p < 1e-9: no plane of incidence), a refraction or
//! reflection within 1e-6 (in cos²) of its critical angle (beyond it the tracer's frustrated
//! total reflection and its tunnelling take over), a segment crossing a shield's plane within
//! `margin` of the shield's edge or of a segment end, an optical path within 1e-9 of the
//! source's coherence length, or Newton not converging in 100 steps.
//!
//! # Speed
//!
//! Per pixel and source, `rays` solves every sequence's root first and then forms each ray's
//! rest (cosines, directions, shields, Fresnel, fields), so the roots' chains of square roots
//! and divisions overlap; where a ray's rest sends the pixel to the exact trace, the roots of
//! the later sequences are put back (`KernelScratch::snapshot`), so `guess` holds what a
//! one-pass order would hold and the picture keeps its bits. Other cuts, each bit for bit:
//! `shielded` keeps the square root and division of its near-end test out of line (inlined,
//! the compiler hoisted them before the bound that skips them: 28% of `shielded`'s samples,
//! `perf annotate`) and skips a crossing beyond ±2 of a segment without its division; the
//! events leaving one slab share cos θi, the events into an index of 1 share cos θt
//! (`fresnel::fresnel_real_pair_with_cos_t`); `shade_terms` pairs in one pass. Measured (session 17,
//! 2-core VM shared with other builds, `fringe render plate_amplitude_division --size 900x900
//! --samples 81 --fidelity vector`, user + sys CPU, interleaved with the previous binary):
//! 2 threads, 15 runs, load 1.6–1.9: min 0.462 → 0.442 s, median 0.511 → 0.473 s; one thread,
//! 25 runs, load 1.1–1.6: min 0.453 → 0.423 s, median 0.528 → 0.483 s: 5–9%, not the 20% hoped
//! for; criterion (`cargo bench -p fringe-benches --bench render --
//! 'picture/amplitude_division_300x300_81_vector$'`, the render without sRGB and PNG), main and
//! this alternated twice, load 1.5–1.9: 32.4 → 30.1 ms, 36.3 → 30.3 ms. The profile stays flat (one thread, `perf record -F 20000`): `rays` 63%, `shielded`
//! 13%, `shade_terms` 8%, the table's sums 4%; within `rays` no source line above 3% (the
//! directions' division by the index, Newton's F and F', the carry of the fields). The shared
//! cosines and the ±2 test are not resolved by these series (min 0.443 → 0.442 s).

use crate::accumulate::fidelity::Fidelity;
use crate::harness::case::build;
use crate::harness::case::spec::Observer;
use crate::optics::fresnel;
use crate::optics::interaction::SurfaceOptics;
use crate::optics::ray::{Field3, INCOHERENT};
use crate::output::render::Shading;
use crate::scene::geometry::{Extent, Plane, Rect};
use crate::scene::source::{Channel, ChannelField, Emitter, field_reference};
use crate::scene::{Scene, SceneOptics, SurfaceKind};
use crate::trace::beats::SpectralContribution;
use crate::trace::path::EventKind;
use crate::trace::{Plan, TraceSettings};
use glam::DVec3;
use num_complex::Complex64;

/// One event of a compiled sequence.
#[derive(Clone, Copy, Debug)]
struct KernelEvent {
    reflect: bool,
    /// The surface's own unit normal (its s vector is formed from it, as the tracer does).
    normal: DVec3,
    /// Index on the arriving side and on the other side.
    n1: f64,
    n2: f64,
    /// Whether the followed child keeps the coherence id.
    keeps: bool,
    /// Height of the plane along the kernel's N (m).
    z: f64,
}

/// A candidate sequence walked through the slabs.
#[derive(Clone, Debug)]
struct Compiled {
    events: Vec<KernelEvent>,
    /// Slab of each segment (`events.len() + 1`).
    seg_slab: Vec<usize>,
    /// Direction of each segment along N (+1 or −1).
    seg_sign: Vec<f64>,
    /// Heights of the segments between two events, summed per slab (m).
    mid: Vec<f64>,
    /// The smallest index of the slabs crossed (p stays below it).
    p_max: f64,
    /// Whether every event keeps coherence.
    keeps: bool,
    /// Reflections from the denser side (n1 < n2): the π jumps of `scalar_jump`, counted as the
    /// path solver counts them (`SolvedPath::denser_reflections`).
    denser_reflections: u32,
}

/// An absorbing rectangle.
#[derive(Clone, Debug)]
struct Shield {
    plane: Plane,
    u: DVec3,
    v: DVec3,
    rect: Rect,
}

#[derive(Clone, Debug)]
struct KernelSource {
    position: DVec3,
    z: f64,
    slab: usize,
    channels: Vec<Channel>,
    /// Per channel, a linear channel's (reference, cos, sin of its angle): its launch field
    /// as [`Channel::launch`] forms it, the angle's cosine and sine taken once.
    linear: Vec<Option<(DVec3, f64, f64)>>,
    /// Per channel, √(intensity), taken once.
    sqrt_intensity: Vec<f64>,
    coherence_length_m: f64,
    /// One per candidate sequence of the plan, in its order; `None`: never arrives.
    seqs: Vec<Option<Compiled>>,
}

/// The kernel of one picture (module docs).
#[derive(Clone, Debug)]
pub(crate) struct StackKernel {
    normal: DVec3,
    origin: DVec3,
    /// Plane heights along `normal`, ascending.
    plane_z: Vec<f64>,
    /// Index of slab k (below plane k; the last one above every plane).
    slab_n: Vec<f64>,
    sources: Vec<KernelSource>,
    shields: Vec<Shield>,
    margin: f64,
}

/// Per-thread scratch space of the kernel.
#[derive(Clone, Debug, Default)]
pub(crate) struct KernelScratch {
    /// The last four roots per (source, sequence) in the current row, newest first (0: none
    /// yet): the next pixel starts from their cubic extrapolation (`start_of`).
    guess: Vec<[f64; 4]>,
    h: Vec<f64>,
    ref_h: Vec<f64>,
    /// q_k(p) = √(n_k² − p²) of the slabs the current ray crosses (`h` ≠ 0), and of the
    /// source's reference ray: each formed once per ray, as `q_of` forms it.
    q: Vec<f64>,
    ref_q: Vec<f64>,
    dirs: Vec<DVec3>,
    frames: Vec<Frame>,
    /// The roots of the current source's sequences as the pixel found them (restored where a
    /// ray's rest sends the pixel to the exact trace), and per sequence solved (its index, p,
    /// the last segment's direction along N) with its heights per slab (`rays`).
    snapshot: Vec<[f64; 4]>,
    /// cos θ = q_k/n_k (at most 1) of the slabs the current ray's events leave (NaN: not yet).
    cos: Vec<f64>,
    solved: Vec<(usize, f64, f64)>,
    solved_h: Vec<f64>,
    /// The complex coefficients of each frame ((c_s, c_p) of `vector`, then of the paper's
    /// rules), filled only by [`KernelArithmetic::Complex`].
    frames_complex: Vec<[[Complex64; 2]; 2]>,
}

/// The arithmetic of the kernel's fields.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) enum KernelArithmetic {
    /// Real: every event the kernel vouches for is below its critical angle between real
    /// indices (cos²θt > 1e-6), so the Fresnel coefficients
    /// ([`fresnel::fresnel_real_with_cos2_t`]) and the launch fields, hence every field, are
    /// real.
    Real,
    /// Complex Fresnel ([`fresnel::fresnel_with_cos2_t`]) and complex fields, as the tracer
    /// forms them: the reference the real arithmetic equals bit for bit (up to the sign of a
    /// zero; `tests/suite/stack_kernel.rs`).
    Complex,
}

/// One event of a pixel's path: the tracer's frames and the coefficients of both models.
#[derive(Clone, Copy, Debug)]
struct Frame {
    /// s, p_i = d_i × s, p_o = d_o × s.
    s: DVec3,
    p_i: DVec3,
    p_o: DVec3,
    /// (c_s, c_p) of complex Fresnel (`vector`): real below the critical angle
    /// ([`KernelArithmetic::Real`]).
    vector: [f64; 2],
    /// (c_s, c_p) under the paper's rules ([`fresnel::paper_rules`], real below the critical
    /// angle); unused unless asked for.
    paper: [f64; 2],
}

/// One ray of a pixel as the kernel finds it: what every rung of the ladder forms its
/// contribution from ([`shade`]), as [`crate::trace::contribution_with`] forms it from an
/// [`crate::trace::Arrival`].
#[derive(Clone, Copy, Debug)]
pub(crate) struct KernelRay {
    /// The (source, sequence) the ray travels: the channels of one source along one path share
    /// it and are consecutive.
    path: usize,
    /// Coherence id of the ray (the `vector` and the paper's ray share it: same events, same
    /// optical path).
    coherence_id: u64,
    /// Optical path minus the pixel's reference (its source's first ray) (m).
    delta_s_m: f64,
    /// Reflections from the denser side along the path (`scalar_jump`'s π jumps).
    denser_reflections: u32,
    /// The field under complex Fresnel: real (its imaginary parts are exactly 0,
    /// [`KernelArithmetic`]).
    vector: DVec3,
    /// The field under the paper's rules (zero unless asked for), real likewise.
    paper: DVec3,
}

impl KernelRay {
    /// A ray of path `path` (rays of one source along one path share it), coherence id,
    /// Δs (m), reflections from the denser side, and its fields under complex Fresnel and
    /// under the paper's rules.
    pub(crate) fn new(
        path: usize,
        coherence_id: u64,
        delta_s_m: f64,
        denser_reflections: u32,
        vector: DVec3,
        paper: DVec3,
    ) -> Self {
        KernelRay {
            path,
            coherence_id,
            delta_s_m,
            denser_reflections,
            vector,
            paper,
        }
    }

    /// Sets Δs (m).
    pub(crate) fn set_delta(&mut self, delta_s_m: f64) {
        self.delta_s_m = delta_s_m;
    }
}

/// Σ|E|² of a real field, as `norm_sqr` summed over a [`Field3`] with zero imaginary parts
/// forms it (x² + 0²)… in the same order: bit for bit.
#[inline]
fn power(e: DVec3) -> f64 {
    e.x * e.x + e.y * e.y + e.z * e.z
}

/// A real field as a [`Field3`].
#[inline]
fn complex(e: DVec3) -> Field3 {
    [
        Complex64::from(e.x),
        Complex64::from(e.y),
        Complex64::from(e.z),
    ]
}

/// One contribution of [`shade_terms`]: coherence id, Δs (m), λ-independent phase (cycles),
/// real field.
type RealContribution = (u64, f64, f64, DVec3);

/// The beat terms of a pixel's kernel rays under `shading`, without forming
/// [`SpectralContribution`]s: the constant Σ_k |E_k|² is returned and the terms (Δs (m),
/// λ-independent phase (cycles), real amplitude b) are left in `terms`, exactly (bit for bit,
/// up to the sign of a zero) what [`shade`] followed by [`crate::trace::beats::Beats::set`]
/// gives, every field being real ([`KernelArithmetic`]): the contributions of [`shade`] in its
/// order, each pair (k, l < k) of one coherence id giving Δ = Δs_k − Δs_l, e = e_k − e_l,
/// b = 2 E_k·E_l, merged into an earlier term of bitwise equal (Δ, e). `None` where `Beats`
/// would not use the paired form (more pairs than rays).
pub(crate) fn shade_terms(
    rays: &[KernelRay],
    shading: Shading,
    contributions: &mut Vec<RealContribution>,
    terms: &mut Vec<(f64, f64, f64)>,
) -> Option<f64> {
    contributions.clear();
    terms.clear();
    // One pass: each contribution, as it comes, is paired with the earlier ones of its id (the
    // pairs (k, l < k) in the order of k, then l). A pixel with more pairs than rays (hence than
    // contributions) stops pairing at once.
    let mut constant = 0.0;
    let mut pairs = 0;
    let mut over = false;
    for_each_contribution(rays, shading, |a| {
        if over {
            return;
        }
        constant += power(a.3);
        if a.0 != INCOHERENT {
            for b in contributions.iter().filter(|b| b.0 == a.0) {
                pairs += 1;
                if pairs > rays.len() {
                    over = true;
                    return;
                }
                let (delta, extra) = (a.1 - b.1, a.2 - b.2);
                // 2 Σ_c a_c conj(b_c) of real fields, summed in `dot_conj`'s order.
                let amplitude = 2.0 * (a.3.x * b.3.x + a.3.y * b.3.y + a.3.z * b.3.z);
                match terms.iter_mut().find(|t| t.0 == delta && t.1 == extra) {
                    Some(t) => t.2 += amplitude,
                    None => terms.push((delta, extra, amplitude)),
                }
            }
        }
        contributions.push(a);
    });
    if over || pairs > contributions.len() {
        return None;
    }
    Some(constant)
}

/// Each contribution of a pixel's kernel rays under `shading`, in the rays' order, to `f`
/// (coherence id, Δs (m), λ-independent phase (cycles), real field), formed as
/// [`crate::trace::contribution_with`] forms each rung (docs/PHYSICS.md §4): `incoherent`
/// and the scalar rungs carry √I of the ray's exact (`vector`) intensity I = Σ|E|²
/// (`incoherent` with id 0, `scalar_jump` with ½ cycle per reflection from the denser side),
/// `paper_rules` the field under the paper's coefficients, `vector` the complex-Fresnel
/// field; [`Shading::UnpolarizedScalarJump`] one scalar ray per path carrying the power of all
/// its channels. Every λ-independent phase is exactly what the rung adds: the exact trace's
/// `extra_cycles` differ from it by whole cycles and the rounding of the double-double phase
/// reduction (≲ 1e-15 cycles).
fn for_each_contribution(
    rays: &[KernelRay],
    shading: Shading,
    mut f: impl FnMut(RealContribution),
) {
    let scalar = |amplitude: f64| DVec3::new(amplitude, 0.0, 0.0);
    match shading {
        Shading::Level(level) => {
            for r in rays {
                f(match level {
                    Fidelity::Incoherent => {
                        (INCOHERENT, r.delta_s_m, 0.0, scalar(power(r.vector).sqrt()))
                    }
                    Fidelity::Scalar => (
                        r.coherence_id,
                        r.delta_s_m,
                        0.0,
                        scalar(power(r.vector).sqrt()),
                    ),
                    Fidelity::ScalarJump => (
                        r.coherence_id,
                        r.delta_s_m,
                        0.5 * r.denser_reflections as f64,
                        scalar(power(r.vector).sqrt()),
                    ),
                    Fidelity::PaperRules => (r.coherence_id, r.delta_s_m, 0.0, r.paper),
                    Fidelity::Vector => (r.coherence_id, r.delta_s_m, 0.0, r.vector),
                })
            }
        }
        Shading::UnpolarizedScalarJump => {
            let mut k = 0;
            while k < rays.len() {
                let first = &rays[k];
                let mut p = 0.0;
                while k < rays.len() && rays[k].path == first.path {
                    p += power(rays[k].vector);
                    k += 1;
                }
                f((
                    first.coherence_id,
                    first.delta_s_m,
                    0.5 * first.denser_reflections as f64,
                    scalar(p.sqrt()),
                ));
            }
        }
    }
}

/// The contributions of a pixel's kernel rays under `shading` as [`SpectralContribution`]s
/// (those of [`for_each_contribution`], the fields made complex): what `render::prepare`
/// makes of the exact trace's arrivals.
pub(crate) fn shade(rays: &[KernelRay], shading: Shading, out: &mut Vec<SpectralContribution>) {
    out.clear();
    for_each_contribution(
        rays,
        shading,
        |(coherence_id, delta_s_m, extra_cycles, field)| {
            out.push(SpectralContribution {
                coherence_id,
                delta_s_m,
                extra_cycles,
                field: complex(field),
            })
        },
    );
}

impl KernelScratch {
    /// Forget the roots of the previous row: each row then starts alike whichever thread
    /// renders it, so the picture does not depend on the thread count.
    pub(crate) fn new_row(&mut self) {
        self.guess.fill([0.0; 4]);
    }
}

/// √((n − p)(n + p)) = n cos θ.
#[inline]
fn q_of(n: f64, p: f64) -> f64 {
    ((n - p) * (n + p)).sqrt()
}

/// The root of the lateral equation (module docs), or `None` without convergence.
///
/// Newton's error after a step δ is ≈ (F''/2F') δ² (F' = Σ H n²/q³, F'' = Σ 3 H n² p/q⁵, so
/// F''/2F' ≤ 1.5 p / min q²): once that is below u/4 of p the step is taken and the root
/// returned without another evaluation; a step below 4 ulp of p ends it too.
fn solve_p(h: &[f64], n: &[f64], d: f64, p_max: f64, guess: f64) -> Option<f64> {
    let (mut lo, mut hi) = (0.0, p_max);
    let mut p = if guess > 0.0 && guess < p_max {
        guess
    } else {
        0.5 * p_max
    };
    for _ in 0..100 {
        let (mut f, mut df) = (-d, 0.0);
        let mut q2_min = f64::INFINITY;
        for (&hk, &nk) in h.iter().zip(n) {
            if hk != 0.0 {
                let q2 = (nk - p) * (nk + p);
                let q = q2.sqrt();
                f += hk * p / q;
                df += hk * nk * nk / (q2 * q);
                q2_min = q2_min.min(q2);
            }
        }
        if f > 0.0 {
            hi = p;
        } else if f < 0.0 {
            lo = p;
        } else {
            return Some(p);
        }
        let step = f / df;
        let mut next = p - step;
        if next == p {
            // A step below half an ulp of p: p is the root to rounding (bisecting from here
            // would wander off and back for tens of steps).
            return Some(p);
        }
        if !(next > lo && next < hi) {
            next = 0.5 * (lo + hi);
        } else if 1.5 * p / q2_min * step * step <= 0.25 * f64::EPSILON * p {
            return Some(next);
        }
        if (next - p).abs() <= 4.0 * f64::EPSILON * p {
            return Some(next);
        }
        p = next;
    }
    None
}

/// The first root of a row's pixel: the cubic extrapolation of the last four roots `g`
/// (newest first) where there are four, else the quadratic, linear or constant one (0: no root
/// yet, `solve_p` then starts from p_max/2). Along a row p(D) is smooth on the pixel pitch, so
/// the cubic's error (~ (pitch/height)⁴ of p) is mostly below what one Newton step needs to end
/// (`solve_p`): one evaluation of F per pixel and sequence instead of two.
#[inline]
fn start_of(g: [f64; 4]) -> f64 {
    let [g1, g2, g3, g4] = g;
    if g4 > 0.0 {
        4.0 * (g1 + g3) - 6.0 * g2 - g4
    } else if g3 > 0.0 {
        3.0 * (g1 - g2) + g3
    } else if g2 > 0.0 {
        2.0 * g1 - g2
    } else {
        g1
    }
}

/// Complex `e · v`, as [`crate::optics::interaction`] forms it.
fn dot_complex(e: &Field3, v: DVec3) -> Complex64 {
    e[0] * v.x + e[1] * v.y + e[2] * v.z
}

/// Real `e · v` in the order of `dot_complex`.
#[inline(always)]
fn dot_real(e: DVec3, v: DVec3) -> f64 {
    e.x * v.x + e.y * v.y + e.z * v.z
}

/// A channel's launch field through the events, in the tracer's frames, under complex Fresnel
/// or (`PAPER`) the paper's coefficients, in real arithmetic ([`KernelArithmetic::Real`]): each
/// operation is the real part of `carry_complex`'s, whose imaginary parts stay exactly 0.
#[inline(always)]
fn carry<const PAPER: bool>(launch: DVec3, frames: &[Frame]) -> DVec3 {
    let mut f = launch;
    for fr in frames {
        let [cs, cp] = if PAPER { fr.paper } else { fr.vector };
        let a_s = cs * dot_real(f, fr.s);
        let a_p = cp * dot_real(f, fr.p_i);
        f = DVec3::new(
            a_s * fr.s.x + a_p * fr.p_o.x,
            a_s * fr.s.y + a_p * fr.p_o.y,
            a_s * fr.s.z + a_p * fr.p_o.z,
        );
    }
    f
}

/// `carry` in complex arithmetic with the complex coefficients ([`KernelArithmetic::Complex`]),
/// returning the real parts (the imaginary parts are 0).
fn carry_complex(
    launch: DVec3,
    frames: &[Frame],
    coefficients: &[[[Complex64; 2]; 2]],
    paper: bool,
) -> DVec3 {
    let mut f = complex(launch);
    for (fr, c) in frames.iter().zip(coefficients) {
        let [cs, cp] = c[usize::from(paper)];
        let a_s = cs * dot_complex(&f, fr.s);
        let a_p = cp * dot_complex(&f, fr.p_i);
        f = [
            a_s * fr.s.x + a_p * fr.p_o.x,
            a_s * fr.s.y + a_p * fr.p_o.y,
            a_s * fr.s.z + a_p * fr.p_o.z,
        ];
    }
    debug_assert!(f.iter().all(|c| c.im == 0.0), "a real field gained a phase");
    DVec3::new(f[0].re, f[1].re, f[2].re)
}

/// The verdict on a shield's crossing at `t` along the segment `ab` where `t` lies within
/// 2·margin/l of an end (`shielded`): `Some(false)` beyond tm = margin/|ab| of both ends (the
/// segment misses the shield's plane), `None` within tm of an end, `Some(true)` between them.
/// Out of line and cold: inlined, the compiler formed tm's square root and division for every
/// segment before the bound that skips them (`perf annotate`: 28% of `shielded`).
#[cold]
#[inline(never)]
fn near_end(margin: f64, ab: DVec3, t: f64) -> Option<bool> {
    let tm = margin / ab.length();
    if t < -tm || t > 1.0 + tm {
        return Some(false);
    }
    if t.abs() <= tm || (t - 1.0).abs() <= tm {
        return None;
    }
    Some(true)
}

impl StackKernel {
    /// The kernel of a picture, or `None` when the scene is not of its class (module docs):
    /// point sources in distinct coherence groups, every non-opaque surface an unbounded
    /// dielectric interface parallel to the others (normals bitwise ±), no two at one height,
    /// every opaque surface a rectangle without apertures, consistent indices between faces,
    /// no spreading, no tunnelling event in the plan.
    pub(crate) fn new(
        scene: &Scene,
        optics: &SceneOptics,
        plan: &Plan,
        settings: &TraceSettings,
    ) -> Option<StackKernel> {
        if settings.solve.spreading {
            return None;
        }
        let mut normal: Option<DVec3> = None;
        let mut planes: Vec<(f64, usize)> = Vec::new();
        let mut shields = Vec::new();
        let mut scale: f64 = 1e-3;
        for (i, s) in scene.surfaces.iter().enumerate() {
            scale = scale.max(s.plane.point.abs().max_element());
            match (&s.kind, &s.extent) {
                (SurfaceKind::Interface { .. }, Extent::Unbounded) => {
                    let n = s.plane.normal;
                    let nn = *normal.get_or_insert(n);
                    if n != nn && n != -nn {
                        return None;
                    }
                    planes.push((0.0, i));
                }
                (SurfaceKind::Opaque { apertures }, Extent::Rect { u, v, rect })
                    if apertures.is_empty() =>
                {
                    shields.push(Shield {
                        plane: s.plane,
                        u: *u,
                        v: *v,
                        rect: *rect,
                    });
                }
                _ => return None,
            }
        }
        let normal = normal?;
        let origin = scene.surfaces[planes[0].1].plane.point;
        for pl in &mut planes {
            pl.0 = normal.dot(scene.surfaces[pl.1].plane.point - origin);
        }
        planes.sort_by(|a, b| a.0.total_cmp(&b.0));
        if planes.windows(2).any(|w| w[0].0 == w[1].0) {
            return None;
        }
        // Slab indices: slab k lies below plane k, slab m above every plane.
        let m = planes.len();
        let mut slab_n = vec![f64::NAN; m + 1];
        for (j, &(_, i)) in planes.iter().enumerate() {
            let Some(SurfaceOptics::Dielectric { n_front, n_back }) = optics.surfaces[i] else {
                return None;
            };
            let up_front = scene.surfaces[i].plane.normal == normal;
            let (above, below) = if up_front {
                (n_front, n_back)
            } else {
                (n_back, n_front)
            };
            for (k, n) in [(j, below), (j + 1, above)] {
                if slab_n[k].is_nan() {
                    slab_n[k] = n;
                } else if slab_n[k] != n {
                    return None;
                }
            }
        }
        let plane_z: Vec<f64> = planes.iter().map(|p| p.0).collect();
        let plane_of = |surface: usize| planes.iter().position(|p| p.1 == surface);
        let mut sources = Vec::new();
        let mut groups = Vec::new();
        for (si, src) in scene.sources.iter().enumerate() {
            let Emitter::Point { position } = src.emitter else {
                return None;
            };
            if groups.contains(&src.coherence_group) {
                return None;
            }
            groups.push(src.coherence_group);
            scale = scale.max(position.abs().max_element());
            let z = normal.dot(position - origin);
            let slab = plane_z.iter().filter(|&&pz| pz < z).count();
            if plane_z.contains(&z) || slab_n[slab] != optics.ambient_index {
                return None;
            }
            let mut seqs = Vec::new();
            let mut tunnel = false;
            plan.sequences[si].for_each(|seq| {
                tunnel |= seq.iter().any(|e| e.kind == EventKind::Tunnel);
                seqs.push(Self::compile(
                    scene, &planes, &slab_n, seq, slab, z, &plane_of,
                ));
            });
            if tunnel {
                return None;
            }
            let channels = src.channels();
            sources.push(KernelSource {
                position,
                z,
                slab,
                linear: channels
                    .iter()
                    .map(|ch| match ch.field {
                        ChannelField::Linear {
                            reference,
                            angle_rad,
                        } => Some((reference, angle_rad.cos(), angle_rad.sin())),
                        ChannelField::Dipole { .. } => None,
                    })
                    .collect(),
                sqrt_intensity: channels.iter().map(|ch| ch.intensity.sqrt()).collect(),
                channels,
                coherence_length_m: src.coherence_length_m,
                seqs,
            });
        }
        Some(StackKernel {
            normal,
            origin,
            plane_z,
            slab_n,
            sources,
            shields,
            margin: 1e-9 * scale,
        })
    }

    /// Walk `seq` from slab `slab` (source height `z`) through the planes; `None` where the
    /// walk meets a plane the sequence does not name (or names a surface that is no plane).
    fn compile(
        scene: &Scene,
        planes: &[(f64, usize)],
        slab_n: &[f64],
        seq: &[crate::trace::path::Event],
        slab: usize,
        z: f64,
        plane_of: &dyn Fn(usize) -> Option<usize>,
    ) -> Option<Compiled> {
        let mut k = slab;
        let mut sign = 0.0;
        let mut prev_z = z;
        let mut c = Compiled {
            events: Vec::new(),
            seg_slab: vec![slab],
            seg_sign: Vec::new(),
            mid: vec![0.0; slab_n.len()],
            p_max: slab_n[slab],
            keeps: true,
            denser_reflections: 0,
        };
        for (i, ev) in seq.iter().enumerate() {
            let j = plane_of(ev.surface)?;
            let up = if j == k {
                true
            } else if j + 1 == k {
                false
            } else {
                return None;
            };
            let s = if up { 1.0 } else { -1.0 };
            if i == 0 {
                sign = s;
            } else if s != sign {
                return None;
            } else {
                c.mid[k] += (planes[j].0 - prev_z).abs();
            }
            c.seg_sign.push(s);
            let other = if up { k + 1 } else { k - 1 };
            let surf = &scene.surfaces[ev.surface];
            let reflect = match ev.kind {
                EventKind::Reflect => true,
                EventKind::Refract => false,
                EventKind::Tunnel => return None,
            };
            let rules = surf.coherence();
            c.events.push(KernelEvent {
                reflect,
                normal: surf.plane.normal,
                n1: slab_n[k],
                n2: slab_n[other],
                keeps: if reflect {
                    rules.reflected_keeps
                } else {
                    rules.refracted_keeps
                },
                z: planes[j].0,
            });
            if reflect {
                sign = -sign;
            } else {
                k = other;
            }
            prev_z = planes[j].0;
            c.seg_slab.push(k);
            c.p_max = c.p_max.min(slab_n[k]);
        }
        // The last segment's direction (the first one's for a direct path is the pixel's).
        c.seg_sign.push(sign);
        c.keeps = c.events.iter().all(|e| e.keeps);
        c.denser_reflections = c.events.iter().filter(|e| e.reflect && e.n1 < e.n2).count() as u32;
        Some(c)
    }

    /// The rays reaching `point` (seen by `observer`), in the exact trace's order, into `out`
    /// (Δs relative to each source's first ray; the fields under the paper's rules too when
    /// `paper`), for [`shade`] to form any rung's contributions from, the fields formed in
    /// `arithmetic` (the same bits either way); `false` (with `out` undefined) where the pixel
    /// must be traced exactly (module docs).
    pub(crate) fn rays(
        &self,
        point: DVec3,
        observer: &Observer,
        paper: bool,
        arithmetic: KernelArithmetic,
        s: &mut KernelScratch,
        out: &mut Vec<KernelRay>,
    ) -> bool {
        out.clear();
        let nn = self.normal;
        let ns = self.slab_n.len();
        let zp = nn.dot(point - self.origin);
        if self.plane_z.iter().any(|&z| (zp - z).abs() <= self.margin) {
            return false;
        }
        let pix_slab = self.plane_z.iter().filter(|&&pz| pz < zp).count();
        let total: usize = self.sources.iter().map(|src| src.seqs.len()).sum();
        s.guess.resize(total, [0.0; 4]);
        s.h.resize(ns, 0.0);
        s.ref_h.resize(ns, 0.0);
        s.q.resize(ns, 0.0);
        s.ref_q.resize(ns, 0.0);
        s.cos.resize(ns, f64::NAN);
        let mut flat = 0;
        for src in &self.sources {
            let v = point - src.position;
            let lat = v - v.dot(nn) * nn;
            let d = lat.length();
            if d <= self.margin {
                return false;
            }
            let u = lat / d;
            let mut reference: Option<f64> = None;
            // Every root first, then the rest of each ray (module docs, "Speed"): the roots'
            // chains of square roots and divisions overlap. The roots stored in `guess` are
            // those the one-pass order stores: where a ray's rest sends the pixel to the exact
            // trace, the roots of the later sequences are restored.
            let len = src.seqs.len();
            s.snapshot.clear();
            s.snapshot.extend_from_slice(&s.guess[flat..flat + len]);
            s.solved.clear();
            s.solved_h.clear();
            let mut failed = false;
            for (k, seq) in src.seqs.iter().enumerate() {
                let idx = flat + k;
                let Some(c) = seq else { continue };
                if *c.seg_slab.last().unwrap() != pix_slab {
                    continue;
                }
                // The direct path is the straight segment from the source to the pixel whatever
                // p: a shield that stops it (the figures' plate hides its source from the whole
                // screen) is known before solving for p. Its roots start afresh where it next
                // reaches a pixel.
                if c.events.is_empty()
                    && !self.shields.is_empty()
                    && self.shielded(src, c, point, &[nn]) == Some(true)
                {
                    s.guess[idx] = [0.0; 4];
                    continue;
                }
                // The heights crossed per slab: the middle segments, then the first, then the
                // last (one order for every sequence, so equal legs give equal sums).
                s.h.copy_from_slice(&c.mid);
                let last = c.seg_slab.len() - 1;
                let mut sign_last = c.seg_sign[last];
                if c.events.is_empty() {
                    let dz = zp - src.z;
                    if dz.abs() <= self.margin {
                        failed = true;
                        break;
                    }
                    sign_last = dz.signum();
                    s.h[src.slab] += dz.abs();
                } else {
                    s.h[c.seg_slab[0]] += (c.events[0].z - src.z).abs();
                    s.h[c.seg_slab[last]] += (zp - c.events[last - 1].z).abs();
                }
                let g = s.guess[idx];
                let Some(p) = solve_p(&s.h, &self.slab_n, d, c.p_max, start_of(g)) else {
                    failed = true;
                    break;
                };
                s.guess[idx] = [p, g[0], g[1], g[2]];
                if p < 1e-9 {
                    failed = true;
                    break;
                }
                s.solved.push((k, p, sign_last));
                s.solved_h.extend_from_slice(&s.h);
            }
            // The sequence whose rest sends the pixel to the exact trace, if any.
            let tail_failed = 'tail: {
                for j in 0..s.solved.len() {
                    let (k, p, sign_last) = s.solved[j];
                    let idx = flat + k;
                    let Some(c) = &src.seqs[k] else { continue };
                    let last = c.seg_slab.len() - 1;
                    s.h.copy_from_slice(&s.solved_h[j * ns..(j + 1) * ns]);
                    // Away from grazing in every slab crossed, and from every critical angle; the
                    // cosines of the slabs crossed.
                    for ((&hk, &nk), qk) in s.h.iter().zip(&self.slab_n).zip(s.q.iter_mut()) {
                        if hk != 0.0 {
                            if (nk - p) * (nk + p) <= 1e-6 * nk * nk {
                                break 'tail Some(idx);
                            }
                            *qk = q_of(nk, p);
                        }
                    }
                    // Directions of the segments (every segment's slab is crossed: h ≠ 0).
                    s.dirs.clear();
                    for (i, &slab) in c.seg_slab.iter().enumerate() {
                        let n = self.slab_n[slab];
                        let sg = if i == last { sign_last } else { c.seg_sign[i] };
                        let q = if s.h[slab] != 0.0 {
                            s.q[slab]
                        } else {
                            q_of(n, p)
                        };
                        let dir = p * u + (sg * q) * nn;
                        // x/1 = x: the air's segments skip the division.
                        s.dirs.push(if n == 1.0 { dir } else { dir / n });
                    }
                    let d_last = s.dirs[last];
                    if !build::records(observer, d_last) {
                        continue;
                    }
                    if !self.shields.is_empty() {
                        match self.shielded(src, c, point, &s.dirs) {
                            Some(true) => continue,
                            Some(false) => {}
                            None => break 'tail Some(idx),
                        }
                    }
                    // Fresnel coefficients and frames of the events.
                    s.frames.clear();
                    s.frames_complex.clear();
                    s.cos.fill(f64::NAN);
                    let mut q_unit = f64::NAN;
                    for (i, ev) in c.events.iter().enumerate() {
                        let q2_2 = (ev.n2 - p) * (ev.n2 + p);
                        if q2_2 <= 1e-6 * ev.n2 * ev.n2 {
                            break 'tail Some(idx);
                        }
                        // n1 cos θi = q of the arriving segment's slab (n1 is its index).
                        // (x/1 = x: the divisions by an index of 1 are skipped.)
                        // Formed once per slab (`cos`): two events leaving one slab share it.
                        let k1 = c.seg_slab[i];
                        if s.cos[k1].is_nan() {
                            let q1 = s.q[k1];
                            s.cos[k1] = (if ev.n1 == 1.0 { q1 } else { q1 / ev.n1 }).min(1.0);
                        }
                        let cos_i = s.cos[k1];
                        let c2t = if ev.n2 == 1.0 {
                            q2_2
                        } else {
                            q2_2 / (ev.n2 * ev.n2)
                        };
                        // cos θt = √c2t; into an index of 1 that is √((1 − p)(1 + p)), formed
                        // once per ray (`q_unit`): the events into air share it.
                        let cos_t = if ev.n2 == 1.0 {
                            if q_unit.is_nan() {
                                q_unit = c2t.sqrt();
                            }
                            q_unit
                        } else {
                            c2t.sqrt()
                        };
                        let (d_i, d_o) = (s.dirs[i], s.dirs[i + 1]);
                        let Some(sv) = fresnel::s_of_plane_of_incidence(d_i, ev.normal) else {
                            break 'tail Some(idx);
                        };
                        let pick = |f: fresnel::FresnelCoefficients| {
                            if ev.reflect {
                                [f.r_s, f.r_p]
                            } else {
                                [f.t_s, f.t_p]
                            }
                        };
                        // (c_s, c_p), real: no interface where n1 = n2 (`fresnel`).
                        let vector = match (ev.n1 == ev.n2, ev.reflect) {
                            (true, true) => [0.0; 2],
                            (true, false) => [1.0; 2],
                            (false, reflect) => fresnel::fresnel_real_pair_with_cos_t(
                                ev.n1, ev.n2, cos_i, cos_t, reflect,
                            ),
                        };
                        let paper_c =
                            paper.then(|| pick(fresnel::paper_rules(ev.n1, ev.n2, cos_i)));
                        s.frames.push(Frame {
                            s: sv,
                            p_i: d_i.cross(sv),
                            p_o: d_o.cross(sv),
                            vector,
                            paper: paper_c.map_or([0.0; 2], |[a, b]| [a.re, b.re]),
                        });
                        if arithmetic == KernelArithmetic::Complex {
                            let f = if ev.n1 == ev.n2 {
                                fresnel::fresnel(ev.n1, ev.n2, cos_i)
                            } else {
                                fresnel::fresnel_with_cos2_t(ev.n1, ev.n2, cos_i, c2t)
                            };
                            s.frames_complex
                                .push([pick(f), paper_c.unwrap_or([Complex64::default(); 2])]);
                        }
                    }
                    // The optical path (for the coherence-length rule) and Δs.
                    let mut path = p * d;
                    for (&hk, &qk) in s.h.iter().zip(&s.q) {
                        if hk != 0.0 {
                            path += hk * qk;
                        }
                    }
                    let delta = match reference {
                        None => {
                            reference = Some(p);
                            s.ref_h.copy_from_slice(&s.h);
                            s.ref_q.copy_from_slice(&s.q);
                            0.0
                        }
                        Some(pr) => {
                            let mut bracket = d;
                            let mut extra = 0.0;
                            for (k, ((&hj, &hr), &nk)) in
                                s.h.iter().zip(&s.ref_h).zip(&self.slab_n).enumerate()
                            {
                                // q_k(p) of a slab this ray does not cross (hj = 0) is not cached.
                                let qj = if hj != 0.0 { s.q[k] } else { q_of(nk, p) };
                                if hr != 0.0 {
                                    bracket -= hr * (pr + p) / (s.ref_q[k] + qj);
                                }
                                let dh = hj - hr;
                                if dh != 0.0 {
                                    extra += dh * qj;
                                }
                            }
                            (p - pr) * bracket + extra
                        }
                    };
                    let lost_length = path > src.coherence_length_m;
                    if (path - src.coherence_length_m).abs() <= 1e-9 * path {
                        break 'tail Some(idx);
                    }
                    let d0 = s.dirs[0];
                    let mut shared: Option<(DVec3, DVec3)> = None;
                    for ((ch, linear), &sqrt_intensity) in src
                        .channels
                        .iter()
                        .zip(&src.linear)
                        .zip(&src.sqrt_intensity)
                    {
                        let (e, amp) = match *linear {
                            Some((reference, cos, sin)) => {
                                let e_ref = match shared {
                                    Some((r, e)) if r == reference => e,
                                    _ => {
                                        let e = field_reference(reference, d0);
                                        shared = Some((reference, e));
                                        e
                                    }
                                };
                                (cos * e_ref + sin * d0.cross(e_ref), 1.0)
                            }
                            None => ch.launch(d0),
                        };
                        let a = amp * sqrt_intensity;
                        let launch = DVec3::new(e.x * a, e.y * a, e.z * a);
                        let coherent = c.keeps && !lost_length && ch.coherence_id != INCOHERENT;
                        out.push(KernelRay {
                            path: idx,
                            coherence_id: if coherent {
                                ch.coherence_id
                            } else {
                                INCOHERENT
                            },
                            delta_s_m: delta,
                            denser_reflections: c.denser_reflections,
                            vector: match arithmetic {
                                KernelArithmetic::Real => carry::<false>(launch, &s.frames),
                                KernelArithmetic::Complex => {
                                    carry_complex(launch, &s.frames, &s.frames_complex, false)
                                }
                            },
                            paper: match (paper, arithmetic) {
                                (false, _) => DVec3::ZERO,
                                (true, KernelArithmetic::Real) => carry::<true>(launch, &s.frames),
                                (true, KernelArithmetic::Complex) => {
                                    carry_complex(launch, &s.frames, &s.frames_complex, true)
                                }
                            },
                        });
                    }
                }
                None
            };
            if let Some(idx) = tail_failed {
                s.guess[idx + 1..flat + len].copy_from_slice(&s.snapshot[idx + 1 - flat..]);
                return false;
            }
            if failed {
                return false;
            }
            flat += src.seqs.len();
        }
        true
    }

    /// Whether a shield stops the path from `src` to `point` along `dirs` (`Some(true)`), lets it
    /// pass (`Some(false)`), or the verdict is within `margin` of an edge (`None`).
    fn shielded(
        &self,
        src: &KernelSource,
        c: &Compiled,
        point: DVec3,
        dirs: &[DVec3],
    ) -> Option<bool> {
        let nn = self.normal;
        let last = c.seg_slab.len() - 1;
        let mut a = src.position;
        let mut za = src.z;
        for (i, &d) in dirs.iter().enumerate().take(last + 1) {
            let b = if i == last {
                point
            } else {
                let zb = c.events[i].z;
                // Along d to height zb.
                let t = (zb - za) / d.dot(nn);
                let b = a + t * d;
                za = zb;
                b
            };
            let ab = b - a;
            for sh in &self.shields {
                let den = ab.dot(sh.plane.normal);
                if den == 0.0 {
                    continue;
                }
                let num = (sh.plane.point - a).dot(sh.plane.normal);
                // |num| > 2|den| (2|den| and the comparison exact): the quotient is beyond ±2 and
                // so is its rounding (rounding is monotonic and ±2 are floats), outside the range
                // below, without the division (the segments of a thin layer far from a shield).
                if num.abs() > 2.0 * den.abs() {
                    continue;
                }
                let t = num / den;
                if !(-0.5..=1.5).contains(&t) {
                    continue;
                }
                // tm = margin/|ab| ≤ margin/l (l = the largest |component| of ab, l ≤ |ab|,
                // roundings aside): where t is beyond 2·margin/l of both ends the verdicts
                // below on tm are known without its square root and division.
                let l = ab.abs().max_element();
                let far = 2.0 * self.margin;
                if t * l < -far || (t - 1.0) * l > far {
                    continue;
                }
                if !(t * l > far && (1.0 - t) * l > far) {
                    match near_end(self.margin, ab, t) {
                        Some(false) => continue,
                        Some(true) => {}
                        None => return None,
                    }
                }
                let x = a + t * ab;
                let uv = Extent::uv(sh.u, sh.v, &sh.plane, x);
                let outside = ((uv[0] - sh.rect.center_uv[0]).abs() - sh.rect.half_width_m)
                    .max((uv[1] - sh.rect.center_uv[1]).abs() - sh.rect.half_height_m);
                if outside.abs() <= self.margin {
                    return None;
                }
                if outside < 0.0 {
                    return Some(true);
                }
            }
            a = b;
        }
        Some(false)
    }
}
