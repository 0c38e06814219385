//! The case file format (serde types). Every struct denies unknown keys; units are in the key
//! names (`_m`, `_um`, `_nm`, `_deg`). Documented for users in `cases/README.md` and
//! `cases/schema.json`, which is generated from these types (`fringe schema`,
//! [`super::schema`]): the doc comments below are the schema's descriptions, and the
//! `#[schemars(...)]` attributes carry the per-key ranges the loader enforces
//! ([`super::load::limits`] where the range has a named limit). The loader checks more than a
//! schema can say (names that must exist, geometry, caps across keys).
//!
//! Units are in the key names: metres (`_m`), micrometres (`_um`), nanometres of vacuum
//! wavelength (`_nm`), degrees (`_deg`); directions are any non-zero length and are normalized
//! (docs/PHYSICS.md §1).

use super::load::limits;
use crate::accumulate::fidelity::Fidelity;
use schemars::JsonSchema;
use serde::{Deserialize, Serialize};
use std::collections::BTreeMap;

/// A 3-vector in a case file: a point in metres (`…_m` keys) or a direction (normalized on
/// load), in the scene's right-handed frame (docs/PHYSICS.md §1).
pub type Vec3 = [f64; 3];

/// A whole case file.
#[derive(Clone, Debug, Deserialize, Serialize, JsonSchema)]
#[serde(deny_unknown_fields)]
#[schemars(
    title = "fringe case file",
    description = "A case of the fringe verification harness, generated from src/harness/case/spec.rs by `fringe schema` (documented in cases/README.md). The loader (src/harness/case/load/) checks more than this schema can say: names that must exist, geometry, the sampled band, caps across keys."
)]
pub struct CaseFile {
    /// Case name, 1–64 characters from [a-z0-9_] (it names output files).
    #[schemars(regex(pattern = r"^[a-z0-9_]{1,64}$"))]
    pub name: String,
    /// What the case shows, for the report.
    pub description: String,
    /// The formula the reference evaluates, with its source (equation numbers).
    pub formula: String,
    /// The light: one wavelength or a sampled spectrum.
    pub light: Light,
    /// The scene: media, surfaces, sources.
    pub scene: SceneSpec,
    /// Where the traced and closed-form values are compared.
    pub probe: Probe,
    /// Closed-form references (at least one); the first is the primary.
    #[schemars(length(min = 1))]
    pub references: Vec<ReferenceSpec>,
    /// Fidelity levels to run (absent or null: all five); must include `vector`.
    #[serde(default)]
    #[schemars(length(min = 1), extend("uniqueItems" = true))]
    pub fidelities: Option<Vec<Fidelity>>,
    /// Tracing settings (defaults: two beams, no spreading, golden tolerance 1e-9).
    #[serde(default)]
    pub trace: TraceSpec,
}

/// The light: one wavelength or a sampled spectrum (docs/PHYSICS.md §6). Exactly one key.
#[derive(Clone, Debug, Deserialize, Serialize, JsonSchema)]
#[serde(rename_all = "snake_case", deny_unknown_fields)]
pub enum Light {
    /// Monochromatic light of vacuum wavelength `wavelength_nm`.
    Monochrome {
        /// Vacuum wavelength, nm.
        #[schemars(range(min = limits::WAVELENGTH_NM.0, max = limits::WAVELENGTH_NM.1))]
        wavelength_nm: f64,
    },
    /// A spectrum Gaussian in wavenumber, FWHM `fwhm_nm` around `center_nm`, sampled uniformly in
    /// wavenumber over ±`sigmas` standard deviations with `samples` points (trapezoid weights).
    /// The sampled band must stay within [200, 2500] nm.
    Gaussian {
        /// Centre vacuum wavelength, nm.
        #[schemars(range(min = limits::WAVELENGTH_NM.0, max = limits::WAVELENGTH_NM.1))]
        center_nm: f64,
        /// Full width at half maximum, nm; > 0 and at most 20% of `center_nm`.
        #[schemars(extend("exclusiveMinimum" = 0.0))]
        fwhm_nm: f64,
        /// Spectral samples.
        #[schemars(range(min = 2, max = limits::MAX_SPECTRAL_SAMPLES))]
        samples: usize,
        /// Half-width of the sampled band in standard deviations (default 8).
        #[serde(default = "default_sigmas")]
        #[schemars(range(min = 1.0, max = 12.0))]
        sigmas: f64,
    },
}

fn default_sigmas() -> f64 {
    8.0
}

/// A medium's real refractive index: constant, Cauchy or Sellmeier (or the named BK7). Exactly
/// one key. Complex (lossy) indices are out of scope (docs/PHYSICS.md §1).
#[derive(Clone, Debug, Deserialize, Serialize, JsonSchema)]
#[serde(rename_all = "snake_case", deny_unknown_fields)]
#[schemars(rename = "Medium")]
pub enum MediumSpec {
    /// A constant real index.
    Constant {
        /// Refractive index (real; complex/lossy indices are out of scope).
        #[schemars(range(min = limits::INDEX.0, max = limits::INDEX.1))]
        n: f64,
    },
    /// Cauchy: n = a + b/λ² + c/λ⁴ (λ in µm), valid on [`min_nm`, `max_nm`].
    Cauchy {
        /// Constant term.
        a: f64,
        /// b, µm².
        b_um2: f64,
        /// c, µm⁴.
        c_um4: f64,
        /// Shortest valid wavelength, nm.
        #[schemars(range(min = limits::WAVELENGTH_NM.0, max = limits::WAVELENGTH_NM.1))]
        min_nm: f64,
        /// Longest valid wavelength, nm (> `min_nm`).
        #[schemars(range(min = limits::WAVELENGTH_NM.0, max = limits::WAVELENGTH_NM.1))]
        max_nm: f64,
    },
    /// Sellmeier: n² = 1 + Σ b_k λ²/(λ² − c_k) (λ in µm), valid on [`min_nm`, `max_nm`].
    Sellmeier {
        /// b_1..b_3.
        b: [f64; 3],
        /// c_1..c_3, µm².
        c_um2: [f64; 3],
        /// Shortest valid wavelength, nm.
        #[schemars(range(min = limits::WAVELENGTH_NM.0, max = limits::WAVELENGTH_NM.1))]
        min_nm: f64,
        /// Longest valid wavelength, nm (> `min_nm`).
        #[schemars(range(min = limits::WAVELENGTH_NM.0, max = limits::WAVELENGTH_NM.1))]
        max_nm: f64,
    },
    /// Schott N-BK7 (Sellmeier, 300–2500 nm). Write `{"bk7": {}}`.
    Bk7 {},
}

/// Coherence rules of a surface (paper §3.4; docs/PHYSICS.md §3): whether reflected /
/// refracted children keep the parent's coherence.
#[derive(Clone, Copy, Debug, Deserialize, Serialize, JsonSchema)]
#[serde(deny_unknown_fields)]
#[schemars(rename = "Coherence")]
pub struct CoherenceSpec {
    /// Reflected rays stay coherent with their parent.
    pub reflected_keeps: bool,
    /// Refracted rays stay coherent with their parent.
    pub refracted_keeps: bool,
}

/// A rectangular extent centred on the surface point: size (width along `u_axis`, height along
/// normal × `u_axis`).
#[derive(Clone, Debug, Deserialize, Serialize, JsonSchema)]
#[serde(deny_unknown_fields)]
#[schemars(rename = "Rect")]
pub struct RectSpec {
    /// [width along `u_axis`, height along normal × `u_axis`], metres.
    #[schemars(inner(range(max = 2.0 * limits::MAX_LENGTH_M)), transform = super::schema::positive_items)]
    pub size_m: [f64; 2],
    /// The width direction (in the surface plane).
    #[schemars(with = "super::schema::Direction")]
    pub u_axis: Vec3,
}

/// A rectangular hole in an opaque screen: centre (u, v) and size in the screen's axes.
#[derive(Clone, Debug, Deserialize, Serialize, JsonSchema)]
#[serde(deny_unknown_fields)]
#[schemars(rename = "Aperture")]
pub struct ApertureSpec {
    /// Centre (u, v), metres.
    #[schemars(inner(range(min = -limits::MAX_LENGTH_M, max = limits::MAX_LENGTH_M)))]
    pub center_m: [f64; 2],
    /// [width, height], metres.
    #[schemars(inner(range(max = 2.0 * limits::MAX_LENGTH_M)), transform = super::schema::positive_items)]
    pub size_m: [f64; 2],
}

/// A surface of the scene. Exactly one key.
#[derive(Clone, Debug, Deserialize, Serialize, JsonSchema)]
#[serde(rename_all = "snake_case", deny_unknown_fields)]
#[schemars(rename = "Surface")]
pub enum SurfaceSpec {
    /// A single interface between two media; `front` is on the side the normal points to.
    Interface {
        /// Surface name, unique in the scene; a plate or wedge `p` has faces `p.top` and
        /// `p.bottom`.
        #[schemars(regex(pattern = r"^[A-Za-z0-9_-]{1,64}$"))]
        name: String,
        /// A point of the interface, metres.
        #[schemars(with = "super::schema::Point")]
        point_m: Vec3,
        /// The surface normal (its side is `front`).
        #[schemars(with = "super::schema::Direction")]
        normal: Vec3,
        /// Medium on the normal's side.
        front: String,
        /// Medium behind.
        back: String,
        /// The interface's extent (absent: unbounded).
        #[serde(default)]
        rect: Option<RectSpec>,
        /// Coherence rules (absent: both children keep the parent's coherence).
        #[serde(default)]
        coherence: Option<CoherenceSpec>,
    },
    /// A plane-parallel plate: two unbounded interfaces, the top through `top_point_m`, the
    /// bottom `thickness_um` below (against the normal).
    Plate {
        /// Surface name, unique in the scene; a plate or wedge `p` has faces `p.top` and
        /// `p.bottom`.
        #[schemars(regex(pattern = r"^[A-Za-z0-9_-]{1,64}$"))]
        name: String,
        /// A point of the top face, metres.
        #[schemars(with = "super::schema::Point")]
        top_point_m: Vec3,
        /// The top face's outward normal.
        #[schemars(with = "super::schema::Direction")]
        normal: Vec3,
        /// Thickness, µm (at least 1 pm).
        #[schemars(range(min = limits::MIN_THICKNESS_UM, max = 1.0e6))]
        thickness_um: f64,
        /// The plate's medium.
        medium: String,
        /// Medium on the normal's side.
        above: String,
        /// Medium below the bottom face.
        below: String,
        /// Coherence rules of both faces (absent: children keep the parent's coherence).
        #[serde(default)]
        coherence: Option<CoherenceSpec>,
    },
    /// A wedge: a plate whose bottom face is tilted by `angle_deg` about `hinge_axis`.
    Wedge {
        /// Surface name, unique in the scene; a plate or wedge `p` has faces `p.top` and
        /// `p.bottom`.
        #[schemars(regex(pattern = r"^[A-Za-z0-9_-]{1,64}$"))]
        name: String,
        /// A point of the top face, metres.
        #[schemars(with = "super::schema::Point")]
        top_point_m: Vec3,
        /// The top face's outward normal.
        #[schemars(with = "super::schema::Direction")]
        normal: Vec3,
        /// Thickness below `top_point_m`, µm (at least 1 pm).
        #[schemars(range(min = limits::MIN_THICKNESS_UM, max = 1.0e6))]
        thickness_um: f64,
        /// Wedge angle, degrees.
        #[schemars(range(max = 10.0), extend("exclusiveMinimum" = 0.0))]
        angle_deg: f64,
        /// The axis (through `top_point_m`) the bottom face is tilted about.
        #[schemars(with = "super::schema::Direction")]
        hinge_axis: Vec3,
        /// The wedge's medium.
        medium: String,
        /// Medium on the normal's side.
        above: String,
        /// Medium below the bottom face.
        below: String,
    },
    /// A perfectly conducting mirror (unbounded unless `rect`).
    Mirror {
        /// Surface name, unique in the scene; a plate or wedge `p` has faces `p.top` and
        /// `p.bottom`.
        #[schemars(regex(pattern = r"^[A-Za-z0-9_-]{1,64}$"))]
        name: String,
        /// A point of the mirror, metres.
        #[schemars(with = "super::schema::Point")]
        point_m: Vec3,
        /// The mirror's normal (either side reflects).
        #[schemars(with = "super::schema::Direction")]
        normal: Vec3,
        /// The mirror's extent (absent: unbounded).
        #[serde(default)]
        rect: Option<RectSpec>,
    },
    /// An ideal thin lossless beam splitter of power reflectance `reflectance` (unbounded unless
    /// `rect`).
    Splitter {
        /// Surface name, unique in the scene; a plate or wedge `p` has faces `p.top` and
        /// `p.bottom`.
        #[schemars(regex(pattern = r"^[A-Za-z0-9_-]{1,64}$"))]
        name: String,
        /// A point of the splitter, metres.
        #[schemars(with = "super::schema::Point")]
        point_m: Vec3,
        /// The splitter's normal.
        #[schemars(with = "super::schema::Direction")]
        normal: Vec3,
        /// Power reflectance.
        #[schemars(range(min = 0.0, max = 1.0))]
        reflectance: f64,
        /// The splitter's extent (absent: unbounded).
        #[serde(default)]
        rect: Option<RectSpec>,
    },
    /// An absorbing rectangle.
    Shield {
        /// Surface name, unique in the scene; a plate or wedge `p` has faces `p.top` and
        /// `p.bottom`.
        #[schemars(regex(pattern = r"^[A-Za-z0-9_-]{1,64}$"))]
        name: String,
        /// The rectangle's centre, metres.
        #[schemars(with = "super::schema::Point")]
        point_m: Vec3,
        /// The rectangle's normal.
        #[schemars(with = "super::schema::Direction")]
        normal: Vec3,
        /// The rectangle.
        rect: RectSpec,
    },
    /// An opaque screen (unbounded unless `rect`) with rectangular apertures.
    OpaqueScreen {
        /// Surface name, unique in the scene; a plate or wedge `p` has faces `p.top` and
        /// `p.bottom`.
        #[schemars(regex(pattern = r"^[A-Za-z0-9_-]{1,64}$"))]
        name: String,
        /// A point of the screen (the origin of its (u, v) axes), metres.
        #[schemars(with = "super::schema::Point")]
        point_m: Vec3,
        /// The screen's normal.
        #[schemars(with = "super::schema::Direction")]
        normal: Vec3,
        /// The screen's extent (absent: unbounded).
        #[serde(default)]
        rect: Option<RectSpec>,
        /// The screen's u axis (v = normal × u), for the apertures.
        #[schemars(with = "super::schema::Direction")]
        u_axis: Vec3,
        /// The holes.
        apertures: Vec<ApertureSpec>,
    },
}

impl SurfaceSpec {
    /// The surface's name in the case file.
    pub fn name(&self) -> &str {
        match self {
            SurfaceSpec::Interface { name, .. }
            | SurfaceSpec::Plate { name, .. }
            | SurfaceSpec::Wedge { name, .. }
            | SurfaceSpec::Mirror { name, .. }
            | SurfaceSpec::Splitter { name, .. }
            | SurfaceSpec::Shield { name, .. }
            | SurfaceSpec::OpaqueScreen { name, .. } => name,
        }
    }

    /// The serde tag of the surface's kind (`plate`, `mirror`, …).
    pub fn kind(&self) -> &'static str {
        match self {
            SurfaceSpec::Interface { .. } => "interface",
            SurfaceSpec::Plate { .. } => "plate",
            SurfaceSpec::Wedge { .. } => "wedge",
            SurfaceSpec::Mirror { .. } => "mirror",
            SurfaceSpec::Splitter { .. } => "splitter",
            SurfaceSpec::Shield { .. } => "shield",
            SurfaceSpec::OpaqueScreen { .. } => "opaque_screen",
        }
    }
}

/// The geometry of a source. Exactly one key.
#[derive(Clone, Debug, Deserialize, Serialize, JsonSchema)]
#[serde(rename_all = "snake_case", deny_unknown_fields)]
#[schemars(rename = "Emitter")]
pub enum EmitterSpec {
    /// A point source.
    Point {
        /// Where it is, metres.
        #[schemars(with = "super::schema::Point")]
        position_m: Vec3,
    },
    /// An infinite line source (a slit) through `point_m` along `axis`.
    Line {
        /// A point of the line, metres.
        #[schemars(with = "super::schema::Point")]
        point_m: Vec3,
        /// The line's direction.
        #[schemars(with = "super::schema::Direction")]
        axis: Vec3,
    },
    /// A plane wave travelling along `direction`, phase zero on the wavefront through
    /// `reference_point_m`.
    PlaneWave {
        /// The direction of travel.
        #[schemars(with = "super::schema::Direction")]
        direction: Vec3,
        /// A point of the zero-phase wavefront, metres.
        #[schemars(with = "super::schema::Point")]
        reference_point_m: Vec3,
    },
}

/// Polarization of a source (docs/PHYSICS.md §3). Exactly one key.
#[derive(Clone, Debug, Deserialize, Serialize, JsonSchema)]
#[serde(rename_all = "snake_case", deny_unknown_fields)]
#[schemars(rename = "Polarization")]
pub enum PolarizationSpec {
    /// Linear: `reference` projected perpendicular to each ray, rotated by `angle_deg` about it.
    Linear {
        /// The field direction before projection.
        #[schemars(with = "super::schema::Direction")]
        reference: Vec3,
        /// Rotation about the ray, degrees.
        #[schemars(range(min = -360.0, max = 360.0))]
        angle_deg: f64,
    },
    /// Unpolarized light. `model` `basis_free` (the default): three incoherent dipole
    /// channels along x, y, z, no reference (docs/PHYSICS.md §3); `paper_two_channel`: the
    /// paper's two incoherent channels at 0° and 90° from `reference` (required then, and only
    /// then).
    Unpolarized {
        /// `basis_free` (default) or `paper_two_channel`.
        #[serde(default)]
        model: UnpolarizedModel,
        /// The paper's 0° channel direction (`paper_two_channel` only).
        #[serde(default, skip_serializing_if = "Option::is_none")]
        #[schemars(with = "Option<super::schema::Direction>")]
        reference: Option<Vec3>,
    },
}

/// The model of an unpolarized source (docs/PHYSICS.md §3).
#[derive(Clone, Copy, Debug, Default, Deserialize, Serialize, PartialEq, Eq, JsonSchema)]
#[serde(rename_all = "snake_case")]
pub enum UnpolarizedModel {
    /// Three incoherent dipoles along x, y, z: independent of any basis.
    #[default]
    BasisFree,
    /// The paper's two linear channels built from a reference vector.
    PaperTwoChannel,
}

/// A light source.
#[derive(Clone, Debug, Deserialize, Serialize, JsonSchema)]
#[serde(deny_unknown_fields)]
#[schemars(rename = "Source")]
pub struct SourceSpec {
    /// Source name, unique in the scene.
    #[schemars(regex(pattern = r"^[A-Za-z0-9_-]{1,64}$"))]
    pub name: String,
    /// The source's geometry.
    pub emitter: EmitterSpec,
    /// The source's polarization.
    pub polarization: PolarizationSpec,
    /// |E|² of the source (default 1; docs/PHYSICS.md §3a).
    #[serde(default = "one")]
    #[schemars(range(max = 1.0e12), extend("exclusiveMinimum" = 0.0))]
    pub intensity: f64,
    /// Sources with equal groups are mutually coherent (default 0).
    #[serde(default)]
    #[schemars(range(min = 0, max = limits::MAX_COHERENCE_GROUP))]
    pub coherence_group: u64,
    /// The paper's coherence length SC_max (P9), metres; absent or null: unlimited.
    #[serde(default)]
    #[schemars(range(max = limits::MAX_LENGTH_M), extend("exclusiveMinimum" = 0.0))]
    pub coherence_length_m: Option<f64>,
}

/// A JSON object read as a map whose keys must be distinct: serde's `BTreeMap` keeps the last of
/// two equal keys; a case file names each medium (or tolerance level) once. The error reads
/// like serde's own for a struct field given twice (`duplicate field `name``), so the loader
/// words both alike.
fn unique_keys<'de, D, K, V>(d: D) -> Result<BTreeMap<K, V>, D::Error>
where
    D: serde::Deserializer<'de>,
    K: Deserialize<'de> + Ord + std::fmt::Display,
    V: Deserialize<'de>,
{
    struct Unique<K, V>(std::marker::PhantomData<(K, V)>);
    impl<'de, K, V> serde::de::Visitor<'de> for Unique<K, V>
    where
        K: Deserialize<'de> + Ord + std::fmt::Display,
        V: Deserialize<'de>,
    {
        type Value = BTreeMap<K, V>;
        fn expecting(&self, f: &mut std::fmt::Formatter) -> std::fmt::Result {
            f.write_str("a map")
        }
        fn visit_map<A: serde::de::MapAccess<'de>>(
            self,
            mut a: A,
        ) -> Result<Self::Value, A::Error> {
            let mut out = BTreeMap::new();
            while let Some(k) = a.next_key::<K>()? {
                if out.contains_key(&k) {
                    return Err(serde::de::Error::custom(format_args!(
                        "duplicate field `{k}`"
                    )));
                }
                let v = a.next_value()?;
                out.insert(k, v);
            }
            Ok(out)
        }
    }
    d.deserialize_map(Unique(std::marker::PhantomData))
}

fn one() -> f64 {
    1.0
}

/// The scene: media, surfaces and sources.
#[derive(Clone, Debug, Deserialize, Serialize, JsonSchema)]
#[serde(deny_unknown_fields)]
#[schemars(rename = "Scene")]
pub struct SceneSpec {
    /// Name of the medium around the sources (a key of `media`).
    pub ambient: String,
    /// Named media (the names are free strings); at least the ambient one. A name defined
    /// twice is an error (not "the last one wins").
    #[serde(deserialize_with = "unique_keys")]
    #[schemars(extend("minProperties" = 1))]
    pub media: BTreeMap<String, MediumSpec>,
    /// The surfaces.
    pub surfaces: Vec<SurfaceSpec>,
    /// The sources (at least one).
    #[schemars(length(min = 1))]
    pub sources: Vec<SourceSpec>,
}

/// Which far field a `far_field` observer looks at (relative to the surface normal).
#[derive(Clone, Copy, Debug, Deserialize, Serialize, PartialEq, Eq, JsonSchema)]
#[serde(rename_all = "snake_case")]
pub enum FarSide {
    /// The reflected side (the normal's side).
    Reflected,
    /// The transmitted side.
    Transmitted,
}

/// The swept parameter. Exactly one key.
#[derive(Clone, Debug, Deserialize, Serialize, PartialEq, JsonSchema)]
#[serde(rename_all = "snake_case", deny_unknown_fields)]
pub enum SweepParameter {
    /// Angle of incidence of every plane-wave source (degrees, 0–90), in the plane spanned by
    /// `surface_normal` and `in_plane_axis`: direction = sin θ·axis − cos θ·normal.
    IncidenceAngleDeg {
        /// The normal the angle is measured from.
        #[schemars(with = "super::schema::Direction")]
        surface_normal: Vec3,
        /// The axis that spans the plane of incidence with the normal.
        #[schemars(with = "super::schema::Direction")]
        in_plane_axis: Vec3,
    },
    /// The vacuum wavelength, nm (monochrome light only). Write `{"wavelength_nm": {}}`.
    WavelengthNm {},
    /// The thickness (nm) of the plate or wedge named `surface`.
    ThicknessNm {
        /// A plate or wedge name.
        surface: String,
    },
}

/// Where a probe point observes. Exactly one key.
#[derive(Clone, Debug, Deserialize, Serialize, PartialEq, JsonSchema)]
#[serde(rename_all = "snake_case", deny_unknown_fields)]
pub enum Observer {
    /// A screen point. With `looks_toward`, the detector is one-sided (an eye or a film looking
    /// that way): it records only rays travelling against `looks_toward`.
    Point {
        /// The screen point, metres.
        #[schemars(with = "super::schema::Point")]
        position_m: Vec3,
        /// The direction the one-sided detector looks toward (absent: two-sided).
        #[serde(default)]
        #[schemars(with = "Option<super::schema::Direction>")]
        looks_toward: Option<Vec3>,
    },
    /// The far field (ideal lens at infinity) on the reflected or transmitted side of the
    /// surface normal of an incidence-angle sweep (or of the plane wave's direction relative to
    /// `surface_normal`), leaving into medium `exit_medium` (default: ambient).
    FarField {
        /// Reflected or transmitted side.
        side: FarSide,
        /// The normal that defines the sides.
        #[schemars(with = "super::schema::Direction")]
        surface_normal: Vec3,
        /// A medium name (absent: the ambient medium).
        #[serde(default)]
        exit_medium: Option<String>,
    },
    /// The far field in one fixed direction, phase referred to the wavefront through
    /// `reference_point_m`.
    Direction {
        /// The direction of observation.
        #[schemars(with = "super::schema::Direction")]
        direction: Vec3,
        /// A point of the zero-phase wavefront, metres.
        #[schemars(with = "super::schema::Point")]
        reference_point_m: Vec3,
    },
}

/// The probe: where and over what the traced and closed-form values are compared. Exactly one
/// key.
#[derive(Clone, Debug, Deserialize, Serialize, JsonSchema)]
#[serde(rename_all = "snake_case", deny_unknown_fields)]
pub enum Probe {
    /// `count` screen points evenly spaced from `from_m` to `to_m`; the coordinate is the
    /// distance from `origin_m` along the line direction (default: from `from_m`).
    Line {
        /// The first point, metres.
        #[schemars(with = "super::schema::Point")]
        from_m: Vec3,
        /// The last point, metres.
        #[schemars(with = "super::schema::Point")]
        to_m: Vec3,
        /// Probe points.
        #[schemars(range(min = 1, max = limits::MAX_PROBE_POINTS))]
        count: usize,
        /// Where the coordinate is zero, metres (absent: `from_m`).
        #[serde(default)]
        #[schemars(with = "Option<super::schema::Point>")]
        origin_m: Option<Vec3>,
        /// One-sided screen: records only rays travelling against this direction.
        #[serde(default)]
        #[schemars(with = "Option<super::schema::Direction>")]
        looks_toward: Option<Vec3>,
    },
    /// `count` values of `parameter` evenly spaced from `from` to `to` (units of the
    /// parameter), observed by `observe`.
    Sweep {
        /// The swept parameter.
        parameter: SweepParameter,
        /// First value (unit of the parameter).
        from: f64,
        /// Last value (unit of the parameter).
        to: f64,
        /// Probe points.
        #[schemars(range(min = 1, max = limits::MAX_PROBE_POINTS))]
        count: usize,
        /// Where each value is observed.
        observe: Observer,
    },
    /// A single observation (e.g. a far-field direction).
    Single {
        /// Where it is observed.
        observe: Observer,
    },
    /// A picture: `pixels` = [columns, rows] screen points at the pixel centres of the rectangle
    /// of `size_m` = [width, height] centred on `center_m`, width along `u_axis` (left → right),
    /// height along `v_axis` (bottom → top, made perpendicular to `u_axis`); row 0 is the top.
    /// `fringe check` traces every point (coordinate: row-major pixel index); `fringe render`
    /// draws it, optionally at another pixel count (`--size`).
    Grid {
        /// The picture's centre, metres.
        #[schemars(with = "super::schema::Point")]
        center_m: Vec3,
        /// Left → right.
        #[schemars(with = "super::schema::Direction")]
        u_axis: Vec3,
        /// Bottom → top (made perpendicular to `u_axis`).
        #[schemars(with = "super::schema::Direction")]
        v_axis: Vec3,
        /// [width, height], metres.
        #[schemars(inner(range(max = 2.0 * limits::MAX_LENGTH_M)), transform = super::schema::positive_items)]
        size_m: [f64; 2],
        /// [columns, rows]; columns × rows ≤ 100000.
        #[schemars(inner(range(min = 1, max = limits::MAX_PROBE_POINTS)))]
        pixels: [usize; 2],
        /// One-sided screen: records only rays travelling against this direction.
        #[serde(default)]
        #[schemars(with = "Option<super::schema::Direction>")]
        looks_toward: Option<Vec3>,
    },
}

/// A closed-form reference and its tolerances per fidelity level (relative deviation, see the
/// metric). Levels without a tolerance are reported for information only.
#[derive(Clone, Debug, Deserialize, Serialize, JsonSchema)]
#[serde(deny_unknown_fields)]
#[schemars(rename = "Reference")]
pub struct ReferenceSpec {
    /// The closed form.
    pub model: ReferenceModel,
    /// Metric name in tables and files (default: the model's key); unique per case.
    #[serde(default)]
    #[schemars(regex(pattern = r"^[A-Za-z0-9_]+$"))]
    pub label: Option<String>,
    /// Relative tolerance per fidelity level; levels without one are information only. The
    /// first reference needs `vector`.
    #[serde(deserialize_with = "unique_keys")]
    #[schemars(schema_with = "super::schema::tolerances")]
    pub tolerances: BTreeMap<Fidelity, f64>,
    /// Why a vector tolerance looser than 1e-9 is physically forced (required when one is).
    #[serde(default)]
    pub tolerance_note: Option<String>,
}

/// A closed-form reference (src/analytic, docs/PHYSICS.md §5), each reading its parameters
/// from the scene. Exactly one key.
#[derive(Clone, Debug, Deserialize, Serialize, PartialEq, JsonSchema)]
#[serde(rename_all = "snake_case", deny_unknown_fields)]
pub enum ReferenceModel {
    /// Two coherent line sources of equal intensity: exact distances, vector fields
    /// (analytic::young). Write `{"young_exact": {}}`.
    YoungExact {},
    /// Paraxial Young 2(1 + cos(2π d y/(λ l))); two line sources.
    YoungParaxial {},
    /// Fringe spacing at the probe centre (line probe, two line sources) vs
    /// λ sqrt(l² + d²/4)/d (exact) or λl/d (paraxial).
    YoungSpacing {
        /// true: λl/d; false: λ sqrt(l² + d²/4)/d.
        paraxial: bool,
    },
    /// Lloyd's mirror: the first surface is a dielectric interface, one s-polarized line
    /// source.
    Lloyd {},
    /// Fringe visibility of Lloyd's mirror, 2|r_s|/(1 + |r_s|²).
    LloydVisibility {},
    /// Two-beam reflection of a point source by the plate `plate` (paper Fig. 4 left).
    TwoBeamPlate {
        /// A plate name.
        plate: String,
    },
    /// Airy reflectance or transmittance of the plate/film `film` (plane wave, `far_field`
    /// observer; the side is the observer's).
    Airy {
        /// A plate name.
        film: String,
        /// Use this constant film index instead of the medium's dispersion (to show what
        /// ignoring dispersion costs).
        #[serde(default)]
        #[schemars(range(min = limits::INDEX.0, max = limits::INDEX.1))]
        index_override: Option<f64>,
    },
    /// The Fizeau wedge `wedge`: two-beam intensity (s-polarized plane wave, normal incidence).
    Wedge {
        /// A wedge name.
        wedge: String,
    },
    /// Fizeau fringe spacing λ/(n sin 2α) (exact) or λ/(2nα) (small angle), line probe.
    WedgeSpacing {
        /// A wedge name.
        wedge: String,
        /// true: λ/(2nα).
        small_angle: bool,
    },
    /// Retardance arg(E_p) − arg(E_s) after `tir_count` TIRs in `glass` at the plane wave's angle
    /// of incidence on `tir_surface` (Fresnel rhomb).
    RhombRetardance {
        /// A medium name.
        glass: String,
        /// A surface name.
        tir_surface: String,
        /// Number of TIRs.
        #[schemars(range(min = 1, max = limits::MAX_TIR_COUNT))]
        tir_count: usize,
    },
    /// Plane waves through planar faces, phase by wavefront continuity: the traced sum of the
    /// listed beams (each a source with its surface sequence), complex Fresnel amplitudes.
    PlaneWaveBeams {
        /// At least one beam.
        #[schemars(length(min = 1))]
        beams: Vec<BeamSpec>,
    },
    /// Michelson interferometer: virtual sources and the vector image rule (point source).
    Michelson {
        /// A splitter name.
        splitter: String,
        /// The two mirror names.
        mirrors: [String; 2],
    },
    /// Mutually incoherent point sources: Σ I_k/r_k² (spreading on) or Σ I_k (off).
    IncoherentSum {},
    /// Two-beam plate reflection at normal incidence with a Gaussian spectrum:
    /// I1 + I2 + 2√(I1 I2)|γ(Δs)| cos(k0 Δs + φ) (docs/PHYSICS.md §3).
    CoherenceGaussian {
        /// A plate name.
        plate: String,
        /// Bandwidth (FWHM, nm) when the case's light is monochromatic (to measure another
        /// coherence model against this truth); must be absent for Gaussian light; at most 20%
        /// of the wavelength.
        #[serde(default)]
        #[schemars(extend("exclusiveMinimum" = 0.0))]
        fwhm_nm: Option<f64>,
    },
    /// The paper's rule (P9) for the same plate: coherent while both rays' own paths are below
    /// the coherence length, I1 + I2 otherwise.
    CoherenceP9 {
        /// A plate name.
        plate: String,
    },
}

/// One beam of a [`ReferenceModel::PlaneWaveBeams`] reference: a plane-wave source and the
/// surfaces it meets in order (each with `reflect` or `refract`).
#[derive(Clone, Debug, Deserialize, Serialize, PartialEq, JsonSchema)]
#[serde(deny_unknown_fields)]
#[schemars(rename = "Beam")]
pub struct BeamSpec {
    /// A plane-wave source name.
    pub source: String,
    /// The events in order.
    pub events: Vec<BeamEvent>,
}

/// One surface a beam meets, and whether it is reflected or refracted there.
#[derive(Clone, Debug, Deserialize, Serialize, PartialEq, JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct BeamEvent {
    /// A surface name (plate faces as `p.top` / `p.bottom`).
    pub surface: String,
    /// true: reflected there; false: refracted.
    pub reflect: bool,
}

/// Tracing settings of a case.
#[derive(Clone, Debug, Deserialize, Serialize, JsonSchema)]
#[serde(deny_unknown_fields)]
#[schemars(rename = "Trace")]
pub struct TraceSpec {
    /// Maximum reflections inside non-ambient media (default 1: two beams).
    #[serde(default = "one_usize")]
    #[schemars(range(min = 0, max = limits::MAX_INTERNAL_REFLECTIONS))]
    pub max_internal_reflections: usize,
    /// Choose the internal-reflection count per probe point so the Airy tail bound of the
    /// `airy` reference's film is below this (overrides `max_internal_reflections`).
    #[serde(default)]
    #[schemars(range(min = 1e-15, max = 0.5))]
    pub airy_tail_epsilon: Option<f64>,
    /// Geometric spreading (1/r² for point sources); off for the paper's figures.
    #[serde(default)]
    pub spreading: bool,
    /// Regression tolerance against `golden/<case>.csv` (relative to the profile scale).
    #[serde(default = "golden_tol")]
    #[schemars(range(min = 0.0, max = 1.0))]
    pub golden_tolerance: f64,
}

fn one_usize() -> usize {
    1
}
fn golden_tol() -> f64 {
    1e-9
}

impl Default for TraceSpec {
    fn default() -> Self {
        TraceSpec {
            max_internal_reflections: 1,
            airy_tail_epsilon: None,
            spreading: false,
            golden_tolerance: golden_tol(),
        }
    }
}
