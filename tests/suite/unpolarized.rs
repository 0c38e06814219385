//! Issue #13 item 3: unpolarized point sources without a basis. The default `Unpolarized`
//! source is three incoherent dipole channels along x, y, z of weight ½ (docs/PHYSICS.md §3):
//! the fields it sends along k1 and k2 are correlated as (I − k1k1ᵀ)(I − k2k2ᵀ)/2, which no
//! choice of axes changes. Expected values are independent: the projector product built from
//! matrices, the two-beam plate's closed form for basis-free light
//! (`TwoBeamPlate::intensity_unpolarized_basis_free`, its own 1-D geometry and Fresnel
//! kernels), and the same scene traced in a rotated frame.

use fringe::accumulate::fidelity::Fidelity;
use fringe::harness::analytic::plate::TwoBeamPlate;
use fringe::optics::material::Medium;
use fringe::scene::Scene;
use fringe::scene::source::{Channel, ChannelField, Emitter, Polarization, Source};
use fringe::trace::path::{EnumerationLimits, Target};
use fringe::trace::{self, Arrival, TraceSettings};
use glam::{DMat3, DQuat, DVec3};
use proptest::prelude::*;
use std::sync::Arc;

const LAMBDA: f64 = 550e-9;
/// The paper's amplitude-division scene (Fig. 4 left): n = 1.5, 50 µm, source 1 cm and
/// observation plane 2 cm above the plate.
const N_GLASS: f64 = 1.5;
const THICKNESS: f64 = 50e-6;
const H_SRC: f64 = 0.01;
const H_OBS: f64 = 0.02;

fn unit_vector(a: f64, b: f64) -> DVec3 {
    // Uniform on the sphere from two numbers in [0, 1).
    let z = 2.0 * a - 1.0;
    let r = (1.0 - z * z).max(0.0).sqrt();
    let phi = std::f64::consts::TAU * b;
    DVec3::new(r * phi.cos(), r * phi.sin(), z)
}

fn outer(a: DVec3, b: DVec3) -> DMat3 {
    DMat3::from_cols(a * b.x, a * b.y, a * b.z)
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(256))]

    /// Σ over the channels of (I/2)·e_a(k1) e_a(k2)ᵀ equals (I − k1k1ᵀ)(I − k2k2ᵀ)/2 for unit
    /// intensity, entry by entry, for any two directions; and each direction gets |E|² = 1
    /// (to a few ulps: each entry is a sum of three products of O(1) numbers).
    #[test]
    fn three_dipoles_correlate_as_the_product_of_transverse_projectors(
        a1 in 0.0..1.0f64, b1 in 0.0..1.0f64, a2 in 0.0..1.0f64, b2 in 0.0..1.0f64,
    ) {
        let (k1, k2) = (unit_vector(a1, b1), unit_vector(a2, b2));
        let src = point_source(DVec3::ZERO, Polarization::Unpolarized);
        let channels = src.channels();
        prop_assert_eq!(channels.len(), 3);
        let mut corr = DMat3::ZERO;
        let mut power1 = 0.0;
        for ch in &channels {
            let (e1, e2) = (ch.launch_field(k1), ch.launch_field(k2));
            corr += outer(e1, e2) * ch.intensity;
            power1 += ch.intensity * e1.length_squared();
        }
        let projector = |k: DVec3| DMat3::IDENTITY - outer(k, k);
        let expected = projector(k1) * projector(k2) * 0.5;
        for (c, (x, y)) in corr
            .to_cols_array()
            .iter()
            .zip(expected.to_cols_array())
            .enumerate()
        {
            prop_assert!(
                (x - y).abs() <= 1e-15,
                "entry {}: actual {:e}, expected {:e}, err {:e}", c, x, y, (x - y).abs()
            );
        }
        prop_assert!((power1 - 1.0).abs() <= 1e-15, "|E|² along k1: actual {:e}, expected 1", power1);
    }
}

/// The paper's two channels correlate as the projector product only for special directions:
/// off the plane containing the reference, the correlation of k1 and k2 misses it by O(angle²).
#[test]
fn the_paper_model_depends_on_its_reference() {
    let k1 = DVec3::new(0.3, 0.2, 1.0).normalize();
    let k2 = DVec3::new(-0.1, 0.25, 1.0).normalize();
    let correlation = |pol| {
        let mut corr = DMat3::ZERO;
        for ch in point_source(DVec3::ZERO, pol).channels() {
            corr += outer(ch.launch_field(k1), ch.launch_field(k2)) * ch.intensity;
        }
        corr
    };
    let a = correlation(Polarization::UnpolarizedTwoChannel {
        reference: DVec3::Y,
    });
    let b = correlation(Polarization::UnpolarizedTwoChannel {
        reference: DVec3::X,
    });
    let free = correlation(Polarization::Unpolarized);
    let trace_of = |m: DMat3| m.x_axis.x + m.y_axis.y + m.z_axis.z;
    let (ta, tb, tf) = (trace_of(a), trace_of(b), trace_of(free));
    // The coherent term of two beams is the trace; the three-channel value is tr(P1P2)/2.
    let expected = 0.5 * (1.0 + k1.dot(k2).powi(2));
    assert!(
        (tf - expected).abs() <= 1e-15,
        "basis-free: actual {tf:e}, expected {expected:e}"
    );
    assert!(
        (ta - tb).abs() > 1e-4,
        "the two-channel model should depend on its reference here: {ta:e} vs {tb:e}"
    );
}

fn point_source(position: DVec3, polarization: Polarization) -> Source {
    Source {
        name: "lamp".into(),
        emitter: Emitter::Point { position },
        polarization,
        intensity: 1.0,
        coherence_group: 0,
        coherence_length_m: f64::INFINITY,
    }
}

/// The two-beam plate scene rotated by `rot` about the plate's top point (the origin).
fn plate_scene(rot: DQuat, polarization: Polarization) -> Scene {
    let mut scene = Scene::new(Medium::vacuum());
    scene.add_plate(
        "plate",
        DVec3::ZERO,
        rot * DVec3::Z,
        THICKNESS,
        Medium::vacuum(),
        Medium::constant("glass", N_GLASS),
        Medium::vacuum(),
    );
    scene.sources.push(point_source(
        rot * DVec3::new(0.0, 0.0, H_SRC),
        polarization,
    ));
    scene
}

/// The arrivals at `p` of the top reflection and the beam with one internal reflection (the
/// direct light left out, as the paper's shield does).
fn two_beams(scene: &Scene, p: DVec3) -> Vec<Arrival> {
    let optics = scene.optics(LAMBDA).unwrap();
    let limits = EnumerationLimits {
        max_internal_reflections: 1,
        max_events: 3,
    };
    let plan = trace::plan(scene, &optics, &[p], &limits);
    let st = TraceSettings {
        limits,
        ..Default::default()
    };
    let (arr, _) = trace::arrivals(scene, &optics, &plan, &Target::Point(p), &st);
    let arr: Vec<Arrival> = arr
        .into_iter()
        .filter(|a| !a.path.sequence.is_empty())
        .collect();
    let paths = arr.len() / scene.sources[0].channels().len();
    assert_eq!(paths, 2, "two beams reach {p:?}");
    arr
}

/// Observation points in the plane 2 cm above the plate, lateral distance `x` from below the
/// source, at azimuths off the x–z plane.
fn probes() -> Vec<DVec3> {
    let mut v = Vec::new();
    for (x, azimuth_deg) in [
        (0.004, 37.0),
        (0.011, 71.0),
        (0.02, 115.0),
        (0.03, 200.0),
        (0.045, 300.0),
    ] {
        let az: f64 = f64::to_radians(azimuth_deg);
        v.push(DVec3::new(x * az.cos(), x * az.sin(), H_OBS));
    }
    v
}

fn closed_form() -> TwoBeamPlate {
    TwoBeamPlate {
        n1: 1.0,
        n2: N_GLASS,
        thickness_m: THICKNESS,
        h_src_m: H_SRC,
        h_obs_m: H_OBS,
    }
}

/// Basis-free light on the plate matches its closed form at points off every coordinate plane
/// (the closed form needs no plane of incidence: the scene is symmetric about the normal
/// through the source), where the paper's channels built from `reference` = y mix s and p.
/// Also measures the paper model's error there (printed; the README quotes it).
#[test]
fn basis_free_light_on_a_plate_matches_its_closed_form_off_the_plane_of_incidence() {
    let free = plate_scene(DQuat::IDENTITY, Polarization::Unpolarized);
    let paper = plate_scene(
        DQuat::IDENTITY,
        Polarization::UnpolarizedTwoChannel {
            reference: DVec3::Y,
        },
    );
    let cf = closed_form();
    let mut worst_paper = 0.0f64;
    for p in probes() {
        let x = (p.x * p.x + p.y * p.y).sqrt();
        let expected = cf.intensity_unpolarized_basis_free(x, LAMBDA);
        let i = trace::intensity(&two_beams(&free, p), Fidelity::Vector);
        let err = (i - expected).abs() / expected;
        assert!(
            err <= 1e-12,
            "at {p:?}: actual {i:e}, expected {expected:e}, err {err:e}"
        );
        let ip = trace::intensity(&two_beams(&paper, p), Fidelity::Vector);
        worst_paper = worst_paper.max((ip - expected).abs() / expected);
    }
    eprintln!(
        "two-beam plate (n 1.5, 50 µm, source 1 cm, screen 2 cm): paper two-channel model \
         (reference y) vs basis-free, worst relative difference {worst_paper:e}"
    );
}

/// Rotating the whole scene (plate, source and probe) while the dipoles stay along x, y, z
/// leaves basis-free intensities unchanged: the three dipoles are a basis of the scene frame,
/// so this is rotating the basis. Deviations are relative to the largest intensity of the
/// probes (the case library's measure): ≤ 1e-12 for rotations about the plate normal (every hit
/// point exactly on its plane) and for rotations that tilt the plate (hit points ~1 ulp off
/// their planes, moved back onto them to first order, `Plane::off_plane_path_correction`;
/// the worst is printed).
#[test]
fn basis_free_light_is_invariant_under_rotating_the_scene() {
    let mut rng = 0x9e37_79b9_7f4a_7c15u64;
    let mut uniform = || {
        rng ^= rng << 13;
        rng ^= rng >> 7;
        rng ^= rng << 17;
        (rng >> 11) as f64 / (1u64 << 53) as f64
    };
    let unrotated = plate_scene(DQuat::IDENTITY, Polarization::Unpolarized);
    let expected: Vec<f64> = probes()
        .iter()
        .map(|&p| trace::intensity(&two_beams(&unrotated, p), Fidelity::Vector))
        .collect();
    // Deviations relative to the profile's largest intensity, as the case library measures.
    let peak = expected.iter().cloned().fold(0.0, f64::max);
    let mut worst_tilted = 0.0f64;
    for k in 0..16 {
        let about_normal = k % 2 == 0;
        let axis = if about_normal {
            DVec3::Z
        } else {
            unit_vector(uniform(), uniform())
        };
        let rot = DQuat::from_axis_angle(axis, std::f64::consts::TAU * uniform());
        let scene = plate_scene(rot, Polarization::Unpolarized);
        for (p, &e) in probes().iter().zip(&expected) {
            let i = trace::intensity(&two_beams(&scene, rot * *p), Fidelity::Vector);
            let err = (i - e).abs() / peak;
            assert!(
                err <= 1e-12,
                "rotation {rot:?}, probe {p:?}: actual {i:e}, expected {e:e}, err {err:e}"
            );
            if !about_normal {
                worst_tilted = worst_tilted.max(err);
            }
        }
    }
    eprintln!(
        "basis-free two-beam plate rotated so that the plate tilts: worst relative deviation \
         {worst_tilted:e}"
    );
}

/// The three dipoles may be any orthonormal triad: the same solved paths carried with a
/// randomly rotated triad give the same intensity to 1e-12 (the basis-free model's "former
/// reference" is the triad, and it does not matter), whereas the paper's channels change with
/// their reference (measured and printed).
#[test]
fn basis_free_light_does_not_depend_on_the_dipole_axes() {
    let scene = plate_scene(DQuat::IDENTITY, Polarization::Unpolarized);
    let optics = scene.optics(LAMBDA).unwrap();
    let mut rng = 0x2545_f491_4f6c_dd1du64;
    let mut uniform = || {
        rng ^= rng << 13;
        rng ^= rng >> 7;
        rng ^= rng << 17;
        (rng >> 11) as f64 / (1u64 << 53) as f64
    };
    let carried = |arr: &[Arrival], channels: &[Channel], p: DVec3| {
        let mut out = Vec::new();
        let mut seen: Vec<*const fringe::trace::path::SolvedPath> = Vec::new();
        for a in arr {
            if seen.contains(&Arc::as_ptr(&a.path)) {
                continue;
            }
            seen.push(Arc::as_ptr(&a.path));
            trace::propagate_channels(
                &scene,
                &optics,
                channels,
                f64::INFINITY,
                &a.path,
                &Target::Point(p),
                fringe::optics::interaction::CoefficientModel::Vector,
                |k, ray| {
                    out.push(Arrival {
                        source: 0,
                        channel: channels[k],
                        path: a.path.clone(),
                        vector: ray,
                        paper: None,
                        tail: None,
                    })
                },
            );
        }
        trace::intensity(&out, Fidelity::Vector)
    };
    let mut worst_paper = 0.0f64;
    for p in probes() {
        let arr = two_beams(&scene, p);
        let expected = trace::intensity(&arr, Fidelity::Vector);
        for _ in 0..6 {
            let rot = DQuat::from_axis_angle(
                unit_vector(uniform(), uniform()),
                std::f64::consts::TAU * uniform(),
            );
            let triad: Vec<Channel> = [DVec3::X, DVec3::Y, DVec3::Z]
                .into_iter()
                .zip(1..)
                .map(|(a, id)| Channel {
                    coherence_id: id,
                    intensity: 0.5,
                    field: ChannelField::Dipole { axis: rot * a },
                })
                .collect();
            let i = carried(&arr, &triad, p);
            let err = (i - expected).abs() / expected;
            assert!(
                err <= 1e-12,
                "triad {rot:?} at {p:?}: actual {i:e}, expected {expected:e}, err {err:e}"
            );
            // The paper's two channels from a random reference, on the same paths.
            let reference = unit_vector(uniform(), uniform());
            let paper = point_source(
                DVec3::ZERO,
                Polarization::UnpolarizedTwoChannel { reference },
            )
            .channels();
            let ip = carried(&arr, &paper, p);
            worst_paper = worst_paper.max((ip - expected).abs() / expected);
        }
    }
    eprintln!(
        "two-beam plate off the plane of incidence: paper two-channel model with random \
         references vs basis-free, worst relative difference {worst_paper:e}"
    );
}

/// The case format: `{"unpolarized": {}}` is basis-free; a reference belongs to the paper's
/// model only, and that model needs one. Each misuse is refused at its JSON path, naming the fix.
#[test]
fn the_case_format_names_the_unpolarized_model_and_refuses_misuse() {
    use fringe::harness::case::load;
    let root = std::path::PathBuf::from(env!("CARGO_MANIFEST_DIR"));
    let path = root.join("cases/michelson.json");
    let text = std::fs::read_to_string(&path).unwrap();
    let mut doc: serde_json::Value = serde_json::from_str(&text).unwrap();
    let pol = "/scene/sources/0/polarization";
    let with = |doc: &mut serde_json::Value, v: serde_json::Value| {
        *doc.pointer_mut(pol).unwrap() = v;
        load::parse(&path, &doc.to_string())
    };
    let case = with(&mut doc, serde_json::json!({"unpolarized": {}})).unwrap();
    let built =
        fringe::harness::case::build::build_scene(&case.spec.scene, &Default::default()).unwrap();
    assert_eq!(
        built.scene.sources[0].polarization,
        Polarization::Unpolarized
    );
    let case = with(
        &mut doc,
        serde_json::json!({"unpolarized": {"model": "paper_two_channel", "reference": [0, 2, 0]}}),
    )
    .unwrap();
    let built =
        fringe::harness::case::build::build_scene(&case.spec.scene, &Default::default()).unwrap();
    assert_eq!(
        built.scene.sources[0].polarization,
        Polarization::UnpolarizedTwoChannel {
            reference: DVec3::Y
        }
    );
    for (v, needle) in [
        (
            serde_json::json!({"unpolarized": {"reference": [0, 1, 0]}}),
            "paper_two_channel",
        ),
        (
            serde_json::json!({"unpolarized": {"model": "basis_free", "reference": [0, 1, 0]}}),
            "takes no reference",
        ),
        (
            serde_json::json!({"unpolarized": {"model": "paper_two_channel"}}),
            "reference direction",
        ),
    ] {
        let e = with(&mut doc, v.clone()).expect_err(&format!("{v} must be refused"));
        let shown = e.to_string();
        assert!(
            shown.contains("scene.sources[0].polarization.unpolarized.reference")
                && shown.contains(needle)
                && shown.contains("michelson.json"),
            "{v}: {shown}"
        );
    }
}

/// Young's slits (the paper's §4.1: λ = 550 nm, d = 500λ, l = 1000d) lit by basis-free
/// unpolarized light: the traced intensity equals 2 + (1 + cos²α) cos δ
/// (`young::exact_line_sources_basis_free`, double-double distances) to 1e-12 of the peak, and
/// the paper's two channels along and across the slits equal 2 + (1 + cos α) cos δ; the two
/// closed forms differ by α²/2-sized amounts the comparison resolves.
#[test]
fn young_slits_with_basis_free_light_match_their_closed_form() {
    use fringe::harness::analytic::young;
    let d = 500.0 * LAMBDA;
    let l = 1000.0 * d;
    let (s1, s2) = (
        DVec3::new(0.0, d / 2.0, 0.0),
        DVec3::new(0.0, -d / 2.0, 0.0),
    );
    let scene_with = |polarization: Polarization| {
        let mut scene = Scene::new(Medium::vacuum());
        for (k, s) in [s1, s2].into_iter().enumerate() {
            scene.sources.push(Source {
                name: format!("slit{k}"),
                emitter: Emitter::Line {
                    point: s,
                    axis: DVec3::Z,
                },
                polarization,
                intensity: 1.0,
                coherence_group: 0,
                coherence_length_m: f64::INFINITY,
            });
        }
        scene
    };
    let traced = |scene: &Scene, p: DVec3| {
        let optics = scene.optics(LAMBDA).unwrap();
        let limits = EnumerationLimits::default();
        let plan = trace::plan(scene, &optics, &[p], &limits);
        let (arr, _) = trace::arrivals(
            scene,
            &optics,
            &plan,
            &Target::Point(p),
            &TraceSettings::default(),
        );
        trace::intensity(&arr, Fidelity::Vector)
    };
    let free = scene_with(Polarization::Unpolarized);
    let paper = scene_with(Polarization::UnpolarizedTwoChannel {
        reference: DVec3::Z,
    });
    let peak = 4.0;
    let mut apart = 0.0f64;
    // Points across ±40 fringes (spacing λl/d = 1000λ), off the z = 0 plane too.
    for k in 0..41 {
        let y = (k as f64 - 20.0) * 2000.0 * LAMBDA + 0.123 * LAMBDA * k as f64;
        let p = DVec3::new(l, y, 0.37 * l * (k % 3) as f64);
        let e_free = young::exact_line_sources_basis_free(s1, s2, DVec3::Z, p, LAMBDA, 1.0);
        let e_paper = young::exact_line_sources(s1, s2, DVec3::Z, p, LAMBDA, 1.0, 0.5);
        apart = apart.max((e_free - e_paper).abs() / peak);
        for (scene, e, what) in [(&free, e_free, "basis-free"), (&paper, e_paper, "paper")] {
            let i = traced(scene, p);
            let err = (i - e).abs() / peak;
            assert!(
                err <= 1e-12,
                "{what} at y = {y:e}: actual {i:e}, expected {e:e}, err {err:e}"
            );
        }
    }
    eprintln!(
        "Young (paper geometry): paper two-channel vs basis-free closed forms differ by up to {apart:e} of the peak"
    );
    assert!(
        apart > 1e-8,
        "the comparison must resolve the two models: they differ by {apart:e}"
    );
}
