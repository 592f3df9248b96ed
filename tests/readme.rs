//! The README's build-script section is `examples/my-app`, verbatim: its manifest, `build.rs`
//! and `src/main.rs` must appear in the README exactly as they are in the crate the test
//! command builds and runs.

use std::path::Path;

#[test]
fn readme_shows_exactly_the_example_crate() {
    let root = Path::new(env!("CARGO_MANIFEST_DIR"));
    let readme = std::fs::read_to_string(root.join("README.md")).unwrap();
    for file in ["Cargo.toml", "build.rs", "src/main.rs"] {
        let code = std::fs::read_to_string(root.join("examples/my-app").join(file)).unwrap();
        assert!(
            readme.contains(&code),
            "README.md does not show examples/my-app/{file} as it is"
        );
    }
}
