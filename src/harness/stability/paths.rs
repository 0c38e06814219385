//! The path rows of the stability sweep: two collinear point sources whose exact path difference
//! is their offset, from 1 nm to 10 m, and the illustration of phases formed from absolute paths
//! stored in f64 or binary32 ([`round_to_binary32`]).

use super::*;

/// Round an f64 to the nearest IEEE 754 binary32 value (round to nearest, ties to even), on f64
/// bits: the significand is rounded to 24 bits (to the fixed spacing 2^-149 below 2^-126, where
/// binary32 is subnormal), and magnitudes that round to 2^128 or beyond become infinite. NaN and
/// infinities pass through.
///
/// Rounding an exactly computed f64 value to 24 bits is what storing it in binary32 does.
/// Moreover, for +, −, ×, ÷ of two binary32 values, the f64 result rounded here is exactly the
/// binary32 result (53 ≥ 2·24 + 2: double rounding is innocuous; Figueroa, "When is double
/// rounding innocuous?", SIGNUM Newsl. 30(3), 1995).
///
/// Method: with e = ⌊log2 |x|⌋ (from the exponent bits; at least −126), the spacing of binary32
/// values near x is q = 2^(e−23); x/q and the product by q are exact power-of-two scalings, so
/// `(x/q).round_ties_even()·q` is the correctly rounded value (a carry to 2^(e+1) included).
pub fn round_to_binary32(x: f64) -> f64 {
    if !x.is_finite() || x == 0.0 {
        return x;
    }
    let biased = ((x.to_bits() >> 52) & 0x7ff) as i32;
    // f64 subnormals (biased 0) are far below binary32's smallest subnormal: e = −126 suffices.
    let e = (biased - 1023).max(-126);
    let q = f64::from_bits(((e - 23 + 1023) as u64) << 52);
    let r = (x / q).round_ties_even() * q;
    if r.abs() >= 2f64.powi(128) {
        f64::INFINITY.copysign(x)
    } else {
        r
    }
}

/// The path lengths of the plot: 1, 2, 5 per decade from 1 nm to 10 m.
pub(crate) fn path_grid() -> Vec<f64> {
    let mut g = Vec::new();
    for e in -9..=0 {
        for m in [1.0, 2.0, 5.0] {
            g.push(m * 10f64.powi(e));
        }
    }
    g.push(10.0);
    g
}

/// The path differences Δs_j = 1e-7·max(s, 1 µm)·(1 + j/K), j < K (the offsets of the tests,
/// spread over a factor 2 so the rounding of s + Δs samples a whole spacing of binary32).
fn path_offsets(path_m: f64) -> Vec<f64> {
    let base = 1e-7 * path_m.max(1e-6);
    (0..PATH_OFFSETS)
        .map(|j| base * (1.0 + j as f64 / PATH_OFFSETS as f64))
        .collect()
}

/// Two coherent, linearly polarized unit point sources in vacuum on the x axis, at 0 and at
/// −`offset_m`: at a point (s, 0, 0) their optical paths differ by exactly `offset_m`.
pub fn collinear_sources(offset_m: f64) -> Scene {
    let mut scene = Scene::new(Medium::vacuum());
    for (k, x) in [0.0, offset_m].into_iter().enumerate() {
        scene.sources.push(Source {
            name: format!("s{k}"),
            emitter: Emitter::Point {
                position: DVec3::new(-x, 0.0, 0.0),
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
    scene
}

/// fringe's traced path difference for [`collinear_sources`] at the point (s, 0, 0): the exact
/// difference is Δs (collinear). Formed in double-double, rounded once; with
/// [`PathArithmetic::AbsoluteF64`] from the two paths rounded to f64 first.
fn traced_path_difference(path_m: f64, offset_m: f64, arithmetic: PathArithmetic) -> f64 {
    let scene = collinear_sources(offset_m);
    let p = DVec3::new(path_m, 0.0, 0.0);
    let Ok(optics) = scene.optics(WAVELENGTH_M) else {
        return f64::NAN;
    };
    let limits = EnumerationLimits::default();
    let plan = trace::plan(&scene, &optics, &[p], &limits);
    let (arr, _) = trace::arrivals(
        &scene,
        &optics,
        &plan,
        &Target::Point(p),
        &TraceSettings::default(),
    );
    let arr = hold(arr, arithmetic);
    let path_of = |source: usize| {
        arr.iter()
            .find(|a| a.source == source)
            .map(|a| a.vector.optical_path)
    };
    match (path_of(1), path_of(0)) {
        (Some(a), Some(b)) => (a - b).to_f64(),
        _ => f64::NAN,
    }
}

/// Two-beam phase from absolute paths: each path as `store` keeps it, φ_k = (2π/λ)·s_k in f64,
/// then φ2 − φ1. The second path is s + Δs as an f64 program computes it.
fn absolute_phase_difference(path_m: f64, offset_m: f64, store: impl Fn(f64) -> f64) -> f64 {
    let k = TAU / WAVELENGTH_M;
    let s1 = store(path_m);
    let s2 = store(path_m + offset_m);
    k * s2 - k * s1
}

/// The three methods' phase errors at each path length (worst over `PATH_OFFSETS`). The exact
/// phase 2πΔs/λ is rounded once (relative 1e-16), orders of magnitude below every error shown.
pub fn path_points(paths_m: &[f64]) -> Vec<PathPoint> {
    path_points_with(paths_m, PathArithmetic::DoubleDouble)
}

/// [`path_points`] with the traced paths held as `arithmetic` says.
pub(crate) fn path_points_with(paths_m: &[f64], arithmetic: PathArithmetic) -> Vec<PathPoint> {
    paths_m
        .iter()
        .map(|&s| {
            let mut worst = [(f64::NEG_INFINITY, 0.0, 0.0); 3];
            for ds in path_offsets(s) {
                let exact = TAU * ds / WAVELENGTH_M;
                let traced = traced_path_difference(s, ds, arithmetic);
                // Differences in metres first: |Δs_traced − Δs| is exact for nearby values.
                let fringe_err = TAU * (traced - ds).abs() / WAVELENGTH_M;
                let fringe_phase = TAU * traced / WAVELENGTH_M;
                let f64_phase = absolute_phase_difference(s, ds, |x| x);
                let b32_phase = absolute_phase_difference(s, ds, round_to_binary32);
                let errs = [
                    (fringe_err, fringe_phase),
                    ((f64_phase - exact).abs(), f64_phase),
                    ((b32_phase - exact).abs(), b32_phase),
                ];
                for (w, (err, phase)) in worst.iter_mut().zip(errs) {
                    // NaN is the worst value and stays.
                    if !w.0.is_nan() && (err.is_nan() || err > w.0) {
                        *w = (err, phase, exact);
                    }
                }
            }
            PathPoint {
                path_m: s,
                fringe_rad: worst[0].0,
                f64_absolute_rad: worst[1].0,
                binary32_absolute_rad: worst[2].0,
                fringe_worst: (worst[0].1, worst[0].2),
                f64_absolute_worst: (worst[1].1, worst[1].2),
                binary32_absolute_worst: (worst[2].1, worst[2].2),
            }
        })
        .collect()
}

/// A length with a readable unit: 1 nm, 100 µm, 10 mm, 1 m.
fn length_label(m: f64) -> String {
    let (v, unit) = if m < 1e-6 {
        (m * 1e9, "nm")
    } else if m < 1e-3 {
        (m * 1e6, "µm")
    } else if m < 1.0 {
        (m * 1e3, "mm")
    } else {
        (m, "m")
    };
    format!("{} {unit}", (v * 1e6).round() / 1e6)
}

/// Rows of the path sweep at whole decades: fringe judged, the two absolute-phase variants
/// for information.
pub(super) fn path_rows(
    rows: &mut Vec<StabilityRow>,
    points: &[PathPoint],
    arithmetic: PathArithmetic,
) {
    for p in points {
        let mantissa = p.path_m / 10f64.powf(p.path_m.log10().round());
        if (mantissa - 1.0).abs() > 1e-9 {
            continue;
        }
        let offsets = path_offsets(p.path_m);
        let cond = |what: &str| {
            format!(
                "s = {}, Δs from {:.0e} to {:.1e} m; {what}",
                length_label(p.path_m),
                offsets[0],
                offsets[PATH_OFFSETS - 1],
            )
        };
        let q = format!("two-beam phase 2πΔs/λ (rad), worst of {PATH_OFFSETS} Δs");
        rows.push(StabilityRow::new(
            "paths",
            cond(match arithmetic {
                PathArithmetic::DoubleDouble => {
                    "fringe: traced, paths differenced in double-double"
                }
                PathArithmetic::AbsoluteF64 => "naive build: traced, absolute paths rounded to f64",
            }),
            &q,
            p.fringe_worst.0,
            p.fringe_worst.1,
            DeviationKind::Absolute,
            Some(PATH_PHASE_TOLERANCE_RAD),
        ));
        for (what, (phase, exact)) in [
            ("absolute phases from f64 paths", p.f64_absolute_worst),
            (
                "absolute phases from binary32 paths",
                p.binary32_absolute_worst,
            ),
        ] {
            rows.push(StabilityRow::new(
                "precision illustration",
                cond(what),
                &q,
                phase,
                exact,
                DeviationKind::Absolute,
                None,
            ));
        }
    }
}
