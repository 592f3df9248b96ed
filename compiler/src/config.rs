//! The build-script API, in the style of `prost_build::Config`: compile scheme files into
//! `OUT_DIR` (or any directory).

use crate::error::{Error, Location};
use crate::exact::codegen::{generate_registry, generate_with, module_name};
use crate::exact::ev;
use crate::exact::pipeline::Scheme;
use crate::exact::scheme;
use std::path::{Path, PathBuf};

/// Build-script configuration, in the style of `prost_build::Config`.
#[derive(Clone, Debug, Default)]
pub struct Config {
    out_dir: Option<PathBuf>,
    registry: Option<String>,
}

impl Config {
    /// Defaults: output to `OUT_DIR`, no registry.
    pub fn new() -> Config {
        Config::default()
    }

    /// Writes to `dir` instead of `OUT_DIR`.
    pub fn out_dir(&mut self, dir: impl Into<PathBuf>) -> &mut Config {
        self.out_dir = Some(dir.into());
        self
    }

    /// Also writes `file_name` holding one module per scheme, `NAMES` and dispatch functions.
    pub fn registry(&mut self, file_name: &str) -> &mut Config {
        self.registry = Some(file_name.to_string());
        self
    }

    /// Compiles every scheme file exactly and writes `<module_name>.rs` for each. Emits
    /// `cargo:rerun-if-changed` for each input; files are rewritten only when they change.
    pub fn compile(&self, paths: &[impl AsRef<Path>]) -> Result<Vec<String>, Error> {
        let out_dir = match &self.out_dir {
            Some(d) => d.clone(),
            None => PathBuf::from(std::env::var_os("OUT_DIR").ok_or_else(|| {
                Error::input("OUT_DIR is not set")
                    .with_hint("call from a build script, or set Config::out_dir")
            })?),
        };
        let mut names = Vec::new();
        let mut surfaces = Vec::new();
        for p in paths {
            let p = p.as_ref();
            println!("cargo:rerun-if-changed={}", p.display());
            let ls = scheme::load(p)?;
            let compiled = Scheme::build(ls)?;
            if names.contains(&compiled.ls.name) {
                return Err(Error::at(
                    Location::file(&p.display().to_string()),
                    format!("a scheme named `{}` was already compiled", compiled.ls.name),
                )
                .with_hint("give each scheme file a distinct `name`"));
            }
            let file = out_dir.join(format!("{}.rs", module_name(&compiled.ls.name)));
            let surface = ev::analyse(&compiled).ok();
            write_if_changed(&file, &generate_with(&compiled, surface.as_ref()))?;
            if surface.is_some() {
                surfaces.push(compiled.ls.name.clone());
            }
            names.push(compiled.ls.name);
        }
        if let Some(r) = &self.registry {
            write_if_changed(&out_dir.join(r), &generate_registry(&names, &surfaces))?;
        }
        Ok(names)
    }
}

/// Compiles scheme files into `OUT_DIR` with the default configuration.
pub fn compile(paths: &[impl AsRef<Path>]) -> Result<Vec<String>, Error> {
    Config::new().compile(paths)
}

/// Writes `text` to `path` unless it already holds exactly that; writes go to a temporary file
/// renamed into place, so the output is whole or absent.
fn write_if_changed(path: &Path, text: &str) -> Result<(), Error> {
    if std::fs::read_to_string(path).is_ok_and(|old| old == text) {
        return Ok(());
    }
    crate::output::write_atomic(path, text.as_bytes()).map_err(|e| Error::io(path, &e))
}
