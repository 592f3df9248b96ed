//! Runs `my-app` as a user would on an OBJ file with a crease, a corner and texture coordinates,
//! and checks what it writes: counts predicted from the scheme's own tables, a normal per vertex,
//! texture coordinates per corner, the crease's vertices on the crease's limit curve, and the
//! refusal of an unknown scheme.

use std::path::{Path, PathBuf};
use std::process::{Command, Output};

/// A cube cut open at the top (five quads, one boundary loop), with a crease around its
/// bottom, a sharp corner, and a texture layout.
const BOX: &str = "v -1 -1 -1\nv 1 -1 -1\nv 1 1 -1\nv -1 1 -1\nv -1 -1 1\nv 1 -1 1\nv 1 1 1\n\
    v -1 1 1\nvt 0 0\nvt 1 0\nvt 1 1\nvt 0 1\n\
    f 1/1 4/2 3/3 2/4\nf 1/1 2/2 6/3 5/4\nf 2/1 3/2 7/3 6/4\nf 3/1 4/2 8/3 7/4\nf 4/1 1/2 5/3 8/4\n\
    t crease 2/1/0 0 1 10\nt crease 2/1/0 1 2 10\nt crease 2/1/0 2 3 10\nt crease 2/1/0 3 0 10\n\
    t corner 1/1/0 6 10\n";

fn run(args: &[&Path]) -> Output {
    Command::new(env!("CARGO_BIN_EXE_my-app"))
        .args(args)
        .output()
        .expect("my-app runs")
}

fn scratch() -> PathBuf {
    let dir = std::env::temp_dir().join(format!("my-app-test-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    dir
}

#[test]
fn refines_an_obj_with_creases_and_uvs_to_the_limit() {
    let dir = scratch();
    let input = dir.join("box.obj");
    std::fs::write(&input, BOX).unwrap();
    for (scheme, tables) in [
        ("fibonacci", lsubdiv::generated::fibonacci::TABLES),
        ("uniform-binary", lsubdiv::generated::uniform_binary::TABLES),
    ] {
        let output = dir.join(format!("{scheme}.obj"));
        let out = run(&[&input, &output, Path::new(scheme)]);
        let stdout = String::from_utf8_lossy(&out.stdout);
        assert!(
            out.status.success(),
            "{stdout}{}",
            String::from_utf8_lossy(&out.stderr)
        );
        assert!(stdout.contains("5 faces"), "{stdout}");
        let text = std::fs::read_to_string(&output).unwrap();
        let count = |tag: &str| text.lines().filter(|l| l.starts_with(tag)).count();
        // Three steps: each quad becomes n × n, n = |π³(axiom)|.
        let n = tables.image_len(tables.axiom, 3) as usize;
        assert_eq!(count("f "), 5 * n * n, "{scheme}");
        assert_eq!(count("vn "), count("v "), "{scheme}: a normal per vertex");
        assert!(count("vt ") > 0, "{scheme}: texture coordinates");
        let corner = text.lines().find(|l| l.starts_with("f ")).unwrap();
        assert_eq!(
            corner.split(' ').nth(1).unwrap().split('/').count(),
            3,
            "{corner}"
        );
        // The bottom quad is bounded by infinitely sharp creases, so its (n + 1)² refined
        // vertices come from its own corners: they stay at z = −1 (to rounding). Without the
        // creases, none would.
        let on_bottom = text
            .lines()
            .filter_map(|l| l.strip_prefix("v "))
            .filter(|l| l.split(' ').nth(2).unwrap().parse::<f64>().unwrap() < -1.0 + 1e-12)
            .count();
        assert_eq!(on_bottom, (n + 1) * (n + 1), "{scheme}: vertices at z = −1");
    }
    let unknown = run(&[&input, &dir.join("x.obj"), Path::new("fibonaci")]);
    assert!(!unknown.status.success());
    let stderr = String::from_utf8_lossy(&unknown.stderr);
    assert!(
        stderr.contains("no shipped scheme is called `fibonaci`"),
        "{stderr}"
    );
    assert!(!dir.join("x.obj").exists());
    std::fs::remove_dir_all(&dir).unwrap();
}
