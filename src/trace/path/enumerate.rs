//! Enumerating the surface sequences a source's light can follow to a target, within the
//! limits of a case (internal reflections, sequence count).

use super::*;

/// Limits of sequence enumeration.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct EnumerationLimits {
    /// Maximum number of reflections inside a medium other than the ambient one.
    pub max_internal_reflections: usize,
    /// Maximum number of events in a sequence.
    pub max_events: usize,
}

impl Default for EnumerationLimits {
    fn default() -> Self {
        EnumerationLimits {
            max_internal_reflections: 1,
            max_events: 8,
        }
    }
}

/// Discover the surface sequences light from `emitter` can follow: probe rays are traced
/// forward (toward each of `probe_targets`) through the real, bounded scene, branching into
/// reflected and refracted children, and every node of the resulting ray trees is a candidate
/// sequence. They are returned as one tree of common beginnings ([`SequenceTree`]: sorted,
/// without duplicates); the exact solver decides which of them reach a given point.
pub fn discover_sequences(
    scene: &Scene,
    optics: &SceneOptics,
    emitter: Emitter,
    probe_targets: &[DVec3],
    limits: &EnumerationLimits,
) -> SequenceTree {
    let mut found = TreeBuilder::new();
    // A plane wave on a stack of unbounded parallel planes meets the same planes in the same
    // order along every line, so one probe ray from the solver's own stack launch
    // ([`plane_wave_launch`], a local anchor 1 mm or more before the first plane) finds every
    // sequence. A probe from the wavefront through a target instead meets the planes at
    // ~h/cos θ: 5.7e13 m out for a reference 1 m above the film at 89.999999999999°, where a
    // coordinate rounds by ~1e-2 m; in a rotated frame the 1 µm film's faces are then not
    // resolved, the ray reflected at the lower face was already above the upper one, and every
    // order with an internal reflection was missing from the plan (T of a film on a substrate
    // 36–44 % off: `fringe fuzz --family airy --seed 1`, scene 7304,
    // `tests/suite/truth_grazing_brewster.rs`).
    let launch = match emitter {
        Emitter::PlaneWave {
            direction,
            reference_point,
        } => {
            let d = direction.normalize();
            stack_launch(scene, d, reference_point)
                .filter(|_| d.is_finite())
                .map(|(launch, _)| (launch, d))
        }
        _ => None,
    };
    let starts = match launch {
        Some(start) => vec![start],
        None => probe_targets
            .iter()
            .map(|&p| probe_start(emitter, p))
            .collect(),
    };
    for (o, d) in starts {
        if !d.is_finite() {
            continue;
        }
        explore(
            scene,
            optics,
            Probe {
                o,
                d,
                n: optics.ambient_index,
                from: None,
                carried: None,
                internal: 0,
                parent: None,
                depth: 0,
            },
            limits,
            &mut found,
        );
    }
    found.finish()
}

/// Where a probe ray toward `p` starts from `emitter`, and its direction.
fn probe_start(emitter: Emitter, p: DVec3) -> (DVec3, DVec3) {
    match emitter {
        Emitter::Point { position } => (position, (p - position).normalize()),
        Emitter::Line { point, axis } => {
            let a = axis.normalize();
            let o = point + (p - point).dot(a) * a;
            (o, (p - o).normalize())
        }
        Emitter::PlaneWave {
            direction,
            reference_point,
        } => {
            let d = direction.normalize();
            (p - (p - reference_point).dot(d) * d, d)
        }
    }
}

/// One probe ray waiting to be explored: where it starts, its direction and medium, the
/// surface it leaves, the (n cos θ)² it carries between parallel faces, the internal
/// reflections so far, and the tree node it extends (`parent`: the node and the event that
/// creates it; `None` for the root).
struct Probe {
    o: DVec3,
    d: DVec3,
    n: f64,
    from: Option<usize>,
    carried: Option<(DVec3, interaction::SnellInvariant)>,
    internal: usize,
    parent: Option<(usize, Event)>,
    depth: usize,
}

/// Explore the ray tree of `start` depth first with an explicit stack (a film near grazing
/// incidence runs thousands of events deep: recursion overflowed a worker thread's stack,
/// `fringe fuzz --family airy --count 10000 --seed 1`). Children are pushed in reverse and
/// their tree nodes created when popped, so nodes are made in the order a recursion would
/// make them: reflected subtree, then tunnelled, then refracted.
fn explore(
    scene: &Scene,
    optics: &SceneOptics,
    start: Probe,
    limits: &EnumerationLimits,
    found: &mut TreeBuilder,
) {
    let mut stack = vec![start];
    while let Some(p) = stack.pop() {
        let node = match p.parent {
            Some((parent, event)) => found.child(parent, event),
            None => TreeBuilder::ROOT,
        };
        found.mark(node);
        let mut children = explore_one(scene, optics, &p, node, limits);
        while let Some(c) = children.pop() {
            stack.push(c);
        }
    }
}

/// The children of one probe ray, in the order they are explored: reflected, tunnelled,
/// refracted (none at the depth limit, at an opaque surface or where nothing is ahead).
fn explore_one(
    scene: &Scene,
    optics: &SceneOptics,
    p: &Probe,
    node: usize,
    limits: &EnumerationLimits,
) -> Vec<Probe> {
    let mut children = Vec::new();
    let (o, d, n) = (p.o, p.d, p.n);
    if p.depth >= limits.max_events {
        return children;
    }
    // Nearest surface ahead that stops or splits the ray.
    let mut best: Option<(f64, usize)> = None;
    for (j, surf) in scene.surfaces.iter().enumerate() {
        if Some(j) == p.from {
            continue;
        }
        // Any plane ahead (t > 0, no distance epsilon: a film of 1 pm is found); the surface
        // the ray leaves is skipped by name.
        if let Some(t) = surf.plane.intersect(o, d)
            && t > 0.0
            && best.is_none_or(|(bt, _)| t < bt)
        {
            let x = o + t * d;
            if surf.blocks(x) || surf.interacts(x) {
                best = Some((t, j));
            }
        }
    }
    let Some((t, j)) = best else { return children };
    // On the plane itself (as the solver's `step_planes` puts it).
    let x = scene.surfaces[j].plane.project(o + t * d);
    let Some(so) = optics.surfaces[j] else {
        return children; // opaque: absorbed
    };
    let normal = scene.surfaces[j].plane.normal;
    let (n1, n2) = interaction::indices_for(so, normal, d, n);
    // TIR verdicts and refracted directions as the solver forms them (`step_planes`): from the
    // (n cos θ)² carried in double-double between parallel faces. An f64 cos²θt = 1 − η²
    // sin²θi rounds at ~η² ε, which near grazing exit (cos²θt ~ 1e-14 and below) decided a
    // total reflection where the ray refracts out, and every order through a film at
    // grazing incidence was missing from the plan (issue #12: the Airy tail could not be
    // closed, `fringe fuzz --family airy --seed 1`, scenes 6, 69, 135, 163, 217).
    let invariant = interaction::snell_invariant(d, normal, n1, p.carried);
    let q2_t = invariant.q2_in(n2);
    let is_internal = n != optics.ambient_index;
    let event = |kind| Some((node, Event { surface: j, kind }));
    if !is_internal || p.internal < limits.max_internal_reflections {
        children.push(Probe {
            o: x,
            d: fresnel::reflect(d, normal),
            n,
            from: Some(j),
            carried: Some((normal, invariant)),
            internal: p.internal + usize::from(is_internal),
            parent: event(EventKind::Reflect),
            depth: p.depth + 1,
        });
    }
    let refracted = match so {
        SurfaceOptics::Dielectric { .. } if n1 != n2 => (q2_t.hi >= 0.0)
            .then(|| interaction::snell_direction(d, normal, (n1, n2), q2_t.sqrt().to_f64() / n2)),
        SurfaceOptics::Dielectric { .. } | SurfaceOptics::Splitter { .. } => {
            fresnel::refract(d, normal, n1, n2)
        }
        _ => None,
    };
    // Beyond the critical angle with a layer behind the face: the tunnelled wave.
    if q2_t.hi < 0.0
        && let Some(c) = tunnelled(
            scene,
            optics,
            (x, d, j),
            (n1, n2),
            (invariant, q2_t),
            p,
            node,
        )
    {
        children.push(c);
    }
    if let Some(d_t) = refracted {
        children.push(Probe {
            o: x,
            d: d_t,
            n: n2,
            from: Some(j),
            carried: Some((normal, invariant)),
            internal: p.internal,
            parent: event(EventKind::Refract),
            depth: p.depth + 1,
        });
    }
    children
}

/// The tunnelled child of a ray meeting surface `j` at `x` along `d` beyond its critical angle
/// (frustrated total reflection, docs/PHYSICS.md §5), when the face has a layer behind it and
/// a wave can leave its far face ((n3 cos θ3)² > 0, as `stack::tunnel_step` decides): it
/// starts from the foot of the normal on the far face ([`tunnel_exit`]).
fn tunnelled(
    scene: &Scene,
    optics: &SceneOptics,
    (x, d, j): (DVec3, DVec3, usize),
    (n1, n2): (f64, f64),
    (invariant, q2_t): (interaction::SnellInvariant, DoubleDouble),
    p: &Probe,
    node: usize,
) -> Option<Probe> {
    let normal = scene.surfaces[j].plane.normal;
    let l = optics.layers[j][usize::from(d.dot(normal) >= 0.0)]?;
    if !matches!(optics.surfaces[j], Some(SurfaceOptics::Dielectric { .. }))
        || n1 == n2
        || q2_t.hi >= 0.0
    {
        return None;
    }
    let n3 = l.n_beyond;
    let q2_3 = invariant.q2_in(n3);
    if q2_3.hi <= 0.0 {
        return None;
    }
    let (exit, partner) = tunnel_exit(scene, optics, j, x, d)?;
    let d_3 = interaction::snell_direction(d, normal, (n1, n3), q2_3.sqrt().to_f64() / n3);
    Some(Probe {
        o: exit,
        d: d_3,
        n: n3,
        from: Some(partner),
        carried: Some((normal, invariant)),
        internal: p.internal,
        parent: Some((
            node,
            Event {
                surface: j,
                kind: EventKind::Tunnel,
            },
        )),
        depth: p.depth + 1,
    })
}
