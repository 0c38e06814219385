//! Plane-parallel plates and films: the Airy multi-beam sum (B&W §7.6.1, §1.6.4; docs/PHYSICS.md §5
//! "Plate / film, multi-beam (Airy)"), its truncation, and the two-beam reflection of a point
//! source (paper §4.2, Fig. 4 left) with the geometry solved here in one dimension.

use super::precise;
use crate::optics::fresnel::{fresnel, fresnel_with_cos2_t};
use num_complex::Complex64;
use twofloat::TwoFloat;

/// s or p.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Pol {
    /// s: the field ⊥ the plane of incidence.
    S,
    /// p: the field in the plane of incidence.
    P,
}

/// Fresnel r, t for one polarization from the cosines on both sides (P1)–(P4), in the
/// conventions of [`crate::optics::fresnel::fresnel`] (r_p = (n_b cos_a − n_a cos_b)/(n_b cos_a + n_a cos_b));
/// `cos_b` imaginary beyond a critical angle. Equal indices: no interface (r = 0, t = 1).
fn coefficients(
    n_a: f64,
    cos_a: Complex64,
    n_b: f64,
    cos_b: Complex64,
    pol: Pol,
) -> (Complex64, Complex64) {
    if n_a == n_b {
        return (Complex64::from(0.0), Complex64::from(1.0));
    }
    let (num, den) = match pol {
        Pol::S => (cos_a * n_a - cos_b * n_b, cos_a * n_a + cos_b * n_b),
        Pol::P => (cos_a * n_b - cos_b * n_a, cos_a * n_b + cos_b * n_a),
    };
    if den == Complex64::from(0.0) {
        // Exactly grazing incidence on a face (cos θa = cos θb = 0 is impossible for n_a ≠ n_b
        // unless both vanish): R = 1, T = 0, the limit of (P1)–(P4).
        let f = fresnel(n_a, n_b, cos_a.re);
        return match pol {
            Pol::S => (f.r_s, f.t_s),
            Pol::P => (f.r_p, f.t_p),
        };
    }
    (num / den, cos_a * (2.0 * n_a) / den)
}

/// A three-medium stack n1 | n2 (thickness d) | n3 lit from n1 at angle θ1.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Film {
    /// Index of the incidence medium.
    pub n1: f64,
    /// Index of the film.
    pub n2: f64,
    /// Index of the exit medium.
    pub n3: f64,
    /// Film thickness d, m.
    pub thickness_m: f64,
}

/// The angle of incidence of a plane wave on a film, held as cos²θ1 in double-double: near a
/// critical angle cos²θ2 = 1 − (n1/n2)² sin²θ1 cancels, and a cos θ1 rounded to f64 before it
/// is squared moved R by up to 5e-5 there (fuzz `airy`, near_critical). From an f64 cos θ1 the
/// square is exact ([`From<f64>`]); [`Incidence::between`] forms it from a direction and a
/// normal as the tracer does (`optics::interaction::normal_wavevector_squares`).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Incidence {
    /// cos²θ1, double-double, in [0, 1].
    pub cos_sq: TwoFloat,
}

impl From<f64> for Incidence {
    fn from(cos_theta_1: f64) -> Self {
        Incidence {
            cos_sq: TwoFloat::new_mul(cos_theta_1, cos_theta_1),
        }
    }
}

impl Incidence {
    /// cos²θ1 = (d·N)²/(|d|²|N|²) of the f64 vectors `direction` and `normal` (neither needs
    /// unit length), with exact products.
    pub fn between(direction: glam::DVec3, normal: glam::DVec3) -> Self {
        let dot = |a: glam::DVec3, b: glam::DVec3| {
            TwoFloat::new_mul(a.x, b.x) + TwoFloat::new_mul(a.y, b.y) + TwoFloat::new_mul(a.z, b.z)
        };
        let c = dot(direction, normal);
        let cos_sq = precise::div(c * c, dot(direction, direction) * dot(normal, normal));
        Incidence {
            cos_sq: if cos_sq.hi() > 1.0 {
                TwoFloat::from(1.0)
            } else {
                cos_sq
            },
        }
    }

    /// cos θ1 rounded to f64.
    pub fn cos(&self) -> f64 {
        f64::from(self.cos_sq.sqrt())
    }

    /// sin²θ1 = 1 − cos²θ1, double-double.
    pub(crate) fn sin_sq(&self) -> TwoFloat {
        TwoFloat::from(1.0) - self.cos_sq
    }
}

/// The fraction of the source intensity below which the evanescent coupling through a layer
/// beyond its top face's critical angle (frustrated total reflection, docs/PHYSICS.md §5) is
/// neglected, so that the ray model's total reflection (R = |r12|² = 1, T = 0) is the exact
/// answer to within it. It is 1/10 of the smallest tolerance the gate derives (1e-12,
/// `harness::conditioning`): a scene whose exact and ray-model answers differ by more is refused,
/// never compared against a closed form that knows what the tracer cannot trace. Since the
/// tracer reflects with the layer's frustrated r_layer (`optics::fresnel::frustrated_layer`)
/// this applies only to the transmittance (the tunnelled wave is not traced).
pub const FTIR_NEGLIGIBLE: f64 = 1e-13;

/// The difference between the exact Airy answer and the ray model's total reflection beyond
/// the critical angle of a film's top face ([`Film::frustration`]), the largest over s and p.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Frustration {
    /// |r − r12|: the amplitude the evanescent coupling adds to the reflected wave.
    pub amplitude: f64,
    /// |R − |r12|²| (R − 1 for lossless media).
    pub reflectance: f64,
    /// T, the power transmittance the ray model sets to 0.
    pub transmittance: f64,
    /// κ = (2π/λ) sqrt(n1² sin²θ1 − n2²), 1/m: the field decays as e^{−κz} in the film.
    pub kappa_per_m: f64,
}

/// The quantities of the Airy sum at one angle, wavelength and polarization.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct AiryTerms {
    /// Reflection amplitude at face 1 from medium 1 (docs/PHYSICS.md §1 convention).
    pub r12: Complex64,
    /// Transmission amplitude through face 1 into the film.
    pub t12: Complex64,
    /// Reflection amplitude at face 1 from inside the film.
    pub r21: Complex64,
    /// Transmission amplitude through face 1 out of the film.
    pub t21: Complex64,
    /// Reflection amplitude at face 2 from inside the film.
    pub r23: Complex64,
    /// Transmission amplitude through face 2 into medium 3.
    pub t23: Complex64,
    /// Round-trip phase β = (4π/λ) n2 d cos θ2 (0 beyond the critical angle of face 1, where
    /// cos θ2 is imaginary and the round trip is the real decay `round_trip`).
    pub beta: f64,
    /// cos θ1 and cos θ3 (for the power ratio of transmission).
    pub cos1: f64,
    /// cos θ3.
    pub cos3: f64,
    /// e^{iβ} and e^{iβ/2}, from β/2π = 2 n2 d cos θ2/λ formed in double-double and reduced to
    /// a fraction of a cycle before rounding (the f64 `beta` of a 1 mm plate carries ~1e-12 rad).
    /// Beyond the critical angle of face 1 (cos θ2 = i sqrt(−cos²θ2), e^{-iωt}) e^{iβ} = e^{−2κd},
    /// κ = (2π/λ) n2 sqrt(−cos²θ2) = (2π/λ) sqrt(n1² sin²θ1 − n2²): frustrated total reflection.
    pub round_trip: Complex64,
    /// e^{iβ/2}.
    pub half_trip: Complex64,
    /// Whether the film carries only an evanescent wave (beyond the critical angle of face 1).
    pub evanescent: bool,
    /// κ = (2π/λ) n2 |cos θ2| (1/m) of the evanescent wave; 0 for a propagating one.
    pub kappa_per_m: f64,
    /// The admittances a_k = n_k cos θk (s) or cos θk/n_k (p) of the three media, so that
    /// r_jk = (a_j − a_k)/(a_j + a_k) (P1, P3).
    pub admittance: [Complex64; 3],
    /// a1 − a3, from (a1² − a3²)/(a1 + a3) with the squares in double-double where both are
    /// real (no cancellation when a1 ≈ a3).
    pub a1_minus_a3: Complex64,
    /// e^{iβ} − 1, without cancellation: 2i sin(β/2) e^{iβ/2}, or expm1(−2κd) when evanescent.
    pub round_trip_minus_1: Complex64,
    /// a2/cos θ2 and β/cos θ2: the limit of the sum exactly at the critical angle of face 1,
    /// where a2 = 0 and e^{iβ} − 1 = 0 (both O(cos θ2)).
    pub per_cos2: (f64, f64),
}

impl Film {
    /// The Fresnel coefficients and round-trip factor at incidence θ1 (cos θ1 as an f64 or an
    /// [`Incidence`]); beyond the critical angle of face 1 with the imaginary cos θ2 of
    /// frustrated total reflection (docs/PHYSICS.md §5).
    pub fn terms(&self, incidence: impl Into<Incidence>, lambda_m: f64, pol: Pol) -> AiryTerms {
        let inc: Incidence = incidence.into();
        // Every cosine from cos²θ1 by Snell's law, in double-double: cos²θk = 1 − (n1/nk)²
        // sin²θ1. (Taking cos θ3 from a rounded cos θ2, as a chain of Fresnel kernels would,
        // loses digits where the wave leaves the film near grazing: an ulp of cos θ2 moved R by
        // 5e-15 at θ1 = 89.7°, found by the 50-digit test.)
        let one = TwoFloat::from(1.0);
        let sin2 = inc.sin_sq();
        let cos_sq = |nk: f64| {
            let ratio = precise::div(TwoFloat::from(self.n1), TwoFloat::from(nk));
            one - sin2 * ratio * ratio
        };
        let cos_theta_1 = inc.cos();
        let c2sq = cos_sq(self.n2);
        let evanescent = c2sq.hi() < 0.0;
        // |cos θ2| in double-double: real, or the modulus of the imaginary cosine.
        let cos2_dd = if evanescent {
            (-c2sq).sqrt()
        } else if c2sq.hi() > 0.0 {
            c2sq.sqrt()
        } else {
            TwoFloat::from(0.0)
        };
        let c3sq = cos_sq(self.n3);
        let cos2 = f64::from(cos2_dd);
        // Beyond the substrate's critical angle cos θ3 = +i sqrt(−cos²θ3) (e^{-iωt}, P5–P6).
        let c3 = if c3sq.hi() >= 0.0 {
            Complex64::from(f64::from(c3sq.sqrt()))
        } else {
            Complex64::new(0.0, f64::from((-c3sq).sqrt()))
        };
        let cos3 = c3.re;
        let c1 = Complex64::from(cos_theta_1);
        let c2 = if evanescent {
            Complex64::new(0.0, cos2)
        } else {
            Complex64::from(cos2)
        };
        let (r12, t12) = coefficients(self.n1, c1, self.n2, c2, pol);
        let (r21, t21) = coefficients(self.n2, c2, self.n1, c1, pol);
        let (r23, t23) = coefficients(self.n2, c2, self.n3, c3, pol);
        // β/2π in double-double: 2 n2 d cos θ2/λ without rounding; whole cycles removed
        // before the phasor. Evanescent: e^{iβ} = e^{−2π·2 n2 d |cos θ2|/λ}, real and < 1.
        let optical = cos2_dd * TwoFloat::new_mul(2.0 * self.n2, self.thickness_m);
        let (round_trip, half_trip, beta, round_trip_minus_1) = if evanescent {
            let decay = f64::from(optical) * std::f64::consts::TAU / lambda_m;
            (
                Complex64::from((-decay).exp()),
                Complex64::from((-0.5 * decay).exp()),
                0.0,
                Complex64::from((-decay).exp_m1()),
            )
        } else {
            let half = precise::path_phasor(optical * 0.5, lambda_m);
            (
                precise::path_phasor(optical, lambda_m),
                half,
                4.0 * std::f64::consts::PI * self.n2 * self.thickness_m * cos2 / lambda_m,
                Complex64::new(0.0, 2.0 * half.im) * half,
            )
        };
        let adm = |n: f64, c: Complex64| match pol {
            Pol::S => c * n,
            Pol::P => c / n,
        };
        let admittance = [adm(self.n1, c1), adm(self.n2, c2), adm(self.n3, c3)];
        let a1_minus_a3 = if c3.im == 0.0 {
            // a1² − a3² in double-double: n1² cos²θ1 − n3² cos²θ3 (s), cos²θ1/n1² − cos²θ3/n3² (p).
            let sq = |n: f64, c_sq: TwoFloat| match pol {
                Pol::S => c_sq * TwoFloat::new_mul(n, n),
                Pol::P => precise::div(c_sq, TwoFloat::new_mul(n, n)),
            };
            let diff = sq(self.n1, inc.cos_sq) - sq(self.n3, c3sq);
            let sum = admittance[0] + admittance[2];
            if sum.re > 0.0 {
                Complex64::from(f64::from(diff) / sum.re)
            } else {
                admittance[0] - admittance[2]
            }
        } else {
            admittance[0] - admittance[2]
        };
        AiryTerms {
            r12,
            t12,
            r21,
            t21,
            r23,
            t23,
            beta,
            cos1: cos_theta_1,
            cos3,
            round_trip,
            half_trip,
            evanescent,
            kappa_per_m: if evanescent {
                std::f64::consts::TAU * self.n2 * cos2 / lambda_m
            } else {
                0.0
            },
            admittance,
            a1_minus_a3,
            round_trip_minus_1,
            per_cos2: (
                match pol {
                    Pol::S => self.n2,
                    Pol::P => 1.0 / self.n2,
                },
                4.0 * std::f64::consts::PI * self.n2 * self.thickness_m / lambda_m,
            ),
        }
    }

    /// Airy reflection amplitude r = r12 + t12 t21 r23 e^{iβ}/(1 − r21 r23 e^{iβ}) (docs/PHYSICS.md §5),
    /// evaluated with the Stokes relations r21 = −r12, t12 t21 = 1 − r12² (exact identities of
    /// (P1)–(P4)) as (r12 + r23 e^{iβ})/(1 + r12 r23 e^{iβ}): the sum of the series as written
    /// relies on those identities holding to the last bit, and near grazing, where R → 1 and
    /// t12 t21 → 0, f64 coefficients that satisfy them only to rounding cost ~40 ε of R
    /// (found by the 50-digit test, `tests/suite/closed_form_precision.rs`).
    pub fn r(&self, incidence: impl Into<Incidence>, lambda_m: f64, pol: Pol) -> Complex64 {
        let a = self.terms(incidence, lambda_m, pol);
        let (num, den) = Self::numerator_denominator(&a);
        num / den
    }

    /// (r12 + r23 e^{iβ})(a1 + a2)(a2 + a3) and (1 + r12 r23 e^{iβ})(a1 + a2)(a2 + a3) in the
    /// admittances a_k ([`AiryTerms::admittance`]), expanded about e^{iβ} = 1:
    /// 2 a2 (a1 − a3) + (a2 − a3)(a1 + a2)(e^{iβ} − 1) and
    /// 2 a2 (a1 + a3) + (a1 − a2)(a2 − a3)(e^{iβ} − 1). Near the critical angle of face 1
    /// (a2 → 0, r12 → 1, r23 → −1) the factored form r = (r12 + r23 e)/(1 + r12 r23 e) is a ratio
    /// of two differences of O(1) terms and lost ~1e-16/|cos θ2| of R (1.5e-12 at 1e-8 from the
    /// critical angle, `tests/suite/beyond_critical.rs`); these forms have no cancellation.
    fn numerator_denominator(a: &AiryTerms) -> (Complex64, Complex64) {
        let [a1, a2, a3] = a.admittance;
        if a2 == Complex64::from(0.0) {
            // Exactly at the critical angle: both forms divided by cos θ2 → 0.
            let (k, b) = a.per_cos2;
            let ib = Complex64::new(0.0, b);
            return (
                a.a1_minus_a3 * 2.0 * k - a3 * a1 * ib,
                (a1 + a3) * 2.0 * k - a1 * a3 * ib,
            );
        }
        let em1 = a.round_trip_minus_1;
        let num = a2 * a.a1_minus_a3 * 2.0 + (a2 - a3) * (a1 + a2) * em1;
        let den = a2 * (a1 + a3) * 2.0 + (a1 - a2) * (a2 - a3) * em1;
        (num, den)
    }

    /// Airy transmission amplitude t = t12 t23 e^{iβ/2}/(1 − r21 r23 e^{iβ}), with r21 = −r12,
    /// as 4 a1 a2 e^{iβ/2} (n1/n3 for p)/(2 a2 (a1 + a3) + (a1 − a2)(a2 − a3)(e^{iβ} − 1)).
    pub fn t(&self, incidence: impl Into<Incidence>, lambda_m: f64, pol: Pol) -> Complex64 {
        let a = self.terms(incidence, lambda_m, pol);
        Self::t_of(&a, self.n1 / self.n3, pol)
    }

    fn t_of(a: &AiryTerms, n1_over_n3: f64, pol: Pol) -> Complex64 {
        let [a1, a2, _] = a.admittance;
        let (_, den) = Self::numerator_denominator(a);
        // Exactly at the critical angle the denominator is divided by cos θ2: so is a2.
        let a2 = if a2 == Complex64::from(0.0) {
            Complex64::from(a.per_cos2.0)
        } else {
            a2
        };
        let scale = match pol {
            Pol::S => 4.0,
            Pol::P => 4.0 * n1_over_n3,
        };
        a1 * a2 * a.half_trip * scale / den
    }

    /// Reflectance R = |r|².
    pub fn reflectance(&self, incidence: impl Into<Incidence>, lambda_m: f64, pol: Pol) -> f64 {
        self.r(incidence, lambda_m, pol).norm_sqr()
    }

    /// Transmittance T = (n3 cos θ3)/(n1 cos θ1)·|t|² (0 when the wave cannot leave into n3).
    pub fn transmittance(&self, incidence: impl Into<Incidence>, lambda_m: f64, pol: Pol) -> f64 {
        let a = self.terms(incidence, lambda_m, pol);
        if a.cos3 == 0.0 {
            return 0.0;
        }
        let t = Self::t_of(&a, self.n1 / self.n3, pol);
        self.n3 * a.cos3 / (self.n1 * a.cos1) * t.norm_sqr()
    }

    /// Beyond the critical angle of face 1 (frustrated total reflection, docs/PHYSICS.md §5):
    /// how far the exact Airy answer is from the ray model's total reflection at face 1, which
    /// reflects r12 (|r12| = 1) and lets nothing into the film. `None` when the film carries a
    /// propagating wave. All three differences are O(e^{−2κd}) and vanish exactly when the exit
    /// medium is beyond its own critical angle too (no wave can carry power out).
    pub fn frustration(
        &self,
        incidence: impl Into<Incidence>,
        lambda_m: f64,
    ) -> Option<Frustration> {
        let inc: Incidence = incidence.into();
        let mut out = Frustration {
            amplitude: 0.0,
            reflectance: 0.0,
            transmittance: 0.0,
            kappa_per_m: 0.0,
        };
        for pol in [Pol::S, Pol::P] {
            let a = self.terms(inc, lambda_m, pol);
            if !a.evanescent {
                return None;
            }
            let e = a.round_trip;
            // r − r12 = r23 e (1 − r12²)/(1 + r12 r23 e): no cancellation.
            let dr = a.r23 * e * (1.0 - a.r12) * (1.0 + a.r12) / (1.0 + a.r12 * a.r23 * e);
            out.amplitude = out.amplitude.max(dr.norm());
            out.reflectance = out
                .reflectance
                .max((self.reflectance(inc, lambda_m, pol) - a.r12.norm_sqr()).abs());
            out.transmittance = out
                .transmittance
                .max(self.transmittance(inc, lambda_m, pol));
            out.kappa_per_m = a.kappa_per_m;
        }
        Some(out)
    }

    /// The reflection amplitude summed over the first `orders` reflected beams only: order 0 is
    /// r12, order m ≥ 1 is t12 t21 r23 (r21 r23)^{m−1} e^{imβ} (m round trips).
    pub(crate) fn r_truncated(
        &self,
        incidence: impl Into<Incidence>,
        lambda_m: f64,
        pol: Pol,
        orders: usize,
    ) -> Complex64 {
        let a = self.terms(incidence, lambda_m, pol);
        if orders == 0 {
            return Complex64::default();
        }
        // Orders 1 … orders−1 summed as a geometric series in closed form,
        // t12 t21 r23 e^{iβ} (1 − q^{orders−1})/(1 − q), q = r21 r23 e^{iβ}, with the Stokes
        // relations r21 = −r12, t12 t21 = (1 − r12)(1 + r12) as in [`Film::r`]: summing term by
        // term rounds each of ~100 terms of a high-finesse film and left the partial sum
        // 1.5e-15 off a 50-digit one (R ≈ 0.7), more than the tail it is meant to show.
        let first = (1.0 - a.r12) * (1.0 + a.r12) * a.r23 * a.round_trip;
        let q = -a.r12 * a.r23 * a.round_trip;
        let n = u32::try_from(orders - 1).unwrap_or(u32::MAX);
        if q == Complex64::from(1.0) {
            return a.r12 + first * f64::from(n);
        }
        a.r12 + first * (1.0 - q.powu(n)) / (1.0 - q)
    }

    /// Bound on the amplitude of the reflected orders left out after `orders` beams:
    /// |t12 t21 r23 e^{iβ}| |r21 r23 e^{iβ}|^{orders−1}/(1 − |r21 r23 e^{iβ}|) (geometric tail;
    /// |e^{iβ}| = 1 for a propagating wave in the film, e^{−2κd} for an evanescent one).
    pub fn r_tail_bound(
        &self,
        incidence: impl Into<Incidence>,
        lambda_m: f64,
        pol: Pol,
        orders: usize,
    ) -> f64 {
        let a = self.terms(incidence, lambda_m, pol);
        let decay = a.round_trip.norm();
        let q = (a.r21 * a.r23).norm() * decay;
        if q >= 1.0 {
            return f64::INFINITY;
        }
        let first = (a.t12 * a.t21 * a.r23).norm() * decay;
        first * q.powi(orders.saturating_sub(1) as i32) / (1.0 - q)
    }

    /// Bound on the transmitted orders left out after `orders` transmitted beams (order m has
    /// 2m internal reflections), in units of √T, the amplitude whose square is the power
    /// transmittance: √(n3 cos θ3/(n1 cos θ1)) |t12 t23 e^{iβ/2}| |r21 r23 e^{iβ}|^orders/(1 −
    /// |r21 r23 e^{iβ}|) (geometric tail, docs/PHYSICS.md §5). 0 where no wave leaves into n3.
    /// It can exceed [`Film::r_tail_bound`] by orders of magnitude: a film much thinner
    /// optically than its ambient (n2 = 0.0063 in air on n3 = 0.01) has t21 = 0.0125 in every
    /// reflected order but t23 = 0.77 in every transmitted one (fuzz `airy` seed 1 scene 230).
    pub fn t_tail_bound(
        &self,
        incidence: impl Into<Incidence>,
        lambda_m: f64,
        pol: Pol,
        orders: usize,
    ) -> f64 {
        let a = self.terms(incidence, lambda_m, pol);
        if a.cos3 == 0.0 || a.cos1 == 0.0 {
            return 0.0;
        }
        let q = (a.r21 * a.r23).norm() * a.round_trip.norm();
        if q >= 1.0 {
            return f64::INFINITY;
        }
        let scale = (self.n3 * a.cos3 / (self.n1 * a.cos1)).sqrt();
        let first = scale * (a.t12 * a.t23).norm() * a.half_trip.norm();
        first * q.powi(i32::try_from(orders).unwrap_or(i32::MAX)) / (1.0 - q)
    }

    /// The larger of the reflected and the transmitted tail bounds after `orders` beams
    /// ([`Film::r_tail_bound`], [`Film::t_tail_bound`]): what an Airy budget must bound when
    /// either side may be observed.
    pub fn tail_bound(
        &self,
        incidence: impl Into<Incidence>,
        lambda_m: f64,
        pol: Pol,
        orders: usize,
    ) -> f64 {
        let inc: Incidence = incidence.into();
        self.r_tail_bound(inc, lambda_m, pol, orders)
            .max(self.t_tail_bound(inc, lambda_m, pol, orders))
    }

    /// The number of beams for which [`Film::tail_bound`] (both sides) is below `epsilon`
    /// (at most 100 000).
    pub fn orders_for_tail_bound(
        &self,
        incidence: impl Into<Incidence>,
        lambda_m: f64,
        pol: Pol,
        epsilon: f64,
    ) -> usize {
        let inc: Incidence = incidence.into();
        orders_below(epsilon, |n| self.tail_bound(inc, lambda_m, pol, n))
    }

    /// The number of reflected orders needed so that the amplitude tail bound is ≤ `epsilon`:
    /// cost grows like log(1/ε)/log(1/|r21 r23|).
    pub fn orders_for_bound(
        &self,
        incidence: impl Into<Incidence>,
        lambda_m: f64,
        pol: Pol,
        epsilon: f64,
    ) -> usize {
        let inc: Incidence = incidence.into();
        orders_below(epsilon, |n| self.r_tail_bound(inc, lambda_m, pol, n))
    }
}

/// The first number of orders n ≥ 1 at which the decreasing tail `bound(n)` is ≤ `epsilon`
/// (at most 100 000).
fn orders_below(epsilon: f64, bound: impl Fn(usize) -> f64) -> usize {
    let mut n = 1;
    while bound(n) > epsilon && n < 100_000 {
        n += 1;
    }
    n
}

/// Geometry of the two-beam point-source plate (paper Fig. 4 left): source at height `h_src`
/// above the top face, observation point at height `h_obs`, horizontal separation `x`, plate
/// thickness `d`, indices n1 (ambient, also below) and n2.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct TwoBeamPlate {
    /// Ambient index (above and below the plate).
    pub n1: f64,
    /// Plate index.
    pub n2: f64,
    /// Plate thickness d, m.
    pub thickness_m: f64,
    /// Source height above the top face, m.
    pub h_src_m: f64,
    /// Observation point height above the top face, m.
    pub h_obs_m: f64,
}

/// The lateral distance of probe from source and their heights above the top face of a
/// [`TwoBeamPlate`] in double-double: formed from the scene's f64 coordinates without rounding
/// (the f64 fields of the plate are their roundings).
#[derive(Clone, Copy, Debug)]
pub struct HeldPoints {
    /// Lateral distance x of the probe from the source, m.
    pub x_m: TwoFloat,
    /// Source height above the top face, m.
    pub h_src_m: TwoFloat,
    /// Probe height above the top face, m.
    pub h_obs_m: TwoFloat,
}

/// Where the beam through a two-beam plate enters it, in double-double.
#[derive(Clone, Copy, Debug)]
struct Entry {
    /// Lateral offset of the entry point from the foot of the source, m.
    a: TwoFloat,
    /// First leg L1 = sqrt(a² + h_s²), m.
    l1: TwoFloat,
    /// cos θt inside the plate.
    cos_t: TwoFloat,
    /// Lateral offset X_e of the exit point (the same face), m.
    x_exit: TwoFloat,
}

/// One of the two beams at the observation point.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Beam {
    /// Angle of incidence on the top face (rad).
    pub theta: f64,
    /// Optical path (m).
    pub optical_path_m: f64,
    /// Amplitude factor for s (product of Fresnel coefficients).
    pub amp_s: Complex64,
    /// Amplitude factor for p.
    pub amp_p: Complex64,
}

impl TwoBeamPlate {
    /// Beam 1: reflection at the top face (image method): tan θ = x/(h_s + h_o).
    pub fn beam_top(&self, x_m: f64) -> Beam {
        self.beam_top_held(&self.held(x_m))
    }

    /// sin²θ = x²/(x² + h²), h = h_s + h_o, of the top beam of the `held` points, double-double.
    fn top_sin_sq(held: &HeldPoints) -> TwoFloat {
        let h = held.h_src_m + held.h_obs_m;
        let x = held.x_m;
        precise::div(x * x, x * x + h * h)
    }

    /// [`TwoBeamPlate::beam_top`] between the `held` points: lateral distance and heights in
    /// double-double, not their f64 roundings. Within 1e-7 of the top face's critical angle
    /// cos²θt = 1 − (n1/n2)² sin²θ is ~1e-7 and one rounding of x moves it by 1e-9 of itself
    /// (fuzz `two_beam_plate` seed 1 scene 4659, a 10 mm plate of n 0.001 under n 3 at 1.2e-7
    /// beyond it: I was 3e-13 off 50 digits from the f64 x, `tests/suite/truth_point_sources.rs`).
    fn beam_top_held(&self, held: &HeldPoints) -> Beam {
        let h = held.h_src_m + held.h_obs_m;
        let x = held.x_m;
        let (x_m, h_m) = (x.hi(), h.hi());
        let theta = x_m.atan2(h_m);
        // cos θ = h/√(x² + h²) keeps its relative precision near grazing, where cos(atan2)
        // loses it (an absolute error of 1e-16 on cos θ ≈ 1e-4).
        let cos_i = f64::from(precise::div(h, (x * x + h * h).sqrt()));
        // cos²θt = 1 − (n1/n2)² x²/(x² + h²) in double-double: near the critical angle, and
        // beyond it where r12 = e^{iφ} is the total reflection of an ambient denser than the
        // plate, an f64 cos²θt cancels (docs/PHYSICS.md §5).
        let f = if self.n1 == self.n2 {
            fresnel(self.n1, self.n2, cos_i)
        } else {
            let ratio = precise::div(TwoFloat::from(self.n1), TwoFloat::from(self.n2));
            let c2t = TwoFloat::from(1.0) - Self::top_sin_sq(held) * ratio * ratio;
            fresnel_with_cos2_t(self.n1, self.n2, cos_i, f64::from(c2t))
        };
        Beam {
            theta,
            optical_path_m: self.n1 * x_m.hypot(h_m),
            amp_s: f.r_s,
            amp_p: f.r_p,
        }
    }

    /// [`TwoBeamPlate::beam_top`] at vacuum wavelength `lambda_m` with the plate's evanescent
    /// coupling: beyond the critical angle of the top face (an ambient denser than the plate)
    /// the top beam's amplitude is the plate's plane-wave reflection r_layer at its angle (the
    /// Airy sum with imaginary cos θ2, [`Film::r`], frustrated total reflection,
    /// docs/PHYSICS.md §5) instead of the face's r12; elsewhere [`TwoBeamPlate::beam_top`].
    pub fn beam_top_frustrated(&self, x_m: f64, lambda_m: f64) -> Beam {
        self.beam_top_frustrated_held(&self.held(x_m), lambda_m)
    }

    /// [`TwoBeamPlate::beam_top_frustrated`] between the `held` points
    /// ([`TwoBeamPlate::beam_top_held`]).
    fn beam_top_frustrated_held(&self, held: &HeldPoints, lambda_m: f64) -> Beam {
        let beam = self.beam_top_held(held);
        let inc = Incidence {
            cos_sq: TwoFloat::from(1.0) - Self::top_sin_sq(held),
        };
        let layer = Film {
            n1: self.n1,
            n2: self.n2,
            n3: self.n1,
            thickness_m: self.thickness_m,
        };
        if self.n1 <= self.n2 || !layer.terms(inc, lambda_m, Pol::S).evanescent {
            return beam;
        }
        Beam {
            amp_s: layer.r(inc, lambda_m, Pol::S),
            amp_p: layer.r(inc, lambda_m, Pol::P),
            ..beam
        }
    }

    /// Beam 2: refracted in, reflected at the bottom face, refracted out. Parametrised by the
    /// entry point's lateral offset `a` (no trigonometry): first leg L1 = √(a² + h_s²),
    /// sin θ = a/L1, sin θt = (n1/n2) sin θ, exit at X_e = a + 2 d tan θt, last leg
    /// L3 = √((x − X_e)² + h_o²). `a` solves X_e + h_o tan θ = x by bisection; the optical path
    /// n1 L1 + 2 n2 d/cos θt + n1 L3 of the broken ray through the computed entry point is
    /// stationary there (Fermat), so the root's rounding enters only to second order, and it is
    /// summed in double-double ([`super::precise`]), so the beam's path keeps ~1e-30 m.
    pub fn beam_bottom(&self, x_m: f64) -> Beam {
        self.beam_bottom_precise(&self.held(x_m)).0
    }

    /// The f64 geometry of `self` at lateral distance `x_m` as [`HeldPoints`].
    fn held(&self, x_m: f64) -> HeldPoints {
        HeldPoints {
            x_m: x_m.into(),
            h_src_m: self.h_src_m.into(),
            h_obs_m: self.h_obs_m.into(),
        }
    }

    /// [`TwoBeamPlate::beam_bottom`] with its optical path in double-double, its outer legs
    /// measured to the `held` points (the entry is solved for `held.x_m` rounded to f64).
    fn beam_bottom_precise(&self, held: &HeldPoints) -> (Beam, TwoFloat) {
        let x_m = held.x_m.hi();
        let entry = if self.n1 > self.n2 {
            self.entry_by_slope(x_m)
        } else {
            self.entry_by_offset(x_m)
        };
        self.beam_through(held, entry)
    }

    /// The beam through a plate denser than its ambient (n1 ≤ n2), solved for the entry point's
    /// lateral offset `a`: X_e(a) + h_o a/h_s = x, with X_e = a + 2 d tan θt. Bisection in f64,
    /// then one Newton step in double-double with the analytic slope
    /// 1 + h_o/h_s + 2 d (n1/n2) h_s²/(L1³ cos³θt) (d sin θt/da = (n1/n2) h_s²/L1³,
    /// d tan θt/d sin θt = 1/cos³θt). Returns the entry (double-double).
    fn entry_by_offset(&self, x_m: f64) -> Entry {
        let (hs, ho, d) = (self.h_src_m, self.h_obs_m, self.thickness_m);
        let (n1, n2) = (self.n1, self.n2);
        // Landing offset of the ray entering at lateral a (f64, for the root only).
        let lateral = |a: f64| {
            let l1 = a.hypot(hs);
            let st = n1 / n2 * a / l1;
            let tan_t = st / (1.0 - st * st).sqrt();
            a + 2.0 * d * tan_t + ho * a / hs - x_m
        };
        let a0 = super::bisect(0.0, x_m, lateral);
        // The entry point's first leg, Snell angle and exit point in double-double, with n1/n2
        // unrounded: a Snell angle off by 1e-16 moves the optical path only to second order, but
        // grazing inside the plate the amplitudes to first order in tan θt / cos²θt (an f64
        // 1/0.001 put I 1.4e-14 off 50 digits at tan θt = 125,
        // `tests/suite/truth_beyond_critical_plates.rs`).
        let offset = |a: TwoFloat| {
            let l1 = (a * a + TwoFloat::new_mul(hs, hs)).sqrt();
            let st = precise::div(a * n1, l1 * n2);
            let ct = (TwoFloat::from(1.0) - st * st).sqrt();
            Entry {
                a,
                l1,
                cos_t: ct,
                x_exit: a + precise::div(st, ct) * (2.0 * d),
            }
        };
        // One Newton step puts the entry point where f64 cannot: near grazing the amplitudes
        // depend on it to first order (cos θ = h_s/L1 is small), the optical path does not.
        let a = {
            let l1 = a0.hypot(hs);
            let st = n1 / n2 * a0 / l1;
            let ct = (1.0 - st * st).sqrt();
            let slope = 1.0 + ho / hs + 2.0 * d * (n1 / n2) * (hs / l1).powi(2) / (l1 * ct.powi(3));
            let a0 = TwoFloat::from(a0);
            let miss = offset(a0).x_exit + a0 * (ho / hs) - x_m;
            a0 - miss / slope
        };
        offset(a)
    }

    /// The beam through a plate less dense than its ambient (n1 > n2), solved for w = tan θt,
    /// which stays conditioned as cos θt → 0: beyond the top face's critical angle the beam
    /// enters just below it and runs grazing inside the plate (tan θt up to 1e8 and beyond in
    /// valid scenes), where the entry offset a → a_c = n2 h_s/sqrt(n1² − n2²) is no longer
    /// resolved by f64 (cos²θt ∝ a_c − a). With r = n2/n1 < 1 and sin θ = r sin θt,
    /// tan θ = r w/sqrt(q), q = 1 + (1 − r²) w², and the landing condition is
    /// G(w) = (h_s + h_o) r w/sqrt(q) + 2 d w − x = 0: G is increasing and concave in w
    /// (G' = (h_s + h_o) r/q^{3/2} + 2 d), with G(0) = −x < 0 ≤ G(x/(2d)). Safeguarded Newton in
    /// f64 on that bracket, then two Newton steps in double-double (the f64 slope reduces the
    /// residual by ~1e-16 per step). The entry has cos θt = 1/sqrt(1 + w²) and X_e = a + 2 d w.
    fn entry_by_slope(&self, x_m: f64) -> Entry {
        let (hs, ho, d) = (self.h_src_m, self.h_obs_m, self.thickness_m);
        let h = hs + ho;
        let r = self.n2 / self.n1;
        let g = |w: f64| {
            let q = 1.0 + (1.0 - r * r) * w * w;
            (
                h * r * w / q.sqrt() + 2.0 * d * w - x_m,
                h * r / (q * q.sqrt()) + 2.0 * d,
            )
        };
        let (mut lo, mut hi) = (0.0_f64, x_m / (2.0 * d));
        let mut w = 0.0_f64;
        for _ in 0..200 {
            let (gw, slope) = g(w);
            if gw < 0.0 {
                lo = lo.max(w);
            } else {
                hi = hi.min(w);
            }
            let mut next = w - gw / slope;
            if !(next > lo && next < hi) {
                next = 0.5 * (lo + hi);
            }
            if next == w || (next - w).abs() <= 1e-16 * w {
                w = next;
                break;
            }
            w = next;
        }
        // Double-double: r = n2/n1 and 1 − r² unrounded.
        let one = TwoFloat::from(1.0);
        let r_dd = precise::div(TwoFloat::from(self.n2), TwoFloat::from(self.n1));
        let one_minus_r2 = one - r_dd * r_dd;
        let tan_in = |w: TwoFloat| precise::div(r_dd * w, (one + one_minus_r2 * w * w).sqrt());
        let mut w_dd = TwoFloat::from(w);
        for _ in 0..2 {
            let t = tan_in(w_dd);
            let miss = t * hs + t * ho + w_dd * (2.0 * d) - x_m;
            w_dd -= miss / g(f64::from(w_dd)).1;
        }
        let a = tan_in(w_dd) * hs;
        let l1 = (a * a + TwoFloat::new_mul(hs, hs)).sqrt();
        let ct = precise::div(one, (one + w_dd * w_dd).sqrt());
        Entry {
            a,
            l1,
            cos_t: ct,
            x_exit: a + w_dd * (2.0 * d),
        }
    }

    /// The beam through the plate from its entry: optical path (double-double) and amplitudes.
    /// The first and last legs are measured to the `held` source and probe (double-double,
    /// [`HeldPoints`]); the entry solved for their f64 roundings moves the path only to second
    /// order (Fermat, [`TwoBeamPlate::beam_bottom`]).
    fn beam_through(&self, held: &HeldPoints, entry: Entry) -> (Beam, TwoFloat) {
        let (hs, d) = (self.h_src_m, self.thickness_m);
        let (n1, n2) = (self.n1, self.n2);
        let Entry {
            a,
            l1,
            cos_t: ct,
            x_exit: x_e,
        } = entry;
        let l1_held = (a * a + held.h_src_m * held.h_src_m).sqrt();
        let dx = held.x_m - x_e;
        let l3 = (dx * dx + held.h_obs_m * held.h_obs_m).sqrt();
        let op = l1_held * n1 + precise::div(TwoFloat::from(2.0 * d) * n2, ct) + l3 * n1;
        let cos_i = f64::from(precise::div(TwoFloat::from(hs), l1));
        let cos_t = f64::from(ct);
        let a = f64::from(a);
        // The ray leaves the plate into n1 at the angle it entered (Snell's law both ways), so
        // every face sees the pair (cos θ, cos θt), both known to double-double: the bottom
        // reflection and the exit take the outside cosine from the entry, not from
        // cos²θ = 1 − (n2/n1)² sin²θt, which a plate much denser than its ambient turns into
        // cancellation (n2/n1 = 1000 near grazing: cos θt ≈ 1 − 2e-7 rounded by 1e-16 moved
        // cos²θ by 6e-7 of itself and I by 1.2e-8, against a 50-digit evaluation;
        // `tests/suite/truth_plates.rs`).
        let (ci, ct) = (Complex64::from(cos_i), Complex64::from(cos_t));
        let amp = |pol| {
            let (_, t12) = coefficients(n1, ci, n2, ct, pol);
            let (r23, t21) = coefficients(n2, ct, n1, ci, pol);
            t12 * r23 * t21
        };
        let beam = Beam {
            theta: a.atan2(hs),
            optical_path_m: f64::from(op),
            amp_s: amp(Pol::S),
            amp_p: amp(Pol::P),
        };
        (beam, op)
    }

    /// Two-beam intensity for an unpolarized unit-intensity source whose channels are s and p
    /// at every ray (observation points in one plane of incidence), spreading off:
    /// I = ½|a1s e^{iφ1} + a2s e^{iφ2}|² + ½(|a1p|² + |a2p|² + 2 Re(a1p a2p* e^{i(φ1−φ2)}) cos(θ1 − θ2)),
    /// where the p fields p_k = d_k × s of the two arriving rays make the angle θ1 − θ2.
    pub fn intensity_unpolarized(&self, x_m: f64, lambda_m: f64) -> f64 {
        self.unpolarized(&self.held(x_m), lambda_m, 1)
    }

    /// [`TwoBeamPlate::intensity_unpolarized`] (`basis_free` false) or
    /// [`TwoBeamPlate::intensity_unpolarized_basis_free`] (true) of a scene whose lateral
    /// distance and heights are known beyond f64 (`held`, double-double, from the scene's own
    /// f64 coordinates; `self.h_src_m`, `self.h_obs_m` their f64 roundings): the phase takes
    /// them unrounded. At grazing incidence the path difference moves by
    /// n1 (sin θ1 − sin θexit) per metre of x, up to ~n1: one rounding of x = 250 m (2.8e-14 m)
    /// turned the phase by 4e-7 rad at 200 nm and put I 1.7e-9 off 50 digits while the tracer
    /// was exact (`fringe fuzz --family two_beam_plate --count 300 --seed 1`, scene 4,
    /// `tests/suite/truth_thick_plates.rs`).
    pub fn intensity_unpolarized_held(
        &self,
        held: &HeldPoints,
        lambda_m: f64,
        basis_free: bool,
    ) -> f64 {
        self.unpolarized(held, lambda_m, if basis_free { 2 } else { 1 })
    }

    /// [`TwoBeamPlate::intensity_unpolarized`] for basis-free unpolarized light (three
    /// incoherent dipoles of weight 1/2, docs/PHYSICS.md §3): the s fields are those of the
    /// dipole along s for both beams; the in-plane dipoles give the launch p fields
    /// (p_k·a) p_k, correlated as Σ_a (p1·a)(p2·a) = cos(θ1 − θ2), so the p cross term carries
    /// cos²(θ1 − θ2) where the two-channel model's has cos(θ1 − θ2).
    pub fn intensity_unpolarized_basis_free(&self, x_m: f64, lambda_m: f64) -> f64 {
        self.unpolarized(&self.held(x_m), lambda_m, 2)
    }

    /// The two models: the p cross term with cos(θ1 − θ2) to the power `p_overlap_power`.
    fn unpolarized(&self, held: &HeldPoints, lambda_m: f64, p_overlap_power: i32) -> f64 {
        let (b1, (b2, op2)) = (
            self.beam_top_frustrated_held(held, lambda_m),
            self.beam_bottom_precise(held),
        );
        let h = held.h_src_m + held.h_obs_m;
        let op1 = (held.x_m * held.x_m + h * h).sqrt() * self.n1;
        let ph = precise::path_phasor(op1 - op2, lambda_m);
        let i_s = (b1.amp_s * ph + b2.amp_s).norm_sqr();
        // |a1|² + |a2|² + 2 Re(a1 a2* e^{iφ}) c^k as |a1 e^{iφ} + a2|² − 2 Re(a1 a2* e^{iφ})(1 − c^k),
        // c = cos(θ1 − θ2), 1 − c = 2 sin²(Δθ/2), 1 − c² = sin²Δθ: at a dark fringe of a thin
        // plate the expanded sum cancels its O(r12²) terms to 1e-6 of them and lost 1.5e-10 of
        // I (fuzz `two_beam_plate` seed 1 scene 181, 0.1 nm plate, I = 9.8e-12 of the source,
        // against 50 digits: `tests/suite/truth_small_deviations.rs`); neither term cancels here.
        let dtheta = b1.theta - b2.theta;
        let one_minus_overlap = match p_overlap_power {
            1 => 2.0 * (0.5 * dtheta).sin().powi(2),
            2 => dtheta.sin().powi(2),
            k => 1.0 - dtheta.cos().powi(k),
        };
        let i_p = (b1.amp_p * ph + b2.amp_p).norm_sqr()
            - 2.0 * (b1.amp_p * b2.amp_p.conj() * ph).re * one_minus_overlap;
        0.5 * (i_s + i_p)
    }
}
