use fringe::harness::case::{build, load};
use fringe::trace::{self, TraceSettings, path::EnumerationLimits};
fn main() {
    let a: Vec<String> = std::env::args().collect();
    let path = std::path::Path::new(&a[1]);
    let which: usize = a.get(2).map(|s| s.parse().unwrap()).unwrap_or(0);
    let internal: usize = a.get(3).map(|s| s.parse().unwrap()).unwrap_or(6);
    let case = load::load(path).unwrap();
    let pts = build::probe_points(&case.spec.probe);
    let pt = &pts[which.min(pts.len() - 1)];
    let built = build::build_scene(&case.spec.scene, &pt.overrides).unwrap();
    let lambda = build::spectrum(&case.spec.light, &pt.overrides)[0].0;
    let optics = built.scene.optics(lambda).unwrap();
    let target = build::target(&pt.observer, &built, lambda).unwrap();
    let st = TraceSettings {
        limits: EnumerationLimits {
            max_internal_reflections: internal,
            max_events: 2 * internal + 8,
        },
        ..TraceSettings::default()
    };
    let tg = match &target {
        trace::path::Target::Point(p) => vec![*p],
        trace::path::Target::Direction { reference, .. } => vec![*reference],
    };
    let plan = trace::plan(&built.scene, &optics, &tg, &st.limits);
    let (arr, failed) = trace::arrivals(&built.scene, &optics, &plan, &target, &st);
    println!(
        "coordinate {} surfaces {:?}",
        pt.coordinate,
        built
            .scene
            .surfaces
            .iter()
            .map(|s| s.plane.normal)
            .collect::<Vec<_>>()
    );
    for x in &arr {
        let e = x.vector.field();
        let i: f64 = e.iter().map(|c| c.norm_sqr()).sum();
        println!(
            "{:?} {} |E|2 {:.6e} dir {:?} q2 {:?}",
            x.channel,
            trace::path::sequence_label(x.path.sequence.iter()),
            i,
            x.vector.dir,
            x.vector.normal_q2
        );
    }
    for f in &failed {
        println!(
            "FAILED {} {:?}",
            trace::path::sequence_label(f.sequence.iter()),
            f.error
        );
    }
}
