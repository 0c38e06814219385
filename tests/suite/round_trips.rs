//! Round trips (`trace::round_trips`): the orders of a plane wave between two parallel faces,
//! each further order the one before after one exactly applied round trip, must be the orders
//! the general far-field walk traces (`trace::arrivals`), ray by ray and in intensity to 1e-14,
//! for several wavelengths, order counts, angles, s/p/unpolarized light, reflected and
//! transmitted, free-standing plates and films on substrates; a dispersive (N-BK7, Sellmeier)
//! spectrum must match the Airy closed form (B&W §7.6.1, evaluated by `Film`, not the tracer)
//! to 1e-12 at every wavelength; and wherever the round trips do not hold (point targets,
//! point sources, non-parallel faces, a third surface, finite coherence length) the general
//! walk must run.

use fringe::accumulate::Accumulator;
use fringe::accumulate::fidelity::Fidelity;
use fringe::harness::analytic::plate::{Film, Pol};
use fringe::optics::material::{Dispersion, Medium};
use fringe::scene::Scene;
use fringe::scene::geometry::{Extent, Plane, Rect};
use fringe::scene::source::{Emitter, Polarization, Source};
use fringe::scene::{Surface, SurfaceKind};
use fringe::trace::beats::Beats;
use fringe::trace::path::{EnumerationLimits, Target};
use fringe::trace::round_trips::{self, Route};
use fringe::trace::{self, TraceSettings};
use glam::DVec3;

const PROBES: [DVec3; 1] = [DVec3::new(0.0, 0.0, 0.001)];

fn bk7() -> Medium {
    Medium {
        name: "N-BK7".into(),
        dispersion: Dispersion::bk7(),
    }
}

#[derive(Clone, Copy, Debug)]
enum Light {
    S,
    P,
    Unpolarized,
}

/// A film (`film` top face at z = 0, normal +z) between `above` and `below`, lit from above
/// at `theta` in the x–z plane, observed in the far field: the specular reflection, or the
/// transmitted direction into `below` (index `n_below` there).
fn film_scene(
    theta: f64,
    (above, film, below): (Medium, Medium, Medium),
    thickness_m: f64,
    light: Light,
    transmitted: Option<f64>,
) -> (Scene, Target) {
    let mut scene = Scene::new(above.clone());
    scene.add_plate(
        "film",
        DVec3::ZERO,
        DVec3::Z,
        thickness_m,
        above,
        film,
        below,
    );
    let (s, c) = theta.sin_cos();
    let polarization = match light {
        Light::S => Polarization::Linear {
            reference: DVec3::Y,
            angle_rad: 0.0,
        },
        Light::P => Polarization::Linear {
            reference: DVec3::X,
            angle_rad: 0.0,
        },
        Light::Unpolarized => Polarization::Unpolarized,
    };
    scene.sources.push(Source {
        name: "beam".into(),
        emitter: Emitter::PlaneWave {
            direction: DVec3::new(s, 0.0, -c),
            reference_point: DVec3::new(0.0, 0.0, 0.001),
        },
        polarization,
        intensity: 1.0,
        coherence_group: 0,
        coherence_length_m: f64::INFINITY,
    });
    let target = match transmitted {
        None => Target::Direction {
            dir: DVec3::new(s, 0.0, c),
            reference: DVec3::new(0.0, 0.0, 0.001),
        },
        Some(n_below) => {
            let s3 = s / n_below;
            Target::Direction {
                dir: DVec3::new(s3, 0.0, -(1.0 - s3 * s3).sqrt()),
                reference: DVec3::new(0.0, 0.0, -0.001),
            }
        }
    };
    (scene, target)
}

/// Media above, inside and below a film; its thickness (m); the index of the transmitted
/// target's medium, `None` for the reflected one.
type Stack = ((Medium, Medium, Medium), f64, Option<f64>);

fn settings(m: usize) -> TraceSettings {
    TraceSettings {
        limits: EnumerationLimits {
            max_internal_reflections: m,
            max_events: 2 * m + 8,
        },
        ..TraceSettings::default()
    }
}

/// The spectrum `round_trips::spectrum` traces at the probe over `lambdas`, and its route.
fn spectrum_of(
    scene: &Scene,
    target: &Target,
    st: &TraceSettings,
    lambdas: &[f64],
) -> (Route, Vec<f64>) {
    let mut out = vec![0.0; lambdas.len()];
    let route = round_trips::spectrum(
        scene,
        &PROBES,
        target,
        st,
        lambdas,
        &mut Beats::default(),
        &mut out,
    )
    .unwrap();
    (route, out)
}

fn walk(scene: &Scene, lambda: f64, target: &Target, st: &TraceSettings) -> Vec<trace::Arrival> {
    let optics = scene.optics(lambda).unwrap();
    let plan = trace::plan(scene, &optics, &PROBES, &st.limits);
    trace::arrivals(scene, &optics, &plan, target, st).0
}

/// Every case: the round-trip rays against the general walk's, ray by ray, and the intensity.
#[test]
fn round_trips_equal_the_general_walk() {
    let c = |n: f64| Medium::constant("m", n);
    let v = Medium::vacuum;
    let mut cases = 0;
    let mut worst_field = 0.0f64;
    let mut worst_path = 0.0f64;
    let mut worst_i = 0.0f64;
    // (media, thickness, transmitted-into index)
    let stacks: Vec<Stack> = vec![
        ((v(), c(1.7), v()), 3.217e-6, None),
        ((v(), c(1.7), v()), 3.217e-6, Some(1.0)),
        ((v(), bk7(), v()), 2e-6, None),
        // Films on substrates: a low-index film on glass, a high-index film on glass.
        ((v(), c(1.38), c(1.52)), 0.41e-6, None),
        ((v(), c(1.38), c(1.52)), 0.41e-6, Some(1.52)),
        ((v(), c(2.3), c(1.52)), 1.3e-6, None),
        ((v(), c(2.3), c(1.52)), 1.3e-6, Some(1.52)),
    ];
    for (media, d, transmitted) in &stacks {
        for theta_deg in [0.5, 35.0, 72.0] {
            for light in [Light::S, Light::P, Light::Unpolarized] {
                for m in [9usize, 27, 60] {
                    for lambda in [400e-9, 550e-9, 800e-9] {
                        let theta = f64::to_radians(theta_deg);
                        let (scene, target) =
                            film_scene(theta, media.clone(), *d, light, *transmitted);
                        let st = settings(m);
                        let optics = scene.optics(lambda).unwrap();
                        let mut fast = round_trips::rays(&scene, &optics, &PROBES, &target, &st)
                            .unwrap_or_else(|e| {
                                panic!("{media:?} {theta_deg}° {light:?}: refused: {e}")
                            });
                        let arrivals = walk(&scene, lambda, &target, &st);
                        let mut general = round_trips::far_field_rays(&arrivals);
                        // The same rays, compared by optical path (the walk's depth-first order
                        // and the round trips' order differ; the order of a sum only moves its
                        // rounding, which the intensity check below bounds).
                        let key = |r: &round_trips::FarFieldRay| {
                            (r.optical_path.hi, r.optical_path.lo, r.coherence_id)
                        };
                        fast.sort_by(|a, b| key(a).partial_cmp(&key(b)).unwrap());
                        general.sort_by(|a, b| key(a).partial_cmp(&key(b)).unwrap());
                        let what = format!(
                            "n {:?}, d {d:e}, {theta_deg}°, {light:?}, m {m}, λ {lambda:e}, \
                             transmitted {transmitted:?}",
                            optics.surfaces
                        );
                        assert_eq!(fast.len(), general.len(), "{what}: ray count");
                        assert!(general.len() >= 2, "{what}: orders arrive");
                        let scale = general
                            .iter()
                            .flat_map(|r| r.field.iter().map(|x| x.norm()))
                            .fold(0.0f64, f64::max);
                        for (k, (f, g)) in fast.iter().zip(&general).enumerate() {
                            assert_eq!(f.coherence_id, g.coherence_id, "{what}: ray {k} id");
                            let de = (0..3)
                                .map(|i| (f.field[i] - g.field[i]).norm())
                                .fold(0.0f64, f64::max);
                            let dp = (f.optical_path - g.optical_path).to_f64().abs();
                            worst_field = worst_field.max(de / scale);
                            worst_path = worst_path.max(dp / lambda);
                            // A few rounding errors per round trip (k ≤ 61 of them).
                            assert!(
                                de <= 1e-14 * scale,
                                "{what}: ray {k}: field off by {de:e} (scale {scale:e})"
                            );
                            // The walk's path is traced segment by segment from f64 points;
                            // ΔS is 2 d n cos θ in double-double: agree to 1e-12 cycles.
                            assert!(
                                dp <= 1e-12 * lambda,
                                "{what}: ray {k}: optical path off by {dp:e} m"
                            );
                        }
                        let i_fast = round_trips::intensity(&fast, lambda, &mut Accumulator::new());
                        let i_walk = trace::intensity(&arrivals, Fidelity::Vector);
                        let di = (i_fast - i_walk).abs();
                        worst_i = worst_i.max(di);
                        assert!(
                            di <= 1e-14,
                            "{what}: intensity {i_fast:e} vs walk {i_walk:e}, err {di:e}"
                        );
                        cases += 1;
                    }
                }
            }
        }
    }
    eprintln!(
        "{cases} cases: worst field {worst_field:e} (relative), path {worst_path:e} cycles, \
         intensity {worst_i:e}"
    );
}

/// The orders for the amplitude tail bound ε at every wavelength of `lambdas` (the most).
fn internal_for_bound(film_at: impl Fn(f64) -> Film, cos: f64, lambdas: &[f64], eps: f64) -> usize {
    let orders = lambdas
        .iter()
        .flat_map(|&l| [Pol::S, Pol::P].map(|p| film_at(l).orders_for_bound(cos, l, p, eps)))
        .max()
        .unwrap();
    2 * orders + 1
}

/// N-BK7 (Sellmeier) plate, 3.217 µm, 35°, unpolarized, 401 wavelengths 400–800 nm, traced at
/// every wavelength by round trips, orders to the tail bound ε = 1e-12: the Airy reflectance
/// (R_s + R_p)/2 and transmittance (T_s + T_p)/2 with n(λ) from the Sellmeier formula, to 1e-12
/// at every wavelength.
#[test]
fn dispersive_spectrum_matches_airy_bk7() {
    let theta = 35f64.to_radians();
    let d = 3.217e-6;
    let lambdas: Vec<f64> = (0..401).map(|i| 400e-9 + 1e-9 * i as f64).collect();
    let n_of = |l: f64| bk7().index(l).unwrap();
    let film_at = |l: f64| Film {
        n1: 1.0,
        n2: n_of(l),
        n3: 1.0,
        thickness_m: d,
    };
    let m = internal_for_bound(film_at, theta.cos(), &lambdas, 1e-12);
    let st = settings(m);
    for transmitted in [None, Some(1.0)] {
        let (scene, target) = film_scene(
            theta,
            (Medium::vacuum(), bk7(), Medium::vacuum()),
            d,
            Light::Unpolarized,
            transmitted,
        );
        assert!(!round_trips::non_dispersive(&scene));
        let (route, out) = spectrum_of(&scene, &target, &st, &lambdas);
        assert_eq!(route, Route::RoundTrips);
        let mut worst = 0.0f64;
        for (&l, &i) in lambdas.iter().zip(&out) {
            let f = film_at(l);
            let airy = match transmitted {
                None => {
                    0.5 * (f.reflectance(theta.cos(), l, Pol::S)
                        + f.reflectance(theta.cos(), l, Pol::P))
                }
                Some(_) => {
                    0.5 * (f.transmittance(theta.cos(), l, Pol::S)
                        + f.transmittance(theta.cos(), l, Pol::P))
                }
            };
            let err = (i - airy).abs();
            worst = worst.max(err);
            assert!(
                err <= 1e-12,
                "λ {l:e}, transmitted {transmitted:?}: actual {i:e}, expected {airy:e}, err {err:e}"
            );
        }
        eprintln!("BK7, transmitted {transmitted:?}: max |I − Airy| = {worst:e} (m = {m})");
    }
}

/// The non-dispersive plate of `beats::spectrum_traced_once_matches_airy_and_per_wavelength_traces`
/// through `round_trips::spectrum` (traced once, by round trips): Airy to 1e-12 at all 401
/// wavelengths.
#[test]
fn non_dispersive_spectrum_matches_airy() {
    let theta = 35f64.to_radians();
    let film = Film {
        n1: 1.0,
        n2: 1.7,
        n3: 1.0,
        thickness_m: 3.217e-6,
    };
    let lambdas: Vec<f64> = (0..401).map(|i| 400e-9 + 1e-9 * i as f64).collect();
    let m = internal_for_bound(|_| film, theta.cos(), &lambdas[200..201], 1e-12);
    let (scene, target) = film_scene(
        theta,
        (
            Medium::vacuum(),
            Medium::constant("glass", 1.7),
            Medium::vacuum(),
        ),
        film.thickness_m,
        Light::Unpolarized,
        None,
    );
    let (route, out) = spectrum_of(&scene, &target, &settings(m), &lambdas);
    assert_eq!(route, Route::RoundTrips);
    for (&l, &i) in lambdas.iter().zip(&out) {
        let airy = 0.5
            * (film.reflectance(theta.cos(), l, Pol::S) + film.reflectance(theta.cos(), l, Pol::P));
        let err = (i - airy).abs();
        assert!(
            err <= 1e-12,
            "λ {l:e}: actual {i:e}, expected {airy:e}, err {err:e}"
        );
    }
}

/// Where the round trips do not hold, `rays` refuses with the reason and `spectrum` runs the
/// general walk: its values are those of tracing each wavelength with `trace::arrivals`.
#[test]
fn general_walk_runs_where_round_trips_do_not_apply() {
    let theta = 30f64.to_radians();
    let glass = || Medium::constant("glass", 1.6);
    let plate = || {
        film_scene(
            theta,
            (Medium::vacuum(), glass(), Medium::vacuum()),
            2e-6,
            Light::Unpolarized,
            None,
        )
    };
    let mut cases: Vec<(&str, Scene, Target)> = Vec::new();
    // A point target (not the far field).
    let (s, _) = plate();
    cases.push((
        "point target",
        s,
        Target::Point(DVec3::new(0.001, 0.0, 0.001)),
    ));
    // A point source.
    let (mut s, t) = plate();
    s.sources[0].emitter = Emitter::Point {
        position: DVec3::new(-0.001, 0.0, 0.001),
    };
    cases.push(("point source", s, t));
    // A finite coherence length.
    let (mut s, t) = plate();
    s.sources[0].coherence_length_m = 1e-5;
    cases.push(("finite coherence length", s, t));
    // Non-parallel faces (a wedge of 1 mrad, N-BK7: traced at every wavelength).
    let mut s = Scene::new(Medium::vacuum());
    s.add_wedge(
        "wedge",
        DVec3::ZERO,
        DVec3::Z,
        2e-6,
        1e-3,
        DVec3::Y,
        Medium::vacuum(),
        bk7(),
        Medium::vacuum(),
    );
    let (p, t) = plate();
    s.sources = p.sources;
    cases.push(("wedge", s, t));
    // A third surface: a shield beside the beam.
    let (mut s, t) = plate();
    s.surfaces.push(Surface {
        name: "shield".into(),
        plane: Plane::new(DVec3::new(0.0, 0.0, 0.01), DVec3::Z),
        extent: Extent::Rect {
            u: DVec3::X,
            v: DVec3::Y,
            rect: Rect {
                center_uv: [0.05, 0.0],
                half_width_m: 0.001,
                half_height_m: 0.001,
            },
        },
        kind: SurfaceKind::Opaque { apertures: vec![] },
    });
    cases.push(("shield", s, t));
    let st = settings(9);
    let lambdas = [450e-9, 600e-9, 750e-9];
    for (what, scene, target) in &cases {
        let optics = scene.optics(550e-9).unwrap();
        let refused = round_trips::rays(scene, &optics, &PROBES, target, &st);
        assert!(refused.is_err(), "{what}: round trips must not apply");
        let mut out = [0.0; 3];
        let route = round_trips::spectrum(
            scene,
            &PROBES,
            target,
            &st,
            &lambdas,
            &mut Beats::default(),
            &mut out,
        )
        .unwrap();
        assert!(
            matches!(route, Route::GeneralWalk(_)),
            "{what}: route {route:?}"
        );
        if round_trips::non_dispersive(scene) {
            // Traced once at the middle wavelength, evaluated by beat terms: bit for bit the
            // general walk's traced-once spectrum.
            let arr = walk(scene, lambdas[1], target, &st);
            let mut beats = Beats::default();
            beats.set(&fringe::trace::beats::vector_rays(&arr));
            let mut want = [0.0; 3];
            beats.intensities(&lambdas, &mut want);
            assert_eq!(
                out.map(f64::to_bits),
                want.map(f64::to_bits),
                "{what}: {out:?} vs {want:?}"
            );
        } else {
            // Traced at every wavelength: the walk's intensity (same phases, same sums).
            for (&l, &i) in lambdas.iter().zip(&out) {
                let arr = walk(scene, l, target, &st);
                let want = trace::intensity(&arr, Fidelity::Vector);
                let err = (i - want).abs();
                assert!(
                    err <= 1e-15 * want.abs().max(1.0),
                    "{what}, λ {l:e}: actual {i:e}, expected {want:e}, err {err:e}"
                );
            }
        }
    }
}

/// The spectrum of a dispersive film by a sweep (`trace::dispersive_sweep::Sweep`: the orders'
/// structure traced once at the middle wavelength; per wavelength only the indices, the Fresnel
/// coefficients and the round trip) against a trace at every wavelength, both by round trips
/// (`round_trips::rays_or_walk`) and by the general walk (`trace::arrivals`), to 1e-14 at every
/// wavelength: free-standing N-BK7 plates, N-BK7 films on a substrate and constant films on
/// N-BK7, reflected and transmitted into constant media, s, p and unpolarized, 0.5°, 35° and
/// 72°, 9 and 27 internal reflections. The sweep must hold at every wavelength there (no
/// critical angle in the band, constant launch and exit media) and be what `spectrum` gives.
#[test]
fn dispersive_sweep_equals_per_wavelength_traces() {
    use fringe::trace::dispersive_sweep::Sweep;
    let c = |n: f64| Medium::constant("m", n);
    let v = Medium::vacuum;
    let stacks: Vec<Stack> = vec![
        ((v(), bk7(), v()), 3.217e-6, None),
        ((v(), bk7(), v()), 3.217e-6, Some(1.0)),
        ((v(), bk7(), c(1.7)), 1.3e-6, None),
        ((v(), bk7(), c(1.7)), 1.3e-6, Some(1.7)),
        ((v(), c(1.38), bk7()), 0.41e-6, None),
    ];
    let lambdas: Vec<f64> = (0..41).map(|i| 400e-9 + 10e-9 * i as f64).collect();
    let mut cases = 0;
    let (mut worst_rt, mut worst_walk) = (0.0f64, 0.0f64);
    for (media, d, transmitted) in &stacks {
        for theta_deg in [0.5, 35.0, 72.0] {
            for light in [Light::S, Light::P, Light::Unpolarized] {
                for m in [9usize, 27] {
                    let theta = f64::to_radians(theta_deg);
                    let (scene, target) = film_scene(theta, media.clone(), *d, light, *transmitted);
                    assert!(!round_trips::non_dispersive(&scene));
                    let st = settings(m);
                    let what = format!(
                        "{media:?}, d {d:e}, {theta_deg}°, {light:?}, m {m}, transmitted \
                         {transmitted:?}"
                    );
                    let mid = scene.optics(lambdas[20]).unwrap();
                    let sweep = Sweep::new(&scene, &mid, &PROBES, &target, &st)
                        .unwrap_or_else(|e| panic!("{what}: sweep refused: {e}"));
                    let (route, out) = spectrum_of(&scene, &target, &st, &lambdas);
                    assert_eq!(route, Route::RoundTrips, "{what}");
                    let mut acc = Accumulator::new();
                    for (&l, &i) in lambdas.iter().zip(&out) {
                        let swept = sweep
                            .intensity(&scene, l)
                            .unwrap()
                            .unwrap_or_else(|| panic!("{what}, λ {l:e}: the sweep does not hold"));
                        assert_eq!(i.to_bits(), swept.to_bits(), "{what}, λ {l:e}: spectrum");
                        let optics = scene.optics(l).unwrap();
                        let (rays, rt) =
                            round_trips::rays_or_walk(&scene, &optics, &PROBES, &target, &st);
                        assert_eq!(rt, Route::RoundTrips, "{what}, λ {l:e}");
                        let i_rt = round_trips::intensity(&rays, l, &mut acc);
                        let i_walk =
                            trace::intensity(&walk(&scene, l, &target, &st), Fidelity::Vector);
                        let (e_rt, e_walk) = ((i - i_rt).abs(), (i - i_walk).abs());
                        worst_rt = worst_rt.max(e_rt);
                        worst_walk = worst_walk.max(e_walk);
                        assert!(
                            e_rt <= 1e-14 && e_walk <= 1e-14,
                            "{what}, λ {l:e}: sweep {i:e}, round trips {i_rt:e} (err {e_rt:e}), \
                             walk {i_walk:e} (err {e_walk:e})"
                        );
                    }
                    cases += 1;
                }
            }
        }
    }
    eprintln!(
        "{cases} cases × {} wavelengths: worst |sweep − round trips| {worst_rt:e}, \
         |sweep − walk| {worst_walk:e}",
        lambdas.len()
    );
}

/// A critical angle inside the band: light from a constant n = 1.6 onto an N-BK7 film (on
/// n = 1.7) at 72° reflects totally at the film's top face where n_BK7(λ) < 1.6 sin 72°
/// (λ ≳ 497 nm). The sweep set up at 400 nm holds below the crossing and not beyond it; set
/// up at the middle wavelength (600 nm, totally reflected: no order through the film) it is
/// refused. `spectrum` sets it up again at the first wavelength traced by round trips and gives
/// a trace's intensity at every wavelength (to 1e-14; the general walk beyond the crossing).
#[test]
fn dispersive_sweep_falls_back_across_a_critical_angle() {
    use fringe::trace::dispersive_sweep::Sweep;
    let theta = 72f64.to_radians();
    let (scene, target) = film_scene(
        theta,
        (
            Medium::constant("dense", 1.6),
            bk7(),
            Medium::constant("substrate", 1.7),
        ),
        1.3e-6,
        Light::Unpolarized,
        None,
    );
    let st = settings(27);
    let lambdas: Vec<f64> = (0..41).map(|i| 400e-9 + 10e-9 * i as f64).collect();
    let at = |l: f64| scene.optics(l).unwrap();
    assert!(Sweep::new(&scene, &at(600e-9), &PROBES, &target, &st).is_err());
    let sweep = Sweep::new(&scene, &at(400e-9), &PROBES, &target, &st).unwrap();
    assert!(sweep.intensity(&scene, 450e-9).unwrap().is_some());
    assert!(sweep.intensity(&scene, 700e-9).unwrap().is_none());
    let (route, out) = spectrum_of(&scene, &target, &st, &lambdas);
    assert!(matches!(route, Route::GeneralWalk(_)), "route {route:?}");
    let mut acc = Accumulator::new();
    let mut by_round_trips = 0;
    for (&l, &i) in lambdas.iter().zip(&out) {
        let (rays, rt) = round_trips::rays_or_walk(&scene, &at(l), &PROBES, &target, &st);
        by_round_trips += usize::from(rt == Route::RoundTrips);
        let want = round_trips::intensity(&rays, l, &mut acc);
        let err = (i - want).abs();
        assert!(
            err <= 1e-14,
            "λ {l:e} ({rt:?}): actual {i:e}, expected {want:e}, err {err:e}"
        );
    }
    assert!(
        (5..35).contains(&by_round_trips),
        "the crossing lies inside the band ({by_round_trips} wavelengths by round trips)"
    );
}

/// Where the sweep's structure does not hold at all (normal incidence: each channel's own frame
/// picks s; two sources, which may share a coherence group) it is refused with its reason, and
/// `spectrum` traces every wavelength: bit for bit a trace by round trips at each wavelength.
/// Light transmitted into an N-BK7 substrate toward the direction of 600 nm leaves at another
/// angle at any other wavelength: the sweep set up at 600 nm holds there only, and `spectrum`
/// traces the others (bit for bit). A wavelength outside N-BK7's Sellmeier range is an error,
/// not a NaN.
#[test]
fn dispersive_sweep_refused_where_its_structure_does_not_hold() {
    use fringe::trace::dispersive_sweep::Sweep;
    let media = (Medium::vacuum(), bk7(), Medium::vacuum());
    let (normal, target_n) = film_scene(0.0, media.clone(), 2e-6, Light::Unpolarized, None);
    let theta = 35f64.to_radians();
    let (mut two, target_2) = film_scene(theta, media.clone(), 2e-6, Light::S, None);
    let mut second = two.sources[0].clone();
    second.name = "second".into();
    second.polarization = Polarization::Linear {
        reference: DVec3::X,
        angle_rad: 0.0,
    };
    two.sources.push(second);
    let st = settings(9);
    let lambdas: Vec<f64> = (0..9).map(|i| 400e-9 + 50e-9 * i as f64).collect();
    for (what, scene, target) in [
        ("normal incidence", &normal, &target_n),
        ("two sources", &two, &target_2),
    ] {
        let optics = scene.optics(600e-9).unwrap();
        let why = Sweep::new(scene, &optics, &PROBES, target, &st).unwrap_err();
        eprintln!("{what}: {why}");
        let (route, out) = spectrum_of(scene, target, &st, &lambdas);
        assert_eq!(route, Route::RoundTrips, "{what}");
        let mut acc = Accumulator::new();
        for (&l, &i) in lambdas.iter().zip(&out) {
            let (rays, _) =
                round_trips::rays_or_walk(scene, &scene.optics(l).unwrap(), &PROBES, target, &st);
            let want = round_trips::intensity(&rays, l, &mut acc);
            assert_eq!(
                i.to_bits(),
                want.to_bits(),
                "{what}, λ {l:e}: {i:e} vs {want:e}"
            );
        }
    }
    let n600 = bk7().index(600e-9).unwrap();
    let (into_bk7, target_t) = film_scene(
        theta,
        (Medium::vacuum(), Medium::constant("film", 1.38), bk7()),
        0.41e-6,
        Light::Unpolarized,
        Some(n600),
    );
    let sweep = Sweep::new(
        &into_bk7,
        &into_bk7.optics(600e-9).unwrap(),
        &PROBES,
        &target_t,
        &st,
    )
    .unwrap();
    assert!(sweep.intensity(&into_bk7, 600e-9).unwrap().is_some());
    assert!(sweep.intensity(&into_bk7, 550e-9).unwrap().is_none());
    let (_, out) = spectrum_of(&into_bk7, &target_t, &st, &lambdas);
    let mut acc = Accumulator::new();
    for (&l, &i) in lambdas.iter().zip(&out) {
        let (rays, _) = round_trips::rays_or_walk(
            &into_bk7,
            &into_bk7.optics(l).unwrap(),
            &PROBES,
            &target_t,
            &st,
        );
        let want = round_trips::intensity(&rays, l, &mut acc);
        if l == lambdas[lambdas.len() / 2] {
            assert!(
                (i - want).abs() <= 1e-14,
                "into N-BK7, middle λ {l:e}: {i:e} vs {want:e}"
            );
        } else {
            assert_eq!(
                i.to_bits(),
                want.to_bits(),
                "into N-BK7, λ {l:e}: {i:e} vs {want:e}"
            );
        }
    }
    let (scene, target) = film_scene(theta, media, 2e-6, Light::Unpolarized, None);
    let mut out = vec![0.0; 3];
    let bad = round_trips::spectrum(
        &scene,
        &PROBES,
        &target,
        &st,
        &[500e-9, 600e-9, 2600e-9],
        &mut Beats::default(),
        &mut out,
    );
    assert!(bad.is_err(), "2600 nm is outside N-BK7's range: {bad:?}");
}

/// Total internal reflection inside the film at every wavelength: light from a constant
/// n = 1.6 at 50° onto an N-BK7 film on vacuum (1.6 sin 50° = 1.23 > 1: the film's bottom face
/// reflects totally, its top face does not, 400–800 nm). The structure holds at every
/// wavelength (the same face reflects totally), and the sweep equals a trace at each
/// wavelength, by round trips and by the walk, to 1e-14, for s, p and unpolarized light. With
/// 27 internal reflections the orders left out are below 1e-15 (|r| ≈ 0.06 at the top face,
/// |r| = 1 at the bottom), so the lossless film reflects all the light: R = 1 to 1e-13.
#[test]
fn dispersive_sweep_with_total_internal_reflection_inside() {
    use fringe::trace::dispersive_sweep::Sweep;
    let lambdas: Vec<f64> = (0..41).map(|i| 400e-9 + 10e-9 * i as f64).collect();
    let (mut worst, mut worst_r) = (0.0f64, 0.0f64);
    for light in [Light::S, Light::P, Light::Unpolarized] {
        for m in [9usize, 27] {
            let (scene, target) = film_scene(
                50f64.to_radians(),
                (Medium::constant("dense", 1.6), bk7(), Medium::vacuum()),
                1.3e-6,
                light,
                None,
            );
            let st = settings(m);
            let sweep = Sweep::new(
                &scene,
                &scene.optics(600e-9).unwrap(),
                &PROBES,
                &target,
                &st,
            )
            .unwrap_or_else(|e| panic!("{light:?}, m {m}: refused: {e}"));
            let (_, out) = spectrum_of(&scene, &target, &st, &lambdas);
            let mut acc = Accumulator::new();
            for (&l, &i) in lambdas.iter().zip(&out) {
                let swept = sweep
                    .intensity(&scene, l)
                    .unwrap()
                    .expect("the sweep holds");
                assert_eq!(i.to_bits(), swept.to_bits(), "{light:?}, λ {l:e}");
                let (rays, rt) = round_trips::rays_or_walk(
                    &scene,
                    &scene.optics(l).unwrap(),
                    &PROBES,
                    &target,
                    &st,
                );
                assert_eq!(rt, Route::RoundTrips, "{light:?}, λ {l:e}");
                let i_rt = round_trips::intensity(&rays, l, &mut acc);
                let i_walk = trace::intensity(&walk(&scene, l, &target, &st), Fidelity::Vector);
                let err = (i - i_rt).abs().max((i - i_walk).abs());
                worst = worst.max(err);
                assert!(
                    err <= 1e-14,
                    "{light:?}, m {m}, λ {l:e}: sweep {i:e}, round trips {i_rt:e}, walk {i_walk:e}"
                );
                if m == 27 {
                    worst_r = worst_r.max((i - 1.0).abs());
                    assert!(
                        (i - 1.0).abs() <= 1e-13,
                        "{light:?}, λ {l:e}: R = {i:e}, not 1"
                    );
                }
            }
        }
    }
    eprintln!(
        "total internal reflection inside: worst |sweep − trace| {worst:e}, |R − 1| {worst_r:e}"
    );
}
