//! Mesh files: [`Mesh`], a file as read (OBJ or PLY by content, [`read_faces`]), and the
//! first stage of a refinement plan ([`read_checked`], [`parse_checked`]) that takes OBJ
//! or PLY by content and checks what it read ([`crate::mesh_data`]).

pub use crate::mesh_data::{Checked, Extras, Parsed};
use lsubdiv_io::Error;
use std::path::Path;

/// The formats [`read_faces`] reads.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Format {
    /// Wavefront OBJ ([`crate::obj`]).
    Obj,
    /// PLY, ASCII or binary ([`crate::ply`]).
    Ply,
}

impl Format {
    /// The format of a file named `file` holding `bytes`: PLY when it begins with the `ply`
    /// magic line (after an optional UTF-8 byte-order mark) or when its name ends in `.ply` (any
    /// case; then a wrong first line is reported as such), OBJ otherwise. The content decides
    /// first, so standard input and pipes need no name.
    pub fn of(file: &str, bytes: &[u8]) -> Format {
        if Format::named(Path::new(file)) == Format::Ply || crate::ply::has_magic(bytes) {
            Format::Ply
        } else {
            Format::Obj
        }
    }

    /// The format a file's name says: PLY when it ends in `.ply` (any case), OBJ otherwise.
    pub fn named(path: &Path) -> Format {
        if path
            .extension()
            .is_some_and(|e| e.eq_ignore_ascii_case("ply"))
        {
            Format::Ply
        } else {
            Format::Obj
        }
    }
}

/// Parses and checks a mesh file's bytes (`file` names it in errors): PLY or OBJ by
/// [`Format::of`], then the topology (2-manifold, closed or open, interior valences ≥ 3; faces other than quads taken one
/// Catmull–Clark step), every error
/// placed at its line, or element and byte offset in a binary PLY.
pub fn parse_checked(file: &str, bytes: Vec<u8>) -> Result<Checked, Error> {
    read_faces(file, bytes)?.check(file)
}

/// Parses a mesh file's bytes, PLY or OBJ by [`Format::of`], without checking its topology
/// ([`Parsed::check`] does).
pub fn read_faces(file: &str, bytes: Vec<u8>) -> Result<Parsed, Error> {
    match Format::of(file, &bytes) {
        Format::Ply => crate::ply::parse(file, &bytes),
        Format::Obj => crate::obj::parse(file, &lsubdiv_io::text(bytes)),
    }
}

/// A mesh as a file holds it: positions, faces (triangles, quads, n-gons), the sharp features
/// and boundary rule of its tags (OBJ `t crease`, `t corner`, `t hole`, …), its texture
/// coordinates, and the reader's warnings; errors found when it is refined name the file's
/// lines. Refine it with [`crate::Refiner`].
#[derive(Clone, Debug, PartialEq)]
pub struct Mesh {
    name: String,
    parsed: Parsed,
}

impl Mesh {
    /// At most this many bytes are read from a file by [`Mesh::read`].
    pub const MAX_FILE_BYTES: u64 = 1 << 32;

    /// Reads an OBJ or PLY file (by content, [`Format::of`]) of at most
    /// [`Mesh::MAX_FILE_BYTES`]; errors name the file's line, or a binary PLY's element and
    /// byte.
    pub fn read(path: impl AsRef<Path>) -> Result<Mesh, crate::Error> {
        let path = path.as_ref();
        let bytes =
            lsubdiv_io::read_bytes(path, Mesh::MAX_FILE_BYTES).map_err(crate::Error::File)?;
        Mesh::parse(&path.display().to_string(), bytes)
    }

    /// Parses the bytes of an OBJ or PLY file called `name` (in messages).
    pub fn parse(name: &str, bytes: Vec<u8>) -> Result<Mesh, crate::Error> {
        Ok(Mesh {
            name: name.to_string(),
            parsed: read_faces(name, bytes).map_err(crate::Error::File)?,
        })
    }

    /// The name its messages give it: its file's.
    pub fn name(&self) -> &str {
        &self.name
    }

    /// What the reader parsed: the polygon mesh, its features, texture coordinates, places
    /// and warnings.
    pub fn parsed(&self) -> &Parsed {
        &self.parsed
    }

    /// The vertex positions.
    pub fn positions(&self) -> &[[f64; 3]] {
        &self.parsed.mesh.positions
    }

    /// The faces, each its vertices in order.
    pub fn faces(&self) -> impl Iterator<Item = &[u32]> {
        self.parsed.mesh.faces()
    }

    /// What the reader skipped, one line of text per kind.
    pub fn warnings(&self) -> &[String] {
        &self.parsed.warnings
    }
}

/// Reads a quad mesh (closed or open, with its OBJ tags) from an OBJ or PLY file ([`parse_checked`]) of at most `max` bytes
/// ([`lsubdiv_io::read_bytes`]: a pipe or device is read only to the bound).
pub fn read_checked(path: &Path, max: u64) -> Result<Checked, Error> {
    let bytes = lsubdiv_io::read_bytes(path, max)?;
    parse_checked(&path.display().to_string(), bytes)
}
