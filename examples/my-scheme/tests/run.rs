//! Runs `my-scheme` as a user would, on its cube and on the cube as an OBJ file, and checks
//! the OBJ it writes against counts predicted from the scheme's own tables (so any scheme works).

use std::path::Path;
use std::process::Command;

lsubdiv::include_scheme!(my_scheme);

/// Quads after three steps of the mesh `faces` quads: each face becomes n × n, n = |π³(axiom)|.
fn expected_quads(faces: usize) -> u128 {
    let n = my_scheme::TABLES.image_len(my_scheme::TABLES.axiom, 3);
    faces as u128 * n * n
}

fn run(args: &[&Path]) -> String {
    let out = Command::new(env!("CARGO_BIN_EXE_my-scheme"))
        .args(args)
        .output()
        .expect("my-scheme runs");
    let stdout = String::from_utf8_lossy(&out.stdout).into_owned();
    assert!(
        out.status.success(),
        "{stdout}{}",
        String::from_utf8_lossy(&out.stderr)
    );
    stdout
}

fn quads_in(path: &Path) -> u128 {
    let text = std::fs::read_to_string(path).unwrap();
    let parsed = lsubdiv::obj::parse(&path.display().to_string(), &text).expect("valid OBJ");
    parsed.mesh.face_count() as u128
}

#[test]
fn refines_the_cube_and_an_obj_file() {
    let dir = std::env::temp_dir().join(format!("my-scheme-test-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let out = dir.join("cube.obj");
    let stdout = run(&[&out]);
    assert!(stdout.contains("polygon: 6 points"), "{stdout}");
    assert_eq!(quads_in(&out), expected_quads(6));

    // The same cube as an OBJ file: the same output, to the byte.
    let input = dir.join("in.obj");
    let cube = "v -1 -1 -1\nv 1 -1 -1\nv 1 1 -1\nv -1 1 -1\nv -1 -1 1\nv 1 -1 1\nv 1 1 1\n\
                v -1 1 1\nf 1 4 3 2\nf 5 6 7 8\nf 1 2 6 5\nf 2 3 7 6\nf 3 4 8 7\nf 4 1 5 8\n";
    std::fs::write(&input, cube).unwrap();
    let again = dir.join("again.obj");
    run(&[&again, &input]);
    assert_eq!(std::fs::read(&again).unwrap(), std::fs::read(&out).unwrap());
    std::fs::remove_dir_all(&dir).unwrap();
}
