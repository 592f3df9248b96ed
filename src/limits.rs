//! Size guard of the command line: `--max-memory`, and what a refinement will make and hold,
//! predicted exactly from the label words before anything is refined, so that a request too
//! large is refused with the prediction instead of dying half-way.
//!
//! Counts are exact: after N steps a curve has |π^N(w)| points (w: its labels, the interior
//! ones for an open curve) and a quad mesh V + E(n − 1) + F(n − 1)² vertices and F n² quads
//! (without what only holes use), n = |π^N(ω)| (`CurveTables::image_len`, `patch::output_counts`), in u128 and
//! saturating. Bytes are a bound on what the CLI's pipeline holds at its peak: the input and
//! the driver's buffers (the fast driver's own model, `patch::footprint`), then the output and
//! the output file, streamed through a buffer.

use lsubdiv::compiler::Error;
use lsubdiv::mesh::features::Features;
use lsubdiv::mesh::patch::footprint;
use lsubdiv::mesh::topology::Topology;
use lsubdiv::mesh_file::Checked;
use lsubdiv::CurveTables;

/// `--max-memory` when the machine's memory cannot be read (no `/proc/meminfo`): 8 GiB.
pub const FALLBACK_MAX_MEMORY: u64 = 8 << 30;

/// Bytes a streamed output file holds in memory: its write buffer
/// (`lsubdiv::write_atomic_with`).
const WRITE_BUFFER: u128 = 64 << 10;

/// Parses a size: bytes, or a number with a binary unit `K`, `M`, `G`, `T` (optionally followed
/// by `B` or `iB`, any case): `4G`, `512M`, `1.5GiB`, `1000000`.
pub fn parse_size(text: &str) -> Result<u64, String> {
    let t = text.trim();
    let bad = || {
        format!("`{text}` is not a size: give bytes or a number with K, M, G or T (powers of 1024), e.g. 4G")
    };
    let lower = t.to_ascii_lowercase();
    let body = lower
        .strip_suffix("ib")
        .or_else(|| lower.strip_suffix('b'))
        .unwrap_or(&lower);
    let (number, shift) = match body.chars().last() {
        Some('k') => (&body[..body.len() - 1], 10),
        Some('m') => (&body[..body.len() - 1], 20),
        Some('g') => (&body[..body.len() - 1], 30),
        Some('t') => (&body[..body.len() - 1], 40),
        _ => (body, 0),
    };
    if number.is_empty() || !number.bytes().all(|b| b.is_ascii_digit() || b == b'.') {
        return Err(bad());
    }
    let value: f64 = number.parse().map_err(|_| bad())?;
    let bytes = value * (1u64 << shift) as f64;
    if !(1.0..=u64::MAX as f64).contains(&bytes) {
        return Err(format!(
            "`{text}`: the size must be at least 1 byte and fit 64 bits"
        ));
    }
    Ok(bytes as u64)
}

/// Half of the machine's memory (`MemTotal` of `/proc/meminfo`), or [`FALLBACK_MAX_MEMORY`].
pub fn default_max_memory() -> u64 {
    std::fs::read_to_string("/proc/meminfo")
        .ok()
        .and_then(|s| {
            let line = s.lines().find(|l| l.starts_with("MemTotal:"))?;
            let kb: u64 = line.split_whitespace().nth(1)?.parse().ok()?;
            Some(kb.saturating_mul(1024) / 2)
        })
        .unwrap_or(FALLBACK_MAX_MEMORY)
}

/// What a refinement will make and hold.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Prediction {
    /// Output points (curves) or vertices (surfaces), exactly.
    pub vertices: u128,
    /// Output quads (surfaces), exactly.
    pub quads: Option<u128>,
    /// Bytes held at the peak, at most.
    pub bytes: u128,
}

impl Prediction {
    /// The prediction with what a refined mesh's limit and texture coordinates add:
    /// with `limit`, the limit pass's f64 positions and normals and the kept normals (72 bytes
    /// a vertex); with `uv`, up to four values a quad with their index (about 80 bytes: the
    /// value, its key and the hash table's share) and the quads' indices (16). The file is
    /// streamed ([`surface`]), so their text is not held.
    pub fn with_extras(self, limit: bool, uv: bool) -> Prediction {
        let (v, q) = (self.vertices, self.quads.unwrap_or(0));
        let limit = if limit { v.saturating_mul(72) } else { 0 };
        let uv = if uv { q.saturating_mul(4 * 80 + 16) } else { 0 };
        self.holding(limit.saturating_add(uv))
    }

    /// The prediction with what a curve's limit pass adds (`curve --limit`, `dim` coordinates a
    /// point): the limit positions and derivatives (16·`dim` bytes a point) beside the refined
    /// points, and with interpolated ends (`ends`) the odd-symmetric extension whose masks give
    /// them (a copy of the refined points and labels, and at most `3d` phantoms more:
    /// [`curve_ends`]).
    pub fn with_curve_limit(self, dim: usize, ends: Option<usize>) -> Prediction {
        let point = 8 * dim as u128;
        let limit = self.vertices.saturating_mul(2 * point);
        let extension = ends.map_or(0, |d| {
            self.vertices
                .saturating_add(3 * d as u128)
                .saturating_mul(point + 1)
        });
        self.holding(limit.saturating_add(extension))
    }

    /// The prediction when `bytes` more are held throughout, e.g. the input copied at another
    /// scale (`lsubdiv_cli::scale`).
    pub fn holding(self, bytes: u128) -> Prediction {
        Prediction {
            bytes: self.bytes.saturating_add(bytes),
            ..self
        }
    }

    /// Refuses a prediction over `max` bytes; `what` says what was asked, e.g. `4 steps of
    /// binary-ternary on cube.obj`.
    pub fn check(&self, what: &str, max: u64) -> Result<(), Error> {
        if self.bytes <= u128::from(max) {
            return Ok(());
        }
        let made = match self.quads {
            Some(q) => format!("{} vertices, {} quads", count(self.vertices), count(q)),
            None => format!("{} points", count(self.vertices)),
        };
        Err(Error::input(format!(
            "{what} would make {made}, {}; --max-memory is {}",
            size(self.bytes),
            size(u128::from(max))
        ))
        .with_hint("use fewer steps or raise --max-memory"))
    }
}

/// Refuses an input file whose reading could exceed `max` bytes: its text plus what is parsed
/// from it, at most 4 bytes per byte of text (`0 0 0\n`, 6 bytes, parses to 24), so 5 times
/// its size.
pub fn input(path: &std::path::Path, max: u64) -> Result<(), Error> {
    let Ok(meta) = std::fs::metadata(path) else {
        return Ok(()); // reading it reports the problem
    };
    holding(path, meta.len(), 5, max)
}

/// Bytes of connectivity per quad: six half-edge and edge words and four wedges per corner.
const TOPOLOGY_PER_QUAD: u128 = 4 * 4 * 6;

/// Bytes a PLY reading holds per byte of file, at most: a binary vertex of three 1-byte
/// coordinates (3 bytes) becomes a position (24 bytes) and its place (8), besides the file.
const PLY_HELD_PER_BYTE: u128 = 12;

/// Refuses a file of `len` bytes whose reading holds up to `per_byte` bytes per byte when that
/// exceeds `max`.
fn holding(path: &std::path::Path, len: u64, per_byte: u128, max: u64) -> Result<(), Error> {
    let bytes = u128::from(len) * per_byte;
    if bytes <= u128::from(max) {
        return Ok(());
    }
    Err(Error::in_file(
        path.display(),
        format!(
            "the file has {}, and reading it may hold {}; --max-memory is {}",
            size(u128::from(len)),
            size(bytes),
            size(u128::from(max))
        ),
    )
    .with_hint("raise --max-memory"))
}

/// The most bytes of an input file (a mesh or a point file) read under `--max-memory max`: its
/// bytes plus what is parsed from them, 5 times its size, as [`input`] counts.
pub fn input_bytes(max: u64) -> u64 {
    max / 5
}

/// Bytes per sample of the render frame: 1/depth (f32), triangle id (u32), two barycentric
/// weights (f32) and the wireframe flag.
const FRAME_SAMPLE: u128 = 4 + 4 + 8 + 1;
/// Bytes per pixel of an image and its encoding: the RGB pixels, the bytes handed to the PNG
/// encoder, the encoded file (at most the raw size and a little, deflate's stored blocks)
/// and the encoder's own row buffers (two filtered rows per pixel row).
const IMAGE_PIXEL: u128 = 3 + 3 + 4 + 2 * 3;
/// Bytes per vertex while drawing: the mesh and its normalised copy, camera-space positions and
/// clip codes, normals, curvature values and the vertex-in-view flags.
const RENDER_VERTEX: u128 = 24 + 24 + 24 + 1 + 24 + 8 + 8 + 1;
/// Bytes per quad while drawing: the mesh's faces, its normalised copy's, their topology (six
/// half-edge and edge words and four wedges), orientation and area vectors.
const RENDER_QUAD: u128 = 16 + 16 + TOPOLOGY_PER_QUAD + 4 * 8 + 1 + 1 + 24 + 2 * 8 + 1;
/// Bytes per pixel row of the curvature legend: its RGBA pixmap and the SVG text of its bar.
const LEGEND_ROW: u128 = 4 * 100 + 160;

/// Refuses a `render` of `width` × `height` pixels (`samples` × `samples` per pixel) of a mesh
/// of `vertices` and `quads` whose buffers would exceed `max` bytes: the supersampled frame,
/// the image and its encoding, the legend and the mesh's drawing data, all allocated only after
/// this check.
pub fn render(
    dims: (usize, usize),
    samples: usize,
    vertices: usize,
    quads: usize,
    max: u64,
) -> Result<(), Error> {
    let (w, h) = (dims.0 as u128, dims.1 as u128);
    let s = samples as u128;
    let bytes = (w * h * s * s) * FRAME_SAMPLE
        + w * h * IMAGE_PIXEL
        + h * LEGEND_ROW
        + vertices as u128 * RENDER_VERTEX
        + quads as u128 * RENDER_QUAD;
    let what = format!(
        "a {}x{} picture ({samples}x{samples} samples per pixel){}",
        dims.0,
        dims.1,
        if quads == 0 {
            String::new()
        } else {
            format!(" of {} quads", count(quads as u128))
        }
    );
    refuse_image(&what, bytes, max)
}

/// Refuses an image whose buffers would hold `bytes`, over `max`, with `what` it is.
fn refuse_image(what: &str, bytes: u128, max: u64) -> Result<(), Error> {
    if bytes <= u128::from(max) {
        return Ok(());
    }
    Err(Error::input(format!(
        "{what} would hold {}; --max-memory is {}",
        size(bytes),
        size(u128::from(max))
    ))
    .with_hint("use a smaller --size or raise --max-memory"))
}

/// What a picture holds once drawn ([`crate::picture::Picture::drawing`], or predicted before
/// drawing it): its SVG text, its elements, their points and its text elements' characters.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct Drawing {
    /// Bytes of SVG text.
    pub text: u128,
    /// Elements (lines, polylines, circles, rectangles, paths, texts).
    pub elements: u128,
    /// Points of their outlines (a polyline's vertices; two for a circle, a line…).
    pub points: u128,
    /// Text elements.
    pub texts: u128,
    /// Characters of the text elements.
    pub glyphs: u128,
}

/// Bytes resvg's tree holds per SVG element, at most: the XML node with its attributes and the
/// converted node with its paint (`cargo run --release` of a minimal resvg 0.45 program on
/// 200,000-element SVGs measured 1.07–1.39 KB a circle or polyline).
const TREE_ELEMENT: u128 = 1_800;
/// Bytes per outline point: its text in the XML node and its segment in the path.
pub const TREE_POINT: u128 = 32;
/// Bytes per text element and per character once its glyphs are outlined (measured about
/// 6.1 KB and 390 bytes with DejaVu Sans).
const TREE_TEXT: u128 = 8 << 10;
const TREE_GLYPH: u128 = 512;

/// Refuses a picture (`plot`, `graph`, `ev --characteristic-map`) of `width` × `height` pixels
/// whose rendering would exceed `max` bytes: the text and the document made of it, resvg's
/// tree of it (per element, point and glyph: `TREE_ELEMENT`), the RGBA pixmap and the PNG
/// encoding.
pub fn picture(dims: (u32, u32), d: &Drawing, max: u64) -> Result<(), Error> {
    let bytes = picture_bytes(dims, d);
    refuse_image(&format!("a {}x{} picture", dims.0, dims.1), bytes, max)
}

/// What rendering a picture holds at most ([`picture`]).
pub fn picture_bytes(dims: (u32, u32), d: &Drawing) -> u128 {
    let pixels = u128::from(dims.0) * u128::from(dims.1);
    [
        d.text.saturating_mul(2),
        d.elements.saturating_mul(TREE_ELEMENT),
        d.points.saturating_mul(TREE_POINT),
        d.texts.saturating_mul(TREE_TEXT),
        d.glyphs.saturating_mul(TREE_GLYPH),
        pixels * (4 + IMAGE_PIXEL),
    ]
    .into_iter()
    .fold(0u128, u128::saturating_add)
}

/// Reads an input file (a mesh or a point file; `-` is standard input) under `--max-memory max`:
/// a regular file whose reading could exceed it is refused unread ([`input`]), a pipe or device
/// is read only up to [`input_bytes`] and refused past them (exit 2, naming the file and the
/// limit). Returns the path read and its bytes.
pub fn read_input(path: &std::path::Path, max: u64) -> Result<(&std::path::Path, Vec<u8>), Error> {
    let path = if path.as_os_str() == "-" {
        std::path::Path::new("/dev/stdin")
    } else {
        path
    };
    input(path, max)?;
    let regular = std::fs::metadata(path).map_or(true, |m| m.is_file());
    let bytes = lsubdiv::compiler::read_bytes(path, input_bytes(max)).map_err(|e| {
        if regular {
            e
        } else {
            e.with_hint(format!(
                "--max-memory is {}, so an input is read up to a fifth of it; raise --max-memory",
                size(u128::from(max))
            ))
        }
    })?;
    Ok((path, bytes))
}

/// Reads a mesh (closed or open), its topology and its features from an OBJ or PLY file (by content:
/// [`lsubdiv::mesh_file::Format::of`], returned with it) by [`read_input`]; a PLY file, once read, is refused
/// before parsing if parsing it could exceed the limit (`PLY_HELD_PER_BYTE`). Errors name the
/// file's line (or a binary PLY's element and byte), the vertex or edge; warnings go to stderr.
pub fn read_mesh(
    path: &std::path::Path,
    max: u64,
    boundary: Option<lsubdiv::mesh::features::Boundary>,
    uv_rule: Option<lsubdiv::mesh::facevarying::UvRule>,
) -> Result<(Checked, lsubdiv::mesh_file::Format), Error> {
    let (path, bytes) = read_input(path, max)?;
    let name = path.display().to_string();
    let format = lsubdiv::mesh_file::Format::of(&name, &bytes);
    if format == lsubdiv::mesh_file::Format::Ply {
        holding(path, bytes.len() as u64, PLY_HELD_PER_BYTE, max)?;
    }
    let bytes_len = bytes.len() as u128;
    let mut parsed = lsubdiv::mesh_file::read_faces(&name, bytes)?;
    // The rule holds from the first step on (a Catmull–Clark step of a polygon mesh too).
    if let Some(b) = boundary {
        parsed.features.boundary = b;
    }
    if let Some(rule) = uv_rule {
        parsed.uv_rule = rule;
    }
    check_reading(&name, &parsed, bytes_len, max)?;
    let read = parsed.check(&name)?;
    for w in &read.warnings {
        eprintln!("{name}: warning: {w}");
    }
    Ok((read, format))
}

/// Bytes per face corner that checking a parsed mesh with faces other than quads holds at most
/// besides the parsed file: its first step (a quad per corner with its positions, face and
/// edge tables) and the topology of the quads (half-edges, edges and wedges);
/// `valgrind --tool=massif` of `subdivide --steps 0` measured 167 bytes a corner on two
/// 200,000-gons with a ring of quads and 190 on a triangulated torus.
const SPLIT_PER_CORNER: u128 = 208;
/// Bytes per corner that the first step of texture coordinates adds (measured 120 on the
/// triangulated torus with `--uv smooth`).
const SPLIT_UV_PER_CORNER: u128 = 128;
/// Bytes per corner of a quad mesh checked: its quads (16 bytes a quad) and their topology
/// ([`TOPOLOGY_PER_QUAD`]), with room for the topology's working vectors; 16 more with
/// texture coordinates (their quads).
const QUADS_PER_CORNER: u128 = 48;
const QUADS_UV_PER_CORNER: u128 = 16;

/// Refuses, before checking it, a mesh (`len` bytes of file, read into `parsed`) whose check
/// could exceed `max` bytes: the file's bytes (freed, but perhaps not yet given back to the
/// system), the parsed mesh twice (a copy where it is not a 2-manifold,
/// `nonmanifold::separate`), and per face corner what the first step and the topology hold
/// ([`SPLIT_PER_CORNER`], [`QUADS_PER_CORNER`]).
fn check_reading(
    name: &str,
    parsed: &lsubdiv::mesh_file::Parsed,
    len: u128,
    max: u64,
) -> Result<(), Error> {
    let corners = parsed.mesh.corners.len() as u128;
    let quads = parsed.mesh.all_quads();
    let per_corner = match (quads, parsed.uv.is_some()) {
        (true, uv) => QUADS_PER_CORNER + if uv { QUADS_UV_PER_CORNER } else { 0 },
        (false, uv) => SPLIT_PER_CORNER + if uv { SPLIT_UV_PER_CORNER } else { 0 },
    };
    let held = len
        .saturating_add(2 * parsed.held_bytes())
        .saturating_add(corners.saturating_mul(per_corner));
    if held <= u128::from(max) {
        return Ok(());
    }
    let faces = parsed.mesh.face_count() as u128;
    let what = if quads {
        format!("its {} quads", count(faces))
    } else {
        format!(
            "its {} faces, split into {} quads by the first (Catmull–Clark) step,",
            count(faces),
            count(corners)
        )
    };
    Err(Error::in_file(
        name,
        format!(
            "checking {what} would hold {}; --max-memory is {}",
            size(held),
            size(u128::from(max))
        ),
    )
    .with_hint("raise --max-memory"))
}

/// `steps` steps of a surface scheme (tables `t`, masks contained from step `contained_from`)
/// on the mesh of topology `topo` with `features`, positions of `scalar` bytes. The refiner's
/// own memory is its [`footprint`]; the output file is streamed from the refined mesh through
/// a buffer of `WRITE_BUFFER` bytes, never held whole.
pub fn surface(
    t: &CurveTables<'_>,
    contained_from: usize,
    topo: &Topology,
    features: &Features,
    steps: usize,
    scalar: u128,
    threads: usize,
) -> Prediction {
    let fp = footprint(t, contained_from, topo, features, steps, scalar, threads);
    Prediction {
        vertices: fp.vertices,
        quads: Some(fp.quads),
        bytes: fp
            .input
            .saturating_add(fp.refining.max(fp.output.saturating_add(WRITE_BUFFER))),
    }
}

/// Bytes per face corner that building a texture layout (`facevarying::Layout::new`) holds:
/// a value and its corner, the layout's quads, a copy to separate and the separated mesh with
/// its origins, and its topology; `valgrind --tool=massif` measured about 190 on a quad mesh
/// whose every edge is a seam.
const LAYOUT_PER_CORNER: u128 = 224;

/// Bytes that building the texture layout of a mesh of `quads` quads holds at most.
pub fn layout_building(quads: usize) -> u128 {
    (4 * quads as u128).saturating_mul(LAYOUT_PER_CORNER)
}

/// Bytes that refining a texture layout by a smooth rule (`facevarying::Layout`: topology
/// `topo`, features `features`) holds besides the positions' refinement and its result: the
/// layout's own [`footprint`] (its mesh and topology, the refiner's buffers or its refined
/// mesh, positions of f64), and a copy of its mesh where it is separated.
pub fn layout(
    t: &CurveTables<'_>,
    contained_from: usize,
    topo: &Topology,
    features: &Features,
    steps: usize,
    threads: usize,
) -> u128 {
    let fp = footprint(t, contained_from, topo, features, steps, 8, threads);
    fp.input
        .saturating_mul(2)
        .saturating_add(fp.refining.max(fp.output))
}

/// `steps` steps of a curve scheme on `points` control points of dimension `dim` labelled
/// `labels` (checked against the tables).
pub fn curve(
    t: &CurveTables<'_>,
    labels: &[u8],
    closed: bool,
    points: usize,
    dim: usize,
    steps: usize,
) -> Prediction {
    // An open curve's first and last d labels only carry its ends: each step keeps d labels
    // before and after π of the interior ones, so it has |π^N(interior)| + d points.
    let d = t.degree;
    let (counted, extra) = if closed {
        (labels, 0)
    } else {
        (labels.get(d..points).unwrap_or(&[]), d as u128)
    };
    refinement(t, counted, extra, 0, points, labels.len(), dim, steps)
}

/// `steps` steps with interpolated ends (`--ends interpolate`) of `points` control points
/// labelled by `edges` (one per edge): |π^N(edges)| + 1 points; each step also holds the
/// odd-symmetric extension, d − 1 phantom points and 2d labels more.
pub fn curve_ends(
    t: &CurveTables<'_>,
    edges: &[u8],
    points: usize,
    dim: usize,
    steps: usize,
) -> Prediction {
    let phantoms = 3 * t.degree as u128;
    refinement(t, edges, 1, phantoms, points, edges.len(), dim, steps)
}

/// A curve refinement that ends with |π^N(`counted`)| + `extra` points, holding `working`
/// more points or labels at every level besides the two levels it refines between, the input
/// and the output file.
#[allow(clippy::too_many_arguments)]
fn refinement(
    t: &CurveTables<'_>,
    counted: &[u8],
    extra: u128,
    working: u128,
    points: usize,
    labels: usize,
    dim: usize,
    steps: usize,
) -> Prediction {
    let m = |s: usize| t.image_len(counted, s).saturating_add(extra);
    let (last, before) = (m(steps), if steps == 0 { 0 } else { m(steps - 1) });
    let point = 8 * dim as u128;
    let input = (points as u128) * point + labels as u128;
    // Two levels of points and labels while refining; the points and labels at the end, their
    // file streamed through a buffer.
    let refine = last
        .saturating_add(before)
        .saturating_add(2 * working)
        .saturating_mul(point + 1);
    let out = last.saturating_mul(point + 1).saturating_add(WRITE_BUFFER);
    Prediction {
        vertices: last,
        quads: None,
        bytes: input.saturating_add(refine.max(out)),
    }
}

/// `1 234 567`, or `more than 10^38` when the count saturated.
pub fn count(n: u128) -> String {
    if n == u128::MAX {
        return "more than 10^38".into();
    }
    let digits = n.to_string();
    let groups: Vec<&str> = digits
        .as_bytes()
        .rchunks(3)
        .rev()
        .map(|g| std::str::from_utf8(g).unwrap_or_default())
        .collect();
    groups.join(" ")
}

/// Bytes in binary units with one decimal: `~3.1 GiB` (display only).
pub fn size(bytes: u128) -> String {
    const UNITS: [&str; 7] = ["bytes", "KiB", "MiB", "GiB", "TiB", "PiB", "EiB"];
    if bytes == u128::MAX {
        return "more than 10^38 bytes".into();
    }
    let mut x = bytes as f64;
    let mut unit = 0;
    while x >= 1024.0 && unit + 1 < UNITS.len() {
        x /= 1024.0;
        unit += 1;
    }
    if unit == 0 {
        format!("{bytes} bytes")
    } else if x >= 1024.0 {
        format!("~{x:.1e} {}", UNITS[unit])
    } else {
        format!("~{x:.1} {}", UNITS[unit])
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn sizes_parse_in_binary_units() {
        for (text, bytes) in [
            ("1000000", 1_000_000),
            ("4G", 4 << 30),
            ("4g", 4 << 30),
            ("4GiB", 4 << 30),
            ("4GB", 4 << 30),
            ("512M", 512 << 20),
            ("1.5G", 3 << 29),
            ("64k", 64 << 10),
            ("2T", 2 << 40),
            (" 7 ", 7),
        ] {
            assert_eq!(parse_size(text), Ok(bytes), "{text}");
        }
        for text in [
            "",
            "G",
            "4X",
            "-1G",
            "0",
            "0.1",
            "1e9",
            "4 G",
            "99999999999T",
            "nan",
        ] {
            assert!(parse_size(text).is_err(), "{text}");
        }
    }

    #[test]
    fn counts_and_sizes_read_well() {
        assert_eq!(count(1_234_567), "1 234 567");
        assert_eq!(count(999), "999");
        assert_eq!(count(1000), "1 000");
        assert_eq!(count(u128::MAX), "more than 10^38");
        assert_eq!(size(512), "512 bytes");
        assert_eq!(size(3 << 29), "~1.5 GiB");
        assert_eq!(size(5 << 60), "~5.0 EiB");
        assert_eq!(size(1 << 80), "~1.0e6 EiB");
        assert_eq!(size(u128::MAX), "more than 10^38 bytes");
    }
}
