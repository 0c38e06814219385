//! Issue #13 items 1 and 2: a global phase must not change results, and films down to 1 pm
//! are films. Every expected value is an independent closed form: the Airy sum of
//! `analytic::plate::Film` (its own Fresnel kernels and geometric series), and the on-axis
//! two-beam Michelson intensity ½(1 − cos(4πΔL/λ)) with ΔL exact in f64.
//!
//! Where a representational limit of f64 points remains (a plate moved ~1 m off the origin
//! with a tilted normal), the test measures it and pins the measured size instead of hiding it.

use fringe::accumulate::fidelity::Fidelity;
use fringe::harness::analytic::plate::{Film, Pol};
use fringe::harness::stability::{PathArithmetic, film_tolerance, traced_film_with};
use fringe::optics::material::{CoherenceRules, Medium};
use fringe::scene::geometry::{Extent, Plane, Rect};
use fringe::scene::source::{Emitter, Polarization, Source};
use fringe::scene::{Scene, Surface, SurfaceKind};
use fringe::trace::path::{EnumerationLimits, Target};
use fringe::trace::{self, TraceSettings};
use glam::{DQuat, DVec3};
use proptest::prelude::*;

const LAMBDA: f64 = 550e-9;

/// Internal reflections for an Airy tail below 1e-15 in both polarizations.
fn internal_for(film: &Film, theta: f64) -> usize {
    let orders = [Pol::S, Pol::P]
        .into_iter()
        .map(|p| film.orders_for_bound(theta.cos(), LAMBDA, p, 1e-15))
        .max()
        .unwrap();
    (2 * orders + 1).min(2001)
}

fn pol_angle(pol: Pol) -> f64 {
    match pol {
        Pol::S => 0.0,
        Pol::P => std::f64::consts::FRAC_PI_2,
    }
}

/// Traced far-field reflectance of the film `n` with thickness `d` at `theta`, reference
/// point `reference`, fringe's double-double paths.
fn traced_r(n: [f64; 3], d: f64, theta: f64, pol: Pol, reference: DVec3) -> f64 {
    let film = Film {
        n1: n[0],
        n2: n[1],
        n3: n[2],
        thickness_m: d,
    };
    traced_film_with(
        n,
        d,
        theta,
        (LAMBDA, pol_angle(pol)),
        internal_for(&film, theta),
        true,
        reference,
        PathArithmetic::DoubleDouble,
    )
}

fn film(n: [f64; 3], d: f64) -> Film {
    Film {
        n1: n[0],
        n2: n[1],
        n3: n[2],
        thickness_m: d,
    }
}

fn airy_r(n: [f64; 3], d: f64, theta: f64, pol: Pol) -> f64 {
    film(n, d).reflectance(theta.cos(), LAMBDA, pol)
}

/// 1e-12 relative plus the conditioning of R on f64 inputs (`stability::film_tolerance`:
/// |d ∂R/∂d|·16ε/R, which matters only for films of ~0.1 mm and more).
fn tol(n: [f64; 3], d: f64, theta: f64, pol: Pol) -> f64 {
    film_tolerance(&film(n, d), theta.cos(), LAMBDA, pol)
}

/// The scene: BK7-like plate (n = 1.5168), 3.217 µm, 80°, s, reference point 1 µm to
/// 100 m above the plate (it was 5.1e-6 off at 100 m).
#[test]
fn reference_point_up_to_100_m_above_the_plate_changes_nothing() {
    let n = [1.0, 1.5168, 1.0];
    let (d, theta) = (3.217e-6, 80f64.to_radians());
    let expected = airy_r(n, d, theta, Pol::S);
    for z in [1e-6, 1e-3, 0.1, 1.0, 10.0, 100.0] {
        let r = traced_r(n, d, theta, Pol::S, DVec3::new(0.0, 0.0, z));
        let err = (r - expected).abs() / expected;
        let tol = tol(n, d, theta, Pol::S);
        assert!(
            err <= tol,
            "reference {z} m: actual {r:e}, expected {expected:e}, err {err:e} > {tol:e}"
        );
    }
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(48))]

    /// (b) A film turned by any rotation and moved anywhere within 1 m of the origin (so its
    /// faces are tilted planes off the origin) reflects as Airy says, to 1e-12 relative (the
    /// film tolerance: 1e-12 plus the conditioning of R on d for the thickest films).
    #[test]
    fn tilted_films_anywhere_within_1_m(
        axis in prop::array::uniform3(-1.0f64..1.0),
        angle in 0.0f64..std::f64::consts::TAU,
        shift in prop::array::uniform3(-0.577f64..0.577),
        theta in 0.0f64..1.45,
        d in prop::sample::select(vec![1e-9, 1e-7, 3.217e-6, 1e-4]),
    ) {
        let axis = DVec3::from_array(axis);
        prop_assume!(axis.length() > 0.1);
        let rot = DQuat::from_axis_angle(axis.normalize(), angle);
        let top = DVec3::from_array(shift);
        let n = [1.0, 1.5168, 1.0];
        let expected = airy_r(n, d, theta, Pol::S);
        let r = rotated_film_r(rot, top, theta, d);
        let err = (r - expected).abs() / expected;
        let tol = tol(n, d, theta, Pol::S);
        prop_assert!(err <= tol, "rotation {rot:?}, top {top:?}: actual {r:e}, expected {expected:e}, err {err:e} > {tol:e}");
    }

    /// (a) The wave's reference point anywhere above the plate within 100 m (laterally too):
    /// R is the Airy value to 1e-12 relative.
    #[test]
    fn reference_point_anywhere_within_100_m(
        x in -100.0f64..100.0,
        y in -100.0f64..100.0,
        log_z in -6.0f64..2.0,
        theta in 0.0f64..1.45,
        d in prop::sample::select(vec![1e-9, 1e-7, 3.217e-6, 1e-4]),
        p in any::<bool>(),
    ) {
        let n = [1.0, 1.5168, 1.33];
        let pol = if p { Pol::P } else { Pol::S };
        let reference = DVec3::new(x, y, 10f64.powf(log_z));
        let expected = airy_r(n, d, theta, pol);
        let r = traced_r(n, d, theta, pol, reference);
        let err = (r - expected).abs() / expected;
        let tol = tol(n, d, theta, pol);
        prop_assert!(err <= tol, "reference {reference:?}: actual {r:e}, expected {expected:e}, err {err:e} > {tol:e}");
    }

    /// Item 2: a film of any thickness from 1 pm to 1 mm at any angle up to 89.9°, either
    /// polarization, matches Airy to 1e-12 relative.
    #[test]
    fn films_from_1_pm_to_1_mm_match_airy(
        log_d in -12.0f64..-3.0,
        theta_deg in 0.0f64..89.9,
        n2 in 1.05f64..3.0,
        n3 in 1.0f64..3.0,
        p in any::<bool>(),
    ) {
        let n = [1.0, n2, n3];
        let d = 10f64.powf(log_d);
        let theta = theta_deg.to_radians();
        let pol = if p { Pol::P } else { Pol::S };
        let expected = airy_r(n, d, theta, pol);
        let r = traced_r(n, d, theta, pol, DVec3::new(0.0, 0.0, 1e-3));
        // Relative to R, with R floored at 1e-6 of the bare interface (near Brewster's angle
        // R_p → 0 and the relative deviation of a vanishing value means nothing).
        let scale = expected.max(1e-6);
        let err = (r - expected).abs() / scale;
        let tol = tol(n, d, theta, pol);
        prop_assert!(err <= tol, "d {d:e} m, θ {theta_deg}°, {pol:?}: actual {r:e}, expected {expected:e}, err {err:e} > {tol:e}");
    }
}

/// Films at the documented extremes: 1 pm and 1 mm, 0° and 89.9°, s and p.
#[test]
fn one_picometre_film_is_a_film_at_every_angle() {
    let n = [1.0, 1.5, 1.33];
    for d in [1e-12, 1e-11, 1e-3] {
        for theta_deg in [0.0, 30.0, 60.0, 85.0, 89.9] {
            for pol in [Pol::S, Pol::P] {
                let theta = f64::to_radians(theta_deg);
                let expected = airy_r(n, d, theta, pol);
                let r = traced_r(n, d, theta, pol, DVec3::new(0.0, 0.0, 1e-3));
                let err = (r - expected).abs() / expected;
                let tol = tol(n, d, theta, pol);
                assert!(
                    err <= tol,
                    "d {d:e} m, θ {theta_deg}°, {pol:?}: actual {r:e}, expected {expected:e}, err {err:e} > {tol:e}"
                );
            }
        }
    }
}

/// R goes to the bare 1 | n3 interface continuously as d → 0: R(d) − R(0) follows the Airy
/// difference at every d down to 1 pm (a vanishing film would give R(0) − R(0) = 0 at 1 pm, or
/// the air–glass value 0.04 as it did).
#[test]
fn reflectance_tends_to_the_bare_interface_as_the_film_vanishes() {
    let n = [1.0, 1.5, 1.33];
    let theta = 0.5;
    let bare = airy_r([1.0, 1.33, 1.33], 0.0, theta, Pol::S);
    let mut last_gap = f64::INFINITY;
    for d in [1e-9, 1e-10, 1e-11, 1e-12] {
        let traced = traced_r(n, d, theta, Pol::S, DVec3::new(0.0, 0.0, 1e-3)) - bare;
        let expected = airy_r(n, d, theta, Pol::S) - bare;
        let err = (traced - expected).abs() / expected.abs();
        // 1e-6 plus the traced R's own rounding, 16ε·R (~20 beams summed), relative to the
        // gap: at 1 pm the gap is 1.7e-11 and the traced R is 5e-17 off a 50-digit Airy sum
        // (the Stokes-form closed form 2e-18), so rounding alone is 3e-6 of the gap.
        let tol = 1e-6 + 16.0 * f64::EPSILON * bare / expected.abs();
        assert!(
            err <= tol,
            "d {d:e}: R − R_bare actual {traced:e}, expected {expected:e}, err {err:e} > {tol:e}"
        );
        assert!(expected.abs() < last_gap, "the gap shrinks with d");
        last_gap = expected.abs();
    }
    // The 1 pm gap is O(d/λ), four orders below the 1 nm one.
    assert!(last_gap < 1e-5);
}

/// The film scene rotated by `rot` about the origin (top face through `top`): the plane wave,
/// the reference point and the far-field direction turn with it.
fn rotated_film_r(rot: DQuat, top: DVec3, theta: f64, d: f64) -> f64 {
    let n = [1.0, 1.5168, 1.0];
    let mut scene = Scene::new(Medium::constant("air", n[0]));
    let normal = rot * DVec3::Z;
    scene.add_plate(
        "film",
        top,
        normal,
        d,
        Medium::constant("air", n[0]),
        Medium::constant("glass", n[1]),
        Medium::constant("air", n[2]),
    );
    let d_in = rot * DVec3::new(theta.sin(), 0.0, -theta.cos());
    let reference = top + rot * DVec3::new(0.0, 0.0, 1e-3);
    scene.sources.push(Source {
        name: "beam".into(),
        emitter: Emitter::PlaneWave {
            direction: d_in,
            reference_point: reference,
        },
        polarization: Polarization::Linear {
            reference: rot * DVec3::Y,
            angle_rad: 0.0,
        },
        intensity: 1.0,
        coherence_group: 0,
        coherence_length_m: f64::INFINITY,
    });
    let optics = scene.optics(LAMBDA).unwrap();
    let dir = rot * DVec3::new(theta.sin(), 0.0, theta.cos());
    let film = Film {
        n1: n[0],
        n2: n[1],
        n3: n[2],
        thickness_m: d,
    };
    let internal = internal_for(&film, theta);
    let limits = EnumerationLimits {
        max_internal_reflections: internal,
        max_events: 2 * internal + 4,
    };
    let plan = trace::plan(&scene, &optics, &[reference], &limits);
    let st = TraceSettings {
        limits,
        ..Default::default()
    };
    let (arr, _) = trace::arrivals(
        &scene,
        &optics,
        &plan,
        &Target::Direction { dir, reference },
        &st,
    );
    trace::intensity(&arr, Fidelity::Vector)
}

/// (b) Rotations of the whole scene by any angle about the plate's top point: invariant to
/// 1e-12 relative; so are translations of an untilted plate along its faces. Tilted plates
/// off the origin: an f64 point at distance D from the origin sits only within ~ulp(D) of a
/// tilted plane, a first-order path error (~2 n cos θ δ) that made R 8.6e-12 off at 1 m and
/// 1.5e-8 at 1000 m. The bottom face is now held as top point − thickness along the normal
/// (`Plane::offset`) and every event moves its point's path back onto the plane to first order
/// (`Plane::off_plane_path_correction`): 1e-12 at 1 m and 1000 m (measured ~2e-15, printed),
/// and measured (printed, not asserted) at 1e5 m, where ulp(D) = 1.5e-11 m.
#[test]
fn rotations_change_nothing_and_translations_are_measured() {
    let (theta, d) = (80f64.to_radians(), 3.217e-6);
    let expected = airy_r([1.0, 1.5168, 1.0], d, theta, Pol::S);
    let mut rng = 0x2545_f491_4f6c_dd1du64;
    let mut unit = || {
        rng ^= rng << 13;
        rng ^= rng >> 7;
        rng ^= rng << 17;
        (rng >> 11) as f64 / (1u64 << 53) as f64
    };
    for _ in 0..16 {
        let axis = DVec3::new(unit() - 0.5, unit() - 0.5, unit() - 0.5).normalize();
        let rot = DQuat::from_axis_angle(axis, std::f64::consts::TAU * unit());
        let r = rotated_film_r(rot, DVec3::ZERO, theta, d);
        let err = (r - expected).abs() / expected;
        assert!(
            err <= 1e-12,
            "rotation {rot:?}: actual {r:e}, expected {expected:e}, err {err:e}"
        );
    }
    // Translations in the plane of an untilted plate keep every point exactly on its plane.
    for shift in [DVec3::new(1.0, 0.0, 0.0), DVec3::new(-0.37, 0.83, 0.0)] {
        let r = rotated_film_r(DQuat::IDENTITY, shift, theta, d);
        let err = (r - expected).abs() / expected;
        assert!(
            err <= 1e-12,
            "shift {shift:?}: actual {r:e}, expected {expected:e}, err {err:e}"
        );
    }
    // A tilted plate 1 m, 1000 m and 1e5 m from the origin (the last measured only).
    for (distance, pinned) in [(1.0, 1e-12), (1000.0, 1e-12), (1e5, f64::INFINITY)] {
        let mut worst = 0.0f64;
        for _ in 0..8 {
            let axis = DVec3::new(unit() - 0.5, unit() - 0.5, unit() - 0.5).normalize();
            let rot = DQuat::from_axis_angle(axis, std::f64::consts::TAU * unit());
            let top = distance * DVec3::new(unit() - 0.5, unit() - 0.5, unit() - 0.5).normalize();
            let r = rotated_film_r(rot, top, theta, d);
            worst = worst.max((r - expected).abs() / expected);
        }
        eprintln!(
            "tilted 3.217 µm plate {distance} m from the origin: worst relative deviation {worst:e}"
        );
        assert!(
            worst <= pinned,
            "the f64 limit grew at {distance} m: {worst:e}"
        );
    }
}

fn rect(size: f64) -> Rect {
    Rect {
        center_uv: [0.0, 0.0],
        half_width_m: size / 2.0,
        half_height_m: size / 2.0,
    }
}

/// A Michelson with a 50 % splitter at the origin (normal (−1, 0, 1)/√2), mirror 1 at z = l1,
/// mirror 2 at x = l2, a y-polarized unit point source at (−2 cm, 0, 0) behind a pinhole
/// screen, observed on the axis at (0, 0, −6 cm).
fn michelson_intensity(l1: f64, l2: f64) -> f64 {
    let air = Medium::constant("air", 1.0);
    let mut scene = Scene::new(air.clone());
    let coherence = CoherenceRules::default();
    let bounded = |point: DVec3, normal: DVec3, u_hint: DVec3, size: f64, kind| {
        let plane = Plane::new(point, normal);
        let (u, v) = plane.axes(u_hint);
        Surface {
            name: "s".into(),
            plane,
            extent: Extent::Rect {
                u,
                v,
                rect: rect(size),
            },
            kind,
        }
    };
    scene.surfaces.push(bounded(
        DVec3::ZERO,
        DVec3::new(-1.0, 0.0, 1.0),
        DVec3::new(1.0, 0.0, 1.0),
        0.04,
        SurfaceKind::Splitter {
            reflectance: 0.5,
            medium: air.clone(),
            coherence,
        },
    ));
    scene.surfaces.push(bounded(
        DVec3::new(0.0, 0.0, l1),
        -DVec3::Z,
        DVec3::X,
        0.04,
        SurfaceKind::IdealMirror { coherence },
    ));
    scene.surfaces.push(bounded(
        DVec3::new(l2, 0.0, 0.0),
        -DVec3::X,
        DVec3::Z,
        0.04,
        SurfaceKind::IdealMirror { coherence },
    ));
    let screen = Plane::new(DVec3::new(-0.018, 0.0, 0.0), DVec3::X);
    // Unbounded: nothing passes beside the pinhole, however long the arms.
    scene.surfaces.push(Surface {
        name: "pinhole".into(),
        plane: screen,
        extent: Extent::Unbounded,
        kind: SurfaceKind::Opaque {
            apertures: vec![rect(0.001)],
        },
    });
    scene.sources.push(Source {
        name: "lamp".into(),
        emitter: Emitter::Point {
            position: DVec3::new(-0.02, 0.0, 0.0),
        },
        polarization: Polarization::Linear {
            reference: DVec3::Y,
            angle_rad: 0.0,
        },
        intensity: 1.0,
        coherence_group: 0,
        coherence_length_m: f64::INFINITY,
    });
    let optics = scene.optics(LAMBDA).unwrap();
    let p = DVec3::new(0.0, 0.0, -0.06);
    let limits = EnumerationLimits {
        max_internal_reflections: 0,
        max_events: 4,
    };
    let plan = trace::plan(&scene, &optics, &[p], &limits);
    let (arr, _) = trace::arrivals(
        &scene,
        &optics,
        &plan,
        &Target::Point(p),
        &TraceSettings::default(),
    );
    let seqs: Vec<String> = arr
        .iter()
        .map(|a| fringe::trace::path::sequence_label(a.path.sequence.iter()))
        .collect();
    assert_eq!(arr.len(), 2, "two arms reach the axis point: {seqs:?}");
    trace::intensity(&arr, Fidelity::Vector)
}

/// (c) Michelson arms from 2 cm to 10 m with the same arm difference ΔL: on the axis the two
/// beams are y-polarized with amplitudes ±½ (splitter −√R from the front, +√R from the back,
/// mirrors −1, √(1−R) in transmission), so I = ½(1 − cos(4πΔL/λ)) whatever the arm length.
#[test]
fn michelson_arms_up_to_10_m_change_nothing() {
    // ΔL a power of two, exact in f64 beside every arm length used.
    for delta in [2f64.powi(-23), 2f64.powi(-22), 3.0 * 2f64.powi(-22)] {
        let expected = 0.5 * (1.0 - (4.0 * std::f64::consts::PI * delta / LAMBDA).cos());
        for l in [0.02, 0.5, 1.0, 4.0, 10.0] {
            let i = michelson_intensity(l, l + delta);
            let err = (i - expected).abs() / expected;
            assert!(
                err <= 1e-12,
                "arms {l} m and {l} m + {delta:e}: actual {i:e}, expected {expected:e}, err {err:e}"
            );
        }
    }
}

/// Young's slits (paper §4.1: λ = 550 nm, d = 500λ, l = 1000d), two coherent line sources
/// along z polarized along z (parallel fields, spreading off): I = 2 + 2 cos δ with the path
/// difference in the cancellation-free form r1 − r2 = (r1² − r2²)/(r1 + r2) = −2yd/(r1 + r2)
/// (relative error ~1e-16, unlike r1 − r2 of two rounded 0.275 m distances, ~6e-10 rad).
/// Traced to 1e-12 of the peak across ±5 fringes.
#[test]
fn young_fringes_match_the_cancellation_free_path_difference() {
    let d = 500.0 * LAMBDA;
    let l = 1000.0 * d;
    let mut scene = Scene::new(Medium::vacuum());
    for (k, y) in [0.5 * d, -0.5 * d].into_iter().enumerate() {
        scene.sources.push(Source {
            name: format!("slit{k}"),
            emitter: Emitter::Line {
                point: DVec3::new(0.0, y, 0.0),
                axis: DVec3::Z,
            },
            polarization: Polarization::Linear {
                reference: DVec3::Z,
                angle_rad: 0.0,
            },
            intensity: 1.0,
            coherence_group: 0,
            coherence_length_m: f64::INFINITY,
        });
    }
    let optics = scene.optics(LAMBDA).unwrap();
    let spacing = LAMBDA * l / d;
    for k in 0..=80 {
        let y = (k as f64 - 40.0) * spacing / 8.0 + 1e-7;
        let p = DVec3::new(l, y, 0.0);
        let plan = trace::plan(&scene, &optics, &[p], &EnumerationLimits::default());
        let (arr, _) = trace::arrivals(
            &scene,
            &optics,
            &plan,
            &Target::Point(p),
            &TraceSettings::default(),
        );
        assert_eq!(arr.len(), 2);
        let traced = trace::intensity(&arr, Fidelity::Vector);
        let (r1, r2) = ((y - 0.5 * d).hypot(l), (y + 0.5 * d).hypot(l));
        let delta = std::f64::consts::TAU * (-2.0 * y * d / (r1 + r2)) / LAMBDA;
        let expected = 2.0 + 2.0 * delta.cos();
        let err = (traced - expected).abs() / 4.0;
        assert!(
            err <= 1e-12,
            "y = {y:e} m: actual {traced:e}, expected {expected:e}, err {err:e} of the peak"
        );
    }
}
