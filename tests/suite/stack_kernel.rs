//! The parallel-stack pixel kernel (`fringe::output::stack_kernel`) against the exact trace it
//! replaces: the same picture rendered both ways (`render::render_with`, `PixelPath::Auto`
//! against `PixelPath::Exact`) agrees in its linear values (XYZ, or intensity) to 1e-10 of the
//! picture's peak at every shading (the five rungs of the ladder and the paper's one scalar ray
//! per path), on the figures' plate and on random stacks of the class, and scenes or pixels
//! outside the kernel's class are traced exactly.
//!
//! The scalar rungs carry √I of the same exact intensity and the half-cycle jumps the path
//! solver counts, `paper_rules` the same frames with the paper's coefficients: their
//! deviations have the `vector` rung's sources (below), and the `scalar_jump` phases differ from
//! the exact trace's by whole cycles and the ~1e-15 cycles of its double-double reduction.
//!
//! The tolerance: both sides carry the same fields through the same Fresnel coefficients; the
//! kernel's Snell invariant p is an f64 root (a few ulp), which moves fields by ~1e-15 of
//! their size, and its path differences Δ are formed without cancelling the two paths (module
//! docs of `stack_kernel`), ~1e-16 of |Δ| + |Δp|·D ≲ 1e-20 m here, a phase of 2π·1e-20/380e-9
//! ≈ 2e-13 rad. The exact trace itself is held to 1e-9 of the 50-digit two-beam formula by
//! this case's reference; 1e-10 of the peak leaves a factor of > 100 over the kernel's own
//! rounding while staying 10× inside the trace's.

use fringe::accumulate::fidelity::Fidelity;
use fringe::colour::{Illuminant, SpectralIntegrator, WavelengthGrid};
use fringe::harness::case::build::GridGeometry;
use fringe::harness::case::load::Case;
use fringe::harness::case::spec::MediumSpec;
use fringe::output::render::{
    self, ImageValues, PixelPath, Render, Request, Screen, Shading, Spectrum,
};
use glam::{DQuat, DVec3};
use proptest::prelude::*;
use serde_json::{Value, json};

const TOLERANCE: f64 = 1e-10;

/// Every shading a picture can have: the ladder's five rungs and the paper's scalar ray.
fn all_shadings() -> Vec<Shading> {
    Fidelity::ALL
        .into_iter()
        .map(Shading::Level)
        .chain([Shading::UnpolarizedScalarJump])
        .collect()
}

fn plate() -> Case {
    fringe::output::figures::plate_case().expect("the plate figure scene is valid")
}

fn white(samples: usize) -> Spectrum {
    Spectrum::White(
        SpectralIntegrator::new(
            &WavelengthGrid::uniform(380e-9, 780e-9, samples).unwrap(),
            Illuminant::D65,
        )
        .unwrap(),
    )
}

fn both(
    case: &Case,
    screen: Screen,
    shadings: Vec<Shading>,
    spectrum: Spectrum,
) -> (Render, Render) {
    auto_and(case, screen, shadings, spectrum, PixelPath::Exact)
}

/// A render by `PixelPath::Auto` and the same render by `other`.
fn auto_and(
    case: &Case,
    screen: Screen,
    shadings: Vec<Shading>,
    spectrum: Spectrum,
    other: PixelPath,
) -> (Render, Render) {
    let req = Request {
        screen,
        shadings,
        spectrum,
        progress: false,
    };
    (
        render::render_with(case, &req, PixelPath::Auto).unwrap(),
        render::render_with(case, &req, other).unwrap(),
    )
}

/// Linear values of every image of a render, flattened (X, Y, Z or I per pixel).
fn linear(r: &Render) -> Vec<f64> {
    r.images
        .iter()
        .flat_map(|im| match &im.values {
            ImageValues::Xyz(v) => v.iter().flat_map(|p| p.to_vec()).collect::<Vec<_>>(),
            ImageValues::Intensity(v) => v.clone(),
        })
        .collect()
}

/// Largest |a − b| over the pictures, relative to the largest |b|.
fn max_deviation(a: &Render, b: &Render) -> f64 {
    let (a, b) = (linear(a), linear(b));
    assert_eq!(a.len(), b.len());
    let peak = b.iter().fold(0.0f64, |m, v| m.max(v.abs()));
    assert!(peak > 0.0, "a black picture");
    a.iter()
        .zip(&b)
        .map(|(x, y)| (x - y).abs())
        .fold(0.0, f64::max)
        / peak
}

#[test]
fn the_kernel_gives_the_exact_trace_of_the_plate_in_white_light() {
    let case = plate();
    let screen = Screen::from_probe(&case.spec.probe, Some((60, 60))).unwrap();
    let (fast, exact) = both(
        &case,
        screen,
        vec![Shading::Level(Fidelity::Vector)],
        white(81),
    );
    assert_eq!(exact.kernel_pixels, 0);
    assert_eq!(
        fast.kernel_pixels, 3600,
        "every pixel of the plate picture is in the class"
    );
    assert_eq!(fast.paths, exact.paths, "the same arrivals");
    let dev = max_deviation(&fast, &exact);
    eprintln!("white 81 λ, 60×60: max |kernel − exact| = {dev:e} of the peak");
    assert!(dev <= TOLERANCE, "deviation {dev:e}");
}

#[test]
fn the_kernel_gives_the_exact_trace_of_the_plate_in_monochrome() {
    let case = plate();
    let screen = Screen::from_probe(&case.spec.probe, Some((60, 60))).unwrap();
    let (fast, exact) = both(
        &case,
        screen,
        vec![
            Shading::Level(Fidelity::Vector),
            Shading::Level(Fidelity::Vector),
        ],
        Spectrum::CaseLight,
    );
    assert_eq!(fast.kernel_pixels, 3600);
    let dev = max_deviation(&fast, &exact);
    eprintln!("monochrome 550 nm, 60×60: max |kernel − exact| = {dev:e} of the peak");
    assert!(dev <= TOLERANCE, "deviation {dev:e}");
}

/// A screen over the source: the pixel straight above it has no plane of incidence, and near
/// it the shield stops the reflected beams (its edge shadow crosses the picture), so those
/// pixels are the exact trace's; the rest agree with it.
#[test]
fn pixels_the_kernel_cannot_vouch_for_are_traced_exactly() {
    let case = plate();
    let screen = Screen {
        geometry: GridGeometry::new(
            DVec3::new(0.0, 0.0, 0.02),
            DVec3::X,
            DVec3::Y,
            [0.006, 0.006],
            [21, 21],
        ),
        looks_toward: Some(DVec3::new(0.0, 0.0, -1.0)),
        strip: false,
    };
    let (fast, exact) = both(
        &case,
        screen,
        vec![Shading::Level(Fidelity::Vector)],
        white(21),
    );
    assert!(
        fast.kernel_pixels < 21 * 21,
        "the pixel above the source went to the exact trace"
    );
    assert!(
        fast.kernel_pixels > 21 * 21 / 2,
        "the kernel served the rest"
    );
    assert_eq!(
        fast.paths, exact.paths,
        "the same arrivals (the shield stops the same beams)"
    );
    let dev = max_deviation(&fast, &exact);
    eprintln!(
        "over the source: {} of 441 pixels by the kernel, max deviation {dev:e}",
        fast.kernel_pixels
    );
    assert!(dev <= TOLERANCE, "deviation {dev:e}");
}

/// Scenes outside the class render exactly as the exact trace does, bit for bit, at every
/// shading.
#[test]
fn scenes_outside_the_class_fall_back_to_the_exact_trace() {
    let plate = plate();
    let mut dispersive = plate.clone();
    dispersive
        .spec
        .scene
        .media
        .insert("glass".into(), MediumSpec::Bk7 {});
    let young = fringe::output::figures::young_case().unwrap();
    let mut spreading = plate.clone();
    spreading.spec.trace.spreading = true;
    let mut young_spreading = young.clone();
    young_spreading.spec.trace.spreading = true;
    let library = |name: &str| {
        fringe::harness::case::load::load(
            &std::path::Path::new(env!("CARGO_MANIFEST_DIR"))
                .join("cases")
                .join(format!("{name}.json")),
        )
        .unwrap()
    };
    // A line source over a mirror (a surface: neither kernel), and point sources in free
    // space (not line sources, and no planes).
    let (lloyd, points) = (library("lloyd_mirror"), library("incoherent_sources"));
    let cases: Vec<(&str, &Case, Vec<Shading>)> = vec![
        // A dispersive medium.
        ("BK7 plate", &dispersive, all_shadings()),
        // Geometric spreading.
        ("plate with spreading", &spreading, all_shadings()),
        ("Young with spreading", &young_spreading, all_shadings()),
        ("Lloyd's mirror", &lloyd, all_shadings()),
        ("point sources in free space", &points, all_shadings()),
    ];
    for (name, case, shadings) in cases {
        let screen = Screen::from_probe(&case.spec.probe, Some((9, 7))).unwrap();
        let (fast, exact) = both(case, screen, shadings, white(9));
        assert_eq!(fast.kernel_pixels, 0, "{name}: no pixel by the kernel");
        assert_eq!(
            linear(&fast),
            linear(&exact),
            "{name}: the exact trace, bit for bit"
        );
    }
}

/// Every shading of the figures' plate (Figs. 5–7 and the vector reference) from the kernel
/// equals the exact trace's, in white light (the beat table's sums) and in monochrome.
#[test]
fn every_rung_of_the_kernel_gives_the_exact_trace_of_the_plate() {
    let case = plate();
    let screen = Screen::from_probe(&case.spec.probe, Some((60, 60))).unwrap();
    for (name, spectrum) in [
        ("white 81", white(81)),
        ("white 9", white(9)),
        ("550 nm", Spectrum::CaseLight),
    ] {
        for sh in all_shadings() {
            let (fast, exact) = both(&case, screen, vec![sh], spectrum.clone());
            assert_eq!(exact.kernel_pixels, 0);
            assert_eq!(fast.kernel_pixels, 3600, "{name} {}", sh.name());
            assert_eq!(fast.paths, exact.paths, "the same arrivals");
            let dev = max_deviation(&fast, &exact);
            eprintln!(
                "{name}, {}: max |kernel − exact| = {dev:e} of the peak",
                sh.name()
            );
            assert!(dev <= TOLERANCE, "{name} {}: deviation {dev:e}", sh.name());
        }
    }
}

/// The figures' plate scene as JSON, changed by `edit`.
fn plate_json(edit: impl FnOnce(&mut Value)) -> Value {
    let mut v: Value = serde_json::from_str(fringe::output::figures::PLATE_SCENE).unwrap();
    edit(&mut v);
    v
}

fn case_of(v: &Value) -> Case {
    fringe::harness::case::load::parse(
        std::path::Path::new("random_stack.json"),
        &serde_json::to_string(v).unwrap(),
    )
    .unwrap_or_else(|e| panic!("{e}: {v}"))
}

use crate::support::draw::Draw;

/// A random scene of the kernel's class and a screen over it: a plate (index 1.2–2.4,
/// 0.3–30 µm) over air, perhaps a substrate interface below it (a second reflecting plane, so
/// up to four events), up to three internal reflections, a point source 3–20 mm above with the
/// paper's two channels, a linear polarization or the basis-free dipoles, perhaps a coherence
/// length among the paths' lengths and perhaps the shield over the source; the whole scene
/// and screen turned by a random rotation (the kernel's frames in general position).
fn random_stack(d: &mut Draw) -> (Case, Screen, String, f64) {
    let rot = DQuat::from_euler(
        glam::EulerRot::ZYX,
        d.range(-3.0, 3.0),
        d.range(-1.5, 1.5),
        d.range(-3.0, 3.0),
    );
    let r = |x: f64, y: f64, z: f64| {
        let v = rot * DVec3::new(x, y, z);
        json!([v.x, v.y, v.z])
    };
    let n_glass = d.range(1.2, 2.4);
    let thick_um = d.range(0.3, 30.0);
    let h = d.range(3e-3, 20e-3);
    let substrate = d
        .chance(0.5)
        .then(|| (d.range(1.1, 2.0), d.range(1e-6, 50e-6)));
    let polarization = match (d.unit() * 3.0) as u32 {
        0 => json!({"unpolarized": {"model": "paper_two_channel",
            "reference": r(d.range(-1.0, 1.0), 1.0, d.range(-1.0, 1.0))}}),
        1 => json!({"linear": {"reference": r(d.range(-1.0, 1.0), 1.0, 0.3),
            "angle_deg": d.range(-90.0, 90.0)}}),
        _ => json!({"unpolarized": {}}),
    };
    let coherence = d.chance(0.3).then(|| d.range(h + 10e-3, 4.0 * h + 0.15));
    let shield = d.chance(0.5);
    let reflections = 1 + (d.unit() * 3.0) as usize;
    let cx = d.range(5e-3, 40e-3);
    let cy = d.range(-20e-3, 20e-3);
    let side = d.range(5e-3, 40e-3);
    let zs = h + d.range(2e-3, 15e-3);
    let v = plate_json(|v| {
        let sc = &mut v["scene"];
        sc["media"]["glass"]["constant"]["n"] = json!(n_glass);
        let plate = &mut sc["surfaces"][0]["plate"];
        plate["thickness_um"] = json!(thick_um);
        plate["top_point_m"] = r(0.0, 0.0, 0.0);
        plate["normal"] = r(0.0, 0.0, 1.0);
        if let Some((n_sub, gap)) = substrate {
            sc["media"]["substrate"] = json!({"constant": {"n": n_sub}});
            let z = -thick_um * 1e-6 - gap;
            sc["surfaces"][0]["plate"]["below"] = json!("air");
            let surfaces = sc["surfaces"].as_array_mut().unwrap();
            surfaces.push(
                json!({"interface": {"name": "substrate", "point_m": r(0.0, 0.0, z),
                "normal": r(0.0, 0.0, 1.0), "front": "air", "back": "substrate"}}),
            );
        }
        if shield {
            let s = &mut sc["surfaces"][1]["shield"];
            s["point_m"] = r(0.0, 0.0, h + 1e-4);
            s["normal"] = r(0.0, 0.0, 1.0);
            s["rect"]["u_axis"] = r(1.0, 0.0, 0.0);
        } else {
            sc["surfaces"].as_array_mut().unwrap().remove(1);
        }
        let src = &mut sc["sources"][0];
        src["emitter"]["point"]["position_m"] = r(0.0, 0.0, h);
        src["polarization"] = polarization;
        if let Some(l) = coherence {
            src["coherence_length_m"] = json!(l);
        }
        let g = &mut v["probe"]["grid"];
        g["center_m"] = r(cx, cy, zs);
        g["u_axis"] = r(1.0, 0.0, 0.0);
        g["v_axis"] = r(0.0, 1.0, 0.0);
        g["size_m"] = json!([side, side]);
        g["looks_toward"] = r(0.0, 0.0, -1.0);
        v["trace"] = json!({"max_internal_reflections": reflections});
    });
    let case = case_of(&v);
    let screen = Screen::from_probe(&case.spec.probe, Some((11, 9))).unwrap();
    let what = format!(
        "n {n_glass:.3}, {thick_um:.2} µm, substrate {substrate:?}, {reflections} internal \
         reflection(s), coherence length {coherence:?}, shield {shield}"
    );
    // The longest optical path of the scene is below `longest` (m): the source's image through
    // the deepest plane to the farthest screen corner, plus 1 mm for the legs inside the plate
    // and the gap (≤ 4 × 30 µm × n / cos θ away from grazing).
    let deepest = -thick_um * 1e-6 - substrate.map_or(0.0, |s| s.1);
    let image = DVec3::new(0.0, 0.0, 2.0 * deepest - h);
    let longest = [(-1.0, -1.0), (-1.0, 1.0), (1.0, -1.0), (1.0, 1.0)]
        .iter()
        .map(|&(a, b)| (DVec3::new(cx + a * side / 2.0, cy + b * side / 2.0, zs) - image).length())
        .fold(0.0, f64::max)
        + 1e-3;
    (case, screen, what, longest)
}

proptest! {
    #![proptest_config(crate::common::config(24))]

    /// Random stacks of the class, every shading at once (one kernel pass feeds them all):
    /// the kernel's picture is the exact trace's to `TOLERANCE` of its peak (or the rounding
    /// bound of the scene's longest path difference, below), with the same arrivals, in white
    /// light (the table's sums and, below 16 samples, the phasors) and in monochrome; a scene
    /// the kernel refuses after all (a tunnelling sequence through the gap above the
    /// substrate) is the exact trace's bit for bit.
    #[test]
    fn random_stacks_at_every_rung_match_the_exact_trace(seed in any::<u64>()) {
        let mut d = Draw(seed);
        let (case, screen, what, longest) = random_stack(&mut d);
        let (spectrum, lambda_min) = match (d.unit() * 3.0) as u32 {
            0 => (white(21), 380e-9),
            1 => (white(7), 380e-9),
            _ => (Spectrum::CaseLight, 550e-9),
        };
        // Without the shield the direct beam meets the reflected ones: path differences of
        // tens of millimetres, 1e5 cycles, whose phase either side holds only to a few
        // roundings of Δ/λ (u = 2^-53): the deviation may reach 2π · 4u · longest/λ of the
        // peak (4e-10 at 60 mm and 380 nm; 4 roundings: the exact trace's rounding of its
        // double-double Δ, the kernel's ~2 of Δ, and Δ/λ), never less than `TOLERANCE`.
        let bound = TOLERANCE.max(std::f64::consts::TAU * 4.0 * (f64::EPSILON / 2.0) * longest / lambda_min);
        let (fast, exact) = both(&case, screen, all_shadings(), spectrum);
        prop_assert_eq!(fast.paths, exact.paths, "the same arrivals");
        if fast.kernel_pixels == 0 {
            // Out of the class after all (e.g. a tunnelling event through the air gap above
            // the substrate): the exact trace, bit for bit.
            prop_assert_eq!(linear(&fast), linear(&exact));
        }
        let dev = max_deviation(&fast, &exact);
        let per_shading: Vec<String> = fast
            .images
            .iter()
            .zip(&exact.images)
            .map(|(a, b)| {
                let one = |im: &fringe::output::render::Image| Render {
                    images: vec![im.clone()],
                    ..exact.clone()
                };
                format!("{} {:.1e}", a.shading.name(), max_deviation(&one(a), &one(b)))
            })
            .collect();
        eprintln!(
            "seed {seed} ({what}): {} of 99 pixels by the kernel, max deviation {dev:e} ({})",
            fast.kernel_pixels,
            per_shading.join(", ")
        );
        prop_assert!(dev <= bound, "deviation {:e} above {:e}", dev, bound);
    }
}

/// Fig. 3's slits through the kernel of line sources without surfaces
/// (`fringe::output::free_kernel`), every shading: the exact trace's picture to `TOLERANCE`
/// of its peak, the same arrivals.
#[test]
fn the_free_kernel_gives_the_exact_trace_of_young() {
    let case = fringe::output::figures::young_case().unwrap();
    let screen = Screen::from_probe(&case.spec.probe, Some((64, 48))).unwrap();
    for (name, spectrum) in [("white 31", white(31)), ("550 nm", Spectrum::CaseLight)] {
        let (fast, exact) = both(&case, screen, all_shadings(), spectrum);
        assert_eq!(fast.kernel_pixels, 64 * 48, "{name}");
        assert_eq!(fast.paths, exact.paths, "the same arrivals");
        let dev = max_deviation(&fast, &exact);
        eprintln!("Young, {name}, every shading: max |kernel − exact| = {dev:e} of the peak");
        assert!(dev <= TOLERANCE, "{name}: deviation {dev:e}");
    }
}

/// Random slits: two or three line sources (random axes, parallel or not, in one or two
/// coherence groups, random polarizations, perhaps a coherence length among the paths'
/// lengths) in air or water, a random screen, the whole turned by a random rotation.
fn random_slits(d: &mut Draw) -> (Case, Screen) {
    let rot = DQuat::from_euler(
        glam::EulerRot::ZYX,
        d.range(-3.0, 3.0),
        d.range(-1.5, 1.5),
        d.range(-3.0, 3.0),
    );
    let r = |v: DVec3| {
        let v = rot * v;
        json!([v.x, v.y, v.z])
    };
    let mut v: Value = serde_json::from_str(fringe::output::figures::YOUNG_SCENE).unwrap();
    let parallel = d.chance(0.5);
    let count = 2 + usize::from(d.chance(0.3));
    let mut sources = Vec::new();
    for k in 0..count {
        let axis = if parallel {
            DVec3::Z
        } else {
            DVec3::new(d.range(-0.3, 0.3), d.range(-0.3, 0.3), 1.0)
        };
        let point = DVec3::new(
            d.range(-1e-3, 1e-3),
            d.range(-1e-3, 1e-3),
            d.range(-1e-3, 1e-3),
        );
        let polarization = match (d.unit() * 3.0) as u32 {
            0 => json!({"unpolarized": {"model": "paper_two_channel",
                "reference": r(DVec3::new(d.range(-1.0, 1.0), d.range(-1.0, 1.0), 1.0))}}),
            1 => json!({"linear": {"reference": r(DVec3::new(d.range(-1.0, 1.0), 1.0, 0.3)),
                "angle_deg": d.range(-90.0, 90.0)}}),
            _ => json!({"unpolarized": {}}),
        };
        let mut src = json!({"name": format!("slit{k}"),
            "emitter": {"line": {"point_m": r(point), "axis": r(axis)}},
            "polarization": polarization,
            "coherence_group": u64::from(d.chance(0.3))});
        if d.chance(0.2) {
            src["coherence_length_m"] = json!(d.range(0.05, 0.3));
        }
        sources.push(src);
    }
    v["scene"]["sources"] = Value::Array(sources);
    if d.chance(0.3) {
        v["scene"]["media"]["water"] = json!({"constant": {"n": 1.33}});
        v["scene"]["ambient"] = json!("water");
    }
    let dist = d.range(0.05, 0.3);
    let side = d.range(1e-3, 2e-2);
    let g = &mut v["probe"]["grid"];
    g["center_m"] = r(DVec3::new(dist, d.range(-5e-3, 5e-3), d.range(-5e-3, 5e-3)));
    g["u_axis"] = r(DVec3::Y);
    g["v_axis"] = r(DVec3::Z);
    g["size_m"] = json!([side, side]);
    if d.chance(0.3) {
        g["looks_toward"] = r(DVec3::new(-1.0, d.range(-0.2, 0.2), 0.0));
    }
    let case = case_of(&v);
    let screen = Screen::from_probe(&case.spec.probe, Some((9, 8))).unwrap();
    (case, screen)
}

proptest! {
    #![proptest_config(crate::common::config(24))]

    /// Random slits of the free kernel's class, every shading at once: the exact trace's
    /// picture to `TOLERANCE` of its peak, with the same arrivals, in white light and in
    /// monochrome.
    #[test]
    fn random_slits_at_every_rung_match_the_exact_trace(seed in any::<u64>()) {
        let mut d = Draw(seed);
        let (case, screen) = random_slits(&mut d);
        let spectrum = if d.chance(0.5) { white(21) } else { Spectrum::CaseLight };
        let (fast, exact) = both(&case, screen, all_shadings(), spectrum);
        prop_assert_eq!(fast.kernel_pixels, 72, "every pixel by the kernel");
        prop_assert_eq!(fast.paths, exact.paths, "the same arrivals");
        let dev = max_deviation(&fast, &exact);
        eprintln!("slits seed {seed}: max deviation {dev:e}");
        prop_assert!(dev <= TOLERANCE, "deviation {:e}", dev);
    }
}

// ---------------------------------------------------------------------------------------------
// The kernel's real arithmetic and direct spectral sums against their complex reference
// ---------------------------------------------------------------------------------------------

/// Below the critical angle between real indices the Fresnel coefficients are real, and
/// `fresnel_real_with_cos2_t` forms them with the very operations num-complex applies to the
/// real parts ((a·d)/(d·d) for a quotient a/(d + 0i)): every coefficient bit for bit the real
/// part of `fresnel_with_cos2_t`'s, whose imaginary part is 0. Indices from nearly equal to a
/// contrast of 4 either way, angles from normal to grazing incidence and up to the critical
/// angle (cos²θt down to 1e-12), cos²θt both from `cos2_theta_t` and as the kernel gives it.
#[test]
fn real_fresnel_is_the_complex_one_bit_for_bit() {
    use fringe::optics::fresnel::{cos2_theta_t, fresnel_real_with_cos2_t, fresnel_with_cos2_t};
    let mut d = Draw(0x5eed_f2e5_04e1);
    let mut checked = 0;
    for k in 0..200_000 {
        let n1 = d.range(1.0, 4.0);
        let n2 = match k % 4 {
            0 => n1 * (1.0 + d.range(-1e-9, 1e-9)),
            1 => d.range(1.0, 4.0),
            2 => n1 * d.range(0.25, 1.0),
            _ => n1 * d.range(1.0, 4.0),
        };
        let cos_i = match k % 3 {
            0 => d.unit(),
            1 => d.range(0.0, 1e-6),
            _ => 1.0 - d.range(0.0, 1e-6),
        };
        let c2t = if k % 2 == 0 {
            cos2_theta_t(n1, n2, cos_i)
        } else {
            // Just above the critical angle's cos²θt = 0, as near as the kernel comes and nearer.
            d.range(1e-12, 1e-5)
        };
        if c2t < 0.0 || n1 == n2 {
            continue;
        }
        let c = fresnel_with_cos2_t(n1, n2, cos_i, c2t);
        let r = fresnel_real_with_cos2_t(n1, n2, cos_i, c2t);
        for (name, z, x) in [
            ("r_s", c.r_s, r[0]),
            ("r_p", c.r_p, r[1]),
            ("t_s", c.t_s, r[2]),
            ("t_p", c.t_p, r[3]),
        ] {
            assert_eq!(
                z.im, 0.0,
                "{name} complex at n1 {n1} n2 {n2} cos_i {cos_i} c2t {c2t}"
            );
            assert_eq!(
                z.re.to_bits(),
                x.to_bits(),
                "{name}: {} against {x} at n1 {n1} n2 {n2} cos_i {cos_i} c2t {c2t}",
                z.re
            );
        }
        checked += 1;
    }
    assert!(
        checked > 150_000,
        "only {checked} draws below the critical angle"
    );
}

/// A render with the kernels' fast paths (`PixelPath::Auto`: real fields, beat terms summed
/// straight from the table) and with their reference (`PixelPath::KernelReference`: complex
/// Fresnel and complex fields, the sums through `Beats`, as before the fast paths).
fn fast_and_reference(
    case: &Case,
    screen: Screen,
    shadings: Vec<Shading>,
    spectrum: Spectrum,
) -> (Render, Render) {
    auto_and(case, screen, shadings, spectrum, PixelPath::KernelReference)
}

/// The fast paths change no bit of the plate's pictures at any shading, in white light (the
/// table's sums, also with the half-cycle jumps of `scalar_jump`), with few samples (no table)
/// and in monochrome; nor of Fig. 3's slits (the free kernel's real fields).
#[test]
fn the_real_kernel_is_its_complex_reference_bit_for_bit() {
    let case = plate();
    let screen = Screen::from_probe(&case.spec.probe, Some((48, 40))).unwrap();
    for spectrum in [white(81), white(31), white(7), Spectrum::CaseLight] {
        let (fast, reference) = fast_and_reference(&case, screen, all_shadings(), spectrum);
        assert_eq!(fast.kernel_pixels, 48 * 40);
        assert_eq!(reference.kernel_pixels, 48 * 40);
        assert_eq!(linear(&fast), linear(&reference));
    }
    let young = fringe::output::figures::young_case().unwrap();
    let screen = Screen::from_probe(&young.spec.probe, Some((40, 30))).unwrap();
    let (fast, reference) = fast_and_reference(&young, screen, all_shadings(), white(31));
    assert!(fast.kernel_pixels > 0);
    assert_eq!(linear(&fast), linear(&reference));
}

proptest! {
    #![proptest_config(crate::common::config(16))]

    /// Random stacks of the class (films and substrates of index 1.1–2.4, so pixels beyond and
    /// near critical angles, which the kernel leaves to the exact trace's complex
    /// arithmetic; scenes it refuses, e.g. with tunnelling, are traced exactly both ways):
    /// the fast paths' pictures are their complex reference's bit for bit at every shading.
    #[test]
    fn random_stacks_real_kernel_is_its_complex_reference(seed in any::<u64>()) {
        let mut d = Draw(seed);
        let (case, screen, what, _) = random_stack(&mut d);
        let spectrum = match (d.unit() * 3.0) as u32 {
            0 => white(21),
            1 => white(7),
            _ => Spectrum::CaseLight,
        };
        let (fast, reference) = fast_and_reference(&case, screen, all_shadings(), spectrum);
        prop_assert_eq!(fast.kernel_pixels, reference.kernel_pixels, "{}", what);
        prop_assert_eq!(linear(&fast), linear(&reference), "{}", what);
    }
}
