//! Checks that combine sections of a field-by-field valid case: the sampled spectrum, the media
//! at every wavelength, the work cap, coincident sources, the probe geometry, intersecting slabs.

use super::*;

impl Validator {
    /// Checks that combine sections of a field-by-field valid case: the sampled spectrum, the
    /// media at every wavelength the case uses, the work cap, where the sources sit.
    pub(super) fn cross(&mut self, c: &CaseFile) {
        let s = &c.scene;
        // The wavelengths the case traces (nm): its spectrum, or the points of a wavelength sweep.
        let spectrum_nm: Vec<f64> =
            crate::harness::case::build::spectrum(&c.light, &Default::default())
                .iter()
                .map(|(l, _)| l * 1e9)
                .collect();
        let (lo, hi) = limits::WAVELENGTH_NM;
        if let Light::Gaussian { .. } = c.light {
            let min = spectrum_nm.iter().copied().fold(f64::INFINITY, f64::min);
            let max = spectrum_nm
                .iter()
                .copied()
                .fold(f64::NEG_INFINITY, f64::max);
            if spectrum_nm
                .iter()
                .any(|l| !(l.is_finite() && *l >= lo && *l <= hi))
            {
                self.fail(
                    "$.light.gaussian",
                    format!("the sampled spectrum (±sigmas standard deviations around center_nm) spans {min:.6} to {max:.6} nm; it must lie within [{lo}, {hi}] nm: reduce fwhm_nm or sigmas"),
                );
                return;
            }
        }
        let points = probe_point_count(&c.probe);
        if points.saturating_mul(spectrum_nm.len()) > limits::MAX_POINT_SAMPLES {
            let key = match &c.probe {
                Probe::Line { .. } => "$.probe.line.count",
                Probe::Sweep { .. } => "$.probe.sweep.count",
                Probe::Grid { .. } => "$.probe.grid.pixels",
                Probe::Single { .. } => "$.probe",
            };
            self.fail(
                key,
                format!(
                    "probe points × spectral samples must be at most {}, got {points} × {}",
                    limits::MAX_POINT_SAMPLES,
                    spectrum_nm.len()
                ),
            );
        }
        let has_plane_wave = s
            .sources
            .iter()
            .any(|x| matches!(x.emitter, EmitterSpec::PlaneWave { .. }));
        let observer = match &c.probe {
            Probe::Sweep { observe, .. } => Some(("$.probe.sweep.observe", observe)),
            Probe::Single { observe } => Some(("$.probe.single.observe", observe)),
            _ => None,
        };
        if let Some((op, Observer::FarField { .. })) = observer
            && !has_plane_wave
        {
            self.fail(
                    &format!("{op}.far_field"),
                    "a far_field observer needs a plane-wave source (it looks along the reflected or refracted plane wave)",
                );
        }
        if let Probe::Sweep { parameter, .. } = &c.probe {
            match parameter {
                SweepParameter::IncidenceAngleDeg { .. } if !has_plane_wave => self.fail(
                    "$.probe.sweep.parameter.incidence_angle_deg",
                    "an incidence-angle sweep turns the plane-wave sources: the scene has none",
                ),
                SweepParameter::WavelengthNm {} if !matches!(c.light, Light::Monochrome { .. }) => {
                    self.fail(
                        "$.probe.sweep.parameter.wavelength_nm",
                        "a wavelength sweep needs monochrome light (each point traces one wavelength)",
                    )
                }
                _ => {}
            }
        }
        let wavelengths: Vec<f64> = match &c.probe {
            Probe::Sweep {
                parameter: SweepParameter::WavelengthNm {},
                ..
            } => crate::harness::case::build::probe_points(&c.probe)
                .iter()
                .filter_map(|p| p.overrides.wavelength_m.map(|l| l * 1e9))
                .collect(),
            _ => spectrum_nm,
        };
        // Every medium the scene uses must have a real index in range at every wavelength.
        let mut used: Vec<(&str, String)> = vec![(s.ambient.as_str(), "$.scene.ambient".into())];
        for (i, surf) in s.surfaces.iter().enumerate() {
            let q = format!("$.scene.surfaces[{i}].{}", surf.kind());
            match surf {
                SurfaceSpec::Interface { front, back, .. } => {
                    used.push((front, format!("{q}.front")));
                    used.push((back, format!("{q}.back")));
                }
                SurfaceSpec::Plate {
                    medium,
                    above,
                    below,
                    ..
                }
                | SurfaceSpec::Wedge {
                    medium,
                    above,
                    below,
                    ..
                } => {
                    used.push((medium, format!("{q}.medium")));
                    used.push((above, format!("{q}.above")));
                    used.push((below, format!("{q}.below")));
                }
                _ => {}
            }
        }
        let mut checked = std::collections::BTreeSet::new();
        for (name, _) in used {
            let Some(spec) = s.media.get(name) else {
                continue;
            };
            if !checked.insert(name) {
                continue;
            }
            let m = crate::harness::case::build::medium(name, spec);
            let (ilo, ihi) = limits::INDEX;
            for l in &wavelengths {
                let bad = match m.index(l * 1e-9) {
                    Err(e) => Some(format!("at the case's wavelength {l} nm: {e}")),
                    Ok(n) if !(n >= ilo && n <= ihi) => Some(format!(
                        "the index at the case's wavelength {l} nm is {n}, outside [{ilo}, {ihi}]"
                    )),
                    Ok(_) => None,
                };
                if let Some(msg) = bad {
                    self.fail(&format!("$.scene.media.{name}"), msg);
                    break;
                }
            }
        }
        for (i, src) in s.sources.iter().enumerate() {
            self.placement(&format!("$.scene.sources[{i}]"), src, s);
        }
        if self.errors.is_empty() {
            self.coincident_sources(s);
        }
        if self.errors.is_empty() {
            self.probe_geometry(c);
        }
        if self.errors.is_empty() {
            self.intersecting_slabs(s);
        }
    }

    /// Two point sources at one place, or two line sources along one line (coincident Young
    /// slits): the "two beams" are one, and the closed forms that need their separation
    /// (Young's d) are undefined.
    fn coincident_sources(&mut self, s: &SceneSpec) {
        use glam::DVec3;
        let anchor = |e: &EmitterSpec| match e {
            EmitterSpec::Point { position_m } => Some((DVec3::from_array(*position_m), None)),
            EmitterSpec::Line { point_m, axis } => Some((DVec3::from_array(*point_m), unit(axis))),
            EmitterSpec::PlaneWave { .. } => None,
        };
        for (j, b) in s.sources.iter().enumerate() {
            for a in &s.sources[..j] {
                let (Some((pa, la)), Some((pb, lb))) = (anchor(&a.emitter), anchor(&b.emitter))
                else {
                    continue;
                };
                let same = match (la, lb) {
                    (None, None) => (pa - pb).length() < MIN_PROBE_DISTANCE_M,
                    (Some(u), Some(w)) => {
                        u.cross(w).length() < 1e-9
                            && (pb - pa - (pb - pa).dot(u) * u).length() < MIN_PROBE_DISTANCE_M
                    }
                    _ => false,
                };
                if same {
                    self.fail(
                        &format!("$.scene.sources[{j}].emitter"),
                        format!(
                            "sources {:?} and {:?} coincide (closer than {MIN_PROBE_DISTANCE_M:e} m, about a wavelength): they are one source, not two beams; separate them or merge them into one source of the summed intensity",
                            a.name, b.name
                        ),
                    );
                    return;
                }
            }
        }
    }

    /// Every probe point must be a place the tracer can mean: not within about a wavelength of
    /// a point or line source (ray optics needs the observer far from its sources; on the
    /// source the spherical or cylindrical wave is singular), and not on a surface (a detector
    /// in an interface has no side). A probe line or grid through a source is refused even if
    /// no sample lands on it.
    fn probe_geometry(&mut self, c: &CaseFile) {
        use glam::DVec3;
        let (key, segment): (&str, Option<(DVec3, DVec3)>) = match &c.probe {
            Probe::Line { from_m, to_m, .. } => (
                "$.probe.line",
                Some((DVec3::from_array(*from_m), DVec3::from_array(*to_m))),
            ),
            Probe::Grid { .. } => ("$.probe.grid", None),
            Probe::Sweep { .. } => ("$.probe.sweep.observe.point.position_m", None),
            Probe::Single { .. } => ("$.probe.single.observe.point.position_m", None),
        };
        let points: Vec<DVec3> = crate::harness::case::build::probe_points(&c.probe)
            .iter()
            .filter_map(|p| match &p.observer {
                Observer::Point { position_m, .. } => Some(DVec3::from_array(*position_m)),
                _ => None,
            })
            .collect();
        if points.is_empty() {
            return;
        }
        // Distance from a source (point, or line through a point) to the probe.
        let segment_distance = |a: DVec3, b: DVec3, x: DVec3| {
            let d = b - a;
            let t = if d.length_squared() > 0.0 {
                ((x - a).dot(d) / d.length_squared()).clamp(0.0, 1.0)
            } else {
                0.0
            };
            (a + t * d - x).length()
        };
        for src in &c.scene.sources {
            let (dist, what) = match &src.emitter {
                EmitterSpec::Point { position_m } => {
                    let x = DVec3::from_array(*position_m);
                    let near = match segment {
                        Some((a, b)) => segment_distance(a, b, x),
                        None => points
                            .iter()
                            .map(|p| (*p - x).length())
                            .fold(f64::INFINITY, f64::min),
                    };
                    (near, "point source")
                }
                EmitterSpec::Line { point_m, axis } => {
                    let (x, u) = (DVec3::from_array(*point_m), unit(axis).unwrap_or(DVec3::Z));
                    let off = |p: DVec3| (p - x - (p - x).dot(u) * u).length();
                    let near = match segment {
                        // The segment's distance to the line: the smallest over the segment
                        // of the perpendicular offset, a convex function of the parameter.
                        Some((a, b)) => {
                            let (mut lo, mut hi) = (0.0f64, 1.0f64);
                            for _ in 0..200 {
                                let (m1, m2) = (lo + (hi - lo) / 3.0, hi - (hi - lo) / 3.0);
                                if off(a + m1 * (b - a)) <= off(a + m2 * (b - a)) {
                                    hi = m2;
                                } else {
                                    lo = m1;
                                }
                            }
                            off(a + 0.5 * (lo + hi) * (b - a))
                        }
                        None => points.iter().map(|p| off(*p)).fold(f64::INFINITY, f64::min),
                    };
                    (near, "line source")
                }
                EmitterSpec::PlaneWave { .. } => continue,
            };
            if dist < MIN_PROBE_DISTANCE_M {
                self.fail(
                    key,
                    format!(
                        "the probe passes within {} m of the {what} {:?}: ray optics needs probe points farther than {MIN_PROBE_DISTANCE_M:e} m (about a wavelength) from a source, and on it the wave is singular",
                        num(dist),
                        src.name
                    ),
                );
                return;
            }
        }
        // A bounded surface: a probe point in its plane and on its rectangle, or within
        // 1e-12 of the scene's scale of its edge, is on the surface (refused as on an unbounded
        // one: which rays reach it, the direct one blocked or not and the reflected one
        // reflecting at the point itself, would be decided by rounding). Beside the rectangle
        // the plane is free space: a point there sees the rays that reach it without touching
        // the surface (a ray reflected by the surface would reflect at the point itself, off
        // the surface), docs/PHYSICS.md §8.
        for surf in &c.scene.surfaces {
            let (point_m, normal, rect) = match surf {
                SurfaceSpec::Interface {
                    point_m,
                    normal,
                    rect: Some(rect),
                    ..
                }
                | SurfaceSpec::Mirror {
                    point_m,
                    normal,
                    rect: Some(rect),
                    ..
                }
                | SurfaceSpec::Splitter {
                    point_m,
                    normal,
                    rect: Some(rect),
                    ..
                }
                | SurfaceSpec::OpaqueScreen {
                    point_m,
                    normal,
                    rect: Some(rect),
                    ..
                }
                | SurfaceSpec::Shield {
                    point_m,
                    normal,
                    rect,
                    ..
                } => (point_m, normal, rect),
                _ => continue,
            };
            let Some(n) = unit(normal) else { continue };
            let plane = crate::scene::geometry::Plane::new(DVec3::from_array(*point_m), n);
            let (u, v) = plane.axes(DVec3::from_array(rect.u_axis));
            let on_it = |p: &DVec3| {
                let scale = plane.point.length().max(p.length()).max(1.0);
                let margin = 1e-12 * scale;
                let d = *p - plane.point;
                d.dot(plane.normal).abs() <= margin
                    && d.dot(u).abs() <= 0.5 * rect.size_m[0] + margin
                    && d.dot(v).abs() <= 0.5 * rect.size_m[1] + margin
            };
            if let Some(p) = points.iter().find(|p| on_it(p)) {
                self.fail(
                    key,
                    format!(
                        "a probe point ({}, {}, {}) lies on {} {:?} (in its plane, on its rectangle or within 1e-12 of the scene's scale of its edge): a detector on a surface has no side; move the probe off the surface, or beside its rectangle",
                        num(p.x),
                        num(p.y),
                        num(p.z),
                        surf.kind(),
                        surf.name()
                    ),
                );
                return;
            }
        }
        // Unbounded faces: anywhere in their planes.
        let bounded = |x: &SurfaceSpec| match x {
            SurfaceSpec::Interface { rect, .. }
            | SurfaceSpec::Mirror { rect, .. }
            | SurfaceSpec::Splitter { rect, .. }
            | SurfaceSpec::OpaqueScreen { rect, .. } => rect.is_some(),
            SurfaceSpec::Shield { .. } => true,
            SurfaceSpec::Plate { .. } | SurfaceSpec::Wedge { .. } => false,
        };
        for surf in c.scene.surfaces.iter().filter(|x| !bounded(x)) {
            for (pt, n) in surface_planes(surf) {
                let scale = pt.length().max(1.0);
                let on = |p: &DVec3| (*p - pt).dot(n).abs() <= 1e-12 * scale;
                let lies_in = match segment {
                    Some((a, b)) => on(&a) && on(&b),
                    None => false,
                };
                if lies_in || points.iter().any(on) {
                    self.fail(
                        key,
                        format!(
                            "{} surface {:?}: a detector in an interface has no side; move the probe off the surface",
                            if lies_in { "the probe line lies in a face of" } else { "a probe point lies on" },
                            surf.name()
                        ),
                    );
                    return;
                }
            }
        }
    }

    /// Plates and wedges are unbounded slabs: two of them must not share any volume (nor a
    /// face). Non-parallel slabs always cross somewhere; parallel ones must be apart along the
    /// normal.
    fn intersecting_slabs(&mut self, s: &SceneSpec) {
        type Faces = Vec<(glam::DVec3, glam::DVec3)>;
        let slabs: Vec<(usize, &SurfaceSpec, Faces)> = s
            .surfaces
            .iter()
            .enumerate()
            .filter(|(_, x)| matches!(x, SurfaceSpec::Plate { .. } | SurfaceSpec::Wedge { .. }))
            .map(|(i, x)| (i, x, surface_planes(x)))
            .collect();
        for (k, (j, b, fb)) in slabs.iter().enumerate() {
            for (_, a, fa) in &slabs[..k] {
                let parallel = fa
                    .iter()
                    .chain(fb.iter())
                    .all(|(_, n)| n.cross(fa[0].1).length() < 1e-9);
                let apart = parallel && {
                    // Intervals along the common normal.
                    let n = fa[0].1;
                    let span = |f: &[(glam::DVec3, glam::DVec3)]| {
                        let (x, y) = (f[0].0.dot(n), f[1].0.dot(n));
                        (x.min(y), x.max(y))
                    };
                    let ((a0, a1), (b0, b1)) = (span(fa), span(fb));
                    a1 < b0 || b1 < a0
                };
                if !apart {
                    self.fail(
                        &format!("$.scene.surfaces[{j}].{}", b.kind()),
                        format!(
                            "{:?} and {:?} intersect or touch: {}; plates and wedges are unbounded slabs and must not share volume or a face",
                            a.name(),
                            b.name(),
                            if parallel {
                                "their thicknesses overlap along the normal"
                            } else {
                                "their faces are not parallel, so the unbounded slabs cross"
                            }
                        ),
                    );
                    return;
                }
            }
        }
    }
}
