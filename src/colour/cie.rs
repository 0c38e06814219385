//! CIE tables: the 1931 2° colour matching functions and the illuminants E and D65, read
//! from the shipped tables (`data/cie1931_2deg.csv`, `data/cie_d65.csv`).

use super::*;
use std::sync::OnceLock;

/// CIE 1931 2° colour matching functions, 360–830 nm at 1 nm (CIE 15:2004 Table T.4).
const CIE1931_2DEG_CSV: &str = include_str!("../../data/cie1931_2deg.csv");
/// CIE standard illuminant D65 relative SPD, 360–830 nm at 1 nm (CIE 15:2004 Table T.1).
const CIE_D65_CSV: &str = include_str!("../../data/cie_d65.csv");

/// First wavelength of the shipped tables, in nanometres.
pub(super) const TABLE_START_NM: f64 = 360.0;
/// Last wavelength of the shipped tables, in nanometres.
pub(super) const TABLE_END_NM: f64 = 830.0;
/// Number of 1 nm rows in each shipped table (360..=830 nm).
pub(super) const TABLE_ROWS: usize = 471;
/// Nanometres per metre.
pub(super) const NM_PER_M: f64 = 1e9;

/// A table sampled every 1 nm from [`TABLE_START_NM`] to [`TABLE_END_NM`], `N` values per row.
pub(super) struct Table1nm<const N: usize> {
    rows: Vec<[f64; N]>,
}

impl<const N: usize> Table1nm<N> {
    /// Parses the columns `columns` (by header name) of a CSV whose first column is
    /// `lambda_nm`; lines starting with '#' are comments. Panics on malformed shipped data
    /// (the data is compiled in, and a test reads every table).
    pub(super) fn parse(csv: &str, columns: [&str; N]) -> Self {
        let mut reader = csv::ReaderBuilder::new()
            .comment(Some(b'#'))
            .from_reader(csv.as_bytes());
        let header = reader.headers().expect("table has a header").clone();
        assert_eq!(&header[0], "lambda_nm", "first column must be lambda_nm");
        let index = columns.map(|name| {
            header
                .iter()
                .position(|h| h == name)
                .unwrap_or_else(|| panic!("table has no column {name}"))
        });
        let rows: Vec<[f64; N]> = reader
            .records()
            .enumerate()
            .map(|(row, record)| {
                let fields = record.expect("table rows are CSV records of one length");
                let lambda_nm: f64 = fields[0].parse().expect("lambda_nm is a number");
                assert_eq!(
                    lambda_nm,
                    TABLE_START_NM + row as f64,
                    "table must be 1 nm steps"
                );
                index.map(|c| fields[c].parse().expect("table value is a number"))
            })
            .collect();
        assert_eq!(rows.len(), TABLE_ROWS, "table must cover 360..=830 nm");
        Table1nm { rows }
    }

    /// Linear interpolation at `lambda_m` (metres); zero outside 360–830 nm.
    pub(super) fn at(&self, lambda_m: f64) -> [f64; N] {
        // Positions within 1e-6 nm of the table ends count as the ends (metre→nm rounding).
        const END_SLACK_NM: f64 = 1e-6;
        let x = lambda_m * NM_PER_M - TABLE_START_NM;
        let span = TABLE_END_NM - TABLE_START_NM;
        if !(x >= -END_SLACK_NM && x <= span + END_SLACK_NM) {
            return [0.0; N];
        }
        let x = x.clamp(0.0, span);
        let i = (x.floor() as usize).min(TABLE_ROWS - 2);
        let t = x - i as f64;
        let (a, b) = (self.rows[i], self.rows[i + 1]);
        std::array::from_fn(|c| (1.0 - t) * a[c] + t * b[c])
    }
}

/// The CIE 1931 2° standard observer colour matching functions x̄, ȳ, z̄ (dimensionless,
/// ȳ(555 nm) = 1), from CIE 15:2004 Table T.4 at 1 nm, 360–830 nm.
///
/// Values between table rows are linearly interpolated; outside 360–830 nm they are zero.
pub struct Cmf {
    table: Table1nm<3>,
}

impl Cmf {
    /// The shared, parsed CIE 1931 2° table (parsed once on first use).
    pub fn cie1931_2deg() -> &'static Cmf {
        static CMF: OnceLock<Cmf> = OnceLock::new();
        CMF.get_or_init(|| Cmf {
            table: Table1nm::parse(CIE1931_2DEG_CSV, ["xbar", "ybar", "zbar"]),
        })
    }

    /// [x̄, ȳ, z̄] at the vacuum wavelength `lambda_m` (metres).
    pub fn xyz_bar(&self, lambda_m: f64) -> [f64; 3] {
        self.table.at(lambda_m)
    }

    /// x̄ at `lambda_m` (metres).
    pub fn xbar(&self, lambda_m: f64) -> f64 {
        self.xyz_bar(lambda_m)[0]
    }

    /// ȳ (the photopic luminous efficiency V(λ)) at `lambda_m` (metres).
    pub fn ybar(&self, lambda_m: f64) -> f64 {
        self.xyz_bar(lambda_m)[1]
    }

    /// z̄ at `lambda_m` (metres).
    pub fn zbar(&self, lambda_m: f64) -> f64 {
        self.xyz_bar(lambda_m)[2]
    }
}

/// A CIE illuminant: the spectral power distribution lighting the scene.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Illuminant {
    /// Equal-energy illuminant E: S(λ) = 1 at every wavelength; white point (1, 1, 1).
    E,
    /// CIE standard illuminant D65 (average daylight, CCT ≈ 6504 K), S(560 nm) = 100
    /// (CIE 15:2004 Table T.1); the white point of sRGB.
    D65,
}

impl Illuminant {
    /// XYZ of a perfect reflector under this illuminant, Y = 1: [`WHITE_E`] or [`WHITE_D65`].
    pub fn white_xyz(self) -> [f64; 3] {
        match self {
            Illuminant::E => WHITE_E,
            Illuminant::D65 => WHITE_D65,
        }
    }

    /// The adaptation fringe uses unless told otherwise: Bradford for E (so a white object
    /// looks white on an sRGB display), none for D65 (already the sRGB white).
    pub fn default_adaptation(self) -> Adaptation {
        match self {
            Illuminant::E => Adaptation::Bradford,
            Illuminant::D65 => Adaptation::None,
        }
    }

    /// Short name for reports and CSV comments: "E" or "D65".
    pub fn name(self) -> &'static str {
        match self {
            Illuminant::E => "E",
            Illuminant::D65 => "D65",
        }
    }
}

/// Relative spectral power S(λ) of `illuminant` at `lambda_m` (metres), dimensionless.
///
/// E: 1 everywhere. D65: CIE 15:2004 Table T.1 normalised to S(560 nm) = 100, linearly
/// interpolated, held at its 780 nm value up to 830 nm (as in `data/cie_d65.csv`), and zero
/// outside 360–830 nm (where the colour matching functions are zero anyway).
pub fn illuminant_spd(illuminant: Illuminant, lambda_m: f64) -> f64 {
    match illuminant {
        Illuminant::E => 1.0,
        Illuminant::D65 => {
            static D65: OnceLock<Table1nm<1>> = OnceLock::new();
            D65.get_or_init(|| Table1nm::parse(CIE_D65_CSV, ["S_D65"]))
                .at(lambda_m)[0]
        }
    }
}
