//! Checks of the probe, the observer and the references.

use super::*;

impl Validator {
    pub(super) fn probe(&mut self, probe: &Probe, s: &SceneSpec) {
        let count_ok = |v: &mut Self, path: &str, n: usize| {
            if n == 0 || n > limits::MAX_PROBE_POINTS {
                v.fail(
                    path,
                    format!("1 to {} probe points, got {n}", limits::MAX_PROBE_POINTS),
                );
            }
        };
        match probe {
            Probe::Line {
                from_m,
                to_m,
                count,
                origin_m,
                looks_toward,
            } => {
                if let Some(l) = looks_toward {
                    self.direction("$.probe.line.looks_toward", l);
                }
                self.point("$.probe.line.from_m", from_m);
                self.point("$.probe.line.to_m", to_m);
                if let Some(o) = origin_m {
                    self.point("$.probe.line.origin_m", o);
                }
                count_ok(self, "$.probe.line.count", *count);
                if *count > 1 && from_m == to_m {
                    self.fail("$.probe.line.to_m", "the probe line has zero length");
                }
            }
            Probe::Sweep {
                parameter,
                from,
                to,
                count,
                observe,
            } => {
                count_ok(self, "$.probe.sweep.count", *count);
                match parameter {
                    SweepParameter::IncidenceAngleDeg {
                        surface_normal,
                        in_plane_axis,
                    } => {
                        // 90° is grazing: the wave runs along the surface and never meets it.
                        for (key, x) in [("from", *from), ("to", *to)] {
                            let path = format!("$.probe.sweep.{key}");
                            if self.finite(&path, x) && !(0.0..90.0).contains(&x) {
                                self.fail(
                                    &path,
                                    format!("an angle of incidence (degrees) must be in [0, 90) (90 is grazing), got {}", num(x)),
                                );
                            }
                        }
                        self.direction(
                            "$.probe.sweep.parameter.incidence_angle_deg.surface_normal",
                            surface_normal,
                        );
                        self.direction(
                            "$.probe.sweep.parameter.incidence_angle_deg.in_plane_axis",
                            in_plane_axis,
                        );
                        self.not_parallel(
                            "$.probe.sweep.parameter.incidence_angle_deg.in_plane_axis",
                            in_plane_axis,
                            surface_normal,
                            "in_plane_axis must not be parallel to surface_normal (they span the plane of incidence)",
                        );
                    }
                    SweepParameter::WavelengthNm {} => {
                        self.wavelength("$.probe.sweep.from", *from);
                        self.wavelength("$.probe.sweep.to", *to);
                    }
                    SweepParameter::ThicknessNm { surface } => {
                        let min_nm = limits::MIN_THICKNESS_UM * 1e3;
                        for (key, x) in [("from", *from), ("to", *to)] {
                            self.range(
                                &format!("$.probe.sweep.{key}"),
                                x,
                                min_nm,
                                1e9,
                                "a thickness (nm, 1 pm to 1 m)",
                            );
                        }
                        if !s.surfaces.iter().any(|x| {
                            x.name() == surface
                                && matches!(
                                    x,
                                    SurfaceSpec::Plate { .. } | SurfaceSpec::Wedge { .. }
                                )
                        }) {
                            self.fail(
                                "$.probe.sweep.parameter.thickness_nm.surface",
                                format!("no plate or wedge named {surface:?}"),
                            );
                        }
                    }
                }
                self.observer("$.probe.sweep.observe", observe, s);
            }
            Probe::Single { observe } => self.observer("$.probe.single.observe", observe, s),
            Probe::Grid {
                center_m,
                u_axis,
                v_axis,
                size_m,
                pixels,
                looks_toward,
            } => {
                self.point("$.probe.grid.center_m", center_m);
                self.direction("$.probe.grid.u_axis", u_axis);
                self.direction("$.probe.grid.v_axis", v_axis);
                let (u, w) = (
                    glam::DVec3::from_array(*u_axis),
                    glam::DVec3::from_array(*v_axis),
                );
                if u.length() > 0.0
                    && w.length() > 0.0
                    && u.normalize().cross(w.normalize()).length() < 1e-9
                {
                    self.fail(
                        "$.probe.grid.v_axis",
                        "v_axis must not be parallel to u_axis",
                    );
                }
                for (k, &size) in size_m.iter().enumerate() {
                    self.positive(
                        &format!("$.probe.grid.size_m[{k}]"),
                        size,
                        2.0 * limits::MAX_LENGTH_M,
                        "a size (m)",
                    );
                }
                if pixels[0] == 0
                    || pixels[1] == 0
                    || pixels[0].saturating_mul(pixels[1]) > limits::MAX_PROBE_POINTS
                {
                    self.fail(
                        "$.probe.grid.pixels",
                        format!(
                            "[columns, rows] ≥ 1 with at most {} points in all, got {pixels:?}",
                            limits::MAX_PROBE_POINTS
                        ),
                    );
                }
                if let Some(l) = looks_toward {
                    self.direction("$.probe.grid.looks_toward", l);
                }
            }
        }
    }

    pub(super) fn observer(&mut self, p: &str, o: &Observer, s: &SceneSpec) {
        match o {
            Observer::Point {
                position_m,
                looks_toward,
            } => {
                self.point(&format!("{p}.point.position_m"), position_m);
                if let Some(l) = looks_toward {
                    self.direction(&format!("{p}.point.looks_toward"), l);
                }
            }
            Observer::FarField {
                surface_normal,
                exit_medium,
                ..
            } => {
                self.direction(&format!("{p}.far_field.surface_normal"), surface_normal);
                if let Some(m) = exit_medium {
                    self.medium_ref(&format!("{p}.far_field.exit_medium"), m, &s.media);
                }
            }
            Observer::Direction {
                direction,
                reference_point_m,
            } => {
                self.direction(&format!("{p}.direction.direction"), direction);
                self.point(
                    &format!("{p}.direction.reference_point_m"),
                    reference_point_m,
                );
            }
        }
    }

    pub(super) fn reference(&mut self, p: &str, r: &ReferenceSpec, s: &SceneSpec, light: &Light) {
        if p.ends_with("[0]")
            && !r
                .tolerances
                .contains_key(&crate::accumulate::fidelity::Fidelity::Vector)
        {
            self.fail(&format!("{p}.tolerances"), "the first (primary) reference needs a `vector` tolerance, e.g. {\"vector\": 1e-9}; later references may be information only ({})");
        }
        for (f, t) in &r.tolerances {
            let tp = format!("{p}.tolerances.{f}");
            self.range(&tp, *t, 0.0, 10.0, "a relative tolerance");
            if *t > 1e-9
                && *f == crate::accumulate::fidelity::Fidelity::Vector
                && r.tolerance_note.is_none()
            {
                self.fail(&tp, "a vector tolerance looser than 1e-9 needs a `tolerance_note` saying why it is physically forced");
            }
        }
        if r.tolerance_note
            .as_deref()
            .is_some_and(|n| n.trim().is_empty())
        {
            self.fail(
                &format!("{p}.tolerance_note"),
                "a tolerance note says why the tolerance is physically forced: write it, or drop the key",
            );
        }
        let surface_exists = |name: &str| s.surfaces.iter().any(|x| x.name() == name);
        let variant = crate::harness::case::reference::name(&r.model);
        let need = |v: &mut Self, key: &str, name: &str| {
            if !surface_exists(name) {
                let known: Vec<&str> = s.surfaces.iter().map(|x| x.name()).collect();
                v.fail(
                    &format!("{p}.model.{variant}.{key}"),
                    format!("no surface named {name:?}; surfaces: {known:?}"),
                );
            }
        };
        match &r.model {
            ReferenceModel::TwoBeamPlate { plate } | ReferenceModel::CoherenceP9 { plate } => {
                need(self, "plate", plate)
            }
            ReferenceModel::CoherenceGaussian { plate, fwhm_nm } => {
                need(self, "plate", plate);
                if let Some(f) = fwhm_nm {
                    let fp = format!("{p}.model.coherence_gaussian.fwhm_nm");
                    match light {
                        Light::Gaussian { .. } => self.fail(
                            &fp,
                            "fwhm_nm is for monochromatic cases (to judge another coherence model); with Gaussian light the bandwidth is the light's: drop this key",
                        ),
                        Light::Monochrome { wavelength_nm } => self.positive(
                            &fp,
                            *f,
                            0.2 * wavelength_nm.abs(),
                            "a bandwidth (FWHM, nm, at most 20% of the wavelength)",
                        ),
                    }
                }
            }
            ReferenceModel::Airy {
                film,
                index_override,
            } => {
                need(self, "film", film);
                if let Some(n) = index_override {
                    self.range(
                        &format!("{p}.model.airy.index_override"),
                        *n,
                        limits::INDEX.0,
                        limits::INDEX.1,
                        "a refractive index",
                    );
                }
            }
            ReferenceModel::Wedge { wedge } | ReferenceModel::WedgeSpacing { wedge, .. } => {
                need(self, "wedge", wedge)
            }
            ReferenceModel::RhombRetardance {
                glass,
                tir_surface,
                tir_count,
            } => {
                self.medium_ref(
                    &format!("{p}.model.rhomb_retardance.glass"),
                    glass,
                    &s.media,
                );
                need(self, "tir_surface", tir_surface);
                if *tir_count == 0 || *tir_count > limits::MAX_TIR_COUNT {
                    self.fail(
                        &format!("{p}.model.rhomb_retardance.tir_count"),
                        format!("1 to {} TIRs, got {tir_count}", limits::MAX_TIR_COUNT),
                    );
                }
            }
            ReferenceModel::PlaneWaveBeams { beams } => {
                if beams.is_empty() {
                    self.fail(
                        &format!("{p}.model.plane_wave_beams.beams"),
                        "list at least one beam",
                    );
                }
                for (k, b) in beams.iter().enumerate() {
                    if !s.sources.iter().any(|x| x.name == b.source) {
                        self.fail(
                            &format!("{p}.model.plane_wave_beams.beams[{k}].source"),
                            format!("no source named {:?}", b.source),
                        );
                    }
                    for (j, e) in b.events.iter().enumerate() {
                        if !surface_exists(&e.surface)
                            && !surface_exists(e.surface.split('.').next().unwrap_or(""))
                        {
                            self.fail(
                                &format!(
                                    "{p}.model.plane_wave_beams.beams[{k}].events[{j}].surface"
                                ),
                                format!("no surface named {:?}", e.surface),
                            );
                        }
                    }
                }
            }
            ReferenceModel::Michelson { splitter, mirrors } => {
                need(self, "splitter", splitter);
                need(self, "mirrors[0]", &mirrors[0]);
                need(self, "mirrors[1]", &mirrors[1]);
            }
            ReferenceModel::YoungExact {}
            | ReferenceModel::YoungParaxial {}
            | ReferenceModel::YoungSpacing { .. }
            | ReferenceModel::Lloyd {}
            | ReferenceModel::LloydVisibility {}
            | ReferenceModel::IncoherentSum {} => {}
        }
    }
}
