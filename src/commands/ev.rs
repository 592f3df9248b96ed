//! `lsubdiv ev`: α and the spectrum at extraordinary vertices ([G] §4.2.3), and the
//! characteristic map ([G] Fig. 4).

use crate::commands::{build, load};
use lsubdiv::compiler::Error;
use lsubdiv_cli::input_error;
use lsubdiv_cli::report;

/// Arguments of `lsubdiv ev`.
#[derive(clap::Args)]
pub struct EvArgs {
    scheme: String,
    /// A valence `n` or a range `a..b` (inclusive).
    #[arg(long, default_value = "3..16")]
    valence: String,
    /// One JSON object per valence, in an array.
    #[arg(long)]
    json: bool,
    /// Draw the characteristic map's control net at the (single) valence ([G] Fig. 4).
    #[arg(long, requires = "output")]
    characteristic_map: bool,
    /// Output picture of --characteristic-map: `.svg` or `.png`; SVG for a name without an
    /// extension (`-`: standard output).
    #[arg(short, long, requires = "characteristic_map")]
    output: Option<std::path::PathBuf>,
    /// Picture size in pixels, WxH.
    #[arg(long, default_value = "800x800")]
    size: String,
    #[command(flatten)]
    limit: crate::commands::args::MemoryLimit,
}

/// The spectrum per valence, or the characteristic map's picture.
pub fn run(a: EvArgs) -> Result<(), Error> {
    match &a.output {
        Some(out) if a.characteristic_map => charmap(&a, out),
        _ => ev_report(&a.scheme, &a.valence, a.json),
    }
}

/// Parses `n`, `a..b` or `a..=b` (both inclusive).
/// The largest valence `ev` analyses (meshes have no limit: their EVs are refined whatever
/// their valence).
const MAX_VALENCE: usize = 10_000;

fn valences(text: &str) -> Result<std::ops::RangeInclusive<usize>, Error> {
    let bad_range = || {
        Error::input(format!(
            "--valence `{text}`: expected `n` or `a..b` with 2 ≤ a ≤ b ≤ {MAX_VALENCE}"
        ))
    };
    let parse = |s: &str| s.trim().parse::<usize>().map_err(|_| bad_range());
    let (a, b) = match text.split_once("..") {
        Some((a, b)) => (parse(a)?, parse(b.trim_start_matches('='))?),
        None => {
            let n = parse(text)?;
            (n, n)
        }
    };
    if a < 2 || b < a || b > MAX_VALENCE {
        return Err(bad_range());
    }
    Ok(a..=b)
}

/// `lsubdiv ev`: α, λ1, λ2, μ0 and the EV normalisation per valence.
fn ev_report(scheme: &str, valence: &str, json: bool) -> Result<(), Error> {
    let range = valences(valence)?;
    let s = build(&load(scheme, None)?)?;
    let a = lsubdiv::compiler::exact::ev::analyse(&s)?;
    let c = a.coefficients_f64();
    let mut rows = Vec::new();
    let two = *range.start() == 2;
    for n in range {
        let sp = c.spectrum(n).map_err(input_error)?;
        rows.push(sp);
    }
    if json {
        let v: Vec<serde_json::Value> = rows
            .iter()
            .map(|sp| {
                serde_json::json!({
                    "n": sp.n, "alpha": sp.alpha, "lambda1": sp.lambda1, "lambda2": sp.lambda2,
                    "mu0": sp.mu0, "normalisation": sp.normalisation,
                })
            })
            .collect();
        println!("{}", serde_json::Value::Array(v));
    } else {
        print!("{}", report::ev_text(&s, &a, &rows));
        if two {
            println!(
                "valence 2: no alpha gives mu0 = lambda1^2 (two faces share both edges at the vertex; \
                 Fourier index 2 is index 0 there): alpha gives the vertex Catmull-Clark's weight \
                 1/8, as OpenSubdiv refines it"
            );
        }
    }
    Ok(())
}

/// `lsubdiv ev --characteristic-map`: finds the control net numerically, checks λ1 against
/// the closed form, draws it ([`lsubdiv_cli::charmap`]).
fn charmap(a: &EvArgs, output: &std::path::Path) -> Result<(), Error> {
    use lsubdiv_cli::picture;
    let (scheme, valence) = (&a.scheme, &a.valence);
    picture::format_of(output)?;
    let size = picture::parse_size(&a.size)?;
    let range = valences(valence)?;
    let n = *range.start();
    if range.end() != range.start() {
        return Err(Error::input(format!(
            "--characteristic-map draws one valence; --valence {valence} is a range"
        )));
    }
    // The power iteration's net grows with n (about 0.4 s per valence unit in debug builds);
    // beyond this the picture's n-fold sectors are thinner than its lines anyway.
    const MAX_MAP_VALENCE: usize = 100;
    if n < 3 {
        return Err(Error::input(format!(
            "--characteristic-map draws valences 3 to {MAX_MAP_VALENCE}: at valence 2 the limit \
             has no tangent plane"
        )));
    }
    if n > MAX_MAP_VALENCE {
        return Err(Error::input(format!(
            "--characteristic-map draws valences 3 to {MAX_MAP_VALENCE}; --valence {n} is beyond"
        )));
    }
    let s = build(&load(scheme, None)?)?;
    let name = s.ls.name.clone();
    let rho = s.analysis.rho.to_f64();
    let surface = lsubdiv::generic::GenericSurface::new(s)?;
    let closed = surface
        .analysis()
        .coefficients_f64()
        .spectrum(n)
        .map_err(input_error)?
        .lambda1;
    // Refine the net until its quads are about a quarter of the net's.
    let steps = (4f64.ln() / rho.ln()).ceil().max(1.0) as usize;
    let bar = indicatif::ProgressBar::new_spinner().with_message("power iteration");
    let map = lsubdiv_cli::charmap::characteristic_map(&surface, n, steps, &|i| {
        bar.set_position(i as u64)
    })?;
    bar.finish_and_clear();
    println!(
        "{name}, valence {n}: lambda1 = {:.15} by power iteration on the {}-ring neighbourhood after {} steps ({} iterations, residual {:.1e}); closed form {:.15}",
        map.lambda, map.k, map.step, map.iterations, map.residual, closed
    );
    if (map.lambda - closed).abs() > 1e-9 * closed.abs() {
        return Err(Error::internal(
            None,
            format!(
                "the numeric subdominant eigenvalue {} differs from the closed form {closed}",
                map.lambda
            ),
        ));
    }
    picture::save(
        &lsubdiv_cli::charmap::picture(&name, &map, closed, size),
        output,
        a.limit.bytes(),
    )
}
