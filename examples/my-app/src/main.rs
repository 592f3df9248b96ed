//! A user's program: the scheme of `schemes/my_scheme.toml`, compiled by `build.rs`, refines a
//! closed 3D polygon and a quad mesh (an OBJ or PLY file, or the cube), and writes the mesh as
//! OBJ.
//!
//! Usage: `my-app OUT.obj [IN.obj|IN.ply]`.

use std::f64::consts::TAU;
use std::path::PathBuf;

lsubdiv::include_scheme!(my_scheme); // pub mod my_scheme { Scheme, TABLES, RHO, … }

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let mut args = std::env::args_os().skip(1).map(PathBuf::from);
    let output = args.next().ok_or("usage: my-app OUT.obj [IN.obj]")?;

    // A closed polygon in 3D, every interval labelled by the axiom, refined four times.
    let polygon: Vec<[f64; 3]> = (0..6)
        .map(|i| {
            let t = TAU * f64::from(i) / 6.0;
            [t.cos(), t.sin(), if i % 2 == 0 { 0.3 } else { -0.3 }]
        })
        .collect();
    let coarse = lsubdiv::Curve::with_axiom(&my_scheme::TABLES, polygon, true);
    let fine = lsubdiv::refine(&my_scheme::Scheme, &coarse, 4)?;
    let (before, after) = (coarse.points.len(), fine.points.len());
    println!("polygon: {before} points → {after} points");

    // A quad mesh of any topology, open or closed: read (OBJ or PLY, at most 1 GiB; errors
    // name the file's line; creases, corners and holes from OBJ `t` tags) or built.
    let (mesh, topology, features) = match args.next() {
        Some(input) => {
            let read = lsubdiv::read_mesh(&input, 1 << 30)?;
            (read.mesh, read.topology, read.features)
        }
        None => {
            let cube = lsubdiv::mesh::generators::cube();
            let topology = lsubdiv::mesh::topology::Topology::build(&cube)?;
            (cube, topology, Default::default())
        }
    };
    let threads = std::thread::available_parallelism().map_or(1, usize::from);
    let fine = lsubdiv::mesh::patch::subdivide_with::<_, f64>(
        &my_scheme::Scheme,
        &mesh,
        &topology,
        &features,
        3,
        threads,
    )?;
    lsubdiv::obj::write(&output, &fine)?; // whole or not at all
    println!(
        "mesh: {} quads → {} quads, written to {}",
        mesh.faces.len(),
        fine.faces.len(),
        output.display()
    );
    Ok(())
}
