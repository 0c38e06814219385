//! The case runner's shared work (src/harness/case/run/): what it reuses instead of tracing
//! again must be what a new trace gives, bit for bit.
//!
//! - The convergence report's rungs (the traced orders up to 1, 3, 5, … internal reflections)
//!   are summed from the arrivals the run traced with its full budget
//!   (`run::orders_within`): for films and plates at any angle, reflected and transmitted,
//!   those are the arrivals of a trace with the smaller budget, in its order; and every
//!   library case's report equals the one with every rung traced (`run::convergence_traced`).
//! - A wavelength sweep over one non-dispersive scene is traced once per worker and relabelled
//!   (`Arrival::set_wavelength`): each point's traced values equal a run of that point alone.

use crate::support::airy_plate::{plane_wave_film, specular_target};
use fringe::harness::case::load;
use fringe::harness::case::run;
use fringe::optics::material::Medium;
use fringe::scene::Scene;
use fringe::scene::source::Polarization;
use fringe::trace::path::{EnumerationLimits, Target};
use fringe::trace::{self, TraceSettings};
use glam::DVec3;
use std::path::Path;

const PROBES: [DVec3; 1] = [DVec3::new(0.0, 0.0, 0.001)];

/// A film between `above` and `below` (top face at z = 0), a plane wave at `theta` in the x–z
/// plane with polarization `pol`, observed in the far field: reflected, or transmitted into
/// `below` (index `n_below`).
fn film_scene(
    theta: f64,
    (n_above, n_film, n_below): (f64, f64, f64),
    thickness_m: f64,
    pol: Polarization,
    transmitted: bool,
) -> (Scene, Target) {
    let m = |n: f64| Medium::constant("m", n);
    let scene = plane_wave_film(theta, [m(n_above), m(n_film), m(n_below)], thickness_m, pol);
    let target = if transmitted {
        let s3 = n_above * theta.sin() / n_below;
        Target::Direction {
            dir: DVec3::new(s3, 0.0, -(1.0 - s3 * s3).sqrt()),
            reference: DVec3::new(0.0, 0.0, -0.001),
        }
    } else {
        specular_target(theta)
    };
    (scene, target)
}

/// The runner's settings for `m` internal reflections (`run::trace_settings`' event cap).
fn settings(scene: &Scene, m: usize) -> TraceSettings {
    TraceSettings {
        limits: EnumerationLimits {
            max_internal_reflections: m,
            max_events: 2 * m + 2 * scene.surfaces.len() + 4,
        },
        ..TraceSettings::default()
    }
}

fn walk(scene: &Scene, lambda: f64, target: &Target, st: &TraceSettings) -> Vec<trace::Arrival> {
    let optics = scene.optics(lambda).unwrap();
    let plan = trace::plan(scene, &optics, &PROBES, &st.limits);
    trace::arrivals(scene, &optics, &plan, target, st).0
}

/// A reproducible draw in [0, 1) (splitmix64).
fn uniform(state: &mut u64) -> f64 {
    *state = state.wrapping_add(0x9e37_79b9_7f4a_7c15);
    let mut z = *state;
    z = (z ^ (z >> 30)).wrapping_mul(0xbf58_476d_1ce4_e5b9);
    z = (z ^ (z >> 27)).wrapping_mul(0x94d0_49bb_1331_11eb);
    ((z ^ (z >> 31)) >> 11) as f64 / (1u64 << 53) as f64
}

/// Random films (index 1.2–2.6 in air or on glass 1.45–1.75, 50 nm–20 µm, 0–85°, s, p or
/// unpolarized, reflected or transmitted, 400–800 nm): the arrivals of a trace with m internal
/// reflections are the arrivals of the trace with M > m that `orders_within` keeps, bit for
/// bit (rays, paths, ledgers and order), and so is their intensity.
#[test]
fn convergence_rungs_are_the_orders_a_smaller_budget_traces() {
    let mut state = 14u64;
    let mut compared = 0;
    for scene_k in 0..40 {
        let mut u = || uniform(&mut state);
        let n_film = 1.2 + 1.4 * u();
        let n_below = if u() < 0.5 { 1.0 } else { 1.45 + 0.3 * u() };
        let d = 50e-9 * (400.0f64).powf(u());
        let theta = (85.0 * u()).to_radians();
        let pol = match scene_k % 3 {
            0 => Polarization::Linear {
                reference: DVec3::Y,
                angle_rad: 0.0,
            },
            1 => Polarization::Linear {
                reference: DVec3::X,
                angle_rad: 0.0,
            },
            _ => Polarization::Unpolarized,
        };
        let transmitted = u() < 0.5;
        let lambda = 400e-9 + 400e-9 * u();
        let (scene, target) = film_scene(theta, (1.0, n_film, n_below), d, pol, transmitted);
        let big = if scene_k % 2 == 0 { 23 } else { 61 };
        let all = walk(&scene, lambda, &target, &settings(&scene, big));
        let ambient = scene.optics(lambda).unwrap().ambient_index;
        for m in [1usize, 3, 5, 7, 11, 15, 23] {
            let st = settings(&scene, m);
            let what = format!(
                "scene {scene_k}: n {n_film} on {n_below}, d {d:e}, θ {theta}, λ {lambda:e}, \
                 transmitted {transmitted}, m {m} of {big}"
            );
            let Some(kept) = run::orders_within(&all, big, m, st.limits.max_events, ambient) else {
                assert!(m > big, "{what}: refused");
                continue;
            };
            let traced = walk(&scene, lambda, &target, &st);
            assert!(!traced.is_empty(), "{what}: nothing arrives");
            assert_eq!(format!("{kept:?}"), format!("{traced:?}"), "{what}");
            let (a, b) = (
                trace::intensity(&kept, fringe::accumulate::fidelity::Fidelity::Vector),
                trace::intensity(&traced, fringe::accumulate::fidelity::Fidelity::Vector),
            );
            assert_eq!(a.to_bits(), b.to_bits(), "{what}: intensity {a:e} vs {b:e}");
            compared += 1;
        }
    }
    assert!(compared >= 200, "{compared} rungs compared");
}

/// Every library case with a convergence report: the report a run gives (rungs summed from its
/// own arrivals where they hold them) is the report with every rung traced, bit for bit.
#[test]
fn library_convergence_reports_equal_traced_rungs() {
    let root = fringe::harness::check::library_root().join("cases");
    let mut reports = 0;
    for name in fringe::harness::check::library_names(&root) {
        let case = load::load(&root.join(format!("{name}.json"))).unwrap();
        let traced = run::convergence_traced(&case).unwrap();
        if traced.is_empty() {
            continue;
        }
        let result = run::run(&case).unwrap();
        assert_eq!(result.convergence, traced, "{name}");
        reports += 1;
    }
    assert!(reports >= 5, "{reports} reports compared");
}

/// `plate_airy_wavelength`, a sweep over one non-dispersive scene traced once per worker:
/// each traced value at every level equals, bit for bit, a run of that wavelength alone.
#[test]
fn a_wavelength_sweep_traced_once_is_each_point_traced_alone() {
    let root = fringe::harness::check::library_root().join("cases");
    let file = root.join("plate_airy_wavelength.json");
    let text = std::fs::read_to_string(&file).unwrap();
    let case = load::parse(&file, &text).unwrap();
    let swept = run::run_with(&case, false).unwrap();
    let json: serde_json::Value = serde_json::from_str(&text).unwrap();
    let sweep = &json["probe"]["sweep"];
    let count = sweep["count"].as_u64().unwrap() as usize;
    let primary = &swept.metrics[0];
    for k in [0, 1, count / 3, count / 2, count - 1] {
        let lambda_nm = primary.coordinates[k];
        let mut alone = json.clone();
        alone["light"] = serde_json::json!({"monochrome": {"wavelength_nm": lambda_nm}});
        alone["probe"] = serde_json::json!({"single": {"observe": sweep["observe"].clone()}});
        let single = load::parse(
            Path::new("plate_airy_wavelength_point.json"),
            &serde_json::to_string(&alone).unwrap(),
        )
        .unwrap();
        let r = run::run_with(&single, false).unwrap();
        for (level, values) in &primary.traced {
            let v = r.metrics[0].traced[level][0];
            assert_eq!(
                values[k].to_bits(),
                v.to_bits(),
                "point {k} ({lambda_nm} nm), {level}: swept {:e}, alone {v:e}",
                values[k]
            );
        }
    }
}
