//! The default job (no command): a short tour. Compiles the shipped Fibonacci scheme exactly,
//! refines a closed polygon and the cube by the generic and the generated implementation,
//! checks that they agree bit for bit, and says what to try next. Every number is computed.

use crate::commands::args::polygon;
use crate::commands::{build, load};
use lsubdiv::compiler::exact::Scheme;
use lsubdiv::compiler::Error;
use lsubdiv::generic::{GenericScheme, GenericSurface};
use lsubdiv::mesh::patch::Subdivide;
use lsubdiv::mesh::surface::SurfaceVisitor;
use lsubdiv::mesh::topology::Topology;
use lsubdiv_cli::implementation::{Geometry, PathChoice};
use lsubdiv_cli::input_error;
use std::time::Instant;

/// Runs `f` and returns its result with the time it took, in milliseconds.
fn timed<T>(f: impl FnOnce() -> T) -> (T, f64) {
    let t = Instant::now();
    let out = f();
    (out, t.elapsed().as_secs_f64() * 1e3)
}

/// The number field the masks' weights live in: `Q`, `Q(√m)`, or `Q(ρ)` with ρ's minimal
/// polynomial.
fn field_name(s: &Scheme) -> String {
    let rho = &s.analysis.rho;
    match rho.quadratic_parts() {
        Some((_, _, m)) => format!("Q(√{m})"),
        None if rho.as_rational().is_some() => "Q".into(),
        None => format!("Q(ρ), ρ a root of {}", rho.field().minpoly()),
    }
}

/// Fails (internal error) when the two implementations differ.
fn agree(what: &str, same: bool) -> Result<&'static str, Error> {
    if same {
        Ok("agree bit for bit")
    } else {
        Err(Error::internal(
            None,
            format!("generic and generated {what} paths differ"),
        ))
    }
}

/// The tour.
pub fn run() -> Result<(), Error> {
    println!("lsubdiv: exact non-uniform B-spline subdivision from L-systems ([N], [G])\n");

    // The curve scheme: compiled exactly from its L-system ([N] §3–4).
    let r = load("fibonacci", None)?;
    PathChoice::Generated.pick(&r, Geometry::Curve)?;
    let (s, ms) = timed(|| build(&r));
    let s = s?;
    let transitional = s.graph.words.iter().filter(|w| w.transitional).count();
    println!(
        "scheme {} ({}): degree {}, {} symbols, compiled in {ms:.0} ms",
        r.ls.name,
        r.ls.source.file,
        r.ls.degree,
        r.ls.symbols.len()
    );
    println!(
        "  ρ = {} ≈ {:.6}; {} masks ({transitional} transitional), every weight exact in {}",
        s.analysis.rho,
        s.analysis.rho.to_f64(),
        s.masks.len(),
        field_name(&s)
    );

    let n = 12;
    let points: Vec<[f64; 3]> = (0..n)
        .map(|i| {
            let t = std::f64::consts::TAU * i as f64 / n as f64;
            [t.cos(), t.sin(), if i % 2 == 0 { 0.25 } else { -0.25 }]
        })
        .collect();
    let generic = GenericScheme::new(s)?;
    let curve = polygon(&r, &generic, points, true, None)?;
    let steps = 8;
    let (a, generic_ms) = timed(|| lsubdiv::refine(&generic, &curve, steps));
    let a = a.map_err(input_error)?;
    let (b, generated_ms) = timed(|| lsubdiv::generated::refine_curve(&r.ls.name, &curve, steps));
    let b = b
        .ok_or_else(|| Error::internal(None, "fibonacci is not in the registry"))?
        .map_err(input_error)?;
    println!(
        "curve: a closed {n}-gon refined {steps} times: {} points",
        a.points.len()
    );
    println!(
        "  generic and generated paths {} (generic {generic_ms:.1} ms, generated {generated_ms:.1} ms)",
        agree("curve", a == b)?
    );

    // A surface ([G] §4): the cube's corners are extraordinary vertices.
    let cube = lsubdiv::mesh::generators::cube();
    let mut valence = vec![0usize; cube.positions.len()];
    cube.faces
        .iter()
        .flatten()
        .for_each(|&v| valence[v as usize] += 1);
    let mut evs: Vec<usize> = valence.iter().copied().filter(|&k| k != 4).collect();
    evs.sort_unstable();
    evs.dedup();
    let ev_count = valence.iter().filter(|&&k| k != 4).count();
    let r = load("binary-ternary", None)?;
    PathChoice::Generated.pick(&r, Geometry::Surface)?;
    let surface = GenericSurface::new(build(&r)?)?;
    let steps = 3;
    let topology = Topology::build(&cube).map_err(|e| Error::internal(None, e.to_string()))?;
    let features = Default::default();
    let job = |threads| Subdivide {
        mesh: &cube,
        topology: &topology,
        features: &features,
        steps,
        threads,
        limit: false,
    };
    let (generic, generic_ms) = timed(|| job(2).visit(&surface));
    let generic = generic.map_err(input_error)?;
    let (generated, generated_ms) = timed(|| lsubdiv::generated::visit_surface(&r.ls.name, job(1)));
    let generated = generated
        .ok_or_else(|| Error::internal(None, "binary-ternary is not in the registry"))?
        .map_err(input_error)?;
    println!(
        "surface: the cube ({ev_count} extraordinary vertices of valence {}), {steps} steps of {}: {} vertices, {} quads",
        evs.iter().map(usize::to_string).collect::<Vec<_>>().join(", "),
        r.ls.name,
        generic.mesh.positions.len(),
        generic.mesh.faces.len()
    );
    println!(
        "  generic (2 threads) and generated (1 thread) paths {} (generic {generic_ms:.1} ms, generated {generated_ms:.1} ms)",
        agree("surface", generic == generated)?
    );

    println!("\nwhat to try next:");
    let next = [
        ("lsubdiv inspect fibonacci", "every mask, exactly"),
        ("lsubdiv schemes", "the shipped schemes"),
        (
            "lsubdiv subdivide binary-ternary --steps 3 mesh.obj -o out.obj",
            "your mesh: open or closed, any polygons, OBJ creases and holes",
        ),
        (
            "lsubdiv subdivide fibonacci --steps 3 mesh.obj -o on.obj --limit",
            "on the limit surface: points, normals, texture coordinates",
        ),
        (
            "lsubdiv render cube --scheme binary-ternary --steps 3 -o cube.png",
            "a picture",
        ),
        ("lsubdiv plot fibonacci -o fibonacci.svg", "[N] Fig. 2"),
    ];
    let width = next.iter().map(|(c, _)| c.len()).max().unwrap_or(0);
    for (command, what) in next {
        println!("  {command:<width$}  # {what}");
    }
    Ok(())
}
