//! The case file format (serde types). Every struct denies unknown keys; units are in the key
//! names (`_m`, `_um`, `_nm`, `_deg`). Documented for users in `cases/README.md` and
//! `cases/schema.json`.

use crate::fidelity::Fidelity;
use serde::{Deserialize, Serialize};
use std::collections::BTreeMap;

pub type Vec3 = [f64; 3];

/// A whole case file.
#[derive(Clone, Debug, Deserialize, Serialize)]
#[serde(deny_unknown_fields)]
pub struct CaseFile {
    /// Case name: lowercase letters, digits and `_` (it names output files).
    pub name: String,
    /// What the case shows, for the report.
    pub description: String,
    /// The formula the reference evaluates, with its source (equation numbers).
    pub formula: String,
    pub light: Light,
    pub scene: SceneSpec,
    pub probe: Probe,
    /// Closed-form references the traced result is compared with.
    pub references: Vec<ReferenceSpec>,
    /// Fidelity levels to run (default: all five).
    #[serde(default)]
    pub fidelities: Option<Vec<Fidelity>>,
    #[serde(default)]
    pub trace: TraceSpec,
}

/// The light: one wavelength or a sampled spectrum.
#[derive(Clone, Debug, Deserialize, Serialize)]
#[serde(rename_all = "snake_case", deny_unknown_fields)]
pub enum Light {
    /// Monochromatic light of vacuum wavelength `wavelength_nm`.
    Monochrome { wavelength_nm: f64 },
    /// A spectrum Gaussian in wavenumber, FWHM `fwhm_nm` around `center_nm`, sampled uniformly in
    /// wavenumber over ±`sigmas` standard deviations with `samples` points (trapezoid weights).
    Gaussian {
        center_nm: f64,
        fwhm_nm: f64,
        samples: usize,
        #[serde(default = "default_sigmas")]
        sigmas: f64,
    },
}

fn default_sigmas() -> f64 {
    8.0
}

/// A medium: constant index, Cauchy or Sellmeier (or the named BK7).
#[derive(Clone, Debug, Deserialize, Serialize)]
#[serde(rename_all = "snake_case", deny_unknown_fields)]
pub enum MediumSpec {
    Constant {
        n: f64,
    },
    Cauchy {
        a: f64,
        b_um2: f64,
        c_um4: f64,
        min_nm: f64,
        max_nm: f64,
    },
    Sellmeier {
        b: [f64; 3],
        c_um2: [f64; 3],
        min_nm: f64,
        max_nm: f64,
    },
    /// Schott N-BK7 (Sellmeier, 300–2500 nm).
    Bk7 {},
}

/// Coherence rules of a surface (paper §3.4).
#[derive(Clone, Copy, Debug, Deserialize, Serialize)]
#[serde(deny_unknown_fields)]
pub struct CoherenceSpec {
    pub reflected_keeps: bool,
    pub refracted_keeps: bool,
}

/// A rectangular extent: size (width along `u_axis`, height along normal × u_axis).
#[derive(Clone, Debug, Deserialize, Serialize)]
#[serde(deny_unknown_fields)]
pub struct RectSpec {
    pub size_m: [f64; 2],
    pub u_axis: Vec3,
}

/// An aperture in an opaque screen: centre (u, v) and size in the screen's axes.
#[derive(Clone, Debug, Deserialize, Serialize)]
#[serde(deny_unknown_fields)]
pub struct ApertureSpec {
    pub center_m: [f64; 2],
    pub size_m: [f64; 2],
}

/// A surface of the scene.
#[derive(Clone, Debug, Deserialize, Serialize)]
#[serde(rename_all = "snake_case", deny_unknown_fields)]
pub enum SurfaceSpec {
    /// A single interface; `front` is the medium on the side the normal points to.
    Interface {
        name: String,
        point_m: Vec3,
        normal: Vec3,
        front: String,
        back: String,
        #[serde(default)]
        rect: Option<RectSpec>,
        #[serde(default)]
        coherence: Option<CoherenceSpec>,
    },
    /// A plane-parallel plate (two unbounded interfaces).
    Plate {
        name: String,
        top_point_m: Vec3,
        normal: Vec3,
        thickness_um: f64,
        medium: String,
        above: String,
        below: String,
        #[serde(default)]
        coherence: Option<CoherenceSpec>,
    },
    /// A wedge: the bottom face tilted by `angle_deg` about `hinge_axis`.
    Wedge {
        name: String,
        top_point_m: Vec3,
        normal: Vec3,
        thickness_um: f64,
        angle_deg: f64,
        hinge_axis: Vec3,
        medium: String,
        above: String,
        below: String,
    },
    /// A perfectly conducting mirror.
    Mirror {
        name: String,
        point_m: Vec3,
        normal: Vec3,
        #[serde(default)]
        rect: Option<RectSpec>,
    },
    /// An ideal thin lossless beam splitter of power reflectance `reflectance`.
    Splitter {
        name: String,
        point_m: Vec3,
        normal: Vec3,
        reflectance: f64,
        #[serde(default)]
        rect: Option<RectSpec>,
    },
    /// An absorbing rectangle.
    Shield {
        name: String,
        point_m: Vec3,
        normal: Vec3,
        rect: RectSpec,
    },
    /// An opaque screen (unbounded unless `rect`) with rectangular apertures.
    OpaqueScreen {
        name: String,
        point_m: Vec3,
        normal: Vec3,
        #[serde(default)]
        rect: Option<RectSpec>,
        u_axis: Vec3,
        apertures: Vec<ApertureSpec>,
    },
}

impl SurfaceSpec {
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

/// The geometry of a source.
#[derive(Clone, Debug, Deserialize, Serialize)]
#[serde(rename_all = "snake_case", deny_unknown_fields)]
pub enum EmitterSpec {
    Point {
        position_m: Vec3,
    },
    Line {
        point_m: Vec3,
        axis: Vec3,
    },
    PlaneWave {
        direction: Vec3,
        reference_point_m: Vec3,
    },
}

/// Polarization of a source.
#[derive(Clone, Debug, Deserialize, Serialize)]
#[serde(rename_all = "snake_case", deny_unknown_fields)]
pub enum PolarizationSpec {
    /// Linear: `reference` projected perpendicular to each ray, rotated by `angle_deg` about it.
    Linear { reference: Vec3, angle_deg: f64 },
    /// Unpolarized light. `model` `basis_free` (the default): three incoherent dipole
    /// channels along x, y, z, no reference (docs/PHYSICS.md §3); `paper_two_channel`: the
    /// paper's two incoherent channels at 0° and 90° from `reference` (required then, and only
    /// then).
    Unpolarized {
        #[serde(default)]
        model: UnpolarizedModel,
        #[serde(default, skip_serializing_if = "Option::is_none")]
        reference: Option<Vec3>,
    },
}

/// The model of an unpolarized source (docs/PHYSICS.md §3).
#[derive(Clone, Copy, Debug, Default, Deserialize, Serialize, PartialEq, Eq)]
#[serde(rename_all = "snake_case")]
pub enum UnpolarizedModel {
    /// Three incoherent dipoles along x, y, z: independent of any basis.
    #[default]
    BasisFree,
    /// The paper's two linear channels built from a reference vector.
    PaperTwoChannel,
}

/// A source.
#[derive(Clone, Debug, Deserialize, Serialize)]
#[serde(deny_unknown_fields)]
pub struct SourceSpec {
    pub name: String,
    pub emitter: EmitterSpec,
    pub polarization: PolarizationSpec,
    /// |E|² of the source (default 1).
    #[serde(default = "one")]
    pub intensity: f64,
    /// Sources with equal groups are mutually coherent (default 0).
    #[serde(default)]
    pub coherence_group: u64,
    /// The paper's coherence length SC_max (P9), metres; absent: unlimited.
    #[serde(default)]
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

/// The scene.
#[derive(Clone, Debug, Deserialize, Serialize)]
#[serde(deny_unknown_fields)]
pub struct SceneSpec {
    /// Name of the medium around the sources.
    pub ambient: String,
    /// Media by name; a name defined twice is an error (not "the last one wins").
    #[serde(deserialize_with = "unique_keys")]
    pub media: BTreeMap<String, MediumSpec>,
    pub surfaces: Vec<SurfaceSpec>,
    pub sources: Vec<SourceSpec>,
}

/// What the far field observes in a sweep.
#[derive(Clone, Copy, Debug, Deserialize, Serialize, PartialEq, Eq)]
#[serde(rename_all = "snake_case")]
pub enum FarSide {
    Reflected,
    Transmitted,
}

/// A swept parameter.
#[derive(Clone, Debug, Deserialize, Serialize, PartialEq)]
#[serde(rename_all = "snake_case", deny_unknown_fields)]
pub enum SweepParameter {
    /// Angle of incidence of every plane-wave source, in the plane spanned by `surface_normal`
    /// and `in_plane_axis`: direction = sin θ·axis − cos θ·normal.
    IncidenceAngleDeg {
        surface_normal: Vec3,
        in_plane_axis: Vec3,
    },
    /// The vacuum wavelength (monochrome light only).
    WavelengthNm {},
    /// The thickness of the plate or wedge called `surface`.
    ThicknessNm { surface: String },
}

/// Where a probe point observes.
#[derive(Clone, Debug, Deserialize, Serialize, PartialEq)]
#[serde(rename_all = "snake_case", deny_unknown_fields)]
pub enum Observer {
    /// A screen point. With `looks_toward`, the detector is one-sided (an eye or a film looking
    /// that way): it records only rays travelling against `looks_toward`.
    Point {
        position_m: Vec3,
        #[serde(default)]
        looks_toward: Option<Vec3>,
    },
    /// The far field (ideal lens at infinity) on the reflected or transmitted side of the
    /// surface normal of an incidence-angle sweep (or of the plane wave's direction relative to
    /// `surface_normal`), leaving into medium `exit_medium` (default: ambient).
    FarField {
        side: FarSide,
        surface_normal: Vec3,
        #[serde(default)]
        exit_medium: Option<String>,
    },
    /// The far field in one fixed direction, phase referred to the wavefront through
    /// `reference_point_m`.
    Direction {
        direction: Vec3,
        reference_point_m: Vec3,
    },
}

/// The probe: where and over what the traced and closed-form values are compared.
#[derive(Clone, Debug, Deserialize, Serialize)]
#[serde(rename_all = "snake_case", deny_unknown_fields)]
pub enum Probe {
    /// `count` screen points evenly spaced from `from_m` to `to_m`; the coordinate is the
    /// distance from `origin_m` along the line direction (default: from `from_m`).
    Line {
        from_m: Vec3,
        to_m: Vec3,
        count: usize,
        #[serde(default)]
        origin_m: Option<Vec3>,
        /// One-sided screen: records only rays travelling against this direction.
        #[serde(default)]
        looks_toward: Option<Vec3>,
    },
    /// `count` values of `parameter` evenly spaced from `from` to `to`, observed by `observe`.
    Sweep {
        parameter: SweepParameter,
        from: f64,
        to: f64,
        count: usize,
        observe: Observer,
    },
    /// A single observation (e.g. a far-field direction).
    Single { observe: Observer },
    /// A picture: `pixels` = [columns, rows] screen points at the pixel centres of the rectangle
    /// of `size_m` = [width, height] centred on `center_m`, width along `u_axis` (left → right),
    /// height along `v_axis` (bottom → top, made perpendicular to `u_axis`); row 0 is the top.
    /// `fringe check` traces every point (coordinate: row-major pixel index); `fringe render`
    /// draws it, optionally at another pixel count (`--size`).
    Grid {
        center_m: Vec3,
        u_axis: Vec3,
        v_axis: Vec3,
        size_m: [f64; 2],
        pixels: [usize; 2],
        /// One-sided screen: records only rays travelling against this direction.
        #[serde(default)]
        looks_toward: Option<Vec3>,
    },
}

/// A closed-form reference and its tolerances per fidelity level (relative deviation, see the
/// metric). Levels without a tolerance are reported for information only.
#[derive(Clone, Debug, Deserialize, Serialize)]
#[serde(deny_unknown_fields)]
pub struct ReferenceSpec {
    pub model: ReferenceModel,
    /// Name of the metric in tables and files (default: the model's name); unique per case.
    #[serde(default)]
    pub label: Option<String>,
    #[serde(deserialize_with = "unique_keys")]
    pub tolerances: BTreeMap<Fidelity, f64>,
    /// Why a tolerance looser than 1e-9 is physically forced (required when one is).
    #[serde(default)]
    pub tolerance_note: Option<String>,
}

/// The closed forms (src/analytic), each reading its parameters from the scene.
#[derive(Clone, Debug, Deserialize, Serialize, PartialEq)]
#[serde(rename_all = "snake_case", deny_unknown_fields)]
pub enum ReferenceModel {
    /// Two coherent line sources: exact distances, vector fields (analytic::young).
    YoungExact {},
    /// Paraxial Young 2(1 + cos(2π d y/(λ l))).
    YoungParaxial {},
    /// Fringe spacing at the probe centre vs λ sqrt(l² + d²/4)/d (exact) or λl/d (paraxial).
    YoungSpacing { paraxial: bool },
    /// Lloyd's mirror with the first surface as mirror (s-polarized line source).
    Lloyd {},
    /// Fringe visibility of Lloyd's mirror, 2|r_s|/(1 + |r_s|²).
    LloydVisibility {},
    /// Two-beam reflection of a point source by the plate `plate` (paper Fig. 4 left).
    TwoBeamPlate { plate: String },
    /// Airy reflectance or transmittance of the plate/film `film` (side from the observer).
    Airy {
        film: String,
        /// Use this constant film index instead of the medium's dispersion (to show what
        /// ignoring dispersion costs).
        #[serde(default)]
        index_override: Option<f64>,
    },
    /// The Fizeau wedge `wedge`: two-beam intensity (s-polarized plane wave, normal incidence).
    Wedge { wedge: String },
    /// Fizeau fringe spacing λ/(n sin 2α) (exact) or λ/(2nα) (small angle).
    WedgeSpacing { wedge: String, small_angle: bool },
    /// Retardance arg(E_p) − arg(E_s) after `tir_count` TIRs in `glass` at the plane wave's angle
    /// of incidence on `tir_surface` (Fresnel rhomb).
    RhombRetardance {
        glass: String,
        tir_surface: String,
        tir_count: usize,
    },
    /// Plane waves through planar faces, phase by wavefront continuity: the traced sum of the
    /// listed beams (each a source with its surface sequence), complex Fresnel amplitudes.
    PlaneWaveBeams { beams: Vec<BeamSpec> },
    /// Michelson interferometer: virtual sources and the vector image rule.
    Michelson {
        splitter: String,
        mirrors: [String; 2],
    },
    /// Mutually incoherent point sources: Σ I_k/r_k² (spreading on) or Σ I_k (off).
    IncoherentSum {},
    /// Two-beam plate reflection at normal incidence with a Gaussian spectrum:
    /// I1 + I2 + 2√(I1 I2)|γ(Δs)| cos(k0 Δs + φ) (docs/PHYSICS.md §3).
    CoherenceGaussian {
        plate: String,
        /// Bandwidth (FWHM, nm) when the case's light is monochromatic (to measure another
        /// coherence model against this truth); must be absent for Gaussian light.
        #[serde(default)]
        fwhm_nm: Option<f64>,
    },
    /// The paper's rule (P9) for the same plate: coherent while both rays' own paths are below
    /// the coherence length, I1 + I2 otherwise.
    CoherenceP9 { plate: String },
}

/// One beam of a [`ReferenceModel::PlaneWaveBeams`] reference: a plane-wave source and the
/// surfaces it meets in order (each with `reflect` or `refract`).
#[derive(Clone, Debug, Deserialize, Serialize, PartialEq)]
#[serde(deny_unknown_fields)]
pub struct BeamSpec {
    pub source: String,
    pub events: Vec<BeamEvent>,
}

#[derive(Clone, Debug, Deserialize, Serialize, PartialEq)]
#[serde(deny_unknown_fields)]
pub struct BeamEvent {
    pub surface: String,
    pub reflect: bool,
}

/// Tracing settings of a case.
#[derive(Clone, Debug, Deserialize, Serialize)]
#[serde(deny_unknown_fields)]
pub struct TraceSpec {
    /// Maximum reflections inside non-ambient media (default 1: two beams).
    #[serde(default = "one_usize")]
    pub max_internal_reflections: usize,
    /// Choose the internal-reflection count per probe point so the Airy tail bound of the
    /// reference film is below this (overrides `max_internal_reflections`).
    #[serde(default)]
    pub airy_tail_epsilon: Option<f64>,
    /// Geometric spreading (1/r² for point sources); off for the paper's figures.
    #[serde(default)]
    pub spreading: bool,
    /// Regression tolerance against `golden/<case>.csv` (relative to the profile scale).
    #[serde(default = "golden_tol")]
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
