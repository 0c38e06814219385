//! 8-bit sRGB pictures: display of rendered intensities and XYZ, PNG encoding, and the
//! difference statistics and histogram-stretched difference image of the paper's Fig. 8.
//!
//! Display conventions (stated in the report next to every picture):
//! - **Monochrome** images are drawn in the hue of their wavelength
//!   ([`crate::colour::wavelength_to_srgb_hue`], brightest channel 1), linear value
//!   I / I_scale, then clipped and sRGB-encoded; I_scale is the brightest pixel unless a common
//!   scale is given, so the brightest fringe is full scale.
//! - **Colour** images: XYZ × exposure → [`crate::colour::xyz_to_srgb8`] (adaptation, IEC
//!   matrix, clip, transfer curve); the exposure makes the brightest Y of the image (or of a
//!   set of images shown together) equal 1.

use crate::colour::{self, Adaptation, Illuminant};
use rayon::prelude::*;

/// An 8-bit sRGB picture, row-major, row 0 at the top.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Rgb8Image {
    pub width: usize,
    pub height: usize,
    pub pixels: Vec<[u8; 3]>,
}

impl Rgb8Image {
    /// A black picture.
    pub fn new(width: usize, height: usize) -> Self {
        Rgb8Image {
            width,
            height,
            pixels: vec![[0; 3]; width * height],
        }
    }

    /// Pixel (`x`, `y`) (column, row).
    pub fn at(&self, x: usize, y: usize) -> [u8; 3] {
        self.pixels[y * self.width + x]
    }

    /// This one-row picture repeated `height` times (a line probe drawn as a strip).
    pub(crate) fn extrude(&self, height: usize) -> Rgb8Image {
        let row = &self.pixels[..self.width];
        Rgb8Image {
            width: self.width,
            height,
            pixels: (0..height).flat_map(|_| row.iter().copied()).collect(),
        }
    }

    /// The picture as a PNG file (8-bit RGB, tagged sRGB), compressed with the encoder's `Fast`
    /// setting: the same pixels, a larger file, and the deflate no longer a serial tenth of a
    /// 900×900 render's CPU.
    pub fn png(&self) -> Result<Vec<u8>, String> {
        encode_png_with(
            self.width,
            self.height,
            &self.pixels,
            Some(png::Compression::Fast),
        )
    }
}

/// Encode 8-bit sRGB pixels (row-major) as a PNG file with the given compression (`None`: the
/// encoder's defaults); pictures ([`Rgb8Image::png`]) and report plots use `Fast`.
pub(crate) fn encode_png_with(
    width: usize,
    height: usize,
    pixels: &[[u8; 3]],
    compression: Option<png::Compression>,
) -> Result<Vec<u8>, String> {
    if pixels.len() != width * height || width == 0 || height == 0 {
        return Err(format!(
            "encode_png: {} pixels for a {width}x{height} picture",
            pixels.len()
        ));
    }
    let flat: Vec<u8> = pixels.iter().flatten().copied().collect();
    encode_rgb_bytes(width, height, &flat, compression)
}

/// [`encode_png_with`] of pixels already laid out as R, G, B bytes, row-major (a bitmap
/// backend's buffer), without a copy of them.
pub(crate) fn encode_rgb_bytes(
    width: usize,
    height: usize,
    rgb: &[u8],
    compression: Option<png::Compression>,
) -> Result<Vec<u8>, String> {
    if rgb.len() != 3 * width * height || width == 0 || height == 0 {
        return Err(format!(
            "encode_png: {} bytes for a {width}x{height} RGB picture",
            rgb.len()
        ));
    }
    let mut out = Vec::new();
    {
        let mut enc = png::Encoder::new(&mut out, width as u32, height as u32);
        enc.set_color(png::ColorType::Rgb);
        enc.set_depth(png::BitDepth::Eight);
        enc.set_source_srgb(png::SrgbRenderingIntent::Perceptual);
        if let Some(c) = compression {
            enc.set_compression(c);
        }
        let mut w = enc.write_header().map_err(|e| e.to_string())?;
        w.write_image_data(rgb).map_err(|e| e.to_string())?;
        w.finish().map_err(|e| e.to_string())?;
    }
    Ok(out)
}

/// Decode an 8-bit RGB PNG (as written by [`Rgb8Image::png`]); for tests and checks.
pub fn decode_png(bytes: &[u8]) -> Result<Rgb8Image, String> {
    let dec = png::Decoder::new(std::io::Cursor::new(bytes));
    let mut reader = dec.read_info().map_err(|e| e.to_string())?;
    let mut buf = vec![0; reader.output_buffer_size().ok_or("PNG too large")?];
    let info = reader.next_frame(&mut buf).map_err(|e| e.to_string())?;
    let (w, h) = (info.width as usize, info.height as usize);
    let channels = match (info.color_type, info.bit_depth) {
        (png::ColorType::Rgb, png::BitDepth::Eight) => 3,
        (png::ColorType::Rgba, png::BitDepth::Eight) => 4,
        other => return Err(format!("decode_png: unsupported PNG format {other:?}")),
    };
    let pixels = buf[..w * h * channels]
        .chunks_exact(channels)
        .map(|c| [c[0], c[1], c[2]])
        .collect();
    Ok(Rgb8Image {
        width: w,
        height: h,
        pixels,
    })
}

/// Largest finite value of `values` (0 if none is positive).
pub fn peak(values: &[f64]) -> f64 {
    values
        .iter()
        .copied()
        .filter(|v| v.is_finite())
        .fold(0.0, f64::max)
}

/// A monochrome intensity image in the hue of `lambda_m`: linear RGB = hue · I / `scale`,
/// clipped and sRGB-encoded. `scale` ≤ 0 gives black.
pub fn monochrome(
    width: usize,
    height: usize,
    intensity: &[f64],
    lambda_m: f64,
    scale: f64,
) -> Rgb8Image {
    let hue = colour::wavelength_to_srgb_hue(lambda_m);
    let pixels = intensity
        .par_iter()
        .map(|&i| {
            let t = if scale > 0.0 { i / scale } else { 0.0 };
            colour::to_srgb8(hue.map(|h| h * t))
        })
        .collect();
    Rgb8Image {
        width,
        height,
        pixels,
    }
}

/// A colour image: XYZ × `exposure` through [`colour::xyz_to_srgb8`].
pub fn colour(
    width: usize,
    height: usize,
    xyz: &[[f64; 3]],
    exposure: f64,
    illuminant: Illuminant,
    adaptation: Adaptation,
) -> Rgb8Image {
    let pixels = xyz
        .par_iter()
        .map(|p| colour::xyz_to_srgb8(p.map(|c| c * exposure), illuminant, adaptation).srgb8)
        .collect();
    Rgb8Image {
        width,
        height,
        pixels,
    }
}

/// The exposure that maps the largest Y of `images` to 1 (1 if all are black).
pub(crate) fn exposure_for_peak_y<'a>(images: impl IntoIterator<Item = &'a [[f64; 3]]>) -> f64 {
    let y = images
        .into_iter()
        .flat_map(|im| im.iter().map(|p| p[1]))
        .filter(|y| y.is_finite())
        .fold(0.0, f64::max);
    if y > 0.0 { 1.0 / y } else { 1.0 }
}

/// Difference statistics of two 8-bit pictures of equal size, as the paper reports them for its
/// Fig. 7 (left vs right). Positions are (column, row), 0-based, row 0 at the top; ties keep the
/// first pixel in row-major order.
#[derive(Clone, Debug, PartialEq, Eq, serde::Serialize, serde::Deserialize)]
pub struct DiffStats {
    pub width: usize,
    pub height: usize,
    /// Total number of pixels.
    pub pixels: usize,
    /// Pixels whose (r, g, b) differ in at least one channel.
    pub differing: usize,
    /// Largest |Δr| + |Δg| + |Δb| and where.
    pub max_sum: u32,
    pub max_sum_at: (usize, usize),
    /// Largest single-channel |Δ| and where.
    pub max_channel: u8,
    pub max_channel_at: (usize, usize),
}

/// [`DiffStats`] of `a` against `b`. Errors if the sizes differ.
pub fn diff_stats(a: &Rgb8Image, b: &Rgb8Image) -> Result<DiffStats, String> {
    if (a.width, a.height) != (b.width, b.height) {
        return Err(format!(
            "diff_stats: {}x{} vs {}x{} pictures",
            a.width, a.height, b.width, b.height
        ));
    }
    let mut s = DiffStats {
        width: a.width,
        height: a.height,
        pixels: a.pixels.len(),
        differing: 0,
        max_sum: 0,
        max_sum_at: (0, 0),
        max_channel: 0,
        max_channel_at: (0, 0),
    };
    for (k, (p, q)) in a.pixels.iter().zip(&b.pixels).enumerate() {
        let d: [u8; 3] = std::array::from_fn(|c| p[c].abs_diff(q[c]));
        if d == [0; 3] {
            continue;
        }
        s.differing += 1;
        let at = (k % a.width, k / a.width);
        let sum = d.iter().map(|&x| u32::from(x)).sum::<u32>();
        if sum > s.max_sum {
            s.max_sum = sum;
            s.max_sum_at = at;
        }
        let m = d.iter().copied().max().unwrap_or(0);
        if m > s.max_channel {
            s.max_channel = m;
            s.max_channel_at = at;
        }
    }
    Ok(s)
}

/// The histogram-stretched difference image (paper Fig. 8): per channel |a − b| (8-bit values)
/// mapped linearly from [0, max over the image and channels] to [0, 255]. An all-zero
/// difference stays black. Returns the picture and the stretch factor 255 / max.
pub fn stretched_difference(a: &Rgb8Image, b: &Rgb8Image) -> Result<(Rgb8Image, f64), String> {
    let s = diff_stats(a, b)?;
    let factor = if s.max_channel > 0 {
        255.0 / f64::from(s.max_channel)
    } else {
        1.0
    };
    let pixels = a
        .pixels
        .iter()
        .zip(&b.pixels)
        .map(|(p, q)| {
            std::array::from_fn(|c| {
                (f64::from(p[c].abs_diff(q[c])) * factor).round().min(255.0) as u8
            })
        })
        .collect();
    Ok((
        Rgb8Image {
            width: a.width,
            height: a.height,
            pixels,
        },
        factor,
    ))
}
