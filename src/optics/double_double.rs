//! Double-double numbers: an unevaluated sum hi + lo of two f64 with |lo| ≤ ulp(hi)/2, about
//! 106 significant bits, for optical paths (metres) that must keep their digits.
//!
//! Interference is a phase measurement: a 100 m optical path is 1.8·10^8 wavelengths, and an
//! absolute path summed in f64 loses ~1e-14 m there (~1e-7 rad of phase), while the fringes
//! depend only on path *differences* of a few µm. fringe therefore carries every optical path as
//! a [`DoubleDouble`] (docs/PHYSICS.md §1, "Precision"): segment lengths are formed from the f64 hit
//! points with exact coordinate differences (`segment_length`), the far-field wavefront
//! projection n d·(x − reference) with exact differences and products ([`projection`]), sums
//! with Knuth's TwoSum, and differences of paths to the same point in double-double before they
//! are rounded to f64 cycles. The points themselves stay f64: by Fermat's principle the optical
//! length of an exact path is stationary, so their rounding along the surfaces changes a path
//! only to second order.
//!
//! The error-free transformations (Knuth's TwoSum, Dekker's TwoProd through the fused
//! multiply-add) and the double-double sum, product and square root follow Hida, Li and Bailey,
//! "Library for double-double and quad-double arithmetic" (2007), §2–3: relative error of a sum
//! or product ≤ 4·2⁻¹⁰⁶ ≈ 5e-32 (a few units of 2⁻¹⁰⁶), of the square root a few units more.

use glam::DVec3;
use std::ops::{Add, AddAssign, Div, Mul, Neg, Sub, SubAssign};

/// hi + lo, with hi = fl(hi + lo) (normalized). Units are the caller's (metres for paths).
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct DoubleDouble {
    /// The value rounded to f64.
    pub hi: f64,
    /// What rounding to f64 left out.
    pub lo: f64,
}

/// a + b exactly as hi + lo (Knuth's TwoSum; no condition on |a|, |b|).
#[inline(always)]
pub fn two_sum(a: f64, b: f64) -> DoubleDouble {
    let s = a + b;
    let bb = s - a;
    let e = (a - (s - bb)) + (b - bb);
    DoubleDouble { hi: s, lo: e }
}

/// a + b exactly when |a| ≥ |b| or a = 0 (Dekker's FastTwoSum).
#[inline(always)]
fn fast_two_sum(a: f64, b: f64) -> DoubleDouble {
    let s = a + b;
    DoubleDouble {
        hi: s,
        lo: b - (s - a),
    }
}

/// a − b exactly as hi + lo (TwoSum of a and −b): the exact difference of two coordinates.
#[inline(always)]
pub fn two_diff(a: f64, b: f64) -> DoubleDouble {
    two_sum(a, -b)
}

/// a·b exactly as hi + lo (TwoProd: the fused multiply-add returns the rounding error).
#[inline(always)]
pub fn two_prod(a: f64, b: f64) -> DoubleDouble {
    let p = a * b;
    DoubleDouble {
        hi: p,
        lo: a.mul_add(b, -p),
    }
}

impl DoubleDouble {
    /// Zero (both parts 0).
    pub const ZERO: DoubleDouble = DoubleDouble { hi: 0.0, lo: 0.0 };

    /// The f64 `x` exactly.
    #[inline(always)]
    pub const fn from_f64(x: f64) -> Self {
        DoubleDouble { hi: x, lo: 0.0 }
    }

    /// The value rounded to f64 (hi, since the pair is normalized).
    #[inline(always)]
    pub fn to_f64(self) -> f64 {
        self.hi + self.lo
    }

    /// |self|.
    #[inline]
    pub fn abs(self) -> Self {
        if self.hi < 0.0 || (self.hi == 0.0 && self.lo < 0.0) {
            -self
        } else {
            self
        }
    }

    /// self · b for an f64 `b` (Hida–Li–Bailey, double-double times double).
    #[inline(always)]
    pub fn mul_f64(self, b: f64) -> Self {
        let p = two_prod(self.hi, b);
        fast_two_sum(p.hi, self.lo.mul_add(b, p.lo))
    }

    /// The square root (one Newton step on the f64 root: Karp's method); 0 for 0.
    #[inline]
    pub fn sqrt(self) -> Self {
        if self.hi <= 0.0 {
            return DoubleDouble::ZERO;
        }
        // x = √hi; √(hi + lo) ≈ x + (hi + lo − x²)/(2x), the residual formed exactly.
        let x = self.hi.sqrt();
        let residual = (self - two_prod(x, x)).to_f64();
        fast_two_sum(x, residual / (2.0 * x))
    }
}

impl Div for DoubleDouble {
    type Output = DoubleDouble;
    /// self / b in double-double (long division: three f64 quotient digits, each remainder
    /// formed with [`DoubleDouble::mul_f64`]; relative error ~2⁻¹⁰⁴). `b` must not be 0.
    #[inline]
    fn div(self, b: DoubleDouble) -> DoubleDouble {
        let q1 = self.hi / b.hi;
        let r = self - b.mul_f64(q1);
        let q2 = r.hi / b.hi;
        let r = r - b.mul_f64(q2);
        let q3 = r.hi / b.hi;
        fast_two_sum(q1, q2) + q3
    }
}

impl DoubleDouble {
    /// a·b of two f64 vectors in double-double (exact products, summed in double-double).
    #[inline]
    pub fn dot(a: DVec3, b: DVec3) -> Self {
        two_prod(a.x, b.x) + two_prod(a.y, b.y) + two_prod(a.z, b.z)
    }
}

impl From<f64> for DoubleDouble {
    fn from(x: f64) -> Self {
        DoubleDouble::from_f64(x)
    }
}

impl Add for DoubleDouble {
    type Output = DoubleDouble;
    /// The accurate double-double sum (two TwoSums; relative error ≤ 2·2⁻¹⁰⁶ for sums without
    /// cancellation, and exact-difference quality for cancelling ones).
    #[inline(always)]
    fn add(self, b: DoubleDouble) -> DoubleDouble {
        let s = two_sum(self.hi, b.hi);
        let t = two_sum(self.lo, b.lo);
        let s = fast_two_sum(s.hi, s.lo + t.hi);
        fast_two_sum(s.hi, s.lo + t.lo)
    }
}

impl Add<f64> for DoubleDouble {
    type Output = DoubleDouble;
    #[inline(always)]
    fn add(self, b: f64) -> DoubleDouble {
        let s = two_sum(self.hi, b);
        fast_two_sum(s.hi, s.lo + self.lo)
    }
}

impl Neg for DoubleDouble {
    type Output = DoubleDouble;
    #[inline(always)]
    fn neg(self) -> DoubleDouble {
        DoubleDouble {
            hi: -self.hi,
            lo: -self.lo,
        }
    }
}

impl Sub for DoubleDouble {
    type Output = DoubleDouble;
    #[inline(always)]
    fn sub(self, b: DoubleDouble) -> DoubleDouble {
        self + (-b)
    }
}

impl Mul for DoubleDouble {
    type Output = DoubleDouble;
    /// The double-double product (relative error ≤ ~4·2⁻¹⁰⁶).
    #[inline(always)]
    fn mul(self, b: DoubleDouble) -> DoubleDouble {
        let p = two_prod(self.hi, b.hi);
        let lo = self.hi.mul_add(b.lo, self.lo * b.hi) + p.lo;
        fast_two_sum(p.hi, lo)
    }
}

impl Mul<f64> for DoubleDouble {
    type Output = DoubleDouble;
    #[inline(always)]
    fn mul(self, b: f64) -> DoubleDouble {
        self.mul_f64(b)
    }
}

impl AddAssign for DoubleDouble {
    #[inline(always)]
    fn add_assign(&mut self, b: DoubleDouble) {
        *self = *self + b;
    }
}

impl SubAssign for DoubleDouble {
    #[inline(always)]
    fn sub_assign(&mut self, b: DoubleDouble) {
        *self = *self - b;
    }
}

/// The exact coordinate differences b − a, each as a double-double.
#[inline(always)]
pub fn difference(a: DVec3, b: DVec3) -> [DoubleDouble; 3] {
    [two_diff(b.x, a.x), two_diff(b.y, a.y), two_diff(b.z, a.z)]
}

/// |b − a| (m) in double-double for the f64 points `a`, `b`: the coordinate differences are
/// exact, their squares and sum double-double, so the length of a 100 m segment keeps ~1e-30 m
/// (relative ~1e-31), far below what rounding the points themselves does to a path.
#[inline]
pub fn segment_length(a: DVec3, b: DVec3) -> DoubleDouble {
    // Each square (h + l)² = TwoProd(h, h) + 2hl (l² < 2⁻¹⁰⁶ h² is below the format); the three
    // are positive, so the sum needs no cancellation-proof addition: two TwoSums of the high
    // parts, the low parts added in f64 (relative error a few 2⁻¹⁰⁴).
    let square = |x: DoubleDouble| {
        let p = two_prod(x.hi, x.hi);
        (p.hi, p.lo + 2.0 * x.hi * x.lo)
    };
    let [dx, dy, dz] = difference(a, b);
    let ((x, xl), (y, yl), (z, zl)) = (square(dx), square(dy), square(dz));
    let s = two_sum(x, y);
    let t = two_sum(s.hi, z);
    fast_two_sum(t.hi, t.lo + s.lo + xl + yl + zl).sqrt()
}

/// d·(x − reference)/|d| in double-double for the f64 vectors `d` (a ray direction), `x`
/// and `reference`: the signed distance of `x` ahead of the plane through `reference`
/// perpendicular to `d` — the far-field wavefront projection (times −n it is the optical path
/// from `x` to the wavefront through `reference`, docs/PHYSICS.md §5 Airy: equal paths to the lens
/// focus), and the phase of a plane wave at `x` (times n). The differences are exact and the
/// products and sum double-double, so a reference 100 m away costs nothing.
///
/// The division by |d| (in double-double) matters: an f64 "unit" vector is unit only to
/// ~1e-16, and a plate near its critical angle walks the exit points of successive Airy orders
/// 0.26 m apart, so the projection through an unnormalized d was off by ~1e-17 m per round trip
/// of ΔS = 3.7e-11 m, 4e-7 of the round-trip phase (fuzz `airy` seed 1 scene 114: T 8.8e-7 off
/// 50 digits; docs/PHYSICS.md §8).
#[inline]
pub fn projection(d: DVec3, x: DVec3, reference: DVec3) -> DoubleDouble {
    let [dx, dy, dz] = difference(reference, x);
    let p = dx * d.x + dy * d.y + dz * d.z;
    let norm2 = DoubleDouble::dot(d, d);
    if norm2.hi == 1.0 && norm2.lo == 0.0 {
        p
    } else {
        p / norm2.sqrt()
    }
}
