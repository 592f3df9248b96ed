//! Sharp features of a mesh and how its boundary is refined, with OpenSubdiv's semantics
//! ("Subdivision Surfaces": semi-sharp creases, boundary interpolation rules, holes).
//!
//! A boundary, and an edge that is sharp at a step, is a line of odd symmetry for that step:
//! each side is refined as if the points across it were phantoms 2P − Q (P on the line, Q its
//! mirror image), with mirrored labels. So the line is refined as the scheme's own curve, and
//! a vertex where three or more sharp edges meet (a corner) is interpolated.

/// How long an edge or vertex stays sharp: integer sharpness s keeps it sharp for s steps
/// (OpenSubdiv's uniform rule, sharpness minus one per step); 10 or more is infinitely sharp
/// (`Sdc::Crease::SHARPNESS_INFINITE`). Fractional sharpness is not represented: readers
/// refuse it (see [`Sharpness::from_f64`]).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, PartialOrd, Ord, Hash)]
pub struct Sharpness(u8);

/// Why a sharpness value is refused.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum SharpnessError {
    /// Below zero, or not a number.
    Negative(f64),
    /// Between two integers below 10: OpenSubdiv blends rules there; lsubdiv does not.
    Fractional(f64),
}

impl std::fmt::Display for SharpnessError {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            SharpnessError::Negative(s) => write!(f, "sharpness {s} is not ≥ 0"),
            SharpnessError::Fractional(s) => write!(
                f,
                "sharpness {s} is fractional; only whole steps 0..9 (sharp for that many steps) \
                 and 10 or more (infinitely sharp) are supported"
            ),
        }
    }
}

impl std::error::Error for SharpnessError {}

impl Sharpness {
    /// Not sharp.
    pub const SMOOTH: Sharpness = Sharpness(0);
    /// Sharp at every step.
    pub const INFINITE: Sharpness = Sharpness(10);

    /// Sharp for `s` steps (10 or more: infinitely).
    pub fn steps(s: u32) -> Sharpness {
        Sharpness(s.min(10) as u8)
    }

    /// A sharpness as files write it (`inf` included); fractional values below 10 are refused.
    pub fn from_f64(s: f64) -> Result<Sharpness, SharpnessError> {
        if s.is_nan() || s < 0.0 {
            return Err(SharpnessError::Negative(s));
        }
        if s >= 10.0 {
            return Ok(Sharpness::INFINITE);
        }
        if s.fract() != 0.0 {
            return Err(SharpnessError::Fractional(s));
        }
        Ok(Sharpness(s as u8))
    }

    /// Sharp at the next step.
    pub fn is_sharp(self) -> bool {
        self.0 > 0
    }

    /// Sharp at every step.
    pub fn is_infinite(self) -> bool {
        self == Sharpness::INFINITE
    }

    /// Whether sharp at step `k` (0-based) of the refinement.
    pub fn sharp_at(self, k: usize) -> bool {
        self.is_infinite() || k < usize::from(self.0)
    }

    /// The sharpness of the children after one step.
    pub fn decremented(self) -> Sharpness {
        if self.is_infinite() {
            self
        } else {
            Sharpness(self.0.saturating_sub(1))
        }
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
}

impl Features {
    /// No creases, corners or holes, and the given boundary rule.
    pub fn with_boundary(boundary: Boundary) -> Features {
        Features {
            boundary,
            ..Features::default()
        }
    }

    /// Whether there are creases, corners or holes (the boundary rule aside).
    pub fn is_empty(&self) -> bool {
        self.creases.is_empty() && self.corners.is_empty() && self.holes.is_empty()
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
