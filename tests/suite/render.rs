//! Pictures (`fringe::output::render`): a rendered pixel is the exact trace at its screen point, the
//! streamed XYZ equals the sum of stored per-wavelength images, the plate picture matches the
//! two-beam closed form where that applies, and the command line writes PNGs of the asked size.

use fringe::accumulate::fidelity::Fidelity;
use fringe::colour::{Illuminant, SpectralIntegrator, WavelengthGrid};
use fringe::harness::case::build::{self, Overrides};
use fringe::harness::case::load::{self, Case};
use fringe::harness::case::spec::{Light, MediumSpec, Observer, Probe};
use fringe::output::render::{self, ImageValues, Request, Screen, Shading, Spectrum};
use fringe::output::report::image as img;
use fringe::trace;
use glam::DVec3;
use predicates::prelude::PredicateBooleanExt;
use std::path::Path;

fn plate() -> Case {
    fringe::output::figures::plate_case().expect("the plate figure scene is valid")
}

fn intensities(r: &render::Render, k: usize) -> &[f64] {
    match &r.images[k].values {
        ImageValues::Intensity(v) => v,
        ImageValues::Xyz(_) => panic!("expected an intensity image"),
    }
}

fn xyz(r: &render::Render, k: usize) -> &[[f64; 3]] {
    match &r.images[k].values {
        ImageValues::Xyz(v) => v,
        ImageValues::Intensity(_) => panic!("expected an XYZ image"),
    }
}

/// The intensity at one screen point the way `fringe check` traces a probe point: a plan of
/// its own for that point, every arrival the one-sided screen records, the accumulation core.
fn traced_at(
    case: &Case,
    p: DVec3,
    looks_toward: Option<[f64; 3]>,
    lambda: f64,
    level: Fidelity,
) -> f64 {
    let built = build::build_scene(&case.spec.scene, &Overrides::default()).unwrap();
    let optics = built.scene.optics(lambda).unwrap();
    let st = render::trace_settings(case, &built, lambda).unwrap();
    let plan = trace::plan(&built.scene, &optics, &[p], &st.limits);
    let observer = Observer::Point {
        position_m: p.to_array(),
        looks_toward,
    };
    let arr = render::arrivals_at(&built.scene, &optics, &plan, p, &observer, &st, true);
    trace::intensity(&arr, level)
}

#[test]
fn monochrome_pixels_equal_the_trace_at_their_points() {
    for case in [plate(), fringe::output::figures::young_case().unwrap()] {
        let screen = Screen::from_probe(&case.spec.probe, Some((7, 5))).unwrap();
        let levels: Vec<Shading> = Fidelity::ALL.iter().map(|l| Shading::Level(*l)).collect();
        let r = render::render(
            &case,
            &Request {
                screen,
                shadings: levels.clone(),
                spectrum: Spectrum::CaseLight,
                progress: false,
            },
        )
        .unwrap();
        let lambda = r.display_lambda_m;
        let looks = screen.looks_toward.map(|l| l.to_array());
        for (k, sh) in levels.iter().enumerate() {
            let Shading::Level(level) = sh else {
                unreachable!()
            };
            let image = intensities(&r, k);
            assert_eq!(image.len(), 35);
            let scale = img::peak(image);
            assert!(scale > 0.0, "{}: {level} picture is black", case.spec.name);
            for row in 0..5 {
                for col in 0..7 {
                    let p = screen.geometry.position(col, row);
                    let expected = traced_at(&case, p, looks, lambda, *level);
                    let actual = image[row * 7 + col];
                    let err = (actual - expected).abs() / scale;
                    assert!(
                        err < 1e-12,
                        "{} {level} pixel ({col}, {row}): rendered {actual:e}, traced {expected:e}, err {err:e}",
                        case.spec.name
                    );
                }
            }
        }
    }
}

#[test]
fn a_line_probe_renders_as_its_probe_points() {
    let case = load::load(Path::new("cases/young_paper.json")).unwrap();
    let screen = Screen::from_probe(&case.spec.probe, Some((9, 1))).unwrap();
    assert!(screen.strip);
    let r = render::render(
        &case,
        &Request {
            screen,
            shadings: vec![Shading::Level(Fidelity::Vector)],
            spectrum: Spectrum::CaseLight,
            progress: false,
        },
    )
    .unwrap();
    let Probe::Line { from_m, to_m, .. } = case.spec.probe else {
        unreachable!()
    };
    let (a, b) = (DVec3::from_array(from_m), DVec3::from_array(to_m));
    for (i, &v) in intensities(&r, 0).iter().enumerate() {
        let p = a.lerp(b, i as f64 / 8.0);
        assert!((screen.geometry.position(i, 0) - p).length() < 1e-15);
        // Independent closed form: Young's exact two-slit intensity.
        let built = build::build_scene(&case.spec.scene, &Overrides::default()).unwrap();
        let expected = fringe::harness::case::reference::value(
            &case.spec.references[0].model,
            &built,
            &fringe::trace::path::Target::Point(p),
            550e-9,
            false,
        )
        .unwrap();
        assert!(
            (v - expected).abs() < 1e-9 * 4.0,
            "point {i}: rendered {v}, Young exact {expected}"
        );
    }
}

#[test]
fn the_middle_row_of_the_plate_matches_the_two_beam_closed_form() {
    // With an odd number of rows the middle row lies in the plane of incidence through the
    // source (y = 0), where the paper's two-beam formula (P1–P4, exact geometry) applies.
    let case = plate();
    let screen = Screen::from_probe(&case.spec.probe, Some((25, 3))).unwrap();
    let r = render::render(
        &case,
        &Request {
            screen,
            shadings: vec![
                Shading::Level(Fidelity::Vector),
                Shading::Level(Fidelity::PaperRules),
            ],
            spectrum: Spectrum::CaseLight,
            progress: false,
        },
    )
    .unwrap();
    let built = build::build_scene(&case.spec.scene, &Overrides::default()).unwrap();
    let expected: Vec<f64> = (0..25)
        .map(|col| {
            let p = screen.geometry.position(col, 1);
            assert!(
                p.y.abs() < 1e-15,
                "middle row must lie at y = 0, got {}",
                p.y
            );
            fringe::harness::case::reference::value(
                &case.spec.references[0].model,
                &built,
                &fringe::trace::path::Target::Point(p),
                550e-9,
                false,
            )
            .unwrap()
        })
        .collect();
    // The case library's metric: deviation relative to the largest closed-form value.
    let scale = img::peak(&expected);
    for k in 0..2 {
        let image = intensities(&r, k);
        for (col, e) in expected.iter().enumerate() {
            let actual = image[25 + col];
            let dev = (actual - e).abs() / scale;
            assert!(
                dev < 1e-9,
                "column {col}: rendered {actual:e}, two-beam closed form {e:e}, deviation {dev:e}"
            );
        }
    }
}

/// The plate scene with its glass made dispersive (N-BK7), so paths are re-solved per λ.
fn dispersive_plate() -> Case {
    let mut case = plate();
    case.spec
        .scene
        .media
        .insert("glass".into(), MediumSpec::Bk7 {});
    case
}

#[test]
fn streamed_xyz_equals_the_sum_of_stored_per_wavelength_images() {
    let grid = WavelengthGrid::from_list(vec![420e-9, 480e-9, 530e-9, 610e-9, 690e-9]).unwrap();
    let integ = SpectralIntegrator::new(&grid, Illuminant::D65).unwrap();
    for case in [plate(), dispersive_plate()] {
        let screen = Screen::from_probe(&case.spec.probe, Some((6, 4))).unwrap();
        let shadings = vec![
            Shading::Level(Fidelity::ScalarJump),
            Shading::Level(Fidelity::Vector),
            Shading::UnpolarizedScalarJump,
        ];
        let streamed = render::render(
            &case,
            &Request {
                screen,
                shadings: shadings.clone(),
                spectrum: Spectrum::White(integ.clone()),
                progress: false,
            },
        )
        .unwrap();
        // Stored: one monochrome picture per wavelength (the case's light set to that λ),
        // combined afterwards by the colour module's accumulator.
        for (k, _) in shadings.iter().enumerate() {
            let mut acc = integ.accumulator(24);
            for (i, &lambda) in grid.lambdas_m.iter().enumerate() {
                let mut mono = case.clone();
                mono.spec.light = Light::Monochrome {
                    wavelength_nm: lambda * 1e9,
                };
                let r = render::render(
                    &mono,
                    &Request {
                        screen,
                        shadings: shadings.clone(),
                        spectrum: Spectrum::CaseLight,
                        progress: false,
                    },
                )
                .unwrap();
                acc.add_image(i, intensities(&r, k)).unwrap();
            }
            let stored = acc.finish().unwrap();
            let peak = stored.iter().map(|p| p[1]).fold(0.0, f64::max);
            assert!(peak > 0.0);
            for (px, (a, b)) in xyz(&streamed, k).iter().zip(&stored).enumerate() {
                for c in 0..3 {
                    let err = (a[c] - b[c]).abs() / peak;
                    assert!(
                        err < 1e-12,
                        "{} shading {k} pixel {px} channel {c}: streamed {:e}, stored {:e}, err {err:e}",
                        case.spec.name,
                        a[c],
                        b[c]
                    );
                }
            }
        }
    }
}

#[test]
fn dispersion_is_detected_and_changes_the_picture() {
    let grid = WavelengthGrid::from_list(vec![450e-9, 650e-9]).unwrap();
    let integ = SpectralIntegrator::new(&grid, Illuminant::E).unwrap();
    let run = |case: &Case| {
        render::render(
            case,
            &Request {
                screen: Screen::from_probe(&case.spec.probe, Some((4, 3))).unwrap(),
                shadings: vec![Shading::Level(Fidelity::Vector)],
                spectrum: Spectrum::White(integ.clone()),
                progress: false,
            },
        )
        .unwrap()
    };
    let (a, b) = (run(&plate()), run(&dispersive_plate()));
    assert!(!a.dispersive && b.dispersive);
    // Non-dispersive: one path solve per arrival and pixel; dispersive: one per wavelength.
    assert_eq!(b.paths, 2 * a.paths, "paths: {} vs {}", a.paths, b.paths);
    let differs = xyz(&a, 0)
        .iter()
        .zip(xyz(&b, 0))
        .any(|(p, q)| (p[1] - q[1]).abs() > 1e-6);
    assert!(
        differs,
        "BK7 (n ≈ 1.52) must change the film colours of n = 1.5"
    );
}

#[test]
fn the_unpolarized_scalar_ray_follows_the_two_beam_formula_with_summed_powers() {
    // One scalar ray per path with the channel powers summed: I = I1 + I2 + 2√(I1 I2) cos δ,
    // δ = 2π Δs/λ + π (one reflection from the denser side on the top face, none inside).
    let case = plate();
    let screen = Screen::from_probe(&case.spec.probe, Some((5, 5))).unwrap();
    let r = render::render(
        &case,
        &Request {
            screen,
            shadings: vec![Shading::UnpolarizedScalarJump],
            spectrum: Spectrum::CaseLight,
            progress: false,
        },
    )
    .unwrap();
    let built = build::build_scene(&case.spec.scene, &Overrides::default()).unwrap();
    let lambda = 550e-9;
    let optics = built.scene.optics(lambda).unwrap();
    let st = render::trace_settings(&case, &built, lambda).unwrap();
    for row in 0..5 {
        for col in 0..5 {
            let p = screen.geometry.position(col, row);
            let plan = trace::plan(&built.scene, &optics, &[p], &st.limits);
            let obs = screen.observer(p);
            let arr = render::arrivals_at(&built.scene, &optics, &plan, p, &obs, &st, true);
            assert_eq!(arr.len(), 4, "two paths × two channels at ({col}, {row})");
            let top: Vec<_> = arr.iter().filter(|a| a.path.sequence.len() == 1).collect();
            let inner: Vec<_> = arr.iter().filter(|a| a.path.sequence.len() == 3).collect();
            let i1: f64 = top.iter().map(|a| a.vector.intensity()).sum();
            let i2: f64 = inner.iter().map(|a| a.vector.intensity()).sum();
            // The path difference formed before rounding, as the render forms it.
            let ds = (inner[0].vector.optical_path - top[0].vector.optical_path).to_f64();
            let delta = std::f64::consts::TAU * ds / lambda + std::f64::consts::PI;
            let expected = i1 + i2 + 2.0 * (i1 * i2).sqrt() * delta.cos();
            let actual = intensities(&r, 0)[row * 5 + col];
            assert!(
                (actual - expected).abs() < 1e-12 * (i1 + i2),
                "({col}, {row}): rendered {actual:e}, formula {expected:e}"
            );
            // Cauchy–Schwarz: the summed scalar ray never has less fringe contrast than the
            // s/p decomposition (paper_rules), so it is ≥ where cos δ > 0.
            let pr = trace::intensity(&arr, Fidelity::PaperRules);
            if delta.cos() > 0.1 {
                assert!(actual >= pr - 1e-15, "({col}, {row}): {actual:e} < {pr:e}");
            }
        }
    }
}

#[test]
fn screen_and_size_validation() {
    assert_eq!(render::parse_size("900x900"), Ok((900, 900)));
    assert_eq!(render::parse_size("12X7"), Ok((12, 7)));
    for bad in ["", "900", "0x5", "5x0", "axb", "100000x2"] {
        assert!(render::parse_size(bad).is_err(), "{bad:?} accepted");
    }
    assert_eq!(
        render::parse_shading("paper_rules"),
        Ok(Shading::Level(Fidelity::PaperRules))
    );
    assert_eq!(
        render::parse_shading("unpolarized_scalar_jump"),
        Ok(Shading::UnpolarizedScalarJump)
    );
    assert!(render::parse_shading("auto").is_err());
    // A sweep cannot be drawn.
    let sweep = load::load(Path::new("cases/plate_airy_s.json")).unwrap();
    let e = Screen::from_probe(&sweep.spec.probe, None).unwrap_err();
    assert!(e.contains("grid"), "{e}");
    // Pixel centres of a grid: symmetric about the centre, row 0 at the top (+v).
    let case = plate();
    let s = Screen::from_probe(&case.spec.probe, Some((4, 2))).unwrap();
    let g = s.geometry;
    let tl = g.position(0, 0);
    let br = g.position(3, 1);
    assert!((0.5 * (tl + br) - DVec3::new(0.035, 0.0, 0.02)).length() < 1e-15);
    assert!(
        (tl - DVec3::new(0.035 - 0.0225, 0.015, 0.02)).length() < 1e-15,
        "{tl}"
    );
}

#[test]
fn render_command_writes_pngs_of_the_asked_size() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("young.png");
    let status = assert_cmd::Command::cargo_bin("fringe")
        .unwrap()
        .args(["render", "young_fig3", "--size", "16x8", "-o"])
        .arg(&out)
        .assert()
        .success();
    // What was written and how it was normalised is information: stderr.
    let text = String::from_utf8_lossy(&status.get_output().stderr).to_string();
    assert!(
        text.contains("brightest pixel"),
        "normalisation not stated: {text}"
    );
    let pic = img::decode_png(&std::fs::read(&out).unwrap()).unwrap();
    assert_eq!((pic.width, pic.height), (16, 8));
    // Colour, two levels: the file name gets the level.
    let base = dir.path().join("plate.png");
    assert_cmd::Command::cargo_bin("fringe")
        .unwrap()
        .args([
            "render",
            "figures/plate_amplitude_division.json",
            "--samples",
            "4",
            "--fidelity",
            "incoherent,vector",
            "--size",
            "10x6",
            "-o",
        ])
        .arg(&base)
        .assert()
        .success();
    for level in ["incoherent", "vector"] {
        let f = dir.path().join(format!("plate_{level}.png"));
        let pic = img::decode_png(&std::fs::read(&f).unwrap()).unwrap();
        assert_eq!((pic.width, pic.height), (10, 6), "{}", f.display());
    }
    // Bad input: exit 2 and a message naming the problem.
    assert_cmd::Command::cargo_bin("fringe")
        .unwrap()
        .args(["render", "plate_airy_s"])
        .assert()
        .code(2)
        .stderr(predicates::str::contains("grid"));
}

/// A render larger than the memory it may use is refused before it starts: exit 2, a message
/// with both amounts, no picture. The budget is simulated with FRINGE_MEMORY_BYTES; the
/// estimate for 2000 × 2000 pixels and two pictures is at least the 2 × 4e6 × 2 × 24 bytes of
/// the per-pixel XYZ sums (≈ 366 MiB), far above 100 MB and far below 4 GB.
#[test]
fn a_render_too_large_for_the_memory_budget_is_refused_before_it_starts() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("big.png");
    let screen = Screen::from_probe(&plate().spec.probe, Some((2000, 2000))).unwrap();
    let estimate = render::memory_estimate(&screen, 2);
    assert!(estimate >= 2 * 4_000_000 * 2 * 24, "estimate {estimate}");
    assert_cmd::Command::cargo_bin("fringe")
        .unwrap()
        .env("FRINGE_MEMORY_BYTES", "100000000")
        .args([
            "render",
            "figures/plate_amplitude_division.json",
            "--fidelity",
            "scalar_jump,vector",
            "--size",
            "2000x2000",
            "-o",
        ])
        .arg(&out)
        .assert()
        .code(2)
        .stderr(
            predicates::str::contains("needs about").and(predicates::str::contains("95.4 MiB")),
        );
    assert!(
        std::fs::read_dir(dir.path()).unwrap().next().is_none(),
        "a refused render wrote a file"
    );
    // A malformed budget is an error too, never silently ignored.
    assert_cmd::Command::cargo_bin("fringe")
        .unwrap()
        .env("FRINGE_MEMORY_BYTES", "lots")
        .args(["render", "young_fig3", "--size", "4x4", "-o"])
        .arg(&out)
        .assert()
        .code(2)
        .stderr(predicates::str::contains("FRINGE_MEMORY_BYTES"));
}
