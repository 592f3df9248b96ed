//! Point files: one point per line, coordinates separated by white space (2 or 3 of them).
//! Blank lines and lines starting with `#` are skipped on input; output has nothing else in it.

use lsubdiv_io::{Error, Location};

/// Points of dimension 2 or 3.
#[derive(Clone, Debug, PartialEq)]
pub enum Points {
    /// Planar points.
    D2(Vec<[f64; 2]>),
    /// Spatial points.
    D3(Vec<[f64; 3]>),
}

/// Parses a point file; `file` names it in errors (`file:line:column: error: …`, the column of
/// the offending coordinate when there is one).
pub fn parse(file: &str, text: &str) -> Result<Points, Error> {
    let mut rows: Vec<Vec<f64>> = Vec::new();
    let mut dim = None;
    for (i, raw) in text.lines().enumerate() {
        let line = raw.trim();
        if line.is_empty() || line.starts_with('#') {
            continue;
        }
        let at = || Location::line(file, i + 1);
        let row = line
            .split_whitespace()
            .map(|t| {
                // `t` is a slice of `raw`: its byte offset gives the column.
                let offset = t.as_ptr() as usize - raw.as_ptr() as usize;
                let at_token = Location {
                    column: Some(raw[..offset].chars().count() + 1),
                    ..at()
                };
                match t.parse::<f64>() {
                    Ok(x) if x.is_finite() => Ok(x),
                    Ok(_) => Err(Error::at(
                        at_token,
                        format!("coordinate `{t}` is not finite"),
                    )),
                    Err(_) => Err(Error::at(at_token, format!("`{t}` is not a number"))),
                }
            })
            .collect::<Result<Vec<f64>, Error>>()?;
        match dim {
            None if row.len() == 2 || row.len() == 3 => dim = Some(row.len()),
            None => {
                return Err(Error::at(
                    at(),
                    format!("{} coordinates; points have 2 or 3", row.len()),
                ))
            }
            Some(d) if d != row.len() => {
                return Err(Error::at(
                    at(),
                    format!("{} coordinates, but earlier points have {d}", row.len()),
                ))
            }
            Some(_) => {}
        }
        rows.push(row);
    }
    match dim {
        None => Err(Error::in_file(file, "no points")),
        Some(2) => Ok(Points::D2(rows.iter().map(|r| [r[0], r[1]]).collect())),
        Some(_) => Ok(Points::D3(
            rows.iter().map(|r| [r[0], r[1], r[2]]).collect(),
        )),
    }
}

/// Refuses a point or vertex with a non-finite coordinate before anything is written: lsubdiv
/// writes finite numbers only (its readers refuse `NaN` and `inf`). `what` names the element
/// (`vertex`, `point`), counted from 1 as in the files.
pub fn finite<const D: usize>(what: &str, points: &[[f64; D]]) -> Result<(), Error> {
    match points.iter().position(|p| !p.iter().all(|x| x.is_finite())) {
        None => Ok(()),
        Some(i) => Err(Error::input(format!(
            "{what} {} has a non-finite coordinate ({}); nothing was written",
            i + 1,
            points[i].map(|x| format!("{x:?}")).join(" ")
        ))),
    }
}

/// Formats points at full (round-trip) f64 precision, one per line; refuses a non-finite
/// coordinate ([`finite`]).
pub fn format<const D: usize>(points: &[[f64; D]]) -> Result<String, Error> {
    Ok(Text::new(points)?.to_string())
}

/// A point file's text, checked ([`format()`]) and not yet formatted: `write!` it into any
/// writer (`lsubdiv::write_atomic_with` streams it to a file). Each line holds a point's
/// coordinates, then those of the same point in each further column set (a limit point's
/// tangent: [`Text::with_columns`]).
pub struct Text<'a, const D: usize> {
    columns: Vec<&'a [[f64; D]]>,
}

impl<'a, const D: usize> Text<'a, D> {
    /// One point per line; refuses a non-finite coordinate ([`finite`]).
    pub fn new(points: &'a [[f64; D]]) -> Result<Text<'a, D>, Error> {
        Text::with_columns(vec![points])
    }

    /// Line i holds point i of every column set in turn (`x y z tx ty tz`); the sets must be
    /// as long as each other. Refuses a non-finite coordinate, named by its line ([`finite`]).
    pub fn with_columns(columns: Vec<&'a [[f64; D]]>) -> Result<Text<'a, D>, Error> {
        let lines = columns.first().map_or(0, |c| c.len());
        if let Some(c) = columns.iter().find(|c| c.len() != lines) {
            return Err(Error::internal(
                None,
                format!("point columns of {} and {lines} lines", c.len()),
            ));
        }
        // The column set whose first non-finite point comes first names it.
        let first_bad = |c: &&[[f64; D]]| c.iter().position(|p| !p.iter().all(|x| x.is_finite()));
        if let Some(c) = columns
            .iter()
            .min_by_key(|c| first_bad(c).unwrap_or(usize::MAX))
        {
            finite("point", c)?;
        }
        Ok(Text { columns })
    }
}

impl<const D: usize> std::fmt::Display for Text<'_, D> {
    fn fmt(&self, s: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        let lines = self.columns.first().map_or(0, |c| c.len());
        for i in 0..lines {
            let mut sep = "";
            for x in self.columns.iter().flat_map(|c| &c[i]) {
                write!(s, "{sep}{x:?}")?;
                sep = " ";
            }
            writeln!(s)?;
        }
        Ok(())
    }
}
