//! Scheme files (TOML): `name`, `degree`, `axiom`, `[rules]`, optional `[symmetry]` and
//! `[lengths]`. Parsing keeps byte spans so that every error names file, line and column.

use crate::exact::lsystem::{parse_word, LSystem, Source, Sym, Word, WordError};
use crate::{Error, Location};
use num_bigint::BigInt;
use num_rational::BigRational;
use num_traits::Zero;
use std::ops::Range;
use std::path::{Path, PathBuf};
use toml_edit::{ImDocument, Item, TableLike};

/// Largest degree accepted (masks have |π(w)| − d entries; beyond this tables explode).
pub const MAX_DEGREE: usize = 15;

/// The scheme files (`*.toml`) of a folder, sorted.
pub fn scheme_files(dir: &Path) -> Result<Vec<PathBuf>, Error> {
    let io = |e: std::io::Error| Error::io(dir, &e);
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

/// The largest scheme file read, in bytes (1 MiB): a pipe or device given as a scheme is read
/// no further.
pub const MAX_SCHEME_BYTES: u64 = 1 << 20;

/// Reads (at most [`MAX_SCHEME_BYTES`]) and parses a scheme file.
pub fn load(path: &Path) -> Result<LSystem, Error> {
    let text = crate::read_text(path, MAX_SCHEME_BYTES)?;
    parse(&path.display().to_string(), &text)
}

/// An exact rational written as an integer (`-3`), a fraction (`2/3`) or a decimal (`1.25`,
/// `-.5`): the numbers of `[lengths]` expressions and of the CLI's flags.
pub fn parse_rational(text: &str) -> Result<BigRational, String> {
    let t = text.trim();
    let fail = || format!("`{t}`: expected an integer, a fraction a/b or a decimal");
    if let Some((a, b)) = t.split_once('/') {
        let int = |s: &str| s.trim().parse::<BigInt>().map_err(|_| fail());
        let b = int(b)?;
        if b.is_zero() {
            return Err(format!(
                "`{t}`: the denominator of a fraction a/b cannot be 0"
            ));
        }
        return Ok(BigRational::new(int(a)?, b));
    }
    let (negative, body) = match t.strip_prefix('-') {
        Some(rest) => (true, rest),
        None => (false, t.strip_prefix('+').unwrap_or(t)),
    };
    let (whole, frac) = body.split_once('.').unwrap_or((body, ""));
    let digits = format!("{whole}{frac}");
    if digits.is_empty() || !digits.bytes().all(|c| c.is_ascii_digit()) {
        return Err(fail());
    }
    let n: BigInt = digits.parse().map_err(|_| fail())?;
    let r = BigRational::new(n, BigInt::from(10).pow(frac.len() as u32));
    Ok(if negative { -r } else { r })
}

/// How a scheme file looks, for hints on syntax errors.
const SHAPE: &str = "scheme files are TOML: `name = \"...\"`, `degree = 3` and `axiom = \"...\"`, then `[rules]` with one `SYMBOL = \"WORD\"` line per symbol";

/// The scheme file text of `ls`, which [`parse`] reads back: name, degree, axiom, `[rules]`,
/// and `[symmetry]` (each twin pair once) and `[lengths]` when declared.
pub fn to_toml(ls: &LSystem) -> String {
    use std::fmt::Write as _;
    let mut out = format!(
        "name = \"{}\"\ndegree = {}\naxiom = \"{}\"\n\n[rules]\n",
        ls.name,
        ls.degree,
        ls.word_str(&ls.axiom)
    );
    for (a, rule) in ls.rules.iter().enumerate() {
        let _ = writeln!(out, "{} = \"{}\"", ls.symbols[a], ls.word_str(rule));
    }
    if let Some(s) = &ls.symmetry {
        out += "\n[symmetry]\n";
        for a in (0..ls.n()).filter(|&a| s[a] as usize > a) {
            let _ = writeln!(out, "{} = \"{}\"", ls.symbols[a], ls.symbols[s[a] as usize]);
        }
    }
    if let Some(lengths) = &ls.lengths {
        out += "\n[lengths]\n";
        for (a, l) in lengths.iter().enumerate() {
            let _ = writeln!(out, "{} = \"{l}\"", ls.symbols[a]);
        }
    }
    out
}

/// Parses scheme text; `file` is used in error locations.
pub fn parse(file: &str, text: &str) -> Result<LSystem, Error> {
    let cx = Cx { file, text };
    let doc = ImDocument::parse(text).map_err(|e| {
        let span = e.span().unwrap_or(0..0);
        let message = toml_edit::TomlError::message(&e).trim().to_string();
        let hint = if message.starts_with("duplicate key") {
            "each key appears once per table (one rule per symbol): delete or merge the repeated line"
        } else {
            SHAPE
        };
        cx.err(span, message, Some(hint.into()))
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
            return Err(cx.err(
                cx.span_of_key(root, key),
                format!("unknown key `{key}`"),
                Some(format!("known keys: {}", known.join(", "))),
            ));
        }
    }

    let name = cx.string(root, "name", "name = \"my-scheme\"")?;
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
            text.len()..text.len(),
            "missing `[rules]` table".into(),
            Some("add `[rules]` at the end of the file, then one `SYMBOL = \"WORD\"` line per symbol, e.g. `L = \"LC\"`".into()),
        )
    })?;
    let rules_span = cx.span_of_key(root, "rules");
    let symbols: Vec<String> = rules_item.iter().map(|(k, _)| k.to_string()).collect();
    if symbols.is_empty() {
        return Err(cx.err(
            rules_span,
            "`[rules]` is empty".into(),
            Some(
                "add one `SYMBOL = \"WORD\"` line per symbol under `[rules]`, e.g. `L = \"LC\"`"
                    .into(),
            ),
        ));
    }
    if symbols.len() > Sym::MAX as usize {
        return Err(cx.err(
            rules_span,
            format!(
                "{} symbols: at most {} are supported",
                symbols.len(),
                Sym::MAX
            ),
            Some(format!("use at most {} symbols", Sym::MAX)),
        ));
    }
    for s in &symbols {
        if s.is_empty() || s.contains(char::is_whitespace) {
            return Err(cx.err(
                cx.span_of_key(rules_item, s),
                format!("symbol name `{s}` must be non-empty without white space"),
                Some("name symbols with letters and digits, e.g. `A1`".into()),
            ));
        }
    }
    let mut rules = Vec::with_capacity(symbols.len());
    let mut source = Source {
        file: file.to_string(),
        rules: Some(cx.loc(rules_span)),
        degree: Some(cx.loc(degree.0)),
        ..Source::default()
    };
    for s in &symbols {
        let (span, text) = cx.value_str(rules_item, s, "L = \"LC\"")?;
        source.rule.push(cx.loc(span.clone()));
        let word = cx.word(&symbols, span, &text, &format!("rule for `{s}`"))?;
        rules.push(word);
    }
    let axiom_raw = cx.string(root, "axiom", "axiom = \"C\"")?;
    source.axiom = Some(cx.loc(axiom_raw.0.clone()));
    let axiom = cx.word(&symbols, axiom_raw.0, &axiom_raw.1, "axiom")?;

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
                        format!("`[lengths]` names `{k}`, which has no rule"),
                        Some(format!(
                            "`[lengths]` has one entry per symbol of `[rules]`: {}",
                            symbols.join(", ")
                        )),
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
                let (span, text) = cx.value_str(t, s, "L = \"rho - 1\"")?;
                source.lengths.push(cx.loc(span));
                out.push(text);
            }
            Some(out)
        }
    };
    Ok(LSystem {
        name: name.1,
        degree: degree.1,
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
        Error::at(self.loc(span), message).with_hint_opt(hint)
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

    /// A top-level key; when it is missing the error points at the start of the file, where
    /// top-level keys belong (before the first table).
    fn required<'t>(
        &self,
        t: &'t dyn TableLike,
        key: &str,
        example: &str,
    ) -> Result<(Range<usize>, &'t Item), Error> {
        self.item(t, key).ok_or_else(|| {
            self.err(
                0..0,
                format!("missing key `{key}`"),
                Some(format!(
                    "add `{example}` at the top of the file, before `[rules]`"
                )),
            )
        })
    }

    fn string(
        &self,
        t: &dyn TableLike,
        key: &str,
        example: &str,
    ) -> Result<(Range<usize>, String), Error> {
        let (span, v) = self.required(t, key, example)?;
        self.as_string(span, v, key, example)
    }

    fn as_string(
        &self,
        span: Range<usize>,
        v: &Item,
        key: &str,
        example: &str,
    ) -> Result<(Range<usize>, String), Error> {
        let s = v.as_str().ok_or_else(|| {
            self.err(
                span.clone(),
                format!("the value of `{key}` must be a string"),
                Some(format!("write it in double quotes, e.g. `{example}`")),
            )
        })?;
        Ok((span, s.to_string()))
    }

    /// The value of a key the table is known to hold.
    fn value_str(
        &self,
        t: &dyn TableLike,
        key: &str,
        example: &str,
    ) -> Result<(Range<usize>, String), Error> {
        let (span, v) = self.item(t, key).expect("key listed by the table");
        self.as_string(span, v, key, example)
    }

    fn degree(&self, t: &dyn TableLike) -> Result<(Range<usize>, usize), Error> {
        let (span, v) = self.required(t, "degree", "degree = 3")?;
        let d = v.as_integer().ok_or_else(|| {
            self.err(
                span.clone(),
                "the value of `degree` must be an integer".into(),
                Some("write a whole number without quotes, e.g. `degree = 3`".into()),
            )
        })?;
        if d < 1 || d > MAX_DEGREE as i64 {
            return Err(self.err(
                span,
                format!("degree {d} is out of range"),
                Some(format!(
                    "use a degree from 1 to {MAX_DEGREE} (3: cubic B-splines)"
                )),
            ));
        }
        Ok((span, d as usize))
    }

    fn table<'t>(
        &self,
        t: &'t dyn TableLike,
        key: &str,
    ) -> Result<Option<&'t dyn TableLike>, Error> {
        match self.item(t, key) {
            None => Ok(None),
            Some((span, item)) => item.as_table_like().map(Some).ok_or_else(|| {
                self.err(
                    span,
                    format!("`{key}` must be a table"),
                    Some(format!(
                        "write `[{key}]` on a line of its own, followed by `KEY = \"VALUE\"` lines"
                    )),
                )
            }),
        }
    }

    /// Parses the word of a string value at `span`; an unknown symbol is located exactly when
    /// the string is written without escapes.
    fn word(
        &self,
        symbols: &[String],
        span: Range<usize>,
        text: &str,
        what: &str,
    ) -> Result<Word, Error> {
        parse_word(symbols, text).map_err(|e| match e {
            WordError::Empty => self.err(
                span,
                format!("{what}: empty word"),
                Some(
                    "every interval splits into at least one interval ([N] eq. (1)): write one or more symbols, e.g. `\"LC\"`"
                        .into(),
                ),
            ),
            WordError::Unknown {
                symbol,
                offset,
                alphabet,
                split_by_character,
            } => {
                // The raw text is the value in quotes when it has no escapes.
                let raw = self.text.get(span.clone()).unwrap_or("");
                let plain = raw.len() == text.len() + 2 && raw.get(1..raw.len() - 1) == Some(text);
                let at = if plain { span.start + 1 + offset } else { span.start };
                let mut hint = format!(
                    "add a rule `{symbol} = \"...\"` under `[rules]`, or use a symbol that has one: {alphabet}"
                );
                if split_by_character {
                    hint += "; separate symbols longer than one character with spaces, e.g. `\"A1 A2\"`";
                }
                self.err(
                    at..at,
                    format!("{what}: symbol `{symbol}` has no rule"),
                    Some(hint),
                )
            }
        })
    }

    /// `[symmetry]`: pairs `L = "R"`; unlisted symbols are fixed by σ; must be an involution.
    fn symmetry(&self, t: &dyn TableLike, symbols: &[String]) -> Result<Vec<Sym>, Error> {
        let hint = || {
            Some(format!(
                "`[symmetry]` pairs twin symbols of `[rules]` ({}), e.g. `L = \"R\"`",
                symbols.join(", ")
            ))
        };
        let mut sigma: Vec<Option<Sym>> = vec![None; symbols.len()];
        for (k, _) in t.iter() {
            let span = self.span_of_key(t, k);
            let a = symbols.iter().position(|s| s == k).ok_or_else(|| {
                self.err(
                    span.clone(),
                    format!("`[symmetry]` names `{k}`, which has no rule"),
                    hint(),
                )
            })?;
            let (vspan, v) = self.value_str(t, k, "L = \"R\"")?;
            let b = symbols.iter().position(|s| *s == v).ok_or_else(|| {
                self.err(
                    vspan.clone(),
                    format!("`[symmetry]` maps `{k}` to `{v}`, which has no rule"),
                    hint(),
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

#[cfg(test)]
mod tests {
    use super::*;

    /// Every shipped scheme (symmetry and lengths included) reads back from [`to_toml`].
    #[test]
    fn rationals_are_integers_fractions_or_decimals() {
        let r = |a: i64, b: i64| BigRational::new(a.into(), b.into());
        for (text, want) in [
            ("3", r(3, 1)),
            ("-3", r(-3, 1)),
            ("+2", r(2, 1)),
            (" 2/6 ", r(1, 3)),
            ("-1/4", r(-1, 4)),
            ("1.25", r(5, 4)),
            ("-.5", r(-1, 2)),
            ("7.", r(7, 1)),
        ] {
            assert_eq!(parse_rational(text), Ok(want), "{text}");
        }
        for bad in [
            "", "-", ".", "1.2.3", "1e5", "--1", "1.-5", "x", "1/0", "1/",
        ] {
            let e = parse_rational(bad).unwrap_err();
            assert!(e.contains(&format!("`{}`", bad.trim())), "{bad}: {e}");
        }
    }

    #[test]
    fn written_schemes_parse_back_to_the_same_system() {
        let dir = Path::new(env!("CARGO_MANIFEST_DIR")).join("../schemes");
        let files = scheme_files(&dir).unwrap();
        assert!(files.len() >= 2, "the shipped schemes are found");
        for file in files {
            let ls = load(&file).unwrap();
            let again = parse("again.toml", &to_toml(&ls)).unwrap();
            let strip = |l: &LSystem| LSystem {
                source: Source::default(),
                ..l.clone()
            };
            assert_eq!(strip(&again), strip(&ls), "{}", file.display());
        }
    }
}
