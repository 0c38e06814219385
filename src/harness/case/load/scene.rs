//! Checks of the light and the scene: media, surfaces, plates and wedges, sources and where
//! they sit.

use super::*;

impl Validator {
    pub(super) fn light(&mut self, l: &Light) {
        match l {
            Light::Monochrome { wavelength_nm } => {
                self.wavelength("$.light.monochrome.wavelength_nm", *wavelength_nm)
            }
            Light::Gaussian {
                center_nm,
                fwhm_nm,
                samples,
                sigmas,
            } => {
                self.wavelength("$.light.gaussian.center_nm", *center_nm);
                self.positive(
                    "$.light.gaussian.fwhm_nm",
                    *fwhm_nm,
                    center_nm.abs() * 0.2,
                    "the FWHM (nm, at most 20% of the centre)",
                );
                if *samples < 2 || *samples > limits::MAX_SPECTRAL_SAMPLES {
                    self.fail(
                        "$.light.gaussian.samples",
                        format!(
                            "2 to {} spectral samples, got {samples}",
                            limits::MAX_SPECTRAL_SAMPLES
                        ),
                    );
                }
                self.range(
                    "$.light.gaussian.sigmas",
                    *sigmas,
                    1.0,
                    12.0,
                    "the sampled half-width in standard deviations",
                );
            }
        }
    }

    pub(super) fn scene(&mut self, s: &SceneSpec) {
        if s.media.is_empty() {
            self.fail("$.scene.media", "define at least the ambient medium");
        }
        for (name, m) in &s.media {
            let p = format!("$.scene.media.{name}");
            match m {
                MediumSpec::Constant { n } => {
                    let (lo, hi) = limits::INDEX;
                    if self.finite(&format!("{p}.constant.n"), *n) && !(*n >= lo && *n <= hi) {
                        self.fail(&format!("{p}.constant.n"), format!("a refractive index must be real and in [{lo}, {hi}] (lossy/complex indices are out of scope), got {n}"));
                    }
                }
                MediumSpec::Cauchy {
                    a,
                    b_um2,
                    c_um4,
                    min_nm,
                    max_nm,
                } => {
                    for (k, x) in [("a", a), ("b_um2", b_um2), ("c_um4", c_um4)] {
                        self.finite(&format!("{p}.cauchy.{k}"), *x);
                    }
                    self.wavelength(&format!("{p}.cauchy.min_nm"), *min_nm);
                    self.wavelength(&format!("{p}.cauchy.max_nm"), *max_nm);
                    if min_nm >= max_nm {
                        self.fail(&format!("{p}.cauchy.max_nm"), "max_nm must exceed min_nm");
                    }
                }
                MediumSpec::Sellmeier {
                    b,
                    c_um2,
                    min_nm,
                    max_nm,
                } => {
                    for k in 0..3 {
                        self.finite(&format!("{p}.sellmeier.b[{k}]"), b[k]);
                        self.finite(&format!("{p}.sellmeier.c_um2[{k}]"), c_um2[k]);
                    }
                    self.wavelength(&format!("{p}.sellmeier.min_nm"), *min_nm);
                    self.wavelength(&format!("{p}.sellmeier.max_nm"), *max_nm);
                    if min_nm >= max_nm {
                        self.fail(
                            &format!("{p}.sellmeier.max_nm"),
                            "max_nm must exceed min_nm",
                        );
                    }
                }
                MediumSpec::Bk7 {} => {}
            }
        }
        self.medium_ref("$.scene.ambient", &s.ambient, &s.media);
        let mut names = std::collections::BTreeSet::new();
        for (i, surf) in s.surfaces.iter().enumerate() {
            let p = format!("$.scene.surfaces[{i}]");
            let np = format!("{p}.{}.name", surf.kind());
            if !names.insert(surf.name().to_string()) {
                self.fail(
                    &np,
                    format!(
                        "surface names must be unique: {:?} appears twice",
                        surf.name()
                    ),
                );
            }
            if !name_ok(surf.name()) {
                self.fail(
                    &np,
                    format!("a surface name is 1–64 characters from [A-Za-z0-9_-] (a plate or wedge `p` has faces `p.top` and `p.bottom`), got {:?}", surf.name()),
                );
            }
            self.surface(&p, surf, s);
        }
        if s.sources.is_empty() {
            self.fail("$.scene.sources", "at least one source is required");
        }
        let mut snames = std::collections::BTreeSet::new();
        for (i, src) in s.sources.iter().enumerate() {
            let p = format!("$.scene.sources[{i}]");
            if !name_ok(&src.name) {
                self.fail(
                    &format!("{p}.name"),
                    format!(
                        "a source name is 1–64 characters from [A-Za-z0-9_-], got {:?}",
                        src.name
                    ),
                );
            }
            if !snames.insert(src.name.clone()) {
                self.fail(
                    &format!("{p}.name"),
                    format!("source names must be unique: {:?} appears twice", src.name),
                );
            }
            self.source(&p, src);
        }
    }

    /// The thickness and the three media of a plate or wedge at `q`.
    fn slab(
        &mut self,
        q: &str,
        thickness_um: f64,
        media: [&String; 3],
        defined: &BTreeMap<String, MediumSpec>,
    ) {
        let path = format!("{q}.thickness_um");
        if self.finite(&path, thickness_um)
            && !(limits::MIN_THICKNESS_UM..=1e6).contains(&thickness_um)
        {
            self.fail(
                &path,
                format!(
                    "a thickness (µm) must be in [{}, 1e6] (1 pm to 1 m), got {}",
                    num(limits::MIN_THICKNESS_UM),
                    num(thickness_um)
                ),
            );
        }
        for (k, m) in ["medium", "above", "below"].into_iter().zip(media) {
            self.medium_ref(&format!("{q}.{k}"), m, defined);
        }
    }

    pub(super) fn surface(&mut self, p: &str, surf: &SurfaceSpec, s: &SceneSpec) {
        match surf {
            SurfaceSpec::Interface {
                point_m,
                normal,
                front,
                back,
                rect,
                ..
            } => {
                let q = format!("{p}.interface");
                self.point(&format!("{q}.point_m"), point_m);
                self.direction(&format!("{q}.normal"), normal);
                self.medium_ref(&format!("{q}.front"), front, &s.media);
                self.medium_ref(&format!("{q}.back"), back, &s.media);
                if let Some(r) = rect {
                    self.rect(&format!("{q}.rect"), r, normal);
                }
            }
            SurfaceSpec::Plate {
                top_point_m,
                normal,
                thickness_um,
                medium,
                above,
                below,
                ..
            } => {
                let q = format!("{p}.plate");
                self.point(&format!("{q}.top_point_m"), top_point_m);
                self.direction(&format!("{q}.normal"), normal);
                self.slab(&q, *thickness_um, [medium, above, below], &s.media);
            }
            SurfaceSpec::Wedge {
                top_point_m,
                normal,
                thickness_um,
                angle_deg,
                hinge_axis,
                medium,
                above,
                below,
                ..
            } => {
                let q = format!("{p}.wedge");
                self.point(&format!("{q}.top_point_m"), top_point_m);
                self.direction(&format!("{q}.normal"), normal);
                self.direction(&format!("{q}.hinge_axis"), hinge_axis);
                self.not_parallel(
                    &format!("{q}.hinge_axis"),
                    hinge_axis,
                    normal,
                    "the hinge axis must not be parallel to the wedge's normal",
                );
                self.positive(
                    &format!("{q}.angle_deg"),
                    *angle_deg,
                    10.0,
                    "a wedge angle (degrees)",
                );
                self.slab(&q, *thickness_um, [medium, above, below], &s.media);
            }
            SurfaceSpec::Mirror {
                point_m,
                normal,
                rect,
                ..
            } => {
                let q = format!("{p}.mirror");
                self.point(&format!("{q}.point_m"), point_m);
                self.direction(&format!("{q}.normal"), normal);
                if let Some(r) = rect {
                    self.rect(&format!("{q}.rect"), r, normal);
                }
            }
            SurfaceSpec::Splitter {
                point_m,
                normal,
                reflectance,
                rect,
                ..
            } => {
                let q = format!("{p}.splitter");
                self.point(&format!("{q}.point_m"), point_m);
                self.direction(&format!("{q}.normal"), normal);
                self.range(
                    &format!("{q}.reflectance"),
                    *reflectance,
                    0.0,
                    1.0,
                    "a power reflectance",
                );
                if let Some(r) = rect {
                    self.rect(&format!("{q}.rect"), r, normal);
                }
            }
            SurfaceSpec::Shield {
                point_m,
                normal,
                rect,
                ..
            } => {
                let q = format!("{p}.shield");
                self.point(&format!("{q}.point_m"), point_m);
                self.direction(&format!("{q}.normal"), normal);
                self.rect(&format!("{q}.rect"), rect, normal);
            }
            SurfaceSpec::OpaqueScreen {
                point_m,
                normal,
                rect,
                u_axis,
                apertures,
                ..
            } => {
                let q = format!("{p}.opaque_screen");
                self.point(&format!("{q}.point_m"), point_m);
                self.direction(&format!("{q}.normal"), normal);
                self.direction(&format!("{q}.u_axis"), u_axis);
                self.not_parallel(
                    &format!("{q}.u_axis"),
                    u_axis,
                    normal,
                    "u_axis must not be parallel to the screen's normal",
                );
                if let Some(r) = rect {
                    self.rect(&format!("{q}.rect"), r, normal);
                }
                for (k, a) in apertures.iter().enumerate() {
                    let ap = format!("{q}.apertures[{k}]");
                    for j in 0..2 {
                        self.range(
                            &format!("{ap}.center_m[{j}]"),
                            a.center_m[j],
                            -limits::MAX_LENGTH_M,
                            limits::MAX_LENGTH_M,
                            "an aperture centre (m)",
                        );
                        self.positive(
                            &format!("{ap}.size_m[{j}]"),
                            a.size_m[j],
                            2.0 * limits::MAX_LENGTH_M,
                            "an aperture size (m)",
                        );
                    }
                    if let Some(r) = rect {
                        for j in 0..2 {
                            if (a.center_m[j].abs() + 0.5 * a.size_m[j]) > 0.5 * r.size_m[j] {
                                self.fail(&format!("{ap}.size_m[{j}]"), format!("the aperture reaches beyond its screen (screen half-size {} m)", 0.5 * r.size_m[j]));
                            }
                        }
                    }
                }
            }
        }
    }

    pub(super) fn source(&mut self, p: &str, src: &SourceSpec) {
        match &src.emitter {
            EmitterSpec::Point { position_m } => {
                self.point(&format!("{p}.emitter.point.position_m"), position_m)
            }
            EmitterSpec::Line { point_m, axis } => {
                self.point(&format!("{p}.emitter.line.point_m"), point_m);
                self.direction(&format!("{p}.emitter.line.axis"), axis);
            }
            EmitterSpec::PlaneWave {
                direction,
                reference_point_m,
            } => {
                self.direction(&format!("{p}.emitter.plane_wave.direction"), direction);
                self.point(
                    &format!("{p}.emitter.plane_wave.reference_point_m"),
                    reference_point_m,
                );
            }
        }
        match &src.polarization {
            PolarizationSpec::Linear {
                reference,
                angle_deg,
            } => {
                self.direction(&format!("{p}.polarization.linear.reference"), reference);
                self.range(
                    &format!("{p}.polarization.linear.angle_deg"),
                    *angle_deg,
                    -360.0,
                    360.0,
                    "a polarization angle (degrees)",
                );
            }
            PolarizationSpec::Unpolarized { model, reference } => {
                let path = format!("{p}.polarization.unpolarized.reference");
                match (model, reference) {
                    (UnpolarizedModel::PaperTwoChannel, Some(r)) => {
                        self.direction(&path, r);
                    }
                    (UnpolarizedModel::PaperTwoChannel, None) => self.fail(
                        &path,
                        "the model \"paper_two_channel\" builds its two channels from a \
                         reference direction: give one, e.g. [0, 0, 1]",
                    ),
                    (UnpolarizedModel::BasisFree, Some(_)) => self.fail(
                        &path,
                        "unpolarized light is basis-free by default (three incoherent dipoles \
                         along x, y, z) and takes no reference; remove it, or write \
                         \"model\": \"paper_two_channel\" for the paper's two channels built \
                         from it",
                    ),
                    (UnpolarizedModel::BasisFree, None) => {}
                }
            }
        }
        self.positive(
            &format!("{p}.intensity"),
            src.intensity,
            1e12,
            "a source intensity",
        );
        if src.coherence_group > limits::MAX_COHERENCE_GROUP {
            self.fail(
                &format!("{p}.coherence_group"),
                format!(
                    "a coherence group is 0 to {}, got {}",
                    limits::MAX_COHERENCE_GROUP,
                    src.coherence_group
                ),
            );
        }
        if let Some(l) = src.coherence_length_m {
            self.positive(
                &format!("{p}.coherence_length_m"),
                l,
                limits::MAX_LENGTH_M,
                "a coherence length (m)",
            );
        }
    }

    /// Where a source sits relative to the surfaces (after every field is valid): not on a
    /// surface, not inside a plate or wedge, in the ambient medium, a line source not crossing
    /// an unbounded surface, and a plane wave's polarization reference not along its direction.
    pub(super) fn placement(&mut self, p: &str, src: &SourceSpec, s: &SceneSpec) {
        use glam::DVec3;
        // The polarization reference, if the source has one (basis-free unpolarized light has
        // none).
        let pol_reference = match &src.polarization {
            PolarizationSpec::Linear { reference, .. } => {
                Some((format!("{p}.polarization.linear.reference"), reference))
            }
            PolarizationSpec::Unpolarized {
                reference: Some(reference),
                ..
            } => Some((format!("{p}.polarization.unpolarized.reference"), reference)),
            PolarizationSpec::Unpolarized {
                reference: None, ..
            } => None,
        };
        let (anchor, line_axis) = match &src.emitter {
            EmitterSpec::Point { position_m } => (DVec3::from_array(*position_m), None),
            EmitterSpec::Line { point_m, axis } => (DVec3::from_array(*point_m), unit(axis)),
            EmitterSpec::PlaneWave { direction, .. } => {
                if let Some((pol_path, reference)) = &pol_reference {
                    self.not_parallel(
                        pol_path,
                        reference,
                        direction,
                        "the polarization reference must not be parallel to the plane wave's direction (the field would be undefined)",
                    );
                }
                return;
            }
        };
        let on = |x: f64| x.abs() < 1e-12;
        for surf in &s.surfaces {
            let name = surf.name();
            // (plane point, unit normal, bounded?, medium in front, medium behind) per face.
            type Face<'a> = (DVec3, DVec3, bool, Option<&'a str>, Option<&'a str>);
            let mut faces: Vec<Face> = Vec::new();
            let mut slab = None;
            match surf {
                SurfaceSpec::Interface {
                    point_m,
                    normal,
                    rect,
                    front,
                    back,
                    ..
                } => faces.push((
                    DVec3::from_array(*point_m),
                    unit(normal).unwrap_or(DVec3::Z),
                    rect.is_some(),
                    Some(front),
                    Some(back),
                )),
                SurfaceSpec::Mirror {
                    point_m,
                    normal,
                    rect,
                    ..
                }
                | SurfaceSpec::Splitter {
                    point_m,
                    normal,
                    rect,
                    ..
                }
                | SurfaceSpec::OpaqueScreen {
                    point_m,
                    normal,
                    rect,
                    ..
                } => faces.push((
                    DVec3::from_array(*point_m),
                    unit(normal).unwrap_or(DVec3::Z),
                    rect.is_some(),
                    None,
                    None,
                )),
                SurfaceSpec::Shield {
                    point_m, normal, ..
                } => faces.push((
                    DVec3::from_array(*point_m),
                    unit(normal).unwrap_or(DVec3::Z),
                    true,
                    None,
                    None,
                )),
                SurfaceSpec::Plate {
                    top_point_m,
                    normal,
                    thickness_um,
                    above,
                    below,
                    ..
                } => {
                    let (t, n) = (
                        DVec3::from_array(*top_point_m),
                        unit(normal).unwrap_or(DVec3::Z),
                    );
                    let b = t - thickness_um * 1e-6 * n;
                    faces.push((t, n, false, Some(above), None));
                    faces.push((b, n, false, None, Some(below)));
                    slab = Some(((t, n), (b, n)));
                }
                SurfaceSpec::Wedge {
                    top_point_m,
                    normal,
                    thickness_um,
                    angle_deg,
                    hinge_axis,
                    above,
                    below,
                    ..
                } => {
                    let (t, n) = (
                        DVec3::from_array(*top_point_m),
                        unit(normal).unwrap_or(DVec3::Z),
                    );
                    let h = DVec3::from_array(*hinge_axis);
                    let axis = (h - h.dot(n) * n).normalize_or_zero();
                    let tilted = glam::DQuat::from_axis_angle(axis, angle_deg.to_radians()) * n;
                    let b = t - thickness_um * 1e-6 * n;
                    faces.push((t, n, false, Some(above), None));
                    faces.push((b, tilted, false, None, Some(below)));
                    slab = Some(((t, n), (b, tilted)));
                }
            }
            for (pt, n, bounded, front, back) in faces {
                let d = (anchor - pt).dot(n);
                if on(d) {
                    self.fail(
                        &format!("{p}.emitter"),
                        format!("the source lies on surface {name:?}: move it off the surface"),
                    );
                    return;
                }
                if bounded {
                    continue;
                }
                if let Some(a) = line_axis
                    && a.dot(n).abs() > 1e-9
                {
                    let kind = match &src.emitter {
                        EmitterSpec::Line { .. } => "line",
                        _ => "point",
                    };
                    self.fail(
                            &format!("{p}.emitter.{kind}.axis"),
                            format!("the line source crosses the unbounded surface {name:?}: its axis must be parallel to the surface"),
                        );
                    return;
                }
                let side = if d > 0.0 { front } else { back };
                if let Some(m) = side
                    && m != s.ambient
                {
                    self.fail(
                            &format!("{p}.emitter"),
                            format!("the source is on the {m:?} side of surface {name:?}, but sources must be in the ambient medium {:?}", s.ambient),
                        );
                    return;
                }
            }
            if let Some(((t, n), (b, nb))) = slab
                && (anchor - t).dot(n) < 0.0
                && (anchor - b).dot(nb) > 0.0
            {
                self.fail(
                        &format!("{p}.emitter"),
                        format!("the source is inside {name:?} (between its faces); sources must be in the ambient medium {:?}", s.ambient),
                    );
                return;
            }
        }
    }
}
