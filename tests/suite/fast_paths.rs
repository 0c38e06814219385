//! The render's shortcuts through `trace::arrivals_with` give bitwise the results of the plain
//! code they replace:
//!
//! * `trace::propagate_channels` (all channels of a source along a path in one pass) equals
//!   `trace::propagate` channel by channel, under both coefficient models, including normal
//!   incidence, where each channel's own frame picks the s axis;
//! * `path::cannot_reach` (skip a sequence without solving) only ever claims sequences that
//!   `path::solve` rejects, so `arrivals_with` without a failure list finds exactly the arrivals
//!   of `arrivals`;
//! * the far-field walk of a plane wave (`TraceSettings::share_beginnings`: every beginning of a
//!   sequence traced and propagated once) finds exactly the arrivals and failures of tracing
//!   every sequence from the source, in the same order, and its reflected orders share the
//!   records of their common beginning.
//!
//! Scenes are random (plates, wedges, films on mirrors and splitters, bounded interfaces,
//! shields with and without apertures; point, line and plane-wave sources; point and far-field
//! targets, including points straight above the source, i.e. normal incidence on level planes).
//! Comparisons are of `Debug` text, which prints every f64 exactly (shortest round trip, signed
//! zeros), so "equal" means equal bit for bit.

use crate::common;
use crate::support::airy_plate as support_airy_plate;

use common::config;
use fringe::optics::interaction::CoefficientModel;
use fringe::optics::material::{CoherenceRules, Medium};
use fringe::scene::geometry::{Extent, Plane, Rect};
use fringe::scene::source::{Emitter, Polarization, Source};
use fringe::scene::{Scene, SceneOptics, Surface, SurfaceKind};
use fringe::trace::path::{self, Event, EventKind, Target};
use fringe::trace::{self, Plan, TraceSettings};
use glam::DVec3;
use proptest::prelude::*;
use support_airy_plate::airy_plate;

const LAMBDA: f64 = 550e-9;

use crate::support::draw::Draw;

fn medium(n: f64) -> Medium {
    Medium::constant("m", n)
}

fn shield(point: DVec3, apertures: Vec<Rect>) -> Surface {
    Surface {
        name: "shield".into(),
        plane: Plane::new(point, DVec3::Z),
        extent: Extent::Rect {
            u: DVec3::X,
            v: DVec3::Y,
            rect: Rect {
                center_uv: [0.0, 0.0],
                half_width_m: 0.004,
                half_height_m: 0.004,
            },
        },
        kind: SurfaceKind::Opaque { apertures },
    }
}

/// A random scene around a source 10 mm above the plane z = 0, with its settings.
fn scene(d: &mut Draw) -> (Scene, TraceSettings) {
    let mut scene = Scene::new(Medium::vacuum());
    let level = d.chance(0.6);
    let normal = if level {
        DVec3::Z
    } else {
        DVec3::new(d.range(-0.2, 0.2), d.range(-0.2, 0.2), 1.0).normalize()
    };
    let n = d.range(1.2, 2.5);
    let thickness = if d.chance(0.5) {
        d.range(1e-7, 2e-6)
    } else {
        d.range(1e-4, 3e-3)
    };
    match d.pick(4) {
        0 => {
            scene.add_plate(
                "plate",
                DVec3::ZERO,
                normal,
                thickness,
                Medium::vacuum(),
                medium(n),
                Medium::vacuum(),
            );
        }
        1 => {
            scene.add_wedge(
                "wedge",
                DVec3::ZERO,
                normal,
                thickness,
                d.range(-0.05, 0.05),
                DVec3::X,
                Medium::vacuum(),
                medium(n),
                Medium::vacuum(),
            );
        }
        2 => {
            // A film on a substrate, and a mirror or a splitter under the substrate.
            let below = d.range(1.0, 2.0);
            let (_, bottom) = scene.add_plate(
                "film",
                DVec3::ZERO,
                normal,
                thickness,
                Medium::vacuum(),
                medium(n),
                medium(below),
            );
            let depth = thickness + d.range(1e-4, 2e-3);
            let kind = if d.chance(0.5) {
                SurfaceKind::IdealMirror {
                    coherence: CoherenceRules::default(),
                }
            } else {
                SurfaceKind::Splitter {
                    reflectance: d.range(0.1, 0.9),
                    medium: medium(below),
                    coherence: CoherenceRules::default(),
                }
            };
            let _ = bottom;
            scene.surfaces.push(Surface {
                name: "under".into(),
                plane: Plane::new(-depth * normal, normal),
                extent: Extent::Unbounded,
                kind,
            });
        }
        _ => {
            // A bounded glass interface over a mirror.
            let plane = Plane::new(DVec3::ZERO, normal);
            let (u, v) = plane.axes(DVec3::X);
            scene.surfaces.push(Surface {
                name: "glass".into(),
                plane,
                extent: Extent::Rect {
                    u,
                    v,
                    rect: Rect {
                        center_uv: [d.range(-0.01, 0.01), 0.0],
                        half_width_m: d.range(0.005, 0.05),
                        half_height_m: 0.05,
                    },
                },
                kind: SurfaceKind::Interface {
                    front: Medium::vacuum(),
                    back: medium(n),
                    coherence: CoherenceRules {
                        reflected_keeps: true,
                        refracted_keeps: d.chance(0.8),
                    },
                },
            });
            scene.surfaces.push(Surface {
                name: "mirror".into(),
                plane: Plane::new(DVec3::new(0.0, 0.0, -0.01), DVec3::Z),
                extent: Extent::Unbounded,
                kind: SurfaceKind::IdealMirror {
                    coherence: CoherenceRules::default(),
                },
            });
        }
    }
    if d.chance(0.6) {
        let apertures = if d.chance(0.5) {
            vec![Rect {
                center_uv: [d.range(-0.003, 0.003), 0.0],
                half_width_m: d.range(2e-4, 2e-3),
                half_height_m: d.range(2e-4, 2e-3),
            }]
        } else {
            Vec::new()
        };
        let at = DVec3::new(d.range(0.0, 0.02), d.range(-0.002, 0.002), 0.012);
        scene.surfaces.push(shield(at, apertures));
    }
    let polarization = if d.chance(0.5) {
        Polarization::Unpolarized
    } else {
        Polarization::Linear {
            reference: DVec3::new(d.range(-1.0, 1.0), 1.0, 0.3),
            angle_rad: d.range(0.0, 3.0),
        }
    };
    let emitter = match d.pick(5) {
        0..=2 => Emitter::Point {
            position: DVec3::new(0.0, 0.0, 0.01),
        },
        3 => Emitter::Line {
            point: DVec3::new(0.0, 0.0, 0.01),
            axis: DVec3::Y,
        },
        _ => Emitter::PlaneWave {
            direction: DVec3::new(d.range(-0.5, 0.5), d.range(-0.1, 0.1), -1.0).normalize(),
            reference_point: DVec3::new(0.0, 0.0, 0.01),
        },
    };
    scene.sources.push(Source {
        name: "lamp".into(),
        emitter,
        polarization,
        intensity: d.range(0.5, 2.0),
        coherence_group: 0,
        coherence_length_m: if d.chance(0.2) { 0.03 } else { f64::INFINITY },
    });
    let mut settings = TraceSettings::default();
    settings.solve.spreading = d.chance(0.5);
    settings.limits.max_internal_reflections = d.pick(3);
    (scene, settings)
}

/// Random targets: screen points above (and a few below) the scene, the first one straight
/// above the source; or far-field directions.
fn targets(d: &mut Draw) -> Vec<Target> {
    let far = d.chance(0.25);
    (0..10)
        .map(|k| {
            if far {
                Target::Direction {
                    dir: DVec3::new(d.range(-0.5, 0.5), d.range(-0.3, 0.3), 1.0).normalize(),
                    reference: DVec3::new(0.0, 0.0, 0.02),
                }
            } else if k == 0 {
                Target::Point(DVec3::new(0.0, 0.0, 0.02))
            } else {
                let z = if d.chance(0.8) { 0.02 } else { -0.03 };
                Target::Point(DVec3::new(d.range(-0.03, 0.06), d.range(-0.02, 0.02), z))
            }
        })
        .collect()
}

fn plan_for(scene: &Scene, optics: &SceneOptics, targets: &[Target], st: &TraceSettings) -> Plan {
    let probes: Vec<DVec3> = targets
        .iter()
        .map(|t| match t {
            Target::Point(p) => *p,
            Target::Direction { dir, .. } => DVec3::new(0.0, 0.0, 0.01) + 0.02 * *dir,
        })
        .collect();
    trace::plan(scene, optics, &probes, &st.limits)
}

/// Every channel of the source, propagated in one pass and one at a time, under `model`.
fn one_pass_and_alone(
    scene: &Scene,
    optics: &SceneOptics,
    a: &trace::Arrival,
    target: &Target,
    model: CoefficientModel,
) -> (Vec<String>, Vec<String>) {
    let src = &scene.sources[a.source];
    let channels = src.channels();
    let mut shared = Vec::new();
    trace::propagate_channels(
        scene,
        optics,
        &channels,
        src.coherence_length_m,
        &a.path,
        target,
        model,
        |k, ray| shared.push(format!("{k} {ray:?}")),
    );
    let alone = channels
        .iter()
        .enumerate()
        .map(|(k, ch)| {
            let ray = trace::propagate(
                scene,
                optics,
                ch,
                src.coherence_length_m,
                &a.path,
                target,
                model,
            );
            format!("{k} {ray:?}")
        })
        .collect();
    (shared, alone)
}

proptest! {
    #![proptest_config(config(64))]

    /// One pass over the channels equals one channel at a time, bit for bit; `arrivals_with`
    /// without a failure list (which skips what `cannot_reach` claims) finds exactly the
    /// arrivals of `arrivals`; and every sequence `cannot_reach` claims is one `solve` rejects.
    #[test]
    fn shortcuts_equal_the_plain_trace(seed in any::<u64>()) {
        let mut d = Draw(seed);
        let (scene, st) = scene(&mut d);
        let optics = scene.optics(LAMBDA).unwrap();
        let targets = targets(&mut d);
        let plan = plan_for(&scene, &optics, &targets, &st);
        for t in &targets {
            let (found, failed) = trace::arrivals(&scene, &optics, &plan, t, &st);
            let quick = trace::arrivals_with(&scene, &optics, &plan, t, &st, true, None);
            prop_assert_eq!(format!("{quick:?}"), format!("{found:?}"), "arrivals_with(None) vs arrivals at {:?}", t);
            for a in found.iter().filter(|a| a.channel == scene.sources[a.source].channels()[0]) {
                for model in [CoefficientModel::Vector, CoefficientModel::PaperRules] {
                    let (shared, alone) = one_pass_and_alone(&scene, &optics, a, t, model);
                    prop_assert_eq!(shared, alone, "{:?} along {}", model, path::sequence_label(&a.path.sequence));
                }
            }
            for (si, src) in scene.sources.iter().enumerate() {
                for seq in &plan.sequences[si].sequences() {
                    if path::cannot_reach(&scene, src.emitter, seq, t) {
                        let solved = path::solve(&scene, &optics, src.emitter, seq, *t, &st.solve);
                        prop_assert!(solved.is_err(), "cannot_reach claimed {} at {:?}, but solve found {:?}", path::sequence_label(seq), t, solved);
                        prop_assert!(failed.iter().any(|f| f.source == si && &f.sequence == seq));
                    }
                }
            }
        }
    }
}

proptest! {
    #![proptest_config(config(96))]

    /// A plane wave into the far field: the walk over the sequence tree (shared beginnings)
    /// equals tracing each sequence from the source, bit for bit — arrivals under both models,
    /// their order, and every failure with its reason (missed planes, TIR, extents, blockers,
    /// direction mismatches) — with and without the paper's rules and a failure list.
    #[test]
    fn the_far_field_walk_equals_the_one_by_one_trace(seed in any::<u64>()) {
        let mut d = Draw(seed);
        let (mut scene, mut st) = scene(&mut d);
        scene.sources[0].emitter = Emitter::PlaneWave {
            direction: DVec3::new(d.range(-0.6, 0.6), d.range(-0.1, 0.1), -1.0).normalize(),
            reference_point: DVec3::new(d.range(-0.03, 0.03), d.range(-0.002, 0.002), 0.01),
        };
        for surf in scene.surfaces.iter_mut() {
            if matches!(surf.extent, Extent::Unbounded) && d.chance(0.4) {
                // Bounded faces: events outside them, and sequences failing on two counts.
                let (u, v) = surf.plane.axes(DVec3::X);
                surf.extent = Extent::Rect {
                    u,
                    v,
                    rect: Rect {
                        center_uv: [d.range(-0.01, 0.01), 0.0],
                        half_width_m: d.range(0.002, 0.02),
                        half_height_m: 0.05,
                    },
                };
            }
        }
        if d.chance(0.5) {
            // A shield between the wave's reference point and the scene, often with a hole.
            let apertures = if d.chance(0.7) {
                vec![Rect {
                    center_uv: [d.range(-0.004, 0.004), 0.0],
                    half_width_m: d.range(5e-4, 3e-3),
                    half_height_m: d.range(5e-4, 3e-3),
                }]
            } else {
                Vec::new()
            };
            let at = DVec3::new(d.range(-0.01, 0.01), 0.0, d.range(0.001, 0.009));
            scene.surfaces.push(shield(at, apertures));
        }
        st.limits.max_internal_reflections = d.pick(7);
        st.limits.max_events = 2 * st.limits.max_internal_reflections + 6;
        let optics = scene.optics(LAMBDA).unwrap();
        // Far-field directions on both sides, and the specular and straight-through ones.
        let incident = match scene.sources[0].emitter {
            Emitter::PlaneWave { direction, .. } => direction,
            _ => unreachable!(),
        };
        let mut targets: Vec<Target> = (0..6)
            .map(|_| DVec3::new(d.range(-0.6, 0.6), d.range(-0.3, 0.3), if d.chance(0.7) { 1.0 } else { -1.0 }).normalize())
            .chain([DVec3::new(incident.x, incident.y, -incident.z), incident])
            .map(|dir| Target::Direction { dir, reference: DVec3::new(0.0, 0.0, 0.02) })
            .collect();
        targets.push(Target::Direction { dir: DVec3::Z, reference: DVec3::new(0.001, 0.0, 0.015) });
        let plan = plan_for(&scene, &optics, &targets, &st);
        let one_by_one = TraceSettings { share_beginnings: false, ..st };
        let walk = TraceSettings { share_beginnings: true, ..st };
        for t in &targets {
            let want = trace::arrivals(&scene, &optics, &plan, t, &one_by_one);
            let got = trace::arrivals(&scene, &optics, &plan, t, &walk);
            prop_assert_eq!(format!("{:?}", got.0), format!("{:?}", want.0), "arrivals at {:?}", t);
            prop_assert_eq!(format!("{:?}", got.1), format!("{:?}", want.1), "failures at {:?}", t);
            let quick = trace::arrivals_with(&scene, &optics, &plan, t, &walk, false, None);
            let plain = trace::arrivals_with(&scene, &optics, &plan, t, &one_by_one, false, None);
            prop_assert_eq!(format!("{quick:?}"), format!("{plain:?}"), "vector only, no failure list, at {:?}", t);
        }
    }
}

/// The walk's cost is O(1) per reflected order because the orders share what they have in
/// common: order k + 1's path records (events, points, directions, indices) and its ray's phase
/// ledger begin with order k's, stored once. Checked for 400 internal reflections (200 orders):
/// each order's records share all but their last few elements with the next order's, so the
/// memory of the whole family is O(m), where copies would be O(m²).
#[test]
fn the_reflected_orders_share_their_common_beginning() {
    use EventKind::{Reflect as R, Refract as T};
    let (scene, target) = airy_plate(60f64.to_radians());
    let optics = scene.optics(LAMBDA).unwrap();
    let limits = path::EnumerationLimits {
        max_internal_reflections: 400,
        max_events: 806,
    };
    let st = TraceSettings {
        limits,
        ..TraceSettings::default()
    };
    let plan = trace::plan(&scene, &optics, &[DVec3::new(0.0, 0.0, 0.02)], &limits);
    let (found, _) = trace::arrivals(&scene, &optics, &plan, &target, &st);
    // Order k ≥ 1: T0 (R1 R0)^(k−1) R1 T0, 2k + 1 events; one channel's arrivals, by order.
    let mut orders: Vec<&trace::Arrival> = found
        .iter()
        .filter(|a| a.channel == scene.sources[0].channels()[0] && a.path.sequence.len() > 1)
        .collect();
    orders.sort_by_key(|a| a.path.sequence.len());
    assert_eq!(orders.len(), 200, "reflected orders 1..=200 arrive");
    for (k, a) in orders.iter().enumerate() {
        let want: Vec<Event> = std::iter::once(ev(0, T))
            .chain((0..2 * k + 1).map(|i| ev(1 - i % 2, R)))
            .chain([ev(0, T)])
            .collect();
        assert_eq!(a.path.sequence, want, "order {}", k + 1);
    }
    for pair in orders.windows(2) {
        let (a, b) = (&pair[0].path, &pair[1].path);
        // Order k's records without its last event and exit are order k + 1's beginning.
        let n = a.sequence.len() - 1;
        assert!(
            a.sequence.shares_beginning(&b.sequence, n),
            "sequence of {} events",
            n + 1
        );
        assert!(a.points.shares_beginning(&b.points, n + 1), "points");
        assert!(a.dirs.shares_beginning(&b.dirs, n + 1), "directions");
        assert!(a.indices.shares_beginning(&b.indices, n + 1), "indices");
        // Ledger: a path and an interaction entry per shared event.
        let (la, lb) = (
            &pair[0].vector.ledger.entries,
            &pair[1].vector.ledger.entries,
        );
        assert!(la.shares_beginning(lb, 2 * n), "ledger");
    }
}

fn ev(surface: usize, kind: EventKind) -> Event {
    Event { surface, kind }
}

/// The amplitude-division picture's scene (figures/plate_amplitude_division.json): a 0.7 µm
/// film of n = 1.5, an unpolarized point 10 mm above it, a 2 mm shield 0.1 mm above the source.
fn amplitude_division() -> Scene {
    let mut scene = Scene::new(Medium::vacuum());
    scene.add_plate(
        "plate",
        DVec3::ZERO,
        DVec3::Z,
        0.7e-6,
        Medium::vacuum(),
        medium(1.5),
        Medium::vacuum(),
    );
    let mut s = shield(DVec3::new(0.0, 0.0, 0.0101), Vec::new());
    if let Extent::Rect { rect, .. } = &mut s.extent {
        rect.half_width_m = 0.001;
        rect.half_height_m = 0.001;
    }
    scene.surfaces.push(s);
    scene.sources.push(Source {
        name: "lamp".into(),
        emitter: Emitter::Point {
            position: DVec3::new(0.0, 0.0, 0.01),
        },
        polarization: Polarization::Unpolarized,
        intensity: 1.0,
        coherence_group: 0,
        coherence_length_m: f64::INFINITY,
    });
    scene
}

/// In the amplitude-division scene, at a screen point beside the source, `cannot_reach` claims
/// exactly the four sequences that cannot get there (direct: the shield; T0 and T0 T1: they end
/// going down; T0 R1: it must cross the top face again), and neither of the two beams, each
/// claim confirmed by `solve`. Pins that the shortcut does its job, not only that it is safe.
#[test]
fn the_amplitude_division_scene_skips_exactly_its_four_dead_sequences() {
    use EventKind::{Reflect as R, Refract as T};
    let scene = amplitude_division();
    let optics = scene.optics(LAMBDA).unwrap();
    let emitter = scene.sources[0].emitter;
    let target = Target::Point(DVec3::new(0.035, 0.004, 0.02));
    let cases = [
        (vec![], true),
        (vec![ev(0, R)], false),
        (vec![ev(0, T)], true),
        (vec![ev(0, T), ev(1, R)], true),
        (vec![ev(0, T), ev(1, R), ev(0, T)], false),
        (vec![ev(0, T), ev(1, T)], true),
    ];
    for (seq, claimed) in cases {
        let label = path::sequence_label(&seq);
        let got = path::cannot_reach(&scene, emitter, &seq, &target);
        assert_eq!(
            got, claimed,
            "cannot_reach({label}): actual {got}, expected {claimed}"
        );
        let solved = path::solve(&scene, &optics, emitter, &seq, target, &Default::default());
        assert_eq!(
            solved.is_err(),
            claimed,
            "solve({label}) failed: actual {}, expected {claimed}",
            solved.is_err()
        );
    }
}

/// Straight above an unpolarized source over a level film, the top-face reflection meets the
/// film at exactly normal incidence: the plane of incidence is undefined and each channel's own
/// field picks its s axis, so the x and y dipole channels leave with different frames. One pass
/// over the channels must still give each channel's own ray bit for bit (a pass that took the
/// first channel's s for all would give all the same frame).
#[test]
fn normal_incidence_keeps_each_channels_frame_in_one_pass() {
    let mut scene = amplitude_division();
    scene.surfaces.pop(); // no shield: the direct path exists too
    let optics = scene.optics(LAMBDA).unwrap();
    let target = Target::Point(DVec3::new(0.0, 0.0, 0.02));
    let seq = vec![ev(0, EventKind::Reflect)];
    let src = &scene.sources[0];
    let p = path::solve(
        &scene,
        &optics,
        src.emitter,
        &seq,
        target,
        &Default::default(),
    )
    .unwrap();
    let c = p.dirs[0].cross(DVec3::Z).length();
    assert!(
        c <= 1e-12,
        "normal incidence: |d × N| actual {c:e}, expected ≤ 1e-12"
    );
    let channels = src.channels();
    let mut rays = Vec::new();
    trace::propagate_channels(
        &scene,
        &optics,
        &channels,
        src.coherence_length_m,
        &p,
        &target,
        CoefficientModel::Vector,
        |_, r| rays.push(r),
    );
    // Basis-free light: dipoles along x, y, z (the z dipole sends nothing straight up).
    assert_eq!(rays.len(), 3, "rays: actual {}, expected 3", rays.len());
    let gap = (rays[0].x - rays[1].x).length();
    assert!(
        gap > 1.0,
        "the channels' frames differ: |X0 − X1| actual {gap:e}, expected √2"
    );
    for (k, ch) in channels.iter().enumerate() {
        let alone = trace::propagate(
            &scene,
            &optics,
            ch,
            src.coherence_length_m,
            &p,
            &target,
            CoefficientModel::Vector,
        );
        assert_eq!(
            format!("{:?}", rays[k]),
            format!("{alone:?}"),
            "channel {k}"
        );
    }
}

proptest! {
    #![proptest_config(config(64))]

    /// Non-dispersive media: tracing at another wavelength gives the arrivals traced at 550 nm
    /// with only their wavelength changed (`Arrival::at_wavelength`), bit for bit — paths,
    /// fields, optical paths, ledgers and the paper's-rules rays. This is what lets `fringe
    /// check` trace a spectrum through such a scene once per probe point.
    #[test]
    fn a_trace_at_another_wavelength_is_the_same_arrivals_relabelled(seed in any::<u64>()) {
        let mut d = Draw(seed);
        let (scene, st) = scene(&mut d);
        let targets = targets(&mut d);
        let l2 = d.range(400e-9, 800e-9);
        let (o1, o2) = (scene.optics(LAMBDA).unwrap(), scene.optics(l2).unwrap());
        let p1 = plan_for(&scene, &o1, &targets, &st);
        let p2 = plan_for(&scene, &o2, &targets, &st);
        for t in &targets {
            let relabelled: Vec<trace::Arrival> = trace::arrivals(&scene, &o1, &p1, t, &st)
                .0
                .iter()
                .map(|a| a.at_wavelength(l2))
                .collect();
            let traced = trace::arrivals(&scene, &o2, &p2, t, &st).0;
            prop_assert_eq!(format!("{relabelled:?}"), format!("{traced:?}"), "at {:?}", t);
        }
    }
}
