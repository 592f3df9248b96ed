//! Refines an OBJ or PLY mesh (its creases, corners and holes, its texture coordinates) to the
//! limit surface of a shipped scheme, and writes it with normals and texture coordinates.
//!
//! Usage: `my-app IN.obj OUT.obj [SCHEME]` (default: fibonacci).

fn main() -> std::process::ExitCode {
    let args: Vec<String> = std::env::args().skip(1).collect();
    let [input, output, scheme @ ..] = &args[..] else {
        eprintln!("usage: my-app IN.obj OUT.obj [SCHEME]");
        return std::process::ExitCode::from(2);
    };
    match refine(input, output, scheme.first().map_or("fibonacci", |s| s)) {
        Ok(()) => std::process::ExitCode::SUCCESS,
        Err(e) => {
            eprintln!("error: {e}"); // file:line: what is wrong, and a hint
            std::process::ExitCode::FAILURE
        }
    }
}

fn refine(input: &str, output: &str, scheme: &str) -> Result<(), lsubdiv::Error> {
    let scheme = lsubdiv::Scheme::shipped(scheme)?;
    let mesh = lsubdiv::Mesh::read(input)?;
    let plan = lsubdiv::Refiner::new(&scheme, &mesh)
        .steps(3)
        .limit(true)
        .build()?;
    let fine = plan.refine()?;
    fine.write(output)?; // positions, normals, texture coordinates: whole or not at all
    let (faces, quads) = (mesh.faces().count(), fine.mesh.faces.len());
    println!(
        "{input}: {faces} faces → {quads} quads on {}'s limit surface",
        scheme.name()
    );
    Ok(())
}
