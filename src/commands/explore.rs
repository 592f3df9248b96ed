//! `lsubdiv enumerate` and `lsubdiv search`: the explorer's [G] §5.2 families and the Pareto
//! search ([`lsubdiv_explorer`]).

use crate::commands::args::TableArgs;
use crate::commands::check_degree;
use lsubdiv::compiler::exact::scheme::parse_rational;
use lsubdiv::compiler::Error;

/// Arguments of `lsubdiv enumerate`.
#[derive(clap::Args)]
pub struct EnumerateArgs {
    /// lcr (eq. 44), slcr (45), lcdr (46), slcdr (47), or all.
    #[arg(long)]
    family: String,
    /// Longest π(C).
    #[arg(long, default_value_t = 3)]
    max_word_len: usize,
    /// Lift the paper's constraints on π(C) (symmetry, first and last letters; S allowed).
    #[arg(long)]
    unconstrained: bool,
    /// Keep integer ratios (Remark 5.5 leaves them out).
    #[arg(long)]
    include_integer: bool,
    /// Spline degree.
    #[arg(long, default_value_t = 3)]
    degree: usize,
    #[command(flatten)]
    out: TableArgs,
}

/// The explorer's search options ([`lsubdiv_explorer::Search`]) as flags.
#[derive(clap::Args)]
pub struct SearchOptions {
    /// Alphabet size (2 to 6).
    #[arg(long)]
    symbols: usize,
    /// Longest rule (1 to 4).
    #[arg(long)]
    max_word_len: usize,
    /// Smallest ρ, exact (an integer, a fraction a/b or a decimal).
    #[arg(long)]
    rho_min: Option<String>,
    /// Largest ρ, exact.
    #[arg(long)]
    rho_max: Option<String>,
    /// Most masks (mirror pairs counted once).
    #[arg(long)]
    max_masks: Option<usize>,
    /// Keep only surface schemes ([G] §4.2: stationary and contained).
    #[arg(long)]
    require_surface: bool,
    /// Keep integer ratios.
    #[arg(long)]
    include_integer: bool,
    /// Also examine rule sets without an involution (curve schemes only).
    #[arg(long)]
    asymmetric: bool,
    /// Most rule sets examined (the whole space when smaller, else a deterministic sample).
    #[arg(long, default_value_t = 300_000)]
    limit: u64,
    /// Spline degree.
    #[arg(long, default_value_t = 3)]
    degree: usize,
}

/// Arguments of `lsubdiv search`.
#[derive(clap::Args)]
pub struct SearchArgs {
    #[command(flatten)]
    search: SearchOptions,
    #[command(flatten)]
    out: TableArgs,
}

impl SearchOptions {
    /// The checked options, ρ bounds exact.
    fn to_search(&self) -> Result<lsubdiv_explorer::Search, Error> {
        let (symbols, max_word_len) = (self.symbols, self.max_word_len);
        if !(2..=6).contains(&symbols) || !(1..=4).contains(&max_word_len) {
            return Err(Error::input(format!(
                "--symbols {symbols} must be 2 to 6 and --max-word-len {max_word_len} 1 to 4"
            )));
        }
        check_degree(self.degree)?;
        let rho =
            |flag: &str, t: &Option<String>| t.as_deref().map(|t| rational(flag, t)).transpose();
        Ok(lsubdiv_explorer::Search {
            symbols,
            max_word_len,
            rho_min: rho("--rho-min", &self.rho_min)?,
            rho_max: rho("--rho-max", &self.rho_max)?,
            max_masks: self.max_masks,
            require_surface: self.require_surface,
            include_integer: self.include_integer,
            asymmetric: self.asymmetric,
            limit: self.limit,
            degree: self.degree,
        })
    }
}

/// Lists the L-systems of the family (or all families).
pub fn enumerate(a: EnumerateArgs) -> Result<(), Error> {
    let EnumerateArgs {
        family,
        max_word_len,
        unconstrained,
        include_integer,
        degree,
        out,
    } = a;
    use lsubdiv_explorer::{enumerate, Enumeration, Family};
    let families = match family.as_str() {
        "all" => Family::ALL.to_vec(),
        f => vec![Family::parse(f).ok_or_else(|| {
            Error::input(format!(
                "--family {f}: expected lcr, slcr, lcdr, slcdr or all"
            ))
        })?],
    };
    if !(1..=6).contains(&max_word_len) {
        return Err(Error::input(format!(
            "--max-word-len {max_word_len} must be 1 to 6"
        )));
    }
    check_degree(degree)?;
    let opts = Enumeration {
        max_word_len,
        unconstrained,
        include_integer,
        degree,
    };
    let mut rows = Vec::new();
    for f in families {
        rows.extend(enumerate(f, opts)?);
    }
    out.emit(&rows)
}

/// Prints the Pareto front of (ρ, masks) and a summary of the search on stderr.
pub fn search(a: SearchArgs) -> Result<(), Error> {
    let opts = a.search.to_search()?;
    let bar = lsubdiv_cli::progress::bar(0, "rule sets");
    let found = lsubdiv_explorer::search(&opts, &|done, total| {
        bar.set_length(total);
        bar.set_position(done);
    })?;
    bar.finish_and_clear();
    eprintln!(
        "searched {} of {} rule sets ({}); {} distinct candidates; {} on the Pareto front",
        found.examined,
        found.space,
        if u128::from(found.examined) == found.space {
            "all"
        } else {
            "a deterministic sample"
        },
        found.candidates,
        found.front.len()
    );
    a.out.emit(&found.front)
}

/// An exact rational from `3`, `7/2` or `1.45` (the compiler's one parser).
fn rational(flag: &str, text: &str) -> Result<num_rational::BigRational, Error> {
    parse_rational(text).map_err(|e| Error::input(format!("{flag} {e}")))
}
