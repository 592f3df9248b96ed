//! Scheme files (TOML): `name`, `degree`, `axiom`, `[rules]`, optional `[symmetry]` and
//! `[lengths]`. Parsing keeps byte spans so that every error names file, line and column.

use crate::error::{Error, Location};
use crate::lsystem::{parse_word, LSystem, Source, Sym};
use std::ops::Range;
use std::path::{Path, PathBuf};
use toml_edit::{ImDocument, Item, TableLike};

/// Largest degree accepted (masks have |π(w)| − d entries; beyond this tables explode).
pub const MAX_DEGREE: usize = 15;

/// The scheme files (`*.toml`) of a folder, sorted.
pub fn scheme_files(dir: &Path) -> Result<Vec<PathBuf>, Error> {
    let io = |e: std::io::Error| Error::Io {
        path: dir.display().to_string(),
        message: e.to_string(),
    };
    let mut files = Vec::new();
    for entry in std::fs::read_dir(dir).map_err(io)? {
        let p = entry.map_err(io)?.path();
        if p.extension().is_some_and(|e| e == "toml") {
            files.push(p);
        }
    }
    files.sort();
    Ok(files)
}

/// Reads and parses a scheme file.
pub fn load(path: &Path) -> Result<LSystem, Error> {
    let text = std::fs::read_to_string(path).map_err(|e| Error::Io {
        path: path.display().to_string(),
        message: e.to_string(),
    })?;
    parse(&path.display().to_string(), &text)
}

/// Parses scheme text; `file` is used in error locations.
pub fn parse(file: &str, text: &str) -> Result<LSystem, Error> {
    let cx = Cx { file, text };
    let doc = ImDocument::parse(text).map_err(|e| {
        let span = e.span().unwrap_or(0..0);
        cx.err(span, e.message().trim().to_string(), None)
    })?;
    let root = doc.as_table();
    let known = [
        "name",
        "degree",
        "axiom",
        "rules",
        "symmetry",
        "lengths",
        "description",
    ];
    for (key, _) in root.iter() {
        if !known.contains(&key) {
            let span = root.key(key).and_then(|k| k.span()).unwrap_or(0..0);
            return Err(cx.err(
                span,
                format!("unknown key `{key}`"),
                Some(format!("known keys: {}", known.join(", "))),
            ));
        }
    }

    let name = cx.string(root, "name")?;
    if name.1.is_empty()
        || !name
            .1
            .chars()
            .all(|c| c.is_ascii_alphanumeric() || c == '-' || c == '_')
    {
        return Err(cx.err(
            name.0,
            format!("scheme name `{}` is not a slug", name.1),
            Some("use letters, digits, `-` and `_`, e.g. `binary-ternary`".into()),
        ));
    }
    let degree = cx.degree(root)?;
    let rules_item = cx.table(root, "rules")?.ok_or_else(|| {
        cx.err(
            0..0,
            "missing `[rules]` table".into(),
            Some("add `[rules]` with one `SYMBOL = \"WORD\"` line per symbol".into()),
        )
    })?;
    let symbols: Vec<String> = rules_item.iter().map(|(k, _)| k.to_string()).collect();
    if symbols.is_empty() {
        return Err(cx.err(
            cx.span_of_key(root, "rules"),
            "`[rules]` is empty".into(),
            None,
        ));
    }
    if symbols.len() > Sym::MAX as usize {
        return Err(cx.err(
            cx.span_of_key(root, "rules"),
            format!(
                "{} symbols: at most {} are supported",
                symbols.len(),
                Sym::MAX
            ),
            None,
        ));
    }
    for s in &symbols {
        if s.is_empty() || s.contains(char::is_whitespace) {
            return Err(cx.err(
                cx.span_of_key(rules_item, s),
                format!("symbol name `{s}` must be non-empty without white space"),
                None,
            ));
        }
    }
    let mut rules = Vec::with_capacity(symbols.len());
    let mut source = Source {
        file: file.to_string(),
        rules: Some(cx.loc(cx.span_of_key(root, "rules"))),
        ..Source::default()
    };
    for s in &symbols {
        let (span, text) = cx.value_str(rules_item, s)?;
        source.rule.push(cx.loc(span.clone()));
        let word = parse_word(&symbols, &text).map_err(|m| {
            cx.err(
                span,
                format!("rule for `{s}`: {m}"),
                Some("each symbol of the right-hand side must have its own rule".into()),
            )
        })?;
        rules.push(word);
    }
    let axiom_raw = cx.string(root, "axiom")?;
    let axiom = parse_word(&symbols, &axiom_raw.1)
        .map_err(|m| cx.err(axiom_raw.0.clone(), format!("axiom: {m}"), None))?;

    let symmetry = match cx.table(root, "symmetry")? {
        None => None,
        Some(t) => {
            source.symmetry = Some(cx.loc(cx.span_of_key(root, "symmetry")));
            Some(cx.symmetry(t, &symbols)?)
        }
    };
    let lengths = match cx.table(root, "lengths")? {
        None => None,
        Some(t) => {
            let mut out = Vec::with_capacity(symbols.len());
            for (k, _) in t.iter() {
                if !symbols.iter().any(|s| s == k) {
                    return Err(cx.err(
                        cx.span_of_key(t, k),
                        format!("`[lengths]` names unknown symbol `{k}`"),
                        None,
                    ));
                }
            }
            for s in &symbols {
                if t.get(s).is_none() {
                    return Err(cx.err(
                        cx.span_of_key(root, "lengths"),
                        format!("`[lengths]` has no entry for symbol `{s}`"),
                        Some(
                            "give every symbol a length, e.g. `L = \"1\"`, `C = \"rho - 1\"`"
                                .into(),
                        ),
                    ));
                }
                let (span, text) = cx.value_str(t, s)?;
                source.lengths.push(cx.loc(span));
                out.push(text);
            }
            Some(out)
        }
    };
    Ok(LSystem {
        name: name.1,
        degree,
        symbols,
        rules,
        axiom,
        symmetry,
        lengths,
        source,
    })
}

struct Cx<'a> {
    file: &'a str,
    text: &'a str,
}

impl Cx<'_> {
    fn loc(&self, span: Range<usize>) -> Location {
        Location::from_offset(self.file, self.text, span.start)
    }

    fn err(&self, span: Range<usize>, message: String, hint: Option<String>) -> Error {
        Error::Scheme {
            at: self.loc(span),
            message,
            hint,
        }
    }

    fn span_of_key(&self, t: &dyn TableLike, key: &str) -> Range<usize> {
        t.get_key_value(key)
            .and_then(|(k, _)| k.span())
            .unwrap_or(0..0)
    }

    fn item<'t>(&self, t: &'t dyn TableLike, key: &str) -> Option<(Range<usize>, &'t Item)> {
        let (k, v) = t.get_key_value(key)?;
        Some((v.span().or_else(|| k.span()).unwrap_or(0..0), v))
    }

    fn string(&self, t: &dyn TableLike, key: &str) -> Result<(Range<usize>, String), Error> {
        let (span, v) = self.item(t, key).ok_or_else(|| {
            self.err(
                0..0,
                format!("missing key `{key}`"),
                Some(format!("add `{key} = \"...\"` at the top of the file")),
            )
        })?;
        let s = v
            .as_str()
            .ok_or_else(|| self.err(span.clone(), format!("`{key}` must be a string"), None))?;
        Ok((span, s.to_string()))
    }

    fn value_str(&self, t: &dyn TableLike, key: &str) -> Result<(Range<usize>, String), Error> {
        let (span, v) = self.item(t, key).expect("key listed by the table");
        let s = v.as_str().ok_or_else(|| {
            self.err(
                span.clone(),
                format!("value of `{key}` must be a string"),
                None,
            )
        })?;
        Ok((span, s.to_string()))
    }

    fn degree(&self, t: &dyn TableLike) -> Result<usize, Error> {
        let (span, v) = self.item(t, "degree").ok_or_else(|| {
            self.err(
                0..0,
                "missing key `degree`".into(),
                Some("add `degree = 3` (cubic B-splines)".into()),
            )
        })?;
        let d = v
            .as_integer()
            .ok_or_else(|| self.err(span.clone(), "`degree` must be an integer".into(), None))?;
        if d < 1 || d as usize > MAX_DEGREE {
            return Err(self.err(
                span,
                format!("degree {d} is out of range"),
                Some(format!("use a degree from 1 to {MAX_DEGREE}")),
            ));
        }
        Ok(d as usize)
    }

    fn table<'t>(
        &self,
        t: &'t dyn TableLike,
        key: &str,
    ) -> Result<Option<&'t dyn TableLike>, Error> {
        match self.item(t, key) {
            None => Ok(None),
            Some((span, item)) => item
                .as_table_like()
                .map(Some)
                .ok_or_else(|| self.err(span, format!("`{key}` must be a table"), None)),
        }
    }

    /// `[symmetry]`: pairs `L = "R"`; unlisted symbols are fixed by σ; must be an involution.
    fn symmetry(&self, t: &dyn TableLike, symbols: &[String]) -> Result<Vec<Sym>, Error> {
        let mut sigma: Vec<Option<Sym>> = vec![None; symbols.len()];
        for (k, _) in t.iter() {
            let span = self.span_of_key(t, k);
            let a = symbols.iter().position(|s| s == k).ok_or_else(|| {
                self.err(
                    span.clone(),
                    format!("`[symmetry]` names unknown symbol `{k}`"),
                    None,
                )
            })?;
            let (vspan, v) = self.value_str(t, k)?;
            let b = symbols.iter().position(|s| *s == v).ok_or_else(|| {
                self.err(
                    vspan.clone(),
                    format!("`[symmetry]` maps `{k}` to unknown symbol `{v}`"),
                    None,
                )
            })?;
            for (x, y) in [(a, b), (b, a)] {
                match sigma[x] {
                    Some(prev) if prev as usize != y => {
                        return Err(self.err(
                            vspan,
                            format!(
                                "`[symmetry]` is not an involution: `{}` is paired with both `{}` and `{}`",
                                symbols[x], symbols[prev as usize], symbols[y]
                            ),
                            Some("list each twin pair once, e.g. `L = \"R\"`".into()),
                        ))
                    }
                    _ => sigma[x] = Some(y as Sym),
                }
            }
        }
        Ok(sigma
            .iter()
            .enumerate()
            .map(|(i, s)| s.unwrap_or(i as Sym))
            .collect())
    }
}
