//! Closed quad meshes: the [`QuadMesh`] type, OBJ parsing with line-numbered errors, OBJ and PLY
//! output.
//!
//! Validation of the connectivity (closed 2-manifold) lives in [`crate::topology`]; this module
//! only checks what a file can get wrong on its own line.

use std::fmt::{self, Write as _};

/// A polygonal mesh with quad faces (corner order as given in the file).
#[derive(Clone, Debug, PartialEq)]
pub struct QuadMesh {
    /// Vertex positions.
    pub positions: Vec<[f64; 3]>,
    /// Faces: four 0-based vertex indices each, in corner order.
    pub faces: Vec<[u32; 4]>,
}

/// What is wrong with a mesh file or a mesh, with the place (1-based line for file problems,
/// face/edge/vertex index otherwise).
#[derive(Clone, Debug, PartialEq, Eq)]
pub enum MeshError {
    /// A token that should be a number is not one.
    BadNumber {
        /// 1-based line.
        line: usize,
        /// The token (shortened if long).
        token: String,
    },
    /// A coordinate that parses to NaN or ±∞.
    NonFinite {
        /// 1-based line.
        line: usize,
        /// The token (shortened if long).
        token: String,
    },
    /// A `v` line with a number of values other than 3 (x y z), 4 (x y z w) or 6 (x y z r g b).
    CoordinateCount {
        /// 1-based line.
        line: usize,
        /// Values given.
        count: usize,
    },
    /// A face with other than four corners.
    NotQuad {
        /// 1-based line.
        line: usize,
        /// Corners given.
        count: usize,
    },
    /// A face corner that is not `i`, `i/t`, `i//n` or `i/t/n` with an integer `i`.
    BadIndex {
        /// 1-based line.
        line: usize,
        /// The corner token (shortened if long).
        token: String,
    },
    /// Vertex index 0 (OBJ indices start at 1).
    ZeroIndex {
        /// 1-based line.
        line: usize,
    },
    /// A vertex index that refers to no vertex.
    IndexOutOfRange {
        /// 1-based line.
        line: usize,
        /// The index as written (it may not fit any integer type).
        index: String,
        /// Vertices it could refer to: all of the file's for a positive index, those before the
        /// line for a negative (relative) one.
        vertices: usize,
    },
    /// The mesh has no faces.
    NoFaces,
    /// More vertices or faces than 32-bit indices can address.
    TooLarge {
        /// Vertex count.
        vertices: usize,
        /// Face count.
        faces: usize,
    },
    /// A face names a vertex that does not exist.
    FaceIndexOutOfRange {
        /// Face index.
        face: u32,
        /// The vertex index.
        index: u32,
        /// Vertex count of the mesh.
        vertices: usize,
    },
    /// A face lists the same vertex twice.
    RepeatedVertex {
        /// Face index.
        face: u32,
        /// The repeated vertex.
        vertex: u32,
    },
    /// Two faces have the same vertex set.
    DuplicateFaces {
        /// The earlier face.
        first: u32,
        /// The later face.
        second: u32,
    },
    /// An edge with only one face.
    BoundaryEdge {
        /// Endpoints, smaller first.
        edge: [u32; 2],
        /// The face.
        face: u32,
    },
    /// An edge with more than two faces.
    NonManifoldEdge {
        /// Endpoints, smaller first.
        edge: [u32; 2],
        /// Number of faces on it.
        faces: usize,
        /// The first face on it.
        face: u32,
    },
    /// The faces around a vertex form more than one cycle.
    NonManifoldVertex {
        /// The vertex.
        vertex: u32,
        /// Number of separate fans (cycles).
        fans: usize,
    },
    /// A vertex used by no face.
    IsolatedVertex {
        /// The vertex.
        vertex: u32,
    },
    /// A vertex where only two faces meet: a closed manifold, but no extraordinary-vertex
    /// rule applies (\[G\] §2.2.2 needs valence ≥ 3).
    LowValence {
        /// The vertex.
        vertex: u32,
        /// Its valence.
        valence: usize,
    },
}

fn plural(n: usize, one: &str, many: &str) -> String {
    format!("{n} {}", if n == 1 { one } else { many })
}

impl MeshError {
    /// The 1-based line of a problem found while reading a file.
    pub fn line(&self) -> Option<usize> {
        match self {
            MeshError::BadNumber { line, .. }
            | MeshError::NonFinite { line, .. }
            | MeshError::CoordinateCount { line, .. }
            | MeshError::NotQuad { line, .. }
            | MeshError::BadIndex { line, .. }
            | MeshError::ZeroIndex { line }
            | MeshError::IndexOutOfRange { line, .. } => Some(*line),
            _ => None,
        }
    }

    /// The error as `file:line: error: message` for a mesh read from the OBJ `text` of `file`:
    /// a problem of a face or vertex found after reading is placed at that face's `f` line or
    /// that vertex's `v` line, with vertices numbered as in the file (from 1).
    pub fn in_obj(&self, file: &str, text: &str) -> String {
        let nth = |kind: &str, k: u32| {
            text.lines()
                .enumerate()
                .filter(|(_, l)| matches!(directive(l), Some((d, _)) if d == kind))
                .nth(k as usize)
                .map(|(i, _)| i + 1)
        };
        let (face, vertex) = (|f: u32| nth("f", f), |v: u32| nth("v", v));
        let obj = |v: u32| u64::from(v) + 1;
        let (line, message) = match self {
            MeshError::FaceIndexOutOfRange {
                face: f,
                index,
                vertices,
            } => (
                face(*f),
                format!(
                    "vertex index {} out of range (the file has {})",
                    obj(*index),
                    plural(*vertices, "vertex", "vertices")
                ),
            ),
            MeshError::RepeatedVertex { face: f, vertex: v } => (
                face(*f),
                format!("the face lists vertex {} twice", obj(*v)),
            ),
            MeshError::DuplicateFaces { first, second } => (
                face(*second),
                match face(*first) {
                    Some(l) => format!("duplicate face: the face at line {l} has the same vertices"),
                    None => "duplicate face".into(),
                },
            ),
            MeshError::BoundaryEdge { edge, face: f } => (
                face(*f),
                format!(
                    "edge {}–{} of this face has no other face (open boundary; lsubdiv refines closed meshes)",
                    obj(edge[0]),
                    obj(edge[1])
                ),
            ),
            MeshError::NonManifoldEdge {
                edge,
                faces,
                face: f,
            } => (
                face(*f),
                format!(
                    "edge {}–{} of this face is shared by {faces} faces (non-manifold edge: at most 2)",
                    obj(edge[0]),
                    obj(edge[1])
                ),
            ),
            MeshError::NonManifoldVertex { vertex: v, fans } => (
                vertex(*v),
                format!(
                    "vertex {}: its faces form {fans} separate fans (non-manifold vertex)",
                    obj(*v)
                ),
            ),
            MeshError::IsolatedVertex { vertex: v } => (
                vertex(*v),
                format!("vertex {} is used by no face (isolated vertex)", obj(*v)),
            ),
            MeshError::LowValence { vertex: v, valence } => (
                vertex(*v),
                format!(
                    "vertex {} has valence {valence}; extraordinary vertices need valence ≥ 3",
                    obj(*v)
                ),
            ),
            e => (e.line(), e.what()),
        };
        match line {
            Some(l) => format!("{file}:{l}: error: {message}"),
            None => format!("{file}: error: {message}"),
        }
    }

    /// What is wrong, without the line.
    fn what(&self) -> String {
        match self {
            MeshError::BadNumber { token, .. } => format!("`{token}` is not a number"),
            MeshError::NonFinite { token, .. } => format!("coordinate `{token}` is not finite"),
            MeshError::CoordinateCount { count, .. } => format!(
                "vertex has {}; expected x y z, x y z w or x y z r g b",
                plural(*count, "value", "values")
            ),
            MeshError::NotQuad { count, .. } => format!(
                "face has {}; lsubdiv refines quad meshes only (convert first, e.g. by a Catmull–Clark step in another tool: triangles are not turned into quads here)",
                plural(*count, "vertex", "vertices")
            ),
            MeshError::BadIndex { token, .. } => {
                format!("`{token}` is not a face corner (i, i/t, i//n or i/t/n)")
            }
            MeshError::ZeroIndex { .. } => {
                "vertex index 0 is invalid (OBJ indices start at 1)".into()
            }
            MeshError::IndexOutOfRange {
                index, vertices, ..
            } => {
                if index.starts_with('-') {
                    format!(
                        "vertex index {index} out of range (only {} precede this line)",
                        plural(*vertices, "vertex", "vertices")
                    )
                } else {
                    format!(
                        "vertex index {index} out of range (the file has {})",
                        plural(*vertices, "vertex", "vertices")
                    )
                }
            }
            MeshError::NoFaces => "empty mesh: no faces".into(),
            MeshError::TooLarge { vertices, faces } => format!(
                "mesh too large: {vertices} vertices and {faces} faces (at most {} vertices and {} faces are supported)",
                u32::MAX,
                u32::MAX / 4
            ),
            MeshError::FaceIndexOutOfRange {
                face,
                index,
                vertices,
            } => format!(
                "face {face}: vertex index {index} out of range (the mesh has {})",
                plural(*vertices, "vertex", "vertices")
            ),
            MeshError::RepeatedVertex { face, vertex } => {
                format!("face {face} repeats vertex {vertex}")
            }
            MeshError::DuplicateFaces { first, second } => {
                format!("faces {first} and {second} are duplicates")
            }
            MeshError::BoundaryEdge { edge, face } => format!(
                "edge ({}, {}) of face {face} has no other face (open boundary)",
                edge[0], edge[1]
            ),
            MeshError::NonManifoldEdge { edge, faces, face } => format!(
                "edge ({}, {}) of face {face} is shared by {faces} faces (non-manifold edge)",
                edge[0], edge[1]
            ),
            MeshError::NonManifoldVertex { vertex, fans } => {
                format!("vertex {vertex}: its faces form {fans} separate fans (non-manifold vertex)")
            }
            MeshError::IsolatedVertex { vertex } => format!("vertex {vertex} is used by no face"),
            MeshError::LowValence { vertex, valence } => format!(
                "vertex {vertex} has valence {valence}; extraordinary vertices need valence ≥ 3"
            ),
        }
    }
}

/// Line-numbered for file problems; faces and vertices 0-based, as in [`QuadMesh`] (see
/// [`MeshError::in_obj`] for the numbering of an OBJ file).
impl fmt::Display for MeshError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self.line() {
            Some(line) => write!(f, "line {line}: {}", self.what()),
            None => write!(f, "{}", self.what()),
        }
    }
}

impl std::error::Error for MeshError {}

/// At most this many characters of a token are quoted in messages.
const TOKEN_CHARS: usize = 32;

fn shorten(s: &str) -> String {
    match s.char_indices().nth(TOKEN_CHARS) {
        Some((i, _)) => format!("{}…", &s[..i]),
        None => s.to_string(),
    }
}

/// The directive of a line (comments stripped) and the rest of its tokens, or None if blank.
fn directive(raw: &str) -> Option<(&str, std::str::SplitWhitespace<'_>)> {
    let content = raw.split('#').next().unwrap_or("");
    let mut tokens = content.split_whitespace();
    tokens.next().map(|d| (d, tokens))
}

/// Directives of the OBJ format that carry nothing a quad mesh needs.
const KNOWN_SKIPPED: &[&str] = &[
    "vt",
    "vn",
    "vp",
    "o",
    "g",
    "s",
    "mg",
    "usemtl",
    "mtllib",
    "l",
    "p",
    "cstype",
    "deg",
    "bmat",
    "step",
    "curv",
    "curv2",
    "surf",
    "parm",
    "trim",
    "hole",
    "scrv",
    "sp",
    "end",
    "con",
    "bevel",
    "c_interp",
    "d_interp",
    "lod",
    "usemap",
    "maplib",
    "shadow_obj",
    "trace_obj",
    "ctech",
    "stech",
    "call",
    "csh",
];

/// Distinct unknown directives reported one by one; further ones are pooled into one warning.
const MAX_UNKNOWN_KINDS: usize = 16;

#[derive(Clone, Debug, PartialEq, Eq)]
enum SkipKind {
    Known(&'static str),
    Unknown(String),
    OtherUnknown,
    VertexColours,
}

/// Skipped lines, one entry per kind, in order of first appearance.
#[derive(Default)]
struct Skipped {
    entries: Vec<(SkipKind, usize, usize)>,
    unknown_kinds: usize,
}

impl Skipped {
    fn note_kind(&mut self, kind: SkipKind, line: usize) {
        if let Some(e) = self.entries.iter_mut().find(|e| e.0 == kind) {
            e.1 += 1;
        } else {
            self.entries.push((kind, 1, line));
        }
    }

    fn note_directive(&mut self, d: &str, line: usize) {
        if let Some(&known) = KNOWN_SKIPPED.iter().find(|&&k| k == d) {
            self.note_kind(SkipKind::Known(known), line);
            return;
        }
        let name = shorten(d);
        let seen = self
            .entries
            .iter()
            .any(|e| matches!(&e.0, SkipKind::Unknown(n) if *n == name));
        if seen || self.unknown_kinds < MAX_UNKNOWN_KINDS {
            if !seen {
                self.unknown_kinds += 1;
            }
            self.note_kind(SkipKind::Unknown(name), line);
        } else {
            self.note_kind(SkipKind::OtherUnknown, line);
        }
    }

    fn warnings(&self) -> Vec<String> {
        self.entries
            .iter()
            .map(|(kind, count, first)| {
                let at = if *count == 1 {
                    format!("(line {first})")
                } else {
                    format!("(first at line {first})")
                };
                let noun = if *count == 1 { "line" } else { "lines" };
                match kind {
                    SkipKind::Known(d) => format!("skipped {count} `{d}` {noun} {at}"),
                    SkipKind::Unknown(d) => {
                        format!("skipped {count} {noun} with unknown directive `{d}` {at}")
                    }
                    SkipKind::OtherUnknown => {
                        format!("skipped {count} {noun} with other unknown directives {at}")
                    }
                    SkipKind::VertexColours => {
                        format!("ignored vertex colours on {count} `v` {noun} {at}")
                    }
                }
            })
            .collect()
    }
}

/// Parses the values of a `v` line; returns the position and whether colours were present.
fn parse_vertex(
    line: usize,
    tokens: std::str::SplitWhitespace<'_>,
) -> Result<([f64; 3], bool), MeshError> {
    let count = tokens.clone().count();
    if !matches!(count, 3 | 4 | 6) {
        return Err(MeshError::CoordinateCount { line, count });
    }
    let mut p = [0.0; 3];
    for (i, tok) in tokens.enumerate() {
        let x: f64 = tok.parse().map_err(|_| MeshError::BadNumber {
            line,
            token: shorten(tok),
        })?;
        if i < 3 {
            if !x.is_finite() {
                return Err(MeshError::NonFinite {
                    line,
                    token: shorten(tok),
                });
            }
            p[i] = x;
        }
    }
    Ok((p, count == 6))
}

/// `[+-]?[0-9]+`
fn is_integer(s: &str) -> bool {
    let digits = s.strip_prefix(['+', '-']).unwrap_or(s);
    !digits.is_empty() && digits.bytes().all(|b| b.is_ascii_digit())
}

/// Resolves one face corner to a 0-based vertex index. `before`: vertices defined before this
/// line (for negative indices); `total`: vertices in the whole file (for positive ones).
fn parse_corner(line: usize, tok: &str, before: usize, total: usize) -> Result<u32, MeshError> {
    let mut parts = tok.split('/');
    let index = parts.next().unwrap_or("");
    // `i`, `i/t`, `i//n` or `i/t/n`: texture and normal indices are integers when present.
    let rest: Vec<&str> = parts.collect();
    let well_formed = match rest.as_slice() {
        [] => true,
        [t] => is_integer(t),
        [t, n] => (t.is_empty() || is_integer(t)) && is_integer(n),
        _ => false,
    };
    if !well_formed || !is_integer(index) {
        return Err(MeshError::BadIndex {
            line,
            token: shorten(tok),
        });
    }
    let negative = index.starts_with('-');
    let limit = if negative { before } else { total };
    let out_of_range = || MeshError::IndexOutOfRange {
        line,
        index: shorten(index),
        vertices: limit,
    };
    let i: i64 = index.parse().map_err(|_| out_of_range())?;
    let resolved = match i {
        0 => return Err(MeshError::ZeroIndex { line }),
        i if i > 0 => i.unsigned_abs() - 1,
        i => (limit as u64)
            .checked_sub(i.unsigned_abs())
            .ok_or_else(out_of_range)?,
    };
    if resolved >= limit as u64 || resolved > u64::from(u32::MAX) {
        return Err(out_of_range());
    }
    Ok(resolved as u32)
}

/// Parses OBJ text: `v x y z [w]` (w ignored; `v x y z r g b` with vertex colours is accepted
/// with a warning), `f a b c d` where each corner may be `i`, `i/t`, `i//n`, `i/t/n`, with
/// negative (relative) indices supported; texture and normal indices are ignored.
///
/// Lines it does not need (`vt`, `vn`, `o`, `g`, `s`, `usemtl`, `mtllib`, `l`, `p`, other OBJ
/// directives, unknown directives, comments, blank lines) are skipped with one warning per kind
/// of skipped directive (count and first line). Errors carry the 1-based line number. A file
/// without faces is an error. Connectivity is not checked here (see
/// [`crate::topology::Topology::build`]).
pub fn parse_obj(text: &str) -> Result<(QuadMesh, Vec<String>), MeshError> {
    // Positive indices may refer to vertices defined later in the file.
    let total = text
        .lines()
        .filter(|l| matches!(directive(l), Some(("v", _))))
        .count();
    let mut positions = Vec::new();
    let mut faces = Vec::new();
    let mut skipped = Skipped::default();
    for (k, raw) in text.lines().enumerate() {
        let line = k + 1;
        let Some((d, tokens)) = directive(raw) else {
            continue;
        };
        match d {
            "v" => {
                let (p, colours) = parse_vertex(line, tokens)?;
                if colours {
                    skipped.note_kind(SkipKind::VertexColours, line);
                }
                positions.push(p);
            }
            "f" => {
                let count = tokens.clone().count();
                if count != 4 {
                    return Err(MeshError::NotQuad { line, count });
                }
                let mut face = [0u32; 4];
                for (slot, tok) in face.iter_mut().zip(tokens) {
                    *slot = parse_corner(line, tok, positions.len(), total)?;
                }
                faces.push(face);
            }
            _ => skipped.note_directive(d, line),
        }
    }
    if faces.is_empty() {
        return Err(MeshError::NoFaces);
    }
    Ok((QuadMesh { positions, faces }, skipped.warnings()))
}

/// OBJ text: a comment line, `v` lines at full round-trip f64 precision (`{:?}` of f64), then
/// `f` lines (1-based). Non-finite coordinates are written as they are (`NaN`, `inf`), which
/// [`parse_obj`] rejects.
pub fn to_obj(mesh: &QuadMesh) -> String {
    let mut s = String::with_capacity(32 * mesh.positions.len() + 24 * mesh.faces.len() + 64);
    let _ = writeln!(
        s,
        "# lsubdiv quad mesh: {} vertices, {} faces",
        mesh.positions.len(),
        mesh.faces.len()
    );
    for p in &mesh.positions {
        let _ = writeln!(s, "v {:?} {:?} {:?}", p[0], p[1], p[2]);
    }
    for f in &mesh.faces {
        let [a, b, c, d] = f.map(|i| u64::from(i) + 1);
        let _ = writeln!(s, "f {a} {b} {c} {d}");
    }
    s
}

/// ASCII PLY: vertex x y z as double (round-trip precision), faces as a `uchar int` list.
pub fn to_ply(mesh: &QuadMesh) -> String {
    let mut s = String::with_capacity(32 * mesh.positions.len() + 24 * mesh.faces.len() + 256);
    let _ = write!(
        s,
        "ply\nformat ascii 1.0\ncomment lsubdiv quad mesh\nelement vertex {}\n\
         property double x\nproperty double y\nproperty double z\nelement face {}\n\
         property list uchar int vertex_indices\nend_header\n",
        mesh.positions.len(),
        mesh.faces.len()
    );
    for p in &mesh.positions {
        let _ = writeln!(s, "{:?} {:?} {:?}", p[0], p[1], p[2]);
    }
    for f in &mesh.faces {
        let _ = writeln!(s, "4 {} {} {} {}", f[0], f[1], f[2], f[3]);
    }
    s
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::generators::{cube, klein_bottle, torus};
    use crate::topology::Topology;

    /// Deterministic pseudo-random numbers.
    struct Rng(u64);
    impl Rng {
        fn next(&mut self) -> u64 {
            self.0 ^= self.0 << 13;
            self.0 ^= self.0 >> 7;
            self.0 ^= self.0 << 17;
            self.0
        }
        fn below(&mut self, n: usize) -> usize {
            (self.next() % n as u64) as usize
        }
    }

    const SQUARE_V: &str = "v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\n";

    fn err(text: &str) -> MeshError {
        parse_obj(text).expect_err("should not parse")
    }

    #[test]
    fn face_corner_syntax_variants() {
        for face in [
            "f 1 2 3 4",
            "f 1/1 2/2 3/3 4/4",
            "f 1//7 2//7 3//7 4//7",
            "f 1/1/1 2/2/2 3/3/3 4/4/4",
            "f 1 2/5 3//6 4/7/8",
            "f -4 -3 -2 -1",
            "f -4/1 -3//2 3/3/4 -1",
            "f +1 2 3 4",
        ] {
            let (m, w) = parse_obj(&format!("{SQUARE_V}{face}\n")).unwrap();
            assert_eq!(m.faces, vec![[0, 1, 2, 3]], "{face}");
            assert_eq!(m.positions.len(), 4);
            assert!(w.is_empty(), "{face}: {w:?}");
        }
    }

    #[test]
    fn negative_indices_are_relative_to_the_line() {
        let text = "v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nf -4 -3 -2 -1\n\
                    v 0 0 1\nv 1 0 1\nf -6 -5 -1 -2\n";
        let (m, _) = parse_obj(text).unwrap();
        assert_eq!(m.faces, vec![[0, 1, 2, 3], [0, 1, 5, 4]]);
        // Positive indices may point forward.
        let (m, _) = parse_obj("f 1 2 3 4\nv 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\n").unwrap();
        assert_eq!(m.faces, vec![[0, 1, 2, 3]]);
    }

    #[test]
    fn vertex_forms_and_comments() {
        let text = "# header\n\n  v 1 2 3 # trailing\nv 1 2 3 0.5\nv\t1e0 -2.5E1 .5 \r\n\
                    v 1 2 3 0.1 0.2 0.3\nf 1 2 3 4 # quad\n";
        let (m, w) = parse_obj(text).unwrap();
        assert_eq!(
            m.positions,
            vec![
                [1.0, 2.0, 3.0],
                [1.0, 2.0, 3.0],
                [1.0, -25.0, 0.5],
                [1.0, 2.0, 3.0]
            ]
        );
        assert_eq!(
            w,
            vec!["ignored vertex colours on 1 `v` line (line 6)".to_string()]
        );
    }

    #[test]
    fn skipped_directives_give_one_warning_per_kind() {
        let text = format!(
            "mtllib a.mtl\no thing\n{SQUARE_V}vt 0 0\nvt 1 0\nvn 0 0 1\ng grp\ns 1\nusemtl m\n\
             l 1 2\np 3\nfoo bar\nvt 1 1\nfoo\nf 1 2 3 4\n"
        );
        let (m, w) = parse_obj(&text).unwrap();
        assert_eq!(m.faces.len(), 1);
        assert_eq!(
            w,
            vec![
                "skipped 1 `mtllib` line (line 1)",
                "skipped 1 `o` line (line 2)",
                "skipped 3 `vt` lines (first at line 7)",
                "skipped 1 `vn` line (line 9)",
                "skipped 1 `g` line (line 10)",
                "skipped 1 `s` line (line 11)",
                "skipped 1 `usemtl` line (line 12)",
                "skipped 1 `l` line (line 13)",
                "skipped 1 `p` line (line 14)",
                "skipped 2 lines with unknown directive `foo` (first at line 15)",
            ]
        );
    }

    #[test]
    fn many_unknown_directives_are_pooled() {
        let mut text = String::from(SQUARE_V);
        for i in 0..40 {
            let _ = writeln!(text, "x{i} 1");
        }
        text.push_str("f 1 2 3 4\n");
        let (_, w) = parse_obj(&text).unwrap();
        assert_eq!(w.len(), MAX_UNKNOWN_KINDS + 1);
        assert_eq!(
            w.last().unwrap(),
            "skipped 24 lines with other unknown directives (first at line 21)"
        );
    }

    #[test]
    fn errors_name_their_line() {
        let cases: Vec<(String, MeshError, &str)> = vec![
            (
                format!("{SQUARE_V}\nf 1 2 3\n"),
                MeshError::NotQuad { line: 6, count: 3 },
                "line 6: face has 3 vertices; lsubdiv refines quad meshes only (convert first, e.g. by a Catmull–Clark step in another tool: triangles are not turned into quads here)",
            ),
            (
                format!("{SQUARE_V}f 1 2 3 4 1\n"),
                MeshError::NotQuad { line: 5, count: 5 },
                "line 5: face has 5 vertices; lsubdiv refines quad meshes only (convert first, e.g. by a Catmull–Clark step in another tool: triangles are not turned into quads here)",
            ),
            (
                format!("{SQUARE_V}f\n"),
                MeshError::NotQuad { line: 5, count: 0 },
                "line 5: face has 0 vertices; lsubdiv refines quad meshes only (convert first, e.g. by a Catmull–Clark step in another tool: triangles are not turned into quads here)",
            ),
            (
                format!("{SQUARE_V}f 0 1 2 3\n"),
                MeshError::ZeroIndex { line: 5 },
                "line 5: vertex index 0 is invalid (OBJ indices start at 1)",
            ),
            (
                format!("{SQUARE_V}f 1 2 3 -0\n"),
                MeshError::ZeroIndex { line: 5 },
                "line 5: vertex index 0 is invalid (OBJ indices start at 1)",
            ),
            (
                format!("{SQUARE_V}v 0 0 1\nv 1 1 1\nv 1 0 1\nv 0 1 1\nf 1 2 3 40\n"),
                MeshError::IndexOutOfRange {
                    line: 9,
                    index: "40".into(),
                    vertices: 8,
                },
                "line 9: vertex index 40 out of range (the file has 8 vertices)",
            ),
            (
                format!("{SQUARE_V}f -5 1 2 3\n"),
                MeshError::IndexOutOfRange {
                    line: 5,
                    index: "-5".into(),
                    vertices: 4,
                },
                "line 5: vertex index -5 out of range (only 4 vertices precede this line)",
            ),
            (
                format!("{SQUARE_V}f 1 2 3 99999999999999999999\n"),
                MeshError::IndexOutOfRange {
                    line: 5,
                    index: "99999999999999999999".into(),
                    vertices: 4,
                },
                "line 5: vertex index 99999999999999999999 out of range (the file has 4 vertices)",
            ),
            (
                format!("{SQUARE_V}f 1 2 3 -99999999999999999999\n"),
                MeshError::IndexOutOfRange {
                    line: 5,
                    index: "-99999999999999999999".into(),
                    vertices: 4,
                },
                "line 5: vertex index -99999999999999999999 out of range (only 4 vertices precede this line)",
            ),
            (
                format!("{SQUARE_V}f 1 2 3 -9223372036854775808\n"),
                MeshError::IndexOutOfRange {
                    line: 5,
                    index: "-9223372036854775808".into(),
                    vertices: 4,
                },
                "line 5: vertex index -9223372036854775808 out of range (only 4 vertices precede this line)",
            ),
            (
                format!("{SQUARE_V}f 1 2 3 a\n"),
                MeshError::BadIndex {
                    line: 5,
                    token: "a".into(),
                },
                "line 5: `a` is not a face corner (i, i/t, i//n or i/t/n)",
            ),
            (
                format!("{SQUARE_V}f 1 2 3 4/1/1/1\n"),
                MeshError::BadIndex {
                    line: 5,
                    token: "4/1/1/1".into(),
                },
                "line 5: `4/1/1/1` is not a face corner (i, i/t, i//n or i/t/n)",
            ),
            (
                format!("{SQUARE_V}f 1 2 3 4/x\n"),
                MeshError::BadIndex {
                    line: 5,
                    token: "4/x".into(),
                },
                "line 5: `4/x` is not a face corner (i, i/t, i//n or i/t/n)",
            ),
            (
                format!("{SQUARE_V}f 1 2 3 4/\n"),
                MeshError::BadIndex {
                    line: 5,
                    token: "4/".into(),
                },
                "line 5: `4/` is not a face corner (i, i/t, i//n or i/t/n)",
            ),
            (
                format!("{SQUARE_V}f 1 2 3 4/1/\n"),
                MeshError::BadIndex {
                    line: 5,
                    token: "4/1/".into(),
                },
                "line 5: `4/1/` is not a face corner (i, i/t, i//n or i/t/n)",
            ),
            (
                format!("{SQUARE_V}f 1 2 3 /4\n"),
                MeshError::BadIndex {
                    line: 5,
                    token: "/4".into(),
                },
                "line 5: `/4` is not a face corner (i, i/t, i//n or i/t/n)",
            ),
            (
                "v 0 0 0\nv nan 0 0\nf 1 1 1 1\n".into(),
                MeshError::NonFinite {
                    line: 2,
                    token: "nan".into(),
                },
                "line 2: coordinate `nan` is not finite",
            ),
            (
                "v 0 0 1e999\n".into(),
                MeshError::NonFinite {
                    line: 1,
                    token: "1e999".into(),
                },
                "line 1: coordinate `1e999` is not finite",
            ),
            (
                "v 0 0 -inf\n".into(),
                MeshError::NonFinite {
                    line: 1,
                    token: "-inf".into(),
                },
                "line 1: coordinate `-inf` is not finite",
            ),
            (
                "\n\nv 0 0x1 0\n".into(),
                MeshError::BadNumber {
                    line: 3,
                    token: "0x1".into(),
                },
                "line 3: `0x1` is not a number",
            ),
            (
                "v 0 0 0 1 abc 3\n".into(),
                MeshError::BadNumber {
                    line: 1,
                    token: "abc".into(),
                },
                "line 1: `abc` is not a number",
            ),
            (
                "v 0 0\n".into(),
                MeshError::CoordinateCount { line: 1, count: 2 },
                "line 1: vertex has 2 values; expected x y z, x y z w or x y z r g b",
            ),
            (
                "v 0 0 0 0 0\n".into(),
                MeshError::CoordinateCount { line: 1, count: 5 },
                "line 1: vertex has 5 values; expected x y z, x y z w or x y z r g b",
            ),
            (SQUARE_V.into(), MeshError::NoFaces, "empty mesh: no faces"),
            (String::new(), MeshError::NoFaces, "empty mesh: no faces"),
        ];
        for (text, expected, message) in cases {
            let e = err(&text);
            assert_eq!(e, expected, "{text:?}");
            assert_eq!(e.to_string(), message, "{text:?}");
        }
    }

    #[test]
    fn long_tokens_are_shortened_in_messages() {
        let long = "y".repeat(1000);
        let e = err(&format!("v 0 0 {long}\n"));
        let msg = e.to_string();
        assert!(msg.len() < 100, "{msg}");
        assert!(msg.contains('…'), "{msg}");
    }

    #[test]
    fn obj_round_trip_is_bit_exact() {
        let mut rng = Rng(0x9e37_79b9_7f4a_7c15);
        let mut m = torus(5, 7);
        // Awkward values: tiny, huge, negative zero, subnormal, many digits.
        m.positions[0] = [-0.0, 1e-300, 5e-324];
        m.positions[1] = [1.7976931348623157e308, -1e22, 0.1 + 0.2];
        for p in &mut m.positions[2..] {
            for x in p.iter_mut() {
                *x = f64::from_bits(rng.next() >> 2) * if rng.next() & 1 == 0 { 1.0 } else { -1.0 };
                if !x.is_finite() {
                    *x = 1.0 / 3.0;
                }
            }
        }
        for mesh in [m, cube(), klein_bottle(4, 5)] {
            let text = to_obj(&mesh);
            let (back, warnings) = parse_obj(&text).unwrap();
            assert!(warnings.is_empty());
            assert_eq!(back.faces, mesh.faces);
            assert_eq!(back.positions.len(), mesh.positions.len());
            for (a, b) in back.positions.iter().zip(&mesh.positions) {
                for c in 0..3 {
                    assert_eq!(a[c].to_bits(), b[c].to_bits());
                }
            }
        }
    }

    #[test]
    fn ply_header_and_body() {
        let m = cube();
        let ply = to_ply(&m);
        let lines: Vec<&str> = ply.lines().collect();
        assert_eq!(
            &lines[..10],
            &[
                "ply",
                "format ascii 1.0",
                "comment lsubdiv quad mesh",
                "element vertex 8",
                "property double x",
                "property double y",
                "property double z",
                "element face 6",
                "property list uchar int vertex_indices",
                "end_header",
            ]
        );
        assert_eq!(lines.len(), 10 + 8 + 6);
        assert_eq!(lines[10], "-1.0 -1.0 -1.0");
        let f0 = m.faces[0];
        assert_eq!(
            lines[18],
            format!("4 {} {} {} {}", f0[0], f0[1], f0[2], f0[3])
        );
        for (line, p) in lines[10..18].iter().zip(&m.positions) {
            let xs: Vec<f64> = line.split(' ').map(|t| t.parse().unwrap()).collect();
            assert_eq!(xs, p.to_vec());
        }
    }

    /// Parsing and topology building never panic, whatever the input.
    #[test]
    fn garbage_never_panics() {
        let mut rng = Rng(12345);
        let base = to_obj(&torus(3, 4));
        let alphabet = b"0123456789 -+/.\nfvte#\r\tnai\xff";
        let mut checked = 0;
        for round in 0..600 {
            let text = if round % 3 == 0 {
                // Random bytes.
                let n = rng.below(200);
                let bytes: Vec<u8> = (0..n).map(|_| rng.next() as u8).collect();
                String::from_utf8_lossy(&bytes).into_owned()
            } else if round % 3 == 1 {
                // Random strings over an OBJ-ish alphabet.
                let n = rng.below(300);
                let bytes: Vec<u8> = (0..n)
                    .map(|_| alphabet[rng.below(alphabet.len())])
                    .collect();
                String::from_utf8_lossy(&bytes).into_owned()
            } else {
                // A valid file with a few mutations.
                let mut bytes = base.clone().into_bytes();
                for _ in 0..1 + rng.below(4) {
                    let at = rng.below(bytes.len());
                    match rng.below(4) {
                        0 => {
                            bytes.remove(at);
                        }
                        1 => bytes.insert(at, alphabet[rng.below(alphabet.len())]),
                        2 => bytes[at] = alphabet[rng.below(alphabet.len())],
                        _ => {
                            let len = rng.below(40).min(bytes.len() - at);
                            bytes.drain(at..at + len);
                        }
                    }
                }
                String::from_utf8_lossy(&bytes).into_owned()
            };
            if let Ok((mesh, _)) = parse_obj(&text) {
                let _ = Topology::build(&mesh);
                checked += 1;
            }
        }
        assert!(checked > 20, "only {checked} inputs parsed");
    }

    /// Random connectivity (in and out of range) never panics the topology builder.
    #[test]
    fn random_meshes_never_panic_topology() {
        let mut rng = Rng(777);
        for round in 0..400 {
            let nv = 1 + rng.below(12);
            let nf = rng.below(16);
            let faces = (0..nf)
                .map(|_| {
                    std::array::from_fn(|_| rng.below(nv + usize::from(round % 5 == 0)) as u32)
                })
                .collect();
            let mesh = QuadMesh {
                positions: vec![[0.0; 3]; nv],
                faces,
            };
            let _ = Topology::build(&mesh);
        }
        // Mutations of valid meshes: one face index changed.
        for round in 0..300 {
            let mut m = if round % 2 == 0 { torus(3, 3) } else { cube() };
            let f = rng.below(m.faces.len());
            let c = rng.below(4);
            m.faces[f][c] = rng.below(m.positions.len()) as u32;
            if round % 7 == 0 {
                m.faces.swap_remove(rng.below(m.faces.len()));
            }
            let _ = Topology::build(&m);
        }
    }
}
