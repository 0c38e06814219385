//! `Beats::intensities`, a point's spectrum from rays traced once: at every wavelength of a
//! grid it must give the accumulation core's intensity (eqs. 5–6, docs/PHYSICS.md §3; the
//! reference is `Accumulator`, one wavelength at a time, tested on its own in
//! tests/suite/accumulate.rs), in both of its forms (beat terms, and rays by blocks of
//! wavelengths with one phasor batch per distinct ray phase), for grids longer than one block
//! and for rays that share phases across coherence groups in any order.

use crate::beats::core;
use fringe::optics::ray::Field3;
use fringe::trace::beats::{Beats, SpectralContribution};
use num_complex::Complex64;
use proptest::prelude::*;

/// (Σ_k |E_k|)², the scale of every cross term and of the rounding of any order of summation.
fn scale(rays: &[SpectralContribution]) -> f64 {
    rays.iter()
        .map(|r| r.field.iter().map(|c| c.norm()).sum::<f64>())
        .sum::<f64>()
        .powi(2)
}

fn field() -> impl Strategy<Value = Field3> {
    proptest::array::uniform6(-1.0..1.0f64).prop_map(|a| {
        [
            Complex64::new(a[0], a[1]),
            Complex64::new(a[2], a[3]),
            Complex64::new(a[4], a[5]),
        ]
    })
}

/// Rays whose phases come from a pool of four (Δs, extra) pairs, so that rays of different
/// groups (ids 0–3, 0 incoherent) share phases in arbitrary order; with 6+ rays in few groups
/// the accumulator form is taken.
fn rays() -> impl Strategy<Value = Vec<SpectralContribution>> {
    (
        proptest::array::uniform4((-3e-5..3e-5f64, prop_oneof![Just(0.0), -1.0..1.0f64])),
        proptest::collection::vec((0u64..4, 0usize..4, field()), 0..24),
    )
        .prop_map(|(phases, rays)| {
            rays.into_iter()
                .map(|(coherence_id, p, field)| SpectralContribution {
                    coherence_id,
                    delta_s_m: phases[p].0,
                    extra_cycles: phases[p].1,
                    field,
                })
                .collect()
        })
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(256))]

    /// Every wavelength of a grid of 1–300 points (several blocks of the accumulator form, and
    /// a partial last one): the core's intensity to rounding.
    #[test]
    fn spectrum_equals_the_core_at_every_wavelength(
        rays in rays(),
        n in 1usize..300,
        start in 380e-9..500e-9f64,
    ) {
        let lambdas: Vec<f64> = (0..n).map(|i| start + 1e-9 * i as f64).collect();
        let mut beats = Beats::default();
        beats.set(&rays);
        let mut out = vec![f64::NAN; n];
        beats.intensities(&lambdas, &mut out);
        let tol = 1e-13 * scale(&rays).max(1e-300);
        for (&l, &got) in lambdas.iter().zip(&out) {
            let want = core(&rays, l);
            prop_assert!(
                (got - want).abs() <= tol,
                "λ = {l:e}: {got:e} vs core {want:e} (tol {tol:e}, terms {:?})",
                beats.term_count()
            );
        }
    }
}

/// A long grid (4001 wavelengths, 63 blocks) over 40 coherent rays in two groups whose phases
/// are shared pairwise (the s and p channels of 20 orders of a plate, Δs up to 4·10^-4 m, i.e.
/// up to 10^3 cycles): every wavelength equals the core to 1e-14 of (Σ|E_k|)², and reusing the
/// same `Beats` for a second, shorter spectrum gives the same values as a fresh one.
#[test]
fn long_grid_with_shared_phases_matches_the_core() {
    let rays: Vec<SpectralContribution> = (0..20)
        .flat_map(|k| {
            let ds = 2.0e-5 * k as f64 + 1.234_567e-7 * (k * k) as f64;
            let a = 0.8f64.powi(k);
            [1u64, 2].map(|id| SpectralContribution {
                coherence_id: id,
                delta_s_m: ds,
                extra_cycles: 0.0,
                field: [
                    Complex64::new(a * id as f64, -0.3 * a),
                    Complex64::new(0.1 * a, 0.2 * a * id as f64),
                    Complex64::new(-0.05 * a, 0.0),
                ],
            })
        })
        .collect();
    let lambdas: Vec<f64> = (0..4001).map(|i| 400e-9 + 0.1e-9 * i as f64).collect();
    let mut beats = Beats::default();
    beats.set(&rays);
    assert_eq!(
        beats.term_count(),
        None,
        "many beams per group: accumulator form"
    );
    let mut out = vec![0.0; lambdas.len()];
    beats.intensities(&lambdas, &mut out);
    let tol = 1e-14 * scale(&rays);
    let mut worst = 0.0f64;
    for (&l, &got) in lambdas.iter().zip(&out) {
        worst = worst.max((got - core(&rays, l)).abs());
    }
    assert!(worst <= tol, "max |I − core| = {worst:e} > {tol:e}");
    let short = &lambdas[..70];
    let mut again = vec![0.0; short.len()];
    beats.intensities(short, &mut again);
    let mut fresh = Beats::default();
    fresh.set(&rays);
    let mut want = vec![0.0; short.len()];
    fresh.intensities(short, &mut want);
    assert_eq!(again, want);
    assert_eq!(&out[..70], &want[..]);
}
