//! Surface refinement of closed quad meshes by mask diffusion (\[G\] §2.2).
//!
//! Every face stores the label of its edge 0 (corner 0 → 1) and of the edge corner 0 → 3;
//! opposite edges carry the same label in parallel directions, so a face splits into a
//! |π(a)| × |π(b)| grid. Each old vertex scatters its mask quadrant by quadrant, one quadrant per
//! face around it: an ordinary vertex the tensor product of its two 1D masks, an EV the tensor
//! product of the second half of its radial mask with itself and α at the centre. Quadrant
//! entries beyond the vertex's faces walk across face strips; an entry that would pass *through*
//! an EV (along a line or across a corner) has no well-defined target and is dropped — this only
//! happens in steps whose masks are not contained (\[G\] Prop. 4.8, e.g. Binary-Ternary's first
//! step). Afterwards the EV child is divided by α + n·(ring weight) and any other new vertex whose
//! weights do not sum to 1 by its weight sum (the ad hoc generalisation of \[G\] §3.1.2).

pub use lsubdiv_runtime::surface::{SurfaceScheme, SurfaceTables, SurfaceVisitor};

use crate::grid::{along_edge, corner_at, site, Site, TOWARD_NEXT, TOWARD_PREV};
use crate::mesh::QuadMesh;
use crate::stencil::{Scatter, Stencil};
use crate::threads::in_threads;
use crate::topology::{Topology, TopologyError};
use lsubdiv_runtime::curve::CurveTables;
use lsubdiv_runtime::ev::EvError;
use std::collections::HashMap;
use std::fmt;

/// A quad mesh with edge labels (see the module documentation).
#[derive(Clone, Debug, PartialEq)]
pub struct LabelledMesh {
    /// The mesh.
    pub mesh: QuadMesh,
    /// Per face: labels of edge corner 0 → 1 and of edge corner 0 → 3.
    pub labels: Vec<[u8; 2]>,
}

/// What one step did, for checks.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct StepStats {
    /// EV children divided by α + n·(ring weight).
    pub ev_children: usize,
    /// Other new vertices whose weights did not sum to 1 and were normalised.
    pub normalised: usize,
    /// Mask entries dropped because they would pass through an EV.
    pub dropped: usize,
}

/// Why a surface cannot be refined.
#[derive(Clone, Debug, PartialEq)]
pub enum SurfaceError {
    /// The mesh is not a closed 2-manifold quad mesh, or its result would be too large.
    Topology(TopologyError),
    /// The axiom is not a single symbol.
    Axiom,
    /// A vertex's word has no mask in the tables.
    UnknownWord(String),
    /// No α for a valence.
    Ev(EvError),
    /// A crease, corner or hole names something the mesh does not have.
    Features(crate::features::FeatureError),
    /// A combination of scheme and mesh the drivers do not refine (the message says why).
    Unsupported(String),
}

impl fmt::Display for SurfaceError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            SurfaceError::Topology(e) => write!(f, "{e}"),
            SurfaceError::Axiom => write!(f, "surfaces need a one-symbol axiom"),
            SurfaceError::UnknownWord(w) => write!(f, "word {w} has no tabulated mask"),
            SurfaceError::Ev(e) => write!(f, "{e}"),
            SurfaceError::Features(e) => write!(f, "{e}"),
            SurfaceError::Unsupported(m) => write!(f, "{m}"),
        }
    }
}

impl std::error::Error for SurfaceError {}

impl From<TopologyError> for SurfaceError {
    fn from(e: TopologyError) -> Self {
        SurfaceError::Topology(e)
    }
}

impl LabelledMesh {
    /// Every edge labelled with the (one-symbol) axiom.
    pub fn with_axiom(t: &CurveTables<'_>, mesh: QuadMesh) -> Result<LabelledMesh, SurfaceError> {
        let [a] = t.axiom else {
            return Err(SurfaceError::Axiom);
        };
        let labels = vec![[*a, *a]; mesh.faces.len()];
        Ok(LabelledMesh { mesh, labels })
    }
}

/// Refines `steps` times; returns the mesh and per-step statistics.
pub fn refine_surface<S: SurfaceScheme>(
    scheme: &S,
    mesh: &LabelledMesh,
    steps: usize,
) -> Result<(LabelledMesh, Vec<StepStats>), SurfaceError> {
    refine_from(scheme, mesh, None, steps)
}

/// [`refine_surface`] of a mesh whose topology is at hand (`topo`, built from `mesh.mesh`):
/// only the refined levels' topologies are built.
pub fn refine_surface_with<S: SurfaceScheme>(
    scheme: &S,
    mesh: &LabelledMesh,
    topo: &Topology,
    steps: usize,
) -> Result<(LabelledMesh, Vec<StepStats>), SurfaceError> {
    refine_from(scheme, mesh, Some(topo), steps)
}

/// One step of a mesh of topology `topo` and face labels `labels` as a map (\[G\] §2.2): the
/// new level's quads and labels, and its points' weights on the old ones ([`Stencil`]). The
/// vertices `skip` marks are not scattered: the new points their masks reach are wrong, and
/// the caller keeps only the others (the real faces' points of a mesh with ghost layers,
/// `patch::reference`, or the points the patch driver makes by the step's 1D plan away from
/// the EVs, `patch::near`). Up to `threads` workers scatter runs of the old vertices (the
/// same map).
pub(crate) fn step_map<S: SurfaceScheme>(
    scheme: &S,
    labels: &[[u8; 2]],
    topo: &Topology,
    skip: Option<&[bool]>,
    threads: usize,
) -> Result<(StepMap, StepStats), SurfaceError> {
    let t = scheme.tables();
    let lookup = t.word_index();
    let cx = Step {
        t,
        s: scheme.surface(),
        lookup: &lookup,
        labels,
        topo,
        skip,
        threads,
    };
    cx.map()
}

/// Weights one vertex scatters per face corner at it at most: (L − 1) · L, L the longest mask
/// from its child on (the entries past the child along one edge times those from the child
/// along the other; an even degree's mask has no child: the whole of it).
pub(crate) fn weights_per_corner(t: &CurveTables<'_>) -> usize {
    let longest = (0..t.word_count())
        .map(|w| {
            let len = t.mask_range(w).len();
            len.saturating_sub((t.mask_children[w] as usize).min(len))
        })
        .max()
        .unwrap_or(0);
    longest.saturating_sub(1) * longest
}

/// One step of the reference driver as a map: the new points' weights on the old ones, the new
/// quads and their labels.
pub(crate) struct StepMap {
    pub stencil: Stencil,
    pub faces: Vec<[u32; 4]>,
    pub labels: Vec<[u8; 2]>,
}

impl StepMap {
    /// The new level from `old`, the positions of the level the map was built on.
    fn apply(self, old: &[[f64; 3]]) -> LabelledMesh {
        let mut positions = Vec::new();
        self.stencil.apply::<f64>(old, &mut positions);
        LabelledMesh {
            mesh: QuadMesh {
                positions,
                faces: self.faces,
            },
            labels: self.labels,
        }
    }
}

fn refine_from<S: SurfaceScheme>(
    scheme: &S,
    mesh: &LabelledMesh,
    mut topo: Option<&Topology>,
    steps: usize,
) -> Result<(LabelledMesh, Vec<StepStats>), SurfaceError> {
    let mut cur = mesh.clone();
    let mut stats = Vec::with_capacity(steps);
    for _ in 0..steps {
        let built;
        let topo = match topo.take() {
            Some(t) => t,
            None => {
                built = Topology::build(&cur.mesh)?;
                &built
            }
        };
        topo.require_closed()?;
        let (map, st) = step_map(scheme, &cur.labels, topo, None, 1)?;
        cur = map.apply(&cur.mesh.positions);
        stats.push(st);
    }
    Ok((cur, stats))
}

/// One step's context: the old level's face labels and topology.
struct Step<'a> {
    t: CurveTables<'a>,
    s: SurfaceTables<'a>,
    lookup: &'a HashMap<&'a [u8], u32>,
    labels: &'a [[u8; 2]],
    topo: &'a Topology,
    /// The vertices marked are not scattered ([`step_map`]).
    skip: Option<&'a [bool]>,
    /// Workers that scatter.
    threads: usize,
}

/// Old vertices a worker scatters at least: a vertex takes about a microsecond, a scoped
/// thread ~47 µs to start and join on the 2-vCPU VM (`patch/direct.rs`).
const PER_WORKER: usize = 4096;

impl Step<'_> {
    fn sigma(&self, a: u8) -> u8 {
        self.s.sigma[a as usize]
    }

    /// Label of local edge `local` of face f read from corner `local` to corner `local + 1`.
    fn label(&self, f: u32, local: u8) -> u8 {
        let [a, b] = self.labels[f as usize];
        match local {
            0 => a,
            1 => b,
            2 => self.sigma(a),
            _ => self.sigma(b),
        }
    }

    /// Number of sub-edges local edge `local` of face f splits into.
    fn count(&self, f: u32, local: u8) -> i64 {
        self.t.rule(self.label(f, local)).len() as i64
    }

    /// The edge leaving corner c of face f toward c+1 (`plus`) or c−1: (edge id, local index,
    /// label read from corner c).
    fn edge_from(&self, f: u32, c: u8, plus: bool) -> (u32, u8, u8) {
        if plus {
            (self.topo.edge_of(f, c), c, self.label(f, c))
        } else {
            let l = (c + 3) % 4;
            (self.topo.edge_of(f, l), l, self.sigma(self.label(f, l)))
        }
    }

    /// The edges around v in rotation order E_0..E_{n−1}, E_k shared by wedges k−1 and k,
    /// as (edge id, label read from v); at a boundary vertex (of a ghosted mesh) the last
    /// wedge's other edge E_n follows.
    fn spokes(&self, v: u32) -> Vec<(u32, u8)> {
        let rot = self.topo.rotation(v);
        let closing = self.topo.is_boundary(v).then(|| {
            let w = rot[rot.len() - 1];
            let (e, _, l) = self.edge_from(w.face, w.corner, w.next_is_plus);
            (e, l)
        });
        rot.iter()
            .map(|w| {
                let (e, _, l) = self.edge_from(w.face, w.corner, !w.next_is_plus);
                (e, l)
            })
            .chain(closing)
            .collect()
    }

    /// Whether v is an interior vertex of valence 4, through which lines continue straight.
    fn ordinary(&self, v: u32) -> bool {
        self.topo.valence(v) == 4 && !self.topo.is_boundary(v)
    }

    /// The spoke of v straight on from its spoke k ([`Step::spokes`] order), if a line
    /// continues through v there: the opposite one at an ordinary vertex, and the other
    /// boundary edge at a boundary vertex with two faces arrived at along a boundary edge (a
    /// ghosted level's straight boundary, `patch/cut.rs`).
    fn straight_on(&self, v: u32, k: usize) -> Option<usize> {
        if self.ordinary(v) {
            Some((k + 2) % 4)
        } else if self.topo.valence(v) == 2 && self.topo.is_boundary(v) && k != 1 {
            Some(2 - k)
        } else {
            None
        }
    }

    /// `len` labels along the straight line leaving v by its spoke `start` (edge, label read
    /// from v), read outward. At an ordinary vertex the line continues through the opposite
    /// edge ([`Step::straight_on`]); at an EV it continues with the mirrored label (\[G\]
    /// §2.2.2). No EV's spokes are read on the way, so a ray costs the same beside an EV of any
    /// valence.
    fn ray(&self, v: u32, start: (u32, u8), len: usize) -> Vec<u8> {
        let (mut e, mut label) = start;
        let mut at = v;
        let mut out = vec![label];
        while out.len() < len {
            let q = self.topo.other_end(e, at);
            // Spokes are read only where a line may continue (never around an EV).
            let next = (self.ordinary(q) || self.topo.valence(q) == 2).then(|| {
                let qs = self.spokes(q);
                let i = qs.iter().position(|s| s.0 == e);
                let i = i.expect("edge is a spoke of its end");
                self.straight_on(q, i).map(|j| qs[j])
            });
            match next.flatten() {
                Some(spoke) => (e, label) = spoke,
                None => label = self.sigma(label),
            }
            at = q;
            out.push(label);
        }
        out
    }

    /// The (d+1)-word of v along spoke k of its spokes `sp` ([`Step::spokes`]), read outward,
    /// and its mask index.
    fn word(&self, v: u32, sp: &[(u32, u8)], k: usize) -> Result<u32, SurfaceError> {
        let half = self.t.degree.div_ceil(2);
        let ahead = self.ray(v, sp[k], half);
        let behind = match self.straight_on(v, k) {
            Some(j) => self.ray(v, sp[j], half),
            None => ahead.clone(),
        };
        let w: Vec<u8> = behind
            .iter()
            .rev()
            .map(|&s| self.sigma(s))
            .chain(ahead.iter().copied())
            .collect();
        self.lookup
            .get(w.as_slice())
            .copied()
            .ok_or_else(|| SurfaceError::UnknownWord(self.t.word_str(&w)))
    }

    /// The mask of word w from its child on: entry t ≥ 0 is the weight at offset t.
    fn half_mask(&self, w: u32) -> &[f64] {
        let r = self.t.mask_range(w as usize);
        let child = self.t.mask_children[w as usize] as usize;
        &self.t.mask_weights[r][child..]
    }

    /// The grid point at offset (x, y) from corner c of face f, x toward c+1 when `plus` (else
    /// c−1) and y along the other edge, walking across faces; None when the walk would pass
    /// through an EV.
    fn locate(
        &self,
        mut f: u32,
        mut c: u8,
        mut plus: bool,
        mut x: i64,
        mut y: i64,
    ) -> Option<(u32, i64, i64)> {
        loop {
            let xl = if plus { c } else { (c + 3) % 4 };
            let yl = if plus { (c + 3) % 4 } else { c };
            let (p, q) = (self.count(f, xl), self.count(f, yl));
            if x <= p && y <= q {
                let (pf, qf) = (self.count(f, 0), self.count(f, 1));
                let (cx, cy) = corner_at(c, pf, qf);
                let (dx, dy) = if plus {
                    (TOWARD_NEXT[c as usize], TOWARD_PREV[c as usize])
                } else {
                    (TOWARD_PREV[c as usize], TOWARD_NEXT[c as usize])
                };
                let gx = cx + x * dx.0 + y * dy.0;
                let gy = cy + x * dx.1 + y * dy.1;
                return Some((f, gx, gy));
            }
            if x <= p {
                // Cross along y instead: swap the axes.
                plus = !plus;
                std::mem::swap(&mut x, &mut y);
                continue;
            }
            if y > q {
                // Diagonal: only across an ordinary corner is the next face well defined.
                let far = self.topo.vertex(f, (c + 2) % 4);
                if self.topo.valence(far) != 4 {
                    return None;
                }
            }
            // Cross the edge at the end of the x-edge, parallel to y.
            let cp = if plus { (c + 1) % 4 } else { (c + 3) % 4 };
            if y == 0 && self.topo.valence(self.topo.vertex(f, cp)) != 4 {
                return None; // straight through an EV
            }
            let far_local = if plus { cp } else { (cp + 3) % 4 };
            // Closed meshes only (`refine_from` checks), so there is a face across.
            let (g, gl) = self.topo.across(f, far_local)?;
            let vc = self.topo.vertex(f, cp);
            let gc = if self.topo.vertex(g, gl) == vc {
                gl
            } else {
                (gl + 1) % 4
            };
            plus = gc != gl;
            f = g;
            c = gc;
            x -= p;
        }
    }

    fn map(&self) -> Result<(StepMap, StepStats), SurfaceError> {
        let topo = self.topo;
        let nv = topo.vertex_count();
        let nf = topo.face_count();
        // The numbering of [`crate::grid`]: children, edge points, face points.
        let mut edge_len = vec![0i64; topo.edge_count()];
        for f in 0..nf as u32 {
            for l in 0..4 {
                let e = topo.edge_of(f, l) as usize;
                debug_assert!(
                    edge_len[e] == 0 || edge_len[e] == self.count(f, l),
                    "labels agree"
                );
                edge_len[e] = self.count(f, l);
            }
        }
        let mut edge_base = vec![0u32; topo.edge_count()];
        let mut next = nv as u32;
        for (base, len) in edge_base.iter_mut().zip(&edge_len) {
            *base = next;
            next += (len - 1) as u32;
        }
        // Each face's grid, read for every point it gets.
        let mut grids = Vec::with_capacity(nf);
        for f in 0..nf as u32 {
            let (p, q) = (self.count(f, 0), self.count(f, 1));
            grids.push(FaceGrid {
                p,
                q,
                corners: [0, 1, 2, 3].map(|c| topo.vertex(f, c)),
                edges: [0, 1, 2, 3].map(|l| {
                    let e = topo.edge_of(f, l) as usize;
                    (edge_base[e], edge_len[e], topo.from_smaller(f, l))
                }),
                inside: next,
            });
            next += ((p - 1) * (q - 1)) as u32;
        }
        let total = next as usize;
        let index = |f: u32, gx: i64, gy: i64| grids[f as usize].index(gx, gy);

        // The old vertices in runs, one per worker, each scattered in order: together the
        // scatter of them all in order.
        let share = nv.div_ceil(self.threads.clamp(1, nv.div_ceil(PER_WORKER).max(1)));
        let runs = (0..nv as u32).step_by(share.max(1));
        let scattered = in_threads(runs, |from| {
            self.scatter(from..(from + share as u32).min(nv as u32), &index)
        });
        let mut stats = StepStats::default();
        let (mut scatters, mut ev_norm) = (Vec::new(), Vec::new());
        for run in scattered {
            let (scatter, evs, dropped) = run?;
            scatters.push(scatter);
            ev_norm.extend(evs);
            stats.dropped += dropped;
        }
        // Divisors: an EV child's α + n·(ring weight), any other point's weight sum where
        // it is not 1, else 1 (which leaves the sum exactly).
        stats.ev_children = ev_norm.len();
        // (In increasing order of their vertex.)
        let ev_child = |i: usize| {
            let at = ev_norm.binary_search_by_key(&i, |&(v, _)| v as usize);
            at.ok().map(|at| ev_norm[at].1)
        };
        let stencil = Stencil::from_scatter(scatters, total, |i, sum| match ev_child(i) {
            Some(norm) => norm,
            None if (sum - 1.0).abs() > 1e-9 && sum != 0.0 => {
                stats.normalised += 1;
                sum
            }
            None => 1.0,
        });

        // The split: each face becomes a grid of faces labelled by π(a) × π(b).
        let mut faces = Vec::new();
        let mut labels = Vec::new();
        for f in 0..nf as u32 {
            let [a, b] = self.labels[f as usize];
            let (ra, rb) = (self.t.rule(a), self.t.rule(b));
            for (y, &lb) in rb.iter().enumerate() {
                for (x, &la) in ra.iter().enumerate() {
                    let (x, y) = (x as i64, y as i64);
                    faces.push([
                        index(f, x, y),
                        index(f, x + 1, y),
                        index(f, x + 1, y + 1),
                        index(f, x, y + 1),
                    ]);
                    labels.push([la, lb]);
                }
            }
        }
        Ok((
            StepMap {
                stencil,
                faces,
                labels,
            },
            stats,
        ))
    }

    /// The masks of the old vertices `vs` in order (\[G\] §2.2.2), the new point of grid point
    /// (x, y) of face f at `index(f, x, y)`: their weights, each EV's divisor α + n·(ring
    /// weight), and the mask entries dropped (they would pass through an EV).
    #[allow(clippy::type_complexity)]
    fn scatter(
        &self,
        vs: std::ops::Range<u32>,
        index: &(impl Fn(u32, i64, i64) -> u32 + Sync),
    ) -> Result<(Scatter, Vec<(u32, f64)>, usize), SurfaceError> {
        let topo = self.topo;
        // Each vertex its centre and at most `weights_per_corner` per face corner at it: room
        // for them all at once (no regrowth and copy).
        let corners: usize = vs.clone().map(|v| topo.valence(v)).sum();
        let most = vs.len() + corners * weights_per_corner(&self.t);
        let mut scatter = Scatter::with_capacity(vs.len(), most);
        let (mut ev_norm, mut dropped) = (Vec::new(), 0);
        for v in vs {
            if self.skip.is_some_and(|skip| skip[v as usize]) {
                scatter.close();
                continue;
            }
            let n = topo.valence(v);
            // One word per spoke: n at an interior vertex, n + 1 at a boundary one (a chain).
            let sp = self.spokes(v);
            let words = (0..sp.len())
                .map(|k| self.word(v, &sp, k))
                .collect::<Result<Vec<u32>, _>>()?;
            let centre = if n == 4 || topo.is_boundary(v) {
                // A boundary vertex of a ghosted mesh: its child is not kept (a ghost), or set
                // by its rule afterwards (a boundary vertex of the input).
                self.half_mask(words[0])[0] * self.half_mask(words[1])[0]
            } else {
                let alpha = self.alpha(n)?;
                let ring = self.s.ring_weights[words[0] as usize];
                ev_norm.push((v, alpha + n as f64 * ring));
                alpha
            };
            scatter.add(v, centre);
            for (k, w) in topo.rotation(v).iter().enumerate() {
                let mx = self.half_mask(words[k]);
                let my = self.half_mask(words[(k + 1) % words.len()]);
                for (x, wx) in mx.iter().enumerate().skip(1) {
                    for (y, wy) in my.iter().enumerate() {
                        match self.locate(w.face, w.corner, !w.next_is_plus, x as i64, y as i64) {
                            Some((g, gx, gy)) => scatter.add(index(g, gx, gy), wx * wy),
                            None => dropped += 1,
                        }
                    }
                }
            }
            scatter.close();
        }
        Ok((scatter, ev_norm, dropped))
    }

    /// α at valence n: the table, or the same solver beyond it.
    fn alpha(&self, n: usize) -> Result<f64, SurfaceError> {
        match self.s.alpha.get(n.wrapping_sub(3)) {
            Some(&a) => Ok(a),
            None => self.s.ev.alpha(n).map_err(SurfaceError::Ev),
        }
    }
}

/// Where a face's new points go in the new level's numbering ([`crate::grid`]): children,
/// edge points, face points.
struct FaceGrid {
    /// Sides of the face's grid (sub-edges of its local edges 0 and 1).
    p: i64,
    q: i64,
    /// The vertex of each corner (its child keeps its index).
    corners: [u32; 4],
    /// Per local edge: its first point's index, its sub-edges, and whether it runs from
    /// the edge's smaller vertex.
    edges: [(u32, i64, bool); 4],
    /// The first interior point's index (the others follow row by row).
    inside: u32,
}

impl FaceGrid {
    /// The index of grid point (x, y).
    fn index(&self, x: i64, y: i64) -> u32 {
        match site(x, y, self.p, self.q) {
            Site::Corner(c) => self.corners[c as usize],
            Site::Edge(l, t) => {
                let (base, len, forward) = self.edges[l as usize];
                base + along_edge(t, len, forward) as u32
            }
            Site::Inside(i) => self.inside + i as u32,
        }
    }
}
