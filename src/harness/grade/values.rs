//! Value files: another tracer's values at a case's probes.
//!
//! ```text
//! quantity,coordinate,value
//! reflectance,0,0.04
//! reflectance,0.5,0.0401
//! …
//! ```
//!
//! One row per quantity and probe coordinate, quantities in the order of the pack
//! (`values_exact.csv` of `fringe export` is a complete example), coordinates in the probe's
//! order and unit, values finite and in the observable's unit. Lines starting with `#` and blank
//! lines are ignored. Every error names the line and column (1-based) and what is allowed.

use super::Quantity;

/// An error in a value file: line and column (1-based) and what is wrong.
#[derive(Clone, Debug, PartialEq)]
pub struct ValuesError {
    pub line: usize,
    pub column: usize,
    pub message: String,
}

impl std::fmt::Display for ValuesError {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(
            f,
            "line {}, column {}: {}",
            self.line, self.column, self.message
        )
    }
}

/// The header every value file starts with.
pub(crate) const HEADER: &str = "quantity,coordinate,value";

/// Coordinates must match the probe's to this relative precision (they are written with 17
/// significant digits; a tracer's own rounding of the sweep is allowed).
pub(crate) const COORDINATE_TOLERANCE: f64 = 1e-9;

/// Write `values` (one vector per quantity) as a value file.
pub(crate) fn to_csv(quantities: &[Quantity], values: &[Vec<f64>]) -> String {
    let rows = quantities.iter().zip(values).flat_map(|(q, v)| {
        q.coordinates
            .iter()
            .zip(v)
            .map(|(x, y)| vec![q.name.clone(), format!("{x:.17e}"), format!("{y:.17e}")])
    });
    crate::io::csv_text(&HEADER.split(',').collect::<Vec<_>>(), rows)
}

/// Parse a value file against the quantities it must supply; returns one vector per quantity.
pub fn parse(text: &str, quantities: &[Quantity]) -> Result<Vec<Vec<f64>>, ValuesError> {
    let err = |line: usize, column: usize, message: String| ValuesError {
        line,
        column,
        message,
    };
    let expected_rows: Vec<(usize, usize)> = quantities
        .iter()
        .enumerate()
        .flat_map(|(qi, q)| (0..q.coordinates.len()).map(move |k| (qi, k)))
        .collect();
    let mut out: Vec<Vec<f64>> = quantities.iter().map(|_| Vec::new()).collect();
    let mut header_seen = false;
    let mut next = 0usize;
    let last_line = text.lines().count();
    // Read by the `csv` crate (quoted fields, CRLF); comment and blank lines are skipped here.
    let mut reader = csv::ReaderBuilder::new()
        .has_headers(false)
        .flexible(true)
        .comment(Some(b'#'))
        .from_reader(text.as_bytes());
    let mut record = csv::StringRecord::new();
    loop {
        match reader.read_record(&mut record) {
            Ok(true) => {}
            Ok(false) => break,
            Err(e) => {
                let line = e.position().map_or(last_line, |p| p.line() as usize);
                return Err(err(line, 1, format!("not CSV text: {e}")));
            }
        }
        let line = record.position().map_or(last_line, |p| p.line() as usize);
        let fields: Vec<&str> = record.iter().collect();
        let l = fields.join(",");
        if fields.iter().all(|f| f.trim().is_empty()) || fields[0].trim_start().starts_with('#') {
            continue;
        }
        if !header_seen {
            if !fields.iter().map(|f| f.trim()).eq(HEADER.split(',')) {
                return Err(err(
                    line,
                    1,
                    format!("expected the header `{HEADER}`, got {l:?}"),
                ));
            }
            header_seen = true;
            continue;
        }
        if fields.len() != 3 {
            return Err(err(
                line,
                fields.len().min(3) + 1,
                format!(
                    "expected 3 comma-separated fields `{HEADER}`, got {} in {l:?}",
                    fields.len()
                ),
            ));
        }
        let Some(&(qi, k)) = expected_rows.get(next) else {
            let total: usize = quantities.iter().map(|q| q.coordinates.len()).sum();
            return Err(err(
                line,
                1,
                format!(
                    "more rows than probe values: the case has {total} ({})",
                    summary(quantities)
                ),
            ));
        };
        let q = &quantities[qi];
        let name = fields[0].trim();
        if name != q.name {
            let have = out[qi].len();
            return Err(err(
                line,
                1,
                if quantities.iter().any(|x| x.name == name) && have < q.coordinates.len() {
                    format!(
                        "quantity {name:?} where value {} of {} of {:?} is due (wrong count of {:?} rows)",
                        have + 1,
                        q.coordinates.len(),
                        q.name,
                        q.name
                    )
                } else {
                    format!(
                        "expected quantity {:?}, got {name:?}; allowed: {}",
                        q.name,
                        summary(quantities)
                    )
                },
            ));
        }
        let number = |col: usize, what: &str| -> Result<f64, ValuesError> {
            let f = fields[col - 1].trim();
            match f.parse::<f64>() {
                Ok(v) if v.is_finite() => Ok(v),
                Ok(_) => Err(err(
                    line,
                    col,
                    format!("{what} must be a finite number, got {f:?}"),
                )),
                Err(_) => Err(err(
                    line,
                    col,
                    format!("{what} must be a number, got {f:?}"),
                )),
            }
        };
        let x = number(2, "the coordinate")?;
        let want = q.coordinates[k];
        if (x - want).abs() > COORDINATE_TOLERANCE * want.abs().max(1.0) {
            return Err(err(
                line,
                2,
                format!(
                    "coordinate {x:e} where probe point {} of {:?} is at {want:e} (same unit and order as the pack's probes.csv)",
                    k + 1,
                    q.name
                ),
            ));
        }
        let v = number(3, &format!("the {} value", q.name))?;
        let (lo, hi) = q.observable.allowed();
        if v < lo || hi.is_some_and(|h| v > h) {
            return Err(err(
                line,
                3,
                format!(
                    "{} must be in {} ({}), got {v:e}: wrong units?",
                    q.observable.name(),
                    q.observable.unit(),
                    match hi {
                        Some(h) => format!("[{lo:e}, {h:e}]"),
                        None => format!("≥ {lo:e}"),
                    }
                ),
            ));
        }
        out[qi].push(v);
        next += 1;
    }
    if !header_seen {
        return Err(err(
            last_line.max(1),
            1,
            format!("empty value file: expected the header `{HEADER}` and the values"),
        ));
    }
    if let Some(&(qi, _)) = expected_rows.get(next) {
        return Err(err(
            last_line + 1,
            1,
            format!(
                "the file ends after {} of {} values of {:?} (wrong count; the case has {})",
                out[qi].len(),
                quantities[qi].coordinates.len(),
                quantities[qi].name,
                summary(quantities)
            ),
        ));
    }
    Ok(out)
}

fn summary(quantities: &[Quantity]) -> String {
    quantities
        .iter()
        .map(|q| format!("{} × {}", q.coordinates.len(), q.name))
        .collect::<Vec<_>>()
        .join(", ")
}
