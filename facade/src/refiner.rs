//! Refining a mesh at the front door, in OpenSubdiv's two stages: a [`Refiner`] (the scheme, the
//! mesh and named options, as a builder) builds a [`Plan`] once — the mesh checked, its first
//! Catmull–Clark step when it has faces other than quads, its texture layout, whether its limit
//! is available — and the plan refines: positions, limit positions and normals, texture
//! coordinates ([`Refined`], written whole with every channel by [`Refined::write`]).
//!
//! Steps count as the command line counts them: `steps(3)` on a triangle mesh is its
//! Catmull–Clark step and two steps of the scheme.

use crate::error::Error;
use crate::mesh_data::Extras;
use crate::mesh_file::{Checked, Format, Mesh, Parsed};
use crate::scheme::{Scheme, Surface};
use lsubdiv_mesh::facevarying::{Layout, QuadUv, UvRule};
use lsubdiv_mesh::features::Boundary;
use lsubdiv_mesh::nonmanifold::{separate, Joined};
use lsubdiv_mesh::patch::{self, limit_available, limit_with, subdivide_with, Refined as Fine};
use lsubdiv_mesh::polygon::{PolyMesh, SplitPlan};
use lsubdiv_mesh::real::Real;
use lsubdiv_mesh::surface::SurfaceError;
use lsubdiv_mesh::QuadMesh;
use std::path::Path;

/// Whether a plan takes the refined vertices to the limit surface.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum Limit {
    /// The refined control points.
    #[default]
    Off,
    /// The limit surface with normals, or the refusal as the error (a limit asked before the
    /// step from which it is derived, a semi-sharp feature still sharp).
    On,
    /// The limit surface where it is available, else the refined control points and the
    /// reason ([`Refined::limit_refused`]).
    IfAvailable,
}

/// The options of a refinement, each named ([`Refiner`] sets them).
#[derive(Clone, Copy, Debug)]
pub struct Options {
    /// Refinement steps, the first Catmull–Clark step of a mesh with faces other than quads
    /// included (default 1).
    pub steps: usize,
    /// Worker threads (default: the machine's; results do not depend on it).
    pub threads: usize,
    /// The boundary rule, if not the file's (OBJ `t interpolateboundary`) or the default
    /// (edge and corner).
    pub boundary: Option<Boundary>,
    /// How texture coordinates are refined, if not the file's (OBJ `t facevaryinginterpolation`)
    /// or the default (linear).
    pub uv_rule: Option<UvRule>,
    /// Whether texture coordinates, if the mesh has some, are refined (default yes).
    pub uv: bool,
    /// Whether the vertices go to the limit surface.
    pub limit: Limit,
    /// Whether the refined copies of a point where the mesh is not a 2-manifold are joined
    /// again (default yes, as OpenSubdiv keeps the file's vertices), or each fan kept a
    /// 2-manifold of its own.
    pub join: bool,
}

impl Default for Options {
    fn default() -> Options {
        Options {
            steps: 1,
            threads: std::thread::available_parallelism().map_or(1, usize::from),
            boundary: None,
            uv_rule: None,
            uv: true,
            limit: Limit::Off,
            join: true,
        }
    }
}

/// The builder of a [`Plan`]: a scheme, a mesh and named options.
///
/// ```
/// # fn main() -> Result<(), lsubdiv::Error> {
/// let scheme = lsubdiv::Scheme::shipped("fibonacci")?;
/// let obj = "v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nv 0.5 0.5 1\n\
///            f 1 2 5\nf 2 3 5\nf 3 4 5\nf 4 1 5\nf 4 3 2 1\n";
/// let mesh = lsubdiv::Mesh::parse("pyramid.obj", obj.as_bytes().to_vec())?;
/// let plan = lsubdiv::Refiner::new(&scheme, &mesh).steps(4).limit(true).build()?;
/// let fine = plan.refine()?;
/// assert_eq!(fine.normals.as_ref().map(Vec::len), Some(fine.mesh.positions.len()));
/// # Ok(())
/// # }
/// ```
#[derive(Clone, Debug)]
pub struct Refiner<'a> {
    scheme: &'a Scheme,
    mesh: &'a Mesh,
    options: Options,
}

impl<'a> Refiner<'a> {
    /// `mesh` refined by `scheme`, with the default [`Options`].
    pub fn new(scheme: &'a Scheme, mesh: &'a Mesh) -> Refiner<'a> {
        Refiner {
            scheme,
            mesh,
            options: Options::default(),
        }
    }

    /// Refinement steps, counted as the command line counts them (a polygon mesh's first
    /// Catmull–Clark step included).
    pub fn steps(mut self, steps: usize) -> Self {
        self.options.steps = steps;
        self
    }

    /// Worker threads (at least one; results do not depend on it).
    pub fn threads(mut self, threads: usize) -> Self {
        self.options.threads = threads.max(1);
        self
    }

    /// The boundary rule, over the file's.
    pub fn boundary(mut self, boundary: Boundary) -> Self {
        self.options.boundary = Some(boundary);
        self
    }

    /// The rule texture coordinates are refined by, over the file's.
    pub fn uv_rule(mut self, rule: UvRule) -> Self {
        self.options.uv_rule = Some(rule);
        self
    }

    /// Whether texture coordinates are refined (when the mesh has some).
    pub fn uv(mut self, on: bool) -> Self {
        self.options.uv = on;
        self
    }

    /// Whether the vertices go to the limit surface, with normals ([`Limit::On`]).
    pub fn limit(mut self, on: bool) -> Self {
        self.options.limit = if on { Limit::On } else { Limit::Off };
        self
    }

    /// Every option at once.
    pub fn options(mut self, options: Options) -> Self {
        self.options = options;
        self
    }

    /// Checks the mesh (its topology and features, the first step of a polygon mesh, its
    /// texture layout) and the options against the scheme: the plan, or why not.
    pub fn build(self) -> Result<Plan<'a>, Error> {
        let Refiner {
            scheme,
            mesh,
            options,
        } = self;
        let mut parsed = mesh.parsed().clone();
        if let Some(b) = options.boundary {
            parsed.features.boundary = b;
        }
        if let Some(rule) = options.uv_rule {
            parsed.uv_rule = rule;
        }
        let checked = parsed.check(mesh.name()).map_err(Error::File)?;
        let mut plan = Plan::new(scheme, mesh.name(), checked, options)?;
        plan.source = Some(mesh.parsed());
        Ok(plan)
    }
}

/// A refinement derived once: the scheme's surface tables, the checked mesh (its first step
/// taken), the scheme's own steps, the texture layout a smooth rule refines, and whether the
/// limit is available. [`Plan::refine`] refines with it.
pub struct Plan<'s> {
    scheme: Surface<'s>,
    name: String,
    input: Checked,
    /// The scheme's steps: the options' less the first Catmull–Clark step of a polygon mesh.
    steps: usize,
    options: Options,
    /// Whether the vertices go to the limit, and why not where asked only if available.
    limit: bool,
    limit_refused: Option<String>,
    /// The texture layout refined by a smooth rule.
    layout: Option<Layout>,
    /// The mesh as read, for frames of a mesh whose first step is a Catmull–Clark step.
    source: Option<&'s Parsed>,
}

impl std::fmt::Debug for Plan<'_> {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("Plan")
            .field("mesh", &self.name)
            .field("steps", &self.steps)
            .field("options", &self.options)
            .finish_non_exhaustive()
    }
}

impl<'s> Plan<'s> {
    /// The plan of `input` (a mesh read and checked, called `name` in messages) refined by
    /// `scheme` with `options` (whose boundary and texture rules `input` was checked with).
    pub fn new(
        scheme: &'s Scheme,
        name: &str,
        input: Checked,
        options: Options,
    ) -> Result<Plan<'s>, Error> {
        let scheme = scheme.surface()?;
        let steps = Plan::scheme_steps(name, &input, options.steps)?;
        let layout = match (&input.uv, options.uv) {
            (Some(uv), true) if input.uv_rule.is_smooth() => {
                let layout = Layout::new(
                    &input.mesh,
                    &input.features,
                    uv,
                    input.uv_rule,
                    input.points(),
                )
                .map_err(|error| Error::Uv {
                    mesh: name.to_string(),
                    error,
                })?;
                Some(layout)
            }
            _ => None,
        };
        let mut plan = Plan {
            scheme,
            name: name.to_string(),
            input,
            steps,
            options,
            limit: false,
            limit_refused: None,
            layout,
            source: None,
        };
        // Whether the limit is available, before refining: refused, or left out where it is
        // only wanted if available.
        let available = || {
            match limit_available(
                &plan.scheme,
                &plan.input.topology,
                &plan.input.features,
                steps,
            ) {
                Err(SurfaceError::Unsupported(why)) => Err(why),
                // Anything else the refinement itself reports.
                _ => Ok(()),
            }
        };
        (plan.limit, plan.limit_refused) = match options.limit {
            Limit::Off => (false, None),
            Limit::On => {
                available().map_err(|why| Error::NoLimit {
                    mesh: plan.name.clone(),
                    why,
                    note: plan.steps_note(),
                })?;
                (true, None)
            }
            Limit::IfAvailable => match available() {
                Ok(()) => (true, None),
                Err(why) => (false, Some(why)),
            },
        };
        Ok(plan)
    }

    /// The scheme's steps of `steps` on `input` (called `name`): one less where its first step
    /// was a Catmull–Clark step, which it needs.
    pub fn scheme_steps(name: &str, input: &Checked, steps: usize) -> Result<usize, Error> {
        match (input.split, steps) {
            (false, s) => Ok(s),
            (true, 0) => Err(Error::NoSteps {
                mesh: name.to_string(),
            }),
            (true, s) => Ok(s - 1),
        }
    }

    /// How steps count, where the mesh took a Catmull–Clark step first.
    fn steps_note(&self) -> Option<String> {
        self.input.split.then(|| {
            "steps of the scheme: the steps asked count one more, the first Catmull–Clark step"
                .into()
        })
    }

    /// The mesh as checked: its quads (the first step of a polygon mesh), topology, features
    /// and texture coordinates.
    pub fn input(&self) -> &Checked {
        &self.input
    }

    /// The scheme's steps: the options' less the first Catmull–Clark step of a polygon mesh.
    pub fn steps(&self) -> usize {
        self.steps
    }

    /// The texture layout a smooth rule refines, if the plan refines one.
    pub fn layout(&self) -> Option<&Layout> {
        self.layout.as_ref()
    }

    /// The refusal `e` of the refinement, placed at the mesh; the steps explained where the
    /// mesh took a Catmull–Clark step first.
    fn refused(&self, error: SurfaceError) -> Error {
        let note = match error {
            SurfaceError::Unsupported(_) => self.steps_note(),
            _ => None,
        };
        Error::Refine {
            mesh: self.name.clone(),
            error,
            note,
        }
    }

    /// Refines the mesh's positions as read: the refined mesh (on the limit surface with
    /// normals if asked), its texture coordinates if it has some and the plan refines them.
    /// Huge or tiny coordinates are refined scaled to magnitude 1 ([`crate::scale`]).
    pub fn refine(&self) -> Result<Refined, Error> {
        let (m, topology, features) =
            (&self.input.mesh, &self.input.topology, &self.input.features);
        let (steps, threads) = (self.steps, self.options.threads);
        let (rest, positions) = crate::scale::refine_scaled(&self.name, &m.positions, |scaled| {
            let scaled = scaled.map(|positions| QuadMesh {
                positions,
                faces: m.faces.clone(),
            });
            let mesh = scaled.as_ref().unwrap_or(m);
            let fine = if self.limit {
                limit_with(&self.scheme, mesh, topology, features, steps, threads)
            } else {
                subdivide_with(&self.scheme, mesh, topology, features, steps, threads).map(|mesh| {
                    Fine {
                        mesh,
                        normals: Vec::new(),
                        approximate: Vec::new(),
                    }
                })
            };
            // A refusal comes out beside no positions (nothing to scale back).
            Ok(match fine {
                Ok(fine) => (
                    Ok((fine.mesh.faces, fine.normals, fine.approximate)),
                    fine.mesh.positions,
                ),
                Err(e) => (Err(e), Vec::new()),
            })
        })
        .map_err(Error::File)?;
        let (faces, normals, approximate) = rest.map_err(|e| self.refused(e))?;
        // The texture coordinates (which do not scale) by the rule they were read with, to the
        // layout's limit where the positions went to theirs.
        let limit = !normals.is_empty();
        let uv = self.refine_uv(limit)?;
        let fine = Fine {
            mesh: QuadMesh { positions, faces },
            normals,
            approximate,
        };
        // A mesh that was not a 2-manifold: the refined copies of each point joined again.
        let fine = match &self.input.weld {
            Some(weld) if self.options.join => weld.apply(&m.faces, &features.holes, fine),
            _ => fine,
        };
        Ok(Refined {
            normals: limit.then_some(fine.normals),
            mesh: fine.mesh,
            approximate: fine.approximate,
            uv,
            limit_refused: self.limit_refused.clone(),
        })
    }

    /// The texture coordinates (which do not scale), refined by the rule they were read with,
    /// to the layout's limit with `limit`, if the mesh has some and the plan refines them.
    fn refine_uv(&self, limit: bool) -> Result<Option<QuadUv>, Error> {
        let (m, topology, features) =
            (&self.input.mesh, &self.input.topology, &self.input.features);
        let (steps, threads) = (self.steps, self.options.threads);
        let uv_error = |error| Error::Uv {
            mesh: self.name.clone(),
            error,
        };
        Ok(match (&self.input.uv, &self.layout) {
            (_, Some(layout)) => Some(
                layout
                    .refine(&self.scheme, limit, steps, threads)
                    .map_err(uv_error)?,
            ),
            (Some(uv), None) if self.options.uv => {
                let points = self.input.points();
                Some(
                    lsubdiv_mesh::facevarying::refine_uv(
                        &self.scheme,
                        m,
                        topology,
                        features,
                        (uv, points),
                        (self.input.uv_rule, limit),
                        steps,
                        threads,
                    )
                    .map_err(uv_error)?,
                )
            }
            _ => None,
        })
    }

    /// The first step of frames of `source` (the mesh as read), as the check took it
    /// ([`Parsed::check`]): the mesh separated where it is not a 2-manifold, then the step's
    /// plan.
    fn split_lift(&self, source: &Parsed) -> Result<SplitLift, Error> {
        let internal = |e: String| Error::File(lsubdiv_io::Error::internal(None, e));
        let mut features = source.features.clone();
        features.boundary = self.input.features.boundary;
        let separated = separate(&source.mesh, &features).map_err(|e| internal(e.to_string()))?;
        let (mut polygons, features, origin) = match separated {
            Some(s) => (s.mesh, s.features, Some(s.origin)),
            None => (source.mesh.clone(), features, None),
        };
        let plan = SplitPlan::new(&polygons, &features).map_err(|e| internal(format!("{e:?}")))?;
        polygons.positions = Vec::new();
        Ok(SplitLift {
            plan,
            polygons,
            origin,
            vertices: source.mesh.positions.len(),
        })
    }

    /// The plan applied frame after frame ([`Frames`]): new positions of the mesh's vertices,
    /// the same topology, each frame one refinement with what the plan derived kept.
    pub fn frames(&self) -> Result<Frames<'_, 's>, Error> {
        self.frames_in()
    }

    /// [`Plan::frames`] refining into `T`, f64 or f32 (`let frames: Frames<'_, '_, f32> =
    /// plan.frames_in()?`): f32 halves the output's memory and moves faster; the input
    /// positions stay f64.
    pub fn frames_in<T: Real>(&self) -> Result<Frames<'_, 's, T>, Error> {
        let (topology, features) = (&self.input.topology, &self.input.features);
        let refiner = patch::Frames::new(
            &self.scheme,
            topology,
            features,
            self.steps,
            self.options.threads,
        )
        .map_err(|e| self.refused(e))?;
        let lift = match (self.input.split, &self.input.weld, self.source) {
            (true, _, Some(source)) => Lift::Split(Box::new(self.split_lift(source)?)),
            (true, _, None) => {
                return Err(self.refused(SurfaceError::Unsupported(
                    "frames of a mesh with faces other than quads need the mesh as read: \
                     build the plan with `Refiner`"
                        .into(),
                )))
            }
            (false, Some(weld), _) => Lift::Points(weld.points()),
            (false, None, _) => Lift::Same,
        };
        let vertices = match &lift {
            Lift::Split(split) => split.vertices,
            Lift::Points(points) => self.source.map_or_else(
                || points.iter().map(|&p| p as usize + 1).max().unwrap_or(0),
                |s| s.mesh.positions.len(),
            ),
            Lift::Same => self.input.mesh.positions.len(),
        };
        let faces = refiner.faces().to_vec();
        let join = match &self.input.weld {
            Some(weld) if self.options.join => {
                let holes = &features.holes;
                Some(weld.join(&self.input.mesh.faces, holes, refiner.vertices(), &faces))
            }
            _ => None,
        };
        let faces = match &join {
            Some(joined) => joined.faces(&faces),
            None => faces,
        };
        Ok(Frames {
            plan: self,
            refiner,
            lift,
            vertices,
            faces,
            join,
            uv: self.refine_uv(self.limit)?,
        })
    }
}

/// A refined mesh and its channels.
#[derive(Clone, Debug, PartialEq)]
pub struct Refined {
    /// The quads, each vertex refined (or at its limit point).
    pub mesh: QuadMesh,
    /// The unit limit normal of each vertex, on the limit surface.
    pub normals: Option<Vec<[f64; 3]>>,
    /// The refined texture coordinates, faces parallel to the mesh's.
    pub uv: Option<QuadUv>,
    /// On the limit surface, the vertices whose limit normal is not derived in closed form
    /// (`lsubdiv_mesh::patch::Refined::approximate`).
    pub approximate: Vec<u32>,
    /// Why the limit was left out, where it was asked only if available.
    pub limit_refused: Option<String>,
}

impl Refined {
    /// The channels [`crate::obj::write_with`] and [`crate::ply::write_with`] write.
    pub fn extras(&self) -> Extras<'_> {
        Extras {
            normals: self.normals.as_deref(),
            uv: self.uv.as_ref(),
        }
    }

    /// Writes the mesh with its normals and texture coordinates, whole or not at all, streamed:
    /// PLY (ASCII) for a name ending in `.ply`, OBJ otherwise.
    pub fn write(&self, path: impl AsRef<Path>) -> Result<(), Error> {
        let path = path.as_ref();
        match Format::named(path) {
            Format::Ply => crate::ply::write_with(path, &self.mesh, self.extras(), false),
            Format::Obj => crate::obj::write_with(path, &self.mesh, self.extras()),
        }
        .map_err(Error::File)
    }
}

/// Where each vertex the refiner takes comes from in a frame of the mesh's vertices.
enum Lift<'p> {
    /// They are the mesh's vertices.
    Same,
    /// Copies of the mesh's vertices where it is not a 2-manifold: the vertex each stands for.
    Points(&'p [u32]),
    /// The first, Catmull–Clark step of the mesh as read.
    Split(Box<SplitLift>),
}

/// The first, Catmull–Clark step of a frame: the step's plan, made once for the mesh as read
/// (separated where it is not a 2-manifold), and where each of its polygons' vertices comes
/// from.
struct SplitLift {
    plan: SplitPlan,
    /// The polygons the step takes (their connectivity; no positions).
    polygons: PolyMesh,
    /// Each of their vertices' vertex of the mesh as read, where it was separated.
    origin: Option<Vec<u32>>,
    /// The vertices of the mesh as read.
    vertices: usize,
}

/// A [`Plan`] applied frame after frame (OpenSubdiv's primvar refiner on an animation): the
/// refiner, the refined quads, the joins and the texture coordinates are derived once; each
/// [`Frames::refine`] is one refinement (and limit) of new positions.
pub struct Frames<'p, 's, T = f64> {
    plan: &'p Plan<'s>,
    refiner: patch::Frames<'p, Surface<'s>, T>,
    lift: Lift<'p>,
    /// Positions a frame has: the mesh's vertices.
    vertices: usize,
    faces: Vec<[u32; 4]>,
    /// Where the mesh is not a 2-manifold, the refined copies of each point joined again.
    join: Option<Joined>,
    uv: Option<QuadUv>,
}

/// One frame refined: its positions (on the limit surface with normals where the plan takes
/// the limit), faces and texture coordinates being the [`Frames`]'.
#[derive(Clone, Debug, PartialEq)]
pub struct Frame<T = f64> {
    /// The refined positions.
    pub positions: Vec<[T; 3]>,
    /// The unit limit normals, on the limit surface.
    pub normals: Option<Vec<[T; 3]>>,
    /// On the limit surface, the vertices whose limit normal is not derived in closed form.
    pub approximate: Vec<u32>,
}

impl<T: Real> Frames<'_, '_, T> {
    /// The refined quads, the same for every frame.
    pub fn faces(&self) -> &[[u32; 4]] {
        &self.faces
    }

    /// The refined texture coordinates, the same for every frame.
    pub fn uv(&self) -> Option<&QuadUv> {
        self.uv.as_ref()
    }

    /// Refines `positions`, one per vertex of the mesh, in its order: the plan's refinement of
    /// the mesh with these positions, bit for bit.
    pub fn refine(&mut self, positions: &[[f64; 3]]) -> Result<Frame<T>, Error> {
        let plan = self.plan;
        let name = plan.name.as_str();
        if positions.len() != self.vertices {
            return Err(Error::File(lsubdiv_io::Error::in_file(
                name,
                format!(
                    "a frame of {} positions for a mesh of {} vertices",
                    positions.len(),
                    self.vertices
                ),
            )));
        }
        crate::points::finite("vertex", positions).map_err(Error::File)?;
        let lifted: std::borrow::Cow<'_, [[f64; 3]]> = match &self.lift {
            Lift::Same => positions.into(),
            Lift::Points(points) => points.iter().map(|&p| positions[p as usize]).collect(),
            Lift::Split(split) => {
                let polygons: std::borrow::Cow<'_, [[f64; 3]]> = match &split.origin {
                    Some(origin) => origin.iter().map(|&v| positions[v as usize]).collect(),
                    None => positions.into(),
                };
                split.plan.positions(&split.polygons, &polygons).into()
            }
        };
        let (refiner, limit) = (&mut self.refiner, plan.limit);
        let (rest, positions) = crate::scale::refine_scaled(name, &lifted, |scaled| {
            let at = scaled.as_deref().unwrap_or(&lifted);
            // A refusal comes out beside no positions (nothing to scale back).
            Ok(if limit {
                match refiner.limit(at) {
                    Ok(l) => (Ok((Some(l.normals), l.approximate)), l.positions),
                    Err(e) => (Err(e), Vec::new()),
                }
            } else {
                match refiner.refine(at) {
                    Ok(p) => (Ok((None, Vec::new())), p),
                    Err(e) => (Err(e), Vec::new()),
                }
            })
        })
        .map_err(Error::File)?;
        let (normals, approximate) = rest.map_err(|e| plan.refused(e))?;
        Ok(match &self.join {
            None => Frame {
                positions,
                normals,
                approximate,
            },
            Some(joined) => Frame {
                positions: joined.values(&positions),
                normals: normals.as_deref().map(|n| joined.values(n)),
                approximate: joined.vertices(&approximate),
            },
        })
    }

    /// Refines per-vertex values of any dimension D (colours, weights, a blend shape), one per
    /// vertex of the mesh, as [`Frames::refine`] refines positions — the same steps, taken to
    /// the limit where the plan takes the limit — three coordinates at a time: each
    /// coordinate's refinement is linear in that coordinate alone.
    pub fn refine_values<const D: usize>(
        &mut self,
        values: &[[f64; D]],
    ) -> Result<Vec<[T; D]>, Error> {
        let mut refined: Vec<[T; D]> = Vec::new();
        for first in (0..D.max(1)).step_by(3) {
            let coordinate = |v: &[f64; D], i: usize| v.get(first + i).copied().unwrap_or(0.0);
            let three: Vec<[f64; 3]> = (values.iter())
                .map(|v| std::array::from_fn(|i| coordinate(v, i)))
                .collect();
            let frame = self.refine(&three)?;
            refined.resize(frame.positions.len(), [T::default(); D]);
            for (to, from) in refined.iter_mut().zip(&frame.positions) {
                for (i, &x) in from.iter().enumerate().take(D.saturating_sub(first)) {
                    to[first + i] = x;
                }
            }
        }
        Ok(refined)
    }
}
