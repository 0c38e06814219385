//! The film rows of the stability sweep: films from 1 pm to 1 mm summed bounce by bounce against
//! the Airy sum, truncated sums (finesse) against the truncated closed form, and seeded random
//! films (every number finite, R + T = 1).

use super::interface::{DEFAULT_REFERENCE, plane_wave_at, pol_angle};
use super::*;

/// The far-field reflectance (or transmittance) of a film n1 | n2 (thickness d, m) | n3 lit by
/// a plane wave at `theta` (rad) of vacuum wavelength `lambda_m`, traced at `vector` fidelity
/// with `internal` internal reflections, for linear polarization at `pol_angle` (rad) from s;
/// NaN when the scene has no optics at `lambda_m` or the transmitted direction does not exist.
pub fn traced_film(
    n: [f64; 3],
    d: f64,
    theta: f64,
    lambda_m: f64,
    pol_angle: f64,
    internal: usize,
    reflected: bool,
) -> f64 {
    traced_film_with(
        n,
        d,
        theta,
        (lambda_m, pol_angle),
        internal,
        reflected,
        DEFAULT_REFERENCE,
        PathArithmetic::DoubleDouble,
    )
}

/// [`traced_film`] with the plane wave's phase (and far-field wavefront) referred to
/// `reference` and the traced paths held as `arithmetic` says; `(λ, polarization angle)`.
#[allow(clippy::too_many_arguments)]
pub fn traced_film_with(
    n: [f64; 3],
    d: f64,
    theta: f64,
    (lambda_m, pol_angle): (f64, f64),
    internal: usize,
    reflected: bool,
    reference: DVec3,
    arithmetic: PathArithmetic,
) -> f64 {
    let mut scene = Scene::new(Medium::constant("n1", n[0]));
    scene.add_plate(
        "film",
        DVec3::ZERO,
        DVec3::Z,
        d,
        Medium::constant("n1", n[0]),
        Medium::constant("n2", n[1]),
        Medium::constant("n3", n[2]),
    );
    scene
        .sources
        .push(plane_wave_at(theta, pol_angle, reference));
    let Ok(optics) = scene.optics(lambda_m) else {
        return f64::NAN;
    };
    let d_in = DVec3::new(theta.sin(), 0.0, -theta.cos());
    let dir = if reflected {
        DVec3::new(theta.sin(), 0.0, theta.cos())
    } else {
        match fresnel::refract(d_in, DVec3::Z, n[0], n[2]) {
            Some(d) => d,
            None => return f64::NAN,
        }
    };
    let target = Target::Direction { dir, reference };
    let limits = EnumerationLimits {
        max_internal_reflections: internal,
        max_events: 2 * internal + 4,
    };
    let plan = trace::plan(&scene, &optics, &[reference], &limits);
    let st = TraceSettings {
        limits,
        ..Default::default()
    };
    let (arr, _) = trace::arrivals(&scene, &optics, &plan, &target, &st);
    let i = trace::intensity(&hold(arr, arithmetic), Fidelity::Vector);
    if reflected {
        i
    } else {
        // Far-field |E|² of the transmitted plane wave → power ratio (n3 cos θ3)/(n1 cos θ1).
        i * n[2] * dir.z.abs() / (n[0] * theta.cos())
    }
}

/// The internal reflections that bring the Airy tail of `film` at `theta` below 1e-15 for
/// both polarizations (2 per reflected order, plus one), at most the case cap 2000 + 1.
fn internal_for(film: &Film, theta: f64) -> usize {
    let orders = [Pol::S, Pol::P]
        .into_iter()
        .map(|p| film.orders_for_bound(theta.cos(), WAVELENGTH_M, p, 1e-15))
        .max()
        .unwrap_or(1);
    (2 * orders + 1).min(2001)
}

/// Films 1 pm … 1 mm (air | 1.5 | 1.33) at 0, 1 rad and 89.9° (grazing) against Airy, bounce
/// counts from the tail bound; the 1 µm film with the wave's phase reference 100 m away (a
/// global phase, it must cancel); and R → the bare interface's value as d → 0.
pub(super) fn film_rows(rows: &mut Vec<StabilityRow>, arithmetic: PathArithmetic) {
    let g = "films";
    let n = [1.0, 1.5, 1.33];
    let film_of = |d: f64| Film {
        n1: n[0],
        n2: n[1],
        n3: n[2],
        thickness_m: d,
    };
    let grazing = 89.9f64.to_radians();
    for d in [1e-12, 1e-10, 1e-8, 1e-6, 1e-3] {
        let film = film_of(d);
        for (theta, angle) in [(0.0f64, "0"), (1.0, "1 rad"), (grazing, "89.9°")] {
            let internal = internal_for(&film, theta);
            for pol in [Pol::S, Pol::P] {
                rows.push(StabilityRow::new(
                    g,
                    format!(
                        "d = {d:.0e} m, θ = {angle}, {}, 1 | 1.5 | 1.33, {internal} internal reflections (tail < 1e-15)",
                        pol_name(pol)
                    ),
                    "R (Airy)",
                    traced_film_with(
                        n,
                        d,
                        theta,
                        (WAVELENGTH_M, pol_angle(pol)),
                        internal,
                        true,
                        DEFAULT_REFERENCE,
                        arithmetic,
                    ),
                    film.reflectance(theta.cos(), WAVELENGTH_M, pol),
                    DeviationKind::Relative,
                    Some(film_tolerance(&film, theta.cos(), WAVELENGTH_M, pol)),
                ));
            }
        }
    }
    // A global phase: the wave's reference point 100 m above the film.
    let (d, theta) = (1e-6, 80f64.to_radians());
    let film = film_of(d);
    let internal = internal_for(&film, theta);
    for (z, label) in [(1e-3, "1 mm"), (100.0, "100 m")] {
        rows.push(StabilityRow::new(
            g,
            format!(
                "d = 1 µm, θ = 80°, s, reference point of the wave {label} above the film (a global phase)"
            ),
            "R (Airy)",
            traced_film_with(
                n,
                d,
                theta,
                (WAVELENGTH_M, pol_angle(Pol::S)),
                internal,
                true,
                DVec3::new(0.0, 0.0, z),
                arithmetic,
            ),
            film.reflectance(theta.cos(), WAVELENGTH_M, Pol::S),
            DeviationKind::Relative,
            Some(film_tolerance(&film, theta.cos(), WAVELENGTH_M, Pol::S)),
        ));
    }
    // d → 0: the 1 pm film's R tends to the bare 1 | 1.33 interface's, with the first-order
    // slope of the Airy sum: |R(1 pm) − R(0)| is O(d/λ), far above rounding, and
    // R(1 pm) − R_bare agrees with the Airy difference (continuity, no film that vanishes).
    let theta: f64 = 0.5;
    let bare = {
        let r0 = Film {
            n1: n[0],
            n2: n[2],
            n3: n[2],
            thickness_m: 0.0,
        };
        r0.reflectance(theta.cos(), WAVELENGTH_M, Pol::S)
    };
    let film = film_of(1e-12);
    let traced = traced_film_with(
        n,
        1e-12,
        theta,
        (WAVELENGTH_M, pol_angle(Pol::S)),
        internal_for(&film, theta),
        true,
        DEFAULT_REFERENCE,
        arithmetic,
    );
    rows.push(StabilityRow::new(
        g,
        "d = 1 pm vs d = 0, θ = 0.5 rad, s: R(1 pm) − R(bare 1 | 1.33 interface)".to_string(),
        "ΔR (Airy)",
        traced - bare,
        film.reflectance(theta.cos(), WAVELENGTH_M, Pol::S) - bare,
        DeviationKind::Relative,
        // 1e-6 plus the rounding of the traced R itself, 16ε·R (the sum of ~20 beams, as in
        // `film_tolerance`), relative to ΔR ~ 2e-11: the tracer's R(1 pm) is ~5e-17 off a
        // 50-digit Airy sum, which the Stokes-form closed form meets to 2e-18 (a closed form
        // that summed the series as the tracer does shared its rounding and hid it).
        Some(
            1e-6 + 16.0 * f64::EPSILON * bare
                / (film.reflectance(theta.cos(), WAVELENGTH_M, Pol::S) - bare).abs(),
        ),
    ));
}

/// High finesse: 1 | 1.5 | 1 film, 1 µm, 85°, s: the traced sum truncated after N reflected
/// orders against the closed-form truncated sum (`Film::r_truncated`, the geometric series
/// summed independently) at 1e-12 relative, and the tail bound checked for honesty: the
/// truncated closed form's distance to the full Airy sum never exceeds 2|r|τ + τ².
pub(super) fn finesse_rows(rows: &mut Vec<StabilityRow>, arithmetic: PathArithmetic) {
    let g = "finesse";
    let film = Film {
        n1: 1.0,
        n2: 1.5,
        n3: 1.0,
        thickness_m: 1e-6,
    };
    let theta = 85f64.to_radians();
    let c = theta.cos();
    let r = film.r(c, WAVELENGTH_M, Pol::S).norm();
    let exact = r * r;
    let auto = film.orders_for_bound(c, WAVELENGTH_M, Pol::S, 1e-15);
    for orders in [2usize, 5, 10, 20, 40, auto] {
        // 2N − 1 internal reflections reach reflected order N (N round trips): N + 1 beams
        // with order 0, the top face's reflection.
        let beams = orders + 1;
        let truncated = film.r_truncated(c, WAVELENGTH_M, Pol::S, beams).norm_sqr();
        let traced = traced_film_with(
            [1.0, 1.5, 1.0],
            1e-6,
            theta,
            (WAVELENGTH_M, 0.0),
            2 * orders - 1,
            true,
            DEFAULT_REFERENCE,
            arithmetic,
        );
        rows.push(StabilityRow::new(
            g,
            format!("1 | 1.5 | 1, d = 1 µm, θ = 85°, s, orders 0 to N = {orders}"),
            "R truncated (closed-form partial sum)",
            traced,
            truncated,
            DeviationKind::Relative,
            Some(FILM_TOLERANCE),
        ));
        let tau = film.r_tail_bound(c, WAVELENGTH_M, Pol::S, beams);
        let bound = 2.0 * r * tau + tau * tau;
        rows.push(StabilityRow::new(
            g,
            format!(
                "orders 0 to N = {orders}: |R_N − R| ≤ tail bound 2|r|τ + τ² = {bound:.3e} (closed forms)"
            ),
            "R_N − R vs tail bound",
            (truncated - exact).abs(),
            0.0,
            DeviationKind::Absolute,
            Some(bound * (1.0 + 1e-9) + 1e-16),
        ));
    }
    rows.push(StabilityRow::new(
        g,
        format!("N = {auto} orders (tail bound < 1e-15): traced R against the full Airy sum"),
        "R (Airy)",
        traced_film_with(
            [1.0, 1.5, 1.0],
            1e-6,
            theta,
            (WAVELENGTH_M, 0.0),
            2 * auto - 1,
            true,
            DEFAULT_REFERENCE,
            arithmetic,
        ),
        exact,
        DeviationKind::Relative,
        Some(FILM_TOLERANCE),
    ));
}

/// A small deterministic generator (SplitMix64) for the random films.
struct SplitMix(u64);

impl SplitMix {
    fn next_unit(&mut self) -> f64 {
        self.0 = self.0.wrapping_add(0x9e37_79b9_7f4a_7c15);
        let mut z = self.0;
        z = (z ^ (z >> 30)).wrapping_mul(0xbf58_476d_1ce4_e5b9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94d0_49bb_1331_11eb);
        z ^= z >> 31;
        (z >> 11) as f64 / (1u64 << 53) as f64
    }
    fn range(&mut self, a: f64, b: f64) -> f64 {
        a + (b - a) * self.next_unit()
    }
}

/// Seeded random valid films: every traced R, T finite and R + T = 1 with the bounce count
/// from the Airy tail bound (the proptest of tests/suite/stability.rs, as one row).
pub(super) fn random_film_rows(rows: &mut Vec<StabilityRow>, arithmetic: PathArithmetic) {
    const SCENES: usize = 32;
    let mut rng = SplitMix(6);
    let mut worst = 0.0f64;
    let mut worst_at = String::new();
    for _ in 0..SCENES {
        let n2 = rng.range(1.0, 4.0);
        let n3 = rng.range(1.0, 4.0);
        let d = 10f64.powf(rng.range(-10.0, -3.0));
        let theta = rng.range(0.0, 1.55);
        let pol = rng.range(0.0, 3.2);
        let film = Film {
            n1: 1.0,
            n2,
            n3,
            thickness_m: d,
        };
        let orders = [Pol::S, Pol::P]
            .into_iter()
            .map(|p| film.orders_for_bound(theta.cos(), WAVELENGTH_M, p, 1e-12))
            .max()
            .unwrap_or(1);
        let internal = (2 * orders + 1).min(2001);
        let trace = |reflected| {
            traced_film_with(
                [1.0, n2, n3],
                d,
                theta,
                (WAVELENGTH_M, pol),
                internal,
                reflected,
                DEFAULT_REFERENCE,
                arithmetic,
            )
        };
        let r = trace(true);
        let transmits = fresnel::refract(
            DVec3::new(theta.sin(), 0.0, -theta.cos()),
            DVec3::Z,
            1.0,
            n3,
        )
        .is_some();
        let t = if transmits { trace(false) } else { 0.0 };
        // A NaN anywhere makes the sum NaN, and NaN is the worst value.
        let dev = (r + t - 1.0).abs();
        if dev.is_nan() || dev > worst || worst_at.is_empty() {
            worst_at = format!(
                "n2 {n2:.3}, n3 {n3:.3}, d {d:.2e} m, θ {theta:.3} rad, R {r:.6}, T {t:.6}"
            );
            if dev.is_nan() {
                worst = f64::NAN;
                break;
            }
            worst = dev;
        }
    }
    rows.push(StabilityRow::new(
        "random films",
        format!(
            "{SCENES} seeded films 1 | n2 | n3, n ∈ [1, 4), d ∈ [0.1 nm, 1 mm), θ ∈ [0, 1.55] rad, \
             any linear polarization, orders from ε = 1e-12; worst: {worst_at}"
        ),
        "R + T (finite, lossless)",
        1.0 + worst,
        1.0,
        DeviationKind::Absolute,
        Some(1e-9),
    ));
}
