//! The README's library sections are the example crates, verbatim: `examples/my-app`'s manifest
//! and `src/main.rs`, and `examples/my-scheme`'s manifest, `build.rs` and `src/main.rs`, must
//! appear in the README exactly as they are in the crates the test command builds and runs.

use std::path::Path;

#[test]
fn readme_shows_exactly_the_example_crates() {
    let root = Path::new(env!("CARGO_MANIFEST_DIR"));
    let readme = std::fs::read_to_string(root.join("README.md")).unwrap();
    for (krate, files) in [
        ("my-app", &["Cargo.toml", "src/main.rs"][..]),
        ("my-scheme", &["Cargo.toml", "build.rs", "src/main.rs"][..]),
    ] {
        for file in files {
            let path = root.join("examples").join(krate).join(file);
            let code = std::fs::read_to_string(&path).unwrap();
            assert!(
                readme.contains(&code),
                "README.md does not show examples/{krate}/{file} as it is"
            );
        }
    }
}
