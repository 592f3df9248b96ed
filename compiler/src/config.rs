//! The build-script API, in the style of `prost_build::Config`: compile scheme files into
//! `OUT_DIR` (or any directory).

use crate::exact::codegen::{module_name, Codegen, DEFAULT_RUNTIME_PATH};
use crate::exact::pipeline::Scheme;
use crate::exact::scheme;
use crate::exact::tables::Tables;
use crate::{Error, Location};
use std::path::{Path, PathBuf};

/// Build-script configuration, in the style of `prost_build::Config`.
#[derive(Clone, Debug)]
pub struct Config {
    out_dir: Option<PathBuf>,
    registry: Option<String>,
    runtime_path: String,
    emit_rerun_directives: bool,
}

impl Default for Config {
    fn default() -> Config {
        Config {
            out_dir: None,
            registry: None,
            runtime_path: DEFAULT_RUNTIME_PATH.to_string(),
            emit_rerun_directives: true,
        }
    }
}

impl Config {
    /// Defaults: output to `OUT_DIR`, no registry, runtime path `lsubdiv_runtime`, cargo
    /// directives printed.
    pub fn new() -> Config {
        Config::default()
    }

    /// Writes to `dir` instead of `OUT_DIR`.
    pub fn out_dir(&mut self, dir: impl Into<PathBuf>) -> &mut Config {
        self.out_dir = Some(dir.into());
        self
    }

    /// Also writes `file_name` holding one module per scheme (each including its file from the
    /// same folder), `NAMES` and dispatch functions. Include it with
    /// `include!(concat!(env!("OUT_DIR"), "/registry.rs"))`; its code names the runtime by the
    /// runtime path, so a crate without a direct `lsubdiv-runtime` dependency sets
    /// [`Config::runtime_path`] (say to `lsubdiv::runtime`).
    pub fn registry(&mut self, file_name: &str) -> &mut Config {
        self.registry = Some(file_name.to_string());
        self
    }

    /// The path by which generated code names the runtime (default `lsubdiv_runtime`, which
    /// `lsubdiv_runtime::include_scheme!` and `lsubdiv::include_scheme!` bring into scope), for
    /// crates that re-export the runtime elsewhere (`crate::rt`), as `prost_build`'s
    /// `prost_path`.
    pub fn runtime_path(&mut self, path: &str) -> &mut Config {
        self.runtime_path = path.to_string();
        self
    }

    /// Whether to print `cargo:rerun-if-changed` for each input, and `cargo:warning` for each
    /// scheme that compiles for curves only (default true; off outside build scripts).
    pub fn emit_rerun_directives(&mut self, on: bool) -> &mut Config {
        self.emit_rerun_directives = on;
        self
    }

    /// Compiles every scheme file exactly and writes `<module_name>.rs` for each; files are
    /// rewritten only when they change. Returns the scheme names.
    pub fn compile(&self, paths: &[impl AsRef<Path>]) -> Result<Vec<String>, Error> {
        let emit = self.emit_rerun_directives;
        self.compile_with(paths, &mut |line| {
            if emit {
                println!("{line}");
            }
        })
    }

    /// [`Config::compile`], handing each cargo directive to `directive` as it comes.
    fn compile_with(
        &self,
        paths: &[impl AsRef<Path>],
        directive: &mut dyn FnMut(String),
    ) -> Result<Vec<String>, Error> {
        let out_dir = match &self.out_dir {
            Some(d) => d.clone(),
            None => PathBuf::from(std::env::var_os("OUT_DIR").ok_or_else(|| {
                Error::input("OUT_DIR is not set")
                    .with_hint("call from a build script, or set Config::out_dir")
            })?),
        };
        let codegen = Codegen::new(&self.runtime_path).map_err(Error::input)?;
        let mut compiled: Vec<Tables> = Vec::new();
        for p in paths {
            let p = p.as_ref();
            directive(format!("cargo:rerun-if-changed={}", p.display()));
            let t = Tables::new(Scheme::build(scheme::load(p)?)?)?;
            let name = &t.scheme().ls.name;
            if compiled.iter().any(|c| c.scheme().ls.name == *name) {
                return Err(Error::at(
                    Location::file(&p.display().to_string()),
                    format!("a scheme named `{name}` was already compiled"),
                )
                .with_hint("give each scheme file a distinct `name`"));
            }
            if let Some(w) = curves_only_warning(p, &t) {
                directive(format!("cargo:warning={w}"));
            }
            let file = out_dir.join(format!("{}.rs", module_name(name)));
            crate::write_if_changed(&file, &codegen.scheme(&t))?;
            compiled.push(t);
        }
        if let Some(r) = &self.registry {
            let all: Vec<&Tables> = compiled.iter().collect();
            crate::write_if_changed(&out_dir.join(r), &codegen.registry(&all))?;
        }
        Ok(compiled
            .into_iter()
            .map(|t| t.scheme().ls.name.clone())
            .collect())
    }
}

/// `<place>: scheme `x` compiles for curves only: <the condition of [G] §4.2 that fails>`, for
/// a scheme that is not a surface scheme.
fn curves_only_warning(path: &Path, t: &Tables) -> Option<String> {
    let e = t.curves_only()?;
    let place =
        e.at.as_ref()
            .map_or_else(|| path.display().to_string(), |l| l.to_string());
    Some(format!(
        "{place}: scheme `{}` compiles for curves only: {}",
        t.scheme().ls.name,
        e.message
    ))
}

/// Compiles scheme files into `OUT_DIR` with the default configuration.
pub fn compile(paths: &[impl AsRef<Path>]) -> Result<Vec<String>, Error> {
    Config::new().compile(paths)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A valid curve scheme of degree 2: surfaces need degree 3 (\[G\] §2.2).
    const QUADRATIC: &str =
        "name = \"quad\"\ndegree = 2\naxiom = \"A\"\n[rules]\nA = \"AB\"\nB = \"A\"\n";

    fn compile_in(dir: &Path, text: &str, config: &Config) -> (Vec<String>, String) {
        let file = dir.join("s.toml");
        std::fs::write(&file, text).unwrap();
        let mut lines = Vec::new();
        config
            .clone()
            .out_dir(dir)
            .compile_with(&[&file], &mut |l| lines.push(l))
            .unwrap();
        let src = std::fs::read_to_string(dir.join("quad.rs")).unwrap();
        (lines, src)
    }

    #[test]
    fn a_curve_only_scheme_warns_and_says_why_in_its_docs() {
        let dir = std::env::temp_dir().join(format!("lsubdiv-config-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        let (lines, src) = compile_in(&dir, QUADRATIC, &Config::new());
        let file = dir.join("s.toml").display().to_string();
        assert_eq!(lines[0], format!("cargo:rerun-if-changed={file}"));
        let why = "surfaces need degree 3 (bicubic, [G] §2.2); this scheme has degree 2";
        assert_eq!(
            lines[1],
            format!("cargo:warning={file}:2:10: scheme `quad` compiles for curves only: {why}")
        );
        assert_eq!(lines.len(), 2);
        let doc = why.replace('[', "\\[").replace(']', "\\]");
        assert!(
            src.contains(&format!("/// Compiles for curves only: {doc}")),
            "{src}"
        );
        assert!(!src.contains("SurfaceScheme for"));
        std::fs::remove_dir_all(&dir).unwrap();
    }

    #[test]
    fn the_runtime_path_is_an_option_and_checked() {
        let dir = std::env::temp_dir().join(format!("lsubdiv-config-rt-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        let (_, src) = compile_in(&dir, QUADRATIC, Config::new().runtime_path("crate::rt"));
        assert!(
            src.contains("pub const TABLES: crate::rt::CurveTables"),
            "{src}"
        );
        assert!(!src.contains("lsubdiv_runtime"), "{src}");
        let e = Config::new()
            .out_dir(&dir)
            .runtime_path("not a path")
            .compile(&[dir.join("s.toml")])
            .unwrap_err();
        assert!(e.to_string().contains("runtime path `not a path`"), "{e}");
        std::fs::remove_dir_all(&dir).unwrap();
    }
}
