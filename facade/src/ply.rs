//! PLY meshes: reading ASCII and binary (little- and big-endian) PLY 1.0 with every problem
//! placed — header problems at their line and column, ASCII data at its line, binary data at its
//! element, property and byte offset — and writing, ASCII or binary (`subdivide --binary`),
//! with normals and texture coordinates.
//!
//! The reader takes a `vertex` element with scalar `x`, `y`, `z` of any type and a `face`
//! element with a `vertex_indices` (or `vertex_index`) list of integers, or a `tristrips`
//! element with such a list (triangle strips, −1 restarting a strip); texture coordinates
//! from vertex properties `u v`, `s t` or `texture_u texture_v` (any type), or from a face list
//! `texcoord` (u v per corner, as MeshLab writes it; it takes precedence); other properties,
//! lists and elements are skipped in order. Nothing is allocated from a count in the header:
//! a binary element's count is checked against the bytes that follow before it is read, and
//! values are stored only as they are read.

use crate::mesh_data::{shorten, too_few_corners, Extras, Parsed, Places, Unit};
use lsubdiv_io::{Error, Location};
use lsubdiv_mesh::facevarying::{PolyUv, QuadUv};
use lsubdiv_mesh::features::Features;
use lsubdiv_mesh::polygon::PolyMesh;
use lsubdiv_mesh::topology::TopologyError;
use lsubdiv_mesh::QuadMesh;
use std::fmt::{self, Write as _};

/// A scalar type of PLY.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum Scalar {
    I8,
    U8,
    I16,
    U16,
    I32,
    U32,
    F32,
    F64,
}

/// The type names of PLY 1.0 and their sized aliases; the first name of a type is used in
/// messages.
const TYPES: &[(&str, Scalar)] = &[
    ("char", Scalar::I8),
    ("uchar", Scalar::U8),
    ("short", Scalar::I16),
    ("ushort", Scalar::U16),
    ("int", Scalar::I32),
    ("uint", Scalar::U32),
    ("float", Scalar::F32),
    ("double", Scalar::F64),
    ("int8", Scalar::I8),
    ("uint8", Scalar::U8),
    ("int16", Scalar::I16),
    ("uint16", Scalar::U16),
    ("int32", Scalar::I32),
    ("uint32", Scalar::U32),
    ("float32", Scalar::F32),
    ("float64", Scalar::F64),
];

/// A value read: integers exactly, floats as f64.
#[derive(Clone, Copy, Debug, PartialEq)]
enum Value {
    Int(i64),
    Float(f64),
}

impl Value {
    fn to_f64(self) -> f64 {
        match self {
            Value::Int(i) => i as f64,
            Value::Float(x) => x,
        }
    }
}

impl fmt::Display for Value {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Value::Int(i) => write!(f, "{i}"),
            Value::Float(x) => write!(f, "{x:?}"),
        }
    }
}

impl Scalar {
    fn named(name: &str) -> Option<Scalar> {
        TYPES.iter().find(|(n, _)| *n == name).map(|&(_, t)| t)
    }

    fn name(self) -> &'static str {
        TYPES
            .iter()
            .find(|(_, t)| *t == self)
            .map_or("?", |(n, _)| n)
    }

    fn size(self) -> usize {
        match self {
            Scalar::I8 | Scalar::U8 => 1,
            Scalar::I16 | Scalar::U16 => 2,
            Scalar::I32 | Scalar::U32 | Scalar::F32 => 4,
            Scalar::F64 => 8,
        }
    }

    fn is_integer(self) -> bool {
        !matches!(self, Scalar::F32 | Scalar::F64)
    }

    /// The value of `b` (exactly [`Scalar::size`] bytes) in the given byte order.
    fn decode(self, b: &[u8], big: bool) -> Value {
        fn bytes<const N: usize>(b: &[u8], big: bool) -> [u8; N] {
            let mut a = [0u8; N];
            a.copy_from_slice(&b[..N]);
            if big {
                a.reverse();
            }
            a
        }
        match self {
            Scalar::I8 => Value::Int(i64::from(i8::from_le_bytes(bytes(b, big)))),
            Scalar::U8 => Value::Int(i64::from(b[0])),
            Scalar::I16 => Value::Int(i64::from(i16::from_le_bytes(bytes(b, big)))),
            Scalar::U16 => Value::Int(i64::from(u16::from_le_bytes(bytes(b, big)))),
            Scalar::I32 => Value::Int(i64::from(i32::from_le_bytes(bytes(b, big)))),
            Scalar::U32 => Value::Int(i64::from(u32::from_le_bytes(bytes(b, big)))),
            Scalar::F32 => Value::Float(f64::from(f32::from_le_bytes(bytes(b, big)))),
            Scalar::F64 => Value::Float(f64::from_le_bytes(bytes(b, big))),
        }
    }

    /// The value of an ASCII token: an integer in the type's range, or any number for floats.
    fn parse(self, tok: &str) -> Option<Value> {
        let (lo, hi) = match self {
            Scalar::I8 => (i8::MIN.into(), i8::MAX.into()),
            Scalar::U8 => (0, u8::MAX.into()),
            Scalar::I16 => (i16::MIN.into(), i16::MAX.into()),
            Scalar::U16 => (0, u16::MAX.into()),
            Scalar::I32 => (i32::MIN.into(), i32::MAX.into()),
            Scalar::U32 => (0, u32::MAX.into()),
            Scalar::F32 | Scalar::F64 => return tok.parse().ok().map(Value::Float),
        };
        let i: i64 = tok.parse().ok()?;
        (lo..=hi).contains(&i).then_some(Value::Int(i))
    }
}

/// A property's type: a scalar, or a list of `item`s preceded by its length of type `count`.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum Kind {
    Scalar(Scalar),
    List { count: Scalar, item: Scalar },
}

#[derive(Clone, Debug)]
struct Property {
    name: String,
    kind: Kind,
    /// Header line.
    line: usize,
}

#[derive(Clone, Debug)]
struct Element {
    name: String,
    count: u64,
    properties: Vec<Property>,
    /// Header line.
    line: usize,
}

impl Element {
    /// Bytes of one instance in a binary file, at least (lists empty).
    fn min_size(&self) -> u64 {
        let size = |p: &Property| match p.kind {
            Kind::Scalar(t) | Kind::List { count: t, .. } => t.size() as u64,
        };
        self.properties.iter().map(size).sum()
    }
}

/// How the data after the header is written.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum Encoding {
    Ascii,
    Binary { big: bool },
}

/// A parsed header: the encoding, the elements in order, where the data begins (byte offset
/// and line) and the line of `end_header`.
struct Header {
    encoding: Encoding,
    elements: Vec<Element>,
    body: usize,
    end_line: usize,
}

const UTF8_BOM: &[u8] = b"\xEF\xBB\xBF";

/// Whether `bytes` begin with the PLY magic line `ply` (after an optional UTF-8 byte-order
/// mark).
pub fn has_magic(bytes: &[u8]) -> bool {
    let b = bytes.strip_prefix(UTF8_BOM).unwrap_or(bytes);
    b.strip_prefix(b"ply")
        .is_some_and(|rest| rest.first().is_none_or(u8::is_ascii_whitespace))
}

/// The whitespace-separated words of a header line with their 1-based columns (characters).
fn words(line: &str) -> Vec<(usize, &str)> {
    let mut out = Vec::new();
    let mut start = None;
    let ends = line
        .char_indices()
        .chain(std::iter::once((line.len(), ' ')));
    for (column, (i, c)) in ends.enumerate() {
        match (c.is_whitespace(), start) {
            (true, Some((s, col))) => {
                out.push((col, &line[s..i]));
                start = None;
            }
            (false, None) => start = Some((i, column + 1)),
            _ => {}
        }
    }
    out
}

/// The names of the types, for messages.
const TYPE_NAMES: &str = "char, uchar, short, ushort, int, uint, float, double or int8 … float64";

/// Parses the header: `ply`, `format`, `comment` and `obj_info`, `element`, `property`,
/// `end_header`, each problem at its line and column.
fn header(file: &str, bytes: &[u8]) -> Result<Header, Error> {
    let mut pos = if bytes.starts_with(UTF8_BOM) { 3 } else { 0 };
    let mut encoding = None;
    let mut elements: Vec<Element> = Vec::new();
    let mut line = 0;
    loop {
        line += 1;
        if pos >= bytes.len() {
            let at = Location::line(file, (line - 1).max(1));
            return Err(Error::at(
                at,
                "the header ends without an `end_header` line (or the file is truncated)",
            ));
        }
        let end = bytes[pos..]
            .iter()
            .position(|&b| b == b'\n')
            .map_or(bytes.len(), |i| pos + i);
        let raw = String::from_utf8_lossy(&bytes[pos..end]);
        pos = (end + 1).min(bytes.len());
        let w = words(&raw);
        let at = |column: usize, message: String| {
            Error::at(
                Location {
                    file: file.to_string(),
                    line: Some(line),
                    column: Some(column),
                },
                message,
            )
        };
        if line == 1 {
            if w.len() != 1 || w[0] != (1, "ply") {
                return Err(at(
                    1,
                    "not a PLY file: the first line must be `ply`".to_string(),
                ));
            }
            continue;
        }
        let Some(&(_, keyword)) = w.first() else {
            continue;
        };
        let args = &w[1..];
        match keyword {
            "comment" | "obj_info" => {}
            "format" => {
                if encoding.is_some() {
                    return Err(at(1, "a second `format` line".into()));
                }
                let [(c, name), (vc, version)] = args else {
                    return Err(at(
                        1,
                        "expected `format ascii 1.0`, `format binary_little_endian 1.0` or `format binary_big_endian 1.0`".into(),
                    ));
                };
                encoding = Some(match *name {
                    "ascii" => Encoding::Ascii,
                    "binary_little_endian" => Encoding::Binary { big: false },
                    "binary_big_endian" => Encoding::Binary { big: true },
                    other => {
                        return Err(at(
                            *c,
                            format!(
                                "unknown format `{}` (ascii, binary_little_endian or binary_big_endian)",
                                shorten(other)
                            ),
                        ))
                    }
                });
                if *version != "1.0" {
                    return Err(at(
                        *vc,
                        format!("PLY version `{}` is not supported (1.0)", shorten(version)),
                    ));
                }
            }
            "element" => {
                let [(_, name), (c, count)] = args else {
                    return Err(at(1, "expected `element NAME COUNT`".into()));
                };
                if elements.iter().any(|e| e.name == *name) && matches!(*name, "vertex" | "face") {
                    return Err(at(1, format!("a second `{name}` element")));
                }
                let count = match count.parse::<u64>() {
                    Ok(n) if !count.starts_with('+') => n,
                    _ if !count.is_empty() && count.bytes().all(|b| b.is_ascii_digit()) => {
                        return Err(at(
                            *c,
                            format!("element count `{}` does not fit 64 bits", shorten(count)),
                        ))
                    }
                    _ => {
                        return Err(at(
                            *c,
                            format!(
                                "`{}` is not an element count (a non-negative integer)",
                                shorten(count)
                            ),
                        ))
                    }
                };
                if *name == "vertex" && count > u64::from(u32::MAX) {
                    return Err(at(
                        *c,
                        format!("{count} vertices: at most {} (32-bit indices)", u32::MAX),
                    ));
                }
                elements.push(Element {
                    name: name.to_string(),
                    count,
                    properties: Vec::new(),
                    line,
                });
            }
            "property" => {
                let Some(element) = elements.last_mut() else {
                    return Err(at(1, "a `property` before any `element`".into()));
                };
                let scalar = |&(c, t): &(usize, &str)| {
                    Scalar::named(t).ok_or_else(|| {
                        at(c, format!("unknown type `{}` ({TYPE_NAMES})", shorten(t)))
                    })
                };
                let (kind, name) = match args {
                    [(_, "list"), count, item, (_, name)] => {
                        let c = scalar(count)?;
                        if !c.is_integer() {
                            return Err(at(
                                count.0,
                                format!(
                                    "the length of a list must be an integer type, not `{}`",
                                    count.1
                                ),
                            ));
                        }
                        let item = scalar(item)?;
                        (Kind::List { count: c, item }, *name)
                    }
                    [(_, "list"), ..] => {
                        return Err(at(
                            1,
                            "expected `property list COUNT_TYPE ITEM_TYPE NAME`".into(),
                        ))
                    }
                    [t, (_, name)] => (Kind::Scalar(scalar(t)?), *name),
                    _ => return Err(at(1, "expected `property TYPE NAME`".into())),
                };
                if element.properties.iter().any(|p| p.name == name) {
                    return Err(at(
                        args[args.len() - 1].0,
                        format!(
                            "a second property `{}` in element `{}`",
                            shorten(name),
                            shorten(&element.name)
                        ),
                    ));
                }
                element.properties.push(Property {
                    name: name.to_string(),
                    kind,
                    line,
                });
            }
            "end_header" => {
                if !args.is_empty() {
                    return Err(at(args[0].0, "text after `end_header`".into()));
                }
                let Some(encoding) = encoding else {
                    return Err(at(1, "the header has no `format` line".into()));
                };
                return Ok(Header {
                    encoding,
                    elements,
                    body: pos,
                    end_line: line,
                });
            }
            other => {
                return Err(at(
                    1,
                    format!(
                        "unknown header line `{}` (expected format, comment, obj_info, element, property or end_header)",
                        shorten(other)
                    ),
                ));
            }
        }
    }
}

/// The pairs of vertex properties read as texture coordinates, the first pair present.
const UV_NAMES: [[&str; 2]; 3] = [["u", "v"], ["s", "t"], ["texture_u", "texture_v"]];

/// What the reader takes from the elements: the vertex element and its x, y, z properties and
/// its texture coordinates, the face element and its index list and its `texcoord` list
/// (element and property indices).
struct Roles {
    vertex: usize,
    xyz: [usize; 3],
    uv: Option<[usize; 2]>,
    face: Option<(usize, usize)>,
    texcoord: Option<usize>,
    /// A `tristrips` element and its index list (strips, −1 restarting one).
    strips: Option<(usize, usize)>,
}

impl Roles {
    /// Whether property `i` of element `e` is read.
    fn reads(&self, e: usize, i: usize) -> bool {
        let vertex = e == self.vertex
            && (self.xyz.contains(&i) || self.uv.is_some_and(|uv| uv.contains(&i)));
        let face = self
            .face
            .is_some_and(|(f, p)| f == e && (p == i || self.texcoord == Some(i)));
        vertex || face || self.strips == Some((e, i))
    }
}

/// The index list of element `e` (`vertex_indices` or `vertex_index`), refused unless a list of
/// integers.
fn index_list(file: &str, element: &Element) -> Result<usize, Error> {
    let Some(i) = element
        .properties
        .iter()
        .position(|p| p.name == "vertex_indices" || p.name == "vertex_index")
    else {
        return Err(Error::at(
            Location::line(file, element.line),
            format!(
                "the `{}` element has no `vertex_indices` list",
                element.name
            ),
        ));
    };
    let p = &element.properties[i];
    match p.kind {
        Kind::List { item, .. } if item.is_integer() => Ok(i),
        Kind::List { item, .. } => Err(Error::at(
            Location::line(file, p.line),
            format!(
                "vertex indices of type `{}`; expected an integer type",
                item.name()
            ),
        )),
        Kind::Scalar(_) => Err(Error::at(
            Location::line(file, p.line),
            format!("`{}` is not a list", p.name),
        )),
    }
}

fn roles(file: &str, h: &Header) -> Result<Roles, Error> {
    let find = |name: &str| h.elements.iter().position(|e| e.name == name);
    let Some(vertex) = find("vertex") else {
        return Err(Error::at(
            Location::line(file, h.end_line),
            "the header declares no `vertex` element",
        ));
    };
    let ve = &h.elements[vertex];
    // The vertex property `name`, refused if it is a list.
    let scalar = |name: &str| -> Result<Option<usize>, Error> {
        let Some(i) = ve.properties.iter().position(|p| p.name == name) else {
            return Ok(None);
        };
        if matches!(ve.properties[i].kind, Kind::List { .. }) {
            return Err(Error::at(
                Location::line(file, ve.properties[i].line),
                format!("vertex property `{name}` is a list; expected a number"),
            ));
        }
        Ok(Some(i))
    };
    let mut xyz = [0; 3];
    for (slot, axis) in xyz.iter_mut().zip(["x", "y", "z"]) {
        *slot = scalar(axis)?.ok_or_else(|| {
            Error::at(
                Location::line(file, ve.line),
                format!("the `vertex` element has no `{axis}` property"),
            )
        })?;
    }
    let mut uv = None;
    for [u, v] in UV_NAMES {
        let present = |name| ve.properties.iter().any(|p| p.name == name);
        if present(u) && present(v) {
            uv = scalar(u)?.zip(scalar(v)?).map(|(u, v)| [u, v]);
            break;
        }
    }
    let mut texcoord = None;
    let face = match find("face") {
        None => None,
        Some(f) => {
            let fe = &h.elements[f];
            let i = index_list(file, fe)?;
            if let Some(t) = fe.properties.iter().position(|p| p.name == "texcoord") {
                let p = &fe.properties[t];
                if let Kind::Scalar(_) = p.kind {
                    return Err(Error::at(
                        Location::line(file, p.line),
                        "face property `texcoord` is not a list (u v per corner)",
                    ));
                }
                texcoord = Some(t);
                uv = None; // per corner, finer than per vertex
            }
            Some((f, i))
        }
    };
    let strips = match find("tristrips") {
        Some(t) => Some((t, index_list(file, &h.elements[t])?)),
        None => None,
    };
    Ok(Roles {
        vertex,
        xyz,
        uv,
        face,
        texcoord,
        strips,
    })
}

/// Which value is being read, for messages: `vertex 3, property `y``.
#[derive(Clone, Copy)]
struct Context<'a> {
    element: &'a str,
    index: u64,
    property: Option<&'a str>,
}

impl fmt::Display for Context<'_> {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "{} {}", shorten(self.element), self.index)?;
        match self.property {
            Some(p) => write!(f, ", property `{}`", shorten(p)),
            None => Ok(()),
        }
    }
}

/// The data after the header, read value by value.
trait Source {
    /// Starts element instance `cx` (`of`: the element's count); returns its place (line or
    /// byte offset).
    fn begin(&mut self, cx: Context<'_>, of: u64) -> Result<usize, Error>;
    /// The next value, of type `t`; `finite`: refuse NaN and infinities.
    fn value(&mut self, t: Scalar, cx: Context<'_>, finite: bool) -> Result<Value, Error>;
    /// Skips `n` values of type `t`.
    fn skip(&mut self, t: Scalar, n: u64, cx: Context<'_>) -> Result<(), Error>;
    /// Ends the instance.
    fn end(&mut self, cx: Context<'_>) -> Result<(), Error>;
    /// What follows the last element, as a warning.
    fn rest(&mut self) -> Option<String>;
    /// A problem with the value read last.
    fn fail(&self, cx: Context<'_>, message: &str) -> Error;
    /// Refuses an element whose count cannot fit in the data left (binary: each instance has at
    /// least [`Element::min_size`] bytes), before anything of it is read or stored.
    fn check_count(&self, file: &str, element: &Element) -> Result<(), Error>;
}

/// ASCII data: one element instance per line (blank lines skipped), values separated by
/// whitespace; errors at line and column.
struct Ascii<'a> {
    file: &'a str,
    rest: &'a [u8],
    line: usize,
    tokens: Vec<(&'a [u8], usize)>,
    next: usize,
}

/// The column of the value read last on the current line.
fn last_column(tokens: &[(&[u8], usize)], next: usize) -> Option<usize> {
    next.checked_sub(1).and_then(|i| tokens.get(i)).map(|t| t.1)
}

impl<'a> Ascii<'a> {
    fn at(&self, column: Option<usize>, message: String) -> Error {
        Error::at(
            Location {
                file: self.file.to_string(),
                line: Some(self.line.max(1)),
                column,
            },
            message,
        )
    }

    /// The next line with a value; false at the end of the data.
    fn next_line(&mut self) -> bool {
        while !self.rest.is_empty() {
            let end = self.rest.iter().position(|&b| b == b'\n');
            let (l, rest) = match end {
                Some(i) => (&self.rest[..i], &self.rest[i + 1..]),
                None => (self.rest, &[][..]),
            };
            self.rest = rest;
            self.line += 1;
            self.tokens.clear();
            self.next = 0;
            let mut start = None;
            for (i, &b) in l.iter().chain(b" ").enumerate() {
                match (b.is_ascii_whitespace(), start) {
                    (true, Some(s)) => {
                        self.tokens.push((&l[s..i], s + 1));
                        start = None;
                    }
                    (false, None) => start = Some(i),
                    _ => {}
                }
            }
            if !self.tokens.is_empty() {
                return true;
            }
        }
        false
    }
}

impl Source for Ascii<'_> {
    fn begin(&mut self, cx: Context<'_>, of: u64) -> Result<usize, Error> {
        if self.next_line() {
            return Ok(self.line);
        }
        Err(self.at(
            None,
            format!(
                "the file ends after {} of {of} `{}` elements (truncated, or a wrong count in the header)",
                cx.index,
                shorten(cx.element)
            ),
        ))
    }

    fn value(&mut self, t: Scalar, cx: Context<'_>, finite: bool) -> Result<Value, Error> {
        let Some(&(tok, column)) = self.tokens.get(self.next) else {
            return Err(self.at(None, format!("{cx}: the line ends before this value")));
        };
        self.next += 1;
        let text = String::from_utf8_lossy(tok);
        let v = t.parse(&text).ok_or_else(|| {
            self.at(
                Some(column),
                format!("{cx}: `{}` is not a {}", shorten(&text), t.name()),
            )
        })?;
        if finite && !v.to_f64().is_finite() {
            return Err(self.at(
                Some(column),
                format!("{cx}: coordinate `{}` is not finite", shorten(&text)),
            ));
        }
        Ok(v)
    }

    fn skip(&mut self, _: Scalar, n: u64, cx: Context<'_>) -> Result<(), Error> {
        let left = (self.tokens.len() - self.next) as u64;
        if n > left {
            return Err(self.at(
                None,
                format!("{cx}: the list has {n} values but the line only {left} more"),
            ));
        }
        self.next += n as usize;
        Ok(())
    }

    fn end(&mut self, cx: Context<'_>) -> Result<(), Error> {
        match self.tokens.get(self.next) {
            None => Ok(()),
            Some(&(_, column)) => Err(self.at(
                Some(column),
                format!(
                    "{cx}: {} more values than the header declares",
                    self.tokens.len() - self.next
                ),
            )),
        }
    }

    fn rest(&mut self) -> Option<String> {
        let first = self.next_line().then_some(self.line)?;
        let mut lines = 1;
        while self.next_line() {
            lines += 1;
        }
        let noun = if lines == 1 { "line" } else { "lines" };
        Some(format!(
            "ignored {lines} {noun} after the last element (first at line {first})"
        ))
    }

    fn fail(&self, cx: Context<'_>, message: &str) -> Error {
        self.at(
            last_column(&self.tokens, self.next),
            format!("{cx}: {message}"),
        )
    }

    fn check_count(&self, _: &str, _: &Element) -> Result<(), Error> {
        Ok(()) // each instance takes a line: the count is bounded by the lines read
    }
}

/// Binary data: values of their type's size in the file's byte order; errors name the
/// element, the property and the byte offset.
struct Binary<'a> {
    file: &'a str,
    bytes: &'a [u8],
    pos: usize,
    /// Offset of the value read last.
    last: usize,
    big: bool,
}

impl Binary<'_> {
    fn at(&self, cx: Context<'_>, message: &str) -> Error {
        Error::at(
            Location::whole(self.file),
            format!("{cx}, byte {}: {message}", self.pos),
        )
    }

    fn left(&self) -> u64 {
        (self.bytes.len() - self.pos) as u64
    }

    /// The next `n` bytes.
    fn take(&mut self, n: u64, cx: Context<'_>) -> Result<&[u8], Error> {
        let left = self.left();
        if n > left {
            return Err(self.at(
                cx,
                &format!(
                    "the file ends inside this element ({n} bytes needed, {left} left; truncated)"
                ),
            ));
        }
        let start = self.pos;
        self.pos += n as usize;
        Ok(&self.bytes[start..self.pos])
    }
}

impl Source for Binary<'_> {
    fn begin(&mut self, _: Context<'_>, _: u64) -> Result<usize, Error> {
        Ok(self.pos)
    }

    fn value(&mut self, t: Scalar, cx: Context<'_>, finite: bool) -> Result<Value, Error> {
        let start = self.pos;
        let big = self.big;
        let v = t.decode(self.take(t.size() as u64, cx)?, big);
        self.last = start;
        if finite && !v.to_f64().is_finite() {
            return Err(self.fail(cx, &format!("coordinate {v} is not finite")));
        }
        Ok(v)
    }

    fn skip(&mut self, t: Scalar, n: u64, cx: Context<'_>) -> Result<(), Error> {
        let bytes = n.saturating_mul(t.size() as u64);
        self.take(bytes, cx).map(|_| ())
    }

    fn end(&mut self, _: Context<'_>) -> Result<(), Error> {
        Ok(())
    }

    fn rest(&mut self) -> Option<String> {
        let left = self.left();
        (left > 0).then(|| format!("ignored {left} bytes after the last element"))
    }

    fn fail(&self, cx: Context<'_>, message: &str) -> Error {
        Error::at(
            Location::whole(self.file),
            format!("{cx}, byte {}: {message}", self.last),
        )
    }

    fn check_count(&self, file: &str, e: &Element) -> Result<(), Error> {
        let (size, left) = (e.min_size(), self.left());
        if e.count.saturating_mul(size) <= left {
            return Ok(());
        }
        Err(Error::at(
            Location::line(file, e.line),
            format!(
                "{} `{}` elements of at least {size} bytes each do not fit in the {left} bytes left at byte {} (truncated, or a wrong count)",
                e.count,
                shorten(&e.name),
                self.pos
            ),
        ))
    }
}

/// The elements' data read from `src` by the header's `roles`; other values are skipped.
fn body(
    file: &str,
    h: &Header,
    roles: &Roles,
    src: &mut dyn Source,
    unit: Unit,
) -> Result<Parsed, Error> {
    let mut mesh = PolyMesh::new();
    let mut places = Places::new(unit, 0);
    let mut warnings = Vec::new();
    // Texture coordinates per vertex (roles.uv) or per corner (roles.texcoord).
    let mut uv_values: Vec<[f64; 2]> = Vec::new();
    for (e, element) in h.elements.iter().enumerate() {
        let role_xyz = (e == roles.vertex).then_some(roles.xyz);
        let role_uv = roles.uv.filter(|_| e == roles.vertex);
        let role_face = roles.face.filter(|&(f, _)| f == e).map(|(_, p)| p);
        let role_texcoord = roles.texcoord.filter(|_| role_face.is_some());
        let role_strip = roles.strips.filter(|&(t, _)| t == e).map(|(_, p)| p);
        let skipped: Vec<&str> = (element.properties.iter().enumerate())
            .filter(|&(i, _)| !roles.reads(e, i))
            .map(|(_, p)| p.name.as_str())
            .collect();
        if role_xyz.is_none() && role_face.is_none() && role_strip.is_none() {
            if element.count > 0 {
                warnings.push(format!(
                    "skipped {} `{}` elements (header line {})",
                    element.count,
                    shorten(&element.name),
                    element.line
                ));
            }
        } else if !skipped.is_empty() && element.count > 0 {
            let names: Vec<String> = skipped.iter().map(|n| shorten(n)).collect();
            warnings.push(format!(
                "ignored {} properties {} (header line {})",
                element.name,
                names.join(", "),
                element.line
            ));
        }
        if element.properties.is_empty() {
            continue; // nothing to read, whatever the count
        }
        src.check_count(file, element)?;
        for k in 0..element.count {
            let mut cx = Context {
                element: &element.name,
                index: k,
                property: None,
            };
            let place = src.begin(cx, element.count)?;
            let mut p = [0.0; 3];
            let mut t = [0.0; 2];
            let mut face = None;
            let mut strip = None;
            let mut corner_uv = None;
            for (i, prop) in element.properties.iter().enumerate() {
                cx.property = Some(&prop.name);
                let axis = role_xyz.and_then(|xyz| xyz.iter().position(|&j| j == i));
                let uv_axis = role_uv.and_then(|uv| uv.iter().position(|&j| j == i));
                match prop.kind {
                    Kind::Scalar(s) => {
                        let v = src.value(s, cx, axis.is_some() || uv_axis.is_some())?;
                        if let Some(a) = axis {
                            p[a] = v.to_f64();
                        }
                        if let Some(a) = uv_axis {
                            t[a] = v.to_f64();
                        }
                    }
                    Kind::List { count, item } => {
                        let n = match src.value(count, cx, false)? {
                            Value::Int(n) if n >= 0 => n as u64,
                            v => return Err(src.fail(cx, &format!("list length {v} is negative"))),
                        };
                        if role_face == Some(i) {
                            face = Some(indices(src, item, n, cx)?);
                        } else if role_strip == Some(i) {
                            strip = Some(strip_triangles(src, item, n, cx)?);
                        } else if role_texcoord == Some(i) {
                            for _ in 0..n / 2 {
                                let u = src.value(item, cx, true)?.to_f64();
                                uv_values.push([u, src.value(item, cx, true)?.to_f64()]);
                            }
                            if n % 2 == 1 {
                                src.value(item, cx, true)?;
                            }
                            corner_uv = Some((n, cx));
                        } else {
                            src.skip(item, n, cx)?;
                        }
                    }
                }
            }
            cx.property = None;
            src.end(cx)?;
            if role_xyz.is_some() {
                mesh.positions.push(p);
                places.vertices.push(place);
            }
            if role_uv.is_some() {
                uv_values.push(t);
            }
            if let Some(f) = face {
                if let Some((got, cx)) = corner_uv {
                    if got != 2 * f.len() as u64 {
                        let corners = f.len();
                        return Err(src.fail(
                            cx,
                            &format!(
                                "{got} values for {corners} corners; expected {} (u v per corner)",
                                2 * corners
                            ),
                        ));
                    }
                }
                mesh.push_face(&f);
                places.faces.push(place);
            }
            for t in strip.iter().flatten() {
                mesh.push_face(t);
                places.faces.push(place);
            }
        }
    }
    warnings.extend(src.rest());
    if mesh.face_count() == 0 {
        let e = places.locate(file, &TopologyError::NoFaces);
        // What was skipped may be where the faces are.
        return Err(match warnings.is_empty() {
            true => e,
            false => e.with_hint(warnings.join("; ")),
        });
    }
    let uv = if roles.texcoord.is_some() {
        Some(shared(&mesh, uv_values))
    } else {
        roles.uv.map(|_| PolyUv {
            values: uv_values,
            corners: mesh.corners.clone(),
        })
    };
    Ok(Parsed {
        mesh,
        places,
        features: Features::default(),
        uv,
        uv_rule: Default::default(),
        warnings,
    })
}

/// The channel of per-corner `values` (parallel to `mesh.corners`): corners at one vertex
/// with the same value (bit for bit) share it, values numbered in order of first use. Found by
/// sorting, which holds 8 bytes per corner besides the values, and the values are compacted in
/// place: the first corner of each value comes no earlier than its new index.
fn shared(mesh: &PolyMesh, mut values: Vec<[f64; 2]>) -> PolyUv {
    let key = |c: u32| {
        let c = c as usize;
        (mesh.corners[c], values[c].map(f64::to_bits))
    };
    let mut order: Vec<u32> = (0..values.len() as u32).collect();
    order.sort_unstable_by_key(|&c| (key(c), c));
    // Each corner's first corner with its vertex and value.
    let mut corners = vec![0; values.len()];
    for run in order.chunk_by(|&a, &b| key(a) == key(b)) {
        for &c in run {
            corners[c as usize] = run[0];
        }
    }
    drop(order);
    let mut used = 0;
    for c in 0..corners.len() {
        let first = corners[c] as usize;
        corners[c] = if first == c {
            values[used] = values[c];
            used += 1;
            used as u32 - 1
        } else {
            corners[first]
        };
    }
    values.truncate(used);
    PolyUv { values, corners }
}

/// The vertex indices of a face (a list of `n` values of type `item`, at least 3; read one by
/// one, so a huge `n` holds no more than the file has).
fn indices(src: &mut dyn Source, item: Scalar, n: u64, cx: Context<'_>) -> Result<Vec<u32>, Error> {
    if n < 3 {
        return Err(src.fail(cx, &too_few_corners(n as usize)));
    }
    let mut face = Vec::new();
    for _ in 0..n {
        let v = src.value(item, cx, false)?;
        face.push(
            match v {
                Value::Int(i) => u32::try_from(i).ok(),
                Value::Float(_) => None,
            }
            .ok_or_else(|| src.fail(cx, &format!("vertex index {v} out of range")))?,
        );
    }
    Ok(face)
}

/// A triangle strip's triangles: each three consecutive indices, every second one turned to
/// keep the strip's orientation, −1 starting a new strip; triangles that repeat an index (the
/// degenerate ones strips use to turn or join) left out.
fn strip_triangles(
    src: &mut dyn Source,
    item: Scalar,
    n: u64,
    cx: Context<'_>,
) -> Result<Vec<[u32; 3]>, Error> {
    let mut triangles = Vec::new();
    let mut run: Vec<u32> = Vec::new();
    for _ in 0..n {
        let v = src.value(item, cx, false)?;
        match v {
            Value::Int(-1) => run.clear(),
            Value::Int(i) if (0..=i64::from(u32::MAX)).contains(&i) => {
                run.push(i as u32);
                if let [.., a, b, c] = run[..] {
                    let t = if run.len() % 2 == 1 {
                        [a, b, c]
                    } else {
                        [b, a, c]
                    };
                    if a != b && b != c && a != c {
                        triangles.push(t);
                    }
                }
            }
            v => return Err(src.fail(cx, &format!("vertex index {v} out of range"))),
        }
    }
    Ok(triangles)
}

/// Parses PLY bytes (`file` names it in errors): the header, then the data as it declares,
/// ASCII or binary of either byte order. Vertices are numbered from 0 in messages, as face
/// lists index them. Connectivity is not checked here (see [`Parsed::check`]).
pub fn parse(file: &str, bytes: &[u8]) -> Result<Parsed, Error> {
    let h = header(file, bytes)?;
    let roles = roles(file, &h)?;
    match h.encoding {
        Encoding::Ascii => {
            let mut src = Ascii {
                file,
                rest: &bytes[h.body..],
                line: h.end_line,
                tokens: Vec::new(),
                next: 0,
            };
            body(file, &h, &roles, &mut src, Unit::Line)
        }
        Encoding::Binary { big } => {
            let mut src = Binary {
                file,
                bytes,
                pos: h.body,
                last: h.body,
                big,
            };
            body(file, &h, &roles, &mut src, Unit::Byte)
        }
    }
}

/// Writes `mesh` to `path` as ASCII PLY ([`format()`]), whole or not at all, streamed
/// ([`crate::write_atomic_with`]).
pub fn write(path: &std::path::Path, mesh: &QuadMesh) -> Result<(), Error> {
    write_with(path, mesh, Extras::default(), false)
}

/// [`write()`] with the channels `extras` carries (normals, texture coordinates: [`format_with`]),
/// ASCII or, with `binary`, binary little-endian ([`binary_with`]); checked before anything is
/// written, then streamed.
pub fn write_with(
    path: &std::path::Path,
    mesh: &QuadMesh,
    extras: Extras<'_>,
    binary: bool,
) -> Result<(), Error> {
    let out = Out::new(mesh, extras)?;
    if binary {
        crate::write_atomic_with(path, |file| out.binary(false, file))
    } else {
        crate::write_atomic_with(path, |file| write!(file, "{out}"))
    }
}

/// ASCII PLY: vertex x y z as double (round-trip precision), faces as a `uchar int` list; a
/// non-finite coordinate is refused ([`crate::points::finite`]).
pub fn format(mesh: &QuadMesh) -> Result<String, Error> {
    format_with(mesh, Extras::default())
}

/// [`format()`] with extras: normals as vertex properties `nx ny nz` (double) after x y z;
/// texture coordinates as vertex properties `u v` (double) after them when every vertex has
/// one value at all its corners (`per_vertex`), else as a face list `texcoord` of u v per
/// corner (`uchar double`) after the vertex indices.
pub fn format_with(mesh: &QuadMesh, extras: Extras<'_>) -> Result<String, Error> {
    let out = Out::new(mesh, extras)?;
    let mut s = String::with_capacity(32 * mesh.positions.len() + 24 * mesh.faces.len() + 256);
    let _ = write!(s, "{out}");
    Ok(s)
}

/// A mesh with its extras, checked and laid out for PLY ([`format_with`]), not yet written:
/// `write!` it for ASCII, or [`Out::binary`]; `lsubdiv::write_atomic_with` streams either to
/// a file.
pub struct Out<'a> {
    mesh: &'a QuadMesh,
    extras: Extras<'a>,
    /// Texture coordinates per vertex, when every vertex has one value at all its corners.
    vertex_uv: Option<Vec<[f64; 2]>>,
    /// Else per corner.
    corner_uv: Option<&'a QuadUv>,
}

impl<'a> Out<'a> {
    /// Refuses what a PLY file cannot hold ([`Extras::check`]: a non-finite coordinate, extras
    /// that do not fit the mesh); lays out the texture coordinates.
    pub fn new(mesh: &'a QuadMesh, extras: Extras<'a>) -> Result<Out<'a>, Error> {
        extras.check(mesh)?;
        let vertex_uv = extras.uv.and_then(|uv| per_vertex(mesh, uv));
        Ok(Out {
            mesh,
            extras,
            corner_uv: extras.uv.filter(|_| vertex_uv.is_none()),
            vertex_uv,
        })
    }

    /// The header, in `format` (`ascii`, `binary_little_endian`, `binary_big_endian`) with
    /// vertex indices of type `index`.
    fn header(&self, s: &mut impl fmt::Write, format: &str, index: &str) -> fmt::Result {
        write!(
            s,
            "ply\nformat {format} 1.0\ncomment lsubdiv quad mesh\nelement vertex {}\n\
             property double x\nproperty double y\nproperty double z\n",
            self.mesh.positions.len(),
        )?;
        if self.extras.normals.is_some() {
            s.write_str("property double nx\nproperty double ny\nproperty double nz\n")?;
        }
        if self.vertex_uv.is_some() {
            s.write_str("property double u\nproperty double v\n")?;
        }
        write!(
            s,
            "element face {}\nproperty list uchar {index} vertex_indices\n",
            self.mesh.faces.len()
        )?;
        if self.corner_uv.is_some() {
            s.write_str("property list uchar double texcoord\n")?;
        }
        s.write_str("end_header\n")
    }

    /// Binary PLY in the byte order `big` (big-endian) or little-endian, the properties of
    /// the ASCII file (vertex indices `uint`): a third of its size or less, written several
    /// times faster (`subdivide --binary`).
    pub fn binary(&self, big: bool, out: &mut dyn std::io::Write) -> std::io::Result<()> {
        let order = if big { "big" } else { "little" };
        let mut head = String::new();
        let _ = self.header(&mut head, &format!("binary_{order}_endian"), "uint");
        out.write_all(head.as_bytes())?;
        let double = |out: &mut dyn std::io::Write, x: f64| {
            out.write_all(&if big {
                x.to_be_bytes()
            } else {
                x.to_le_bytes()
            })
        };
        for (i, p) in self.mesh.positions.iter().enumerate() {
            for &x in p {
                double(out, x)?;
            }
            if let Some(n) = self.extras.normals {
                for &x in &n[i] {
                    double(out, x)?;
                }
            }
            if let Some(t) = &self.vertex_uv {
                for &x in &t[i] {
                    double(out, x)?;
                }
            }
        }
        for (k, f) in self.mesh.faces.iter().enumerate() {
            out.write_all(&[4])?;
            for i in f {
                out.write_all(&if big {
                    i.to_be_bytes()
                } else {
                    i.to_le_bytes()
                })?;
            }
            if let Some(uv) = self.corner_uv {
                out.write_all(&[8])?;
                for &i in &uv.faces[k] {
                    for &x in &uv.values[i as usize] {
                        double(out, x)?;
                    }
                }
            }
        }
        Ok(())
    }
}

/// ASCII PLY.
impl fmt::Display for Out<'_> {
    fn fmt(&self, s: &mut fmt::Formatter<'_>) -> fmt::Result {
        self.header(s, "ascii", "int")?;
        for (i, p) in self.mesh.positions.iter().enumerate() {
            write!(s, "{:?} {:?} {:?}", p[0], p[1], p[2])?;
            if let Some(n) = self.extras.normals {
                write!(s, " {:?} {:?} {:?}", n[i][0], n[i][1], n[i][2])?;
            }
            if let Some(t) = &self.vertex_uv {
                write!(s, " {:?} {:?}", t[i][0], t[i][1])?;
            }
            s.write_char('\n')?;
        }
        for (k, f) in self.mesh.faces.iter().enumerate() {
            write!(s, "4 {} {} {} {}", f[0], f[1], f[2], f[3])?;
            if let Some(uv) = self.corner_uv {
                s.write_str(" 8")?;
                for &i in &uv.faces[k] {
                    let t = uv.values[i as usize];
                    write!(s, " {:?} {:?}", t[0], t[1])?;
                }
            }
            s.write_char('\n')?;
        }
        Ok(())
    }
}

/// One texture coordinate per vertex of `mesh`, if each vertex has exactly one value (bit for
/// bit) at all its corners in `uv`: no seam, and no vertex without a face.
fn per_vertex(mesh: &QuadMesh, uv: &QuadUv) -> Option<Vec<[f64; 2]>> {
    let mut at: Vec<Option<[f64; 2]>> = vec![None; mesh.positions.len()];
    for (face, corners) in mesh.faces.iter().zip(&uv.faces) {
        for (&v, &i) in face.iter().zip(corners) {
            let t = uv.values[i as usize];
            match &mut at[v as usize] {
                slot @ None => *slot = Some(t),
                Some(s) if s.map(f64::to_bits) == t.map(f64::to_bits) => {}
                Some(_) => return None,
            }
        }
    }
    at.into_iter().collect()
}

/// Binary PLY in the byte order `big` (big-endian) or little-endian: vertex x y z as double,
/// faces as a `uchar uint` list.
pub fn binary(mesh: &QuadMesh, big: bool) -> Result<Vec<u8>, Error> {
    binary_with(mesh, Extras::default(), big)
}

/// [`binary`] with the extras of [`format_with`] ([`Out::binary`]).
pub fn binary_with(mesh: &QuadMesh, extras: Extras<'_>, big: bool) -> Result<Vec<u8>, Error> {
    let out = Out::new(mesh, extras)?;
    let mut bytes = Vec::with_capacity(48 * mesh.positions.len() + 17 * mesh.faces.len() + 256);
    out.binary(big, &mut bytes)
        .map_err(|e| Error::internal(None, format!("writing binary PLY to memory: {e}")))?;
    Ok(bytes)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::mesh_data::Checked;
    use lsubdiv_mesh::generators::{cube, klein_bottle, torus};

    /// Parses and checks `bytes` as `t.ply`.
    fn read(bytes: &[u8]) -> Result<Checked, Error> {
        crate::mesh_file::parse_checked("t.ply", bytes.to_vec())
    }

    /// `text` with its 1-based line `line` replaced by `new`.
    fn with_line(text: &str, line: usize, new: &str) -> String {
        let mut lines: Vec<&str> = text.lines().collect();
        lines[line - 1] = new;
        lines.join("\n") + "\n"
    }

    /// Where the data of `binary(…)` begins.
    fn body_start(bytes: &[u8]) -> usize {
        let end = b"end_header\n";
        bytes.windows(end.len()).position(|w| w == end).unwrap() + end.len()
    }

    /// The value `x` of type `t` as PLY bytes (the inverse of [`Scalar::decode`]).
    fn encode(t: Scalar, x: f64, big: bool) -> Vec<u8> {
        let mut b = match t {
            Scalar::I8 => (x as i8).to_le_bytes().to_vec(),
            Scalar::U8 => vec![x as u8],
            Scalar::I16 => (x as i16).to_le_bytes().to_vec(),
            Scalar::U16 => (x as u16).to_le_bytes().to_vec(),
            Scalar::I32 => (x as i32).to_le_bytes().to_vec(),
            Scalar::U32 => (x as u32).to_le_bytes().to_vec(),
            Scalar::F32 => (x as f32).to_le_bytes().to_vec(),
            Scalar::F64 => x.to_le_bytes().to_vec(),
        };
        if big {
            b.reverse();
        }
        b
    }

    /// The `texcoord` of [`cube_with_extras`] at vertex `v` of face `f`: by vertex, but face 0
    /// has its own (a seam around it); exact in f32.
    fn corner_uv(f: usize, v: u32) -> [f64; 2] {
        [f64::from(v) / 8.0, if f == 0 { 0.25 } else { 0.5 }]
    }

    /// The cube with every kind of extra: skipped scalar and list properties of many types
    /// around x, y, z, an element between vertices and faces, aliases, comments and `obj_info`,
    /// texture coordinates per corner ([`corner_uv`]); in `format` (`ascii`,
    /// `binary_little_endian` or `binary_big_endian`).
    fn cube_with_extras(format: &str) -> Vec<u8> {
        use Scalar::*;
        let m = cube();
        let mut rows: Vec<Vec<(Scalar, f64)>> = Vec::new();
        for (k, p) in m.positions.iter().enumerate() {
            let tex = [(U8, 2.0), (F32, 0.5), (F32, 0.25)];
            let mut row = vec![(U8, 255.0 - k as f64), (F32, p[0])];
            row.extend(tex);
            row.extend([(F64, p[1]), (I16, p[2]), (F32, -0.5)]);
            rows.push(row);
        }
        rows.push(vec![(I32, 0.0), (I32, 1.0)]);
        rows.push(vec![(I32, 1.0), (I32, 2.0)]);
        for (k, f) in m.faces.iter().enumerate() {
            let mut row = vec![(U8, 7.0), (I8, 4.0)];
            row.extend(f.iter().map(|&i| (U16, f64::from(i))));
            row.push((U8, 8.0));
            row.extend(f.iter().flat_map(|&i| corner_uv(k, i)).map(|x| (F32, x)));
            rows.push(row);
        }
        let mut out = format!(
            "ply\nformat {format} 1.0\ncomment made by hand\nobj_info anything\n\
             element vertex 8\nproperty uchar red\nproperty float32 x\n\
             property list uint8 float tex\nproperty double y\nproperty int16 z\n\
             property float nx\nelement edge 2\nproperty int vertex1\nproperty int32 vertex2\n\
             element face 6\nproperty uchar flags\nproperty list int8 uint16 vertex_index\n\
             property list uchar float texcoord\nelement material 0\nproperty float shine\n\
             end_header\n"
        )
        .into_bytes();
        let big = format == "binary_big_endian";
        for row in rows {
            if format == "ascii" {
                let text: Vec<String> = row.iter().map(|(_, x)| format!("{x}")).collect();
                out.extend(format!("{}\r\n", text.join(" ")).bytes());
            } else {
                for (t, x) in row {
                    out.extend(encode(t, x, big));
                }
            }
        }
        out
    }

    #[test]
    fn every_encoding_reads_the_same_mesh_skipping_the_rest() {
        let m = cube();
        for format in ["ascii", "binary_little_endian", "binary_big_endian"] {
            let read = read(&cube_with_extras(format)).unwrap_or_else(|e| panic!("{format}: {e}"));
            assert_eq!(read.mesh, m, "{format}");
            assert_eq!(read.topology.face_count(), 6);
            assert_eq!(
                read.warnings,
                vec![
                    "ignored vertex properties red, tex, nx (header line 5)",
                    "skipped 2 `edge` elements (header line 12)",
                    "ignored face properties flags (header line 15)",
                ],
                "{format}"
            );
            // Corners at one vertex with one value share it, in order of first use.
            let mut want = PolyUv::default();
            let mut index = std::collections::HashMap::new();
            for (f, face) in m.faces.iter().enumerate() {
                for &v in face {
                    let t = corner_uv(f, v);
                    let i = *index.entry((v, t.map(f64::to_bits))).or_insert_with(|| {
                        want.values.push(t);
                        want.values.len() as u32 - 1
                    });
                    want.corners.push(i);
                }
            }
            assert_eq!(want.values.len(), 8 + 4);
            assert_eq!(read.uv, Some(want.quads()), "{format}");
        }
    }

    /// A square of two vertex properties `names` of type `t` (values `uv(i)` at vertex i) in
    /// `format`.
    fn square_with(
        format: &str,
        names: [&str; 2],
        t: Scalar,
        uv: impl Fn(usize) -> [f64; 2],
    ) -> Vec<u8> {
        let mut out = format!(
            "ply\nformat {format} 1.0\nelement vertex 4\nproperty {t} {u}\nproperty float x\n\
             property float y\nproperty {t} {v}\nproperty float z\nelement face 1\n\
             property list uchar int vertex_indices\nend_header\n",
            t = t.name(),
            u = names[0],
            v = names[1]
        )
        .into_bytes();
        let big = format == "binary_big_endian";
        let square = [[0.0, 0.0], [1.0, 0.0], [1.0, 1.0], [0.0, 1.0]];
        let mut rows: Vec<Vec<(Scalar, f64)>> = (0..4)
            .map(|i| {
                let [u, v] = uv(i);
                let [x, y] = square[i];
                vec![
                    (t, u),
                    (Scalar::F32, x),
                    (Scalar::F32, y),
                    (t, v),
                    (Scalar::F32, 0.0),
                ]
            })
            .collect();
        rows.push(vec![
            (Scalar::U8, 4.0),
            (Scalar::I32, 0.0),
            (Scalar::I32, 1.0),
            (Scalar::I32, 2.0),
            (Scalar::I32, 3.0),
        ]);
        for row in rows {
            if format == "ascii" {
                let text: Vec<String> = row.iter().map(|(_, x)| format!("{x}")).collect();
                out.extend(format!("{}\n", text.join(" ")).bytes());
            } else {
                for (t, x) in row {
                    out.extend(encode(t, x, big));
                }
            }
        }
        out
    }

    #[test]
    fn vertex_texture_coordinates_of_any_type_and_encoding() {
        let uv = |i: usize| [i as f64 * 2.0, 100.0 - i as f64];
        for format in ["ascii", "binary_little_endian", "binary_big_endian"] {
            for (names, t) in [
                (["u", "v"], Scalar::F32),
                (["s", "t"], Scalar::U8),
                (["texture_u", "texture_v"], Scalar::F64),
                (["s", "t"], Scalar::I16),
            ] {
                let p = parse("t.ply", &square_with(format, names, t, uv))
                    .unwrap_or_else(|e| panic!("{format} {names:?}: {e}"));
                let want = PolyUv {
                    values: (0..4).map(uv).collect(),
                    corners: vec![0, 1, 2, 3],
                };
                assert_eq!(p.uv, Some(want), "{format} {names:?}");
                assert!(
                    p.warnings.is_empty(),
                    "{format} {names:?}: {:?}",
                    p.warnings
                );
            }
            // One of a pair is not texture coordinates: skipped with the rest.
            let p = parse("t.ply", &square_with(format, ["u", "t"], Scalar::F32, uv)).unwrap();
            assert_eq!(p.uv, None);
            assert_eq!(
                p.warnings,
                vec!["ignored vertex properties u, t (header line 3)"]
            );
        }
        // Non-finite values are refused at their element.
        let nan = |i: usize| if i == 2 { [0.0, f64::NAN] } else { [0.0, 0.0] };
        let e = parse("t.ply", &square_with("ascii", ["u", "v"], Scalar::F32, nan)).unwrap_err();
        assert_eq!(
            e.to_string(),
            "t.ply:14:7: error: vertex 2, property `v`: coordinate `NaN` is not finite"
        );
        let le = square_with("binary_little_endian", ["s", "t"], Scalar::F64, nan);
        let e = parse("t.ply", &le).unwrap_err();
        let at = body_start(&le) + 2 * 28 + 16;
        assert_eq!(
            e.to_string(),
            format!(
                "t.ply: error: vertex 2, property `t`, byte {at}: coordinate NaN is not finite"
            )
        );
    }

    #[test]
    fn what_lsubdiv_writes_reads_back_bit_exact() {
        let mut awkward = torus(5, 7);
        awkward.positions[0] = [-0.0, 1e-300, 5e-324];
        awkward.positions[1] = [1.7976931348623157e308, -1e22, 0.1 + 0.2];
        for m in [cube(), awkward, klein_bottle(4, 5)] {
            for bytes in [
                format(&m).unwrap().into_bytes(),
                binary(&m, false).unwrap(),
                binary(&m, true).unwrap(),
            ] {
                let back = parse("t.ply", &bytes).unwrap().mesh.into_quads().unwrap();
                assert_eq!(back.faces, m.faces);
                let bits = |m: &QuadMesh| -> Vec<u64> {
                    m.positions.iter().flatten().map(|x| x.to_bits()).collect()
                };
                assert_eq!(bits(&back), bits(&m));
            }
        }
    }

    #[test]
    fn texture_coordinates_round_trip_per_vertex_or_per_corner() {
        use crate::mesh_data::tests::{canonical, torus_grid_uv, xy_uv};
        let m = torus(4, 5);
        let normals: Vec<[f64; 3]> = m.positions.iter().map(|p| [p[2], p[0], -p[1]]).collect();
        let flat = |uv: &QuadUv| uv.faces.iter().flatten().copied().collect::<Vec<u32>>();
        // Seamless: vertex properties; with seams (the grid closed on the torus): per corner.
        for (uv, header) in [
            (xy_uv(&m), "property double u\nproperty double v\nelement face 20\n\
                         property list uchar int vertex_indices\nend_header\n"),
            (torus_grid_uv(4, 5), "property double z\n{N}element face 20\n\
                         property list uchar int vertex_indices\nproperty list uchar double texcoord\n"),
        ] {
            for normals in [None, Some(&normals[..])] {
                let text = format_with(&m, Extras { normals, uv: Some(&uv) }).unwrap();
                let n = if normals.is_some() {
                    "property double nx\nproperty double ny\nproperty double nz\n"
                } else {
                    ""
                };
                assert!(text.contains(&header.replace("{N}", n)), "{text}");
                let p = parse("t.ply", text.as_bytes()).unwrap();
                assert_eq!(p.mesh.corners, m.faces.iter().flatten().copied().collect::<Vec<_>>());
                let back = p.uv.clone().expect("texture coordinates");
                assert_eq!(
                    canonical(&back.values, &back.corners),
                    canonical(&uv.values, &flat(&uv))
                );
                let c = p.clone().check("t.ply").unwrap();
                let back = c.uv.unwrap();
                assert_eq!(canonical(&back.values, &flat(&back)), canonical(&uv.values, &flat(&uv)));
                // Binary, both byte orders: the same header but its format and index type,
                // and the same mesh, texture coordinates and normals read back, bit for bit.
                for big in [false, true] {
                    let bytes = binary_with(&m, Extras { normals, uv: Some(&uv) }, big).unwrap();
                    let h = body_start(&bytes);
                    let order = if big { "big" } else { "little" };
                    let ascii = text[..text.find("end_header\n").unwrap() + 11]
                        .replace("format ascii", &format!("format binary_{order}_endian"))
                        .replace("uchar int vertex_indices", "uchar uint vertex_indices");
                    assert_eq!(String::from_utf8_lossy(&bytes[..h]), ascii);
                    let b = parse("t.ply", &bytes).unwrap();
                    assert_eq!(b.mesh.corners, p.mesh.corners);
                    assert_eq!(b.mesh.positions, p.mesh.positions);
                    let (ub, ua) = (b.uv.unwrap(), p.uv.clone().unwrap());
                    assert_eq!(ub.values, ua.values);
                    assert_eq!(ub.corners, ua.corners);
                    if let Some(normals) = normals {
                        let stride = if text.contains("property double u\n") { 64 } else { 48 };
                        let read = |at: usize| {
                            let b: [u8; 8] = bytes[at..at + 8].try_into().unwrap();
                            if big { f64::from_be_bytes(b) } else { f64::from_le_bytes(b) }
                        };
                        for (i, n) in normals.iter().enumerate() {
                            let at = h + i * stride + 24;
                            assert_eq!([read(at), read(at + 8), read(at + 16)], *n);
                        }
                    }
                }
            }
        }
        assert!(per_vertex(&m, &torus_grid_uv(4, 5)).is_none());
    }

    #[test]
    fn bad_texcoord_lists_are_refused_at_their_face() {
        let m = cube();
        let uv = QuadUv {
            values: vec![[0.5, 0.25]],
            faces: vec![[0; 4]; 6],
        };
        let mut seamed = uv.clone();
        seamed.values.push([1.0, 1.0]);
        seamed.faces[0][0] = 1;
        let ascii = format_with(
            &m,
            Extras {
                normals: None,
                uv: Some(&seamed),
            },
        )
        .unwrap();
        // Header lines 1–11 (`texcoord` at 10), vertices 12–19, face 1 at line 21.
        let face: Vec<&str> = ascii.lines().nth(20).unwrap().split(' ').collect();
        assert_eq!(face[5], "8");
        let column =
            |tokens: &[&str], k: usize| tokens[..k].iter().map(|t| t.len() + 1).sum::<usize>() + 1;
        for (texcoord, last, message) in [
            (
                "6 0 0 0 0 0 0",
                6,
                "6 values for 4 corners; expected 8 (u v per corner)",
            ),
            (
                "9 0 0 0 0 0 0 0 0 0",
                9,
                "9 values for 4 corners; expected 8 (u v per corner)",
            ),
            ("8 0 0 0 0 inf 0 0 0", 5, "coordinate `inf` is not finite"),
        ] {
            let mut tokens = face[..5].to_vec();
            tokens.extend(texcoord.split(' '));
            let text = with_line(&ascii, 21, &tokens.join(" "));
            let e = parse("t.ply", text.as_bytes()).unwrap_err().to_string();
            let at = column(&tokens, 5 + last);
            assert_eq!(
                e,
                format!("t.ply:21:{at}: error: face 1, property `texcoord`: {message}")
            );
        }
        let scalar = ascii.replace("list uchar double texcoord", "double texcoord");
        let e = parse("t.ply", scalar.as_bytes()).unwrap_err().to_string();
        assert_eq!(
            e,
            "t.ply:10: error: face property `texcoord` is not a list (u v per corner)"
        );
        // `texcoord` takes precedence over vertex `u v`, which are then ignored.
        let both = ascii
            .replace(
                "property double z\n",
                "property double z\nproperty float u\nproperty float v\n",
            )
            .lines()
            .enumerate()
            .map(|(i, l)| {
                if (13..21).contains(&i) {
                    format!("{l} 7 7\n")
                } else {
                    format!("{l}\n")
                }
            })
            .collect::<String>();
        let p = parse("t.ply", both.as_bytes()).unwrap();
        assert_eq!(
            p.warnings,
            vec!["ignored vertex properties u, v (header line 4)"]
        );
        let read = p.uv.unwrap();
        let per_corner = read.corners.iter().map(|&i| read.values[i as usize]);
        let written = seamed
            .faces
            .iter()
            .flatten()
            .map(|&i| seamed.values[i as usize]);
        assert!(per_corner.eq(written));
    }

    /// One row per kind of bad file: the bytes, the location and a fragment of the message.
    #[test]
    fn bad_files_are_refused_at_their_place() {
        let ascii = format(&cube()).unwrap(); // header lines 1–10, vertices 11–18, faces 19–24
        let le = binary(&cube(), false).unwrap();
        let h = body_start(&le);
        let mut nan = le.clone();
        nan[h + 2 * 24 + 8..h + 2 * 24 + 16].copy_from_slice(&f64::NAN.to_le_bytes());
        let mut far = le.clone();
        let index = h + 8 * 24 + 3 * 17 + 1 + 2 * 4;
        far[index..index + 4].copy_from_slice(&99u32.to_le_bytes());
        let mut be_short = binary(&cube(), true).unwrap();
        be_short.truncate(be_short.len() - 3);
        let hb = body_start(&be_short);
        let huge = String::from_utf8_lossy(&le[..h])
            .replace("vertex 8", "vertex 999999999")
            .into_bytes();
        let header = |h: &str| format!("ply\nformat ascii 1.0\n{h}\nend_header\n");
        let vertex = "element vertex 1\nproperty float x\nproperty float y\nproperty float z";
        let cases: Vec<(Vec<u8>, &str, String)> = vec![
            (b"plyx\n".to_vec(), "t.ply:1:1", "not a PLY file: the first line must be `ply`".into()),
            (b"v 0 0 0\n".to_vec(), "t.ply:1:1", "not a PLY file".into()),
            (
                ascii.replace("format ascii", "format ebcdic").into_bytes(),
                "t.ply:2:8",
                "unknown format `ebcdic` (ascii, binary_little_endian or binary_big_endian)".into(),
            ),
            (ascii.replace("ascii 1.0", "ascii 2.0").into_bytes(), "t.ply:2:14", "PLY version `2.0` is not supported".into()),
            (ascii.replace("end_header", "end_heade").into_bytes(), "t.ply:10:1", "unknown header line `end_heade`".into()),
            (ascii.lines().take(9).collect::<Vec<_>>().join("\n").into_bytes(), "t.ply:9", "the header ends without an `end_header` line".into()),
            (ascii.replace("double y", "real y").into_bytes(), "t.ply:6:10", "unknown type `real`".into()),
            (ascii.replace("list uchar int", "list float int").into_bytes(), "t.ply:9:15", "the length of a list must be an integer type".into()),
            (ascii.replace("uchar int vertex", "uchar float vertex").into_bytes(), "t.ply:9", "vertex indices of type `float`".into()),
            (ascii.replace("vertex_indices", "corners").into_bytes(), "t.ply:8", "the `face` element has no `vertex_indices` list".into()),
            (ascii.replace("double z", "double y").into_bytes(), "t.ply:7:17", "a second property `y` in element `vertex`".into()),
            (ascii.replace("vertex 8", "vertex 8.0").into_bytes(), "t.ply:4:16", "`8.0` is not an element count".into()),
            (ascii.replace("vertex 8", "vertex 99999999999999999999").into_bytes(), "t.ply:4:16", "does not fit 64 bits".into()),
            (ascii.replace("element vertex", "element point").into_bytes(), "t.ply:10", "the header declares no `vertex` element".into()),
            (header("property float x").into_bytes(), "t.ply:3:1", "a `property` before any `element`".into()),
            (header(vertex).replace("format ascii 1.0\n", "").into_bytes(), "t.ply:6:1", "the header has no `format` line".into()),
            (with_line(&ascii, 12, "1.0 abc 1.0").into_bytes(), "t.ply:12:5", "vertex 1, property `y`: `abc` is not a double".into()),
            (with_line(&ascii, 13, "1 1 nan").into_bytes(), "t.ply:13:5", "vertex 2, property `z`: coordinate `nan` is not finite".into()),
            (with_line(&ascii, 13, "1e999 1 1").into_bytes(), "t.ply:13:1", "coordinate `1e999` is not finite".into()),
            (with_line(&ascii, 14, "1 1").into_bytes(), "t.ply:14", "vertex 3, property `z`: the line ends before this value".into()),
            (with_line(&ascii, 14, "1 1 1 1").into_bytes(), "t.ply:14:7", "vertex 3: 1 more values than the header declares".into()),
            (with_line(&ascii, 20, "2 0 1").into_bytes(), "t.ply:20:1", "face 1, property `vertex_indices`: face has 2 vertices; a face has at least 3".into()),
            (with_line(&ascii, 20, "256 0 1 2 3").into_bytes(), "t.ply:20:1", "`256` is not a uchar".into()),
            (with_line(&ascii, 20, "4 0 1 -2 3").into_bytes(), "t.ply:20:7", "face 1, property `vertex_indices`: vertex index -2 out of range".into()),
            (with_line(&ascii, 20, "4 0 1 8 3").into_bytes(), "t.ply:20", "vertex index 8 out of range (the file has 8 vertices)".into()),
            (ascii.lines().take(22).collect::<Vec<_>>().join("\n").into_bytes(), "t.ply:22", "the file ends after 4 of 6 `face` elements".into()),
            (be_short, "t.ply", format!("face 5, property `vertex_indices`, byte {}: the file ends inside this element", hb + 8 * 24 + 5 * 17 + 13)),
            (nan, "t.ply", format!("vertex 2, property `y`, byte {}: coordinate NaN is not finite", h + 56)),
            (far, "t.ply", format!("face 3, byte {}: vertex index 99 out of range (the file has 8 vertices)", h + 8 * 24 + 3 * 17)),
            (huge, "t.ply:4", "999999999 `vertex` elements of at least 24 bytes each do not fit in the 0 bytes left".into()),
            (ascii.replace("face 6", "face 0").into_bytes(), "t.ply", "empty mesh: no faces".into()),
        ];
        for (bytes, at, fragment) in cases {
            let e = read(&bytes).expect_err(&fragment).to_string();
            assert!(
                e.starts_with(&format!("{at}: error: ")),
                "{e}\nexpected at {at}"
            );
            assert!(e.contains(&fragment), "{e}\nexpected {fragment}");
        }
    }

    #[test]
    fn ply_header_and_body() {
        let m = cube();
        let ply = format(&m).unwrap();
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

    #[test]
    fn triangle_strips_are_read_as_triangles() {
        // A 3 × 2 grid of vertices as one strip 0 3 1 4 2 5, then -1 and a second strip over
        // the same row (repeating an index: its degenerate triangle is left out).
        let header = "ply\nformat ascii 1.0\nelement vertex 6\nproperty float x\n\
                      property float y\nproperty float z\nelement tristrips 2\n\
                      property list int int vertex_indices\nend_header\n";
        let vertices = "0 0 0\n1 0 0\n2 0 0\n0 1 0\n1 1 0\n2 1 0.5\n";
        let text = format!("{header}{vertices}6 0 3 1 4 2 5\n5 0 3 3 -1 1\n");
        let p = parse("t.ply", text.as_bytes()).unwrap();
        let faces: Vec<&[u32]> = p.mesh.faces().collect();
        // Orientation alternates along a strip: (0 3 1), (1 3 4), (1 4 2), (2 4 5).
        let want: [&[u32]; 4] = [&[0, 3, 1], &[1, 3, 4], &[1, 4, 2], &[2, 4, 5]];
        assert_eq!(faces, want);
        assert!(p.warnings.is_empty(), "{:?}", p.warnings);
        assert_eq!(p.places.faces, vec![16, 16, 16, 16]);
        // The strips alone make a mesh lsubdiv refines (split into quads first).
        let text = format!("{header}{vertices}6 0 3 1 4 2 5\n0\n");
        assert!(read(text.as_bytes()).unwrap().split);
        // A negative index other than -1 is refused at its line.
        let text = format!("{header}{vertices}6 0 3 1 4 2 5\n3 0 -2 1\n");
        let e = parse("t.ply", text.as_bytes()).unwrap_err().to_string();
        assert!(
            e.contains("t.ply:17") && e.contains("vertex index -2 out of range"),
            "{e}"
        );
    }

    #[test]
    fn a_file_without_faces_says_what_was_skipped() {
        let text = "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\n\
                    property float y\nproperty float z\nelement polygons 1\n\
                    property list int int vertex_indices\nend_header\n0 0 0\n1 0 0\n0 1 0\n\
                    3 0 1 2\n";
        let e = parse("t.ply", text.as_bytes()).unwrap_err();
        let hint = e.hint.clone().unwrap_or_default();
        assert!(e.to_string().contains("no faces"), "{e}");
        assert!(
            hint.contains("skipped 1 `polygons` elements (header line 7)"),
            "{hint}"
        );
    }
}
