//! Face-varying data: texture coordinates per face corner, refined with the mesh,
//! as OpenSubdiv's face-varying channels.
//!
//! A channel is a list of values and, per face corner, the index of its value: corners that
//! share an index share the value, and an edge whose two faces index different values is a
//! seam. Two rules refine it:
//! - [`UvRule::Linear`] (OpenSubdiv's `FVAR_LINEAR_ALL`): each refined vertex takes the
//!   bilinear interpolation of its base face's corner values at its parameters, its knots
//!   (K_x / K_N, K_y / K_N) with K the prefix sums of W_s's interval lengths (uniform
//!   fractions only for uniform binary); a first Catmull–Clark step of polygons takes corners,
//!   edge midpoints and centroids.
//! - [`UvRule::Smooth`] (`FVAR_LINEAR_NONE`): the scheme refines the layout itself, the quad
//!   mesh whose vertices are the values, with its seams and chart boundaries as edge-only
//!   boundaries and the mesh's creases, corners and holes carried onto it; where the layout
//!   is not a 2-manifold (values whose faces form several fans, edges of more than two faces
//!   or of two in the same direction) its fans are separated and those places made sharp, as
//!   OpenSubdiv's face-varying level makes them ([`crate::nonmanifold`]).
//! - [`UvRule::CornersOnly`], [`UvRule::CornersPlus1`], [`UvRule::CornersPlus2`],
//!   [`UvRule::Boundaries`] (OpenSubdiv's other `FVAR_LINEAR_*` modes): as smooth, with more of
//!   the layout's values kept as corners, where OpenSubdiv's face-varying level tags them sharp.
//!
//! Either way the refined channel's faces are parallel to the refined mesh's faces
//! ([`crate::patch::Refiner::faces`]) and seams stay seams.

use crate::features::{Boundary, FeatureError, Features, Sharpness};
use crate::grid::{site, Site};
use crate::mesh::QuadMesh;
use crate::nonmanifold::{separate, Weld};
use crate::patch::{limit_with, subdivide_with, Refined};
use crate::polygon::{catmull_clark, PolyMesh, SplitError};
use crate::real::Real;
use crate::surface::{SurfaceError, SurfaceScheme};
use crate::topology::{Topology, TopologyError};
use std::collections::HashMap;
use std::fmt;

/// How a face-varying channel is refined: OpenSubdiv's `Sdc::Options::FVarLinearInterpolation`.
/// Every rule but [`UvRule::Linear`] refines the layout by the scheme; they differ in which of
/// its values are kept as corners, as OpenSubdiv's face-varying level tags them
/// (`Vtr::FVarLevel::completeTopologyFromFaceValues`, `UvRule::sharpens`).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum UvRule {
    /// `FVAR_LINEAR_ALL`: bilinear in each base face at the refined vertices' knots.
    #[default]
    Linear,
    /// `FVAR_LINEAR_NONE`: the scheme applied to the layout, seams and chart boundaries
    /// edge-only boundaries.
    Smooth,
    /// `FVAR_LINEAR_CORNERS_ONLY`: as smooth, and a value with one face at its vertex is a
    /// corner.
    CornersOnly,
    /// `FVAR_LINEAR_CORNERS_PLUS1`: as corners-only, and every value of a vertex with more than
    /// two is a corner, both of a vertex with two where either's faces meet at an infinitely
    /// sharp edge.
    CornersPlus1,
    /// `FVAR_LINEAR_CORNERS_PLUS2`: as corners-plus1, and both values of a vertex with two are
    /// corners where either has one face, and the value where a seam ends inside the mesh
    /// (a dart).
    CornersPlus2,
    /// `FVAR_LINEAR_BOUNDARIES`: every value on a seam or the mesh's boundary is a corner
    /// (the channel is linear along them).
    Boundaries,
}

impl UvRule {
    /// Whether the scheme refines the layout (every rule but [`UvRule::Linear`]).
    pub fn is_smooth(self) -> bool {
        self != UvRule::Linear
    }

    /// The corner sharpness each value of a vertex whose layout does not match the mesh's
    /// there (a seam or chart boundary passes, or a seam ends) takes besides what the mesh's
    /// features give it (smooth: none): `values` its values ([`Span`]), `boundary` whether
    /// the vertex is on the mesh's boundary. OpenSubdiv's `allCornersAreSharp`, its one-face
    /// corners and its dependent sharpness of two values, one of whose faces meet at
    /// semi-sharp edges: the other is a corner while they are sharp (`_depSharp`).
    fn sharpens(self, values: &[Span], boundary: bool) -> Vec<Sharpness> {
        use UvRule::*;
        let one = |s: &Span| s.faces == 1;
        let two = values.len() == 2;
        let all = match self {
            Linear | Smooth | CornersOnly => false,
            CornersPlus1 => values.len() > 2 || (two && values.iter().any(|s| s.inf)),
            CornersPlus2 => {
                values.len() > 2
                    || (two && values.iter().any(|s| s.inf || one(s)))
                    || (values.len() == 1 && !boundary)
            }
            Boundaries => true,
        };
        let corners = !matches!(self, Linear | Smooth);
        let dependent = two && matches!(self, CornersPlus1 | CornersPlus2);
        (0..values.len())
            .map(|i| {
                if all || (corners && one(&values[i])) {
                    Sharpness::INFINITE
                } else if dependent && !values[i].semi.is_sharp() {
                    values[1 - i].semi
                } else {
                    Sharpness::SMOOTH
                }
            })
            .collect()
    }
}

/// One value of a vertex: its faces there, and the sharpest edges of the mesh between two of
/// them, infinitely sharp and not.
#[derive(Clone, Copy, Debug, Default)]
struct Span {
    faces: u32,
    inf: bool,
    semi: Sharpness,
}

/// Texture coordinates of a polygon mesh: one value index per corner, parallel to
/// [`PolyMesh::corners`].
#[derive(Clone, Debug, Default, PartialEq)]
pub struct PolyUv {
    /// The values.
    pub values: Vec<[f64; 2]>,
    /// Per face corner, its value.
    pub corners: Vec<u32>,
}

/// Texture coordinates of a quad mesh: one value index per corner, parallel to its faces.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct QuadUv<T = f64> {
    /// The values.
    pub values: Vec<[T; 2]>,
    /// Per face, its corners' values.
    pub faces: Vec<[u32; 4]>,
}

/// Why a channel cannot be refined.
#[derive(Clone, Debug, PartialEq)]
pub enum UvError {
    /// Not one index per corner.
    Corners {
        /// Indices given.
        got: usize,
        /// Corners of the mesh.
        want: usize,
    },
    /// A corner names a value that does not exist.
    NoSuchValue {
        /// The face.
        face: usize,
        /// The index.
        value: u32,
        /// How many values there are.
        values: usize,
    },
    /// The layout (faces over their value indices, whose vertices are the values) is refused
    /// by the topology (after its non-manifold places are separated).
    Layout(TopologyError),
    /// The mesh's features carried onto the layout are refused there.
    Features(FeatureError),
    /// Refining the layout failed.
    Surface(SurfaceError),
}

impl fmt::Display for UvError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            UvError::Corners { got, want } => write!(
                f,
                "{got} texture coordinate indices for {want} face corners"
            ),
            UvError::NoSuchValue {
                face,
                value,
                values,
            } => write!(
                f,
                "face {face} names texture coordinate {value}, but there are {values}"
            ),
            UvError::Layout(e) => write!(
                f,
                "the texture layout (its vertices are the texture coordinates): {e}; the linear \
                 rule takes any layout"
            ),
            UvError::Features(e) => write!(f, "the texture layout's features: {e}"),
            UvError::Surface(e) => write!(f, "the texture layout: {e}"),
        }
    }
}

impl std::error::Error for UvError {}

fn check_indices<'a>(values: usize, faces: impl Iterator<Item = &'a [u32]>) -> Result<(), UvError> {
    for (face, corners) in faces.enumerate() {
        if let Some(&value) = corners.iter().find(|&&i| i as usize >= values) {
            return Err(UvError::NoSuchValue {
                face,
                value,
                values,
            });
        }
    }
    Ok(())
}

/// The mesh's creases, corners and holes on the layout: a crease on every layout edge whose
/// corners sit on the crease's vertices, a corner on every value its vertex's corners use (the
/// mesh's one-face corners under edge-and-corner too), and the corners `rule` adds
/// ([`UvRule::sharpens`]; every value of a fin where the layout does not match the mesh, as
/// OpenSubdiv sharpens the values of a non-manifold vertex: a fin's point, [`Points`], has
/// several values or a seam); the boundary edge-only (seams and chart boundaries are not
/// corners by themselves). The mesh is a 2-manifold (separated).
fn layout_features<'a>(
    faces: impl Iterator<Item = (&'a [u32], &'a [u32])> + Clone,
    features: &Features,
    rule: UvRule,
    points: Points<'_>,
) -> Features {
    let key = |a: u32, b: u32| [a.min(b), a.max(b)];
    let mut edges: HashMap<[u32; 2], Vec<[u32; 2]>> = HashMap::new();
    // Per edge of the mesh (smaller end first), each face's values at its two ends.
    let mut sides: HashMap<[u32; 2], Vec<[u32; 2]>> = HashMap::new();
    let mut at: HashMap<u32, Vec<u32>> = HashMap::new();
    let mut spans: HashMap<(u32, u32), Span> = HashMap::new();
    let mut faces_at: HashMap<u32, u32> = HashMap::new();
    for (pos, uv) in faces {
        let n = pos.len();
        for c in 0..n {
            *faces_at.entry(pos[c]).or_insert(0) += 1;
            spans.entry((pos[c], uv[c])).or_default().faces += 1;
            let d = (c + 1) % n;
            let e = edges.entry(key(pos[c], pos[d])).or_default();
            let k = key(uv[c], uv[d]);
            if !e.contains(&k) {
                e.push(k);
            }
            let ends = match pos[c] < pos[d] {
                true => [uv[c], uv[d]],
                false => [uv[d], uv[c]],
            };
            sides.entry(key(pos[c], pos[d])).or_default().push(ends);
            let v = at.entry(pos[c]).or_default();
            if !v.contains(&uv[c]) {
                v.push(uv[c]);
            }
        }
    }
    // Where the layout does not match the mesh (a seam at the vertex), the mesh's boundary,
    // and the sharpest edges inside each value's faces.
    let sharpness: HashMap<[u32; 2], Sharpness> = (features.creases.iter())
        .map(|&([a, b], s)| (key(a, b), s))
        .collect();
    let mut mismatched: Vec<u32> = (at.iter())
        .filter(|(_, u)| u.len() > 1)
        .map(|(&v, _)| v)
        .collect();
    let mut boundary = std::collections::HashSet::new();
    for (&[a, b], ends) in &sides {
        if ends.len() == 1 {
            boundary.extend([a, b]);
        } else if ends.iter().any(|e| e != &ends[0]) {
            mismatched.extend([a, b]);
        } else {
            let s = sharpness.get(&[a, b]).copied().unwrap_or(Sharpness::SMOOTH);
            for (v, u) in [(a, ends[0][0]), (b, ends[0][1])] {
                let span = spans.get_mut(&(v, u)).expect("a face's corner");
                span.inf |= s.is_infinite();
                if !s.is_infinite() {
                    span.semi = span.semi.max(s);
                }
            }
        }
    }
    // OpenSubdiv makes the mesh's boundary vertices mismatched too where the rule sharpens
    // them (linear boundaries; one-face corners the boundary rule leaves smooth).
    let sharpened = |v: u32| match rule {
        UvRule::Boundaries => true,
        UvRule::CornersOnly | UvRule::CornersPlus1 | UvRule::CornersPlus2 => faces_at[&v] == 1,
        UvRule::Linear | UvRule::Smooth => false,
    };
    mismatched.extend(boundary.iter().copied().filter(|&v| sharpened(v)));
    // A fin's point is mismatched where one of its copies is, or they have several values.
    let mut point_values: HashMap<u32, Vec<u32>> = HashMap::new();
    for (&v, values) in &at {
        point_values.entry(points.of(v)).or_default().extend(values);
    }
    let mismatched_points: std::collections::HashSet<u32> =
        (mismatched.iter()).map(|&v| points.of(v)).collect();
    let mut fins: Vec<u32> = (features.fins.iter().copied())
        .filter(|&v| {
            let p = points.of(v);
            let values = &point_values[&p];
            mismatched_points.contains(&p) || values.iter().any(|&u| u != values[0])
        })
        .collect();
    mismatched.extend(&fins);
    mismatched.sort_unstable();
    mismatched.dedup();
    fins.sort_unstable();
    let mut by_rule = Vec::new();
    for &v in &mismatched {
        let values = &at[&v];
        let span: Vec<Span> = values.iter().map(|&u| spans[&(v, u)]).collect();
        let sharp = match fins.binary_search(&v).is_ok() {
            true => vec![Sharpness::INFINITE; values.len()],
            false => rule.sharpens(&span, boundary.contains(&v)),
        };
        let sharp = values.iter().zip(sharp).filter(|(_, s)| s.is_sharp());
        by_rule.extend(sharp.map(|(&u, s)| ([u, u], s)));
    }
    // Under edge-and-corner a vertex with one face is a corner (OpenSubdiv sharpens it, and
    // with it its values), unless it is a fin.
    let mut corners = features.corners.clone();
    let by_boundary = features.corner_by_boundary();
    let tagged: std::collections::HashSet<u32> = corners.iter().map(|c| c.0).collect();
    let mut one: Vec<u32> = (faces_at.iter())
        .filter(|&(&v, &k)| by_boundary(v, k as usize) && !tagged.contains(&v))
        .map(|(&v, _)| v)
        .collect();
    one.sort_unstable();
    corners.extend(one.into_iter().map(|v| (v, Sharpness::INFINITE)));
    // Several edges or vertices of the mesh (the copies of a non-manifold one) may share a
    // layout edge or value: it takes the sharpest.
    let creases = (features.creases.iter()).flat_map(|&([a, b], s)| {
        let uv = edges.get(&key(a, b)).map_or(&[][..], Vec::as_slice);
        uv.iter().map(move |&e| (e, s))
    });
    let corners = (corners.iter()).flat_map(|&(v, s)| {
        let uv = at.get(&v).map_or(&[][..], Vec::as_slice);
        uv.iter().map(move |&u| ([u, u], s))
    });
    let mut layout_fins: Vec<u32> = (features.fins.iter())
        .flat_map(|v| at.get(v).map_or(&[][..], Vec::as_slice))
        .copied()
        .collect();
    layout_fins.sort_unstable();
    layout_fins.dedup();
    Features {
        boundary: Boundary::EdgeOnly,
        creases: sharpest(creases),
        corners: (sharpest(corners.chain(by_rule)).into_iter())
            .map(|([u, _], s)| (u, s))
            .collect(),
        holes: features.holes.clone(),
        fins: layout_fins,
        triangles: features.triangles,
        creasing: features.creasing,
    }
}

/// One entry per key (in order of first appearance), the sharpest of those given for it.
fn sharpest(entries: impl Iterator<Item = ([u32; 2], Sharpness)>) -> Vec<([u32; 2], Sharpness)> {
    let mut out: Vec<([u32; 2], Sharpness)> = Vec::new();
    let mut at: HashMap<[u32; 2], usize> = HashMap::new();
    for (k, s) in entries {
        match at.get(&k) {
            Some(&i) => out[i].1 = out[i].1.max(s),
            None => {
                at.insert(k, out.len());
                out.push((k, s));
            }
        }
    }
    out
}

/// Quads' corners one after the other.
fn flat_corners(faces: &[[u32; 4]]) -> Vec<u32> {
    faces.iter().flatten().copied().collect()
}

/// Per vertex of a mesh, the point of the file it stands for: the copies of a vertex
/// [`separate`] split share one ([`Weld::points`]); an empty list: each vertex its own.
#[derive(Clone, Copy, Debug, Default)]
pub struct Points<'a>(pub &'a [u32]);

impl Points<'_> {
    fn of(self, v: u32) -> u32 {
        self.0.get(v as usize).copied().unwrap_or(v)
    }
}

/// The layout as a mesh in the plane z = 0: a vertex per point ([`Points`]) and value its
/// corners use there (`vertices` and `corners` parallel), in the order of (value, point), and
/// the corners renumbered to match. A value belongs to a vertex, as in OpenSubdiv's
/// face-varying level (its vertices' "siblings"): one index used at two vertices is two values
/// of the layout, one used by two copies of a separated vertex one.
fn plane(
    values: &[[f64; 2]],
    vertices: &[u32],
    corners: &[u32],
    points: Points<'_>,
) -> (Vec<[f64; 3]>, Vec<u32>) {
    let pair = |(&v, &u): (&u32, &u32)| (u, points.of(v));
    let mut pairs: Vec<(u32, u32)> = vertices.iter().zip(corners).map(pair).collect();
    pairs.sort_unstable();
    pairs.dedup();
    let kept = (pairs.iter())
        .map(|&(u, _)| {
            let [x, y] = values[u as usize];
            [x, y, 0.0]
        })
        .collect();
    let renumbered = (vertices.iter().zip(corners))
        .map(|c| pairs.binary_search(&pair(c)).expect("a pair of the list") as u32)
        .collect();
    (kept, renumbered)
}

impl PolyUv {
    /// Refuses indices that are not one per corner of `mesh`, or name no value.
    pub fn check(&self, mesh: &PolyMesh) -> Result<(), UvError> {
        if self.corners.len() != mesh.corners.len() {
            return Err(UvError::Corners {
                got: self.corners.len(),
                want: mesh.corners.len(),
            });
        }
        let faces = mesh.offsets.windows(2).map(|w| &self.corners[w[0]..w[1]]);
        check_indices(self.values.len(), faces)
    }

    /// The channel of a mesh whose faces are all quads.
    pub fn quads(&self) -> QuadUv {
        QuadUv {
            values: self.values.clone(),
            faces: self
                .corners
                .chunks_exact(4)
                .map(|c| [c[0], c[1], c[2], c[3]])
                .collect(),
        }
    }

    /// The channel after the first Catmull–Clark step of `mesh` (with `features`), quads in
    /// [`catmull_clark`]'s order (per face, per corner: the corner, the point of the edge
    /// after it, the centroid, the point of the edge before). Linear: corner values, edge
    /// midpoints, centroids; smooth: that step on the layout (`layout_features`).
    pub fn split(
        &self,
        mesh: &PolyMesh,
        features: &Features,
        rule: UvRule,
        points: Points<'_>,
    ) -> Result<QuadUv, UvError> {
        self.check(mesh)?;
        let faces = || {
            mesh.offsets
                .windows(2)
                .map(|w| (&mesh.corners[w[0]..w[1]], &self.corners[w[0]..w[1]]))
        };
        if rule.is_smooth() {
            let (positions, corners) = plane(&self.values, &mesh.corners, &self.corners, points);
            let layout = PolyMesh {
                positions,
                offsets: mesh.offsets.clone(),
                corners,
            };
            let renumbered = mesh
                .offsets
                .windows(2)
                .map(|w| (&mesh.corners[w[0]..w[1]], &layout.corners[w[0]..w[1]]));
            let lf = layout_features(renumbered, features, rule, points);
            // A layout that is not a 2-manifold is separated ([`separate`]) and joined after.
            let separated = separate(&layout, &lf).map_err(UvError::Layout)?;
            let (layout, lf) = match &separated {
                Some(s) => (&s.mesh, &s.features),
                None => (&layout, &lf),
            };
            let split = catmull_clark(layout, lf).map_err(|e| match e {
                SplitError::Topology(e) => UvError::Layout(e),
                SplitError::Feature(e) => UvError::Features(e),
            })?;
            let mut quads = split.mesh.clone();
            if let Some(s) = &separated {
                let weld = Weld::after_split(&s.origin, &s.edge_origin, &split);
                let faces = &split.mesh.faces;
                let joined = weld.join(faces, &[], split.mesh.positions.len(), faces);
                quads.positions = joined.values(&split.mesh.positions);
                quads.faces = joined.faces(faces);
            }
            return Ok(QuadUv {
                values: quads.positions.iter().map(|p| [p[0], p[1]]).collect(),
                faces: quads.faces,
            });
        }
        let mut values = self.values.clone();
        let mut midpoints: HashMap<[u32; 2], u32> = HashMap::new();
        let mut quads = Vec::with_capacity(self.corners.len());
        for (_, uv) in faces() {
            let n = uv.len();
            let centroid = uv.iter().fold([0.0; 2], |s, &i| {
                let p = self.values[i as usize];
                [s[0] + p[0] / n as f64, s[1] + p[1] / n as f64]
            });
            let centre = values.len() as u32;
            values.push(centroid);
            let mut mid = |a: u32, b: u32| {
                *midpoints.entry([a.min(b), a.max(b)]).or_insert_with(|| {
                    let (p, q) = (self.values[a as usize], self.values[b as usize]);
                    values.push([(p[0] + q[0]) / 2.0, (p[1] + q[1]) / 2.0]);
                    values.len() as u32 - 1
                })
            };
            for c in 0..n {
                let (prev, next) = (uv[(c + n - 1) % n], uv[(c + 1) % n]);
                let after = mid(uv[c], next);
                let before = mid(prev, uv[c]);
                quads.push([uv[c], after, centre, before]);
            }
        }
        Ok(QuadUv {
            values,
            faces: quads,
        })
    }
}

impl QuadUv {
    /// Refuses indices that are not one per face corner of `mesh`, or name no value.
    pub fn check(&self, mesh: &QuadMesh) -> Result<(), UvError> {
        if self.faces.len() != mesh.faces.len() {
            return Err(UvError::Corners {
                got: 4 * self.faces.len(),
                want: 4 * mesh.faces.len(),
            });
        }
        check_indices(self.values.len(), self.faces.iter().map(|f| &f[..]))
    }
}

/// The texture layout of a quad mesh as a mesh of its own, what the smooth rules refine: its
/// vertices the (point, value) pairs ([`Points`]), its seams and chart boundaries edge-only
/// boundaries, the mesh's features carried onto it by `rule`, its non-manifold places
/// separated ([`separate`]) and joined after refining.
pub struct Layout {
    /// The layout's quads, parallel to the mesh's; its positions are the values (z = 0).
    pub mesh: QuadMesh,
    /// Its connectivity.
    pub topology: Topology,
    /// Its features.
    pub features: Features,
    /// Where it was separated, how to join its refinement again.
    weld: Option<Weld>,
}

impl Layout {
    /// The layout of the channel `uv` of `mesh` (features `features`) refined by the smooth
    /// rule `rule`.
    pub fn new(
        mesh: &QuadMesh,
        features: &Features,
        uv: &QuadUv,
        rule: UvRule,
        points: Points<'_>,
    ) -> Result<Layout, UvError> {
        uv.check(mesh)?;
        let (positions, corners) = plane(
            &uv.values,
            &flat_corners(&mesh.faces),
            &flat_corners(&uv.faces),
            points,
        );
        let layout = QuadMesh {
            positions,
            faces: corners
                .chunks_exact(4)
                .map(|c| [c[0], c[1], c[2], c[3]])
                .collect(),
        };
        let pairs = (mesh.faces.iter())
            .zip(&layout.faces)
            .map(|(p, u)| (&p[..], &u[..]));
        let lf = layout_features(pairs, features, rule, points);
        // A layout that is not a 2-manifold is separated ([`separate`]) and joined after.
        let poly = PolyMesh {
            positions: layout.positions.clone(),
            offsets: (0..=layout.faces.len()).map(|f| 4 * f).collect(),
            corners: flat_corners(&layout.faces),
        };
        let (mesh, features, weld) = match separate(&poly, &lf).map_err(UvError::Layout)? {
            Some(s) => (
                s.mesh.into_quads().expect("quads stay quads"),
                s.features,
                Some(Weld::new(&s.origin, &s.edge_origin)),
            ),
            None => (layout, lf, None),
        };
        let topology = Topology::build(&mesh).map_err(UvError::Layout)?;
        Ok(Layout {
            mesh,
            topology,
            features,
            weld,
        })
    }

    /// The layout refined `steps` times by `scheme`, to its limit surface with `limit`, joined
    /// again where it was separated: the channel's values, faces parallel to the mesh's
    /// refinement ([`crate::patch::subdivide_with`]).
    pub fn refine<S: SurfaceScheme + Sync, T: Real>(
        &self,
        scheme: &S,
        limit: bool,
        steps: usize,
        threads: usize,
    ) -> Result<QuadUv<T>, UvError> {
        let (layout, lt, lf) = (&self.mesh, &self.topology, &self.features);
        let fine = if limit {
            limit_with(scheme, layout, lt, lf, steps, threads)
        } else {
            subdivide_with(scheme, layout, lt, lf, steps, threads).map(|mesh| Refined {
                mesh,
                normals: Vec::new(),
                approximate: Vec::new(),
            })
        }
        .map_err(|e| match e {
            SurfaceError::Features(e) => UvError::Features(e),
            e => UvError::Surface(e),
        })?;
        let fine = match &self.weld {
            Some(w) => w.apply(&layout.faces, &lf.holes, fine),
            None => fine,
        }
        .mesh;
        Ok(QuadUv {
            values: fine.positions.iter().map(|p| [p[0], p[1]]).collect(),
            faces: fine.faces,
        })
    }
}

/// The channel `uv` of the quad mesh `mesh` (topology `topo`, features `features`) refined
/// `steps` times by `rule`, its faces parallel to [`crate::patch::subdivide_with`]'s (holes
/// dropped). With `limit`, the smooth rule takes the values to the layout's limit surface
/// (as [`crate::patch::limit_with`] the positions); the linear rule's values are parameters
/// and do not move.
#[allow(clippy::too_many_arguments)]
pub fn refine_uv<S: SurfaceScheme + Sync, T: Real>(
    scheme: &S,
    mesh: &QuadMesh,
    topo: &Topology,
    features: &Features,
    (uv, points): (&QuadUv, Points<'_>),
    (rule, limit): (UvRule, bool),
    steps: usize,
    threads: usize,
) -> Result<QuadUv<T>, UvError> {
    if rule.is_smooth() {
        let layout = Layout::new(mesh, features, uv, rule, points)?;
        return layout.refine(scheme, limit, steps, threads);
    }
    uv.check(mesh)?;
    linear(scheme, topo, features, uv, steps)
}

/// [`UvRule::Linear`]: bilinear at the knots, one value per (base element, place): a base
/// corner's value index, a point of a base edge by the edge, its two end values and its
/// place from the smaller one, a face's inner point by the face.
fn linear<S: SurfaceScheme, T: Real>(
    scheme: &S,
    topo: &Topology,
    features: &Features,
    uv: &QuadUv,
    steps: usize,
) -> Result<QuadUv<T>, UvError> {
    let t = scheme.tables();
    let word = t.iterate(t.axiom, steps);
    let length = |a: u8| t.lengths.get(a as usize).copied().unwrap_or(1.0);
    let mut knots = vec![0.0];
    for &a in &word {
        knots.push(knots[knots.len() - 1] + length(a));
    }
    let n = word.len() as i64;
    let total = knots[n as usize];
    let holes: std::collections::HashSet<u32> = features.holes.iter().copied().collect();
    let mut index: HashMap<(u8, u32, u32, u32, i64), u32> = HashMap::new();
    let mut values: Vec<[T; 2]> = Vec::new();
    let mut faces = Vec::new();
    for (f, corners) in uv.faces.iter().enumerate() {
        if holes.contains(&(f as u32)) {
            continue;
        }
        let c = corners.map(|i| uv.values[i as usize]);
        let mut value = |x: i64, y: i64| -> u32 {
            let key = match site(x, y, n, n) {
                Site::Corner(k) => (0, corners[k as usize], 0, 0, 0),
                Site::Edge(l, along) => {
                    let (a, b) = (corners[l as usize], corners[(l as usize + 1) % 4]);
                    let e = topo.edge_of(f as u32, l);
                    let forward = topo.from_smaller(f as u32, l);
                    let place = if forward { along } else { n - along };
                    let (a, b) = if forward { (a, b) } else { (b, a) };
                    (1, e, a, b, place)
                }
                Site::Inside(i) => (2, f as u32, 0, 0, i as i64),
            };
            *index.entry(key).or_insert_with(|| {
                let (s, r) = (knots[x as usize] / total, knots[y as usize] / total);
                let w = [(1.0 - s) * (1.0 - r), s * (1.0 - r), s * r, (1.0 - s) * r];
                let p = (0..4).fold([0.0; 2], |p, k| {
                    [p[0] + w[k] * c[k][0], p[1] + w[k] * c[k][1]]
                });
                values.push(p.map(T::from_f64));
                values.len() as u32 - 1
            })
        };
        for y in 0..n {
            for x in 0..n {
                faces.push([
                    value(x, y),
                    value(x + 1, y),
                    value(x + 1, y + 1),
                    value(x, y + 1),
                ]);
            }
        }
    }
    Ok(QuadUv { values, faces })
}

/// [`refine_uv`] as a [`crate::surface::SurfaceVisitor`], for a scheme known only by name (the
/// generated registry's `visit_surface`) as for one at hand.
#[derive(Clone, Copy, Debug)]
pub struct RefineUv<'m> {
    /// The mesh the channel belongs to.
    pub mesh: &'m QuadMesh,
    /// Its topology.
    pub topology: &'m Topology,
    /// Its features.
    pub features: &'m Features,
    /// The channel.
    pub uv: &'m QuadUv,
    /// The points the mesh's vertices stand for ([`Points`]).
    pub points: Points<'m>,
    /// How it is refined, and whether smooth values go to the layout's limit.
    pub rule: (UvRule, bool),
    /// Refinement steps.
    pub steps: usize,
    /// Worker threads (the result does not depend on it).
    pub threads: usize,
}

/// [`Layout::refine`] for a surface scheme known only by name
/// ([`crate::surface::SurfaceVisitor`]).
pub struct RefineLayout<'m> {
    /// The layout.
    pub layout: &'m Layout,
    /// Whether its values go to its limit surface.
    pub limit: bool,
    /// Refinement steps.
    pub steps: usize,
    /// Worker threads (the result does not depend on it).
    pub threads: usize,
}

impl crate::surface::SurfaceVisitor for RefineLayout<'_> {
    type Output = Result<QuadUv, UvError>;
    fn visit<S: SurfaceScheme + Sync>(self, scheme: &S) -> Self::Output {
        (self.layout).refine(scheme, self.limit, self.steps, self.threads)
    }
}

impl crate::surface::SurfaceVisitor for RefineUv<'_> {
    type Output = Result<QuadUv, UvError>;
    fn visit<S: SurfaceScheme + Sync>(self, scheme: &S) -> Self::Output {
        refine_uv(
            scheme,
            self.mesh,
            self.topology,
            self.features,
            (self.uv, self.points),
            self.rule,
            self.steps,
            self.threads,
        )
    }
}
