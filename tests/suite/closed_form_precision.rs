//! The closed forms are better conditioned than the tracer they judge: their own error against
//! an independent 50-digit evaluation (mpmath, `tools/young_mpmath.py`) is ≤ 1e-14 of the
//! profile's scale, where the same formula in plain f64 is off by up to ~1e-9 at dark fringes
//! (the phase of a 1–10 m path difference formed from two rounded distances).

use fringe::harness::analytic::young;
use glam::DVec3;

/// Rows of tests/data/young_mpmath.csv: inputs (exact binary64) and the 50-digit intensity.
fn rows() -> Vec<Vec<f64>> {
    include_str!("../data/young_mpmath.csv")
        .lines()
        .skip(1)
        .map(|l| l.split(',').map(|x| x.parse().unwrap()).collect())
        .collect()
}

#[test]
fn young_exact_is_within_1e_14_of_a_50_digit_evaluation() {
    let mut naive_worst = 0.0f64;
    for (k, r) in rows().iter().enumerate() {
        let (s1, s2, p) = (
            DVec3::new(r[0], r[1], 0.0),
            DVec3::new(r[2], r[3], 0.0),
            DVec3::new(r[4], r[5], 0.0),
        );
        let (lambda, n, f, expected) = (r[6], r[7], r[8], r[9]);
        let got = young::exact_line_sources(s1, s2, DVec3::Z, p, lambda, n, f);
        // Intensities are judged relative to the profile's largest value, 4 for Young.
        assert!(
            (got - expected).abs() <= 4e-14,
            "row {k}: actual {got:e}, expected {expected:e}, err {:e}",
            got - expected
        );
        // The same formula with distances and their difference in plain f64.
        let (r1, r2) = ((p - s1).length(), (p - s2).length());
        let cos_d = (std::f64::consts::TAU * n * (r1 - r2) / lambda).cos();
        let cos_a = (p - s1).dot(p - s2) / (r1 * r2);
        let naive = f * (2.0 + 2.0 * cos_d) + (1.0 - f) * (2.0 + 2.0 * cos_a * cos_d);
        naive_worst = naive_worst.max((naive - expected).abs());
    }
    // The data set has teeth: plain f64 misses by far more than the bound asserted above.
    assert!(naive_worst > 1e-11, "plain f64 worst error {naive_worst:e}");
}

/// The two-beam plate of a point source (paper Fig. 4 left) from normal incidence to 89.99°,
/// against a 50-digit evaluation (`tools/two_beam_mpmath.py`): ≤ 1e-14 of the largest
/// intensity (3e-14 within 0.15° of grazing, see below). (The former form, an angle from bisection and the path n1 h/cos θ + 2 n2 d/cos θt,
/// was 1e-9 to 5e-8 off near grazing: the path of a ray that misses the point by the root's
/// rounding, first order in it.)
#[test]
fn two_beam_plate_is_within_1e_14_of_a_50_digit_evaluation() {
    let rows: Vec<Vec<f64>> = include_str!("../data/two_beam_mpmath.csv")
        .lines()
        .skip(1)
        .map(|l| l.split(',').map(|x| x.parse().unwrap()).collect())
        .collect();
    let scale = rows.iter().map(|r| r[7]).fold(0.0, f64::max);
    for (k, r) in rows.iter().enumerate() {
        let plate = fringe::harness::analytic::plate::TwoBeamPlate {
            n1: r[0],
            n2: r[1],
            thickness_m: r[2],
            h_src_m: r[3],
            h_obs_m: r[4],
        };
        let got = plate.intensity_unpolarized(r[5], r[6]);
        // Known limit, measured and not yet understood: within 0.15° of grazing (89.9°, 89.99°)
        // up to 1.8e-14, not from the entry point (refining it in double-double changes
        // nothing); those rows are held to 3e-14.
        let degrees = r[5].atan2(r[3] + r[4]).to_degrees();
        let bound = if degrees > 89.85 { 3e-14 } else { 1e-14 } * scale;
        assert!(
            (got - r[7]).abs() <= bound,
            "row {k} ({degrees:.2}°): actual {got:e}, expected {:e}, err {:e}, bound {bound:e}",
            r[7],
            got - r[7]
        );
    }
}

/// Rows of a committed 50-digit data set (header skipped), inputs exact binary64.
fn data(text: &str) -> Vec<Vec<f64>> {
    text.lines()
        .skip(1)
        .map(|l| l.split(',').map(|x| x.parse().unwrap()).collect())
        .collect()
}

fn v3(r: &[f64], k: usize) -> DVec3 {
    DVec3::new(r[k], r[k + 1], r[k + 2])
}

/// Lloyd's mirror against a 50-digit image-method evaluation (`tools/lloyd_mpmath.py`): dark
/// fringes, grazing points on and just above the mirror, media, rarer mirrors near and beyond
/// the critical angle, scenes rotated and moved up to 10 m. ≤ 1e-14 of the profile's scale (the
/// largest intensity, (1 + |r_s|)² ≤ 4). The same image method in plain f64 (heights, screen
/// distance and the two hypotenuses rounded, then differenced) misses by ~1e-8.
#[test]
fn lloyd_is_within_1e_14_of_a_50_digit_evaluation() {
    let mut naive_worst = 0.0f64;
    for (k, r) in data(include_str!("../data/lloyd_mpmath.csv"))
        .iter()
        .enumerate()
    {
        let l = fringe::harness::analytic::lloyd::Lloyd {
            n1: r[15],
            n2: r[16],
            source: v3(r, 0),
            axis: v3(r, 3),
            mirror_point: v3(r, 6),
            normal: v3(r, 9),
        };
        let (p, lambda, expected) = (v3(r, 12), r[17], r[18]);
        let got = l.intensity(p, lambda);
        assert!(
            (got - expected).abs() <= 4e-14,
            "row {k}: actual {got:e}, expected {expected:e}, err {:e}",
            got - expected
        );
        // Plain f64: heights, the screen distance and both hypotenuses rounded, then
        // differenced (the former closed form).
        let (nrm, axis) = (l.normal.normalize(), l.axis.normalize());
        let h = (l.source - l.mirror_point).dot(nrm);
        let (nrm, h) = (nrm * h.signum(), h.abs());
        let y = (p - l.mirror_point).dot(nrm);
        let mut horiz = p - l.source;
        horiz -= horiz.dot(nrm) * nrm + horiz.dot(axis) * axis;
        let len = horiz.length();
        let (rd, ri) = (len.hypot(y - h), len.hypot(y + h));
        let rs = fringe::optics::fresnel::fresnel(l.n1, l.n2, (h + y) / ri).r_s;
        let naive = (fringe::harness::analytic::path_phasor(l.n1 * (ri - rd), lambda) * rs + 1.0)
            .norm_sqr();
        naive_worst = naive_worst.max((naive - expected).abs());
    }
    assert!(naive_worst > 1e-11, "plain f64 worst error {naive_worst:e}");
}

/// The Fizeau wedge against an independent 50-digit ray trace (`tools/wedge_mpmath.py`: the
/// entry point found by root finding, not the closed form's algebra): angles 1e-5°–10°,
/// thicknesses 1 µm–1 mm, screens up to 1 m above, dark fringes, media, substrates, scenes
/// rotated and moved up to 10 m. ≤ 1e-14 of the profile's scale ((|a1| + |a2|)² ≤ 1 here, so
/// absolute 1e-14). The former closed form (α, x, h_obs and the depth rounded to f64 from the
/// scene's coordinates, the path difference summed in f64) misses by ~1e-9 and more.
#[test]
fn wedge_is_within_1e_14_of_a_50_digit_evaluation() {
    let mut naive_worst = 0.0f64;
    for (k, r) in data(include_str!("../data/wedge_mpmath.csv"))
        .iter()
        .enumerate()
    {
        let w = fringe::harness::analytic::wedge::Wedge {
            n1: r[15],
            n: r[16],
            n3: r[17],
            top_point: v3(r, 0),
            top_normal: v3(r, 3),
            bottom_point: v3(r, 6),
            bottom_normal: v3(r, 9),
        };
        let (p, lambda, expected) = (v3(r, 12), r[18], r[19]);
        let got = w.intensity_s(p, lambda);
        assert!(
            (got - expected).abs() <= 1e-14,
            "row {k}: actual {got:e}, expected {expected:e}, err {:e}",
            got - expected
        );
        // Plain f64 (the former form): α, x, h_obs, t0 rounded from the scene, path in f64.
        let (nt, nb) = (w.top_normal.normalize(), w.bottom_normal.normalize());
        let a = nt.cross(nb).length().atan2(nt.dot(nb));
        let x_axis = nt.cross(nb).normalize().cross(nt);
        let (x, ho, t0) = (
            (p - w.top_point).dot(x_axis),
            (p - w.top_point).dot(nt),
            (w.top_point - w.bottom_point).dot(nt),
        );
        let psi = (w.n * (2.0 * a).sin() / w.n1).asin();
        let x_i = (x - ho * psi.tan() - t0 * (2.0 * a).tan()) / (1.0 + a.tan() * (2.0 * a).tan());
        let depth = t0 + x_i * a.tan();
        let delta = w.n * depth * (1.0 + 1.0 / (2.0 * a).cos())
            + w.n1 * ho * 2.0 * (0.5 * psi).sin().powi(2) / psi.cos();
        let f = |n1, n2, c| fringe::optics::fresnel::fresnel(n1, n2, c);
        let a2 =
            f(w.n1, w.n, 1.0).t_s * f(w.n, w.n3, a.cos()).r_s * f(w.n, w.n1, (2.0 * a).cos()).t_s;
        let naive = (f(w.n1, w.n, 1.0).r_s
            + a2 * fringe::harness::analytic::path_phasor(delta, lambda))
        .norm_sqr();
        naive_worst = naive_worst.max((naive - expected).abs());
    }
    assert!(naive_worst > 1e-11, "plain f64 worst error {naive_worst:e}");
}

/// The Airy sum against a 50-digit evaluation (`tools/airy_mpmath.py`): grazing down to
/// cos θ1 = 1e-6, near Brewster, near a substrate's critical angle, films from 1 pm to 1 mm,
/// high index contrast, media. R and T (≤ 1) each within 1e-14. The round-trip phase
/// 4π n2 d cos θ2/λ in plain f64 (the former form) carries ~1e-16 × β, ~1e-12 rad for a 1 mm
/// film, and misses by more than 1e-13 on the same data.
#[test]
fn airy_is_within_1e_14_of_a_50_digit_evaluation() {
    use fringe::harness::analytic::plate::{Film, Pol};
    let mut naive_worst = 0.0f64;
    for (k, r) in data(include_str!("../data/airy_mpmath.csv"))
        .iter()
        .enumerate()
    {
        let film = Film {
            n1: r[0],
            n2: r[1],
            n3: r[2],
            thickness_m: r[3],
        };
        let (c1, lambda) = (r[4], r[5]);
        let pol = if r[6] == 0.0 { Pol::S } else { Pol::P };
        let (got_r, got_t) = (
            film.reflectance(c1, lambda, pol),
            film.transmittance(c1, lambda, pol),
        );
        for (what, got, expected) in [("R", got_r, r[7]), ("T", got_t, r[8])] {
            assert!(
                (got - expected).abs() <= 1e-14,
                "row {k} {what}: actual {got:e}, expected {expected:e}, err {:e}",
                got - expected
            );
        }
        // Plain f64 round-trip phase (the former form).
        let a = film.terms(c1, lambda, pol);
        let e = num_complex::Complex64::from_polar(1.0, a.beta);
        let naive = (a.r12 + a.t12 * a.t21 * a.r23 * e / (1.0 - a.r21 * a.r23 * e)).norm_sqr();
        naive_worst = naive_worst.max((naive - r[7]).abs());
    }
    assert!(naive_worst > 1e-13, "plain f64 worst error {naive_worst:e}");
}

/// The optical path of a plane wave through a TIR prism (entry refraction, internal reflection,
/// exit refraction), which `plane_wave_beams` (TIR interference, the Fresnel rhomb) builds its
/// beams from, against a 50-digit evaluation (`tools/plane_wave_mpmath.py`): beams tilted off the
/// entry normal, glass in air and water, scenes rotated and moved up to 10 m. The phase
/// 2π Op/λ at a point ~6 cm away within 1e-14 rad (the phasor within 1e-14); the same sum with
/// directions and lengths in plain f64 misses by ~1e-11 rad.
#[test]
fn plane_wave_path_is_within_1e_14_rad_of_a_50_digit_evaluation() {
    use fringe::harness::analytic::tir::{Face, plane_wave_path};
    let mut naive_worst = 0.0f64;
    for (k, r) in data(include_str!("../data/plane_wave_mpmath.csv"))
        .iter()
        .enumerate()
    {
        let faces: Vec<Face> = (0..3)
            .map(|f| {
                let b = 7 + 9 * f;
                Face {
                    point: v3(r, b),
                    normal: v3(r, b + 3),
                    n_before: r[b + 6],
                    n_after: r[b + 7],
                    reflect: r[b + 8] != 0.0,
                }
            })
            .collect();
        let (u0, r0, n0, x, lambda) = (v3(r, 0), v3(r, 3), r[6], v3(r, 34), r[37]);
        let expected = num_complex::Complex64::new(r[38], r[39]);
        let (op, _) = plane_wave_path(u0, r0, n0, &faces, x).unwrap();
        let got = fringe::harness::analytic::precise::path_phasor(op, lambda);
        assert!(
            (got - expected).norm() <= 1e-14,
            "row {k}: actual {got}, expected {expected}, err {:e}",
            (got - expected).norm()
        );
        // Plain f64: directions by fresnel::refract/reflect, lengths summed in f64.
        let (mut u, mut q, mut n, mut op) = (u0.normalize(), r0, n0, 0.0);
        for f in &faces {
            op += n * u.dot(f.point - q);
            q = f.point;
            let m = f.normal.normalize();
            if f.reflect {
                u = fringe::optics::fresnel::reflect(u, m);
            } else {
                u = fringe::optics::fresnel::refract(u, m, f.n_before, f.n_after).unwrap();
                n = f.n_after;
            }
        }
        op += n * u.dot(x - q);
        let naive = fringe::harness::analytic::path_phasor(op, lambda);
        naive_worst = naive_worst.max((naive - expected).norm());
    }
    assert!(naive_worst > 1e-13, "plain f64 worst error {naive_worst:e}");
}
