//! Explorer output (\[G\] Appendix B columns): JSON (an array), CSV, Markdown and text tables.

use lsubdiv_explorer::Row;
use serde_json::{json, Value};

/// Output formats of `enumerate` and `search`.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Format {
    /// A JSON array of objects.
    Json,
    /// Comma-separated values with a header.
    Csv,
    /// A Markdown table.
    Markdown,
}

/// One row as JSON: the columns plus the exact ρ text, M[C; Σ], σ and the §4.2 steps.
pub fn row_json(r: &Row) -> Value {
    let (stationary, contained, reason) = match &r.surface {
        Ok((s, c)) => (json!(s), json!(c), Value::Null),
        Err(e) => (Value::Null, Value::Null, json!(e)),
    };
    json!({
        "family": r.family,
        "pi_c": r.pi_c,
        "m_row": r.m_row,
        "symbols": r.ls.symbols,
        "rho": r.rho_f64(),
        "rho_exact": r.rho_text,
        "minimal_polynomial": r.minimal_polynomial().iter()
            .map(|c| c.parse::<i64>().map_or_else(|_| json!(c), |v| json!(v)))
            .collect::<Vec<_>>(),
        "integer": r.integer,
        "masks": r.masks,
        "words": r.words,
        "valid": r.valid.is_ok(),
        "invalid_reason": r.valid.as_ref().err(),
        "symmetric": r.sigma.is_some(),
        "involution": r.involution(),
        "surface_ready": r.surface.is_ok(),
        "stationary_from": stationary,
        "contained_from": contained,
        "surface_reason": reason,
    })
}

const HEADER: [&str; 10] = [
    "family",
    "pi_c",
    "M[C]",
    "rho",
    "minimal polynomial",
    "masks",
    "words",
    "valid",
    "sigma",
    "surface",
];

fn cells(r: &Row) -> [String; 10] {
    let surface = match &r.surface {
        Ok((s, c)) => format!("yes (stationary from {s}, contained from {c})"),
        Err(e) => format!("no: {e}"),
    };
    [
        r.family.clone(),
        r.pi_c.clone(),
        r.m_row
            .iter()
            .map(ToString::to_string)
            .collect::<Vec<_>>()
            .join(" "),
        format!("{} ≈ {:.6}", r.rho_text, r.rho_f64()),
        r.minimal_polynomial().join(" "),
        r.masks.to_string(),
        r.words.to_string(),
        match &r.valid {
            Ok(()) => "yes".into(),
            Err(e) => format!("no: {e}"),
        },
        r.involution().unwrap_or_else(|| "none".into()),
        surface,
    ]
}

/// The rows in `format`.
pub fn render(rows: &[Row], format: Format) -> String {
    match format {
        Format::Json => {
            let v: Vec<Value> = rows.iter().map(row_json).collect();
            serde_json::to_string_pretty(&v).unwrap_or_default() + "\n"
        }
        Format::Csv => {
            let quote = |s: &str| format!("\"{}\"", s.replace('"', "\"\""));
            let mut out = HEADER.join(",") + "\n";
            for r in rows {
                let c = cells(r);
                out += &c.iter().map(|s| quote(s)).collect::<Vec<_>>().join(",");
                out += "\n";
            }
            out
        }
        Format::Markdown => {
            let mut out = format!(
                "| {} |\n|{}\n",
                HEADER.join(" | "),
                "---|".repeat(HEADER.len())
            );
            for r in rows {
                out += &format!("| {} |\n", cells(r).join(" | ").replace('\n', " "));
            }
            out
        }
    }
}
