//! A user's program with a scheme of its own: `schemes/my_scheme.toml`, compiled by `build.rs`,
//! refines a closed 3D polygon and a mesh (an OBJ or PLY file, or a cube), written as OBJ.
//!
//! Usage: `my-scheme OUT.obj [IN.obj|IN.ply]`.

use std::f64::consts::TAU;

lsubdiv::include_scheme!(my_scheme); // pub mod my_scheme { Scheme, TABLES, RHO, … }

/// A cube, as an OBJ file holds it.
const CUBE: &str = "v -1 -1 -1\nv 1 -1 -1\nv 1 1 -1\nv -1 1 -1\nv -1 -1 1\nv 1 -1 1\nv 1 1 1\n\
                    v -1 1 1\nf 1 4 3 2\nf 5 6 7 8\nf 1 2 6 5\nf 2 3 7 6\nf 3 4 8 7\nf 4 1 5 8\n";

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let args: Vec<String> = std::env::args().skip(1).collect();
    let output = args.first().ok_or("usage: my-scheme OUT.obj [IN.obj]")?;
    let scheme = lsubdiv::Scheme::compiled(&my_scheme::Scheme);

    // A closed polygon in 3D, every interval labelled by the axiom, refined four times.
    let polygon: Vec<[f64; 3]> = (0..6)
        .map(|i| {
            let t = TAU * f64::from(i) / 6.0;
            [t.cos(), t.sin(), if i % 2 == 0 { 0.3 } else { -0.3 }]
        })
        .collect();
    let coarse = lsubdiv::Curve::with_axiom(&my_scheme::TABLES, polygon, true);
    let fine = scheme.refine_curve(&coarse, 4)?;
    let (before, after) = (coarse.points.len(), fine.points.len());
    println!("polygon: {before} points → {after} points");

    // A mesh of any topology, open or closed, refined three steps.
    let mesh = match args.get(1) {
        Some(input) => lsubdiv::Mesh::read(input)?,
        None => lsubdiv::Mesh::parse("cube.obj", CUBE.as_bytes().to_vec())?,
    };
    let fine = lsubdiv::Refiner::new(&scheme, &mesh)
        .steps(3)
        .build()?
        .refine()?;
    fine.write(output)?; // whole or not at all
    let (before, after) = (mesh.faces().count(), fine.mesh.faces.len());
    println!("mesh: {before} faces → {after} quads, written to {output}");
    Ok(())
}
