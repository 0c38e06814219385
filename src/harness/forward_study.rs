//! The measured cost of "a pixel is not a point": forward-mode estimators against the exact
//! point-to-point result at pixel centres, as a function of rays per pixel and of pixel size
//! relative to the fringe spacing (issue: renderer mode).
//!
//! Three scenes, all with point sources and geometric spreading on in the exact reference (a
//! forward renderer's ray density *is* the spreading):
//! * `young_pinholes`: two coherent pinholes 0.1 mm apart, screen 0.1 m away (spacing 0.55 mm);
//! * `amplitude_division`: the paper's plate scene at 1 cm scale (n = 1.5, 50 µm), two beams;
//! * `airy_plate_screen`: the same plate 10 µm thick, up to 7 internal reflections, on a
//!   finite-distance screen.

use crate::accumulate::fidelity::Fidelity;
use crate::optics::material::Medium;
use crate::scene::geometry::{Extent, Plane, Rect};
use crate::scene::source::{Emitter, Polarization, Source};
use crate::scene::{Scene, Surface, SurfaceKind};
use crate::trace::forward::{self, Estimator, ForwardSettings, Screen};
use crate::trace::path::{EnumerationLimits, SolveOptions, Target};
use crate::trace::{self, TraceSettings};
use glam::DVec3;
use rayon::prelude::*;
use std::time::Instant;

/// A forward-mode test scene.
pub struct StudyScene {
    pub name: &'static str,
    pub scene: Scene,
    pub screen: Screen,
    pub cone_axis: DVec3,
    pub cone_half_angle: f64,
    pub max_depth: usize,
    pub max_internal_reflections: usize,
    /// Fringe spacing at the screen centre (m).
    pub fringe_spacing_m: f64,
    pub lambda_m: f64,
}

fn point_source(name: &str, position: DVec3, group: u64) -> Source {
    Source {
        name: name.into(),
        emitter: Emitter::Point { position },
        // The paper's two channels, as when the study's numbers in the README were measured.
        polarization: Polarization::UnpolarizedTwoChannel {
            reference: DVec3::Y,
        },
        intensity: 1.0,
        coherence_group: group,
        coherence_length_m: f64::INFINITY,
    }
}

/// Young's experiment with two coherent pinholes.
pub fn young_pinholes(pixels: usize) -> StudyScene {
    let (d, l, lambda) = (1e-4, 0.1, 550e-9);
    let mut scene = Scene::new(Medium::vacuum());
    scene
        .sources
        .push(point_source("pinhole1", DVec3::new(0.0, 0.5 * d, 0.0), 0));
    scene
        .sources
        .push(point_source("pinhole2", DVec3::new(0.0, -0.5 * d, 0.0), 0));
    StudyScene {
        name: "young_pinholes",
        scene,
        screen: Screen {
            center: DVec3::new(l, 0.0, 0.0),
            u: DVec3::Y,
            v: DVec3::Z,
            size_m: [2.2e-3, 2.2e-3],
            pixels: [pixels, pixels],
        },
        cone_axis: DVec3::X,
        cone_half_angle: 0.02,
        max_depth: 0,
        max_internal_reflections: 0,
        fringe_spacing_m: lambda * l / d,
        lambda_m: lambda,
    }
}

/// The paper's amplitude-division plate (thickness `thickness_m`), shield and screen.
pub fn plate_scene(
    name: &'static str,
    pixels: usize,
    thickness_m: f64,
    internal: usize,
) -> StudyScene {
    let lambda = 550e-9;
    let mut scene = Scene::new(Medium::vacuum());
    scene.add_plate(
        "plate",
        DVec3::ZERO,
        DVec3::Z,
        thickness_m,
        Medium::vacuum(),
        Medium::constant("glass", 1.5),
        Medium::vacuum(),
    );
    let shield_plane = Plane::new(DVec3::new(-0.005, 0.0, 0.0101), DVec3::Z);
    let (u, v) = shield_plane.axes(DVec3::X);
    scene.surfaces.push(Surface {
        name: "shield".into(),
        plane: shield_plane,
        extent: Extent::Rect {
            u,
            v,
            rect: Rect {
                center_uv: [0.0, 0.0],
                half_width_m: 0.0015,
                half_height_m: 0.0015,
            },
        },
        kind: SurfaceKind::Opaque { apertures: vec![] },
    });
    let src = DVec3::new(-0.005, 0.0, 0.01);
    scene.sources.push(point_source("lamp", src, 0));
    let center = DVec3::new(0.03, 0.0, 0.02);
    let image = DVec3::new(center.x, center.y, -center.z);
    // Local fringe spacing at the centre from the two exact beams (eikonal: ∇Op = n d).
    let optics = scene.optics(lambda).expect("constant indices");
    let lim = EnumerationLimits {
        max_internal_reflections: 1,
        max_events: 6,
    };
    let plan = trace::plan(&scene, &optics, &[center], &lim);
    let (arr, _) = trace::arrivals(
        &scene,
        &optics,
        &plan,
        &Target::Point(center),
        &TraceSettings::default(),
    );
    let mut beams: Vec<(
        f64,
        DVec3,
        &crate::optics::trail::Trail<crate::trace::path::Event>,
    )> = Vec::new();
    for a in &arr {
        if !beams.iter().any(|b| *b.2 == a.path.sequence) {
            beams.push((a.vector.intensity(), a.vector.dir, &a.path.sequence));
        }
    }
    beams.sort_by(|a, b| b.0.total_cmp(&a.0));
    let g = beams[0].1 - beams[1].1;
    StudyScene {
        name,
        scene,
        screen: Screen {
            center,
            u: DVec3::X,
            v: DVec3::Y,
            size_m: [4e-3, 4e-3],
            pixels: [pixels, pixels],
        },
        cone_axis: (image - src).normalize(),
        cone_half_angle: 0.06,
        max_depth: 2 * internal + 2,
        max_internal_reflections: internal,
        fringe_spacing_m: lambda / g.dot(DVec3::X).abs().max(1e-12),
        lambda_m: lambda,
    }
}

/// The exact image at pixel centres (spreading on), row-major, at `level`.
pub(crate) fn exact_image_at(s: &StudyScene, level: Fidelity) -> Vec<f64> {
    let optics = s.scene.optics(s.lambda_m).expect("constant indices");
    let [nx, ny] = s.screen.pixels;
    let lim = EnumerationLimits {
        max_internal_reflections: s.max_internal_reflections,
        max_events: 2 * s.max_internal_reflections + 6,
    };
    let st = TraceSettings {
        limits: lim,
        solve: SolveOptions {
            spreading: true,
            ..SolveOptions::default()
        },
        ..TraceSettings::default()
    };
    let plan = trace::plan(&s.scene, &optics, &[s.screen.center], &lim);
    (0..nx * ny)
        .into_par_iter()
        .map(|k| {
            let p = s.screen.pixel_center(k % nx, k / nx);
            let (arr, _) = trace::arrivals(&s.scene, &optics, &plan, &Target::Point(p), &st);
            trace::intensity(&arr, level)
        })
        .collect()
}

/// The exact image at pixel centres (vector fidelity, spreading on), row-major.
pub fn exact_image(s: &StudyScene) -> Vec<f64> {
    exact_image_at(s, Fidelity::Vector)
}

/// Relative RMS and max error of `img` against `exact`, normalised by `scale`.
pub(crate) fn errors_scaled(img: &[f64], exact: &[f64], scale: f64) -> (f64, f64) {
    let scale = scale.max(f64::MIN_POSITIVE);
    let mut max = 0.0f64;
    let mut sum2 = 0.0;
    for (a, b) in img.iter().zip(exact) {
        let e = (a - b).abs() / scale;
        max = max.max(e);
        sum2 += e * e;
    }
    ((sum2 / img.len() as f64).sqrt(), max)
}

/// Relative RMS and max error of `img` against `exact` (normalised by the largest exact value).
pub fn errors(img: &[f64], exact: &[f64]) -> (f64, f64) {
    errors_scaled(img, exact, exact.iter().fold(0.0f64, |m, v| m.max(v.abs())))
}

/// One measured point of the study.
#[derive(Clone, Debug)]
pub struct StudyRow {
    pub scene: &'static str,
    pub estimator: String,
    pub pixels: usize,
    pub pixel_over_fringe: f64,
    pub rays_per_channel: usize,
    pub mean_rays_per_pixel: f64,
    pub rel_rms_error: f64,
    pub rel_max_error: f64,
    pub seconds: f64,
}

/// Run the study: every scene × pixel count × ray count × estimator.
pub fn run(seed: u64, ray_counts: &[usize], pixel_counts: &[usize]) -> Vec<StudyRow> {
    run_observed(seed, ray_counts, pixel_counts, || {})
}

/// The number of traced settings of [`run`] (scenes × pixel counts × ray counts): the steps
/// [`run_observed`] reports.
pub fn steps(ray_counts: &[usize], pixel_counts: &[usize]) -> usize {
    3 * ray_counts.len() * pixel_counts.len()
}

/// [`run`], calling `step` after each traced setting (for a progress display).
pub fn run_observed(
    seed: u64,
    ray_counts: &[usize],
    pixel_counts: &[usize],
    mut step: impl FnMut(),
) -> Vec<StudyRow> {
    let estimators = [
        Estimator::NaiveRays,
        Estimator::LandingPhase,
        Estimator::TransportedPhase,
        Estimator::Supersampled { cells: 3 },
    ];
    let mut rows = Vec::new();
    for &pixels in pixel_counts {
        let scenes = [
            young_pinholes(pixels),
            plate_scene("amplitude_division", pixels, 50e-6, 1),
            plate_scene("airy_plate_screen", pixels, 10e-6, 7),
        ];
        for s in &scenes {
            let exact = exact_image(s);
            // Errors relative to the brightest intensity without interference (I1 + I2 + …): a
            // scale that stays meaningful when point samples alias onto dark fringes.
            let scale = exact_image_at(s, Fidelity::Incoherent)
                .into_iter()
                .fold(0.0f64, f64::max);
            let optics = s.scene.optics(s.lambda_m).expect("constant indices");
            for &rays in ray_counts {
                let st = ForwardSettings {
                    rays,
                    seed,
                    cone_axis: s.cone_axis,
                    cone_half_angle: s.cone_half_angle,
                    max_depth: s.max_depth,
                    min_power: 1e-12,
                };
                let t0 = Instant::now();
                let landings = forward::trace_fans(&s.scene, &optics, &s.screen, &st);
                let trace_s = t0.elapsed().as_secs_f64();
                let channels: usize = s.scene.sources.iter().map(|x| x.channels().len()).sum();
                let mean_rays = landings.len() as f64 / (channels * pixels * pixels) as f64;
                for est in estimators {
                    let t1 = Instant::now();
                    let img = forward::image(&landings, &s.screen, est);
                    let (rms, max) = errors_scaled(&img, &exact, scale);
                    rows.push(StudyRow {
                        scene: s.name,
                        estimator: est.name(),
                        pixels,
                        pixel_over_fringe: s.screen.pixel_size()[0] / s.fringe_spacing_m,
                        rays_per_channel: rays,
                        mean_rays_per_pixel: mean_rays,
                        rel_rms_error: rms,
                        rel_max_error: max,
                        seconds: trace_s + t1.elapsed().as_secs_f64(),
                    });
                }
                step();
            }
        }
    }
    rows
}

/// The study as CSV (written by the `csv` crate through [`crate::io::csv_text`]).
pub fn csv(rows: &[StudyRow]) -> String {
    crate::io::csv_text(
        &[
            "scene",
            "estimator",
            "pixels",
            "pixel_over_fringe",
            "rays_per_channel",
            "mean_rays_per_pixel_per_channel",
            "rel_rms_error",
            "rel_max_error",
            "seconds",
        ],
        rows.iter().map(|r| {
            vec![
                r.scene.to_string(),
                r.estimator.to_string(),
                r.pixels.to_string(),
                format!("{:.4}", r.pixel_over_fringe),
                r.rays_per_channel.to_string(),
                format!("{:.2}", r.mean_rays_per_pixel),
                format!("{:.4e}", r.rel_rms_error),
                format!("{:.4e}", r.rel_max_error),
                format!("{:.3}", r.seconds),
            ]
        }),
    )
}
