//! Field-by-field checks of a case file: finite numbers, ranges, unit directions and names, and
//! the order in which `Validator::case` visits the sections.

use super::*;

/// The unit vector of a valid direction, `None` if it cannot be normalized.
pub(super) fn unit(v: &Vec3) -> Option<glam::DVec3> {
    let (lo, hi) = limits::DIRECTION_LENGTH;
    let d = glam::DVec3::from_array(*v);
    let len = d.length();
    (len.is_finite() && len >= lo && len <= hi).then(|| d / len)
}

/// A number for a message: plain in [1e-3, 1e6), else in exponent form (1e-15, not 0.000…1).
pub(super) fn num(x: f64) -> String {
    if x == 0.0 || (x.abs() >= 1e-3 && x.abs() < 1e6) {
        format!("{x}")
    } else {
        format!("{x:e}")
    }
}

/// The number of probe points of a probe (saturating: a grid's product cannot overflow).
pub fn probe_point_count(p: &Probe) -> usize {
    match p {
        Probe::Line { count, .. } | Probe::Sweep { count, .. } => *count,
        Probe::Single { .. } => 1,
        Probe::Grid { pixels, .. } => pixels[0].saturating_mul(pixels[1]),
    }
}

/// Surface and source names: 1–64 characters from [A-Za-z0-9_-].
pub(super) fn name_ok(n: &str) -> bool {
    !n.is_empty()
        && n.len() <= 64
        && n.chars()
            .all(|c| c.is_ascii_alphanumeric() || c == '_' || c == '-')
}

/// The nearest a probe point may be to a point or line source (m): about a wavelength; closer,
/// ray optics does not hold and on the source the wave is singular.
pub(crate) const MIN_PROBE_DISTANCE_M: f64 = 1.0e-6;

/// The planes of a surface's faces: (a point, the unit normal); one for thin surfaces, two for
/// plates and wedges (the wedge's bottom tilted by its angle about the hinge). A bounded
/// surface's plane extends beyond the surface: callers say which they need.
pub(super) fn surface_planes(surf: &SurfaceSpec) -> Vec<(glam::DVec3, glam::DVec3)> {
    use glam::DVec3;
    let n = |v: &Vec3| unit(v).unwrap_or(DVec3::Z);
    match surf {
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
        } => vec![(DVec3::from_array(*point_m), n(normal))],
        SurfaceSpec::Plate {
            top_point_m,
            normal,
            thickness_um,
            ..
        } => {
            let (t, n) = (DVec3::from_array(*top_point_m), n(normal));
            vec![(t, n), (t - thickness_um * 1e-6 * n, n)]
        }
        SurfaceSpec::Wedge {
            top_point_m,
            normal,
            thickness_um,
            angle_deg,
            hinge_axis,
            ..
        } => {
            let (t, n) = (DVec3::from_array(*top_point_m), n(normal));
            let h = DVec3::from_array(*hinge_axis);
            let axis = (h - h.dot(n) * n).normalize_or_zero();
            let tilted = glam::DQuat::from_axis_angle(axis, angle_deg.to_radians()) * n;
            vec![(t, n), (t - thickness_um * 1e-6 * n, tilted)]
        }
    }
}

impl Validator {
    pub(super) fn fail(&mut self, path: &str, msg: impl Into<String>) {
        self.errors.push((path.to_string(), msg.into()));
    }

    pub(super) fn finite(&mut self, path: &str, x: f64) -> bool {
        if !x.is_finite() {
            self.fail(path, format!("must be a finite number, got {x}"));
            return false;
        }
        true
    }

    pub(super) fn range(&mut self, path: &str, x: f64, lo: f64, hi: f64, what: &str) {
        if self.finite(path, x) && !(x >= lo && x <= hi) {
            self.fail(
                path,
                format!(
                    "{what} must be in [{}, {}], got {}",
                    num(lo),
                    num(hi),
                    num(x)
                ),
            );
        }
    }

    pub(super) fn positive(&mut self, path: &str, x: f64, hi: f64, what: &str) {
        if self.finite(path, x) && !(x > 0.0 && x <= hi) {
            self.fail(
                path,
                format!("{what} must be > 0 and ≤ {}, got {}", num(hi), num(x)),
            );
        }
    }

    pub(super) fn point(&mut self, path: &str, v: &Vec3) {
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

    /// A direction: finite, not zero, not so small or large that normalizing it fails.
    pub(super) fn direction(&mut self, path: &str, v: &Vec3) -> bool {
        let (lo, hi) = limits::DIRECTION_LENGTH;
        if v.iter().any(|x| !x.is_finite()) {
            self.fail(path, "a direction must have finite components");
            return false;
        }
        let len = glam::DVec3::from_array(*v).length();
        if len == 0.0 {
            self.fail(path, "a direction must not be the zero vector");
            false
        } else if !(len >= lo && len <= hi) {
            self.fail(
                path,
                format!("a direction must have a length in [{lo:e}, {hi:e}], got {len:e}"),
            );
            false
        } else {
            true
        }
    }

    /// `a` (at `path`) must not be parallel to `b` (both valid directions, else no verdict).
    pub(super) fn not_parallel(&mut self, path: &str, a: &Vec3, b: &Vec3, what: &str) {
        let (x, y) = (unit(a), unit(b));
        if let (Some(x), Some(y)) = (x, y)
            && x.cross(y).length() < 1e-9
        {
            self.fail(
                path,
                format!("{what}: the two are parallel, {a:?} and {b:?}"),
            );
        }
    }

    pub(super) fn medium_ref(
        &mut self,
        path: &str,
        name: &str,
        media: &BTreeMap<String, MediumSpec>,
    ) {
        if !media.contains_key(name) {
            let known: Vec<&str> = media.keys().map(|s| s.as_str()).collect();
            self.fail(
                path,
                format!("unknown medium {name:?}; defined media: {known:?}"),
            );
        }
    }

    pub(super) fn wavelength(&mut self, path: &str, nm: f64) {
        let (lo, hi) = limits::WAVELENGTH_NM;
        self.range(path, nm, lo, hi, "a wavelength (nm)");
    }

    pub(super) fn rect(&mut self, path: &str, r: &RectSpec, normal: &Vec3) {
        for k in 0..2 {
            self.positive(
                &format!("{path}.size_m[{k}]"),
                r.size_m[k],
                2.0 * limits::MAX_LENGTH_M,
                "a size (m)",
            );
        }
        self.direction(&format!("{path}.u_axis"), &r.u_axis);
        self.not_parallel(
            &format!("{path}.u_axis"),
            &r.u_axis,
            normal,
            "u_axis must not be parallel to the surface normal",
        );
    }

    pub(super) fn case(&mut self, c: &CaseFile) {
        if c.name.is_empty()
            || c.name.len() > 64
            || !c
                .name
                .chars()
                .all(|ch| ch.is_ascii_lowercase() || ch.is_ascii_digit() || ch == '_')
        {
            self.fail("$.name", format!("a case name is 1–64 characters from [a-z0-9_] (it names output files), got {:?}", c.name));
        } else if limits::RESERVED_CASE_NAMES.contains(&c.name.as_str()) {
            self.fail(
                "$.name",
                format!(
                    "the case name {:?} is reserved for fringe's own outputs (reserved: {:?}); choose another",
                    c.name,
                    limits::RESERVED_CASE_NAMES
                ),
            );
        }
        self.light(&c.light);
        self.scene(&c.scene);
        self.probe(&c.probe, &c.scene);
        if let Some(f) = &c.fidelities {
            if f.is_empty() {
                self.fail(
                    "$.fidelities",
                    "list at least one fidelity level, or omit the key for all",
                );
            }
            if !f.contains(&crate::accumulate::fidelity::Fidelity::Vector) {
                self.fail(
                    "$.fidelities",
                    "the `vector` level (the reference) must be run",
                );
            }
            for (k, level) in f.iter().enumerate() {
                if f[..k].contains(level) {
                    self.fail(
                        &format!("$.fidelities[{k}]"),
                        format!("level `{level}` is listed twice"),
                    );
                }
            }
        }
        if c.references.is_empty() {
            self.fail("$.references", "at least one reference is required");
        }
        let mut labels = std::collections::BTreeSet::new();
        for (i, r) in c.references.iter().enumerate() {
            self.reference(&format!("$.references[{i}]"), r, &c.scene, &c.light);
            let label = r
                .label
                .clone()
                .unwrap_or_else(|| crate::harness::case::reference::name(&r.model));
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
            if let Some(f) = &c.fidelities {
                for level in r.tolerances.keys() {
                    if !f.contains(level) {
                        self.fail(
                            &format!("$.references[{i}].tolerances.{level}"),
                            format!("a tolerance for level `{level}`, which $.fidelities does not run: add `{level}` to $.fidelities or drop the tolerance"),
                        );
                    }
                }
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
            if !c
                .references
                .iter()
                .any(|r| matches!(r.model, ReferenceModel::Airy { .. }))
            {
                self.fail(
                    "$.trace.airy_tail_epsilon",
                    "needs an `airy` reference naming the film whose tail it bounds (or use max_internal_reflections)",
                );
            }
        }
        self.range(
            "$.trace.golden_tolerance",
            t.golden_tolerance,
            0.0,
            1.0,
            "the golden tolerance",
        );
        // Checks across sections need every field in range first.
        if self.errors.is_empty() {
            self.cross(c);
        }
    }
}
