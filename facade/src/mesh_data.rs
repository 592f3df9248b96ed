//! What a mesh file holds once parsed, before and after its check: the mesh as written
//! ([`Parsed`]), the places (lines, or elements and byte offsets of a binary PLY) where each
//! vertex, face and sharp-feature tag was read, so that the topology's errors — face k, vertex
//! v, edge a–b — and the features' are placed in the file, the check shared by OBJ and PLY
//! ([`Parsed::check`] → [`Checked`]), and what a written mesh carries ([`Extras`]).

use lsubdiv_io::{Error, Location};
use lsubdiv_mesh::facevarying::{Points, PolyUv, QuadUv, UvError, UvRule};
use lsubdiv_mesh::features::{FeatureError, FeatureList, Features};
use lsubdiv_mesh::nonmanifold::{separate, Weld};
use lsubdiv_mesh::polygon::{catmull_clark, check_features, PolyMesh, SplitError};
use lsubdiv_mesh::topology::{Topology, TopologyError};
use lsubdiv_mesh::QuadMesh;

/// What a place in [`Places`] counts.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Unit {
    /// 1-based lines of a text file (OBJ, ASCII PLY).
    Line,
    /// Byte offsets of the element in a binary PLY.
    Byte,
}

/// Where each vertex, face and feature of a file was read: vertex i at `vertices[i]`, face k at
/// `faces[k]`, in lines or byte offsets ([`Unit`]), the features at the lines of their tags;
/// `first` is the number the file gives its first vertex (1 in OBJ, 0 in PLY), so that messages
/// number vertices as the file does.
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
    /// Lines of the tags of the features.
    pub features: FeatureLines,
    /// The file's vertex of each vertex of the mesh checked, where it was separated
    /// ([`lsubdiv_mesh::nonmanifold::separate`]); empty where it is the file's own.
    pub origin: Vec<u32>,
}

/// The line of the tag of each entry of a file's [`Features`]: crease k read at line
/// `creases[k]`, and so on; `boundary` is the line of the tag that set the boundary rule, if
/// the file has one (OBJ's `t interpolateboundary`).
#[derive(Clone, Debug, Default, PartialEq, Eq)]
pub struct FeatureLines {
    /// Line of each crease.
    pub creases: Vec<usize>,
    /// Line of each corner.
    pub corners: Vec<usize>,
    /// Line of each hole.
    pub holes: Vec<usize>,
    /// Line of the boundary rule.
    pub boundary: Option<usize>,
}

/// What a reader parsed: the mesh, its sharp features and its texture coordinates (none checked
/// against the others), where each of its vertices, faces and features was read, and warnings
/// about what it skipped.
#[derive(Clone, Debug, PartialEq)]
pub struct Parsed {
    /// The mesh as written: triangles, quads, n-gons.
    pub mesh: PolyMesh,
    /// Where each vertex, face and feature was read.
    pub places: Places,
    /// Creases, corners and holes (OBJ tags; none in PLY) and the boundary rule (the file's,
    /// or the default; a caller may set it before [`Parsed::check`], which applies it in the
    /// first step of a mesh that is not all quads).
    pub features: Features,
    /// Texture coordinates, one value index per corner of `mesh` (OBJ `vt` and face corners
    /// `i/t`; PLY vertex `u v` or face `texcoord`), if the file has them.
    pub uv: Option<PolyUv>,
    /// How [`Parsed::check`] takes `uv` through the first step of a mesh that is not all quads
    /// (the default; a caller may set it before).
    pub uv_rule: UvRule,
    /// Skipped directives, elements and values, one line of text per kind.
    pub warnings: Vec<String>,
}

/// A mesh ready to refine: read by [`crate::mesh_file::read_checked`] or [`crate::mesh_file::parse_checked`], a
/// 2-manifold the topology accepts, with its topology (build it once, pass it along), its
/// features and the reader's warnings. A file with faces that are not quads is taken one
/// Catmull–Clark step ([`lsubdiv_mesh::polygon`], boundaries and features included), the first
/// step of its refinement ([`Checked::split`]).
#[derive(Clone, Debug)]
pub struct Checked {
    /// The quad mesh: the file's, or its Catmull–Clark step when it has other faces.
    pub mesh: QuadMesh,
    /// The file had faces that are not quads: `mesh` is its first step, so it is refined one
    /// step less.
    pub split: bool,
    /// Its connectivity.
    pub topology: Topology,
    /// Its features, named by the vertices and faces of `mesh`: the file's, or their image
    /// after the first step ([`lsubdiv_mesh::polygon::Split::features`]).
    pub features: Features,
    /// Its texture coordinates, faces parallel to `mesh`'s: the file's, or their first step
    /// by [`Parsed::uv_rule`] ([`PolyUv::split`]).
    pub uv: Option<QuadUv>,
    /// The rule `uv` is refined by: [`Parsed::uv_rule`].
    pub uv_rule: UvRule,
    /// Skipped directives, elements and values, one line of text per kind.
    pub warnings: Vec<String>,
    /// Where the file is not a 2-manifold: which vertices of `mesh` are copies of one point,
    /// to join after refining ([`Weld::join`]).
    pub weld: Option<Weld>,
}

impl Checked {
    /// The file's point each vertex of the mesh stands for, where it was separated
    /// ([`Weld::points`]); none where the vertices are the file's own.
    pub fn points(&self) -> Points<'_> {
        Points(self.weld.as_ref().map_or(&[], Weld::points))
    }
}

/// `n` and the noun, singular for one: `1 vertex`, `8 vertices`.
pub(crate) fn counted(n: usize, one: &str, many: &str) -> String {
    format!("{n} {}", if n == 1 { one } else { many })
}

/// The hint of a feature tag naming an element that is not there.
pub(crate) const TAG_NUMBERS: &str = "tags number vertices and faces from 0, as OpenSubdiv \
    writes them: an OBJ `v` or `f` number less one";

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
            features: FeatureLines::default(),
            origin: Vec::new(),
        }
    }

    /// The file's vertex of vertex v of the mesh checked.
    fn file_vertex(&self, v: u32) -> u32 {
        self.origin.get(v as usize).copied().unwrap_or(v)
    }

    /// The feature error `e` of the mesh read from `file` as a diagnostic at the line of the
    /// tag of the feature it names (tags number vertices and faces from 0, as OpenSubdiv
    /// writes them, and messages quote them so).
    pub fn locate_feature(&self, file: &str, e: &FeatureError) -> Error {
        let lines = |list| match list {
            FeatureList::Creases => &self.features.creases,
            FeatureList::Corners => &self.features.corners,
            FeatureList::Holes => &self.features.holes,
        };
        let (list, k, message) = match *e {
            FeatureError::NoSuchEdge { crease, edge } => (
                FeatureList::Creases,
                crease,
                format!(
                    "crease {}–{}: no such edge (the vertices are not joined by an edge of a face; tags count vertices from 0)",
                    edge[0], edge[1]
                ),
            ),
            FeatureError::NoSuchVertex {
                corner,
                vertex,
                vertices,
            } => (
                FeatureList::Corners,
                corner,
                format!(
                    "corner vertex {vertex} out of range (tags count vertices from 0; the file has {})",
                    counted(vertices, "vertex", "vertices")
                ),
            ),
            FeatureError::NoSuchFace { hole, face, faces } => (
                FeatureList::Holes,
                hole,
                format!(
                    "hole face {face} out of range (tags count faces from 0; the file has {})",
                    counted(faces, "face", "faces")
                ),
            ),
            FeatureError::Repeated { list, first, second } => (
                list,
                second,
                match lines(list).get(first) {
                    Some(l) => format!("tagged twice: also at line {l}"),
                    None => e.to_string(),
                },
            ),
        };
        let hint = match e {
            FeatureError::Repeated { .. } => "tag each edge, vertex or face once",
            _ => TAG_NUMBERS,
        };
        match lines(list).get(k) {
            Some(&l) => Error::at(Location::line(file, l), message),
            None => Error::at(Location::whole(file), e.to_string()),
        }
        .with_hint(hint)
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
        let vertex = |v: u32| {
            let v = self.file_vertex(v);
            self.at(file, "vertex", v, self.vertices.get(v as usize))
        };
        let num = |v: u32| u64::from(self.file_vertex(v)) + self.first;
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
                    "vertex {} has valence {valence}; an interior vertex has two faces at least",
                    num(v)
                ),
            ),
            TopologyError::NoFaces | TopologyError::TooLarge { .. } => {
                ((Location::whole(file), String::new()), e.to_string())
            }
        };
        let hint = match e {
            TopologyError::FaceIndexOutOfRange { .. } => match self.first {
                1 => "OBJ counts vertices from 1 (negative indices back from the last `v`)",
                _ => "PLY face lists count vertices from 0",
            },
            TopologyError::DuplicateFaces { .. } => "remove one of the two faces",
            TopologyError::BoundaryEdge { .. } => "this command needs a closed mesh",
            TopologyError::NoFaces => "a mesh needs faces: OBJ `f` lines, a PLY `face` element",
            TopologyError::TooLarge { .. } => "split the mesh into parts",
            TopologyError::RepeatedVertex { .. } => "a face lists each of its corners once",
            TopologyError::NonManifoldEdge { .. } | TopologyError::NonManifoldVertex { .. } => {
                "a file's non-manifold places are separated when it is read (mesh_file::read_checked)"
            }
            TopologyError::IsolatedVertex { .. } => {
                "a file's unused vertices are dropped when it is read (mesh_file::read_checked)"
            }
            TopologyError::LowValence { .. } => "an interior vertex needs two faces",
        };
        Error::at(place, format!("{prefix}{message}")).with_hint(hint)
    }
}

impl Parsed {
    /// Bytes the parsed file holds on the heap: its vectors' capacities (positions, faces,
    /// places, texture coordinates).
    pub fn held_bytes(&self) -> u128 {
        fn of<T>(v: &[T], capacity: usize) -> u128 {
            (capacity.max(v.len()) * size_of::<T>()) as u128
        }
        let (m, p) = (&self.mesh, &self.places);
        let uv = self.uv.as_ref().map_or(0, |uv| {
            of(&uv.values, uv.values.capacity()) + of(&uv.corners, uv.corners.capacity())
        });
        of(&m.positions, m.positions.capacity())
            + of(&m.offsets, m.offsets.capacity())
            + of(&m.corners, m.corners.capacity())
            + of(&p.vertices, p.vertices.capacity())
            + of(&p.faces, p.faces.capacity())
            + uv
    }

    /// Builds the topology of the parsed mesh and checks it and its features (every crease an
    /// edge, every corner a vertex, every hole a face), its errors placed in `file`; a mesh with
    /// faces that are not quads is first taken one Catmull–Clark step with its boundaries and
    /// features ([`catmull_clark`]), and errors found after it name the file's faces. Texture
    /// coordinates take the same step by [`Parsed::uv_rule`] ([`PolyUv::split`]); their errors
    /// name the file.
    pub fn check(self, file: &str) -> Result<Checked, Error> {
        let Parsed {
            mesh,
            places,
            features,
            uv,
            uv_rule,
            warnings,
        } = self;
        let mut places = places;
        let mut warnings = warnings;
        let uv_error = |e: UvError| Error::in_file(file, format!("texture coordinates: {e}"));
        if let Some(uv) = &uv {
            uv.check(&mesh).map_err(uv_error)?;
        }
        check_features(
            mesh.positions.len(),
            (0..mesh.face_count()).map(|f| mesh.face(f)),
            &features,
        )
        .map_err(|e| places.locate_feature(file, &e))?;
        let separated = separate(&mesh, &features).map_err(|e| places.locate(file, &e))?;
        let (mesh, features, edge_origin) = match separated {
            None => (mesh, features, None),
            Some(s) => {
                warnings.extend(separation_notes(&s));
                places.origin = s.origin;
                (s.mesh, s.features, Some(s.edge_origin))
            }
        };
        let origin = edge_origin.as_ref().map(|e| (&places.origin[..], e));
        let topology_of =
            |q: &QuadMesh| Topology::build(q).and_then(|t| t.check_valences().map(|()| t));
        let (quads, features, topology, uv, split, weld) = match mesh.into_quads() {
            Ok(q) => {
                let topology = topology_of(&q).map_err(|e| places.locate(file, &e))?;
                let weld = origin.map(|(o, e)| Weld::new(o, e));
                (q, features, topology, uv.map(|uv| uv.quads()), false, weld)
            }
            Err(mesh) => {
                let s = catmull_clark(&mesh, &features).map_err(|e| match e {
                    SplitError::Topology(e) => places.locate(file, &e),
                    SplitError::Feature(e) => places.locate_feature(file, &e),
                })?;
                let topology =
                    topology_of(&s.mesh).map_err(|e| places.locate(file, &e.in_input(&s)))?;
                let points = Points(&places.origin);
                let uv = (uv
                    .map(|uv| uv.split(&mesh, &features, uv_rule, points))
                    .transpose())
                .map_err(uv_error)?;
                let weld = origin.map(|(o, e)| Weld::after_split(o, e, &s));
                (s.mesh, s.features, topology, uv, true, weld)
            }
        };
        Ok(Checked {
            mesh: quads,
            split,
            topology,
            features,
            uv,
            uv_rule,
            warnings,
            weld,
        })
    }
}

/// One line each for what [`separate`] did to a file: vertices dropped, non-manifold vertices
/// and edges made sharp.
fn separation_notes(s: &lsubdiv_mesh::nonmanifold::Separated) -> Vec<String> {
    let mut notes = Vec::new();
    if s.isolated > 0 {
        notes.push(format!(
            "{} used by no face: dropped",
            counted(s.isolated, "vertex", "vertices")
        ));
    }
    if s.vertices + s.edges > 0 {
        notes.push(format!(
            "not a 2-manifold: {} and {} made infinitely sharp, each fan refined on its own, as \
             OpenSubdiv does (docs/real-meshes.md)",
            counted(s.vertices, "non-manifold vertex", "non-manifold vertices"),
            counted(s.edges, "non-manifold edge", "non-manifold edges")
        ));
    }
    notes
}

/// What a written mesh carries beside its positions and faces.
#[derive(Clone, Copy, Debug, Default)]
pub struct Extras<'a> {
    /// One unit normal per vertex, in the vertices' order (OBJ `vn` with faces `v//vn`, PLY
    /// `nx ny nz`).
    pub normals: Option<&'a [[f64; 3]]>,
    /// Texture coordinates, faces parallel to the mesh's (OBJ `vt` with faces `v/vt`, PLY
    /// vertex `u v` or face `texcoord`).
    pub uv: Option<&'a QuadUv>,
}

impl Extras<'_> {
    /// What a mesh file cannot hold, refused before it is written: a non-finite coordinate of
    /// `mesh` (which the readers would reject), normals that are not one per vertex, texture
    /// coordinates whose faces are not `mesh`'s or name no value, and values that are not
    /// finite.
    pub fn check(&self, mesh: &QuadMesh) -> Result<(), Error> {
        crate::points::finite("vertex", &mesh.positions)?;
        let vertices = mesh.positions.len();
        if let Some(n) = self.normals {
            if n.len() != vertices {
                return Err(Error::internal(
                    None,
                    format!("{} normals for {vertices} vertices", n.len()),
                ));
            }
            crate::points::finite("normal", n)?;
        }
        if let Some(uv) = self.uv {
            uv.check(mesh)
                .map_err(|e| Error::internal(None, format!("texture coordinates: {e}")))?;
            crate::points::finite("texture coordinate", &uv.values)?;
        }
        Ok(())
    }
}

#[cfg(test)]
pub(crate) mod tests {
    use super::*;
    use crate::mesh_file::parse_checked as parse;
    use lsubdiv_mesh::features::Boundary;
    use lsubdiv_mesh::generators::torus;

    /// The torus `torus(rows, cols)` laid out on the grid [0,1]²: vertex (i, j) at
    /// (i / rows, j / cols), so the rows i = 0 and the columns j = 0 have two values each (the
    /// seams where the grid is closed), vertex (0, 0) four.
    pub(crate) fn torus_grid_uv(rows: usize, cols: usize) -> QuadUv {
        let id = |i: usize, j: usize| (i * (cols + 1) + j) as u32;
        let values = (0..=rows)
            .flat_map(|i| (0..=cols).map(move |j| [i as f64 / rows as f64, j as f64 / cols as f64]))
            .collect();
        let faces = (0..rows)
            .flat_map(|i| {
                (0..cols).map(move |j| [id(i, j), id(i + 1, j), id(i + 1, j + 1), id(i, j + 1)])
            })
            .collect();
        QuadUv { values, faces }
    }

    /// One value per vertex of `mesh`: its x and y.
    pub(crate) fn xy_uv(mesh: &QuadMesh) -> QuadUv {
        QuadUv {
            values: mesh.positions.iter().map(|p| [p[0], p[1]]).collect(),
            faces: mesh.faces.clone(),
        }
    }

    /// A channel's values per corner (bits) and which corners share one, numbered in order of
    /// first use: equal for two channels that differ only in how their values are numbered.
    pub(crate) fn canonical(values: &[[f64; 2]], corners: &[u32]) -> (Vec<[u64; 2]>, Vec<u32>) {
        let mut renumbered = vec![u32::MAX; values.len()];
        let mut out = (Vec::new(), Vec::new());
        for &c in corners {
            let r = &mut renumbered[c as usize];
            if *r == u32::MAX {
                *r = out.0.len() as u32;
                out.0.push(values[c as usize].map(f64::to_bits));
            }
            out.1.push(*r);
        }
        out
    }

    /// A flat open mesh (z = 0) of a square and a triangle on its right edge, and a second
    /// triangle on its top edge: OBJ text with vertices and `vt` lines, faces to be added.
    const FLAT: &str = "v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nv 2 0.5 0\nv 0.5 2 0\n";

    fn parsed(text: &str) -> Parsed {
        crate::obj::parse("t.obj", text).unwrap()
    }

    fn mid(p: [f64; 2], q: [f64; 2]) -> [f64; 2] {
        [(p[0] + q[0]) / 2.0, (p[1] + q[1]) / 2.0]
    }

    fn close(a: [f64; 2], b: [f64; 2]) -> bool {
        (a[0] - b[0]).abs() < 1e-15 && (a[1] - b[1]).abs() < 1e-15
    }

    #[test]
    fn linear_texture_coordinates_of_a_split_mesh() {
        // Texture coordinates unlike the positions, with a seam between the square and the
        // first triangle (edge 2–3 has other values there).
        let text = format!(
            "{FLAT}vt 0 0\nvt 0.5 0\nvt 0.5 0.5\nvt 0 0.5\nvt 0.75 0\nvt 0.75 0.25\nvt 1 0.1\n\
             vt 0.2 0.9\nf 1/1 2/2 3/3 4/4\nf 2/5 5/7 3/6\nf 4/4 3/3 6/8\n"
        );
        let p = parsed(&text);
        let uv = p.uv.clone().unwrap();
        let faces: Vec<Vec<[f64; 2]>> = (p.mesh.offsets.windows(2))
            .map(|w| {
                uv.corners[w[0]..w[1]]
                    .iter()
                    .map(|&i| uv.values[i as usize])
                    .collect()
            })
            .collect();
        let c = p.check("t.obj").unwrap();
        assert!(c.split);
        let got = c.uv.expect("texture coordinates");
        got.check(&c.mesh).unwrap();
        // Per face, per corner: the corner, the edge midpoint after it, the centroid, the
        // midpoint before it.
        let mut k = 0;
        for f in &faces {
            let n = f.len();
            let sum = f.iter().fold([0.0; 2], |s, p| [s[0] + p[0], s[1] + p[1]]);
            let centroid = [sum[0] / n as f64, sum[1] / n as f64];
            for i in 0..n {
                let want = [
                    f[i],
                    mid(f[i], f[(i + 1) % n]),
                    centroid,
                    mid(f[(i + n - 1) % n], f[i]),
                ];
                let quad = got.faces[k].map(|v| got.values[v as usize]);
                for (a, b) in quad.iter().zip(&want) {
                    assert!(close(*a, *b), "quad {k}: {quad:?}, want {want:?}");
                }
                k += 1;
            }
        }
        assert_eq!(k, got.faces.len());
        // The seam stays one: the edge 2–3 point of the square and of the triangle differ.
        let values_at = |face: usize, corner: usize| got.faces[face][corner];
        assert_ne!(values_at(1, 1), values_at(4, 3)); // after corner 1 of the square; before corner 0 of triangle 1
    }

    #[test]
    fn smooth_texture_coordinates_of_a_split_mesh_follow_the_mesh() {
        // One value per vertex, its x and y: the smooth rule's layout is the flat mesh itself,
        // so with the same (edge-only) boundary its split is the mesh's split.
        let text = format!(
            "{FLAT}vt 0 0\nvt 1 0\nvt 1 1\nvt 0 1\nvt 2 0.5\nvt 0.5 2\n\
             f 1/1 2/2 3/3 4/4\nf 2/2 5/5 3/3\nf 4/4 3/3 6/6\n"
        );
        let split = |rule| {
            let mut p = parsed(&text);
            p.features.boundary = Boundary::EdgeOnly;
            p.uv_rule = rule;
            p.check("t.obj").unwrap()
        };
        let smooth = split(UvRule::Smooth);
        let uv = smooth.uv.as_ref().unwrap();
        for (face, corners) in smooth.mesh.faces.iter().zip(&uv.faces) {
            for (&v, &t) in face.iter().zip(corners) {
                let p = smooth.mesh.positions[v as usize];
                assert!(close([p[0], p[1]], uv.values[t as usize]), "vertex {v}");
            }
        }
        // The linear rule takes midpoints instead: on the interior edge 2–3 they differ.
        let linear = split(UvRule::Linear);
        let at = |c: &Checked| c.uv.as_ref().map(|uv| uv.values[uv.faces[1][1] as usize]);
        assert_eq!(at(&linear), Some([1.0, 0.5]));
        assert!(!close(at(&smooth).unwrap(), [1.0, 0.5]));
    }

    #[test]
    fn texture_coordinates_of_quads_are_kept_and_checked() {
        let m = torus(3, 4);
        let uv = torus_grid_uv(3, 4);
        let text = crate::obj::format_with(
            &m,
            Extras {
                normals: None,
                uv: Some(&uv),
            },
        )
        .unwrap();
        let c = parse("t.obj", text.into_bytes()).unwrap();
        assert!(!c.split);
        assert_eq!(c.uv, Some(uv));
        // A channel that does not fit the mesh is refused, naming the file.
        let mut p = parsed(&format!("{FLAT}f 1 2 3 4\nf 2 5 3\n"));
        p.uv = Some(PolyUv {
            values: vec![[0.0; 2]],
            corners: vec![0; 6],
        });
        assert_eq!(
            p.check("t.obj").unwrap_err().to_string(),
            "t.obj: error: texture coordinates: 6 texture coordinate indices for 7 face corners"
        );
    }

    #[test]
    fn extras_are_checked_against_the_mesh() {
        let m = torus(3, 4);
        let mut uv = torus_grid_uv(3, 4);
        let check = |uv: &QuadUv| {
            Extras {
                normals: None,
                uv: Some(uv),
            }
            .check(&m)
        };
        check(&uv).unwrap();
        uv.values[5][1] = f64::INFINITY;
        assert!(check(&uv)
            .unwrap_err()
            .to_string()
            .contains("texture coordinate 6 has a non-finite coordinate"));
        uv.faces[2][3] = 99;
        assert!(check(&uv)
            .unwrap_err()
            .to_string()
            .contains("face 2 names texture coordinate 99, but there are 20"));
        uv.faces.pop();
        assert!(check(&uv)
            .unwrap_err()
            .to_string()
            .contains("44 texture coordinate indices for 48 face corners"));
    }
}
