//! Plane-parallel plates and films: the Airy multi-beam sum (B&W §7.6.1, §1.6.4; docs/PHYSICS.md §5
//! "Plate / film, multi-beam (Airy)"), its truncation, and the two-beam reflection of a point
//! source (paper §4.2, Fig. 4 left) with the geometry solved here in one dimension.

use super::precise;
use crate::fresnel::fresnel;
use num_complex::Complex64;
use twofloat::TwoFloat;

/// s or p.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Pol {
    S,
    P,
}

/// Fresnel r, t for one polarization.
fn rt(n1: f64, n2: f64, cos_i: f64, pol: Pol) -> (Complex64, Complex64) {
    let f = fresnel(n1, n2, cos_i);
    match pol {
        Pol::S => (f.r_s, f.t_s),
        Pol::P => (f.r_p, f.t_p),
    }
}

/// A three-medium stack n1 | n2 (thickness d) | n3 lit from n1 at angle θ1.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Film {
    pub n1: f64,
    pub n2: f64,
    pub n3: f64,
    pub thickness_m: f64,
}

/// The quantities of the Airy sum at one angle, wavelength and polarization.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct AiryTerms {
    pub r12: Complex64,
    pub t12: Complex64,
    pub r21: Complex64,
    pub t21: Complex64,
    pub r23: Complex64,
    pub t23: Complex64,
    /// Round-trip phase β = (4π/λ) n2 d cos θ2.
    pub beta: f64,
    /// cos θ1 and cos θ3 (for the power ratio of transmission).
    pub cos1: f64,
    pub cos3: f64,
}

impl Film {
    /// The Fresnel coefficients and round-trip phase at incidence cos θ1 (must not be TIR at
    /// the 1→2 interface).
    pub fn terms(&self, cos_theta_1: f64, lambda_m: f64, pol: Pol) -> AiryTerms {
        let sin2_1 = 1.0 - cos_theta_1 * cos_theta_1;
        let cos2 = (1.0 - sin2_1 * (self.n1 / self.n2).powi(2)).sqrt();
        let c3sq = 1.0 - sin2_1 * (self.n1 / self.n3).powi(2);
        let cos3 = c3sq.max(0.0).sqrt();
        let (r12, t12) = rt(self.n1, self.n2, cos_theta_1, pol);
        let (r21, t21) = rt(self.n2, self.n1, cos2, pol);
        let (r23, t23) = rt(self.n2, self.n3, cos2, pol);
        AiryTerms {
            r12,
            t12,
            r21,
            t21,
            r23,
            t23,
            beta: 4.0 * std::f64::consts::PI * self.n2 * self.thickness_m * cos2 / lambda_m,
            cos1: cos_theta_1,
            cos3,
        }
    }

    /// Airy reflection amplitude r = r12 + t12 t21 r23 e^{iβ}/(1 − r21 r23 e^{iβ}) (docs/PHYSICS.md §5).
    pub fn r(&self, cos_theta_1: f64, lambda_m: f64, pol: Pol) -> Complex64 {
        let a = self.terms(cos_theta_1, lambda_m, pol);
        let e = Complex64::from_polar(1.0, a.beta);
        a.r12 + a.t12 * a.t21 * a.r23 * e / (1.0 - a.r21 * a.r23 * e)
    }

    /// Airy transmission amplitude t = t12 t23 e^{iβ/2}/(1 − r21 r23 e^{iβ}).
    pub fn t(&self, cos_theta_1: f64, lambda_m: f64, pol: Pol) -> Complex64 {
        let a = self.terms(cos_theta_1, lambda_m, pol);
        let e = Complex64::from_polar(1.0, a.beta);
        a.t12 * a.t23 * Complex64::from_polar(1.0, 0.5 * a.beta) / (1.0 - a.r21 * a.r23 * e)
    }

    /// Reflectance R = |r|².
    pub fn reflectance(&self, cos_theta_1: f64, lambda_m: f64, pol: Pol) -> f64 {
        self.r(cos_theta_1, lambda_m, pol).norm_sqr()
    }

    /// Transmittance T = (n3 cos θ3)/(n1 cos θ1)·|t|² (0 when the wave cannot leave into n3).
    pub fn transmittance(&self, cos_theta_1: f64, lambda_m: f64, pol: Pol) -> f64 {
        let a = self.terms(cos_theta_1, lambda_m, pol);
        if a.cos3 == 0.0 {
            return 0.0;
        }
        self.n3 * a.cos3 / (self.n1 * cos_theta_1) * self.t(cos_theta_1, lambda_m, pol).norm_sqr()
    }

    /// The reflection amplitude summed over the first `orders` reflected beams only: order 0 is
    /// r12, order m ≥ 1 is t12 t21 r23 (r21 r23)^{m−1} e^{imβ} (m round trips).
    pub fn r_truncated(
        &self,
        cos_theta_1: f64,
        lambda_m: f64,
        pol: Pol,
        orders: usize,
    ) -> Complex64 {
        let a = self.terms(cos_theta_1, lambda_m, pol);
        let mut sum = if orders > 0 {
            a.r12
        } else {
            Complex64::default()
        };
        let mut term = a.t12 * a.t21 * a.r23 * Complex64::from_polar(1.0, a.beta);
        let q = a.r21 * a.r23 * Complex64::from_polar(1.0, a.beta);
        for _ in 1..orders {
            sum += term;
            term *= q;
        }
        sum
    }

    /// Bound on the amplitude of the reflected orders left out after `orders` beams:
    /// |t12 t21 r23| |r21 r23|^{orders−1}/(1 − |r21 r23|) (geometric tail).
    pub fn r_tail_bound(&self, cos_theta_1: f64, lambda_m: f64, pol: Pol, orders: usize) -> f64 {
        let a = self.terms(cos_theta_1, lambda_m, pol);
        let q = (a.r21 * a.r23).norm();
        if q >= 1.0 {
            return f64::INFINITY;
        }
        let first = (a.t12 * a.t21 * a.r23).norm();
        first * q.powi(orders.saturating_sub(1) as i32) / (1.0 - q)
    }

    /// The number of reflected orders needed so that the amplitude tail bound is ≤ `epsilon`:
    /// cost grows like log(1/ε)/log(1/|r21 r23|).
    pub fn orders_for_bound(
        &self,
        cos_theta_1: f64,
        lambda_m: f64,
        pol: Pol,
        epsilon: f64,
    ) -> usize {
        let mut n = 1;
        while self.r_tail_bound(cos_theta_1, lambda_m, pol, n) > epsilon && n < 100_000 {
            n += 1;
        }
        n
    }
}

/// Geometry of the two-beam point-source plate (paper Fig. 4 left): source at height `h_src`
/// above the top face, observation point at height `h_obs`, horizontal separation `x`, plate
/// thickness `d`, indices n1 (ambient, also below) and n2.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct TwoBeamPlate {
    pub n1: f64,
    pub n2: f64,
    pub thickness_m: f64,
    pub h_src_m: f64,
    pub h_obs_m: f64,
}

/// One of the two beams at the observation point.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Beam {
    /// Angle of incidence on the top face (rad).
    pub theta: f64,
    /// Optical path (m).
    pub optical_path_m: f64,
    /// Amplitude factors for s and p (product of Fresnel coefficients).
    pub amp_s: Complex64,
    pub amp_p: Complex64,
}

impl TwoBeamPlate {
    /// Beam 1: reflection at the top face (image method): tan θ = x/(h_s + h_o).
    pub fn beam_top(&self, x_m: f64) -> Beam {
        let h = self.h_src_m + self.h_obs_m;
        let theta = x_m.atan2(h);
        // cos θ = h/√(x² + h²) keeps its relative precision near grazing, where cos(atan2)
        // loses it (an absolute error of 1e-16 on cos θ ≈ 1e-4).
        let f = fresnel(self.n1, self.n2, h / x_m.hypot(h));
        Beam {
            theta,
            optical_path_m: self.n1 * x_m.hypot(h),
            amp_s: f.r_s,
            amp_p: f.r_p,
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
        self.beam_bottom_precise(x_m).0
    }

    /// [`TwoBeamPlate::beam_bottom`] with its optical path in double-double.
    fn beam_bottom_precise(&self, x_m: f64) -> (Beam, TwoFloat) {
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
        // The entry point's first leg, Snell angle and exit point in double-double. n1/n2 is an
        // input ratio, rounded once (a Snell angle off by 1e-16 moves the path's interior points
        // along their planes: second order in the optical path).
        let offset = |a: TwoFloat| {
            let l1 = (a * a + TwoFloat::new_mul(hs, hs)).sqrt();
            let st = precise::div(a * (n1 / n2), l1);
            let ct = (TwoFloat::from(1.0) - st * st).sqrt();
            (l1, ct, a + precise::div(st, ct) * (2.0 * d))
        };
        // One Newton step puts the entry point where f64 cannot: near grazing the amplitudes
        // depend on it to first order (cos θ = h_s/L1 is small), the optical path does not.
        let a = {
            let h = 1e-7 * a0.max(hs);
            let slope = (lateral(a0 + h) - lateral(a0 - h)) / (2.0 * h);
            let a0 = TwoFloat::from(a0);
            let miss = offset(a0).2 + a0 * (ho / hs) - x_m;
            a0 - miss / slope
        };
        let (l1, ct, x_e) = offset(a);
        let dx = TwoFloat::from(x_m) - x_e;
        let l3 = (dx * dx + TwoFloat::new_mul(ho, ho)).sqrt();
        let op = l1 * n1 + precise::div(TwoFloat::from(2.0 * d) * n2, ct) + l3 * n1;
        let cos_i = f64::from(precise::div(TwoFloat::from(hs), l1));
        let cos_t = f64::from(ct);
        let a = f64::from(a);
        let f12 = fresnel(n1, n2, cos_i);
        let f23 = fresnel(n2, n1, cos_t);
        let f21 = fresnel(n2, n1, cos_t);
        let beam = Beam {
            theta: a.atan2(hs),
            optical_path_m: f64::from(op),
            amp_s: f12.t_s * f23.r_s * f21.t_s,
            amp_p: f12.t_p * f23.r_p * f21.t_p,
        };
        (beam, op)
    }

    /// Two-beam intensity for an unpolarized unit-intensity source whose channels are s and p
    /// at every ray (observation points in one plane of incidence), spreading off:
    /// I = ½|a1s e^{iφ1} + a2s e^{iφ2}|² + ½(|a1p|² + |a2p|² + 2 Re(a1p a2p* e^{i(φ1−φ2)}) cos(θ1 − θ2)),
    /// where the p fields p_k = d_k × s of the two arriving rays make the angle θ1 − θ2.
    pub fn intensity_unpolarized(&self, x_m: f64, lambda_m: f64) -> f64 {
        self.unpolarized(x_m, lambda_m, 1)
    }

    /// [`TwoBeamPlate::intensity_unpolarized`] for basis-free unpolarized light (three
    /// incoherent dipoles of weight 1/2, docs/PHYSICS.md §3): the s fields are those of the
    /// dipole along s for both beams; the in-plane dipoles give the launch p fields
    /// (p_k·a) p_k, correlated as Σ_a (p1·a)(p2·a) = cos(θ1 − θ2), so the p cross term carries
    /// cos²(θ1 − θ2) where the two-channel model's has cos(θ1 − θ2).
    pub fn intensity_unpolarized_basis_free(&self, x_m: f64, lambda_m: f64) -> f64 {
        self.unpolarized(x_m, lambda_m, 2)
    }

    /// The two models: the p cross term with cos(θ1 − θ2) to the power `p_overlap_power`.
    fn unpolarized(&self, x_m: f64, lambda_m: f64, p_overlap_power: i32) -> f64 {
        let (b1, (b2, op2)) = (self.beam_top(x_m), self.beam_bottom_precise(x_m));
        let op1 = precise::distance(
            glam::DVec3::new(x_m, self.h_src_m, 0.0),
            glam::DVec3::new(0.0, -self.h_obs_m, 0.0),
        ) * self.n1;
        let ph = precise::path_phasor(op1 - op2, lambda_m);
        let i_s = (b1.amp_s * ph + b2.amp_s).norm_sqr();
        let i_p = b1.amp_p.norm_sqr()
            + b2.amp_p.norm_sqr()
            + 2.0
                * (b1.amp_p * b2.amp_p.conj() * ph).re
                * (b1.theta - b2.theta).cos().powi(p_overlap_power);
        0.5 * (i_s + i_p)
    }
}
