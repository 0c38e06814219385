//! The Airy plate under a plane wave, shared by `tests/fast_paths.rs` and `benches/airy.rs`: a
//! free-standing plate (n = 1.5, 2 µm, top face at z = 0, normal +z) in vacuum, lit by an
//! unpolarized plane wave at `theta` from the normal in the x–z plane, observed at the specular
//! far-field direction (wavefronts referred to (0, 0, 1 mm)).

use fringe::optics::material::Medium;
use fringe::scene::Scene;
use fringe::scene::source::{Emitter, Polarization, Source};
use fringe::trace::path::Target;
use glam::DVec3;

/// The scene and its specular far-field target.
pub fn airy_plate(theta: f64) -> (Scene, Target) {
    airy_plate_of(theta, Medium::constant("glass", 1.5), 2e-6)
}

/// The same scene with a plate of `glass`, `thickness_m` thick.
#[allow(dead_code)] // used by benches/airy.rs and tests/suite/beats.rs, not by every includer
pub fn airy_plate_of(theta: f64, glass: Medium, thickness_m: f64) -> (Scene, Target) {
    let scene = plane_wave_film(
        theta,
        [Medium::vacuum(), glass, Medium::vacuum()],
        thickness_m,
        Polarization::Unpolarized,
    );
    (scene, specular_target(theta))
}

/// A film of `media[1]`, `thickness_m` thick, between `media[0]` (above, also the ambient
/// medium) and `media[2]` (below), top face at z = 0, normal +z, lit by a plane wave at
/// `theta` from the normal in the x–z plane with polarization `pol` (wavefronts referred to
/// (0, 0, 1 mm)).
#[allow(dead_code)] // used by tests/suite/case_runs.rs, not by every includer
pub fn plane_wave_film(
    theta: f64,
    [above, film, below]: [Medium; 3],
    thickness_m: f64,
    pol: Polarization,
) -> Scene {
    let mut scene = Scene::new(above.clone());
    scene.add_plate(
        "plate",
        DVec3::ZERO,
        DVec3::Z,
        thickness_m,
        above,
        film,
        below,
    );
    let (s, c) = theta.sin_cos();
    scene.sources.push(Source {
        name: "beam".into(),
        emitter: Emitter::PlaneWave {
            direction: DVec3::new(s, 0.0, -c),
            reference_point: DVec3::new(0.0, 0.0, 0.001),
        },
        polarization: pol,
        intensity: 1.0,
        coherence_group: 0,
        coherence_length_m: f64::INFINITY,
    });
    scene
}

/// The specular far-field direction of [`plane_wave_film`]'s wave at `theta` (wavefronts
/// referred to (0, 0, 1 mm)).
#[allow(dead_code)] // not used by every includer
pub fn specular_target(theta: f64) -> Target {
    let (s, c) = theta.sin_cos();
    Target::Direction {
        dir: DVec3::new(s, 0.0, c),
        reference: DVec3::new(0.0, 0.0, 0.001),
    }
}
