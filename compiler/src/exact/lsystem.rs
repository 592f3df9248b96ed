//! L-systems as interval-subdivision descriptors (\[N\] §2.1, \[G\] §2.1).
//!
//! Symbols are small integers (`Sym`) indexing [`LSystem::symbols`]; a word is a `Vec<Sym>`.
//! π rewrites every symbol of a word simultaneously (\[N\] eq. (1)).

use crate::{Error, Location};
use lsubdiv_runtime::curve::format_word;

/// A symbol, as an index into the alphabet.
pub type Sym = u8;
/// A word over the alphabet.
pub type Word = Vec<Sym>;

/// A context-free L-system with the degree of the B-splines it drives.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct LSystem {
    /// Scheme name (a Rust-identifier-friendly slug such as `binary-ternary`).
    pub name: String,
    /// Spline degree d ≥ 1.
    pub degree: usize,
    /// The alphabet Σ, in declaration order.
    pub symbols: Vec<String>,
    /// π(A) for every symbol A, never empty.
    pub rules: Vec<Word>,
    /// The axiom ω: the label of every initial interval (repeated).
    pub axiom: Word,
    /// A declared involution σ over Σ (\[G\] §4.1): `sigma[a]` is the twin of symbol a.
    pub symmetry: Option<Vec<Sym>>,
    /// Declared lengths (expressions in ρ), one per symbol, when the eigenvector is not unique.
    pub lengths: Option<Vec<String>>,
    /// Where the parts were written, for error messages.
    pub source: Source,
}

/// Where the parts of an L-system were written (empty for systems built in code).
#[derive(Clone, Debug, Default, PartialEq, Eq)]
pub struct Source {
    /// File name.
    pub file: String,
    /// The `degree` value.
    pub degree: Option<Location>,
    /// The `axiom` value.
    pub axiom: Option<Location>,
    /// The `[rules]` table.
    pub rules: Option<Location>,
    /// Each symbol's rule.
    pub rule: Vec<Location>,
    /// The `[symmetry]` table.
    pub symmetry: Option<Location>,
    /// Each symbol's `[lengths]` entry.
    pub lengths: Vec<Location>,
}

/// A part of a scheme file that an error can point at.
#[derive(Clone, Copy, Debug)]
pub enum Part {
    /// The `degree` value.
    Degree,
    /// The `axiom` value.
    Axiom,
    /// The `[rules]` table (the L-system as a whole).
    Rules,
    /// The rule of one symbol.
    Rule(usize),
    /// The `[symmetry]` table.
    Symmetry,
    /// The `[lengths]` entry of one symbol.
    Length(usize),
}

impl LSystem {
    /// The location of a part, or the start of the file when it is not known.
    pub fn locate(&self, part: Part) -> Location {
        let s = &self.source;
        let found = match part {
            Part::Degree => s.degree.clone(),
            Part::Axiom => s.axiom.clone(),
            Part::Rules => s.rules.clone(),
            Part::Rule(i) => s.rule.get(i).cloned(),
            Part::Symmetry => s.symmetry.clone(),
            Part::Length(i) => s.lengths.get(i).cloned(),
        };
        found.unwrap_or_else(|| Location::file(self.file()))
    }

    /// The file name for messages (`<scheme>` for systems built in code).
    pub fn file(&self) -> &str {
        if self.source.file.is_empty() {
            "<scheme>"
        } else {
            &self.source.file
        }
    }

    /// A scheme error at a part of this L-system.
    pub fn error(&self, part: Part, message: String, hint: Option<String>) -> Error {
        Error::at(self.locate(part), message).with_hint_opt(hint)
    }

    /// Number of symbols n.
    pub fn n(&self) -> usize {
        self.symbols.len()
    }

    /// π(w): every symbol rewritten.
    pub fn rewrite(&self, w: &[Sym]) -> Word {
        w.iter()
            .flat_map(|&s| self.rules[s as usize].iter().copied())
            .collect()
    }

    /// The matrix M of \[N\] eq. (4): m_ij = number of A_j in π(A_i).
    pub fn matrix(&self) -> Vec<Vec<i64>> {
        let n = self.n();
        let mut m = vec![vec![0i64; n]; n];
        for (i, rule) in self.rules.iter().enumerate() {
            for &s in rule {
                m[i][s as usize] += 1;
            }
        }
        m
    }

    /// Formats a word: `LCR`, or `A1 A2` when some symbol name is longer than one character
    /// (the runtime's [`format_word`], which generated tables use too).
    pub fn word_str(&self, w: &[Sym]) -> String {
        format_word(&self.symbols, w)
    }

    /// Mirror σ̄ of a word (\[G\] eq. (12)): read backwards, each symbol replaced by its twin.
    pub fn mirror(&self, sigma: &[Sym], w: &[Sym]) -> Word {
        w.iter().rev().map(|&s| sigma[s as usize]).collect()
    }

    /// Parses a word written as in scheme files: symbols separated by white space, or, when
    /// there is no white space, one symbol per character (or the whole text naming one symbol).
    pub fn parse_word(&self, text: &str) -> Result<Word, WordError> {
        parse_word(&self.symbols, text)
    }
}

/// Why a written word is not a word over the alphabet.
#[derive(Clone, Debug, PartialEq, Eq)]
pub enum WordError {
    /// No symbol at all.
    Empty,
    /// A symbol that is not in the alphabet (in a scheme file: that has no rule).
    Unknown {
        /// The symbol as written.
        symbol: String,
        /// Its byte offset in the text.
        offset: usize,
        /// The alphabet, comma-separated.
        alphabet: String,
        /// The text had no white space and some symbol names are longer than one character,
        /// so it was read one character per symbol.
        split_by_character: bool,
    },
}

impl std::fmt::Display for WordError {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            WordError::Empty => write!(f, "empty word: every word needs at least one symbol"),
            WordError::Unknown {
                symbol, alphabet, ..
            } => write!(f, "unknown symbol `{symbol}` (the alphabet is {alphabet})"),
        }
    }
}

/// Word parser shared by scheme files and the CLI (see [`LSystem::parse_word`]).
pub fn parse_word(symbols: &[String], text: &str) -> Result<Word, WordError> {
    let split_by_character =
        !text.trim().contains(char::is_whitespace) && symbols.iter().any(|s| s.chars().count() > 1);
    let lookup = |(offset, name): (usize, &str)| -> Result<Sym, WordError> {
        symbols
            .iter()
            .position(|s| s == name)
            .map(|i| i as Sym)
            .ok_or_else(|| WordError::Unknown {
                symbol: name.to_string(),
                offset,
                alphabet: symbols.join(", "),
                split_by_character,
            })
    };
    // Tokens with their byte offsets in `text`.
    let mut tokens: Vec<(usize, &str)> = Vec::new();
    let mut start = None;
    for (i, c) in text
        .char_indices()
        .chain(std::iter::once((text.len(), ' ')))
    {
        match (c.is_whitespace(), start) {
            (true, Some(s)) => {
                tokens.push((s, &text[s..i]));
                start = None;
            }
            (false, None) => start = Some(i),
            _ => {}
        }
    }
    match tokens.as_slice() {
        [] => Err(WordError::Empty),
        [(at, whole)] => match lookup((*at, whole)) {
            Ok(s) => Ok(vec![s]),
            Err(_) => whole
                .char_indices()
                .map(|(i, c)| lookup((at + i, &whole[i..i + c.len_utf8()])))
                .collect(),
        },
        _ => tokens.iter().copied().map(lookup).collect(),
    }
}
