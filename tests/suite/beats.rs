//! Beat terms (`beats`): a point's rays evaluated at many wavelengths through the pair identity
//! |Σ E_k e^{iφ_k}|² = Σ|E_k|² + Σ_{k<l} 2 Re[(E_k·E_l*) e^{i(φ_k − φ_l)}] must give the
//! accumulation core's intensity (eqs. 5–6, the reference here: `Accumulator`, tested on its own
//! in tests/accumulate.rs) at every wavelength, merged or not, and the weighted spectral sum
//! must equal Σ_i w_i I(λ_i) summed term by term.

use fringe::accumulate::Accumulator;
use fringe::optics::ray::Field3;
use fringe::trace::beats::{Beats, SpectralContribution};
use num_complex::Complex64;
use proptest::prelude::*;

fn field() -> impl Strategy<Value = Field3> {
    proptest::array::uniform6(-1.0..1.0f64).prop_map(|a| {
        [
            Complex64::new(a[0], a[1]),
            Complex64::new(a[2], a[3]),
            Complex64::new(a[4], a[5]),
        ]
    })
}

fn ray() -> impl Strategy<Value = SpectralContribution> {
    (
        0u64..4,
        -2e-5..2e-5f64,
        prop_oneof![Just(0.0), Just(0.5), -1.0..1.0f64],
        field(),
    )
        .prop_map(
            |(coherence_id, delta_s_m, extra_cycles, field)| SpectralContribution {
                coherence_id,
                delta_s_m,
                extra_cycles,
                field,
            },
        )
}

/// The accumulation core's intensity of `rays` at `lambda` (compensated sums; also the
/// reference of `spectrum_batch`).
pub(crate) fn core(rays: &[SpectralContribution], lambda: f64) -> f64 {
    let mut acc = Accumulator::new();
    for r in rays {
        acc.add_parts(
            r.coherence_id,
            r.delta_s_m / lambda + r.extra_cycles,
            &r.field,
        );
    }
    acc.intensity()
}

fn power(rays: &[SpectralContribution]) -> f64 {
    rays.iter()
        .map(|r| r.field.iter().map(|c| c.norm_sqr()).sum::<f64>())
        .sum()
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(512))]

    /// Any set of rays (ids 0–3, 0 incoherent), any wavelength: the same intensity as the core,
    /// to rounding (relative to Σ|E_k|, the scale of every cross term).
    #[test]
    fn beats_equal_the_accumulation_core(
        rays in proptest::collection::vec(ray(), 0..9),
        lambda in 380e-9..780e-9f64,
    ) {
        let mut beats = Beats::default();
        beats.set(&rays);
        let mut acc = Accumulator::new();
        let got = beats.intensity(lambda, &mut acc);
        let want = core(&rays, lambda);
        let scale: f64 = rays.iter().map(|r| r.field.iter().map(|c| c.norm()).sum::<f64>()).sum::<f64>().powi(2);
        let tol = 1e-13 * scale.max(1e-300);
        prop_assert!((got - want).abs() <= tol, "beats {got:e}, core {want:e}, tol {tol:e}, terms {:?}", beats.term_count());
    }

    /// Σ_i w_i I(λ_i) on a wavelength grid equals the sum of the core's intensities.
    #[test]
    fn weighted_sum_equals_sum_of_intensities(
        rays in proptest::collection::vec(ray(), 0..7),
        weights in proptest::collection::vec(proptest::array::uniform3(0.0..2.0f64), 1..40),
    ) {
        let lambdas: Vec<f64> = (0..weights.len()).map(|i| 380e-9 + 5e-9 * i as f64).collect();
        let mut beats = Beats::default();
        beats.set(&rays);
        let mut acc = Accumulator::new();
        let got = beats.weighted_sum(&lambdas, &weights, &mut acc);
        let scale: f64 = rays.iter().map(|r| r.field.iter().map(|c| c.norm()).sum::<f64>()).sum::<f64>().powi(2);
        for c in 0..3 {
            let want: f64 = lambdas.iter().zip(&weights).map(|(&l, w)| w[c] * core(&rays, l)).sum();
            let wsum: f64 = weights.iter().map(|w| w[c]).sum();
            let tol = 1e-13 * scale.max(1e-300) * wsum.max(1.0);
            prop_assert!((got[c] - want).abs() <= tol, "channel {c}: {:e} vs {want:e}", got[c]);
        }
    }
}

/// The weighted sum is exactly (bit for bit) C Σ_i w_i, summed in wavelength order, plus each
/// term's Re b_t Σ_i w_i cos 2πφ_ti − Im b_t Σ_i w_i sin 2πφ_ti in term order — the documented
/// formula, evaluated here with the terms rebuilt by hand for one coherent group (pairs (1,0),
/// (2,0), (2,1), …) and with `phasor_from_cycles` per wavelength. Pins that interleaving the
/// constant's sum with the first term's leaves every value as it was.
#[test]
fn weighted_sum_is_the_documented_sum_bit_for_bit() {
    use fringe::accumulate::phasor_from_cycles;
    let fields = [
        [
            Complex64::new(0.7, -0.2),
            Complex64::new(0.1, 0.3),
            Complex64::new(-0.05, 0.0),
        ],
        [
            Complex64::new(-0.4, 0.6),
            Complex64::new(0.2, -0.1),
            Complex64::new(0.0, 0.15),
        ],
        [
            Complex64::new(0.3, 0.3),
            Complex64::new(-0.6, 0.05),
            Complex64::new(0.1, -0.2),
        ],
    ];
    let deltas = [0.0, 1.37e-6, -2.9e-6];
    let extras = [0.0, 0.5, 0.25];
    let weights: Vec<[f64; 3]> = (0..81)
        .map(|i| {
            let x = i as f64 / 80.0;
            [x * (1.0 - x), 0.3 + 0.1 * x, (1.7 * x).sin().abs()]
        })
        .collect();
    let lambdas: Vec<f64> = (0..81).map(|i| 380e-9 + 5e-9 * i as f64).collect();
    for n in 0..=3 {
        let rays: Vec<SpectralContribution> = (0..n)
            .map(|k| SpectralContribution {
                coherence_id: 1,
                delta_s_m: deltas[k],
                extra_cycles: extras[k],
                field: fields[k],
            })
            .collect();
        let mut beats = Beats::default();
        beats.set(&rays);
        let got = beats.weighted_sum(&lambdas, &weights, &mut Accumulator::new());
        let dot =
            |a: &Field3, b: &Field3| -> Complex64 { (0..3).map(|c| a[c] * b[c].conj()).sum() };
        let constant = power(&rays);
        let mut want = [0.0; 3];
        for w in &weights {
            for c in 0..3 {
                want[c] += w[c] * constant;
            }
        }
        for k in 0..n {
            for l in 0..k {
                let (a, b) = (&rays[k], &rays[l]);
                let amp = 2.0 * dot(&a.field, &b.field);
                let (mut re, mut im) = ([0.0; 3], [0.0; 3]);
                for (&lambda, w) in lambdas.iter().zip(&weights) {
                    let p = phasor_from_cycles(
                        (a.delta_s_m - b.delta_s_m) / lambda + (a.extra_cycles - b.extra_cycles),
                    );
                    for c in 0..3 {
                        re[c] += w[c] * p.re;
                        im[c] += w[c] * p.im;
                    }
                }
                for c in 0..3 {
                    want[c] += amp.re * re[c] - amp.im * im[c];
                }
            }
        }
        for c in 0..3 {
            assert_eq!(
                got[c].to_bits(),
                want[c].to_bits(),
                "{n} rays, channel {c}: actual {:e}, expected {:e}, err {:e}",
                got[c],
                want[c],
                got[c] - want[c]
            );
        }
    }
}

/// An unpolarized source's two channels (ids 1 and 2) along the same two paths: two pairs with
/// the same path difference merge into one beat term, and the intensity is the two-beam
/// formula I1 + I2 + 2 Re[(E1a·E2a* + E1b·E2b*) e^{2πiΔs/λ}] evaluated here by hand.
#[test]
fn two_channels_on_two_paths_make_one_beat() {
    let c = |re: f64, im: f64| Complex64::new(re, im);
    let e1a = [c(0.2, 0.0), c(0.0, 0.0), c(0.0, 0.0)];
    let e1b = [c(0.0, 0.0), c(0.1, 0.05), c(0.0, 0.0)];
    let e2a = [c(-0.15, 0.0), c(0.0, 0.0), c(0.0, 0.0)];
    let e2b = [c(0.0, 0.0), c(0.08, -0.02), c(0.0, 0.0)];
    let ds = 1.234e-6;
    let rays = [
        SpectralContribution {
            coherence_id: 1,
            delta_s_m: 0.0,
            extra_cycles: 0.0,
            field: e1a,
        },
        SpectralContribution {
            coherence_id: 2,
            delta_s_m: 0.0,
            extra_cycles: 0.0,
            field: e1b,
        },
        SpectralContribution {
            coherence_id: 1,
            delta_s_m: ds,
            extra_cycles: 0.0,
            field: e2a,
        },
        SpectralContribution {
            coherence_id: 2,
            delta_s_m: ds,
            extra_cycles: 0.0,
            field: e2b,
        },
    ];
    let mut beats = Beats::default();
    beats.set(&rays);
    assert_eq!(
        beats.term_count(),
        Some(1),
        "one beat term for two channels on two paths"
    );
    let lambda = 550e-9;
    let phi = std::f64::consts::TAU * ds / lambda;
    // E_k(path 2)·E_k(path 1)* for each channel, summed; path 2 is the later one (+Δs).
    let cross = e2a[0] * e1a[0].conj() + e2b[1] * e1b[1].conj();
    let by_hand = power(&rays) + 2.0 * (cross * Complex64::from_polar(1.0, phi)).re;
    let got = beats.intensity(lambda, &mut Accumulator::new());
    assert!(
        (got - by_hand).abs() < 1e-15,
        "beats {got:e}, by hand {by_hand:e}"
    );
}

/// Many beams in one group (an Airy plate): more pairs than rays, so the accumulator is used.
#[test]
fn many_beams_in_one_group_use_the_accumulator() {
    let rays: Vec<SpectralContribution> = (0..6)
        .map(|k| SpectralContribution {
            coherence_id: 1,
            delta_s_m: k as f64 * 1e-6,
            extra_cycles: 0.0,
            field: [
                Complex64::new(0.5f64.powi(k), 0.0),
                Complex64::default(),
                Complex64::default(),
            ],
        })
        .collect();
    let mut beats = Beats::default();
    beats.set(&rays);
    assert_eq!(beats.term_count(), None);
    // Geometric series at λ = 1 µm: every phase is a whole cycle, so |Σ 0.5^k|² = (2(1 − 2^-6))².
    let got = beats.intensity(1e-6, &mut Accumulator::new());
    let want = (2.0 * (1.0 - 0.5f64.powi(6))).powi(2);
    assert!((got - want).abs() < 1e-14, "{got} vs {want}");
}

/// A spectrum traced once: a plane wave on a free-standing plate (n = 1.7, 3.217 µm, 35°,
/// non-dispersive) has the same paths, Fresnel coefficients and orders at every wavelength, so
/// its arrivals traced at the middle wavelength, with the reflected orders the amplitude tail
/// bound ε = 1e-12 asks for (`Film::orders_for_bound`), give the whole 401-wavelength spectrum
/// through `Beats::intensities`. It must agree with the Airy reflectance (R_s + R_p)/2
/// (B&W §7.6.1, evaluated from the closed form, not the tracer) to 1e-12 at every wavelength,
/// and with tracing every wavelength on its own (`trace::intensity`, compensated sums) to
/// 1e-14.
#[test]
fn spectrum_traced_once_matches_airy_and_per_wavelength_traces() {
    use crate::support::airy_plate::airy_plate_of;
    use fringe::accumulate::fidelity::Fidelity;
    use fringe::harness::analytic::plate::{Film, Pol};
    use fringe::optics::material::Medium;
    use fringe::trace::path::EnumerationLimits;
    use fringe::trace::{self, TraceSettings};
    use glam::DVec3;

    let theta = 35f64.to_radians();
    let film = Film {
        n1: 1.0,
        n2: 1.7,
        n3: 1.0,
        thickness_m: 3.217e-6,
    };
    let (scene, target) = airy_plate_of(theta, Medium::constant("glass", 1.7), film.thickness_m);
    let lambdas: Vec<f64> = (0..401).map(|i| 400e-9 + 1e-9 * i as f64).collect();
    let mid = lambdas[200];
    let orders = [Pol::S, Pol::P]
        .map(|p| film.orders_for_bound(theta.cos(), mid, p, 1e-12))
        .into_iter()
        .max()
        .unwrap();
    let m = 2 * orders + 1;
    let st = TraceSettings {
        limits: EnumerationLimits {
            max_internal_reflections: m,
            max_events: 2 * m + 8,
        },
        ..TraceSettings::default()
    };
    let trace_at = |lambda: f64| {
        let optics = scene.optics(lambda).unwrap();
        let plan = trace::plan(&scene, &optics, &[DVec3::new(0.0, 0.0, 0.001)], &st.limits);
        trace::arrivals(&scene, &optics, &plan, &target, &st).0
    };
    let arrivals = trace_at(mid);
    assert!(
        arrivals.len() >= 2 * orders,
        "every order within the bound arrives"
    );
    let mut beats = Beats::default();
    beats.set(&fringe::trace::beats::vector_rays(&arrivals));
    let mut spectrum = vec![0.0; lambdas.len()];
    beats.intensities(&lambdas, &mut spectrum);
    let mut worst_airy = 0.0f64;
    let mut worst_trace = 0.0f64;
    for (k, (&l, &i)) in lambdas.iter().zip(&spectrum).enumerate() {
        let airy = 0.5
            * (film.reflectance(theta.cos(), l, Pol::S) + film.reflectance(theta.cos(), l, Pol::P));
        worst_airy = worst_airy.max((i - airy).abs());
        if k % 40 == 0 {
            let traced = trace::intensity(&trace_at(l), Fidelity::Vector);
            worst_trace = worst_trace.max((i - traced).abs());
        }
    }
    assert!(worst_airy <= 1e-12, "max |I - R_Airy| = {worst_airy:e}");
    assert!(
        worst_trace <= 1e-14,
        "max |I - I_traced(λ)| = {worst_trace:e}"
    );
}
