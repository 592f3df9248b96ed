//! Mesh files as every command reads them: one entry point ([`read`], [`parse`]) that takes OBJ
//! or PLY by content, the topology check shared by both formats, and the places (lines, or
//! elements and byte offsets of a binary PLY) where each vertex and face was read, so that the
//! topology's errors — face k, vertex v, edge a–b — are placed in the file.

use lsubdiv_compiler::{Error, Location};
use lsubdiv_runtime::features::Features;
use lsubdiv_runtime::mesh::QuadMesh;
use lsubdiv_runtime::polygon::{catmull_clark, PolyMesh};
use lsubdiv_runtime::topology::{Topology, TopologyError};
use std::path::Path;

/// What a place in [`Places`] counts.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Unit {
    /// 1-based lines of a text file (OBJ, ASCII PLY).
    Line,
    /// Byte offsets of the element in a binary PLY.
    Byte,
}

/// Where each vertex and face of a file was read: vertex i at `vertices[i]`, face k at
/// `faces[k]`, in lines or byte offsets ([`Unit`]); `first` is the number the file gives its
/// first vertex (1 in OBJ, 0 in PLY), so that messages number vertices as the file does.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Places {
    /// Lines or byte offsets.
    pub unit: Unit,
    /// The file's number of vertex 0.
    pub first: u64,
    /// Place of each vertex.
    pub vertices: Vec<usize>,
    /// Place of each face.
    pub faces: Vec<usize>,
}

/// What a reader parsed: the mesh (connectivity not checked), where each of its vertices and
/// faces was read, and warnings about what it skipped.
#[derive(Clone, Debug, PartialEq)]
pub struct Parsed {
    /// The mesh as written: triangles, quads, n-gons.
    pub mesh: PolyMesh,
    /// Where each vertex and face was read.
    pub places: Places,
    /// Skipped directives, elements and values, one line of text per kind.
    pub warnings: Vec<String>,
}

/// A mesh ready to refine: read by [`read`] or [`parse`], a closed 2-manifold with valences
/// ≥ 3, with its topology (build it once, pass it along) and the reader's warnings. A file with
/// faces that are not quads is taken one Catmull–Clark step ([`lsubdiv_runtime::polygon`]), the
/// first step of its refinement ([`Checked::split`]).
#[derive(Clone, Debug)]
pub struct Checked {
    /// The quad mesh: the file's, or its Catmull–Clark step when it has other faces.
    pub mesh: QuadMesh,
    /// The file had faces that are not quads: `mesh` is its first step, so it is refined one
    /// step less.
    pub split: bool,
    /// Its connectivity.
    pub topology: Topology,
    /// Its sharp features and boundary rule.
    pub features: Features,
    /// Skipped directives, elements and values, one line of text per kind.
    pub warnings: Vec<String>,
}

/// `n` and the noun, singular for one: `1 vertex`, `8 vertices`.
pub(crate) fn counted(n: usize, one: &str, many: &str) -> String {
    format!("{n} {}", if n == 1 { one } else { many })
}

/// At most this many characters of a token are quoted in messages.
const TOKEN_CHARS: usize = 32;

/// `s`, cut after [`TOKEN_CHARS`] characters (with `…`), for quoting in a message.
pub(crate) fn shorten(s: &str) -> String {
    match s.char_indices().nth(TOKEN_CHARS) {
        Some((i, _)) => format!("{}…", &s[..i]),
        None => s.to_string(),
    }
}

/// The message for a face of `count` corners, fewer than 3.
pub(crate) fn too_few_corners(count: usize) -> String {
    format!(
        "face has {}; a face has at least 3",
        counted(count, "vertex", "vertices")
    )
}

impl Places {
    /// No places yet, counted in `unit`, vertex 0 numbered `first` in messages.
    pub fn new(unit: Unit, first: u64) -> Places {
        Places {
            unit,
            first,
            vertices: Vec::new(),
            faces: Vec::new(),
        }
    }

    /// The location of `what` (`face`, `vertex`) number `k` placed at `place`: its line, or the
    /// whole file and a message prefix naming the element and its byte offset.
    fn at(&self, file: &str, what: &str, k: u32, place: Option<&usize>) -> (Location, String) {
        match (self.unit, place) {
            (Unit::Line, Some(&l)) => (Location::line(file, l), String::new()),
            (Unit::Byte, Some(&b)) => (
                Location::whole(file),
                format!("{what} {}, byte {b}: ", u64::from(k) + self.first),
            ),
            (_, None) => (Location::whole(file), String::new()),
        }
    }

    /// The topology error `e` of the mesh read from `file` as a diagnostic at the place of the
    /// face or vertex it names, with vertices numbered as in the file.
    pub fn locate(&self, file: &str, e: &TopologyError) -> Error {
        let face = |f: u32| self.at(file, "face", f, self.faces.get(f as usize));
        let vertex = |v: u32| self.at(file, "vertex", v, self.vertices.get(v as usize));
        let num = |v: u32| u64::from(v) + self.first;
        let ((place, prefix), message) = match *e {
            TopologyError::FaceIndexOutOfRange {
                face: f,
                index,
                vertices,
            } => (
                face(f),
                format!(
                    "vertex index {} out of range (the file has {})",
                    num(index),
                    counted(vertices, "vertex", "vertices")
                ),
            ),
            TopologyError::RepeatedVertex { face: f, vertex: v } => {
                (face(f), format!("the face lists vertex {} twice", num(v)))
            }
            TopologyError::DuplicateFaces { first, second } => (
                face(second),
                match (self.unit, self.faces.get(first as usize)) {
                    (Unit::Line, Some(l)) => {
                        format!("duplicate face: the face at line {l} has the same vertices")
                    }
                    (Unit::Byte, Some(b)) => format!(
                        "duplicate face: face {} (byte {b}) has the same vertices",
                        num(first)
                    ),
                    (_, None) => "duplicate face".into(),
                },
            ),
            TopologyError::BoundaryEdge { edge, face: f } => (
                face(f),
                format!(
                    "edge {}–{} of this face has no other face (open boundary; this needs a closed mesh)",
                    num(edge[0]),
                    num(edge[1])
                ),
            ),
            TopologyError::NonManifoldEdge {
                edge,
                faces,
                face: f,
            } => (
                face(f),
                format!(
                    "edge {}–{} of this face is shared by {faces} faces (non-manifold edge: at most 2)",
                    num(edge[0]),
                    num(edge[1])
                ),
            ),
            TopologyError::NonManifoldVertex { vertex: v, fans } => (
                vertex(v),
                format!(
                    "vertex {}: its faces form {fans} separate fans (non-manifold vertex)",
                    num(v)
                ),
            ),
            TopologyError::IsolatedVertex { vertex: v } => (
                vertex(v),
                format!("vertex {} is used by no face (isolated vertex)", num(v)),
            ),
            TopologyError::LowValence { vertex: v, valence } => (
                vertex(v),
                format!(
                    "vertex {} has valence {valence}; extraordinary vertices need valence ≥ 3",
                    num(v)
                ),
            ),
            TopologyError::NoFaces | TopologyError::TooLarge { .. } => {
                ((Location::whole(file), String::new()), e.to_string())
            }
        };
        Error::at(place, format!("{prefix}{message}"))
    }
}

impl Parsed {
    /// Builds the topology of the parsed mesh and checks it (closed 2-manifold, valences ≥ 3),
    /// its errors placed in `file`; a mesh with faces that are not quads is first taken one
    /// Catmull–Clark step, and errors found after it name the file's faces.
    pub fn check(self, file: &str) -> Result<Checked, Error> {
        let Parsed {
            mesh,
            places,
            warnings,
        } = self;
        let (quads, face_of) = match mesh.into_quads() {
            Ok(q) => (q, None),
            Err(mesh) => {
                let s = catmull_clark(&mesh).map_err(|e| places.locate(file, &e))?;
                (s.mesh, Some(s.face_of))
            }
        };
        let topology = Topology::build(&quads)
            .and_then(|t| t.check_valences().map(|()| t))
            .map_err(|e| {
                let e = match &face_of {
                    Some(f) => e.in_faces(f),
                    None => e,
                };
                places.locate(file, &e)
            })?;
        Ok(Checked {
            mesh: quads,
            split: face_of.is_some(),
            topology,
            features: Features::default(),
            warnings,
        })
    }
}

/// The formats [`parse`] reads.
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
        let named_ply = Path::new(file)
            .extension()
            .is_some_and(|e| e.eq_ignore_ascii_case("ply"));
        if named_ply || crate::ply::has_magic(bytes) {
            Format::Ply
        } else {
            Format::Obj
        }
    }
}

/// Parses and checks a mesh file's bytes (`file` names it in errors): PLY or OBJ by
/// [`Format::of`], then the topology (closed 2-manifold, valences ≥ 3; faces other than quads taken one
/// Catmull–Clark step), every error
/// placed at its line, or element and byte offset in a binary PLY.
pub fn parse(file: &str, bytes: Vec<u8>) -> Result<Checked, Error> {
    read_faces(file, bytes)?.check(file)
}

/// Parses a mesh file's bytes, PLY or OBJ by [`Format::of`], without checking its topology
/// ([`Parsed::check`] does).
pub fn read_faces(file: &str, bytes: Vec<u8>) -> Result<Parsed, Error> {
    match Format::of(file, &bytes) {
        Format::Ply => crate::ply::parse(file, &bytes),
        Format::Obj => crate::obj::parse(file, &lsubdiv_compiler::text(bytes)),
    }
}

/// Reads a closed quad mesh from an OBJ or PLY file ([`parse`]) of at most `max` bytes
/// ([`lsubdiv_compiler::read_bytes`]: a pipe or device is read only to the bound).
pub fn read(path: &Path, max: u64) -> Result<Checked, Error> {
    let bytes = lsubdiv_compiler::read_bytes(path, max)?;
    parse(&path.display().to_string(), bytes)
}
