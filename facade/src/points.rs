//! Point files: one point per line, coordinates separated by white space (2 or 3 of them).
//! Blank lines and lines starting with `#` are skipped on input; output has nothing else in it.

use std::fmt::Write as _;

/// Points of dimension 2 or 3.
#[derive(Clone, Debug, PartialEq)]
pub enum Points {
    /// Planar points.
    D2(Vec<[f64; 2]>),
    /// Spatial points.
    D3(Vec<[f64; 3]>),
}

/// Parses a point file; `file` names it in errors (`file:line: ...`).
pub fn parse(file: &str, text: &str) -> Result<Points, String> {
    let mut rows: Vec<Vec<f64>> = Vec::new();
    let mut dim = None;
    for (i, line) in text.lines().enumerate() {
        let line = line.trim();
        if line.is_empty() || line.starts_with('#') {
            continue;
        }
        let at = format!("{file}:{}", i + 1);
        let row = line
            .split_whitespace()
            .map(|t| match t.parse::<f64>() {
                Ok(x) if x.is_finite() => Ok(x),
                Ok(_) => Err(format!("{at}: error: coordinate `{t}` is not finite")),
                Err(_) => Err(format!("{at}: error: `{t}` is not a number")),
            })
            .collect::<Result<Vec<f64>, String>>()?;
        match dim {
            None if row.len() == 2 || row.len() == 3 => dim = Some(row.len()),
            None => {
                return Err(format!(
                    "{at}: error: {} coordinates; points have 2 or 3",
                    row.len()
                ))
            }
            Some(d) if d != row.len() => {
                return Err(format!(
                    "{at}: error: {} coordinates, but earlier points have {d}",
                    row.len()
                ))
            }
            Some(_) => {}
        }
        rows.push(row);
    }
    match dim {
        None => Err(format!("{file}: error: no points")),
        Some(2) => Ok(Points::D2(rows.iter().map(|r| [r[0], r[1]]).collect())),
        Some(_) => Ok(Points::D3(
            rows.iter().map(|r| [r[0], r[1], r[2]]).collect(),
        )),
    }
}

/// Formats points at full (round-trip) f64 precision, one per line.
pub fn format<const D: usize>(points: &[[f64; D]]) -> String {
    let mut s = String::new();
    for p in points {
        let coords: Vec<String> = p.iter().map(|x| format!("{x:?}")).collect();
        let _ = writeln!(s, "{}", coords.join(" "));
    }
    s
}
