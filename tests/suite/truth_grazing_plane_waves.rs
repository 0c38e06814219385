//! Plane waves at 89.999999999999° in ambients of small index (issue #12): valid scenes that
//! `fringe fuzz --count 10000 --seed 1` refused as "no light reaches any probe point".
//!
//! Diagnosis: a plane wave on a stack of unbounded parallel planes is launched a fixed 1 mm
//! along its direction before the first plane (`path::plane_wave_launch`). Its height above the
//! plane is 1 mm·cos θ, 1.7e-17 m at cos θ = 1.7e-14: below one rounding of the plane point's
//! coordinates (~4e-16 m at 3 m), so the f64 launch lay on the plane or behind it and the wave
//! met no face. The standoff now grows until the height is 16 roundings of the coordinates
//! the launch is formed from (`launch_standoff`).
//!
//! The verdicts compare the tracer with the `airy` and `plane_wave_beams` closed forms (their
//! own precision is shown against 50 digits in `closed_form_precision` and `truth_airy_tracer`),
//! never with the tracer's own output.

use fringe::harness::fuzz::{self, Family, Verdict};
use std::path::Path;

/// Scenes of `fringe fuzz --count 10000 --seed 1` refused as "no light reaches any probe
/// point": `airy` 8206 (film 1.5 in ambient 0.0034 on a substrate of 0.0026, 1.99 cm thick,
/// translated 15 m) and 9450 (film 3.2 in ambient 0.0023, 0.34 µm, translated 3 m), and
/// `plane_wave_beams` 1294 (one interface, ambient 0.0019 → 2.62, rotated and translated 23 m),
/// all swept from 89.999999999999° to 89.9999999999995°.
const SCENES: [(Family, usize); 3] = [
    (Family::Airy, 8206),
    (Family::Airy, 9450),
    (Family::PlaneWaveBeams, 1294),
];

/// Those scenes are judged, not refused, and pass the gate against their closed forms.
#[test]
fn grazing_plane_waves_reach_the_probe_and_pass() {
    let mut bad = Vec::new();
    for (family, index) in SCENES {
        let scene = fuzz::scene(family, 1, index, None);
        let case = scene.case.expect("a generated case");
        let verdict = fuzz::judge(
            &case,
            Path::new(&format!("grazing_{}_{index}.json", family.name())),
        );
        if !matches!(verdict, Verdict::Pass { .. }) {
            bad.push(format!(
                "{} {index} {:?}: {verdict:?}",
                family.name(),
                scene.tags
            ));
        }
    }
    assert!(bad.is_empty(), "{bad:#?}");
}
