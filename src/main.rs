//! The `lsubdiv` command line: parses the arguments (clap) and dispatches to one module per
//! command (`commands/`). Every failure is one diagnostic ([`Error`]), rendered here only.
//! Exit status: 0 ok, 2 bad input (scheme, points, labels, flags), 1 internal error; a closed
//! standard output ends it by SIGPIPE (141 in a shell), as it ends `cat`.

mod commands;

use clap::{Parser, Subcommand};
use commands::{
    bench, codegen, curve, demo, ev, explore, graph, inspect, plot, render, schemes, subdivide,
};
use lsubdiv::compiler::Error;
use std::process::ExitCode;

#[derive(Parser)]
#[command(
    name = "lsubdiv",
    version,
    about = "Exact non-uniform B-spline subdivision from L-systems"
)]
struct Cli {
    #[command(subcommand)]
    command: Option<Command>,
}
#[derive(Subcommand)]
enum Command {
    /// Validity, M, ρ, lengths, eigenvectors, masks (exact and f64), SCCs, transitional steps.
    Inspect(inspect::InspectArgs),
    /// The transition graph between (d+1)-words: DOT, or a picture ([N] Fig. 3).
    Graph(graph::GraphArgs),
    /// Writes the generated Rust source of a scheme.
    Codegen(codegen::CodegenArgs),
    /// Refines a control polygon (one point per line, 2 or 3 coordinates).
    Curve(curve::CurveArgs),
    /// Draws control polygons of successive steps and the limit curve, coloured by interval
    /// label ([N] Fig. 2), as SVG or PNG (by the output's extension).
    Plot(plot::PlotArgs),
    /// α and the spectrum at extraordinary vertices (\[G\] §4.2.3), per valence.
    Ev(ev::EvArgs),
    /// Refines a polygon mesh (OBJ or PLY) of any topology: open or closed, creases, corners, holes.
    Subdivide(subdivide::SubdivideArgs),
    /// Times surface refinement: one JSON object per line with output vertices/s and peak RSS.
    Bench(bench::BenchArgs),
    /// Draws a mesh, open or closed, to a PNG or PPM image (software, no GPU): flat, smooth,
    /// mean-curvature or reflection-line shading ([G] Fig. 6), optionally with its quad edges.
    Render(render::RenderArgs),
    /// Lists the shipped schemes.
    Schemes,
    /// The L-systems of a [G] §5.2 family, exactly, sorted by ρ then masks (Appendix B).
    Enumerate(explore::EnumerateArgs),
    /// Searches symmetric L-systems for the Pareto front of (ρ, masks).
    Search(explore::SearchArgs),
}

fn main() -> ExitCode {
    // A closed standard output (`lsubdiv … | head`) ends the program as it ends `cat`: quietly,
    // by SIGPIPE (status 141 in a shell). Rust ignores the signal by default, so that each
    // write fails instead, and `println!` panics on the failure.
    #[cfg(unix)]
    // SAFETY: restoring a signal's default action, before any thread is started.
    unsafe {
        libc::signal(libc::SIGPIPE, libc::SIG_DFL);
    }
    let cli = Cli::parse();
    // Ctrl-C, SIGTERM, SIGHUP: outputs are replaced by a rename only, so an interrupted run
    // leaves the previous ones intact; remove the temporary file being written, if any.
    // (Nothing can be done on SIGKILL: a hidden `.NAME.PID.N.tmp` may then remain.)
    let _ = ctrlc::set_handler(|| {
        lsubdiv_cli::output::remove_partial_files();
        std::process::exit(130);
    });
    let hint = where_to_look(cli.command.as_ref());
    match run(cli.command) {
        Ok(()) => ExitCode::SUCCESS,
        Err(e) => {
            let e = if e.is_internal() {
                e.or_hint(
                    "this is a bug in lsubdiv: please report it, with the command and its inputs",
                )
            } else {
                e.or_hint(hint)
            };
            eprintln!("{e}");
            ExitCode::from(if e.is_internal() { 1 } else { 2 })
        }
    }
}

/// The hint of a refusal that has no more particular one: where the command's inputs and
/// options are described.
fn where_to_look(command: Option<&Command>) -> &'static str {
    match command {
        Some(Command::Subdivide(_) | Command::Bench(_) | Command::Render(_)) => {
            "docs/cli.md describes mesh files, their tags and the options; docs/real-meshes.md \
             what each feature does"
        }
        Some(Command::Curve(_) | Command::Plot(_)) => {
            "docs/cli.md describes point files, labels and the options"
        }
        Some(
            Command::Inspect(_)
            | Command::Graph(_)
            | Command::Codegen(_)
            | Command::Ev(_)
            | Command::Enumerate(_)
            | Command::Search(_),
        ) => "docs/schemes.md describes scheme files; `lsubdiv help COMMAND` the options",
        Some(Command::Schemes) | None => "`lsubdiv help` lists the commands and their options",
    }
}

fn run(command: Option<Command>) -> Result<(), Error> {
    match command {
        None => demo::run(),
        Some(Command::Inspect(a)) => inspect::run(a),
        Some(Command::Graph(a)) => graph::run(a),
        Some(Command::Codegen(a)) => codegen::run(a),
        Some(Command::Curve(a)) => curve::run(a),
        Some(Command::Plot(a)) => plot::run(a),
        Some(Command::Ev(a)) => ev::run(a),
        Some(Command::Subdivide(a)) => subdivide::run(a),
        Some(Command::Bench(a)) => bench::run(a),
        Some(Command::Render(a)) => render::run(&a),
        Some(Command::Schemes) => schemes::run(),
        Some(Command::Enumerate(a)) => explore::enumerate(a),
        Some(Command::Search(a)) => explore::search(a),
    }
}
