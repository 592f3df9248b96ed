//! OBJ files of polygon meshes: reading with every problem placed at its line (the reader
//! keeps the line of each `v`, `f` and sharp-feature tag `t` it parsed, so the topology's and
//! the features' errors — face k, vertex v, edge a–b, crease a–b — are placed there too,
//! vertices numbered as in the file), and writing quad meshes. The tags are OpenSubdiv's
//! ([`crate::obj_tags`]).

use crate::mesh_data::{counted, shorten, too_few_corners, Extras, Parsed, Places, Unit};
use crate::obj_tags::{is_integer, Tags, Token};
use lsubdiv_io::{Error, Location};
use lsubdiv_mesh::facevarying::{PolyUv, UvRule};
use lsubdiv_mesh::polygon::PolyMesh;
use lsubdiv_mesh::topology::TopologyError;
use lsubdiv_mesh::QuadMesh;
use std::fmt::Write as _;
use std::path::Path;

/// Calls `f(line, tokens)` for each logical line of `text` that has tokens: `line` is its first
/// physical line, `tokens` its tokens (split at ASCII whitespace) with the physical line of
/// each, comments (`#` to the end of the physical line) stripped. A physical line whose content
/// ends in `\` (trailing spaces and a CR allowed) continues on the next, the `\` read as a
/// space; on the last line it ends the file.
fn for_each_line<'a>(
    text: &'a str,
    mut f: impl FnMut(usize, &[Token<'a>]) -> Result<(), Error>,
) -> Result<(), Error> {
    let mut tokens: Vec<Token<'a>> = Vec::new();
    let mut first = 0;
    for (k, raw) in text.lines().enumerate() {
        let line = k + 1;
        let content = raw.split_once('#').map_or(raw, |(c, _)| c).trim_ascii_end();
        let (content, continued) = match content.strip_suffix('\\') {
            Some(c) if !raw.contains('#') => (c, true),
            _ => (content, false),
        };
        if tokens.is_empty() {
            first = line;
        }
        tokens.extend(content.split_ascii_whitespace().map(|t| (t, line)));
        if !continued && !tokens.is_empty() {
            f(first, &tokens)?;
            tokens.clear();
        }
    }
    if tokens.is_empty() {
        Ok(())
    } else {
        f(first, &tokens)
    }
}

/// Directives of the OBJ format that carry nothing a quad mesh needs.
const KNOWN_SKIPPED: &[&str] = &[
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

/// Distinct unknown directives and tags reported one by one; further ones are pooled into one
/// warning.
const MAX_UNKNOWN_KINDS: usize = 16;

#[derive(Clone, Debug, PartialEq, Eq)]
enum SkipKind {
    Known(&'static str),
    Unknown(String),
    /// A `t` line whose tag lsubdiv does not read.
    UnknownTag(String),
    OtherUnknown,
    VertexColours,
    /// `vt` lines when no face has texture indices.
    UnusedTextures,
    /// `vn` lines and faces with normal indices.
    Normals,
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

    /// Drops the entry of `kind`, if any.
    fn forget(&mut self, kind: &SkipKind) {
        self.entries.retain(|e| e.0 != *kind);
    }

    fn note_directive(&mut self, d: &str, line: usize) {
        match KNOWN_SKIPPED.iter().find(|&&k| k == d) {
            Some(&known) => self.note_kind(SkipKind::Known(known), line),
            None => self.note_unknown(SkipKind::Unknown(shorten(d)), line),
        }
    }

    /// Notes an unknown directive or tag, pooled once [`MAX_UNKNOWN_KINDS`] kinds are seen.
    fn note_unknown(&mut self, kind: SkipKind, line: usize) {
        let seen = self.entries.iter().any(|e| e.0 == kind);
        if seen || self.unknown_kinds < MAX_UNKNOWN_KINDS {
            if !seen {
                self.unknown_kinds += 1;
            }
            self.note_kind(kind, line);
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
                    SkipKind::UnknownTag(t) => {
                        format!("skipped {count} {noun} with unknown tag `t {t}` {at}")
                    }
                    SkipKind::OtherUnknown => {
                        format!("skipped {count} {noun} with other unknown directives or tags {at}")
                    }
                    SkipKind::VertexColours => {
                        format!("ignored vertex colours on {count} `v` {noun} {at}")
                    }
                    SkipKind::UnusedTextures => {
                        format!("ignored {count} `vt` {noun} {at}: no face has texture indices")
                    }
                    SkipKind::Normals => format!(
                        "ignored normals (`vn`, normal indices of faces) on {count} {noun} {at}: \
                         normals are recomputed (e.g. by `--limit`)"
                    ),
                }
            })
            .collect()
    }
}

/// The numbers of a line's values, the first `finite` of them finite (`what` names them in
/// messages), or the line of the bad value and the message.
fn numbers(
    tokens: &[Token<'_>],
    finite: usize,
    what: &str,
) -> Result<Vec<f64>, (Option<usize>, String)> {
    let mut out = Vec::with_capacity(tokens.len());
    for &(tok, line) in tokens {
        let x: f64 = tok
            .parse()
            .map_err(|_| (Some(line), format!("`{}` is not a number", shorten(tok))))?;
        if out.len() < finite && !x.is_finite() {
            return Err((
                Some(line),
                format!("{what} `{}` is not finite", shorten(tok)),
            ));
        }
        out.push(x);
    }
    Ok(out)
}

/// Parses the values of a `v` line; returns the position and whether colours were present, or
/// the line of the bad value and the message.
fn parse_vertex(tokens: &[Token<'_>]) -> Result<([f64; 3], bool), (Option<usize>, String)> {
    let count = tokens.len();
    if !matches!(count, 3 | 4 | 6) {
        return Err((
            None,
            format!(
                "vertex has {}; expected x y z, x y z w or x y z r g b",
                counted(count, "value", "values")
            ),
        ));
    }
    let x = numbers(tokens, 3, "coordinate")?;
    Ok(([x[0], x[1], x[2]], count == 6))
}

/// Parses the values of a `vt` line (`u v [w]`, w ignored), or the line of the bad value and
/// the message.
fn parse_texture(tokens: &[Token<'_>]) -> Result<[f64; 2], (Option<usize>, String)> {
    let count = tokens.len();
    if !matches!(count, 2 | 3) {
        return Err((
            None,
            format!(
                "texture coordinate has {}; expected u v or u v w",
                counted(count, "value", "values")
            ),
        ));
    }
    let x = numbers(tokens, 2, "texture coordinate")?;
    Ok([x[0], x[1]])
}

/// One face corner: its vertex, its texture coordinate if it names one, and whether it names
/// a normal (0-based indices).
struct Corner {
    vertex: u32,
    texture: Option<u32>,
    normal: bool,
}

/// How many of something the file has: defined before this line (for negative indices) and in
/// the whole file (for positive ones).
#[derive(Clone, Copy)]
struct Defined {
    before: usize,
    total: usize,
}

/// Resolves the OBJ index `index` (1-based, or negative: relative to the line) of a `what`
/// (`vertex`, `texture`) among `defined` ones (`one`, `many`: their nouns) to a 0-based index.
fn resolve(
    index: &str,
    what: &str,
    (one, many): (&str, &str),
    defined: Defined,
) -> Result<u32, String> {
    let negative = index.starts_with('-');
    let limit = if negative {
        defined.before
    } else {
        defined.total
    };
    let out_of_range = || {
        let things = counted(limit, one, many);
        let index = shorten(index);
        if negative {
            let verb = if limit == 1 { "precedes" } else { "precede" };
            format!("{what} index {index} out of range (only {things} {verb} this line)")
        } else {
            format!("{what} index {index} out of range (the file has {things})")
        }
    };
    let i: i64 = index.parse().map_err(|_| out_of_range())?;
    let resolved = match i {
        0 => {
            return Err(format!(
                "{what} index 0 is invalid (OBJ indices start at 1)"
            ))
        }
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

/// Parses one face corner `i`, `i/t`, `i//n` or `i/t/n` among the `vertices` and `textures`
/// (`vt`) the file defines; normal indices are not resolved (normals are ignored).
fn parse_corner(tok: &str, vertices: Defined, textures: Defined) -> Result<Corner, String> {
    let mut parts = tok.split('/');
    let index = parts.next().unwrap_or("");
    let rest: Vec<&str> = parts.collect();
    let (texture, normal, well_formed) = match rest.as_slice() {
        [] => ("", false, true),
        [t] => (*t, false, is_integer(t)),
        [t, n] => (*t, true, (t.is_empty() || is_integer(t)) && is_integer(n)),
        _ => ("", false, false),
    };
    if !well_formed || !is_integer(index) {
        return Err(format!(
            "`{}` is not a face corner (i, i/t, i//n or i/t/n)",
            shorten(tok)
        ));
    }
    let noun = ("texture coordinate", "texture coordinates");
    Ok(Corner {
        vertex: resolve(index, "vertex", ("vertex", "vertices"), vertices)?,
        texture: (!texture.is_empty())
            .then(|| resolve(texture, "texture", noun, textures))
            .transpose()?,
        normal,
    })
}

/// Parses OBJ text (`file` names it in errors): `v x y z [w]` (w ignored; `v x y z r g b`
/// with vertex colours is accepted with a warning), `vt u v [w]` (w ignored), `f a b c d`
/// where each corner may be `i`, `i/t`, `i//n`, `i/t/n`, with negative (relative) indices
/// supported. Texture indices are read into [`Parsed::uv`] (values: the `vt` lines in file
/// order): every face has them or none; a file whose faces have none ignores its `vt` lines
/// with a warning. `vn` lines and normal indices are ignored with one warning (normals are
/// recomputed). A line ending in `\` continues on the next. OpenSubdiv's sharp-feature
/// tags (`t crease`, `t corner`, `t hole`, `t interpolateboundary`) are read into
/// [`Parsed::features`] ([`crate::obj_tags`]); other tags are skipped with a warning.
///
/// Lines it does not need (`o`, `g`, `s`, `usemtl`, `mtllib`, `l`, `p`, other OBJ directives,
/// unknown directives, comments, blank lines) are skipped with one warning per kind of
/// skipped directive (count and first line). Errors are at their physical line. A file
/// without faces is an error. Connectivity is not checked here (see [`Parsed::check`]).
pub fn parse(file: &str, text: &str) -> Result<Parsed, Error> {
    // Positive indices may refer to vertices and texture coordinates defined later in the file.
    let (mut vertices, mut textures) = (0, 0);
    for_each_line(text, |_, tokens| {
        vertices += usize::from(tokens[0].0 == "v");
        textures += usize::from(tokens[0].0 == "vt");
        Ok(())
    })?;
    let mut mesh = PolyMesh::new();
    let mut uv = PolyUv::default();
    // Whether the first face has texture indices, and its line.
    let mut textured: Option<(bool, usize)> = None;
    let mut places = Places::new(Unit::Line, 1);
    let mut skipped = Skipped::default();
    let mut tags = Tags::default();
    for_each_line(text, |line, tokens| {
        let at = |l: usize, message: String| Error::at(Location::line(file, l), message);
        let (d, values) = (tokens[0].0, &tokens[1..]);
        match d {
            "v" => {
                let (p, colours) =
                    parse_vertex(values).map_err(|(l, m)| at(l.unwrap_or(line), m))?;
                if colours {
                    skipped.note_kind(SkipKind::VertexColours, line);
                }
                mesh.positions.push(p);
                places.vertices.push(line);
            }
            "vt" => {
                let t = parse_texture(values).map_err(|(l, m)| at(l.unwrap_or(line), m))?;
                uv.values.push(t);
                skipped.note_kind(SkipKind::UnusedTextures, line);
            }
            "vn" => skipped.note_kind(SkipKind::Normals, line),
            "f" => {
                if values.len() < 3 {
                    return Err(at(line, too_few_corners(values.len())));
                }
                let v = Defined {
                    before: mesh.positions.len(),
                    total: vertices,
                };
                let t = Defined {
                    before: uv.values.len(),
                    total: textures,
                };
                let corners = values
                    .iter()
                    .map(|&(tok, l)| parse_corner(tok, v, t).map_err(|m| at(l, m)))
                    .collect::<Result<Vec<Corner>, Error>>()?;
                let has = corners[0].texture.is_some();
                if let Some(k) = corners.iter().position(|c| c.texture.is_some() != has) {
                    return Err(at(
                        values[k].1,
                        "some corners of this face have texture indices and others do not \
                         (every corner has one or none)"
                            .into(),
                    ));
                }
                match textured {
                    None => textured = Some((has, line)),
                    Some((first, l)) if first != has => {
                        let (this, that) = if has {
                            ("has", "none")
                        } else {
                            ("has no", "them")
                        };
                        return Err(at(
                            line,
                            format!(
                                "this face {this} texture indices, but the face at line {l} \
                                 has {that} (every face has them or none)"
                            ),
                        ));
                    }
                    Some(_) => {}
                }
                if corners.iter().any(|c| c.normal) {
                    skipped.note_kind(SkipKind::Normals, line);
                }
                let face: Vec<u32> = corners.iter().map(|c| c.vertex).collect();
                uv.corners.extend(corners.iter().filter_map(|c| c.texture));
                mesh.push_face(&face);
                places.faces.push(line);
            }
            "t" => match tags.read(line, values) {
                Ok(Some(tag)) => skipped.note_unknown(SkipKind::UnknownTag(shorten(tag)), line),
                Ok(None) => {}
                Err((l, m)) => return Err(at(l, m)),
            },
            _ => skipped.note_directive(d, line),
        }
        Ok(())
    })?;
    if mesh.face_count() == 0 {
        return Err(places.locate(file, &TopologyError::NoFaces));
    }
    let uv = textured.is_some_and(|(t, _)| t).then_some(uv);
    if uv.is_some() {
        skipped.forget(&SkipKind::UnusedTextures);
    }
    places.features = tags.lines;
    Ok(Parsed {
        mesh,
        places,
        features: tags.features,
        uv,
        uv_rule: tags.uv_rule.map_or(UvRule::default(), |(rule, _)| rule),
        warnings: skipped.warnings(),
    })
}

/// Writes `mesh` to `path` as OBJ ([`format()`]), whole or not at all, streamed
/// ([`crate::write_atomic_with`]).
pub fn write(path: &Path, mesh: &QuadMesh) -> Result<(), Error> {
    write_with(path, mesh, Extras::default())
}

/// [`write()`] with the channels `extras` carries (normals, texture coordinates: [`format_with`]),
/// checked before anything is written, then streamed.
pub fn write_with(path: &Path, mesh: &QuadMesh, extras: Extras<'_>) -> Result<(), Error> {
    let text = Text::new(mesh, extras)?;
    crate::write_atomic_with(path, |out| write!(out, "{text}"))
}

/// OBJ text: a comment line, `v` lines at full round-trip f64 precision (`{:?}` of f64), then
/// `f` lines (1-based). A non-finite coordinate (which [`parse()`] would reject) is refused
/// instead ([`crate::points::finite`]).
pub fn format(mesh: &QuadMesh) -> Result<String, Error> {
    format_with(mesh, Extras::default())
}

/// [`format()`] with extras: normals as `vn` lines after the `v` lines, one per vertex in the
/// same order, texture coordinates as `vt` lines after them; faces `f a/ta …`, `f a//a …` or
/// `f a/ta/a …`.
pub fn format_with(mesh: &QuadMesh, extras: Extras<'_>) -> Result<String, Error> {
    let text = Text::new(mesh, extras)?;
    let mut s = String::with_capacity(32 * mesh.positions.len() + 24 * mesh.faces.len() + 64);
    let _ = write!(s, "{text}");
    Ok(s)
}

/// The OBJ text of a mesh with its extras, checked ([`format_with`]) and not yet formatted:
/// `write!` it into any writer (`lsubdiv::write_atomic_with` streams it to a file).
pub struct Text<'a> {
    mesh: &'a QuadMesh,
    extras: Extras<'a>,
}

impl<'a> Text<'a> {
    /// Refuses what an OBJ file cannot hold ([`Extras::check`]: a non-finite coordinate, extras
    /// that do not fit the mesh).
    pub fn new(mesh: &'a QuadMesh, extras: Extras<'a>) -> Result<Text<'a>, Error> {
        extras.check(mesh)?;
        Ok(Text { mesh, extras })
    }
}

impl std::fmt::Display for Text<'_> {
    fn fmt(&self, s: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        let Text { mesh, extras } = self;
        writeln!(
            s,
            "# lsubdiv quad mesh: {} vertices, {} faces",
            mesh.positions.len(),
            mesh.faces.len()
        )?;
        for p in &mesh.positions {
            writeln!(s, "v {:?} {:?} {:?}", p[0], p[1], p[2])?;
        }
        for n in extras.normals.into_iter().flatten() {
            writeln!(s, "vn {:?} {:?} {:?}", n[0], n[1], n[2])?;
        }
        for t in extras.uv.iter().flat_map(|uv| &uv.values) {
            writeln!(s, "vt {:?} {:?}", t[0], t[1])?;
        }
        let normals = extras.normals.is_some();
        for (f, face) in mesh.faces.iter().enumerate() {
            s.write_char('f')?;
            for (c, &v) in face.iter().enumerate() {
                let v = u64::from(v) + 1;
                write!(s, " {v}")?;
                if let Some(uv) = extras.uv {
                    write!(s, "/{}", u64::from(uv.faces[f][c]) + 1)?;
                } else if normals {
                    s.write_char('/')?;
                }
                if normals {
                    write!(s, "/{v}")?;
                }
            }
            s.write_char('\n')?;
        }
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use lsubdiv_mesh::features::{Creasing, Triangles};
    use lsubdiv_mesh::generators::{cube, klein_bottle, torus};
    use lsubdiv_mesh::topology::Topology;

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

    fn err(text: &str) -> Error {
        parse("t.obj", text).expect_err("should not parse")
    }

    /// The mesh and warnings of OBJ text.
    fn parse_obj(text: &str) -> Result<(PolyMesh, Vec<String>), Error> {
        parse("t.obj", text).map(|p| (p.mesh, p.warnings))
    }

    /// The faces of a parsed mesh.
    fn faces(m: &PolyMesh) -> Vec<Vec<u32>> {
        m.faces().map(<[u32]>::to_vec).collect()
    }

    #[test]
    fn face_corner_syntax_variants() {
        // Texture indices: none, or per corner (after four `vt` lines, at lines 5–8).
        let vt = "vt 0 0\nvt 1 0\nvt 1 1\nvt 0 1\n";
        for (face, uv, normals) in [
            ("f 1 2 3 4", None, false),
            ("f 1//7 2//7 3//7 4//7", None, true),
            ("f -4 -3 -2 -1", None, false),
            ("f +1 2 3 4", None, false),
            ("f 1/1 2/2 3/3 4/4", Some(vec![0, 1, 2, 3]), false),
            ("f 1/4/1 2/3/2 3/2/3 4/1/4", Some(vec![3, 2, 1, 0]), true),
            ("f -4/1 -3/-3/2 3/+3/4 -1/-1", Some(vec![0, 1, 2, 3]), true),
        ] {
            let p = parse("t.obj", &format!("{SQUARE_V}{vt}{face}\n")).unwrap();
            assert_eq!(faces(&p.mesh), vec![vec![0, 1, 2, 3]], "{face}");
            assert_eq!(p.mesh.positions.len(), 4);
            let values = vec![[0.0, 0.0], [1.0, 0.0], [1.0, 1.0], [0.0, 1.0]];
            let want = uv.map(|corners| PolyUv { values, corners });
            assert_eq!(p.uv, want, "{face}");
            let mut w = Vec::new();
            if p.uv.is_none() {
                w.push("ignored 4 `vt` lines (first at line 5): no face has texture indices");
            }
            if normals {
                w.push(
                    "ignored normals (`vn`, normal indices of faces) on 1 line (line 9): \
                     normals are recomputed (e.g. by `--limit`)",
                );
            }
            assert_eq!(p.warnings, w, "{face}");
        }
    }

    #[test]
    fn texture_coordinates_are_read_with_relative_indices() {
        // A quad and a triangle; the vt lines interleaved, one of them unused, with `w`.
        let text = "v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nvt 0.5 0.25\nvt 1 0 7\n\
                    vt -2 3e1\nf 1/1 2/2 3/3 4/-1\nvt 0.125 0.5\nvt 9 9\nv 2 0 0\n\
                    f 2/-2 5/5 3/3\n";
        let p = parse("t.obj", text).unwrap();
        assert_eq!(faces(&p.mesh), vec![vec![0, 1, 2, 3], vec![1, 4, 2]]);
        let uv = p.uv.expect("textured");
        assert_eq!(
            uv.values,
            vec![
                [0.5, 0.25],
                [1.0, 0.0],
                [-2.0, 30.0],
                [0.125, 0.5],
                [9.0, 9.0]
            ]
        );
        assert_eq!(uv.corners, vec![0, 1, 2, 2, 3, 4, 2]);
        assert!(p.warnings.is_empty(), "{:?}", p.warnings);
    }

    #[test]
    fn texture_errors_name_their_line() {
        let vt = "vt 0 0\nvt 1 0\nvt 1 1\nvt 0 1\n"; // lines 5–8
        for (text, line, message) in [
            (
                format!("{SQUARE_V}{vt}f 1/1 2/2 3/3 4/4\nf 1 2 3 4\n"),
                10,
                "this face has no texture indices, but the face at line 9 has them (every face has them or none)",
            ),
            (
                format!("{SQUARE_V}{vt}f 1 2 3 4\n\nf 1//1 2//1 3//1 4//1\nf 1/1 2/2 3/3 4/4\n"),
                12,
                "this face has texture indices, but the face at line 9 has none (every face has them or none)",
            ),
            (
                format!("{SQUARE_V}{vt}f 1/1 2/2 \\\n3/3 4\n"),
                10,
                "some corners of this face have texture indices and others do not (every corner has one or none)",
            ),
            (
                format!("{SQUARE_V}{vt}f 1 2/5 3//6 4/7/8\n"),
                9,
                "texture index 5 out of range (the file has 4 texture coordinates)",
            ),
            (
                format!("{SQUARE_V}{vt}f 1 \\\n2/2 3//6 4/2/8\n"),
                10,
                "some corners of this face have texture indices and others do not (every corner has one or none)",
            ),
            (
                format!("{SQUARE_V}f 1/1 2/2 3/3 4/4\n"),
                5,
                "texture index 1 out of range (the file has 0 texture coordinates)",
            ),
            (
                format!("{SQUARE_V}vt 0 0\nf 1/1 2/-2 3/1 4/1\nvt 1 1\n"),
                6,
                "texture index -2 out of range (only 1 texture coordinate precedes this line)",
            ),
            (
                format!("{SQUARE_V}{vt}f 1/1 2/0 3/3 4/4\n"),
                9,
                "texture index 0 is invalid (OBJ indices start at 1)",
            ),
            (
                format!("{SQUARE_V}{vt}f 1/1 2/2 \\\n3/3 4/99999999999999999999\n"),
                10,
                "texture index 99999999999999999999 out of range (the file has 4 texture coordinates)",
            ),
            (format!("{SQUARE_V}vt 0\n"), 5, "texture coordinate has 1 value; expected u v or u v w"),
            (format!("{SQUARE_V}vt\n"), 5, "texture coordinate has 0 values; expected u v or u v w"),
            (format!("{SQUARE_V}vt 0 0 0 0\n"), 5, "texture coordinate has 4 values; expected u v or u v w"),
            (format!("{SQUARE_V}vt 0 \\\nnan\n"), 6, "texture coordinate `nan` is not finite"),
            (format!("{SQUARE_V}vt inf 0\n"), 5, "texture coordinate `inf` is not finite"),
            (format!("{SQUARE_V}vt 0 0 u\n"), 5, "`u` is not a number"),
        ] {
            assert_eq!(
                err(&text),
                Error::at(Location::line("t.obj", line), message),
                "{text:?}"
            );
        }
        // The w of `vt u v w` may be anything finite or not: it is ignored.
        let p = parse(
            "t.obj",
            &format!("{SQUARE_V}vt 0 0 nan\nf 1/1 2/1 3/1 4/1\n"),
        )
        .unwrap();
        assert_eq!(p.uv.unwrap().values, vec![[0.0, 0.0]]);
    }

    #[test]
    fn a_trailing_backslash_continues_the_line() {
        for (text, lines) in [
            ("f 1 2 \\\n3 4\n", vec![5]),
            ("f 1 2 \\\r\n3 4\r\n", vec![5]),
            ("f 1 2 \\   \t\n  3 4\n", vec![5]),
            ("f 1 \\\n2 \\\n3 4\n", vec![5]),
            ("f\\\n1 2 3 4\n", vec![5]),
            ("f 1 2 3 4 \\", vec![5]),
            ("# a comment \\\nf 1 2 3 4\n", vec![6]),
        ] {
            let p = parse("t.obj", &format!("{SQUARE_V}{text}"))
                .unwrap_or_else(|e| panic!("{text:?}: {e}"));
            assert_eq!(faces(&p.mesh), vec![vec![0, 1, 2, 3]], "{text:?}");
            assert_eq!(p.places.faces, lines, "{text:?}");
        }
        let p = parse(
            "t.obj",
            "v 1 \\\n 2 \\\n3\nv 0 0 0\nv 1 1 1\nv 2 2 2\nf 1 2 3 4\n",
        )
        .unwrap();
        assert_eq!(p.mesh.positions[0], [1.0, 2.0, 3.0]);
        assert_eq!(p.places.vertices, vec![1, 4, 5, 6]);
        // Errors name the physical line of the bad token, or the first line of the directive.
        for (text, line, message) in [
            (
                "f 1 2 \\\n3 x\n",
                6,
                "`x` is not a face corner (i, i/t, i//n or i/t/n)",
            ),
            (
                "f 1 2 \\\n\\\n3 9\n",
                7,
                "vertex index 9 out of range (the file has 4 vertices)",
            ),
            ("v 1 \\\n2 nan\n", 6, "coordinate `nan` is not finite"),
            (
                "f 1 2 \\ # not continued: a comment follows\n3 4\n",
                5,
                "`\\` is not a face corner (i, i/t, i//n or i/t/n)",
            ),
        ] {
            assert_eq!(
                err(&format!("{SQUARE_V}{text}")),
                Error::at(Location::line("t.obj", line), message),
                "{text:?}"
            );
        }
        // Topology errors are placed at the first line of a continued face.
        let p = parse("t.obj", &format!("{SQUARE_V}\nf 1 2 \\\n 3 3\n")).unwrap();
        let e = Topology::build(&p.mesh.into_quads().unwrap()).expect_err("repeated");
        assert_eq!(
            p.places.locate("t.obj", &e).at,
            Some(Location::line("t.obj", 6))
        );
    }

    #[test]
    fn negative_indices_are_relative_to_the_line() {
        let text = "v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nf -4 -3 -2 -1\n\
                    v 0 0 1\nv 1 0 1\nf -6 -5 -1 -2\n";
        let (m, _) = parse_obj(text).unwrap();
        assert_eq!(faces(&m), vec![vec![0, 1, 2, 3], vec![0, 1, 5, 4]]);
        // Positive indices may point forward.
        let (m, _) = parse_obj("f 1 2 3 4\nv 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\n").unwrap();
        assert_eq!(faces(&m), vec![vec![0, 1, 2, 3]]);
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
             l 1 2\np 3\nfoo bar\nvt 1 1\nfoo\nf 1//1 2//1 3//1 4//1\n"
        );
        let (m, w) = parse_obj(&text).unwrap();
        assert_eq!(m.face_count(), 1);
        assert_eq!(
            w,
            vec![
                "skipped 1 `mtllib` line (line 1)",
                "skipped 1 `o` line (line 2)",
                "ignored 3 `vt` lines (first at line 7): no face has texture indices",
                "ignored normals (`vn`, normal indices of faces) on 2 lines (first at line 9): \
                 normals are recomputed (e.g. by `--limit`)",
                "skipped 1 `g` line (line 10)",
                "skipped 1 `s` line (line 11)",
                "skipped 1 `usemtl` line (line 12)",
                "skipped 1 `l` line (line 13)",
                "skipped 1 `p` line (line 14)",
                "skipped 2 lines with unknown directive `foo` (first at line 15)",
            ]
        );
        // OpenSubdiv's tags are read, without a warning; other tags are skipped with one
        // warning per tag.
        let p = parse(
            "t.obj",
            &format!(
                "{SQUARE_V}f 1 2 3 4\nt crease 2/1/0 0 1 10\nt vertexedit 0/0/1 x\n\
                 t corner 1/1/0 0 5\nt smoothtriangles 0/0/1 smooth\nt creasemethod 0/0/1 normal\n\
                 t vertexedit 0/0/1 y\nt faceedit 0/0/1 z\n"
            ),
        )
        .unwrap();
        assert_eq!(p.features.creases.len(), 1);
        assert_eq!(p.features.corners.len(), 1);
        assert_eq!(p.features.triangles, Triangles::Smooth);
        assert_eq!(
            p.warnings,
            vec![
                "skipped 2 lines with unknown tag `t vertexedit` (first at line 7)",
                "skipped 1 line with unknown tag `t faceedit` (line 12)",
            ]
        );
        // The creasing method, and a method that is none refused at its line.
        let chaikin = format!("{SQUARE_V}f 1 2 3 4\nt creasemethod 0/0/1 chaikin\n");
        let p = parse("t.obj", &chaikin).unwrap();
        assert_eq!(p.features.creasing, Creasing::Chaikin);
        let e = parse("t.obj", &chaikin.replace("chaikin", "loop")).unwrap_err();
        assert!(e.to_string().contains("t.obj:6"), "{e}");
        assert!(e.to_string().contains("not a creasing method"), "{e}");
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
            "skipped 24 lines with other unknown directives or tags (first at line 21)"
        );
    }

    #[test]
    fn errors_name_their_line() {
        let cases: Vec<(String, Option<usize>, &str)> = vec![
            // Tokens are split at ASCII whitespace only: a no-break space stays in its token.
            (
                format!("{SQUARE_V}v 1\u{a0}2 3\n"),
                Some(5),
                "vertex has 2 values; expected x y z, x y z w or x y z r g b",
            ),
            (
                format!("{SQUARE_V}\nf 1 2\n"),
                Some(6),
                "face has 2 vertices; a face has at least 3",
            ),
            (
                format!("{SQUARE_V}f\n"),
                Some(5),
                "face has 0 vertices; a face has at least 3",
            ),
            (
                format!("{SQUARE_V}f 0 1 2 3\n"),
                Some(5),
                "vertex index 0 is invalid (OBJ indices start at 1)",
            ),
            (
                format!("{SQUARE_V}f 1 2 3 -0\n"),
                Some(5),
                "vertex index 0 is invalid (OBJ indices start at 1)",
            ),
            (
                format!("{SQUARE_V}v 0 0 1\nv 1 1 1\nv 1 0 1\nv 0 1 1\nf 1 2 3 40\n"),
                Some(9),
                "vertex index 40 out of range (the file has 8 vertices)",
            ),
            (
                format!("{SQUARE_V}f -5 1 2 3\n"),
                Some(5),
                "vertex index -5 out of range (only 4 vertices precede this line)",
            ),
            (
                format!("{SQUARE_V}f 1 2 3 99999999999999999999\n"),
                Some(5),
                "vertex index 99999999999999999999 out of range (the file has 4 vertices)",
            ),
            (
                format!("{SQUARE_V}f 1 2 3 -99999999999999999999\n"),
                Some(5),
                "vertex index -99999999999999999999 out of range (only 4 vertices precede this line)",
            ),
            (
                format!("{SQUARE_V}f 1 2 3 -9223372036854775808\n"),
                Some(5),
                "vertex index -9223372036854775808 out of range (only 4 vertices precede this line)",
            ),
            (
                format!("{SQUARE_V}f 1 2 3 a\n"),
                Some(5),
                "`a` is not a face corner (i, i/t, i//n or i/t/n)",
            ),
            (
                format!("{SQUARE_V}f 1 2 3 4/1/1/1\n"),
                Some(5),
                "`4/1/1/1` is not a face corner (i, i/t, i//n or i/t/n)",
            ),
            (
                format!("{SQUARE_V}f 1 2 3 4/x\n"),
                Some(5),
                "`4/x` is not a face corner (i, i/t, i//n or i/t/n)",
            ),
            (
                format!("{SQUARE_V}f 1 2 3 4/\n"),
                Some(5),
                "`4/` is not a face corner (i, i/t, i//n or i/t/n)",
            ),
            (
                format!("{SQUARE_V}f 1 2 3 4/1/\n"),
                Some(5),
                "`4/1/` is not a face corner (i, i/t, i//n or i/t/n)",
            ),
            (
                format!("{SQUARE_V}f 1 2 3 /4\n"),
                Some(5),
                "`/4` is not a face corner (i, i/t, i//n or i/t/n)",
            ),
            (
                "v 0 0 0\nv nan 0 0\nf 1 1 1 1\n".into(),
                Some(2),
                "coordinate `nan` is not finite",
            ),
            (
                "v 0 0 1e999\n".into(),
                Some(1),
                "coordinate `1e999` is not finite",
            ),
            (
                "v 0 0 -inf\n".into(),
                Some(1),
                "coordinate `-inf` is not finite",
            ),
            (
                "\n\nv 0 0x1 0\n".into(),
                Some(3),
                "`0x1` is not a number",
            ),
            (
                "v 0 0 0 1 abc 3\n".into(),
                Some(1),
                "`abc` is not a number",
            ),
            (
                "v 0 0\n".into(),
                Some(1),
                "vertex has 2 values; expected x y z, x y z w or x y z r g b",
            ),
            (
                "v 0 0 0 0 0\n".into(),
                Some(1),
                "vertex has 5 values; expected x y z, x y z w or x y z r g b",
            ),
            (SQUARE_V.into(), None, "empty mesh: no faces"),
            (String::new(), None, "empty mesh: no faces"),
        ];
        for (text, line, message) in cases {
            let e = err(&text);
            let at = match line {
                Some(l) => Location::line("t.obj", l),
                None => Location::whole("t.obj"),
            };
            // Topology errors also carry a hint; the place and message are compared here.
            assert_eq!(
                (&e.at, &e.message),
                (&Some(at), &message.to_string()),
                "{text:?}"
            );
        }
    }

    #[test]
    fn topology_errors_are_placed_at_the_lines_read() {
        // Comments, blank lines and a skipped directive shift the lines of `v` and `f`.
        let text = "# square\n\nv 0 0 0\nvt 0 0\nv 1 0 0\nv 1 1 0\n\nv 0 1 0\nv 5 5 5\n# face\nf 1 2 3 3\n";
        let p = parse("t.obj", text).unwrap();
        assert_eq!(p.places.vertices, vec![3, 5, 6, 8, 9]);
        assert_eq!(p.places.faces, vec![11]);
        let e = Topology::build(&p.mesh.into_quads().unwrap()).expect_err("repeated");
        assert_eq!(
            p.places.locate("t.obj", &e).to_string(),
            "t.obj:11: error: the face lists vertex 3 twice\n  hint: a face lists each of its corners once"
        );
        let isolated = TopologyError::IsolatedVertex { vertex: 4 };
        assert_eq!(
            p.places.locate("t.obj", &isolated).message,
            "vertex 5 is used by no face (isolated vertex)"
        );
        let duplicate = TopologyError::DuplicateFaces {
            first: 0,
            second: 0,
        };
        assert_eq!(
            p.places.locate("t.obj", &duplicate).to_string(),
            "t.obj:11: error: duplicate face: the face at line 11 has the same vertices\n  \
             hint: remove one of the two faces"
        );
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
            let text = format(&mesh).unwrap();
            let (back, warnings) = parse_obj(&text).unwrap();
            assert!(warnings.is_empty());
            let back = back.into_quads().unwrap();
            assert_eq!(back.faces, mesh.faces);
            assert_eq!(back.positions.len(), mesh.positions.len());
            for (a, b) in back.positions.iter().zip(&mesh.positions) {
                for c in 0..3 {
                    assert_eq!(a[c].to_bits(), b[c].to_bits());
                }
            }
        }
    }

    /// `write_with` writes what `format_with` (and PLY's `format_with`, `binary_with`) make.
    #[test]
    fn meshes_are_written_with_their_channels() {
        use crate::mesh_data::tests::torus_grid_uv;
        let m = torus(3, 4);
        let uv = torus_grid_uv(3, 4);
        let normals: Vec<[f64; 3]> = m.positions.iter().map(|p| [p[2], p[0], -p[1]]).collect();
        let extras = Extras {
            normals: Some(&normals),
            uv: Some(&uv),
        };
        let dir = std::env::temp_dir().join(format!("lsubdiv-with-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        let (obj, ply) = (dir.join("t.obj"), dir.join("t.ply"));
        write_with(&obj, &m, extras).unwrap();
        let text = std::fs::read_to_string(&obj).unwrap();
        assert_eq!(text, format_with(&m, extras).unwrap());
        assert!(text.contains("\nvn ") && text.contains("\nvt "));
        crate::ply::write_with(&ply, &m, extras, false).unwrap();
        let text = std::fs::read_to_string(&ply).unwrap();
        assert_eq!(text, crate::ply::format_with(&m, extras).unwrap());
        crate::ply::write_with(&ply, &m, extras, true).unwrap();
        let bytes = std::fs::read(&ply).unwrap();
        assert_eq!(bytes, crate::ply::binary_with(&m, extras, false).unwrap());
        std::fs::remove_dir_all(&dir).unwrap();
    }

    #[test]
    fn texture_coordinates_round_trip() {
        use crate::mesh_data::tests::{torus_grid_uv, xy_uv};
        let m = torus(4, 5);
        let normals: Vec<[f64; 3]> = m.positions.iter().map(|p| [p[2], p[0], -p[1]]).collect();
        for uv in [torus_grid_uv(4, 5), xy_uv(&m)] {
            for normals in [None, Some(&normals[..])] {
                let extras = Extras {
                    normals,
                    uv: Some(&uv),
                };
                let text = format_with(&m, extras).unwrap();
                // v, then vn, then vt lines, then faces `a/ta` or `a/ta/a`.
                let kinds: Vec<&str> = text
                    .lines()
                    .skip(1)
                    .map(|l| l.split(' ').next().unwrap())
                    .collect();
                let mut want = vec!["v"; 20];
                want.extend(vec!["vn"; if normals.is_some() { 20 } else { 0 }]);
                want.extend(vec!["vt"; uv.values.len()]);
                want.extend(vec!["f"; 20]);
                assert_eq!(kinds, want);
                let [a, b, c, d] = m.faces[0].map(|v| v + 1);
                let [ta, tb, tc, td] = uv.faces[0].map(|t| t + 1);
                let f0 = match normals {
                    None => format!("f {a}/{ta} {b}/{tb} {c}/{tc} {d}/{td}"),
                    Some(_) => format!("f {a}/{ta}/{a} {b}/{tb}/{b} {c}/{tc}/{c} {d}/{td}/{d}"),
                };
                assert!(text.contains(&format!("\n{f0}\n")), "{f0}");
                let p = parse("t.obj", &text).unwrap();
                assert_eq!(
                    p.mesh.corners,
                    m.faces.iter().flatten().copied().collect::<Vec<_>>()
                );
                let corners = uv.faces.iter().flatten().copied().collect();
                let values = uv.values.clone();
                assert_eq!(p.uv, Some(PolyUv { values, corners }));
                assert_eq!(p.warnings.len(), usize::from(normals.is_some()));
            }
        }
    }

    /// Parsing, topology building and placing its errors never panic, whatever the input.
    #[test]
    fn garbage_never_panics() {
        let mut rng = Rng(12345);
        let base = format(&torus(3, 4)).unwrap();
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
            if let Ok(p) = parse("t.obj", &text) {
                let _ = p.check("t.obj");
                checked += 1;
            }
        }
        assert!(checked > 20, "only {checked} inputs parsed");
    }
}
