//! Random valid scenes, one generator per family with a closed form. Each generator builds a
//! case file (JSON, the format of `cases/README.md`) in a canonical frame (surfaces through the
//! origin, normal +z) from [`Draws`], sampling the documented valid range of every parameter:
//! vacuum wavelengths 200–2500 nm, indices 0.001–10 (the ambient too), films 0.1 nm – 1 m,
//! incidence from normal to grazing with extra weight at the named angles (grazing, critical,
//! Brewster), reflected and transmitted sides, films in the ambient medium and on substrates.
//! The caller then moves the whole scene rigidly ([`super::motion`]).
//!
//! A generator returns `Err(reason)` only where the family's geometry cannot be built for the
//! drawn parameters (for example a point source whose direct light cannot be shielded at
//! near-normal incidence); the run counts it as a refusal with that reason.

use super::draws::Draws;
use serde_json::{Value, json};

/// The families of `fringe fuzz`: one per reference model with a closed form (the primary
/// reference of every scene of the family).
#[derive(Clone, Copy, Debug, PartialEq, Eq, PartialOrd, Ord, Hash)]
pub enum Family {
    YoungExact,
    Lloyd,
    TwoBeamPlate,
    Airy,
    Wedge,
    RhombRetardance,
    PlaneWaveBeams,
    Michelson,
    IncoherentSum,
    CoherenceGaussian,
}

impl Family {
    pub const ALL: [Family; 10] = [
        Family::YoungExact,
        Family::Lloyd,
        Family::TwoBeamPlate,
        Family::Airy,
        Family::Wedge,
        Family::RhombRetardance,
        Family::PlaneWaveBeams,
        Family::Michelson,
        Family::IncoherentSum,
        Family::CoherenceGaussian,
    ];

    /// The family's name: the key of its reference model in case files.
    pub fn name(self) -> &'static str {
        match self {
            Family::YoungExact => "young_exact",
            Family::Lloyd => "lloyd",
            Family::TwoBeamPlate => "two_beam_plate",
            Family::Airy => "airy",
            Family::Wedge => "wedge",
            Family::RhombRetardance => "rhomb_retardance",
            Family::PlaneWaveBeams => "plane_wave_beams",
            Family::Michelson => "michelson",
            Family::IncoherentSum => "incoherent_sum",
            Family::CoherenceGaussian => "coherence_gaussian",
        }
    }

    pub fn parse(s: &str) -> Option<Family> {
        Family::ALL.into_iter().find(|f| f.name() == s)
    }

    /// Draw one scene of this family (canonical frame), pushing region tags.
    pub fn generate(self, d: &mut Draws, tags: &mut Vec<&'static str>) -> Result<Value, String> {
        match self {
            Family::YoungExact => young(d, tags),
            Family::Lloyd => lloyd(d, tags),
            Family::TwoBeamPlate => two_beam_plate(d, tags),
            Family::Airy => airy(d, tags),
            Family::Wedge => wedge(d, tags),
            Family::RhombRetardance => rhomb(d, tags),
            Family::PlaneWaveBeams => plane_wave_beams(d, tags),
            Family::Michelson => michelson(d, tags),
            Family::IncoherentSum => incoherent_sum(d, tags),
            Family::CoherenceGaussian => coherence_gaussian(d, tags),
        }
    }
}

/// The `vector` tolerance of every generated case: the library's (a relative deviation of
/// 1e-9 of the profile's largest value; pointwise for retardances).
pub(crate) const VECTOR_TOLERANCE: f64 = 1e-9;

/// Largest coordinate a generator places (m): below the 1000 m cap with room for the
/// translation of the rigid motion.
const REACH_M: f64 = 250.0;

// ---------------------------------------------------------------- shared samplers

/// A refractive index over the documented range [0.001, 10]: option 0 `simple`, option 1
/// uniform in [1, 4] (the optical media of practice), option 2 log-uniform over the whole
/// range.
fn index(d: &mut Draws, simple: f64) -> f64 {
    match d.choose(3) {
        0 => simple,
        1 => d.real(1.0, 4.0),
        _ => d.log(1e-3, 10.0),
    }
}

/// Whether the film or plate lies on a substrate (probability ½, tagged `substrate`) and the
/// index below it: the substrate's (drawn like [`index`] around 1.33), else `ambient`.
fn substrate(d: &mut Draws, tags: &mut Vec<&'static str>, ambient: f64) -> (bool, f64) {
    if d.flag(0.5) {
        tags.push("substrate");
        (true, index(d, 1.33))
    } else {
        (false, ambient)
    }
}

/// The ambient index (air, or any medium), tagged `air` or `medium`.
fn ambient(d: &mut Draws, tags: &mut Vec<&'static str>) -> f64 {
    let n = index(d, 1.0);
    tags.push(if n == 1.0 { "air" } else { "medium" });
    n
}

/// A vacuum wavelength (nm), uniform over the documented [200, 2500].
fn wavelength_nm(d: &mut Draws) -> f64 {
    d.real(200.0, 2500.0)
}

/// A film or plate thickness (µm), log-uniform over [1e-4, 1e6] (0.1 nm to the 1 m cap).
fn thickness_um(d: &mut Draws, tags: &mut Vec<&'static str>) -> f64 {
    let t = d.log(1e-4, 1e6);
    if t < 1e-3 {
        tags.push("sub_nm_film");
    } else if t > 1e3 {
        tags.push("thick_plate");
    }
    t
}

fn constant(n: f64) -> Value {
    json!({"constant": {"n": n}})
}

/// The case skeleton: `vector` only (the level judged), the primary reference first.
fn case(
    light: Value,
    media: Value,
    surfaces: Value,
    sources: Value,
    probe: Value,
    reference: Value,
    trace: Value,
) -> Value {
    json!({
        "name": "fuzz",
        "description": "",
        "formula": "",
        "light": light,
        "scene": {"ambient": "ambient", "media": media, "surfaces": surfaces, "sources": sources},
        "probe": probe,
        "references": [{"model": reference, "tolerances": {"vector": VECTOR_TOLERANCE}}],
        "fidelities": ["vector"],
        "trace": trace,
    })
}

fn monochrome(nm: f64) -> Value {
    json!({"monochrome": {"wavelength_nm": nm}})
}

/// An incidence angle (degrees, in [0, 90)) over the whole range, with weight at the named
/// angles: option 0 uniform, 1 within 1e-7°–1° of grazing, 2 within 1e-10°–1° of a critical
/// angle (either side; uniform when there is none), 3 within 1e-10°–1° of Brewster's angle.
fn incidence_deg(
    d: &mut Draws,
    critical_deg: &[f64],
    brewster_deg: f64,
    tags: &mut Vec<&'static str>,
) -> f64 {
    let below_90 = |x: f64| x.clamp(0.0, 90.0 - 1e-12);
    match d.choose(4) {
        0 => d.real(0.0, 90.0 - 1e-12),
        1 => {
            tags.push("grazing");
            90.0 - d.log(1e-7, 1.0)
        }
        2 if !critical_deg.is_empty() => {
            tags.push("near_critical");
            let c = critical_deg[d.choose(critical_deg.len())];
            let off = d.log(1e-10, 1.0);
            below_90(if d.flag(0.5) { c + off } else { c - off })
        }
        3 => {
            tags.push("near_brewster");
            let off = d.log(1e-10, 1.0);
            below_90(if d.flag(0.5) {
                brewster_deg + off
            } else {
                brewster_deg - off
            })
        }
        _ => d.real(0.0, 90.0 - 1e-12),
    }
}

/// A sweep of the incidence angle from `theta` over a span of 1e-9°–10° (1 to 5 points).
fn incidence_sweep(d: &mut Draws, theta: f64, azimuth_deg: f64, observe: Value) -> Value {
    let count = 1 + d.choose(5);
    let span = d.log(1e-9, 10.0);
    let to = if count == 1 {
        theta
    } else if theta + span < 90.0 {
        theta + span
    } else {
        theta + 0.5 * (90.0 - theta)
    };
    let (s, c) = azimuth_deg.to_radians().sin_cos();
    json!({"sweep": {
        "parameter": {"incidence_angle_deg": {"surface_normal": [0, 0, 1], "in_plane_axis": [c, s, 0]}},
        "from": theta, "to": to, "count": count, "observe": observe}})
}

/// Linear polarization about `reference` (option 0 at 0°, option 1 at any angle in
/// [−360°, 360°]), unpolarized in the paper's two-channel model (option 2) or basis-free
/// unpolarized light (option 3, three dipole channels, docs/PHYSICS.md §3).
fn polarization(d: &mut Draws, reference: [f64; 3]) -> Value {
    match d.choose(4) {
        0 => json!({"linear": {"reference": reference, "angle_deg": 0.0}}),
        1 => json!({"linear": {"reference": reference, "angle_deg": d.real(-360.0, 360.0)}}),
        2 => json!({"unpolarized": {"model": "paper_two_channel", "reference": reference}}),
        _ => json!({"unpolarized": {}}),
    }
}

/// Source intensity |E|²: 1, or log-uniform over [1e-6, 1e12].
fn intensity(d: &mut Draws) -> f64 {
    if d.flag(0.5) { d.log(1e-6, 1e12) } else { 1.0 }
}

fn brewster_deg(n1: f64, n2: f64) -> f64 {
    (n2 / n1).atan().to_degrees()
}

/// A probe count of 2 to 9 points.
fn line_count(d: &mut Draws) -> usize {
    2 + d.choose(8)
}

// ---------------------------------------------------------------- families

/// Two coherent slits (line sources along z at y = ±d/2) in any medium; a line probe across
/// the fringes at distance l.
fn young(d: &mut Draws, tags: &mut Vec<&'static str>) -> Result<Value, String> {
    let n0 = ambient(d, tags);
    let nm = wavelength_nm(d);
    let sep = d.log(1e-6, 1e-1);
    let l = d.log(1e-4, 100.0);
    let fringe = nm * 1e-9 * (l * l + sep * sep / 4.0).sqrt() / (n0 * sep);
    let centre = (fringe * d.real(-50.0, 50.0)).clamp(-REACH_M / 2.0, REACH_M / 2.0);
    let half = (fringe * d.log(1e-2, 10.0)).min(REACH_M / 2.0);
    let pol = match d.choose(4) {
        0 => json!({"unpolarized": {"model": "paper_two_channel", "reference": [0, 0, 1]}}),
        3 => json!({"unpolarized": {}}),
        1 => json!({"linear": {"reference": [0, 0, 1], "angle_deg": 0.0}}),
        _ => {
            json!({"linear": {"reference": [0, 0, 1], "angle_deg": 90.0 * (d.choose(9) as f64 - 4.0)}})
        }
    };
    let i0 = intensity(d);
    let source = |name: &str, y: f64| {
        json!({"name": name, "emitter": {"line": {"point_m": [0, y, 0], "axis": [0, 0, 1]}},
               "polarization": pol.clone(), "intensity": i0})
    };
    Ok(case(
        monochrome(nm),
        json!({"ambient": constant(n0)}),
        json!([]),
        json!([source("slit1", sep / 2.0), source("slit2", -sep / 2.0)]),
        json!({"line": {"from_m": [l, centre - half, 0], "to_m": [l, centre + half, 0],
                        "count": line_count(d)}}),
        json!({"young_exact": {}}),
        json!({}),
    ))
}

/// Lloyd's mirror: a dielectric interface z = 0 (any index behind it), an s-polarized slit at
/// height h, a vertical line probe at distance l.
fn lloyd(d: &mut Draws, tags: &mut Vec<&'static str>) -> Result<Value, String> {
    let n0 = ambient(d, tags);
    let n2 = index(d, 1.5);
    if n2 < n0 {
        tags.push("rarer_mirror");
    }
    let nm = wavelength_nm(d);
    let h = d.log(1e-6, 1e-1);
    let l = d.log(1e-4, 100.0);
    let fringe = nm * 1e-9 * l / (2.0 * h * n0);
    // The loader takes a probe point within 1e-12 × max(|mirror point|, 1 m) of an unbounded
    // mirror to lie on it (cases/README.md); after the rigid motion the mirror point is up to
    // MAX_OFFSET_M from the origin. The lowest probe point stays ten times above that distance,
    // so a drawn scene is off the mirror in every frame (a generator-validity bound, not a
    // steer: below it the loader rightly refuses the scene as a detector in an interface).
    let off_mirror = 10.0 * 1e-12 * super::MAX_OFFSET_M;
    let z0 = (fringe * d.log(1e-3, 30.0))
        .max(off_mirror)
        .min(REACH_M / 2.0);
    let z1 = (z0 + fringe * d.log(1e-2, 10.0)).min(REACH_M);
    let angle = if d.flag(0.5) { 180.0 } else { 0.0 };
    Ok(case(
        monochrome(nm),
        json!({"ambient": constant(n0), "mirror_glass": constant(n2)}),
        json!([{"interface": {"name": "mirror", "point_m": [0, 0, 0], "normal": [0, 0, 1],
                              "front": "ambient", "back": "mirror_glass"}}]),
        json!([{"name": "slit", "emitter": {"line": {"point_m": [0, 0, h], "axis": [0, 1, 0]}},
                "polarization": {"linear": {"reference": [0, 1, 0], "angle_deg": angle}},
                "intensity": intensity(d)}]),
        json!({"line": {"from_m": [l, 0, z0], "to_m": [l, 0, z1], "count": line_count(d)}}),
        json!({"lloyd": {}}),
        json!({}),
    ))
}

/// Two-beam reflection of an unpolarized point source at height h by a plate in the ambient
/// medium; a horizontal line probe at height h + Δ in the plane of incidence, the direct light
/// blocked by a small shield just above the source.
fn two_beam_plate(d: &mut Draws, tags: &mut Vec<&'static str>) -> Result<Value, String> {
    let n0 = ambient(d, tags);
    let n = index(d, 1.5);
    let nm = wavelength_nm(d);
    let t = thickness_um(d, tags);
    let mut hs = d.log(1e-5, 1.0);
    let mut dh = hs * d.log(1e-2, 1e2);
    // The angle of incidence at the first probe point (top-face reflection).
    let theta = incidence_deg(d, &[], brewster_deg(n0, n), tags);
    let span = d.log(1e-3, 1.0);
    let tan = theta.to_radians().tan();
    // Near grazing the probe runs far out: the scene is scaled down (heights and distances
    // together, the angles kept) until it fits the coordinate range.
    let fit = (REACH_M / ((2.0 * hs + dh) * tan * (1.0 + span))).min(1.0);
    hs *= fit;
    dh *= fit;
    // The loader refuses a probe passing within 1 µm of the point source (about a wavelength:
    // ray optics needs the observer that far away, cases/README.md). The probe line's nearest
    // point is at distance √(x0² + Δ²) from the source; when it is nearer than 2 µm (near
    // normal incidence with Δ below a micrometre) every height is scaled up together, which
    // keeps the angles and the ratio Δ/h_s (a valid scene of the same shape by construction).
    let x_near = (2.0 * hs + dh) * tan;
    let near = x_near.hypot(dh);
    if near < 2e-6 {
        let g = 2e-6 / near;
        hs *= g;
        dh *= g;
    }
    let ho = hs + dh;
    let x0 = (hs + ho) * tan;
    let x1 = x0 * (1.0 + span) + 1e-9 * fit;
    // Direct rays cross the shield plane z = hs + ε within x1·ε/Δ of the source; reflected
    // rays no nearer than x0·2hs/(hs + ho).
    // (At least 1e-11 m: the loader takes a source within 1e-12 m of a plane to lie on it.)
    let eps = (dh * 1e-6).max(1e-11);
    let w_min = x1 * eps / dh;
    let w_max = x0 * 2.0 * hs / (hs + ho);
    if w_min * 100.0 > w_max {
        return Err("two_beam_plate: at near-normal incidence the direct and reflected rays of a point source cannot be separated by a shield".into());
    }
    let w = (w_min * w_max).sqrt();
    // Unpolarized light, basis-free (three dipole channels) or in the paper's two channels.
    let pol = if d.flag(0.5) {
        json!({"unpolarized": {}})
    } else {
        json!({"unpolarized": {"model": "paper_two_channel", "reference": [0, 1, 0]}})
    };
    Ok(case(
        monochrome(nm),
        json!({"ambient": constant(n0), "glass": constant(n)}),
        json!([
            {"plate": {"name": "plate", "top_point_m": [0, 0, 0], "normal": [0, 0, 1],
                       "thickness_um": t, "medium": "glass", "above": "ambient", "below": "ambient"}},
            {"shield": {"name": "shield", "point_m": [0, 0, hs + eps], "normal": [0, 0, 1],
                        "rect": {"size_m": [2.0 * w, 2.0 * w], "u_axis": [1, 0, 0]}}}
        ]),
        json!([{"name": "lamp", "emitter": {"point": {"position_m": [0, 0, hs]}},
                "polarization": pol, "intensity": intensity(d)}]),
        json!({"line": {"from_m": [x0, 0, ho], "to_m": [x1, 0, ho], "count": line_count(d)}}),
        json!({"two_beam_plate": {"plate": "plate"}}),
        json!({}),
    ))
}

/// The Airy sum of a film (in the ambient medium or on a substrate), plane-wave incidence
/// swept near a drawn angle, the reflected or transmitted far field.
fn airy(d: &mut Draws, tags: &mut Vec<&'static str>) -> Result<Value, String> {
    let n1 = ambient(d, tags);
    let n2 = index(d, 1.5);
    let (on_substrate, n3) = substrate(d, tags, n1);
    let t = thickness_um(d, tags);
    let nm = wavelength_nm(d);
    let transmitted = d.flag(0.5);
    tags.push(if transmitted {
        "transmitted"
    } else {
        "reflected"
    });
    let mut critical = Vec::new();
    if n2 < n1 {
        critical.push((n2 / n1).asin().to_degrees());
    }
    if n3 < n1 {
        critical.push((n3 / n1).asin().to_degrees());
    }
    let theta = incidence_deg(d, &critical, brewster_deg(n1, n2), tags);
    let azimuth = d.real(0.0, 360.0);
    let (s, c) = azimuth.to_radians().sin_cos();
    let pol = polarization(d, [-s, c, 0.0]);
    let observe = if transmitted && on_substrate {
        json!({"far_field": {"side": "transmitted", "surface_normal": [0, 0, 1], "exit_medium": "substrate"}})
    } else {
        json!({"far_field": {"side": if transmitted { "transmitted" } else { "reflected" }, "surface_normal": [0, 0, 1]}})
    };
    let probe = incidence_sweep(d, theta, azimuth, observe);
    let height = d.log(1e-6, 1.0);
    let epsilon = d.log(1e-15, 1e-12);
    let mut media = json!({"ambient": constant(n1), "film": constant(n2)});
    if on_substrate {
        media["substrate"] = constant(n3);
    }
    Ok(case(
        monochrome(nm),
        media,
        json!([{"plate": {"name": "film", "top_point_m": [0, 0, 0], "normal": [0, 0, 1],
                          "thickness_um": t, "medium": "film", "above": "ambient",
                          "below": if on_substrate { "substrate" } else { "ambient" }}}]),
        json!([{"name": "beam",
                "emitter": {"plane_wave": {"direction": [0, 0, -1], "reference_point_m": [0, 0, height]}},
                "polarization": pol, "intensity": intensity(d)}]),
        probe,
        json!({"airy": {"film": "film"}}),
        json!({"airy_tail_epsilon": epsilon}),
    ))
}

/// A Fizeau wedge (hinge along y, angle 1e-5°–10°) under a normally incident s-polarized plane
/// wave, a one-sided line probe above it across the fringes.
fn wedge(d: &mut Draws, tags: &mut Vec<&'static str>) -> Result<Value, String> {
    let n0 = ambient(d, tags);
    let n = index(d, 1.5);
    let (on_substrate, n3) = substrate(d, tags, n0);
    let nm = wavelength_nm(d);
    let alpha_deg = d.log(1e-5, 10.0);
    let t0_um = d.log(1e-3, 1e4);
    let tan_a = alpha_deg.to_radians().tan();
    // Where the wedge has positive thickness: |x| < t0/tan α.
    let reach = (0.9 * t0_um * 1e-6 / tan_a).min(REACH_M);
    let fringe = nm * 1e-9 / (2.0 * n * alpha_deg.to_radians().sin());
    let centre = reach * d.real(-0.5, 0.5);
    let half = (fringe * d.log(1e-2, 10.0)).min(0.5 * (reach - centre.abs()));
    let h_src = d.log(1e-6, 1.0);
    // The beam reflected by the bottom face leaves the top face at θe (sin θe = n sin 2α / n0)
    // and walks off sideways by h tan θe before reaching the probe at height h: keep its
    // starting point on the wedge (where the thickness is positive).
    // When n sin 2α ≥ n0 that beam is totally reflected at the top face and never leaves it
    // toward the probe (its next bottom reflection steepens it to 4α): the probe sees the top
    // beam alone, a valid scene (`analytic::wedge`), at any height.
    let sin_exit = n * (2.0 * alpha_deg.to_radians()).sin() / n0;
    let room = reach - centre.abs() - half;
    let h_obs = if sin_exit >= 1.0 {
        tags.push("second_beam_tir");
        d.log(1e-6, 1.0)
    } else {
        let tan_exit = sin_exit / (1.0 - sin_exit * sin_exit).sqrt();
        d.log(1e-6, 1.0).min(0.5 * room / tan_exit)
    };
    if h_obs <= 0.0 {
        return Err("wedge: no probe height keeps the second beam on the wedge".into());
    }
    let angle = if d.flag(0.5) { 180.0 } else { 0.0 };
    let mut media = json!({"ambient": constant(n0), "glass": constant(n)});
    if on_substrate {
        media["substrate"] = constant(n3);
    }
    Ok(case(
        monochrome(nm),
        media,
        json!([{"wedge": {"name": "wedge", "top_point_m": [0, 0, 0], "normal": [0, 0, 1],
                          "thickness_um": t0_um, "angle_deg": alpha_deg, "hinge_axis": [0, 1, 0],
                          "medium": "glass", "above": "ambient",
                          "below": if on_substrate { "substrate" } else { "ambient" }}}]),
        json!([{"name": "beam",
                "emitter": {"plane_wave": {"direction": [0, 0, -1], "reference_point_m": [0, 0, h_src]}},
                "polarization": {"linear": {"reference": [0, 1, 0], "angle_deg": angle}},
                "intensity": intensity(d)}]),
        json!({"line": {"from_m": [centre - half, 0, h_obs], "to_m": [centre + half, 0, h_obs],
                        "count": line_count(d), "looks_toward": [0, 0, -1]}}),
        json!({"wedge": {"wedge": "wedge"}}),
        json!({}),
    ))
}

/// A total-internal-reflection prism: the beam enters and leaves through faces normal to it
/// and is totally reflected once at the face z = 0 at an angle beyond the critical one;
/// retardance of the output in its far-field direction.
fn rhomb(d: &mut Draws, tags: &mut Vec<&'static str>) -> Result<Value, String> {
    let n0 = ambient(d, tags);
    let ng = n0 + (10.0 - n0) * d.log(1e-6, 1.0);
    let nm = wavelength_nm(d);
    let critical = (n0 / ng).asin().to_degrees();
    let theta = match d.choose(3) {
        0 => d.real(critical, 90.0 - 1e-9),
        1 => {
            tags.push("near_critical");
            (critical + d.log(1e-10, 1.0)).min(90.0 - 1e-9)
        }
        _ => {
            // Within 1e-7°–1° of grazing, and above the critical angle by at least 1e-10° (the
            // near-critical draws' least offset) when that lies within a degree of grazing:
            // clamping to the critical angle itself drew scenes without TIR (a generator defect).
            tags.push("grazing");
            90.0 - d.log(1e-7, (90.0 - critical - 1e-10).min(1.0))
        }
    };
    let size = d.log(1e-4, 10.0);
    let (s, c) = theta.to_radians().sin_cos();
    let inward = [s, 0.0, -c];
    let outward = [s, 0.0, c];
    let p_in = [-size * s, 0.0, size * c];
    let p_out = [size * s, 0.0, size * c];
    let start = [-1.5 * size * s, 0.0, 1.5 * size * c];
    let angle = match d.choose(3) {
        0 => 45.0,
        1 => -45.0,
        _ => d.real(-360.0, 360.0),
    };
    // The prism is the triangle of the three face planes: the entry and exit faces meet at the
    // apex (0, 0, size/cos θ), size·tan θ from p_in and p_out along the faces. Their rectangles
    // end halfway to the apex, so the two faces never cross (beyond the apex, near the critical
    // angle of a dense prism, the exit face's rectangle lay across the incoming beam, and no
    // light reached the probe). On the side away from the apex they keep size/2: the TIR face's
    // rectangle (|x| ≤ size/2) ends before the entry and exit planes meet z = 0 (|x| = size/sin θ).
    let to_apex = (0.5 * size * theta.to_radians().tan()).min(0.5 * size);
    let shift = 0.5 * (to_apex - 0.5 * size);
    let height = to_apex + 0.5 * size;
    let c_in = [p_in[0] + shift * c, 0.0, p_in[2] + shift * s];
    let c_out = [p_out[0] - shift * c, 0.0, p_out[2] + shift * s];
    let face = |u: [f64; 3]| json!({"size_m": [size, height], "u_axis": u});
    let rect = |u: [f64; 3]| json!({"size_m": [size, size], "u_axis": u});
    Ok(case(
        monochrome(nm),
        json!({"ambient": constant(n0), "glass": constant(ng)}),
        json!([
            {"interface": {"name": "entry", "point_m": c_in, "normal": [-s, 0.0, c],
                           "front": "ambient", "back": "glass", "rect": face([0.0, 1.0, 0.0])}},
            {"interface": {"name": "tir", "point_m": [0, 0, 0], "normal": [0, 0, -1],
                           "front": "ambient", "back": "glass", "rect": rect([1.0, 0.0, 0.0])}},
            {"interface": {"name": "exit", "point_m": c_out, "normal": [s, 0.0, c],
                           "front": "ambient", "back": "glass", "rect": face([0.0, 1.0, 0.0])}}
        ]),
        json!([{"name": "beam",
                "emitter": {"plane_wave": {"direction": inward, "reference_point_m": start}},
                "polarization": {"linear": {"reference": [0, 1, 0], "angle_deg": angle}},
                "intensity": intensity(d)}]),
        json!({"single": {"observe": {"direction": {"direction": outward, "reference_point_m": p_out}}}}),
        json!({"rhomb_retardance": {"glass": "glass", "tir_surface": "tir", "tir_count": 1}}),
        json!({"max_internal_reflections": 1}),
    ))
}

/// One plane wave at one unbounded interface (any two media), reflected or transmitted beam in
/// the far field, incidence swept near a drawn angle.
fn plane_wave_beams(d: &mut Draws, tags: &mut Vec<&'static str>) -> Result<Value, String> {
    let n1 = ambient(d, tags);
    let n2 = index(d, 1.5);
    let nm = wavelength_nm(d);
    let transmitted = d.flag(0.5);
    tags.push(if transmitted {
        "transmitted"
    } else {
        "reflected"
    });
    let critical: Vec<f64> = if n2 < n1 {
        vec![(n2 / n1).asin().to_degrees()]
    } else {
        vec![]
    };
    let theta = incidence_deg(d, &critical, brewster_deg(n1, n2), tags);
    let azimuth = d.real(0.0, 360.0);
    let (s, c) = azimuth.to_radians().sin_cos();
    let pol = polarization(d, [-s, c, 0.0]);
    let observe = if transmitted {
        json!({"far_field": {"side": "transmitted", "surface_normal": [0, 0, 1], "exit_medium": "back"}})
    } else {
        json!({"far_field": {"side": "reflected", "surface_normal": [0, 0, 1]}})
    };
    let probe = incidence_sweep(d, theta, azimuth, observe);
    let height = d.log(1e-6, 1.0);
    Ok(case(
        monochrome(nm),
        json!({"ambient": constant(n1), "back": constant(n2)}),
        json!([{"interface": {"name": "face", "point_m": [0, 0, 0], "normal": [0, 0, 1],
                              "front": "ambient", "back": "back"}}]),
        json!([{"name": "beam",
                "emitter": {"plane_wave": {"direction": [0, 0, -1], "reference_point_m": [0, 0, height]}},
                "polarization": pol, "intensity": intensity(d)}]),
        probe,
        json!({"plane_wave_beams": {"beams": [{"source": "beam",
                "events": [{"surface": "face", "reflect": !transmitted}]}]}}),
        json!({}),
    ))
}

/// A Michelson interferometer (the library's layout at any scale u from 1 mm to 10 m): splitter
/// at 45°, arms of unequal length, one mirror optionally tilted, a line probe below the
/// splitter, and a pinhole in front of the point source sized to pass exactly the rays of both
/// arms to the probe and block the direct light (refused when no size does both).
fn michelson(d: &mut Draws, tags: &mut Vec<&'static str>) -> Result<Value, String> {
    use glam::DVec3;
    let n0 = ambient(d, tags);
    let nm = wavelength_nm(d);
    let u = d.log(1e-3, 10.0);
    let r = match d.choose(2) {
        0 => 0.5,
        _ => d.real(0.0, 1.0),
    };
    if !(1e-6..=1.0 - 1e-6).contains(&r) {
        tags.push("splitter_0_or_1");
    }
    let a1 = u * d.real(0.5, 1.5);
    let a2 = a1 + u * d.real(-0.1, 0.1);
    let tilt = if d.flag(0.5) {
        tags.push("tilted_mirror");
        d.real(-1e-3, 1e-3)
    } else {
        0.0
    };
    let xs = -u * d.real(0.95, 2.0);
    let z_probe = -3.0 * u * d.real(0.5, 2.0);
    let x0 = u * d.real(0.0, 0.25);
    let x1 = x0 + u * d.log(1e-4, 0.25);
    let h = std::f64::consts::FRAC_1_SQRT_2;
    // Rays of both arms through the pinhole plane x = xh (mirror images, docs/PHYSICS.md §5).
    let reflect = |p: DVec3, q: DVec3, n: DVec3| p - 2.0 * (p - q).dot(n) * n;
    let turn = |v: DVec3, n: DVec3| v - 2.0 * v.dot(n) * n;
    let (nb, n1, n2) = (
        DVec3::new(-h, 0.0, h),
        DVec3::new(0.0, 0.0, -1.0),
        DVec3::new(-tilt.cos(), 0.0, tilt.sin()),
    );
    let (q1, q2) = (DVec3::new(0.0, 0.0, a1), DVec3::new(a2, 0.0, 0.0));
    let s = DVec3::new(xs, 0.0, 0.0);
    let xh = -0.9 * u;
    let (mut need, mut direct) = (0.0f64, f64::INFINITY);
    for x in [x0, 0.5 * (x0 + x1), x1] {
        let p = DVec3::new(x, 0.0, z_probe);
        let v1 = reflect(reflect(s, DVec3::ZERO, nb), q1, n1);
        let v2 = reflect(reflect(s, q2, n2), DVec3::ZERO, nb);
        for d0 in [turn(turn(p - v1, n1), nb), turn(turn(p - v2, nb), n2)] {
            if d0.x <= 0.0 {
                return Err(
                    "michelson: an arm's ray leaves the source away from the splitter".into(),
                );
            }
            need = need.max(((xh - xs) / d0.x * d0.z).abs());
        }
        direct = direct.min(((xh - xs) / (x - xs) * z_probe).abs());
    }
    let half = 1.5 * need + 1e-9 * u;
    if direct < 2.0 * half {
        return Err(
            "michelson: no pinhole passes both arms' rays to the probe and blocks the direct light"
                .into(),
        );
    }
    // m1 lies wholly on the probe side of the pinhole's screen (|x| ≤ 0.8u, the screen at
    // x = −0.9u; the arm's rays meet it within |x| ≤ x1 ≤ 0.5u): a larger m1 reached behind the
    // screen, where the source lit it directly and it sent that light down through the pinhole
    // (source, m1, splitter, probe: not a Michelson interferometer).
    let m1_half = 0.8 * u;
    let pol = polarization(d, [0.0, 1.0, 0.0]);
    Ok(case(
        monochrome(nm),
        json!({"ambient": constant(n0)}),
        json!([
            {"splitter": {"name": "splitter", "point_m": [0, 0, 0], "normal": [-h, 0.0, h],
                          "reflectance": r, "rect": {"size_m": [6.0 * u, 6.0 * u], "u_axis": [h, 0.0, h]}}},
            {"mirror": {"name": "m1", "point_m": [0, 0, a1], "normal": [0, 0, -1],
                        "rect": {"size_m": [2.0 * m1_half, 4.0 * u], "u_axis": [1, 0, 0]}}},
            {"mirror": {"name": "m2", "point_m": [a2, 0, 0], "normal": [-tilt.cos(), 0.0, tilt.sin()],
                        "rect": {"size_m": [4.0 * u, 4.0 * u], "u_axis": [0, 0, 1]}}},
            {"opaque_screen": {"name": "pinhole", "point_m": [xh, 0, 0], "normal": [1, 0, 0],
                               "u_axis": [0, 0, 1],
                               "apertures": [{"center_m": [0, 0], "size_m": [2.0 * half, 2.0 * half]}]}}
        ]),
        json!([{"name": "lamp", "emitter": {"point": {"position_m": [xs, 0, 0]}},
                "polarization": pol, "intensity": intensity(d)}]),
        json!({"line": {"from_m": [x0, 0, z_probe], "to_m": [x1, 0, z_probe], "count": line_count(d)}}),
        json!({"michelson": {"splitter": "splitter", "mirrors": ["m1", "m2"]}}),
        json!({"max_internal_reflections": 0}),
    ))
}

/// One to four mutually incoherent point sources in a box of size 0.1 mm – 30 m, spreading on
/// or off, a line probe through the box.
fn incoherent_sum(d: &mut Draws, tags: &mut Vec<&'static str>) -> Result<Value, String> {
    let n0 = ambient(d, tags);
    let nm = wavelength_nm(d);
    let b = d.log(1e-4, 30.0);
    let k = 1 + d.choose(4);
    let sources: Vec<Value> = (0..k)
        .map(|i| {
            let p = [
                b * d.real(-1.0, 1.0),
                b * d.real(-1.0, 1.0),
                b * d.real(-1.0, 1.0),
            ];
            json!({"name": format!("s{i}"), "emitter": {"point": {"position_m": p}},
                   "polarization": polarization(d, [0.0, 0.0, 1.0]), "intensity": intensity(d),
                   "coherence_group": i})
        })
        .collect();
    let from = [b * d.real(-3.0, 3.0), b * d.real(-3.0, 3.0), b * 3.0];
    let to = [
        b * d.real(-3.0, 3.0),
        b * d.real(-3.0, 3.0),
        b * d.real(1.5, 3.0),
    ];
    let spreading = d.flag(0.5);
    Ok(case(
        monochrome(nm),
        json!({"ambient": constant(n0)}),
        json!([]),
        Value::Array(sources),
        json!({"line": {"from_m": from, "to_m": to, "count": line_count(d)}}),
        json!({"incoherent_sum": {}}),
        json!({"spreading": spreading}),
    ))
}

/// Two-beam reflection of Gaussian light by a plate at normal incidence (in the ambient medium
/// or on a substrate), the plate thickness swept; the spectral sampling is drawn over the
/// documented range (`undersampled` when the trapezoid sum cannot resolve the spectrum to the
/// tolerance: fewer than σ(7 + Δs σ_k)/π + 1 samples, or fewer than 7 standard deviations).
fn coherence_gaussian(d: &mut Draws, tags: &mut Vec<&'static str>) -> Result<Value, String> {
    let n1 = ambient(d, tags);
    let n2 = index(d, 1.5);
    let (on_substrate, n3) = substrate(d, tags, n1);
    // The sampled band k0 ± sigmas·σ_k must lie within [200, 2500] nm (the loader's rule), with
    // a relative margin of 1e-12 on each end for the rounding of the loader's k → λ conversion
    // (a margin relative to k0 − k_min was lost to it for centres near 2500 nm).
    let tau = std::f64::consts::TAU;
    let (k_min, k_max) = (tau / 2500.0 * (1.0 + 1e-12), tau / 200.0 * (1.0 - 1e-12));
    // A centre exactly at a limit has no valid Gaussian around it (any width spills over).
    let centre = wavelength_nm(d).clamp(200.0 * (1.0 + 1e-9), 2500.0 * (1.0 - 1e-9));
    let k0 = tau / centre;
    // σ_k = 2π FWHM/(centre² √(8 ln 2)) (nm⁻¹), the conversion of build::spectrum.
    let fwhm_per_sigma_k = centre * centre * (8.0 * 2f64.ln()).sqrt() / tau;
    // The widest FWHM whose band fits one standard deviation (sigmas ≥ 1, the least the loader
    // takes): the FWHM is drawn log-uniform over [1e-4, 0.2] of the centre below that bound (a
    // valid scene by construction; near 200 or 2500 nm the bound is below 1e-4 of the centre and
    // the range moves down with it).
    let fwhm_fit = (k0 - k_min).min(k_max - k0) * fwhm_per_sigma_k * (1.0 - 1e-6);
    let hi = (fwhm_fit / centre).min(0.2);
    let lo = if hi >= 1e-4 { 1e-4 } else { 1e-3 * hi };
    let fwhm = centre * d.log(lo, hi);
    let t0_nm = d.log(0.1, 1e8);
    let t1_nm = (t0_nm * (1.0 + d.log(1e-6, 10.0))).min(1e9);
    // Resolution the trapezoid sum needs (see the doc comment).
    let sigma_k = fwhm / fwhm_per_sigma_k;
    let ds_nm = 2.0 * n2 * t1_nm;
    // The most standard deviations this spectrum allows (at least 1 by the FWHM's bound).
    let sigmas_max = ((k0 - k_min) / sigma_k)
        .min((k_max - k0) / sigma_k)
        .min(12.0);
    let (sigmas, samples) = match d.choose(2) {
        0 => {
            let sigmas = d.real(7.0, 12.0).min(sigmas_max);
            // The reference is the same discrete sum as the tracer's, so any sampling is valid;
            // beyond 4096 samples the spectrum is undersampled (the sampling error is not part
            // of the verdict).
            let need = sigmas * (7.0 + ds_nm * sigma_k) / std::f64::consts::PI + 1.0;
            if need > 4096.0 || sigmas < 7.0 {
                tags.push("undersampled");
            }
            let n = (need * d.real(1.0, 4.0)).ceil().min(4096.0);
            (sigmas, n as usize)
        }
        _ => {
            let sigmas = d.real(1.0, 12.0).min(sigmas_max);
            let n = d.log(2.0, 4096.0).round() as usize;
            let need = sigmas * (7.0 + ds_nm * sigma_k) / std::f64::consts::PI + 1.0;
            if (n as f64) < need || sigmas < 7.0 {
                tags.push("undersampled");
            }
            (sigmas, n.clamp(2, 4096))
        }
    };
    let mut media = json!({"ambient": constant(n1), "glass": constant(n2)});
    if on_substrate {
        media["substrate"] = constant(n3);
    }
    let count = line_count(d);
    Ok(case(
        json!({"gaussian": {"center_nm": centre, "fwhm_nm": fwhm, "samples": samples, "sigmas": sigmas}}),
        media,
        json!([{"plate": {"name": "plate", "top_point_m": [0, 0, 0], "normal": [0, 0, 1],
                          "thickness_um": t0_nm * 1e-3, "medium": "glass", "above": "ambient",
                          "below": if on_substrate { "substrate" } else { "ambient" }}}]),
        json!([{"name": "lamp",
                "emitter": {"plane_wave": {"direction": [0, 0, -1], "reference_point_m": [0, 0, 1e-6]}},
                "polarization": polarization(d, [0.0, 1.0, 0.0]), "intensity": intensity(d)}]),
        json!({"sweep": {"parameter": {"thickness_nm": {"surface": "plate"}}, "from": t0_nm, "to": t1_nm,
                         "count": count,
                         "observe": {"far_field": {"side": "reflected", "surface_normal": [0, 0, 1]}}}}),
        json!({"coherence_gaussian": {"plate": "plate"}}),
        json!({}),
    ))
}
