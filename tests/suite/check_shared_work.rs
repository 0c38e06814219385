//! Work `fringe check` forms once and reuses (src/harness/case/run/): what it reuses must be
//! what forming it again gives.
//!
//! - A probe point's scene optics: for a scene whose indices do not depend on the wavelength
//!   (`run::dispersionless`), the case runner forms them at the first spectral sample and
//!   relabels them to every other (`run::relabelled_optics`); at every sample of every library
//!   case they equal `Scene::optics` at that sample, field for field.

use fringe::harness::case::{build, load, run};

/// Every probe point and spectral sample of every library case whose scene is dispersionless:
/// the optics relabelled from the first sample equal the optics formed at each sample.
#[test]
fn relabelled_optics_are_the_optics_at_each_sample() {
    let root = fringe::harness::check::library_root().join("cases");
    let (mut compared, mut dispersive) = (0, 0);
    for name in fringe::harness::check::library_names(&root) {
        let case = load::load(&root.join(format!("{name}.json"))).unwrap();
        for pt in build::probe_points(&case.spec.probe) {
            let built = build::build_scene(&case.spec.scene, &pt.overrides).unwrap();
            if !run::dispersionless(&built.scene) {
                dispersive += 1;
                continue;
            }
            let spectrum = build::spectrum(&case.spec.light, &pt.overrides);
            let first = built.scene.optics(spectrum[0].0).unwrap();
            for &(lambda, _) in &spectrum {
                let formed = built.scene.optics(lambda).unwrap();
                assert_eq!(
                    run::relabelled_optics(&first, lambda),
                    formed,
                    "{name} at {lambda:e} m"
                );
                compared += 1;
            }
        }
    }
    // coherence_length alone has 400 points × 129 samples; bk7_dispersion is dispersive.
    assert!(compared >= 50_000, "{compared} samples compared");
    assert!(dispersive > 0, "no dispersive scene in the library");
}

/// A scene with one dispersive medium (N-BK7, Sellmeier) is not dispersionless, and its optics
/// relabelled from one wavelength are not its optics at another: the runner forms them at
/// every sample.
#[test]
fn a_dispersive_medium_makes_a_scene_dispersive() {
    let root = fringe::harness::check::library_root().join("cases");
    let case = load::load(&root.join("bk7_dispersion.json")).unwrap();
    let points = build::probe_points(&case.spec.probe);
    let (first, last) = (&points[0], &points[points.len() - 1]);
    let built = build::build_scene(&case.spec.scene, &first.overrides).unwrap();
    assert!(!run::dispersionless(&built.scene));
    let a = build::spectrum(&case.spec.light, &first.overrides)[0].0;
    let b = build::spectrum(&case.spec.light, &last.overrides)[0].0;
    assert!(
        (a - 380e-9).abs() < 1e-15 && (b - 780e-9).abs() < 1e-15,
        "{a:e} {b:e}"
    );
    let (oa, ob) = (
        built.scene.optics(a).unwrap(),
        built.scene.optics(b).unwrap(),
    );
    assert_ne!(
        run::relabelled_optics(&oa, b),
        ob,
        "N-BK7's index changes with λ"
    );
}
