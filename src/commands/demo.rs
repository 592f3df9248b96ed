//! The default job (no command): the shipped Fibonacci scheme, a curve and a surface refined
//! by both paths.

use crate::commands::{bad, build, load, Failure};
use lsubdiv::compiler::exact::generic::GenericScheme;
use lsubdiv::compiler::exact::validity::analyse;
use lsubdiv::Curve;
use lsubdiv_cli::report;

/// The default job: inspect the shipped Fibonacci scheme and refine a closed polygon with both
/// paths, checking that they agree bit for bit.
pub fn run() -> Result<(), Failure> {
    let r = load("fibonacci", None)?;
    let a = analyse(&r.ls)?;
    let s = build(&r)?;
    print!("{}", report::text(&r.ls, &a, Some(&s)));
    let n = 12;
    let polygon: Vec<[f64; 3]> = (0..n)
        .map(|i| {
            let t = std::f64::consts::TAU * i as f64 / n as f64;
            [t.cos(), t.sin(), if i % 2 == 0 { 0.25 } else { -0.25 }]
        })
        .collect();
    let generic = GenericScheme::new(s);
    let curve = Curve::with_axiom(&lsubdiv::CurveScheme::tables(&generic), polygon, true);
    let steps = 8;
    let a = lsubdiv::refine(&generic, &curve, steps).map_err(|e| bad(e.to_string()))?;
    let b = lsubdiv::generated::refine_curve(&r.ls.name, &curve, steps)
        .ok_or_else(|| bad("fibonacci is not generated".into()))?
        .map_err(|e| bad(e.to_string()))?;
    println!(
        "\nrefined a closed {n}-gon {steps} times: {} points; generic and generated paths {}",
        a.points.len(),
        if a == b {
            "agree bit for bit"
        } else {
            "DIFFER"
        }
    );
    if a != b {
        return Err(Failure {
            code: 1,
            message: "internal error: generic and generated paths differ".into(),
        });
    }
    // A surface: the cube (eight 3-valent EVs), three Binary-Ternary steps, both paths.
    let cube = lsubdiv::runtime::generators::cube();
    let surface = lsubdiv::compiler::exact::generic::GenericSurface::new(build(&load(
        "binary-ternary",
        None,
    )?)?)?;
    let generic = lsubdiv::runtime::patch::subdivide::<_, f64>(&surface, &cube, 3, 2)
        .map_err(|e| bad(e.to_string()))?;
    let generated = lsubdiv::generated::subdivide::<f64>("binary-ternary", &cube, 3, 1)
        .ok_or_else(|| bad("binary-ternary is not generated".into()))?
        .map_err(|e| bad(e.to_string()))?;
    let same = generic == generated;
    println!(
        "refined the cube 3 times with binary-ternary: {} vertices, {} quads; generic (2 threads) and generated (1 thread) paths {}",
        generic.positions.len(),
        generic.faces.len(),
        if same { "agree bit for bit" } else { "DIFFER" }
    );
    if !same {
        return Err(Failure {
            code: 1,
            message: "internal error: generic and generated surface paths differ".into(),
        });
    }
    Ok(())
}
