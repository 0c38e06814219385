//! Paths through a stack of parallel planes: the plane-by-plane step, the launch model of a
//! point source through parallel faces (Snell's invariant solved in double-double), and when a
//! stalled landing through parallel planes is harmless.

use super::*;
use crate::optics::double_double::two_prod;

/// One event of a trace on the unbounded planes (no extents, no blockers).
pub(super) struct PlaneStep {
    /// The event point.
    pub(super) x: DVec3,
    /// Direction and index after the event.
    pub(super) d: DVec3,
    pub(super) n: f64,
    /// A reflection from the denser side (π jump of `scalar_jump`).
    pub(super) denser: bool,
    /// A totally internally reflected reflection.
    pub(super) tir: bool,
    /// n2 cos θt/(n1 cos θi) for a refraction, 1 for a reflection.
    pub(super) refraction_factor: f64,
    /// The normal and Snell's invariant about it ([`Invariant`], as `Ray::normal_q2` carries
    /// it): what the next event at a parallel face forms its normal wavevectors from
    /// (docs/PHYSICS.md §8).
    pub(super) p2: (DVec3, Invariant),
}

/// Snell's invariant held as one medium's (n cos θ)² (the tracer's
/// [`crate::optics::interaction::SnellInvariant`], `Ray::normal_q2`): the path solver and the
/// tracer carry the same thing and form every normal wavevector from it the same way.
pub(super) use crate::optics::interaction::SnellInvariant as Invariant;

/// Event `k` of a sequence, `ev`, met by the ray from `o` along `d` in index `n`, carrying
/// Snell's invariant about the normal of its last face (`carried`, in double-double, as the
/// tracer's ray does, [`crate::optics::ray::Ray::normal_q2`]; `None` forms it from the f64
/// direction). TIR verdicts, refracted directions and the refraction factor come from the
/// normal wavevector squares (n1 cos θi)², (n2 cos θt)² formed from that invariant
/// ([`interaction::normal_wavevector_squares`]), each as well conditioned as the invariant
/// itself, also where it is small (grazing in a plate of low index under a dense ambient).
/// Re-forming the next medium's q² + n2² − n1² at every face instead loses ~n1²·1e-32/q_t² of
/// it: 2e-12 of tan θt for n = 4.76 over n = 0.0092 at tan θt = 3e7, and the landing stalled at
/// 3.5e-10 m (`fringe fuzz --family two_beam_plate --seed 1`, scene 25). `from`: the surface of
/// the previous event, where the ray starts (its point `o` lies on that plane).
#[inline(always)]
pub(super) fn step_planes(
    scene: &Scene,
    optics: &SceneOptics,
    k: usize,
    ev: Event,
    (o, d, n): (DVec3, DVec3, f64),
    carried: Option<(DVec3, Invariant)>,
    from: Option<usize>,
) -> Result<PlaneStep, PathError> {
    let surf = &scene.surfaces[ev.surface];
    let so = surface_optics(optics, k, ev.surface)?;
    let normal = surf.plane.normal;
    let (n1, n2) = indices_for(so, normal, d, n);
    let carried = carried.filter(|(m, _)| *m == normal || *m == -normal);
    let p2 = interaction::snell_invariant(d, normal, n1, carried);
    let (q2_i, q2_t) = (p2.q2_in(n1), p2.q2_in(n2));
    // The distance to the plane: where the ray carries its (n cos θ)² about this plane's normal
    // (a parallel face, or a stack launch), along the cosine formed from it, not from d·N of
    // the f64 direction, whose normal part is off by ~1e-16 absolute on a tilted plane: grazing
    // inside a plate (cos θt ~ 1e-8) that is 1e-8 of the lateral run, and the landing stalled
    // (`fringe fuzz --family two_beam_plate --seed 1`, rotated scenes 23, 26). The lateral
    // run t·d then keeps the relative precision of d's tangential part.
    let carried_cos = match carried {
        Some((m, _)) if m == normal || m == -normal => {
            let c = q2_i.sqrt().to_f64() / n1;
            (c > 0.0 && c.is_finite()).then(|| c.copysign(d.dot(normal)))
        }
        _ => None,
    };
    // The height of `o` above this plane: from the planes' own heights where both are held
    // from one anchor along one normal line (a plate's faces, `Plane::offset`), exact but for
    // one rounding; a hit point rounded to f64 coordinates is off its plane by ~1e-16 of
    // them, which grazing at tan θt = 3e7 inside a 3 µm plate 10 m from the origin moved the
    // landing by 5e-8 m (`fringe fuzz --family two_beam_plate --seed 1`, scene 25).
    let height = |plane: &crate::scene::geometry::Plane| {
        let prev = &scene.surfaces[from?].plane;
        if prev.anchor != plane.anchor {
            return None;
        }
        if prev.normal == plane.normal {
            Some(prev.height_m - plane.height_m)
        } else if prev.normal == -plane.normal {
            Some(-prev.height_m - plane.height_m)
        } else {
            None
        }
    };
    let t = match carried_cos {
        Some(c) if c != 0.0 && c.signum() == d.dot(normal).signum() => {
            let s = height(&surf.plane).unwrap_or_else(|| surf.plane.signed_distance(o));
            Some(-s / c)
        }
        _ => surf.plane.intersect(o, d),
    }
    .filter(|t| *t > 0.0)
    .ok_or(PathError::Missed { event: k })?;
    // The hit point on the plane itself: o + t·d rounds at the size of t (a launch 100 m away
    // leaves the point ~1e-14 m off the plane, a first-order error of every path through it);
    // moved back onto the plane it is off by the rounding of its distance to the plane's point
    // only. Along the plane the rounding is second order (Fermat).
    let x = surf.plane.project(o + t * d);
    let mirror = matches!(so, SurfaceOptics::IdealMirror);
    let splitter = matches!(so, SurfaceOptics::Splitter { .. });
    if n1 != n {
        return Err(PathError::MediumMismatch { event: k });
    }
    Ok(match ev.kind {
        EventKind::Reflect => PlaneStep {
            x,
            d: fresnel::reflect(d, normal),
            n,
            denser: mirror || n1 < n2 || (splitter && d.dot(normal) < 0.0),
            tir: !mirror && !splitter && q2_t.hi < 0.0,
            refraction_factor: 1.0,
            p2: (normal, p2),
        },
        EventKind::Refract => {
            if mirror {
                return Err(PathError::TotalInternalReflection { event: k });
            }
            let d_t = if matches!(so, SurfaceOptics::Dielectric { .. }) && n1 != n2 {
                if q2_t.hi < 0.0 {
                    return Err(PathError::TotalInternalReflection { event: k });
                }
                interaction::snell_direction(d, normal, (n1, n2), q2_t.sqrt().to_f64() / n2)
            } else {
                fresnel::refract(d, normal, n1, n2)
                    .ok_or(PathError::TotalInternalReflection { event: k })?
            };
            PlaneStep {
                x,
                d: d_t,
                n: n2,
                denser: false,
                tir: false,
                refraction_factor: (q2_t.sqrt().to_f64() / q2_i.sqrt().to_f64()),
                p2: (normal, p2),
            }
        }
        EventKind::Tunnel => {
            tunnel_step(optics, k, ev, (d, normal), (n1, n2), (q2_i, q2_t, p2), x)?
        }
    })
}

/// The [`PlaneStep`] of a tunnel event at `x` (frustrated total reflection, docs/PHYSICS.md §5):
/// the direction refracted from n1 into the index beyond the layer, from Snell's invariant
/// ((n3 cos θ3)² = (n1 cos θ1)² + n3² − n1², as `interaction` forms it); the point stays the hit
/// point on the lit face (`FarFieldPaths` starts the next segment on the far face,
/// [`tunnel_exit`]). [`PathError::NoTunnel`] where no tunnelled wave exists.
fn tunnel_step(
    optics: &SceneOptics,
    k: usize,
    ev: Event,
    (d, normal): (DVec3, DVec3),
    (n1, n2): (f64, f64),
    (q2_i, q2_t, p2): (DoubleDouble, DoubleDouble, Invariant),
    x: DVec3,
) -> Result<PlaneStep, PathError> {
    let no = PathError::NoTunnel { event: k };
    let layer = optics.layers[ev.surface][usize::from(d.dot(normal) >= 0.0)].ok_or(no.clone())?;
    let dielectric = matches!(
        optics.surfaces[ev.surface],
        Some(SurfaceOptics::Dielectric { .. })
    );
    let n3 = layer.n_beyond;
    let q2_3 = p2.q2_in(n3);
    if !dielectric || n1 == n2 || q2_t.hi >= 0.0 || q2_3.hi <= 0.0 {
        return Err(no);
    }
    Ok(PlaneStep {
        x,
        d: interaction::snell_direction(d, normal, (n1, n3), q2_3.sqrt().to_f64() / n3),
        n: n3,
        denser: false,
        tir: false,
        refraction_factor: q2_3.sqrt().to_f64() / q2_i.sqrt().to_f64(),
        p2: (normal, p2),
    })
}

/// Trace a ray through `seq` on the unbounded planes (no extents, no blockers) into `g`
/// (cleared first; nothing is allocated when the first event already fails).
pub(super) fn trace_planes(
    scene: &Scene,
    optics: &SceneOptics,
    origin: DVec3,
    dir: DVec3,
    seq: &[Event],
    g: &mut Geometry,
) -> Result<(), PathError> {
    trace_planes_carrying(scene, optics, (origin, dir, None), seq, g)
}

/// [`trace_planes`] for a launch that carries Snell's invariant p² = (n sin θ)² about the
/// first event's normal (in double-double, [`parallel_stack_launch`]); every event passes
/// it on to the next ([`step_planes`]).
pub(super) fn trace_planes_carrying(
    scene: &Scene,
    optics: &SceneOptics,
    (origin, dir, carried): (DVec3, DVec3, Option<(DVec3, Invariant)>),
    seq: &[Event],
    g: &mut Geometry,
) -> Result<(), PathError> {
    g.clear();
    if seq.is_empty() {
        g.start(origin, dir, optics.ambient_index, 0);
    }
    let mut ray = (origin, dir, optics.ambient_index);
    let mut carried = carried;
    for (k, ev) in seq.iter().enumerate() {
        let from = k.checked_sub(1).map(|j| seq[j].surface);
        let step = step_planes(scene, optics, k, *ev, ray, carried, from)?;
        carried = Some(step.p2);
        g.denser_reflections += usize::from(step.denser);
        g.has_tir |= step.tir;
        g.refraction_factor *= step.refraction_factor;
        if k == 0 {
            g.start(origin, dir, optics.ambient_index, seq.len());
        }
        g.points.push(step.x);
        g.dirs.push(step.d);
        g.indices.push(step.n);
        ray = (step.x, step.d, step.n);
    }
    Ok(())
}

/// How the two launch parameters map to a launch ray.
pub(super) struct LaunchModel {
    pub(super) emitter: Emitter,
    /// Guess direction (point/line) or fixed direction (plane wave).
    pub(super) g: DVec3,
    pub(super) e1: DVec3,
    pub(super) e2: DVec3,
    pub(super) base: DVec3,
}

impl LaunchModel {
    pub(super) fn new(emitter: Emitter, guess_dir: DVec3, guess_origin: DVec3) -> Self {
        match emitter {
            Emitter::Point { position } => {
                let g = guess_dir.normalize();
                let e1 = g.any_orthonormal_vector();
                LaunchModel {
                    emitter,
                    g,
                    e1,
                    e2: g.cross(e1),
                    base: position,
                }
            }
            Emitter::Line { point, axis } => {
                let a = axis.normalize();
                let gp = guess_dir - guess_dir.dot(a) * a;
                let g = if gp.length() > 1e-12 {
                    gp.normalize()
                } else {
                    a.any_orthonormal_vector()
                };
                // Origin nearest to the guess origin along the axis.
                let base = point + (guess_origin - point).dot(a) * a;
                LaunchModel {
                    emitter,
                    g,
                    e1: a,
                    e2: a.cross(g),
                    base,
                }
            }
            Emitter::PlaneWave {
                direction,
                reference_point,
            } => {
                let g = direction.normalize();
                let e1 = g.any_orthonormal_vector();
                // Start on the reference plane, on the line through the guess origin.
                let base = guess_origin - (guess_origin - reference_point).dot(g) * g;
                LaunchModel {
                    emitter,
                    g,
                    e1,
                    e2: g.cross(e1),
                    base,
                }
            }
        }
    }

    pub(super) fn launch(&self, p: [f64; 2]) -> (DVec3, DVec3) {
        match self.emitter {
            Emitter::Point { .. } => (
                self.base,
                (self.g + p[0] * self.e1 + p[1] * self.e2).normalize(),
            ),
            Emitter::Line { .. } => (
                self.base + p[0] * self.e1,
                (self.g + p[1] * self.e2).normalize(),
            ),
            Emitter::PlaneWave { .. } => (self.base + p[0] * self.e1 + p[1] * self.e2, self.g),
        }
    }

    /// Launch measure per unit parameter area: solid angle (point, gnomonic Jacobian
    /// (1+a²+b²)^{-3/2}), length × angle (line), or area (plane wave).
    pub(super) fn measure(&self, p: [f64; 2]) -> f64 {
        match self.emitter {
            Emitter::Point { .. } => (1.0 + p[0] * p[0] + p[1] * p[1]).powf(-1.5),
            Emitter::Line { .. } => 1.0 / (1.0 + p[1] * p[1]),
            Emitter::PlaneWave { .. } => 1.0,
        }
    }

    /// Finite-difference step per parameter.
    pub(super) fn step(&self, scale: f64) -> [f64; 2] {
        match self.emitter {
            Emitter::Point { .. } => [1e-6, 1e-6],
            Emitter::Line { .. } => [1e-6 * scale, 1e-6],
            Emitter::PlaneWave { .. } => [1e-6 * scale, 1e-6 * scale],
        }
    }
}

/// The launch direction of the exact path from a point source at `source` to the point
/// `target` when every event plane of `seq` is parallel to the first (a plate, a film stack, a
/// mirror parallel to a plate), or `None` when the planes are not parallel or the sequence
/// cannot be followed in the plane of incidence (the general solver then decides).
///
/// All segments then lie in the plane of incidence through `source`, `target` and the common
/// normal ν, and Snell's law keeps the invariant p = n_k sin θ_k (θ_k: angle of segment k to
/// ν) the same on every segment, reflections included. Segment k of height h_k (its extent
/// along ν, from the plane heights) in index n_k runs h_k tan θ_k = h_k p/√(n_k² − p²)
/// sideways, so p solves the lateral-run equation
///
/// f(p) = Σ_k h_k p/√(n_k² − p²) − D = 0,  0 ≤ p < min n_k,
///
/// with D the lateral distance from source to target. f is increasing and convex, so Newton's
/// method safeguarded by bisection on the bracket converges from any start. The segment
/// indices depend only on the sequence, not on the launch angle.
///
/// Returns the launch direction, with ν and Snell's invariant in double-double (the path
/// solver's [`trace_planes_carrying`] and the tracer's ray, `Ray::normal_q2`, carry it): where
/// the beam grazes in the least index n_g of the stack, held as that medium's own
/// (n_g cos θ_g)² ([`grazing_invariant`]), else as the launch's (n0 cos θ0)² = (n0 − p)(n0 + p),
/// so every
/// segment's cosine is formed from the invariant, not from the f64 launch direction, whose
/// rounding (~1e-16 of sin θ0)
/// is a relative error of ~1e-16/cos²θk in a segment grazing at θk (the beam through a plate
/// less dense than its ambient, just below the critical angle, at tan θt up to 1e8 and beyond:
/// it did not land, `fringe fuzz --family two_beam_plate --seed 1`, scenes 23, 25, 26).
pub(super) fn parallel_stack_launch(
    scene: &Scene,
    optics: &SceneOptics,
    seq: &[Event],
    source: DVec3,
    target: DVec3,
) -> Option<(DVec3, (DVec3, Invariant))> {
    use crate::optics::double_double::two_diff;
    let nu = scene.surfaces[seq.first()?.surface].plane.normal;
    // The target relative to the source from exact coordinate differences, split along ν and
    // across it in double-double: scenes far from the origin (a mirror at 100 m, a source 1 µm
    // above it) keep the heights and the lateral distance to their own size, where f64 dot
    // products of absolute coordinates round at ~1e-14 m (a 1 µm height 1.4e-8 off moved a
    // Lloyd fringe by 1e-11, `fringe fuzz --family lloyd --seed 1`, scene 218).
    let v = [
        two_diff(target.x, source.x),
        two_diff(target.y, source.y),
        two_diff(target.z, source.z),
    ];
    let target_along = v[0].mul_f64(nu.x) + v[1].mul_f64(nu.y) + v[2].mul_f64(nu.z);
    // Heights along ν relative to the source (k = 0), of event plane k (1..=len) and the
    // target: a plane's is minus the source's signed distance from it, in double-double from
    // the plane as held (anchor and height, `Plane::signed_distance_dd`), and kept in
    // double-double until the segment heights are formed: a plate's faces, held from one
    // anchor, then differ by their exact thickness. Rounded to f64 first, two distances of
    // ~0.65 m lost 1.6e-7 of a 0.69 nm plate's thickness, the plate's lateral run (tan θt ~
    // 6e8) as much, and the launch missed by 4e-8 m (`fringe fuzz --family two_beam_plate
    // --seed 1`, scene 239).
    let z = |k: usize| match k {
        0 => DoubleDouble::ZERO,
        k if k <= seq.len() => {
            let plane = &scene.surfaces[seq[k - 1].surface].plane;
            let distance = plane.signed_distance_dd(source);
            if plane.normal.dot(nu) > 0.0 {
                -distance
            } else {
                distance
            }
        }
        _ => target_along,
    };
    // Each height once (a double-double distance, with a square root for a normal not exactly
    // unit): the walk below takes every one twice.
    let z: Vec<DoubleDouble> = (0..=seq.len() + 1).map(z).collect();
    let z = |k: usize| z[k];
    // Walk the segments: the direction along ν (it flips at reflections only) and the index
    // (it changes at refractions only), exactly as `trace_planes` finds them for any launch;
    // anything it would reject is left to the general solver and its error.
    let n0 = optics.ambient_index;
    let first_up = (z(1) - z(0)).to_f64().signum();
    let (mut up, mut n) = (first_up, n0);
    // Total height per index (one entry per medium; more media than this is left to Newton).
    let mut runs = [(0.0, 0.0); 4];
    let mut media = 0;
    for k in 0..=seq.len() {
        let dz = (z(k + 1) - z(k)).to_f64();
        if dz == 0.0 || dz.signum() != up {
            return None;
        }
        match runs[..media].iter_mut().find(|r| r.1 == n) {
            Some(r) => r.0 += dz.abs(),
            None if media < 4 => {
                runs[media] = (dz.abs(), n);
                media += 1;
            }
            None => return None,
        }
        let Some(ev) = seq.get(k) else { break };
        let normal = scene.surfaces[ev.surface].plane.normal;
        if normal.cross(nu).length_squared() > 1e-30 {
            return None;
        }
        let so = optics.surfaces[ev.surface]?;
        let (n1, n2) = indices_for(so, normal, up * nu, n);
        if n1 != n {
            return None;
        }
        match (ev.kind, so) {
            (EventKind::Reflect, _) => up = -up,
            (EventKind::Refract, SurfaceOptics::IdealMirror) => return None,
            (EventKind::Refract, _) => n = n2,
            (EventKind::Tunnel, _) => return None,
        }
    }
    let runs = &runs[..media];
    let lateral = DVec3::new(
        (v[0] - target_along.mul_f64(nu.x)).to_f64(),
        (v[1] - target_along.mul_f64(nu.y)).to_f64(),
        (v[2] - target_along.mul_f64(nu.z)).to_f64(),
    );
    let d = lateral.length();
    // The invariant in double-double: near grazing, p is within a rounding of n0 (cos θ0 =
    // 8.7e-9 puts p at n0 (1 − 3.8e-17), below the ulp of 1), so an f64 p rounds to n0 and
    // the launch is parallel to the plate: the beam through a plate was lost (`Missed`) or,
    // one ulp off, cos θ0 and the landing carried a relative error of ~u/cos²θ0 (`fringe fuzz
    // --family two_beam_plate --seed 1`, scenes 106, 129, docs/PHYSICS.md §8). Newton's method
    // runs on p in double-double and cos θ0 = √((n0 − p)(n0 + p))/n0 is formed from it, so both
    // direction components keep their relative precision at any angle.
    let dd = DoubleDouble::from_f64;
    let p = if d == 0.0 {
        dd(0.0)
    } else {
        let p_max = runs.iter().map(|r| r.1).fold(f64::INFINITY, f64::min);
        let height: f64 = runs.iter().map(|r| r.0).sum();
        // f(p) in double-double and f'(p) in f64; f = +∞ where a segment's cosine vanishes.
        let f = |p: DoubleDouble| -> (DoubleDouble, f64) {
            runs.iter().fold((dd(-d), 0.0), |(f, df), &(h, n)| {
                let c2 = (dd(n) - p) * (dd(n) + p);
                if c2.hi <= 0.0 {
                    return (dd(f64::INFINITY), f64::INFINITY);
                }
                let c = c2.sqrt();
                let c2f = c2.to_f64();
                (f + (p * h) / c, df + h * n * n / (c2f * c.to_f64()))
            })
        };
        // Start where every segment had the lowest index (f ≤ 0 there).
        let (mut lo, mut hi) = (dd(0.0), dd(p_max));
        let mut p = dd(p_max * d / d.hypot(height));
        // Quadratic convergence: a few steps reach the double-double rounding of p_max.
        let ulps = 1e-31 * p_max;
        for _ in 0..256 {
            let (fp, dfp) = f(p);
            if fp.hi == 0.0 {
                break;
            }
            if fp.hi < 0.0 {
                lo = p
            } else {
                hi = p
            }
            let step = if dfp.is_finite() && dfp > 0.0 {
                fp.to_f64() / dfp
            } else {
                f64::NAN
            };
            let newton = p - dd(step);
            if step.abs() <= ulps {
                p = newton;
                break;
            }
            p = if (newton - lo).hi > 0.0 && (hi - newton).hi > 0.0 {
                newton
            } else {
                (lo + hi).mul_f64(0.5)
            };
            if (hi - lo).hi <= ulps {
                break;
            }
        }
        p
    };
    // Held in the grazing medium where the beam grazes there, else as the launch's own
    // (n0 cos θ0)² = (n0 − p)(n0 + p): the rays carry it as formed (`Ray::normal_q2`).
    let (invariant, p) = match grazing_invariant(runs, d, p) {
        Some(inv) => (inv, (two_prod(inv.n_ref, inv.n_ref) - inv.q2_ref).sqrt()),
        None => (Invariant::in_medium(n0, (dd(n0) - p) * (dd(n0) + p)), p),
    };
    let sin0 = (p / dd(n0)).to_f64();
    let cos0 = (invariant.q2_in(n0).sqrt() / dd(n0)).to_f64();
    let u = if d == 0.0 { DVec3::ZERO } else { lateral / d };
    Some((sin0 * u + cos0 * first_up * nu, (nu, invariant)))
}

/// Snell's invariant of a stack launch as the normal wavevector of its grazing medium
/// ([`Invariant`] about the least index n_g of `runs`, (height, index) per medium), refined
/// from the root `p` of [`parallel_stack_launch`]'s lateral-run equation where the beam
/// grazes there (s = q²_g = n_g² − p² < n_g²/2); `None` otherwise (p² is then held as it is).
///
/// Near grazing in n_g the root p is within ~1e-31 of n_g, and s = (n_g − p)(n_g + p) keeps
/// only the digits of p that exceed that: relative ~1e-32/cos²θ_g, 1e-10 at cos θ_g = 1e-11.
/// Newton's method on s itself, with
///
/// F(s) = Σ_k h_k p/q_k − D,  p = √(n_g² − s),  q_k = √(n_k² − n_g² + s),
/// F'(s) = −Σ_k h_k n_k²/(2 p q_k³) < 0,
///
/// (F in double-double, F' in f64) conditions the grazing run h_g p/√s to the relative
/// precision of s (d ln F/d ln s → −1/2): s, and with it cos θ_g and the lateral run
/// 2 d tan θ_g, to ~1e-31 of themselves. Safeguarded by bisection on the bracket it keeps.
fn grazing_invariant(runs: &[(f64, f64)], d: f64, p: DoubleDouble) -> Option<Invariant> {
    let dd = DoubleDouble::from_f64;
    let n_g = runs.iter().map(|r| r.1).fold(f64::INFINITY, f64::min);
    let n_g2 = two_prod(n_g, n_g);
    let mut s = (dd(n_g) - p) * (dd(n_g) + p);
    if !(s.hi > 0.0 && s.hi < 0.5 * n_g2.hi) || d == 0.0 {
        return None;
    }
    let inv = |s: DoubleDouble| Invariant {
        n_ref: n_g,
        q2_ref: s,
    };
    // F(s) (double-double) and F'(s) (f64).
    let f = |s: DoubleDouble| -> Option<(DoubleDouble, f64)> {
        let p = (n_g2 - s).sqrt();
        let pf = p.to_f64();
        runs.iter().try_fold((dd(-d), 0.0), |(f, df), &(h, n)| {
            let q2 = inv(s).q2_in(n);
            if q2.hi <= 0.0 {
                return None;
            }
            let q = q2.sqrt();
            let qf = q.to_f64();
            Some((f + (p * h) / q, df - h * n * n / (2.0 * pf * qf * qf * qf)))
        })
    };
    // F > 0 where s is too small (the beam too grazing): the root lies above.
    let (mut lo, mut hi) = (dd(0.0), n_g2);
    for _ in 0..128 {
        let (fs, dfs) = f(s)?;
        if fs.hi == 0.0 {
            break;
        }
        if fs.hi > 0.0 {
            lo = s
        } else {
            hi = s
        }
        let step = fs.to_f64() / dfs;
        if !step.is_finite() {
            break;
        }
        let newton = s - dd(step);
        if step.abs() <= 1e-31 * s.hi {
            s = newton;
            break;
        }
        s = if (newton - lo).hi > 0.0 && (hi - newton).hi > 0.0 {
            newton
        } else {
            (lo + hi).mul_f64(0.5)
        };
        if (hi - lo).hi <= 1e-31 * s.hi {
            break;
        }
    }
    (s.hi > 0.0).then(|| inv(s))
}

/// [`cannot_reach`] for a sequence on parallel planes.
pub(super) fn stack_cannot_reach(
    scene: &Scene,
    seq: &[Event],
    source: DVec3,
    target: DVec3,
    first: usize,
) -> bool {
    // Longer sequences are left to the solver.
    const MAX_HEIGHTS: usize = 16;
    if seq.len() + 2 > MAX_HEIGHTS {
        return false;
    }
    let nu = scene.surfaces[first].plane.normal;
    let parallel = |n: DVec3| n == nu || n.cross(nu).length_squared() <= 1e-30;
    // Heights along ν of the source (k = 0), event plane k (1..=len) and the target.
    let mut heights = [0.0; MAX_HEIGHTS];
    heights[0] = source.dot(nu);
    for (k, ev) in seq.iter().enumerate() {
        let plane = &scene.surfaces[ev.surface].plane;
        if !parallel(plane.normal) {
            return false;
        }
        heights[k + 1] = plane.point.dot(nu);
    }
    heights[seq.len() + 1] = target.dot(nu);
    let z = &heights[..seq.len() + 2];
    // Every segment runs at most its height plus the lateral distance (all segments run the
    // same way sideways in the plane of incidence): the scene size bounds their lengths.
    let size =
        length_bound(target - source) + z.windows(2).map(|w| (w[1] - w[0]).abs()).sum::<f64>();
    let margin = 1e-9 * (1.0 + size);
    // The first segment runs toward the first plane; any launch that reaches it does.
    let dz0 = z[1] - z[0];
    if dz0.abs() <= margin {
        return false;
    }
    // The unbounded interfaces parallel to the events (surface, height): a segment strictly
    // between two of its own ends' heights that crosses one is blocked.
    const MAX_PLANES: usize = 16;
    let mut planes = [(0, 0.0); MAX_PLANES];
    let mut n_planes = 0;
    for (j, surf) in scene.surfaces.iter().enumerate() {
        if matches!(surf.extent, Extent::Unbounded)
            && !matches!(surf.kind, SurfaceKind::Opaque { .. })
            && parallel(surf.plane.normal)
        {
            if n_planes == MAX_PLANES {
                break; // the rest are not looked at: fewer claims, never a wrong one
            }
            planes[n_planes] = (j, surf.plane.point.dot(nu));
            n_planes += 1;
        }
    }
    let planes = &planes[..n_planes];
    let mut up = dz0.signum();
    for k in 0..=seq.len() {
        let (za, zb) = (z[k], z[k + 1]);
        if (zb - za) * up < -margin {
            // Missed (or the target behind): this segment runs away from its end.
            return true;
        }
        let ends = |j: usize| {
            (k >= 1 && seq[k - 1].surface == j) || (k < seq.len() && seq[k].surface == j)
        };
        let (lo, hi) = (za.min(zb) + margin, za.max(zb) - margin);
        if planes.iter().any(|&(j, zj)| zj > lo && zj < hi && !ends(j)) {
            return true;
        }
        if seq.get(k).is_some_and(|ev| ev.kind == EventKind::Reflect) {
            up = -up;
        }
    }
    false
}

/// Whether the landing error of a path through parallel planes, launched from the Snell
/// invariant of [`parallel_stack_launch`] (the path exists: the invariant's equation has its
/// root) and refined by Newton as far as f64 directions allow, is harmless to what the tracer
/// reports. Directions are f64 unit vectors: leaving a plate whose index is up to 10^4 times the
/// ambient's near grazing, the refraction multiplies their rounding by the index ratio and by
/// 1/cos²θ on the way to the target, so the landing error stalls above 1e-12 of the scene
/// (5.8e-8 m at 125 m for ambient n = 0.001 over a plate n = 1 at 88.9°; `fringe fuzz --family
/// two_beam_plate --seed 7`, scene 5), and the path was dropped, silently losing a beam. The
/// last segment ends exactly at the target and the optical path is stationary in the event
/// points (Fermat), so a landing error δ changes the path by ~n δ²/(2 L) with L the last
/// segment's length: accepted while that is ≤ [`STACK_PATH_SECOND_ORDER_M`], the directions and
/// amplitudes then being those of the exact launch to rounding.
pub(super) fn stack_landing_harmless(
    trace: &impl Fn([f64; 2], &mut Geometry) -> Result<(), PathError>,
    x: [f64; 2],
    g: &mut Geometry,
    target: Target,
) -> bool {
    let Target::Point(p) = target else {
        return false;
    };
    if trace(x, g).is_err() {
        return false;
    }
    let (Some(&last), Some(&d), Some(&n)) = (g.points.last(), g.dirs.last(), g.indices.last())
    else {
        return false;
    };
    let along = (p - last).dot(d);
    if along <= 0.0 {
        return false;
    }
    let miss = ((p - last) - along * d).length();
    n * miss * miss / (2.0 * along) <= STACK_PATH_SECOND_ORDER_M
}

/// The largest second-order optical-path change (m) a stalled landing may cost a path through
/// parallel planes ([`stack_landing_harmless`]): 1e-18 m is 5e-12 of a cycle (3e-11 rad) at
/// 200 nm, the shortest wavelength a case may use, so it moves a two-beam intensity by at most
/// ~6e-11 of its scale, 16 times below the library's tightest tolerance (1e-9 in `fringe fuzz`).
const STACK_PATH_SECOND_ORDER_M: f64 = 1e-18;
