//! Loading and validating a case file. Every error names the file, the JSON path of the bad
//! field and what is allowed; nothing is run or written for an invalid case.

use super::spec::*;
use std::collections::BTreeMap;
use std::fmt;
use std::path::{Path, PathBuf};

/// Documented caps (also in cases/README.md).
pub mod limits {
    /// Wavelengths accepted anywhere (vacuum, nm).
    pub const WAVELENGTH_NM: (f64, f64) = (200.0, 2500.0);
    /// Probe points per case.
    pub const MAX_PROBE_POINTS: usize = 100_000;
    /// Spectral samples per case.
    pub const MAX_SPECTRAL_SAMPLES: usize = 4096;
    /// Internal reflections per path.
    pub const MAX_INTERNAL_REFLECTIONS: usize = 2000;
    /// Largest coordinate or length (m).
    pub const MAX_LENGTH_M: f64 = 1.0e3;
    /// Refractive indices accepted.
    pub const INDEX: (f64, f64) = (1.0e-3, 10.0);
}

/// A case-file error: file, JSON path, message.
#[derive(Clone, Debug, PartialEq)]
pub struct CaseError {
    pub file: PathBuf,
    pub json_path: String,
    pub message: String,
}

impl fmt::Display for CaseError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(
            f,
            "{}: {}: {}",
            self.file.display(),
            self.json_path,
            self.message
        )
    }
}

impl std::error::Error for CaseError {}

/// A validated case.
#[derive(Clone, Debug)]
pub struct Case {
    pub file: PathBuf,
    pub spec: CaseFile,
}

/// Read, parse and validate a case file.
pub fn load(path: &Path) -> Result<Case, CaseError> {
    let err = |json_path: &str, message: String| CaseError {
        file: path.to_path_buf(),
        json_path: json_path.into(),
        message,
    };
    let text = std::fs::read_to_string(path)
        .map_err(|e| err("$", format!("cannot read the file: {e}")))?;
    parse(path, &text)
}

/// Parse and validate case text (the file name is used in errors only).
pub fn parse(path: &Path, text: &str) -> Result<Case, CaseError> {
    let de = &mut serde_json::Deserializer::from_str(text);
    let spec: CaseFile = serde_path_to_error::deserialize(de).map_err(|e| {
        let p = e.path().to_string();
        CaseError {
            file: path.to_path_buf(),
            json_path: if p == "." {
                "$".into()
            } else {
                format!("$.{p}")
            },
            message: e.into_inner().to_string(),
        }
    })?;
    let mut v = Validator { errors: Vec::new() };
    v.case(&spec);
    match v.errors.into_iter().next() {
        Some((json_path, message)) => Err(CaseError {
            file: path.to_path_buf(),
            json_path,
            message,
        }),
        None => Ok(Case {
            file: path.to_path_buf(),
            spec,
        }),
    }
}

struct Validator {
    errors: Vec<(String, String)>,
}

impl Validator {
    fn fail(&mut self, path: &str, msg: impl Into<String>) {
        self.errors.push((path.to_string(), msg.into()));
    }

    fn finite(&mut self, path: &str, x: f64) -> bool {
        if !x.is_finite() {
            self.fail(path, format!("must be a finite number, got {x}"));
            return false;
        }
        true
    }

    fn range(&mut self, path: &str, x: f64, lo: f64, hi: f64, what: &str) {
        if self.finite(path, x) && !(x >= lo && x <= hi) {
            self.fail(path, format!("{what} must be in [{lo}, {hi}], got {x}"));
        }
    }

    fn positive(&mut self, path: &str, x: f64, hi: f64, what: &str) {
        if self.finite(path, x) && !(x > 0.0 && x <= hi) {
            self.fail(path, format!("{what} must be > 0 and ≤ {hi}, got {x}"));
        }
    }

    fn point(&mut self, path: &str, v: &Vec3) {
        for (k, x) in v.iter().enumerate() {
            self.range(
                &format!("{path}[{k}]"),
                *x,
                -limits::MAX_LENGTH_M,
                limits::MAX_LENGTH_M,
                "a coordinate (m)",
            );
        }
    }

    fn direction(&mut self, path: &str, v: &Vec3) {
        if v.iter().any(|x| !x.is_finite()) {
            self.fail(path, "a direction must have finite components");
        } else if glam::DVec3::from_array(*v).length() < 1e-12 {
            self.fail(path, "a direction must not be the zero vector");
        }
    }

    fn medium_ref(&mut self, path: &str, name: &str, media: &BTreeMap<String, MediumSpec>) {
        if !media.contains_key(name) {
            let known: Vec<&str> = media.keys().map(|s| s.as_str()).collect();
            self.fail(
                path,
                format!("unknown medium {name:?}; defined media: {known:?}"),
            );
        }
    }

    fn wavelength(&mut self, path: &str, nm: f64) {
        let (lo, hi) = limits::WAVELENGTH_NM;
        self.range(path, nm, lo, hi, "a wavelength (nm)");
    }

    fn rect(&mut self, path: &str, r: &RectSpec, normal: &Vec3) {
        for k in 0..2 {
            self.positive(
                &format!("{path}.size_m[{k}]"),
                r.size_m[k],
                2.0 * limits::MAX_LENGTH_M,
                "a size (m)",
            );
        }
        self.direction(&format!("{path}.u_axis"), &r.u_axis);
        let (u, n) = (
            glam::DVec3::from_array(r.u_axis),
            glam::DVec3::from_array(*normal),
        );
        if u.length() > 0.0
            && n.length() > 0.0
            && u.normalize().cross(n.normalize()).length() < 1e-9
        {
            self.fail(
                &format!("{path}.u_axis"),
                "u_axis must not be parallel to the surface normal",
            );
        }
    }

    fn case(&mut self, c: &CaseFile) {
        if c.name.is_empty()
            || c.name.len() > 64
            || !c
                .name
                .chars()
                .all(|ch| ch.is_ascii_lowercase() || ch.is_ascii_digit() || ch == '_')
        {
            self.fail("$.name", format!("a case name is 1–64 characters from [a-z0-9_] (it names output files), got {:?}", c.name));
        }
        self.light(&c.light);
        self.scene(&c.scene);
        self.probe(&c.probe, &c.scene);
        if c.references.is_empty() {
            self.fail("$.references", "at least one reference is required");
        }
        let mut labels = std::collections::BTreeSet::new();
        for (i, r) in c.references.iter().enumerate() {
            self.reference(&format!("$.references[{i}]"), r, &c.scene);
            let label = r
                .label
                .clone()
                .unwrap_or_else(|| super::reference::name(&r.model));
            if !label
                .chars()
                .all(|ch| ch.is_ascii_alphanumeric() || ch == '_')
                || label.is_empty()
            {
                self.fail(
                    &format!("$.references[{i}].label"),
                    format!("a label is 1+ characters from [A-Za-z0-9_], got {label:?}"),
                );
            }
            if !labels.insert(label.clone()) {
                self.fail(
                    &format!("$.references[{i}].label"),
                    format!(
                        "metric name {label:?} is used twice: give the reference a distinct `label`"
                    ),
                );
            }
        }
        if let Some(f) = &c.fidelities {
            if f.is_empty() {
                self.fail(
                    "$.fidelities",
                    "list at least one fidelity level, or omit the key for all",
                );
            }
            if !f.contains(&crate::fidelity::Fidelity::Vector) {
                self.fail(
                    "$.fidelities",
                    "the `vector` level (the reference) must be run",
                );
            }
        }
        let t = &c.trace;
        if t.max_internal_reflections > limits::MAX_INTERNAL_REFLECTIONS {
            self.fail(
                "$.trace.max_internal_reflections",
                format!(
                    "at most {} internal reflections, got {}",
                    limits::MAX_INTERNAL_REFLECTIONS,
                    t.max_internal_reflections
                ),
            );
        }
        if let Some(e) = t.airy_tail_epsilon {
            self.range(
                "$.trace.airy_tail_epsilon",
                e,
                1e-15,
                0.5,
                "the Airy tail bound",
            );
        }
        self.range(
            "$.trace.golden_tolerance",
            t.golden_tolerance,
            0.0,
            1.0,
            "the golden tolerance",
        );
    }

    fn light(&mut self, l: &Light) {
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

    fn scene(&mut self, s: &SceneSpec) {
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
            if !names.insert(surf.name().to_string()) {
                self.fail(
                    &format!("{p}.name"),
                    format!(
                        "surface names must be unique: {:?} appears twice",
                        surf.name()
                    ),
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
            if !snames.insert(src.name.clone()) {
                self.fail(
                    &format!("{p}.name"),
                    format!("source names must be unique: {:?} appears twice", src.name),
                );
            }
            self.source(&p, src, s);
        }
    }

    fn surface(&mut self, p: &str, surf: &SurfaceSpec, s: &SceneSpec) {
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
                self.positive(
                    &format!("{q}.thickness_um"),
                    *thickness_um,
                    1e6,
                    "a thickness (µm)",
                );
                for (k, m) in [("medium", medium), ("above", above), ("below", below)] {
                    self.medium_ref(&format!("{q}.{k}"), m, &s.media);
                }
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
                self.positive(
                    &format!("{q}.thickness_um"),
                    *thickness_um,
                    1e6,
                    "a thickness (µm)",
                );
                self.positive(
                    &format!("{q}.angle_deg"),
                    *angle_deg,
                    10.0,
                    "a wedge angle (degrees)",
                );
                for (k, m) in [("medium", medium), ("above", above), ("below", below)] {
                    self.medium_ref(&format!("{q}.{k}"), m, &s.media);
                }
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

    fn source(&mut self, p: &str, src: &SourceSpec, s: &SceneSpec) {
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
            PolarizationSpec::Unpolarized { reference } => self.direction(
                &format!("{p}.polarization.unpolarized.reference"),
                reference,
            ),
        }
        self.positive(
            &format!("{p}.intensity"),
            src.intensity,
            1e12,
            "a source intensity",
        );
        if let Some(l) = src.coherence_length_m {
            self.positive(
                &format!("{p}.coherence_length_m"),
                l,
                limits::MAX_LENGTH_M,
                "a coherence length (m)",
            );
        }
        // A point or line source must not sit on an interacting surface.
        let anchor = match &src.emitter {
            EmitterSpec::Point { position_m } => Some(*position_m),
            EmitterSpec::Line { point_m, .. } => Some(*point_m),
            EmitterSpec::PlaneWave { .. } => None,
        };
        if let Some(a) = anchor {
            let a = glam::DVec3::from_array(a);
            for surf in &s.surfaces {
                let (pt, n) = match surf {
                    SurfaceSpec::Interface {
                        point_m, normal, ..
                    }
                    | SurfaceSpec::Mirror {
                        point_m, normal, ..
                    }
                    | SurfaceSpec::Splitter {
                        point_m, normal, ..
                    }
                    | SurfaceSpec::Shield {
                        point_m, normal, ..
                    }
                    | SurfaceSpec::OpaqueScreen {
                        point_m, normal, ..
                    } => (*point_m, *normal),
                    SurfaceSpec::Plate {
                        top_point_m,
                        normal,
                        ..
                    }
                    | SurfaceSpec::Wedge {
                        top_point_m,
                        normal,
                        ..
                    } => (*top_point_m, *normal),
                };
                let n = glam::DVec3::from_array(n);
                if n.length() > 0.0
                    && (a - glam::DVec3::from_array(pt)).dot(n.normalize()).abs() < 1e-12
                {
                    self.fail(
                        &format!("{p}.emitter"),
                        format!(
                            "the source lies on surface {:?}: move it off the surface",
                            surf.name()
                        ),
                    );
                }
            }
        }
    }

    fn probe(&mut self, probe: &Probe, s: &SceneSpec) {
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
                        self.range(
                            "$.probe.sweep.from",
                            *from,
                            0.0,
                            90.0,
                            "an angle of incidence (degrees)",
                        );
                        self.range(
                            "$.probe.sweep.to",
                            *to,
                            0.0,
                            90.0,
                            "an angle of incidence (degrees)",
                        );
                        self.direction(
                            "$.probe.sweep.parameter.incidence_angle_deg.surface_normal",
                            surface_normal,
                        );
                        self.direction(
                            "$.probe.sweep.parameter.incidence_angle_deg.in_plane_axis",
                            in_plane_axis,
                        );
                    }
                    SweepParameter::WavelengthNm {} => {
                        self.wavelength("$.probe.sweep.from", *from);
                        self.wavelength("$.probe.sweep.to", *to);
                    }
                    SweepParameter::ThicknessNm { surface } => {
                        self.positive("$.probe.sweep.from", *from, 1e9, "a thickness (nm)");
                        self.positive("$.probe.sweep.to", *to, 1e9, "a thickness (nm)");
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
        }
    }

    fn observer(&mut self, p: &str, o: &Observer, s: &SceneSpec) {
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

    fn reference(&mut self, p: &str, r: &ReferenceSpec, s: &SceneSpec) {
        if p.ends_with("[0]")
            && !r
                .tolerances
                .contains_key(&crate::fidelity::Fidelity::Vector)
        {
            self.fail(&format!("{p}.tolerances"), "the first (primary) reference needs a `vector` tolerance, e.g. {\"vector\": 1e-9}; later references may be information only ({})");
        }
        for (f, t) in &r.tolerances {
            let tp = format!("{p}.tolerances.{f}");
            self.range(&tp, *t, 0.0, 10.0, "a relative tolerance");
            if *t > 1e-9 && *f == crate::fidelity::Fidelity::Vector && r.tolerance_note.is_none() {
                self.fail(&tp, "a vector tolerance looser than 1e-9 needs a `tolerance_note` saying why it is physically forced");
            }
        }
        let surface_exists = |name: &str| s.surfaces.iter().any(|x| x.name() == name);
        let need = |v: &mut Self, key: &str, name: &str| {
            if !surface_exists(name) {
                let known: Vec<&str> = s.surfaces.iter().map(|x| x.name()).collect();
                v.fail(
                    &format!("{p}.model.{key}"),
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
                    self.positive(
                        &format!("{p}.model.coherence_gaussian.fwhm_nm"),
                        *f,
                        1000.0,
                        "a bandwidth (nm)",
                    );
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
                if *tir_count == 0 || *tir_count > 100 {
                    self.fail(
                        &format!("{p}.model.rhomb_retardance.tir_count"),
                        "1 to 100 TIRs",
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
