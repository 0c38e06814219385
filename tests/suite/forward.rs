//! Renderer mode: forward ray fans against the exact point-to-point tracer.

use fringe::harness::forward_study::{self, StudyScene};
use fringe::trace::forward::{self, Estimator, ForwardSettings};

fn settings(s: &StudyScene, rays: usize, seed: u64) -> ForwardSettings {
    ForwardSettings {
        rays,
        seed,
        cone_axis: s.cone_axis,
        cone_half_angle: s.cone_half_angle,
        max_depth: s.max_depth,
        min_power: 1e-12,
    }
}

fn render(s: &StudyScene, rays: usize, seed: u64, est: Estimator) -> Vec<f64> {
    let optics = s.scene.optics(s.lambda_m).unwrap();
    let landings = forward::trace_fans(&s.scene, &optics, &s.screen, &settings(s, rays, seed));
    forward::image(&landings, &s.screen, est)
}

fn mean(v: &[f64]) -> f64 {
    v.iter().sum::<f64>() / v.len() as f64
}

/// Rays of one family in one pixel are samples of one wave: with the family estimator the
/// picture does not grow with the ray count, while summing rays coherently (the naive rule)
/// grows like the number of rays per pixel.
#[test]
fn intensity_does_not_grow_with_the_number_of_rays() {
    let s = forward_study::young_pinholes(16);
    let (n, m) = (20_000, 80_000);
    let fam = |r| mean(&render(&s, r, 7, Estimator::TransportedPhase));
    let naive = |r| mean(&render(&s, r, 7, Estimator::NaiveRays));
    let (f1, f4) = (fam(n), fam(m));
    let ratio_family = f4 / f1;
    assert!(
        (ratio_family - 1.0).abs() < 0.03,
        "family estimator: mean {f1:e} at {n} rays, {f4:e} at {m} rays, ratio {ratio_family}"
    );
    let ratio_naive = naive(m) / naive(n);
    assert!(
        ratio_naive > 3.0,
        "naive coherent ray sum should grow ~4x with 4x the rays, grew {ratio_naive}"
    );
    // And the family mean is the exact mean (the exact image at pixel centres, same units).
    let exact = mean(&forward_study::exact_image(&s));
    assert!(
        (f4 / exact - 1.0).abs() < 0.03,
        "family mean {f4:e}, exact mean {exact:e}"
    );
}

/// The transported-phase estimator converges to the exact image (Monte Carlo noise ~ 1/√rays).
#[test]
fn transported_phase_converges_to_the_exact_image() {
    let s = forward_study::young_pinholes(16);
    let exact = forward_study::exact_image(&s);
    let (e1, _) =
        forward_study::errors(&render(&s, 10_000, 3, Estimator::TransportedPhase), &exact);
    let (e2, _) =
        forward_study::errors(&render(&s, 160_000, 3, Estimator::TransportedPhase), &exact);
    assert!(e2 < 0.02, "rms error {e2:e} at 160k rays");
    assert!(
        e2 < 0.5 * e1,
        "error should fall with rays: {e1:e} → {e2:e}"
    );
    // The landing phase (no transport) does not converge: each wave's own phase runs through
    // many cycles across a pixel (carrier k·sin α·pixel), far faster than the fringes.
    let (el, _) = forward_study::errors(&render(&s, 160_000, 3, Estimator::LandingPhase), &exact);
    assert!(
        el > 10.0 * e2,
        "landing phase error {el:e} vs transported {e2:e}"
    );
}

/// Deterministic for a seed, whatever the number of threads.
#[test]
fn forward_mode_is_deterministic() {
    let s = forward_study::plate_scene("amplitude_division", 8, 50e-6, 1);
    let one = rayon::ThreadPoolBuilder::new()
        .num_threads(1)
        .build()
        .unwrap();
    let two = rayon::ThreadPoolBuilder::new()
        .num_threads(2)
        .build()
        .unwrap();
    let a = one.install(|| render(&s, 20_000, 11, Estimator::Supersampled { cells: 2 }));
    let b = two.install(|| render(&s, 20_000, 11, Estimator::Supersampled { cells: 2 }));
    assert_eq!(a, b, "same seed, 1 vs 2 threads");
    let c = render(&s, 20_000, 12, Estimator::Supersampled { cells: 2 });
    assert_ne!(a, c, "a different seed gives a different sample");
}

/// Power bookkeeping: with no surfaces, everything emitted into the cone lands; the power that
/// reaches the screen equals I·Ω per channel (up to the rays that fall outside the screen).
#[test]
fn emitted_power_lands_on_the_screen() {
    let mut s = forward_study::young_pinholes(4);
    s.screen.size_m = [0.1, 0.1]; // larger than the cone's footprint (0.02 rad at 0.1 m)
    let optics = s.scene.optics(s.lambda_m).unwrap();
    let landings = forward::trace_fans(&s.scene, &optics, &s.screen, &settings(&s, 10_000, 1));
    let total: f64 = landings.iter().map(|l| l.power).sum();
    let omega = std::f64::consts::TAU * (1.0 - s.cone_half_angle.cos());
    let expected = 2.0 * omega; // two unit-intensity sources (two half-intensity channels each)
    assert!(
        (total / expected - 1.0).abs() < 1e-12,
        "landed {total:e}, emitted {expected:e}"
    );
}
