//! XYZ → sRGB: white points, the IEC 61966-2-1 matrix, Bradford adaptation, the transfer
//! curve, 8-bit pixels, and the display hue of a wavelength.

use super::*;

/// White point of illuminant E, Y = 1: (1, 1, 1).
pub const WHITE_E: [f64; 3] = [1.0, 1.0, 1.0];

/// White point of D65 for the CIE 1931 2° observer, Y = 1: (0.95047, 1, 1.08883)
/// (ASTM E308, from the CIE D65 table; CIE 15:2004 Table T.3 rounds it to 95.04, 100, 108.88).
pub const WHITE_D65: [f64; 3] = [0.95047, 1.0, 1.08883];

/// XYZ (D65, Y = 1) → linear sRGB, IEC 61966-2-1:1999 §5.2 (the standard's 4-decimal matrix,
/// also used by colour-science).
pub const XYZ_TO_LINEAR_SRGB: [[f64; 3]; 3] = [
    [3.2406, -1.5372, -0.4986],
    [-0.9689, 1.8758, 0.0415],
    [0.0557, -0.2040, 1.0570],
];

/// Bradford cone-response matrix M_BFD (Lam 1985; Hunt, *The Reproduction of Colour*, and
/// CIE 160:2004 use the same numbers).
pub const BRADFORD: [[f64; 3]; 3] = [
    [0.8951, 0.2664, -0.1614],
    [-0.7502, 1.7135, 0.0367],
    [0.0389, -0.0685, 1.0296],
];

/// Inverse of [`BRADFORD`] to 7 decimals (as tabulated by B. Lindbloom, "Chromatic Adaptation").
pub const BRADFORD_INVERSE: [[f64; 3]; 3] = [
    [0.9869929, -0.1470543, 0.1599627],
    [0.4323053, 0.5183603, 0.0492912],
    [-0.0085287, 0.0400428, 0.9684867],
];

/// Chromatic adaptation applied before the XYZ → sRGB matrix.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Adaptation {
    /// Bradford von Kries transform from the illuminant's white to the D65 white
    /// ([`bradford_adapt`]); the identity under D65.
    Bradford,
    /// No adaptation: XYZ goes straight into the sRGB matrix (an E white shows pinkish).
    None,
}

impl Adaptation {
    /// Short name for reports and CSV comments: "Bradford" or "none".
    pub fn name(self) -> &'static str {
        match self {
            Adaptation::Bradford => "Bradford",
            Adaptation::None => "none",
        }
    }
}

/// m · v for a 3×3 matrix.
fn mat3_mul_vec(m: &[[f64; 3]; 3], v: [f64; 3]) -> [f64; 3] {
    std::array::from_fn(|r| m[r][0] * v[0] + m[r][1] * v[1] + m[r][2] * v[2])
}

/// XYZ (D65-referred, Y = 1 for white) → linear sRGB, IEC 61966-2-1:1999 eq. (5.2) with
/// [`XYZ_TO_LINEAR_SRGB`]. Not clipped: out-of-gamut colours give components < 0 or > 1.
pub fn xyz_to_linear_srgb(xyz: [f64; 3]) -> [f64; 3] {
    mat3_mul_vec(&XYZ_TO_LINEAR_SRGB, xyz)
}

/// Bradford chromatic adaptation (von Kries scaling in the Bradford cone space):
///
/// ```text
/// XYZ_out = M⁻¹ · diag(ρ_to / ρ_from) · M · XYZ,   ρ = M · XYZ_white,   M = BRADFORD
/// ```
///
/// `from_white`, `to_white`: XYZ of the source and destination whites (any common scale).
/// Maps `from_white` onto `to_white`.
pub fn bradford_adapt(xyz: [f64; 3], from_white: [f64; 3], to_white: [f64; 3]) -> [f64; 3] {
    let rho_from = mat3_mul_vec(&BRADFORD, from_white);
    let rho_to = mat3_mul_vec(&BRADFORD, to_white);
    let cone = mat3_mul_vec(&BRADFORD, xyz);
    let scaled = std::array::from_fn(|c| cone[c] * rho_to[c] / rho_from[c]);
    mat3_mul_vec(&BRADFORD_INVERSE, scaled)
}

/// XYZ seen under `illuminant` → D65-referred XYZ ready for the sRGB matrix, using
/// `adaptation` (Bradford from the illuminant's white point to [`WHITE_D65`], or none).
pub fn adapt_to_d65(xyz: [f64; 3], illuminant: Illuminant, adaptation: Adaptation) -> [f64; 3] {
    match (illuminant, adaptation) {
        (Illuminant::D65, _) | (_, Adaptation::None) => xyz,
        (Illuminant::E, Adaptation::Bradford) => bradford_adapt(xyz, WHITE_E, WHITE_D65),
    }
}

/// The sRGB transfer curve (IEC 61966-2-1:1999 eq. (5.3)) of a linear value, after clipping it
/// to [0, 1]:
///
/// ```text
/// V = 12.92 L                    for L ≤ 0.0031308
/// V = 1.055 L^(1/2.4) − 0.055    otherwise
/// ```
pub fn srgb_encode(linear: f64) -> f64 {
    let l = linear.clamp(0.0, 1.0);
    if l <= 0.0031308 {
        12.92 * l
    } else {
        1.055 * l.powf(1.0 / 2.4) - 0.055
    }
}

/// Inverse of [`srgb_encode`] on [0, 1] (IEC 61966-2-1:1999 eq. (5.1)): V ≤ 0.04045 → V/12.92,
/// else ((V + 0.055)/1.055)^2.4. The input is clipped to [0, 1].
pub fn srgb_decode(encoded: f64) -> f64 {
    let v = encoded.clamp(0.0, 1.0);
    if v <= 0.04045 {
        v / 12.92
    } else {
        ((v + 0.055) / 1.055).powf(2.4)
    }
}

/// Linear sRGB → 8-bit sRGB: clip to [0, 1], [`srgb_encode`], round(255 V); a NaN gives 0.
///
/// Without a `powf` per channel: the code round(255 V(L)) steps up by one at each of 255
/// thresholds of L, so the code of L is the number of thresholds at or below L, found by
/// binary search in [`srgb8_thresholds`] (8 comparisons). Same bytes as [`to_srgb8_powf`]
/// wherever that reference path is non-decreasing in L: each threshold is the smallest f64 at
/// which it reaches the code. Tests `colour_srgb8::` check that path steps up exactly at each
/// threshold (±64 ulps around each) and compare both on 4 M random values and the special
/// values; renders are byte-identical.
pub fn to_srgb8(linear_srgb: [f64; 3]) -> [u8; 3] {
    let thresholds = srgb8_thresholds();
    // A NaN is at or above no threshold: code 0, as `NaN as u8` in the reference path.
    linear_srgb.map(|l| thresholds.partition_point(|&t| t <= l) as u8)
}

/// The reference 8-bit conversion: round(255 · [`srgb_encode`]\(L)) per channel, a `powf` each
/// (`NaN as u8` is 0). [`to_srgb8`] gives the same bytes from a table.
pub fn to_srgb8_powf(linear_srgb: [f64; 3]) -> [u8; 3] {
    linear_srgb.map(code_powf)
}

/// One channel of [`to_srgb8_powf`].
fn code_powf(l: f64) -> u8 {
    (255.0 * srgb_encode(l)).round() as u8
}

/// The 255 thresholds of the 8-bit code, increasing: entry k − 1 is the smallest f64 L in
/// [0, 1] whose code round(255 · [`srgb_encode`]\(L)) is at least k, found once by bisection on
/// the bit patterns of [0, 1] (ordered like the values) with the `powf` path itself; it lies
/// within rounding of the exact curve's [`srgb_decode`]((k − ½)/255) (IEC 61966-2-1 eq. (5.1)).
pub fn srgb8_thresholds() -> &'static [f64; 255] {
    static THRESHOLDS: std::sync::OnceLock<[f64; 255]> = std::sync::OnceLock::new();
    THRESHOLDS.get_or_init(|| {
        std::array::from_fn(|i| {
            let k = i as u8 + 1;
            // code(lo) < k ≤ code(hi): code(0) = 0, code(1) = 255.
            let (mut lo, mut hi) = (0.0f64.to_bits(), 1.0f64.to_bits());
            while hi - lo > 1 {
                let mid = lo + (hi - lo) / 2;
                if code_powf(f64::from_bits(mid)) >= k {
                    hi = mid;
                } else {
                    lo = mid;
                }
            }
            f64::from_bits(hi)
        })
    })
}

/// An XYZ colour on an sRGB display, with the choices that produced it.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct SrgbPixel {
    /// Linear sRGB after adaptation, **before** clipping (may lie outside [0, 1]).
    pub linear_srgb: [f64; 3],
    /// 8-bit sRGB after clipping and the transfer curve.
    pub srgb8: [u8; 3],
    /// How far the furthest channel lay outside [0, 1] before clipping (0 = in gamut).
    pub clip_excess: f64,
    /// Illuminant the XYZ was computed under.
    pub illuminant: Illuminant,
    /// Adaptation applied before the sRGB matrix.
    pub adaptation: Adaptation,
}

impl SrgbPixel {
    /// True if any channel had to be clipped (strictly outside [0, 1]). Strict on purpose:
    /// even the perfect reflector under D65 exceeds 1 by 7.5e-5 in G (4-decimal IEC matrix),
    /// so compare [`Self::clip_excess`](SrgbPixel::clip_excess) with a tolerance where that matters.
    pub fn clipped(&self) -> bool {
        self.clip_excess > 0.0
    }
}

/// How far the furthest component of `linear` lies outside [0, 1] (0 if none does).
fn clip_excess(linear: [f64; 3]) -> f64 {
    linear
        .iter()
        .map(|&l| (-l).max(l - 1.0).max(0.0))
        .fold(0.0, f64::max)
}

/// XYZ under `illuminant` (Y = 1 for the perfect reflector) → 8-bit sRGB: [`adapt_to_d65`],
/// [`xyz_to_linear_srgb`], clip, [`srgb_encode`]. The result says whether it clipped and which
/// illuminant and adaptation were used.
pub fn xyz_to_srgb8(xyz: [f64; 3], illuminant: Illuminant, adaptation: Adaptation) -> SrgbPixel {
    let linear_srgb = xyz_to_linear_srgb(adapt_to_d65(xyz, illuminant, adaptation));
    SrgbPixel {
        linear_srgb,
        srgb8: to_srgb8(linear_srgb),
        clip_excess: clip_excess(linear_srgb),
        illuminant,
        adaptation,
    }
}

/// Display colour (linear sRGB, brightest channel = 1) of monochromatic light of vacuum
/// wavelength `lambda_m` (metres), to tint a monochrome image "in the hue of its wavelength".
///
/// Method: XYZ = (x̄, ȳ, z̄)(λ) (CIE 1931 2°, no illuminant: the light is the source),
/// linear sRGB by the IEC 61966-2-1 matrix, negative components (spectral colours lie outside
/// the sRGB gamut) set to 0, then divided by the largest component. This keeps the dominant
/// hue but desaturates towards the gamut edge; it is a display convention, not colorimetry.
/// Returns [0, 0, 0] where no channel is positive (outside 360–830 nm).
pub fn wavelength_to_srgb_hue(lambda_m: f64) -> [f64; 3] {
    let linear = xyz_to_linear_srgb(Cmf::cie1931_2deg().xyz_bar(lambda_m)).map(|c| c.max(0.0));
    let peak = linear.iter().copied().fold(0.0, f64::max);
    if peak > 0.0 {
        linear.map(|c| c / peak)
    } else {
        [0.0; 3]
    }
}
