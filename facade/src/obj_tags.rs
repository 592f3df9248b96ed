//! OpenSubdiv's sharp-feature tags in OBJ files, `t name n/m/k` then n integers, m floats and k
//! strings, as its shape files write them (`regression/common/shape_utils.cpp`, `parseTag`) and
//! its regression tools read them (`regression/common/far_utils.h`, `assignComponentTags` and
//! `GetSdcOptions`):
//!
//! - `t crease 2/1/0 a b s`: the edge ab (vertices counted from 0) has sharpness s; several
//!   pairs `t crease 4/1/0 a b c d s` are the edges ab and cd (OpenSubdiv reads the integers
//!   two by two, not as a chain), one sharpness for all or one per pair (`4/2/0`; OpenSubdiv's
//!   loop indexes the floats by the pair's first integer, which no shape of its own exercises:
//!   they all write `2/1/0`);
//! - `t corner 1/1/0 v s`: vertex v has sharpness s; several vertices, one sharpness for all or
//!   one per vertex;
//! - `t hole 1/0/0 f`: face f (counted from 0) is a hole; several faces;
//! - `t interpolateboundary 1/0/0 k`: 0 none (OpenSubdiv's `VTX_BOUNDARY_NONE`: the faces at
//!   the boundary are holes), 1 edge-and-corner, 2 edge-only;
//! - `t smoothtriangles 0/0/1 r`: `catmark` or `smooth` (the smooth-triangle rule of the first
//!   step, [`Triangles`]);
//! - `t facevaryinginterpolateboundary 1/0/0 k`: how texture coordinates are refined
//!   ([`UvRule`]), OpenSubdiv's `FVarLinearInterpolation`: 0 none (smooth), 1 corners-only,
//!   2 corners-plus1, 3 corners-plus2, 4 boundaries, 5 all (linear); `--uv` overrides it;
//! - `t creasemethod 0/0/1 m`: `normal` (OpenSubdiv's uniform creasing) or `chaikin`
//!   ([`Creasing`]).
//!
//! The count field may omit its string count (`2/1`). Sharpness is read by
//! [`Sharpness::from_f64`] (`inf` and 10 or more: infinitely sharp; fractions as OpenSubdiv). A value
//! repeated with the same sharpness is merged (OpenSubdiv's own shapes repeat creases), with
//! another refused. Other tags are skipped with a warning. That an edge, vertex or face exists
//! is checked with the faces ([`crate::mesh_data::Parsed::check`]).

use crate::mesh_data::{shorten, FeatureLines};
use lsubdiv_mesh::facevarying::UvRule;
use lsubdiv_mesh::features::{Boundary, Creasing, Features, Sharpness, Triangles};
use std::collections::{HashMap, HashSet};
use std::hash::Hash;

/// A token of a logical line and the physical line it is on.
pub(crate) type Token<'a> = (&'a str, usize);

/// `[+-]?[0-9]+`
pub(crate) fn is_integer(s: &str) -> bool {
    let digits = s.strip_prefix(['+', '-']).unwrap_or(s);
    !digits.is_empty() && digits.bytes().all(|b| b.is_ascii_digit())
}

/// The tags read so far, with the line of each entry; each edge, vertex and face once.
#[derive(Default)]
pub(crate) struct Tags {
    /// The features.
    pub features: Features,
    /// The line of each.
    pub lines: FeatureLines,
    /// The texture coordinates' rule (`t facevaryinginterpolateboundary`), with its line.
    pub uv_rule: Option<(UvRule, usize)>,
    creases: HashMap<[u32; 2], usize>,
    corners: HashMap<u32, usize>,
    holes: HashSet<u32>,
}

/// An error: the physical line of the bad token and the message.
type Failure = (usize, String);

/// The tags lsubdiv reads.
#[derive(Clone, Copy)]
enum Tag {
    Crease,
    Corner,
    Hole,
    Boundary,
    FaceVarying,
    CreaseMethod,
    Triangles,
}

/// A tag's name and the counts it takes: (ints, floats, strings) are allowed when
/// `shape(ints, floats, strings)` holds, and `forms` says which in the error message.
struct Kind {
    tag: Tag,
    name: &'static str,
    shape: fn(usize, usize, usize) -> bool,
    forms: &'static str,
}

const KINDS: &[Kind] = &[
    Kind {
        tag: Tag::Crease,
        name: "crease",
        shape: |n, m, k| n >= 2 && n % 2 == 0 && (m == 1 || m == n / 2) && k == 0,
        forms: "vertex pairs, then one sharpness for all or one per pair (2/1/0, 4/1/0, 4/2/0, …)",
    },
    Kind {
        tag: Tag::Corner,
        name: "corner",
        shape: |n, m, k| n >= 1 && (m == 1 || m == n) && k == 0,
        forms: "vertices, then one sharpness for all or one per vertex (1/1/0, 2/1/0, 2/2/0, …)",
    },
    Kind {
        tag: Tag::Hole,
        name: "hole",
        shape: |n, m, k| n >= 1 && m == 0 && k == 0,
        forms: "faces and nothing else (1/0/0, 2/0/0, …)",
    },
    Kind {
        tag: Tag::Boundary,
        name: "interpolateboundary",
        shape: |n, m, k| n == 1 && m == 0 && k == 0,
        forms: "one integer, the mode (1/0/0)",
    },
    Kind {
        tag: Tag::FaceVarying,
        name: "facevaryinginterpolateboundary",
        shape: |n, m, k| n == 1 && m == 0 && k == 0,
        forms: "one integer, the mode (1/0/0)",
    },
    Kind {
        tag: Tag::CreaseMethod,
        name: "creasemethod",
        shape: |n, m, k| n == 0 && m == 0 && k == 1,
        forms: "one string, the method (0/0/1)",
    },
    Kind {
        tag: Tag::Triangles,
        name: "smoothtriangles",
        shape: |n, m, k| n == 0 && m == 0 && k == 1,
        forms: "one string, the rule (0/0/1)",
    },
];

/// `n/m/k` or `n/m`: the numbers of integers, floats and strings.
fn parse_counts(tok: &str) -> Option<[usize; 3]> {
    let parts: Vec<&str> = tok.split('/').collect();
    if !matches!(parts.len(), 2 | 3) {
        return None;
    }
    let mut counts = [0; 3];
    for (c, p) in counts.iter_mut().zip(&parts) {
        if p.is_empty() || !p.bytes().all(|b| b.is_ascii_digit()) {
            return None;
        }
        *c = p.parse().ok()?;
    }
    Some(counts)
}

/// A vertex or face index as tags write them: from 0.
fn parse_index((tok, line): Token<'_>) -> Result<u32, Failure> {
    tok.parse().map_err(|_| {
        let message = if is_integer(tok) {
            format!("index {} out of range (tags count from 0)", shorten(tok))
        } else {
            format!("`{}` is not an index", shorten(tok))
        };
        (line, message)
    })
}

fn parse_sharpness((tok, line): Token<'_>) -> Result<Sharpness, Failure> {
    let s: f64 = tok
        .parse()
        .map_err(|_| (line, format!("`{}` is not a number", shorten(tok))))?;
    Sharpness::from_f64(s).map_err(|e| (line, e.to_string()))
}

/// Adds `entry` of `key` to `list` with its line, unless the key is there already: then an
/// entry `same` as the earlier one is merged, another refused with the line of the earlier.
fn add<K: Hash + Eq, E>(
    seen: &mut HashMap<K, usize>,
    (list, lines): (&mut Vec<E>, &mut Vec<usize>),
    (key, entry, line): (K, E, usize),
    same: impl Fn(&E, &E) -> bool,
) -> Result<(), usize> {
    match seen.get(&key) {
        Some(&k) if same(&list[k], &entry) => Ok(()),
        Some(&k) => Err(lines[k]),
        None => {
            seen.insert(key, list.len());
            list.push(entry);
            lines.push(line);
            Ok(())
        }
    }
}

impl Tags {
    /// Reads the tokens of a `t` line after the `t` (the line `line` starts at): the name of
    /// a tag lsubdiv does not read, to be skipped, or nothing.
    pub fn read<'a>(
        &mut self,
        line: usize,
        values: &[Token<'a>],
    ) -> Result<Option<&'a str>, Failure> {
        let Some(&(name, _)) = values.first() else {
            return Err((
                line,
                "`t` needs a tag name, a count field n/m/k and values".into(),
            ));
        };
        let Some(kind) = KINDS.iter().find(|k| k.name == name) else {
            return Ok(Some(name));
        };
        let Some(&(field, field_line)) = values.get(1) else {
            return Err((
                line,
                format!("`t {name}` needs a count field n/m/k (how many integers, floats and strings follow)"),
            ));
        };
        let [n, m, k] = parse_counts(field).ok_or_else(|| {
            (
                field_line,
                format!(
                    "`{}` is not a count field n/m/k (how many integers, floats and strings follow)",
                    shorten(field)
                ),
            )
        })?;
        let args = &values[2..];
        let announced = n as u128 + m as u128 + k as u128;
        if announced != args.len() as u128 {
            return Err((
                field_line,
                format!(
                    "`t {name} {}` announces {announced} values; the line has {}",
                    shorten(field),
                    args.len()
                ),
            ));
        }
        if !(kind.shape)(n, m, k) {
            return Err((
                field_line,
                format!(
                    "`t {name}` takes {} (count field `{}`)",
                    kind.forms,
                    shorten(field)
                ),
            ));
        }
        let (ints, rest) = args.split_at(n);
        let (floats, strings) = rest.split_at(m);
        match kind.tag {
            Tag::Boundary => self.boundary(ints[0]),
            Tag::FaceVarying => self.face_varying(ints[0]),
            Tag::CreaseMethod => {
                self.features.creasing = creasing(strings[0])?;
                Ok(())
            }
            Tag::Triangles => {
                self.features.triangles = triangles(strings[0])?;
                Ok(())
            }
            Tag::Hole => ints.iter().try_for_each(|&tok| {
                let face = parse_index(tok)?;
                if self.holes.insert(face) {
                    self.features.holes.push(face);
                    self.lines.holes.push(tok.1);
                }
                Ok(())
            }),
            Tag::Corner => ints.iter().enumerate().try_for_each(|(i, &tok)| {
                let v = parse_index(tok)?;
                let s = parse_sharpness(floats[if m == 1 { 0 } else { i }])?;
                let list = (&mut self.features.corners, &mut self.lines.corners);
                add(&mut self.corners, list, (v, (v, s), tok.1), |a, b| {
                    a.1 == b.1
                })
                .map_err(|l| {
                    let message = format!("corner vertex {v} has another sharpness at line {l}");
                    (tok.1, message)
                })
            }),
            Tag::Crease => ints.chunks_exact(2).enumerate().try_for_each(|(i, pair)| {
                let (a, b) = (parse_index(pair[0])?, parse_index(pair[1])?);
                let s = parse_sharpness(floats[if m == 1 { 0 } else { i }])?;
                let list = (&mut self.features.creases, &mut self.lines.creases);
                let entry = ([a.min(b), a.max(b)], ([a, b], s), pair[0].1);
                add(&mut self.creases, list, entry, |x, y| x.1 == y.1).map_err(|l| {
                    let message = format!("crease edge {a}–{b} has another sharpness at line {l}");
                    (pair[0].1, message)
                })
            }),
        }?;
        Ok(None)
    }

    /// `t interpolateboundary 1/0/0 k`, the mode `(tok, line)`.
    fn boundary(&mut self, (tok, line): Token<'_>) -> Result<(), Failure> {
        let boundary = match tok.parse::<i64>() {
            Ok(1) => Boundary::EdgeAndCorner,
            Ok(2) => Boundary::EdgeOnly,
            Ok(0) => Boundary::None,
            _ => {
                let message = format!(
                    "`{}` is not a boundary interpolation mode (0 none, 1 edge-and-corner, 2 \
                     edge-only)",
                    shorten(tok)
                );
                return Err((line, message));
            }
        };
        match self.lines.boundary {
            Some(l) if self.features.boundary != boundary => Err((
                line,
                format!("the boundary interpolation is set otherwise at line {l}"),
            )),
            _ => {
                self.features.boundary = boundary;
                self.lines.boundary = Some(line);
                Ok(())
            }
        }
    }
}

impl Tags {
    /// `t facevaryinginterpolateboundary 1/0/0 k`, the mode `(tok, line)`.
    fn face_varying(&mut self, (tok, line): Token<'_>) -> Result<(), Failure> {
        let rule = match tok.parse::<i64>() {
            Ok(0) => UvRule::Smooth,
            Ok(1) => UvRule::CornersOnly,
            Ok(2) => UvRule::CornersPlus1,
            Ok(3) => UvRule::CornersPlus2,
            Ok(4) => UvRule::Boundaries,
            Ok(5) => UvRule::Linear,
            _ => {
                let message = format!(
                    "`{}` is not a face-varying interpolation mode (0 none, 1 corners-only, 2 \
                     corners-plus1, 3 corners-plus2, 4 boundaries, 5 all)",
                    shorten(tok)
                );
                return Err((line, message));
            }
        };
        match self.uv_rule {
            Some((r, l)) if r != rule => Err((
                line,
                format!("the face-varying interpolation is set otherwise at line {l}"),
            )),
            _ => {
                self.uv_rule = Some((rule, line));
                Ok(())
            }
        }
    }
}

/// `t creasemethod 0/0/1 m`: OpenSubdiv's `normal` (uniform) or `chaikin` creasing
/// ([`Creasing`]).
fn creasing((tok, line): Token<'_>) -> Result<Creasing, Failure> {
    match tok {
        "normal" | "uniform" => Ok(Creasing::Uniform),
        "chaikin" => Ok(Creasing::Chaikin),
        _ => Err((
            line,
            format!(
                "`{}` is not a creasing method (normal, chaikin)",
                shorten(tok)
            ),
        )),
    }
}

/// `t smoothtriangles 0/0/1 r`: `catmark` or `smooth` ([`Triangles`]).
fn triangles((tok, line): Token<'_>) -> Result<Triangles, Failure> {
    match tok {
        "catmark" => Ok(Triangles::Catmark),
        "smooth" => Ok(Triangles::Smooth),
        _ => Err((
            line,
            format!(
                "`{}` is not a triangle rule (catmark, smooth)",
                shorten(tok)
            ),
        )),
    }
}

#[cfg(test)]
mod tests {
    use crate::mesh_data::FeatureLines;
    use lsubdiv_io::{Error, Location};
    use lsubdiv_mesh::features::{Boundary, Features, Sharpness};

    /// A square (lines 1–5); tags start at line 6.
    const SQUARE: &str = "v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nf 1 2 3 4\n";

    fn s(steps: u32) -> Sharpness {
        Sharpness::steps(steps)
    }

    const INF: Sharpness = Sharpness::INFINITE;

    /// The features and their lines read from the square and `tags`.
    fn read(tags: &str) -> Result<(Features, FeatureLines), Error> {
        crate::obj::parse("t.obj", &format!("{SQUARE}{tags}"))
            .map(|p| (p.features, p.places.features))
    }

    fn creases(c: &[([u32; 2], Sharpness)]) -> Features {
        Features {
            creases: c.to_vec(),
            ..Features::default()
        }
    }

    fn corners(c: &[(u32, Sharpness)]) -> Features {
        Features {
            corners: c.to_vec(),
            ..Features::default()
        }
    }

    fn holes(h: &[u32]) -> Features {
        Features {
            holes: h.to_vec(),
            ..Features::default()
        }
    }

    #[test]
    fn tags_as_opensubdiv_writes_them() {
        // (tags, features, the line of each entry of the creases, corners and holes)
        let cases = [
            ("t crease 2/1/0 0 1 10", creases(&[([0, 1], INF)]), vec![6]),
            ("t crease 2/1/0 1 0 inf", creases(&[([1, 0], INF)]), vec![6]),
            (
                "t crease 2/1/0 1 0 12.5",
                creases(&[([1, 0], INF)]),
                vec![6],
            ),
            ("t crease 2/1 0 1 2.0", creases(&[([0, 1], s(2))]), vec![6]),
            (
                "t crease 2/1/0 0 1 2.5",
                creases(&[([0, 1], Sharpness::from_f64(2.5).unwrap())]),
                vec![6],
            ),
            (
                "t corner 1/1/0 0 0.7",
                corners(&[(0, Sharpness::from_f64(0.7).unwrap())]),
                vec![6],
            ),
            (
                "t  crease  2/1/0  0 1  0",
                creases(&[([0, 1], s(0))]),
                vec![6],
            ),
            (
                "t crease 4/1/0 0 1 2 3 3",
                creases(&[([0, 1], s(3)), ([2, 3], s(3))]),
                vec![6, 6],
            ),
            (
                "t crease 4/2/0 0 1 1 2 1 2",
                creases(&[([0, 1], s(1)), ([1, 2], s(2))]),
                vec![6, 6],
            ),
            // OpenSubdiv's own shapes repeat creases: the same sharpness is merged.
            (
                "t crease 2/1/0 0 1 10\nt crease 2/1/0 1 0 1e1",
                creases(&[([0, 1], INF)]),
                vec![6],
            ),
            (
                "t crease 2/1/0 \\\n 0 1 3",
                creases(&[([0, 1], s(3))]),
                vec![7],
            ),
            ("t corner 1/1/0 2 10", corners(&[(2, INF)]), vec![6]),
            (
                "t corner 2/2/0 0 3 1 4\nt corner 1/1/0 3 4",
                corners(&[(0, s(1)), (3, s(4))]),
                vec![6, 6],
            ),
            (
                "t corner 3/1/0 0 1 2 5",
                corners(&[(0, s(5)), (1, s(5)), (2, s(5))]),
                vec![6, 6, 6],
            ),
            ("t hole 1/0/0 0", holes(&[0]), vec![6]),
            (
                "t hole 3/0/0 4 2 4\nt hole 1/0 2",
                holes(&[4, 2]),
                vec![6, 6],
            ),
            (
                "t crease 2/1/0 0 1 3\nt hole 1/0/0 0\nt corner 1/1/0 1 2",
                Features {
                    creases: vec![([0, 1], s(3))],
                    corners: vec![(1, s(2))],
                    holes: vec![0],
                    ..Features::default()
                },
                vec![6, 8, 7],
            ),
        ];
        for (tags, want, lines) in cases {
            let (f, l) = read(tags).unwrap_or_else(|e| panic!("{tags:?}: {e}"));
            assert_eq!(f, want, "{tags:?}");
            let all = [l.creases, l.corners, l.holes].concat();
            assert_eq!(all, lines, "{tags:?}");
            assert_eq!(l.boundary, None);
        }
        for (tags, boundary, line) in [
            ("t interpolateboundary 1/0/0 1", Boundary::EdgeAndCorner, 6),
            ("t interpolateboundary 1/0/0 2", Boundary::EdgeOnly, 6),
            ("t interpolateboundary 1/0/0 0", Boundary::None, 6),
            (
                "t interpolateboundary 1/0 +2\n\nt interpolateboundary 1/0/0 2",
                Boundary::EdgeOnly,
                8,
            ),
        ] {
            let (f, l) = read(tags).unwrap();
            assert_eq!(f, Features::with_boundary(boundary), "{tags:?}");
            assert_eq!(l.boundary, Some(line), "{tags:?}");
        }
    }

    #[test]
    fn bad_tags_are_refused_at_their_line() {
        let counts = "(how many integers, floats and strings follow)";
        let crease_forms = "`t crease` takes vertex pairs, then one sharpness for all or one \
                            per pair (2/1/0, 4/1/0, 4/2/0, …)";
        let corner_forms = "`t corner` takes vertices, then one sharpness for all or one per \
                            vertex (1/1/0, 2/1/0, 2/2/0, …)";
        let cases: Vec<(&str, usize, String)> = vec![
            (
                "t",
                6,
                "`t` needs a tag name, a count field n/m/k and values".into(),
            ),
            (
                "t crease",
                6,
                format!("`t crease` needs a count field n/m/k {counts}"),
            ),
            (
                "t crease 2-1-0 0 1 1",
                6,
                format!("`2-1-0` is not a count field n/m/k {counts}"),
            ),
            (
                "t crease 2/1/0/0 0 1 1",
                6,
                format!("`2/1/0/0` is not a count field n/m/k {counts}"),
            ),
            (
                "t crease 2//0 0 1 1",
                6,
                format!("`2//0` is not a count field n/m/k {counts}"),
            ),
            (
                "t crease 2 0 1 1",
                6,
                format!("`2` is not a count field n/m/k {counts}"),
            ),
            (
                "t crease -2/1/0 0 1 1",
                6,
                format!("`-2/1/0` is not a count field n/m/k {counts}"),
            ),
            (
                "t crease 2/1/0 0 1",
                6,
                "`t crease 2/1/0` announces 3 values; the line has 2".into(),
            ),
            (
                "t crease 2/1/0 0 1 1 7",
                6,
                "`t crease 2/1/0` announces 3 values; the line has 4".into(),
            ),
            (
                "t hole 18446744073709551615/1/2 0",
                6,
                "`t hole 18446744073709551615/1/2` announces 18446744073709551618 values; the \
                 line has 1"
                    .into(),
            ),
            (
                "t crease 3/1/0 0 1 2 1",
                6,
                format!("{crease_forms} (count field `3/1/0`)"),
            ),
            (
                "t crease 0/1/0 1",
                6,
                format!("{crease_forms} (count field `0/1/0`)"),
            ),
            (
                "t crease 4/3/0 0 1 2 3 1 1 1",
                6,
                format!("{crease_forms} (count field `4/3/0`)"),
            ),
            (
                "t crease 2/0/0 0 1",
                6,
                format!("{crease_forms} (count field `2/0/0`)"),
            ),
            (
                "t crease 2/1/1 0 1 1 x",
                6,
                format!("{crease_forms} (count field `2/1/1`)"),
            ),
            (
                "t corner 2/3/0 0 1 1 1 1",
                6,
                format!("{corner_forms} (count field `2/3/0`)"),
            ),
            (
                "t corner 1/0/0 0",
                6,
                format!("{corner_forms} (count field `1/0/0`)"),
            ),
            (
                "t hole 1/1/0 0 1",
                6,
                "`t hole` takes faces and nothing else (1/0/0, 2/0/0, …) (count field `1/1/0`)"
                    .into(),
            ),
            (
                "t interpolateboundary 2/0/0 1 1",
                6,
                "`t interpolateboundary` takes one integer, the mode (1/0/0) (count field `2/0/0`)"
                    .into(),
            ),
            (
                "t crease 2/1/0 -1 1 1",
                6,
                "index -1 out of range (tags count from 0)".into(),
            ),
            ("t crease 2/1/0 0 \\\n a 1", 7, "`a` is not an index".into()),
            (
                "t corner 1/1/0 99999999999 1",
                6,
                "index 99999999999 out of range (tags count from 0)".into(),
            ),
            ("t hole 1/0/0 1.0", 6, "`1.0` is not an index".into()),
            ("t crease 2/1/0 0 1 -1", 6, "sharpness -1 is not ≥ 0".into()),
            (
                "t crease 2/1/0 0 1 nan",
                6,
                "sharpness NaN is not ≥ 0".into(),
            ),
            ("t crease 2/1/0 0 1 x", 6, "`x` is not a number".into()),
            (
                "t crease 2/1/0 0 1 2\nt crease 2/1/0 1 0 3",
                7,
                "crease edge 1–0 has another sharpness at line 6".into(),
            ),
            (
                "t crease 4/2/0 0 1 0 1 2 3",
                6,
                "crease edge 0–1 has another sharpness at line 6".into(),
            ),
            (
                "t corner 1/1/0 0 2\nt corner 1/1/0 0 inf",
                7,
                "corner vertex 0 has another sharpness at line 6".into(),
            ),
            (
                "t interpolateboundary 1/0/0 3",
                6,
                "`3` is not a boundary interpolation mode (0 none, 1 edge-and-corner, 2 edge-only)"
                    .into(),
            ),
            (
                "t interpolateboundary 1/0/0 1\nt interpolateboundary 1/0/0 2",
                7,
                "the boundary interpolation is set otherwise at line 6".into(),
            ),
            (
                "t facevaryinginterpolateboundary 1/0/0 6",
                6,
                "`6` is not a face-varying interpolation mode (0 none, 1 corners-only, 2 \
                 corners-plus1, 3 corners-plus2, 4 boundaries, 5 all)"
                    .into(),
            ),
            (
                "t facevaryinginterpolateboundary 1/0/0 1\nt facevaryinginterpolateboundary 1/0/0 0",
                7,
                "the face-varying interpolation is set otherwise at line 6".into(),
            ),
        ];
        for (tags, line, message) in cases {
            assert_eq!(
                read(tags).expect_err(tags),
                Error::at(Location::line("t.obj", line), message),
                "{tags:?}"
            );
        }
    }

    /// `t facevaryinginterpolateboundary k` sets the texture coordinates' rule, OpenSubdiv's
    /// numbering (`regression/common/far_utils.h`); without it the rule is linear.
    #[test]
    fn face_varying_modes() {
        use lsubdiv_mesh::facevarying::UvRule;
        let rule = |tags: &str| {
            crate::obj::parse("t.obj", &format!("{SQUARE}{tags}"))
                .unwrap()
                .uv_rule
        };
        assert_eq!(rule(""), UvRule::Linear);
        for (k, want) in [
            UvRule::Smooth,
            UvRule::CornersOnly,
            UvRule::CornersPlus1,
            UvRule::CornersPlus2,
            UvRule::Boundaries,
            UvRule::Linear,
        ]
        .into_iter()
        .enumerate()
        {
            assert_eq!(
                rule(&format!("t facevaryinginterpolateboundary 1/0/0 {k}\n")),
                want
            );
        }
    }

    /// Parses and checks OBJ text.
    fn check(text: &str) -> Result<crate::mesh_data::Checked, Error> {
        crate::obj::parse("t.obj", text)?.check("t.obj")
    }

    const TETRAHEDRON: &str =
        "v 1 1 1\nv -1 -1 1\nv -1 1 -1\nv 1 -1 -1\nf 1 2 3\nf 1 3 4\nf 1 4 2\nf 2 4 3\n";
    const CUBE: &str = "v -1 -1 -1\nv 1 -1 -1\nv -1 1 -1\nv 1 1 -1\nv -1 -1 1\nv 1 -1 1\n\
                        v -1 1 1\nv 1 1 1\nf 1 5 7 3\nf 2 4 8 6\nf 1 2 6 5\nf 3 7 8 4\n\
                        f 1 3 4 2\nf 5 6 8 7\n";

    #[test]
    fn features_are_checked_with_the_faces() {
        let at = |line, message: &str| {
            let e = Error::at(Location::line("t.obj", line), message);
            Err(e.with_hint(crate::mesh_data::TAG_NUMBERS))
        };
        // Quads, checked as they are (the square has a boundary, which the topology refuses
        // after its features are checked); polygons, by their first step.
        for (text, line, message) in [
            (
                format!("{SQUARE}t crease 2/1/0 0 2 1\n"),
                6,
                "crease 0–2: no such edge (the vertices are not joined by an edge of a face; tags count vertices from 0)",
            ),
            (
                format!("{SQUARE}t corner 1/1/0 4 1\n"),
                6,
                "corner vertex 4 out of range (tags count vertices from 0; the file has 4 vertices)",
            ),
            (
                format!("{SQUARE}t hole 2/0/0 0 1\n"),
                6,
                "hole face 1 out of range (tags count faces from 0; the file has 1 face)",
            ),
            (
                format!("{TETRAHEDRON}t crease 2/1/0 0 1 1\nt crease 2/1/0 3 3 1\n"),
                10,
                "crease 3–3: no such edge (the vertices are not joined by an edge of a face; tags count vertices from 0)",
            ),
            (
                format!("{TETRAHEDRON}\nt hole 1/0/0 4\n"),
                10,
                "hole face 4 out of range (tags count faces from 0; the file has 4 faces)",
            ),
        ] {
            assert_eq!(check(&text).map(|_| ()), at(line, message), "{text}");
        }
    }

    #[test]
    fn checked_features_name_the_refined_mesh() {
        // All quads: the file's features.
        let c = check(&format!("{CUBE}t corner 1/1/0 7 2\nt crease 2/1/0 4 5 3\n")).unwrap();
        assert!(!c.split);
        let want = Features {
            creases: vec![([4, 5], s(3))],
            corners: vec![(7, s(2))],
            ..Features::default()
        };
        assert_eq!(c.features, want);
        // Triangles: their first step's. Edge 0–1 comes first, so its point is vertex 4.
        let text = format!(
            "{TETRAHEDRON}t crease 2/1/0 0 1 3\nt corner 1/1/0 3 1\nt hole 1/0/0 1\n\
             t interpolateboundary 1/0/0 2\n"
        );
        let c = check(&text).unwrap();
        assert!(c.split);
        let want = Features {
            boundary: Boundary::EdgeOnly,
            creases: vec![([0, 4], s(2)), ([4, 1], s(2))],
            corners: vec![],
            holes: vec![3, 4, 5],
            ..Features::default()
        };
        assert_eq!(c.features, want);
        assert_eq!(c.mesh.positions[3], [1.0, -1.0, -1.0]); // the corner, held
    }

    /// Tag lines made of plausible and implausible tokens never panic, parsed or checked.
    #[test]
    fn tag_garbage_never_panics() {
        let words = [
            "t",
            "crease",
            "corner",
            "hole",
            "interpolateboundary",
            "2/1/0",
            "1/1/0",
            "4/2",
            "1/0/0",
            "2/1",
            "0",
            "1",
            "2",
            "3",
            "-1",
            "inf",
            "nan",
            "0.5",
            "10",
            "x",
            "4294967296",
        ];
        let mut state = 0x2545_f491_4f6c_dd1d_u64;
        let mut next = |n: usize| {
            state ^= state << 13;
            state ^= state >> 7;
            state ^= state << 17;
            (state % n as u64) as usize
        };
        let mut read_ok = 0;
        for _ in 0..3000 {
            let mut text = String::from("t");
            for _ in 0..1 + next(7) {
                text.push(' ');
                text.push_str(words[next(words.len())]);
            }
            for mesh in [SQUARE, TETRAHEDRON] {
                let text = format!("{mesh}{text}\n");
                if let Ok(p) = crate::obj::parse("t.obj", &text) {
                    read_ok += 1;
                    let _ = p.check("t.obj");
                }
            }
        }
        assert!(read_ok > 100, "only {read_ok} parsed");
    }
}
