//! Sharp features of a mesh and how its boundary is refined, with OpenSubdiv's semantics
//! ("Subdivision Surfaces": semi-sharp creases, boundary interpolation rules, holes).
//!
//! A boundary, and an edge that is sharp at a step, is a line of odd symmetry for that step:
//! each side is refined as if the points across it were phantoms 2P − Q (P on the line, Q its
//! mirror image), with mirrored labels. So the line is refined as the scheme's own curve, and
//! a vertex where three or more sharp edges meet (a corner) is interpolated.

/// How long an edge or vertex stays sharp, as OpenSubdiv counts it (`Sdc::Crease`, uniform
/// creasing): a value s in \[0, 10\], 10 (`SHARPNESS_INFINITE`) for ever. At each step a
/// sharpness s > 1 becomes s − 1 and one ≤ 1 becomes 0 (`decrementSharpness`, in `f32` as
/// OpenSubdiv computes it). An edge of sharpness s ≥ 1 at a step is sharp there; one of
/// 0 < s < 1 blends the sharp and the smooth rule, s of the sharp ([`Sharpness::weight`]); a
/// vertex whose rule changes across a step blends its two rules
/// ([`Resolved::transition`]).
#[derive(Clone, Copy, Debug, Default)]
pub struct Sharpness(f32);

impl PartialEq for Sharpness {
    fn eq(&self, other: &Sharpness) -> bool {
        self.0.to_bits() == other.0.to_bits()
    }
}

impl Eq for Sharpness {}

impl std::hash::Hash for Sharpness {
    fn hash<H: std::hash::Hasher>(&self, state: &mut H) {
        self.0.to_bits().hash(state);
    }
}

impl PartialOrd for Sharpness {
    fn partial_cmp(&self, other: &Sharpness) -> Option<std::cmp::Ordering> {
        Some(self.cmp(other))
    }
}

/// Sharpness is never negative or NaN, so its bits order as its values.
impl Ord for Sharpness {
    fn cmp(&self, other: &Sharpness) -> std::cmp::Ordering {
        self.0.to_bits().cmp(&other.0.to_bits())
    }
}

/// Why a sharpness value is refused.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum SharpnessError {
    /// Below zero, or not a number.
    Negative(f64),
}

impl std::fmt::Display for SharpnessError {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            SharpnessError::Negative(s) => write!(f, "sharpness {s} is not ≥ 0"),
        }
    }
}

impl std::error::Error for SharpnessError {}

impl Sharpness {
    /// Not sharp.
    pub const SMOOTH: Sharpness = Sharpness(0.0);
    /// Sharp at every step.
    pub const INFINITE: Sharpness = Sharpness(10.0);

    /// Sharp for `s` steps (10 or more: infinitely).
    pub fn steps(s: u32) -> Sharpness {
        Sharpness(s.min(10) as f32)
    }

    /// A sharpness as files write it (`inf` included): 10 or more is infinitely sharp.
    pub fn from_f64(s: f64) -> Result<Sharpness, SharpnessError> {
        if s.is_nan() || s < 0.0 {
            return Err(SharpnessError::Negative(s));
        }
        Ok(Sharpness((s.min(10.0) as f32).max(0.0)))
    }

    /// The value, in \[0, 10\].
    pub fn value(self) -> f32 {
        self.0
    }

    /// Sharp at the next step (s > 0).
    pub fn is_sharp(self) -> bool {
        self.0 > 0.0
    }

    /// Sharp at every step.
    pub fn is_infinite(self) -> bool {
        self.0 >= 10.0
    }

    /// The sharpness after one step (OpenSubdiv's `decrementSharpness`).
    pub fn decremented(self) -> Sharpness {
        if self.is_infinite() {
            self
        } else if self.0 > 1.0 {
            Sharpness(self.0 - 1.0)
        } else {
            Sharpness::SMOOTH
        }
    }

    /// The sharpness at step `k` (0-based): decremented k times.
    pub fn at(self, k: usize) -> Sharpness {
        let mut s = self;
        for _ in 0..k.min(11) {
            s = s.decremented();
        }
        s
    }

    /// Whether sharp at step `k` (0-based) of the refinement: its vertices count it.
    pub fn sharp_at(self, k: usize) -> bool {
        self.at(k).is_sharp()
    }

    /// How much of the sharp rule an edge of this sharpness takes at a step: 1 from 1 on,
    /// the value itself below (`Scheme::ComputeEdgeVertexMask`), 0 when smooth.
    pub fn weight(self) -> f64 {
        f64::from(self.0.min(1.0))
    }

    /// The number of steps at which it is sharp (none infinite).
    fn sharp_steps(self) -> usize {
        (0..=10).take_while(|&k| self.sharp_at(k)).count()
    }
}

/// How boundary vertices with one face are refined: OpenSubdiv's `VtxBoundaryInterpolation`.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
pub enum Boundary {
    /// Boundary edges are sharp; a vertex with one face is smooth (the boundary curve passes
    /// through it).
    EdgeOnly,
    /// Boundary edges are sharp and a vertex with one face is an interpolated corner (USD's
    /// default).
    #[default]
    EdgeAndCorner,
    /// OpenSubdiv's `VTX_BOUNDARY_NONE`: the faces at a vertex with a boundary edge not tagged
    /// infinitely sharp are holes, the rest refined edge-only. Readers apply it
    /// ([`crate::nonmanifold::separate`]); given to a refiner, it is refined edge-only.
    None,
}

/// How the first Catmull–Clark step of a polygon mesh weighs triangles: OpenSubdiv's
/// `Sdc::Options::TriangleSubdivision`.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
pub enum Triangles {
    /// Catmull–Clark's rule for every face.
    #[default]
    Catmark,
    /// The smooth-triangle rule (`TRI_SUB_SMOOTH`): a smooth edge beside a triangle weighs the
    /// triangle's face point 0.47 instead of 0.25 (`Scheme<CATMARK>::assignSmoothMaskForEdge`).
    Smooth,
}

/// How a sharp edge's children take its sharpness: OpenSubdiv's `Sdc::Options::CreasingMethod`.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
pub enum Creasing {
    /// Each child s − 1 (`CREASE_UNIFORM`, [`Sharpness::decremented`]).
    #[default]
    Uniform,
    /// Each child ¾ of s and ¼ of the mean of the other semi-sharp edges at its end, less 1
    /// (`CREASE_CHAIKIN`, `Crease::SubdivideEdgeSharpnessAtVertex`): the sharpness varies
    /// along an edge after a step, so a mesh takes its steps one at a time, each on the level
    /// before as a base mesh (schemes whose axiom rewrites to two copies of itself, whose
    /// every level is one: `patch::subdivide_with`).
    Chaikin,
}

/// The sharp features of a mesh, named by its vertices and faces (0-based, as OpenSubdiv's
/// shape files write them in OBJ `t` tags).
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Features {
    /// The boundary rule.
    pub boundary: Boundary,
    /// Sharp edges by their endpoints (either order), each edge at most once.
    pub creases: Vec<([u32; 2], Sharpness)>,
    /// Sharp vertices: interpolated corners while sharp.
    pub corners: Vec<(u32, Sharpness)>,
    /// Hole faces: refined like every face (the surface is smooth across them), not written.
    pub holes: Vec<u32>,
    /// Vertices on a non-manifold crease ([`crate::nonmanifold`]): never made corners by the
    /// boundary rule, though separated into fans with one face.
    pub fins: Vec<u32>,
    /// The triangle rule of the first step of a mesh that is not all quads.
    pub triangles: Triangles,
    /// How a sharp edge's children take its sharpness.
    pub creasing: Creasing,
}

impl Features {
    /// Per crease (in `creases`' order), the sharpness of its children at its two ends after
    /// a step, by the creasing method ([`Creasing`]). A boundary edge, infinitely sharp, is
    /// no semi-sharp edge at its ends.
    pub fn children(&self) -> Vec<[Sharpness; 2]> {
        let semi = |s: Sharpness| s.is_sharp() && !s.is_infinite();
        // Per vertex, the sum and count of the semi-sharp creases at it (f32, as OpenSubdiv).
        let mut at: std::collections::HashMap<u32, (f32, u32)> = Default::default();
        if self.creasing == Creasing::Chaikin {
            for &(ends, s) in self.creases.iter().filter(|c| semi(c.1)) {
                for v in ends {
                    let e = at.entry(v).or_default();
                    *e = (e.0 + s.0, e.1 + 1);
                }
            }
        }
        let child = |s: Sharpness, v: u32| match at.get(&v) {
            Some(&(sum, count)) if semi(s) && count > 1 => {
                let others = (sum - s.0) / (count - 1) as f32;
                let c = 0.75 * s.0 + 0.25 * others - 1.0;
                if c > 0.0 {
                    Sharpness(c)
                } else {
                    Sharpness::SMOOTH
                }
            }
            _ => s.decremented(),
        };
        (self.creases.iter())
            .map(|&([a, b], s)| [child(s, a), child(s, b)])
            .collect()
    }

    /// Per edge of a mesh whose edges have sharpness `sharpness`, its children's at its two
    /// ends ([`Features::children`]; s − 1 where no crease names it): `edge(ab)` finds crease
    /// ab's edge and whether a is the end listed first.
    pub fn edge_children(
        &self,
        sharpness: &[Sharpness],
        edge: impl Fn([u32; 2]) -> Option<(usize, bool)>,
    ) -> Vec<[Sharpness; 2]> {
        let mut children: Vec<[Sharpness; 2]> =
            sharpness.iter().map(|s| [s.decremented(); 2]).collect();
        for (&(ab, _), [sa, sb]) in self.creases.iter().zip(self.children()) {
            if let Some((e, forward)) = edge(ab).filter(|&(e, _)| !sharpness[e].is_infinite()) {
                children[e] = if forward { [sa, sb] } else { [sb, sa] };
            }
        }
        children
    }

    /// The steps at which some crease or corner is semi-sharp (sharp, not infinitely), under
    /// the creasing method: the creases' children followed step by step (their edge points
    /// named from `u32::MAX` down), at most 11 (every finite sharpness is below 10 and each
    /// child at most the larger of its edge's and its end's mean, less 1).
    pub fn semi_sharp_steps(&self) -> usize {
        let semi = |s: Sharpness| s.is_sharp() && !s.is_infinite();
        let mut level = Features {
            creases: self.creases.iter().copied().filter(|c| semi(c.1)).collect(),
            corners: self.corners.iter().copied().filter(|c| semi(c.1)).collect(),
            creasing: self.creasing,
            ..Features::default()
        };
        let mut next = u32::MAX;
        for k in 0..=11 {
            if level.creases.is_empty() && level.corners.is_empty() {
                return k;
            }
            // (A semi-sharp edge's children are semi-sharp or smooth; no holes to follow.)
            level = level.stepped(
                |_| {
                    next = next.wrapping_sub(1);
                    next
                },
                |_| 0..0,
            );
        }
        11
    }

    /// These features one step on: each crease ab the edges (a, m) and (m, b), m =
    /// `edge_point(ab)`, with its children's sharpness ([`Features::children`]), each corner
    /// its sharpness less one, what becomes smooth dropped; each hole's children
    /// `children(f)`.
    pub fn stepped(
        &self,
        mut edge_point: impl FnMut([u32; 2]) -> u32,
        children: impl Fn(u32) -> std::ops::Range<u32>,
    ) -> Features {
        Features {
            boundary: self.boundary,
            creases: (self.creases.iter().zip(self.children()))
                .flat_map(|(&([a, b], _), [sa, sb])| {
                    let m = edge_point([a, b]);
                    [([a, m], sa), ([m, b], sb)]
                })
                .filter(|c| c.1.is_sharp())
                .collect(),
            corners: (self.corners.iter())
                .map(|&(v, s)| (v, s.decremented()))
                .filter(|c| c.1.is_sharp())
                .collect(),
            holes: self.holes.iter().flat_map(|&f| children(f)).collect(),
            fins: self.fins.clone(),
            triangles: self.triangles,
            creasing: self.creasing,
        }
    }

    /// No creases, corners or holes, and the given boundary rule.
    pub fn with_boundary(boundary: Boundary) -> Features {
        Features {
            boundary,
            ..Features::default()
        }
    }

    /// The boundary rule's corners: whether vertex v with `faces` faces is an interpolated
    /// corner by it. OpenSubdiv sharpens a vertex with one face under edge-and-corner
    /// (`isSharpenedCorner`), not a vertex separated from a non-manifold crease (a fin).
    pub fn corner_by_boundary(&self) -> impl Fn(u32, usize) -> bool + '_ {
        let on = self.boundary == Boundary::EdgeAndCorner;
        let fins: std::collections::HashSet<u32> = match on {
            true => self.fins.iter().copied().collect(),
            false => Default::default(),
        };
        move |v, faces| on && faces == 1 && !fins.contains(&v)
    }

    /// Whether there are creases, corners or holes (the boundary rule aside).
    pub fn is_empty(&self) -> bool {
        self.creases.is_empty()
            && self.corners.is_empty()
            && self.holes.is_empty()
            && self.fins.is_empty()
    }
}

/// Which list of [`Features`] an entry is in.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum FeatureList {
    /// [`Features::creases`].
    Creases,
    /// [`Features::corners`].
    Corners,
    /// [`Features::holes`].
    Holes,
}

/// A sharp feature that does not fit its mesh ([`Features::validate`]), named by its index in
/// its list, so that a reader can place it at the tag it read it from.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum FeatureError {
    /// Crease `crease` joins two vertices that no face joins by an edge.
    NoSuchEdge {
        /// Index in [`Features::creases`].
        crease: usize,
        /// Its endpoints, as listed.
        edge: [u32; 2],
    },
    /// Corner `corner` names a vertex the mesh does not have.
    NoSuchVertex {
        /// Index in [`Features::corners`].
        corner: usize,
        /// The vertex.
        vertex: u32,
        /// Vertex count of the mesh.
        vertices: usize,
    },
    /// Hole `hole` names a face the mesh does not have.
    NoSuchFace {
        /// Index in [`Features::holes`].
        hole: usize,
        /// The face.
        face: u32,
        /// Face count of the mesh.
        faces: usize,
    },
    /// Two entries of one list name the same edge (either order), vertex or face.
    Repeated {
        /// The list.
        list: FeatureList,
        /// The earlier entry.
        first: usize,
        /// The later entry.
        second: usize,
    },
}

impl std::fmt::Display for FeatureError {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match *self {
            FeatureError::NoSuchEdge { crease, edge } => write!(
                f,
                "crease {crease}: no such edge ({}, {}) in the mesh",
                edge[0], edge[1]
            ),
            FeatureError::NoSuchVertex {
                corner,
                vertex,
                vertices,
            } => write!(
                f,
                "corner {corner}: vertex {vertex} out of range (the mesh has {vertices} vertices)"
            ),
            FeatureError::NoSuchFace { hole, face, faces } => write!(
                f,
                "hole {hole}: face {face} out of range (the mesh has {faces} faces)"
            ),
            FeatureError::Repeated {
                list,
                first,
                second,
            } => {
                let (what, thing) = match list {
                    FeatureList::Creases => ("creases", "edge"),
                    FeatureList::Corners => ("corners", "vertex"),
                    FeatureList::Holes => ("holes", "face"),
                };
                write!(f, "{what} {first} and {second} name the same {thing}")
            }
        }
    }
}

impl std::error::Error for FeatureError {}

/// How a vertex is refined at a step (OpenSubdiv's vertex rules, by the number of edges sharp
/// at that step, boundary edges counted).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum VertexRule {
    /// No sharp edge, or one (a dart): the surface rule.
    Smooth,
    /// Two sharp edges: the scheme's curve rule along them.
    Crease,
    /// Three or more sharp edges, a sharp corner tag, or (edge-and-corner) a boundary vertex
    /// with one face: interpolated.
    Corner,
}

/// What a face's patch holds at the ring point diagonal to one of its corners at a step.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum CornerKind {
    /// A real point: the corner is an ordinary interior vertex with neither face edge sharp.
    Real,
    /// Both face edges at the corner are sharp: the double odd reflection of the face.
    Both,
    /// The face edge toward the previous corner (`true`) or the next (`false`) is sharp and
    /// the sector is two faces: the odd reflection of the neighbour's ring across that line.
    OneSide(bool),
    /// None: an extraordinary configuration, whose corner child is set by its vertex rule.
    Ev,
}

/// Features resolved against a topology: per edge its sharpness (boundary edges infinitely
/// sharp), per vertex its corner tag, per face whether it is a hole.
#[derive(Clone, Debug)]
pub struct Resolved {
    edge: Vec<Sharpness>,
    vertex: Vec<Sharpness>,
    hole: Vec<bool>,
    plain: bool,
    /// Under Chaikin creasing, per edge its children's sharpness at its ends (smaller vertex
    /// first): the sharpness at step 1, which varies along an edge (empty under uniform
    /// creasing, where step k's is [`Sharpness::at`]).
    children: Vec<[Sharpness; 2]>,
    /// Under Chaikin creasing, the steps at which some edge or corner is semi-sharp
    /// ([`Features::semi_sharp_steps`]).
    chaikin_steps: usize,
}

impl Resolved {
    /// Resolves `features` against `topo` ([`Features::validate`] first: errors name the
    /// crease, corner or hole that has no edge, vertex or face in the mesh, or is listed
    /// twice).
    pub fn new(
        topo: &crate::topology::Topology,
        features: &Features,
    ) -> Result<Resolved, FeatureError> {
        features.validate(topo.vertex_count(), topo.face_count(), |[a, b]| {
            topo.edge_between(a, b).is_some()
        })?;
        let mut edge = vec![Sharpness::SMOOTH; topo.edge_count()];
        let mut vertex = vec![Sharpness::SMOOTH; topo.vertex_count()];
        let mut hole = vec![false; topo.face_count()];
        for f in 0..topo.face_count() as u32 {
            for l in 0..4 {
                if topo.is_boundary_edge(f, l) {
                    edge[topo.edge_of(f, l) as usize] = Sharpness::INFINITE;
                }
            }
        }
        for &([a, b], s) in &features.creases {
            if let Some(e) = topo.edge_between(a, b) {
                if !edge[e as usize].is_infinite() {
                    edge[e as usize] = s;
                }
            }
        }
        let children = match features.creasing {
            Creasing::Chaikin => features.edge_children(&edge, |[a, b]| {
                let e = topo.edge_between(a, b)?;
                Some((e as usize, topo.edge_vertices(e)[0] == a))
            }),
            Creasing::Uniform => Vec::new(),
        };
        for &(v, s) in &features.corners {
            vertex[v as usize] = s;
        }
        // A vertex's valence is its faces.
        let corner = features.corner_by_boundary();
        for v in 0..topo.vertex_count() as u32 {
            if corner(v, topo.valence(v)) {
                vertex[v as usize] = Sharpness::INFINITE;
            }
        }
        for &f in &features.holes {
            hole[f as usize] = true;
        }
        let plain = topo.is_closed()
            && edge.iter().all(|s| !s.is_sharp())
            && vertex.iter().all(|s| !s.is_sharp());
        let chaikin_steps = match features.creasing {
            Creasing::Chaikin => features.semi_sharp_steps(),
            Creasing::Uniform => 0,
        };
        Ok(Resolved {
            edge,
            vertex,
            hole,
            plain,
            children,
            chaikin_steps,
        })
    }

    /// No boundary and nothing sharp: every step is the scheme's surface rule (holes aside).
    pub fn is_plain(&self) -> bool {
        self.plain
    }

    /// Whether face f is a hole.
    pub fn is_hole(&self, f: u32) -> bool {
        self.hole[f as usize]
    }

    /// Whether any face is a hole.
    pub fn has_holes(&self) -> bool {
        self.hole.contains(&true)
    }

    /// Whether edge e is sharp at step k.
    pub fn edge_sharp(&self, e: u32, k: usize) -> bool {
        self.edge[e as usize].sharp_at(k)
    }

    /// Whether the sharpness at v changes between steps: a semi-sharp edge at v, or a
    /// semi-sharp corner tag.
    pub fn changes_at(&self, topo: &crate::topology::Topology, v: u32) -> bool {
        let finite = |s: Sharpness| s.is_sharp() && !s.is_infinite();
        finite(self.vertex[v as usize]) || topo.spokes(v).any(|e| finite(self.edge[e as usize]))
    }

    /// The sharp spokes of v at step k: for each edge of its rotation E_0, E_1, … (E_k between
    /// wedges k − 1 and k; at a boundary vertex E_0 and E_n are the boundary edges) whether it
    /// is sharp.
    pub(crate) fn sharp_spokes(
        &self,
        topo: &crate::topology::Topology,
        v: u32,
        k: usize,
    ) -> Vec<bool> {
        match self.child_at(topo, v, k) {
            Some(child) => topo.spokes(v).map(|e| child(e).is_sharp()).collect(),
            None => topo.spokes(v).map(|e| self.edge_sharp(e, k)).collect(),
        }
    }

    /// Under Chaikin creasing at step 1, the sharpness of an edge at v's end ([`Creasing`]).
    fn child_at<'a>(
        &'a self,
        topo: &'a crate::topology::Topology,
        v: u32,
        k: usize,
    ) -> Option<impl Fn(u32) -> Sharpness + 'a> {
        (k == 1 && !self.children.is_empty()).then_some(move |e: u32| {
            self.children[e as usize][usize::from(topo.edge_vertices(e)[0] != v)]
        })
    }

    /// Whether the edges take Chaikin's sharpness ([`Creasing::Chaikin`]): the refiner takes
    /// one step of them.
    pub fn chaikin(&self) -> bool {
        !self.children.is_empty()
    }

    /// Whether an edge or a vertex has a sharpness below 1 at step k: there its rule is a
    /// blend of the sharp and the smooth one.
    pub fn has_fractions(&self, k: usize) -> bool {
        (self.edge.iter().chain(&self.vertex)).any(|s| s.at(k).is_sharp() && s.at(k).value() < 1.0)
    }

    /// These features with every sharpness below 1 at step k made smooth: the smooth side of
    /// that step's blends.
    pub fn without_fractions(&self, k: usize) -> Resolved {
        let whole = |s: &Sharpness| match s.at(k).value() < 1.0 {
            true => Sharpness::SMOOTH,
            false => *s,
        };
        Resolved {
            edge: self.edge.iter().map(whole).collect(),
            vertex: self.vertex.iter().map(whole).collect(),
            hole: self.hole.clone(),
            plain: self.plain,
            children: self.children.clone(),
            chaikin_steps: self.chaikin_steps,
        }
    }

    /// How much of the sharp rule edge e takes at step k ([`Sharpness::weight`]).
    pub fn edge_weight(&self, e: u32, k: usize) -> f64 {
        self.edge[e as usize].at(k).weight()
    }

    /// The spokes of v fully sharp at step k (weight 1), in the order of
    /// [`Resolved::sharp_spokes`]: the lines the corners' diagonals are reflected across.
    fn full_spokes(&self, topo: &crate::topology::Topology, v: u32, k: usize) -> Vec<bool> {
        topo.spokes(v)
            .map(|e| self.edge_weight(e, k) >= 1.0)
            .collect()
    }

    /// Where v's rule at step k is not smooth and differs from its rule at step k + 1 (a
    /// sharpness reaching 0): the rule of step k + 1 and the weight it takes, 1 − p with p
    /// OpenSubdiv's `ComputeFractionalWeightAtVertex` (uniform creasing: the mean of the
    /// sharpness of the vertex, if it becomes smooth, and of its edges of sharpness ≤ 1,
    /// clamped to 1). None where p is 1 (every integer sharpness): the rule of step k alone.
    pub fn transition(
        &self,
        topo: &crate::topology::Topology,
        v: u32,
        k: usize,
    ) -> Option<(VertexRule, f64)> {
        // Only a finite sharpness at v that is sharp at step k can change its rule after it.
        let changing = |s: Sharpness| s.sharp_at(k) && !s.is_infinite();
        if !changing(self.vertex[v as usize])
            && !topo.spokes(v).any(|e| changing(self.edge[e as usize]))
        {
            return None;
        }
        let parent = self.vertex_rule(topo, v, k);
        if parent == VertexRule::Smooth {
            return None;
        }
        let child = self.vertex_rule(topo, v, k + 1);
        if child == parent {
            return None;
        }
        let vertex = self.vertex[v as usize];
        let (mut count, mut sum) = (0u32, 0.0f32);
        if vertex.at(k).is_sharp() && !vertex.at(k + 1).is_sharp() {
            (count, sum) = (1, vertex.at(k).value());
        }
        // Uniform: the edges of sharpness ≤ 1; Chaikin: the sharp edges whose child at v is
        // smooth.
        let at_v = self.child_at(topo, v, k + 1);
        for e in topo.spokes(v) {
            let s = self.edge[e as usize].at(k);
            let ends = match &at_v {
                Some(at_v) => !at_v(e).is_sharp(),
                None => s.value() <= 1.0,
            };
            if s.is_sharp() && ends {
                sum += s.value();
                count += 1;
            }
        }
        let p = if count == 0 {
            0.0
        } else {
            (sum / count as f32).min(1.0)
        };
        (p < 1.0).then(|| (child, 1.0 - f64::from(p)))
    }

    /// The vertex rule of v at step k.
    pub fn vertex_rule(&self, topo: &crate::topology::Topology, v: u32, k: usize) -> VertexRule {
        let sharp = self.sharp_spokes(topo, v, k).iter().filter(|&&s| s).count();
        if self.vertex[v as usize].sharp_at(k) || sharp >= 3 {
            VertexRule::Corner
        } else if sharp == 2 {
            VertexRule::Crease
        } else {
            VertexRule::Smooth
        }
    }

    /// The number of faces of the sector (faces between two sharp edges) that holds wedge w of
    /// v's rotation at step k; the valence when no edge at v is sharp.
    fn sector_len(&self, sharp: &[bool], valence: usize, w: usize) -> usize {
        if !sharp.contains(&true) {
            return valence;
        }
        // Wedge i lies between spokes i and i + 1 (cyclically at an interior vertex; at a
        // boundary vertex the walk stops at the boundary spokes before it could wrap).
        let spoke = |i: isize| sharp[i.rem_euclid(sharp.len() as isize) as usize];
        let w = w as isize;
        let back = (0..valence as isize).take_while(|&j| !spoke(w - j)).count();
        let ahead = (1..=valence as isize)
            .take_while(|&j| !spoke(w + j))
            .count();
        (1 + back + ahead).min(valence)
    }

    /// Whether v's child needs its vertex rule applied after a step k (its patches alone do
    /// not give it, or not exactly): every configuration but a smooth interior vertex of
    /// valence 4 without sharp edges and a crease whose two sectors have two faces each. A
    /// corner is always set, so that it stays exactly where it is (its patches would give it
    /// up to rounding when its sectors have one face each).
    pub fn needs_rule(&self, topo: &crate::topology::Topology, v: u32, k: usize) -> bool {
        let sharp = self.sharp_spokes(topo, v, k);
        let n = topo.valence(v);
        let sectors_of = |len: usize| (0..n).all(|w| self.sector_len(&sharp, n, w) == len);
        if self.transition(topo, v, k).is_some() {
            return true;
        }
        match self.vertex_rule(topo, v, k) {
            VertexRule::Smooth => sharp.contains(&true) || n != 4 || topo.is_boundary(v),
            VertexRule::Crease => !sectors_of(2),
            VertexRule::Corner => true,
        }
    }

    /// The kind of the ring point diagonal to each wedge's face corner, for every wedge of v's
    /// rotation at step k, in its order (the fully sharp spokes read once for all of them: an
    /// edge that blends two rules at step k has a real ring beside it).
    pub fn corner_kinds(
        &self,
        topo: &crate::topology::Topology,
        v: u32,
        k: usize,
    ) -> Vec<CornerKind> {
        let rot = topo.rotation(v);
        let n = rot.len();
        let sharp = self.full_spokes(topo, v, k);
        let interior4 = n == 4 && !topo.is_boundary(v);
        rot.iter()
            .enumerate()
            .map(|(w, wedge)| {
                let (prev, next) = (sharp[w], sharp[(w + 1) % sharp.len()]);
                // Which of the face's local edges is the wedge's previous one: c − 1 when the
                // next edge is c → c + 1.
                let prev_is_minus = wedge.next_is_plus;
                match (prev, next) {
                    (true, true) => CornerKind::Both,
                    (true, false) | (false, true) if self.sector_len(&sharp, n, w) == 2 => {
                        CornerKind::OneSide(prev == prev_is_minus)
                    }
                    (false, false) if interior4 => CornerKind::Real,
                    _ => CornerKind::Ev,
                }
            })
            .collect()
    }

    /// The steps after which nothing changes: the largest finite sharpness.
    pub fn changing_steps(&self) -> usize {
        if self.chaikin() {
            return self.chaikin_steps;
        }
        self.edge
            .iter()
            .chain(&self.vertex)
            .filter(|s| !s.is_infinite())
            .map(|s| s.sharp_steps())
            .max()
            .unwrap_or(0)
    }
}

impl Features {
    /// Checks the features against a mesh of `vertices` vertices and `faces` faces whose
    /// edges are those for which `is_edge([lo, hi])` (endpoints smaller first) holds: every
    /// crease is an edge, every corner a vertex, every hole a face, none listed twice.
    pub fn validate(
        &self,
        vertices: usize,
        faces: usize,
        is_edge: impl Fn([u32; 2]) -> bool,
    ) -> Result<(), FeatureError> {
        let key = |[a, b]: [u32; 2]| [a.min(b), a.max(b)];
        if let Some(crease) = self.creases.iter().position(|&(e, _)| !is_edge(key(e))) {
            let edge = self.creases[crease].0;
            return Err(FeatureError::NoSuchEdge { crease, edge });
        }
        if let Some(corner) = self
            .corners
            .iter()
            .position(|&(v, _)| v as usize >= vertices)
        {
            let vertex = self.corners[corner].0;
            return Err(FeatureError::NoSuchVertex {
                corner,
                vertex,
                vertices,
            });
        }
        if let Some(hole) = self.holes.iter().position(|&f| f as usize >= faces) {
            let face = self.holes[hole];
            return Err(FeatureError::NoSuchFace { hole, face, faces });
        }
        let repeated = |list, keys: &mut dyn Iterator<Item = [u32; 2]>| {
            let mut seen = std::collections::HashMap::new();
            keys.enumerate()
                .try_for_each(|(second, k)| match seen.insert(k, second) {
                    Some(first) => Err(FeatureError::Repeated {
                        list,
                        first,
                        second,
                    }),
                    None => Ok(()),
                })
        };
        repeated(
            FeatureList::Creases,
            &mut self.creases.iter().map(|&(e, _)| key(e)),
        )?;
        repeated(
            FeatureList::Corners,
            &mut self.corners.iter().map(|&(v, _)| [v, 0]),
        )?;
        repeated(FeatureList::Holes, &mut self.holes.iter().map(|&f| [f, 0]))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Chaikin's children (`Crease::SubdivideEdgeSharpnessAtVertex`), worked by hand: at a
    /// vertex of semi-sharp edges 2 and 4, ¾ of each and ¼ of the other, less 1; where an edge
    /// is the only semi-sharp one at its end (or infinitely sharp), s − 1; smooth at 0.
    #[test]
    fn chaikin_children_average_the_semi_sharp_edges_at_each_end() {
        let s = |x: f64| Sharpness::from_f64(x).unwrap();
        let features = Features {
            // 0 –2– 1 –4– 2 –inf– 3, and 1 –0.5– 4.
            creases: vec![
                ([0, 1], s(2.0)),
                ([1, 2], s(4.0)),
                ([2, 3], Sharpness::INFINITE),
                ([1, 4], s(0.5)),
            ],
            creasing: Creasing::Chaikin,
            ..Features::default()
        };
        let children = features.children();
        // At 1 the semi-sharp edges are 2, 4 and 0.5 (sum 6.5, three).
        let at_1 = |e: f32| 0.75 * e + 0.25 * (6.5 - e) / 2.0 - 1.0;
        assert_eq!(children[0], [s(1.0), Sharpness(at_1(2.0))]);
        assert_eq!(children[1], [Sharpness(at_1(4.0)), s(3.0)]);
        assert_eq!(children[2], [Sharpness::INFINITE; 2]);
        // 0.75 · 0.5 + 0.25 · 3 − 1 = 0.125 at 1; alone at 4: smooth.
        assert_eq!(children[3], [Sharpness(at_1(0.5)), Sharpness::SMOOTH]);
        assert_eq!(at_1(0.5), 0.125);
        // Uniform creasing: every child s − 1.
        let uniform = Features {
            creasing: Creasing::Uniform,
            ..features.clone()
        };
        let decremented = uniform.creases.iter().map(|c| [c.1.decremented(); 2]);
        assert!(uniform.children().into_iter().eq(decremented));
        // Semi-sharp for four steps: 4's child at 2 is 3, then 2, then 1.
        assert_eq!(features.semi_sharp_steps(), 4);
    }
}
