//! The parallel-stack pixel kernel (`fringe::output::stack_kernel`) against the exact trace it
//! replaces: the same picture rendered both ways (`render::render_with`, `PixelPath::Auto`
//! against `PixelPath::Exact`) agrees in its linear values (XYZ, or intensity) to 1e-10 of the
//! picture's peak, and scenes or pixels outside the kernel's class are traced exactly.
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
use glam::DVec3;

const TOLERANCE: f64 = 1e-10;

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
    let req = Request {
        screen,
        shadings,
        spectrum,
        progress: false,
    };
    (
        render::render_with(case, &req, PixelPath::Auto).unwrap(),
        render::render_with(case, &req, PixelPath::Exact).unwrap(),
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

/// Scenes and shadings outside the class render exactly as the exact trace does, bit for bit.
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
    let cases: Vec<(&str, &Case, Vec<Shading>)> = vec![
        // Other rungs of the ladder.
        (
            "plate, paper_rules too",
            &plate,
            vec![
                Shading::Level(Fidelity::Vector),
                Shading::Level(Fidelity::PaperRules),
            ],
        ),
        (
            "plate, scalar",
            &plate,
            vec![Shading::Level(Fidelity::Scalar)],
        ),
        // A dispersive medium.
        (
            "BK7 plate",
            &dispersive,
            vec![Shading::Level(Fidelity::Vector)],
        ),
        // Slits: no point sources over parallel planes.
        ("Young", &young, vec![Shading::Level(Fidelity::Vector)]),
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
