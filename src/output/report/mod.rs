//! Outputs of a check: the verdict table as text, the HTML report, plots and pictures. The
//! verdict's data (rows, golden files, CSV profiles, the JSON summary) is
//! [`crate::harness::verdict`]; files are written through [`crate::io`].

pub mod html;
pub mod image;
pub mod plot;
pub mod renderers;
pub mod tradeoff_plot;

use crate::harness::verdict::Row;
use std::fmt::Write as _;

/// Print rows as an aligned table.
pub fn table(rows: &[Row]) -> String {
    let mut s = String::new();
    let _ = writeln!(
        s,
        "{:<26} {:<19} {:<22} {:>10} {:>10} {:>9} {:<7} {:>8}",
        "case", "fidelity", "metric", "max|dev|", "rms dev", "tol", "verdict", "seconds"
    );
    for r in rows {
        let verdict = match r.pass {
            Some(true) => "pass",
            Some(false) => "FAIL",
            None => "info",
        };
        let tol = r
            .tolerance
            .map(|t| format!("{t:.0e}"))
            .unwrap_or_else(|| "-".into());
        let _ = writeln!(
            s,
            "{:<26} {:<19} {:<22} {:>10.3e} {:>10.3e} {:>9} {:<7} {:>8.3}",
            r.case, r.fidelity, r.metric, r.max_abs_dev, r.rms_dev, tol, verdict, r.seconds
        );
    }
    s
}
