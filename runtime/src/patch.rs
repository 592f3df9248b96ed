//! Fast surface refinement by patches (\[G\] §2.2, organised for speed).
//!
//! Every initial edge carries the one-symbol axiom ω, so after s steps every face of the input
//! mesh is an (N+1)×(N+1) grid whose rows and columns are both labelled W_s = π^s(ω), a
//! symmetric word (\[G\] Cor. 4.4). One step of a patch is the tensor product of two 1D
//! refinements: the patch plus a ring of old points gathered from its neighbours is refined
//! along x, transposed, and refined along y. Each pass is a sequence of slab updates
//! `dst += w · src` driven by the 1D masks (`CurveScheme::axpy_mask`, specialised with constant
//! weights in generated code), clipped to the entries that land in the patch. Patches are
//! processed in blocks, interleaved so that a slab spans the whole block. A ring of width one
//! suffices for d = 3: the halo is checked when the 1D plan is built.
//!
//! Every level is stored once per point in its final numbering (`Numbering`: base vertices,
//! edge points, face interiors), so a level costs what its unique points cost and the last step
//! writes the output directly.
//!
//! At an EV corner the diagonal point of the ring does not exist (it is left zero): with contained
//! masks (\[G\] Prop. 4.8) it could only reach the EV child, which is then set from its 1-ring:
//! (α·P + Σ_k (E1·R_k + E2·D_k)) / (α + n(E1 + E2)). Steps whose masks are not yet contained
//! (e.g. Binary-Ternary's first) are run by the reference driver (`surface`) when the mesh has
//! EVs, on the coarse mesh, and lifted into the numbering: one semantics for every path.

use crate::curve::{CurveScheme, CurveTables};
use crate::mesh::QuadMesh;
use crate::real::Real;
use crate::surface::{refine_surface, LabelledMesh, SurfaceError, SurfaceScheme};
use crate::topology::Topology;
use std::collections::HashMap;

/// A refined mesh with positions of scalar type T.
#[derive(Clone, Debug, PartialEq)]
pub struct Refined<T> {
    /// Positions.
    pub positions: Vec<[T; 3]>,
    /// Quads.
    pub faces: Vec<[u32; 4]>,
}

/// Grid offset of corner c of a patch with side N, and unit steps toward corners c+1, c−1.
fn corner_at(c: u8, n: i64) -> (i64, i64) {
    [(0, 0), (n, 0), (n, n), (0, n)][c as usize]
}
const TOWARD_NEXT: [(i64, i64); 4] = [(1, 0), (0, 1), (-1, 0), (0, -1)];
const TOWARD_PREV: [(i64, i64); 4] = [(0, 1), (-1, 0), (0, -1), (1, 0)];

/// The 1D refinement of one extended row (old points x = −1..=N+1) for one step.
struct Plan {
    /// Per old point: its word, the new coordinate of its first mask entry, its entry count.
    points: Vec<(u32, i64, i64)>,
    /// New side N'.
    n_new: i64,
}

impl Plan {
    fn new(
        t: &CurveTables<'_>,
        lookup: &HashMap<&[u8], u32>,
        w: &[u8],
    ) -> Result<Plan, SurfaceError> {
        let d = t.degree as i64;
        let n = w.len() as i64;
        let label = |i: i64| w[i.rem_euclid(n) as usize];
        // Off(x): new knot of old knot x (Off(0) = 0).
        let len = |i: i64| t.rule(label(i)).len() as i64;
        let half = (d + 1) / 2;
        // Off(x) for x = −half−1 ..= n + half + 1, by prefix sums (Off(0) = 0).
        let lo_x = -half - 1;
        let mut prefix = vec![0i64];
        for x in lo_x..n + half + 1 {
            prefix.push(prefix.last().copied().unwrap_or(0) + len(x));
        }
        let zero = prefix[(-lo_x) as usize];
        let off = |x: i64| prefix[(x - lo_x) as usize] - zero;
        let n_new = off(n);
        let mut points = Vec::new();
        let mut sums: HashMap<i64, f64> = HashMap::new();
        for x in -1..=n + 1 {
            let word: Vec<u8> = (x - half..x + half).map(label).collect();
            let wi = *lookup
                .get(word.as_slice())
                .ok_or_else(|| SurfaceError::UnknownWord(t.word_str(&word)))?;
            // The entry j of the mask has its middle knot at new knot Off(x − half) + j + half.
            let base = off(x - half) + half;
            let r = t.mask_range(wi as usize);
            let count = r.len() as i64;
            for (j, wt) in t.mask_weights[r].iter().enumerate() {
                *sums.entry(base + j as i64).or_default() += wt;
            }
            points.push((wi, base, count));
        }
        // The ring of width one must hold every parent of the new points 0..=N'.
        for xn in 0..=n_new {
            let s = sums.get(&xn).copied().unwrap_or(0.0);
            if (s - 1.0).abs() > 1e-9 {
                return Err(SurfaceError::UnknownWord(format!(
                    "(new point {xn} of a patch has parents beyond a ring of width one)"
                )));
            }
        }
        Ok(Plan { points, n_new })
    }

    /// `dst[X'·len ..] = Σ` mask entries of every old slab `src[i·len ..]`, for X' = 0..=N' only
    /// (the entries of the ring's masks that land outside the patch are skipped).
    fn pass<S: CurveScheme, T: Real>(&self, scheme: &S, src: &[T], len: usize, dst: &mut Vec<T>) {
        dst.clear();
        dst.resize((self.n_new + 1) as usize * len, T::default());
        for (i, &(w, base, count)) in self.points.iter().enumerate() {
            let start = (-base).max(0);
            let end = (self.n_new + 1 - base).min(count);
            if start < end {
                let at = (base + start) as usize * len;
                let keep = start as usize..end as usize;
                scheme.axpy_mask(w, keep, &src[i * len..(i + 1) * len], &mut dst[at..]);
            }
        }
    }
}

/// Base-mesh connectivity the patches need: the topology, and per face corner the diagonal
/// corner across an ordinary vertex, packed as face·4 + corner (`u32::MAX`: none, at an EV).
struct Base {
    topo: Topology,
    diagonal: Vec<[u32; 4]>,
    /// Extraordinary vertices.
    evs: Vec<u32>,
}

impl Base {
    fn new(mesh: &QuadMesh) -> Result<Base, SurfaceError> {
        let topo = Topology::build(mesh)?;
        let diagonal = (0..topo.face_count() as u32)
            .map(|f| {
                [0u8, 1, 2, 3].map(|c| {
                    let rot = topo.rotation(topo.vertex(f, c));
                    let i = rot.iter().position(|w| w.face == f && w.corner == c);
                    match i {
                        Some(i) if rot.len() == 4 => {
                            let w = rot[(i + 2) % 4];
                            w.face * 4 + u32::from(w.corner)
                        }
                        _ => u32::MAX,
                    }
                })
            })
            .collect();
        let evs = (0..topo.vertex_count() as u32)
            .filter(|&v| topo.valence(v) != 4)
            .collect();
        Ok(Base {
            topo,
            diagonal,
            evs,
        })
    }

    /// The face across local edge l of face f, its local edge, and whether the parameter runs
    /// backwards there.
    fn across(&self, f: u32, l: u8) -> (u32, u8, bool) {
        let (g, gl) = self.topo.across(f, l);
        (g, gl, self.topo.vertex(f, l) != self.topo.vertex(g, gl))
    }

    /// The diagonal (face, corner) across corner c of face f when that vertex is ordinary.
    fn diagonal(&self, f: u32, c: u8) -> Option<(u32, u8)> {
        let d = self.diagonal[f as usize][c as usize];
        (d != u32::MAX).then_some((d / 4, (d % 4) as u8))
    }
}

/// One level, stored once per point in that level's final numbering ([`Numbering`]).
#[derive(Clone, Copy)]
struct Level<'a, T> {
    num: &'a Numbering,
    data: &'a [[T; 3]],
}

impl<T: Real> Level<'_, T> {
    fn n(&self) -> i64 {
        self.num.n
    }

    fn point(&self, f: u32, x: i64, y: i64) -> &[T; 3] {
        &self.data[self.num.index(f as usize, x, y).0]
    }

    /// Points x = 1..N−1 of interior row y (1 ≤ y < N) of face f.
    fn interior_row(&self, f: u32, y: i64) -> &[[T; 3]] {
        let k = (self.n() - 1) as usize;
        let (first, _) = self.num.index(f as usize, 1, 1);
        let s = first + (y - 1) as usize * k;
        &self.data[s..s + k]
    }

    /// The point `inward` steps into face g from its local edge `gl`, at parameter u along that
    /// edge (from corner gl).
    fn inward(&self, g: u32, gl: u8, u: i64, inward: i64) -> &[T; 3] {
        let n = self.n();
        let (x, y) = match gl {
            0 => (u, inward),
            1 => (n - inward, u),
            2 => (n - u, n - inward),
            _ => (inward, n - u),
        };
        self.point(g, x, y)
    }
}

/// Scratch buffers of one worker.
#[derive(Default)]
struct Scratch<T> {
    ext: Vec<T>,
    a: Vec<T>,
    at: Vec<T>,
    b: Vec<T>,
}

/// Where the points of a patch go in the final numbering: base vertices, then N−1 points per
/// base edge (from its smaller vertex), then (N−1)² per face, row by row.
struct Numbering {
    n: i64,
    nv: usize,
    ne: usize,
    /// Per face and local edge: the edge id, whether its points run from corner l, and whether
    /// this face writes them (the first face of the edge does). Shared by every level.
    edges: std::sync::Arc<[[(u32, bool, bool); 4]]>,
    /// Per face corner: whether this face writes the vertex (its first face does).
    corners: std::sync::Arc<[[bool; 4]]>,
    /// Vertex of each face corner.
    vertex: std::sync::Arc<[[u32; 4]]>,
}

impl Numbering {
    fn new(topo: &Topology, n: i64) -> Numbering {
        let nf = topo.face_count();
        let mut edge_done = vec![false; topo.edge_count()];
        let mut vertex_done = vec![false; topo.vertex_count()];
        let mut edges = Vec::with_capacity(nf);
        let mut corners = Vec::with_capacity(nf);
        let mut vertex = Vec::with_capacity(nf);
        for f in 0..nf as u32 {
            let mut e4 = [(0, false, false); 4];
            let mut c4 = [false; 4];
            let mut v4 = [0; 4];
            for l in 0..4u8 {
                let e = topo.edge_of(f, l);
                let forward = topo.vertex(f, l) == topo.edge_vertices(e)[0];
                e4[l as usize] = (
                    e,
                    forward,
                    !std::mem::replace(&mut edge_done[e as usize], true),
                );
                let v = topo.vertex(f, l);
                v4[l as usize] = v;
                c4[l as usize] = !std::mem::replace(&mut vertex_done[v as usize], true);
            }
            edges.push(e4);
            corners.push(c4);
            vertex.push(v4);
        }
        Numbering {
            n,
            nv: topo.vertex_count(),
            ne: topo.edge_count(),
            edges: edges.into(),
            corners: corners.into(),
            vertex: vertex.into(),
        }
    }

    /// The same mesh's numbering at another N (the ownership tables are shared).
    fn with_n(&self, n: i64) -> Numbering {
        Numbering {
            n,
            nv: self.nv,
            ne: self.ne,
            edges: self.edges.clone(),
            corners: self.corners.clone(),
            vertex: self.vertex.clone(),
        }
    }

    fn len(&self) -> usize {
        let k = (self.n - 1) as usize;
        self.nv + self.ne * k + self.edges.len() * k * k
    }

    /// The index of point (x, y) of face f, and whether face f writes it.
    fn index(&self, f: usize, x: i64, y: i64) -> (usize, bool) {
        let n = self.n;
        let k = (n - 1) as usize;
        let corner = match (x, y) {
            (0, 0) => Some(0),
            (a, 0) if a == n => Some(1),
            (a, b) if a == n && b == n => Some(2),
            (0, b) if b == n => Some(3),
            _ => None,
        };
        if let Some(c) = corner {
            return (self.vertex[f][c] as usize, self.corners[f][c]);
        }
        let edge = |l: usize, t: i64| {
            let (e, forward, owner) = self.edges[f][l];
            let t = if forward { t } else { n - t };
            (self.nv + e as usize * k + (t - 1) as usize, owner)
        };
        match (x, y) {
            (x, 0) => edge(0, x),
            (x, y) if x == n => edge(1, y),
            (x, y) if y == n => edge(2, n - x),
            (0, y) => edge(3, n - y),
            (x, y) => (
                self.nv + self.ne * k + f * k * k + (y - 1) as usize * k + (x - 1) as usize,
                true,
            ),
        }
    }
}

/// The output positions, written by several workers at disjoint indices.
struct SharedOut<T> {
    ptr: *mut [T; 3],
    len: usize,
}

// SAFETY: workers write disjoint indices (each point has exactly one writing face, see
// `Numbering::index`), and the buffer outlives the scoped threads.
unsafe impl<T: Send> Send for SharedOut<T> {}
unsafe impl<T: Send> Sync for SharedOut<T> {}

impl<T: Copy> SharedOut<T> {
    /// Writes points i, i+1, … from `coords` (three values per point).
    ///
    /// # Safety
    /// No other thread reads or writes those indices during the call.
    unsafe fn write_run(&self, i: usize, coords: &[T]) {
        let count = coords.len() / 3;
        assert!(i + count <= self.len, "output indices in range");
        // SAFETY: in range (checked); exclusive to this caller (the function's contract); the
        // destination is `count` consecutive [T; 3] values, laid out as 3·count T values.
        unsafe {
            std::ptr::copy_nonoverlapping(coords.as_ptr(), self.ptr.add(i).cast::<T>(), count * 3)
        };
    }
}

/// Refines one closed quad mesh topology again and again (new positions, same connectivity),
/// reusing every buffer: the analogue of OpenSubdiv's topology refiner + primvar refiner.
pub struct Refiner<'s, S, T> {
    scheme: &'s S,
    /// The base quads (positions come with each `refine`).
    faces: Vec<[u32; 4]>,
    base: Base,
    /// Steps run by the reference driver (masks not contained, EVs present).
    first: usize,
    plans: Vec<Plan>,
    alphas: Vec<f64>,
    /// The numbering of every level: after the reference steps, then after each plan.
    numberings: Vec<Numbering>,
    threads: usize,
    /// Two levels' points (ping-pong); the last refine's output is the one it returns.
    levels: [Vec<[T; 3]>; 2],
    /// Wall time of each step of the last `refine` (the reference steps as one entry).
    level_seconds: Vec<f64>,
    /// One scratch per worker, kept across steps and calls (no fresh pages per step).
    scratch: Vec<Scratch<T>>,
}

impl<'s, S: SurfaceScheme + Sync, T: Real> Refiner<'s, S, T> {
    /// Prepares `steps` steps of `scheme` on `mesh` (every edge labelled by the axiom) with
    /// `threads` workers (results do not depend on it).
    pub fn new(
        scheme: &'s S,
        mesh: &QuadMesh,
        steps: usize,
        threads: usize,
    ) -> Result<Self, SurfaceError> {
        let t = scheme.tables();
        let st = scheme.surface();
        let [omega] = t.axiom else {
            return Err(SurfaceError::Axiom);
        };
        let base = Base::new(mesh)?;
        let lookup: HashMap<&[u8], u32> =
            (0..t.word_count()).map(|i| (t.word(i), i as u32)).collect();
        let first = if base.evs.is_empty() {
            0
        } else {
            st.contained_from.min(steps)
        };
        // Output quads index vertices with u32: refuse a result that would not fit, before
        // building anything. |π^steps(ω)| from symbol counts (counts · M per step).
        let mut counts = vec![0u128; t.symbol_count()];
        counts[*omega as usize] = 1;
        for _ in 0..steps {
            let mut next = vec![0u128; counts.len()];
            for (a, &c) in counts.iter().enumerate() {
                for &b in t.rule(a as u8) {
                    next[b as usize] = next[b as usize].saturating_add(c);
                }
            }
            counts = next;
        }
        let n = counts.iter().fold(0u128, |a, &c| a.saturating_add(c));
        let (nv, nf) = (
            base.topo.vertex_count() as u128,
            base.topo.face_count() as u128,
        );
        let k = n.saturating_sub(1);
        let out_v = nv.saturating_add(nf.saturating_mul(k).saturating_mul(k.saturating_add(2)));
        let out_f = nf.saturating_mul(n).saturating_mul(n);
        if out_v > u128::from(u32::MAX) || out_f > u128::from(u32::MAX) {
            return Err(SurfaceError::Mesh(crate::mesh::MeshError::TooLarge {
                vertices: usize::try_from(out_v).unwrap_or(usize::MAX),
                faces: usize::try_from(out_f).unwrap_or(usize::MAX),
            }));
        }
        let mut word = vec![*omega];
        for _ in 0..first {
            word = t_rewrite(&t, &word);
        }
        let mut plans = Vec::new();
        let mut numberings = vec![Numbering::new(&base.topo, word.len() as i64)];
        for _ in first..steps {
            let plan = Plan::new(&t, &lookup, &word)?;
            numberings.push(numberings[0].with_n(plan.n_new));
            plans.push(plan);
            word = t_rewrite(&t, &word);
        }
        let alphas = base
            .evs
            .iter()
            .map(|&v| {
                let n = base.topo.valence(v);
                match st.alpha.get(n.wrapping_sub(3)) {
                    Some(&a) => Ok(a),
                    None => st.ev.alpha(n).map_err(SurfaceError::Ev),
                }
            })
            .collect::<Result<_, _>>()?;
        Ok(Refiner {
            scheme,
            faces: mesh.faces.clone(),
            base,
            first,
            plans,
            alphas,
            numberings,
            threads: threads.max(1),
            levels: [Vec::new(), Vec::new()],
            level_seconds: Vec::new(),
            scratch: Vec::new(),
        })
    }

    /// Number of output vertices.
    pub fn output_vertices(&self) -> usize {
        self.numberings.last().map_or(0, Numbering::len)
    }

    /// Wall time of each step of the last `refine`, in seconds (steps run by the reference
    /// driver count as one entry).
    pub fn level_seconds(&self) -> &[f64] {
        &self.level_seconds
    }

    /// Refines new positions of the base vertices; returns the output positions.
    pub fn refine(&mut self, positions: &[[f64; 3]]) -> Result<&[[T; 3]], SurfaceError> {
        let t = self.scheme.tables();
        let st = self.scheme.surface();
        let nf = self.faces.len();
        self.level_seconds.clear();
        let clock = std::time::Instant::now();
        if self.first == 0 {
            lift(
                &t,
                &self.faces,
                positions,
                0,
                &self.numberings[0],
                &mut self.levels[0],
            );
        } else {
            let mesh = QuadMesh {
                positions: positions.to_vec(),
                faces: self.faces.clone(),
            };
            let lm = LabelledMesh::with_axiom(&t, mesh)?;
            let (coarse, _) = refine_surface(self.scheme, &lm, self.first)?;
            lift(
                &t,
                &coarse.mesh.faces,
                &coarse.mesh.positions,
                self.first,
                &self.numberings[0],
                &mut self.levels[0],
            );
            self.level_seconds.push(clock.elapsed().as_secs_f64());
        }
        let workers = self.threads.min(nf).max(1);
        let chunk = nf.div_ceil(workers);
        self.scratch.resize_with(workers, Scratch::default);
        let mut cur = 0;
        for (i, plan) in self.plans.iter().enumerate() {
            let clock = std::time::Instant::now();
            let s = self.first + i;
            let ring = st.rings[s.min(st.rings.len() - 1)];
            let [a, b] = &mut self.levels;
            let (old_data, new_data) = if cur == 0 { (&*a, b) } else { (&*b, a) };
            let old = Level {
                num: &self.numberings[i],
                data: old_data,
            };
            let new_num = &self.numberings[i + 1];
            new_data.resize(new_num.len(), [T::default(); 3]);
            let out = SharedOut {
                ptr: new_data.as_mut_ptr(),
                len: new_data.len(),
            };
            let (scheme, base, out) = (self.scheme, &self.base, &out);
            std::thread::scope(|sc| {
                for (k, scratch) in self.scratch.iter_mut().enumerate() {
                    sc.spawn(move || {
                        let bs = block_size(old.n());
                        let (lo, hi) = (k * chunk, ((k + 1) * chunk).min(nf));
                        for b in (lo..hi).step_by(bs) {
                            let faces = b..(b + bs).min(hi);
                            refine_block(scheme, plan, base, old, faces.clone(), scratch);
                            let kk = faces.len();
                            for (j, f) in faces.enumerate() {
                                let rows = |yn| &scratch.b[block_row(plan, kk, j, yn)];
                                scatter(new_num, f, rows, out);
                            }
                        }
                    });
                }
            });
            for (&v, &alpha) in base.evs.iter().zip(&self.alphas) {
                new_data[v as usize] = ev_child(base, old, v, alpha, ring);
            }
            cur = 1 - cur;
            self.level_seconds.push(clock.elapsed().as_secs_f64());
        }
        Ok(&self.levels[cur])
    }

    /// The output quads (every face of the base mesh becomes an N × N grid).
    pub fn faces(&self) -> Vec<[u32; 4]> {
        let num = self.numberings.last().expect("at least one level");
        let n = num.n;
        let mut faces = Vec::with_capacity(self.faces.len() * (n * n) as usize);
        for f in 0..self.faces.len() {
            for y in 0..n {
                for x in 0..n {
                    let i = |x, y| num.index(f, x, y).0 as u32;
                    faces.push([i(x, y), i(x + 1, y), i(x + 1, y + 1), i(x, y + 1)]);
                }
            }
        }
        faces
    }
}

/// Writes the points of face f's final patch (`rows(y)`: row y) that face f owns: interior rows
/// as slices, each owned edge as a run, each owned corner.
fn scatter<'r, T: Real>(
    num: &Numbering,
    f: usize,
    rows: impl Fn(usize) -> &'r [T],
    out: &SharedOut<T>,
) {
    let n = num.n as usize;
    let (first, _) = num.index(f, 1, 1);
    for y in 1..n {
        let row = &rows(y)[3..n * 3];
        // SAFETY: interior points of face f are written by face f only.
        unsafe { out.write_run(first + (y - 1) * (n - 1), row) };
    }
    let point = |x: usize, y: usize| &rows(y)[x * 3..x * 3 + 3];
    for l in 0..4 {
        let (e, forward, owner) = num.edges[f][l];
        if owner {
            let base = num.nv + e as usize * (n - 1);
            for t in 1..n {
                // Point t from corner l along edge l.
                let (x, y) = match l {
                    0 => (t, 0),
                    1 => (n, t),
                    2 => (n - t, n),
                    _ => (0, n - t),
                };
                let i = base + if forward { t - 1 } else { n - t - 1 };
                // SAFETY: face f is the only writer of the points of an edge it owns.
                unsafe { out.write_run(i, point(x, y)) };
            }
        }
        if num.corners[f][l] {
            let (x, y) = [(0, 0), (n, 0), (n, n), (0, n)][l];
            // SAFETY: face f is the only writer of a corner it owns.
            unsafe { out.write_run(num.vertex[f][l] as usize, point(x, y)) };
        }
    }
}

/// Refines a closed quad mesh once: `Refiner::new`, `refine`, `faces`.
pub fn subdivide<S: SurfaceScheme + Sync, T: Real>(
    scheme: &S,
    mesh: &QuadMesh,
    steps: usize,
    threads: usize,
) -> Result<Refined<T>, SurfaceError> {
    let mut r = Refiner::new(scheme, mesh, steps, threads)?;
    let positions = r.refine(&mesh.positions)?.to_vec();
    Ok(Refined {
        positions,
        faces: r.faces(),
    })
}

/// The level of a mesh refined `k` times by the reference driver, in the numbering `num`. Its
/// faces come old face by old face, row by row: each face is tracked by its base face and its
/// offset in that face's grid (W_k × W_k, from corner 0).
fn lift<T: Real>(
    t: &CurveTables<'_>,
    quads: &[[u32; 4]],
    positions: &[[f64; 3]],
    k: usize,
    num: &Numbering,
    data: &mut Vec<[T; 3]>,
) {
    let nf = num.edges.len();
    let mut cells: Vec<(u32, i64, i64, u8, u8)> = (0..nf as u32)
        .map(|f| (f, 0, 0, t.axiom[0], t.axiom[0]))
        .collect();
    let mut word = t.axiom.to_vec();
    for _ in 0..k {
        let mut off = vec![0i64];
        for &a in &word {
            off.push(off.last().copied().unwrap_or(0) + t.rule(a).len() as i64);
        }
        cells = cells
            .iter()
            .flat_map(|&(f, x, y, a, b)| {
                let (ra, rb) = (t.rule(a), t.rule(b));
                let (x0, y0) = (off[x as usize], off[y as usize]);
                rb.iter().enumerate().flat_map(move |(j, &lb)| {
                    ra.iter()
                        .enumerate()
                        .map(move |(i, &la)| (f, x0 + i as i64, y0 + j as i64, la, lb))
                })
            })
            .collect();
        word = t_rewrite(t, &word);
    }
    data.clear();
    data.resize(num.len(), [T::default(); 3]);
    for (cell, quad) in cells.iter().zip(quads) {
        let (f, x, y, _, _) = *cell;
        for (c, (dx, dy)) in [(0, 0), (1, 0), (1, 1), (0, 1)].into_iter().enumerate() {
            let i = num.index(f as usize, x + dx, y + dy).0;
            data[i] = positions[quad[c] as usize].map(T::from_f64);
        }
    }
}

/// π(w) with the tables' rules.
fn t_rewrite(t: &CurveTables<'_>, w: &[u8]) -> Vec<u8> {
    w.iter().flat_map(|&s| t.rule(s).iter().copied()).collect()
}

/// The EV child from the old 1-ring: (α·P + Σ_k (E1·R_k + E2·D_k)) / (α + n(E1 + E2)).
fn ev_child<T: Real>(
    base: &Base,
    level: Level<'_, T>,
    v: u32,
    alpha: f64,
    ring: [f64; 2],
) -> [T; 3] {
    let n = level.n();
    let rot = base.topo.rotation(v);
    let mut acc = [0.0f64; 3];
    let mut add = |p: &[T; 3], w: f64| {
        for (a, x) in acc.iter_mut().zip(p) {
            *a += w * x.to_f64();
        }
    };
    let w0 = rot[0];
    let (cx, cy) = corner_at(w0.corner, n);
    add(level.point(w0.face, cx, cy), alpha);
    for w in rot {
        let (cx, cy) = corner_at(w.corner, n);
        let (nx, ny) = TOWARD_NEXT[w.corner as usize];
        let (px, py) = TOWARD_PREV[w.corner as usize];
        // E_k is the edge shared with the previous wedge: the one not toward `next`.
        let (ex, ey) = if w.next_is_plus { (px, py) } else { (nx, ny) };
        add(level.point(w.face, cx + ex, cy + ey), ring[0]);
        add(level.point(w.face, cx + nx + px, cy + ny + py), ring[1]);
    }
    let norm = alpha + rot.len() as f64 * (ring[0] + ring[1]);
    acc.map(|a| T::from_f64(a / norm))
}

/// A block of patches (faces `faces`): gather each patch with its ring, refine along x,
/// transpose, refine along y. Patches are interleaved so that every slab spans the whole block
/// (long vectors, one dispatch per old point and block). The new patches are left in `sc.b`:
/// row Y' of the j-th patch is `sc.b[row(j, Y')]` (see [`block_row`]).
fn refine_block<S: CurveScheme, T: Real>(
    scheme: &S,
    plan: &Plan,
    base: &Base,
    level: Level<'_, T>,
    faces: std::ops::Range<usize>,
    sc: &mut Scratch<T>,
) {
    const L: usize = 3;
    let n = level.n();
    let k = faces.len();
    let m = (n + 3) as usize; // extended side: x = −1..=N+1
                              // ext[x][face][y]: x-major, then patch, then y; three values each.
    sc.ext.clear();
    sc.ext.resize(m * k * m * L, T::default());
    for (fi, f) in faces.clone().enumerate() {
        let f = f as u32;
        let mut put = |x: i64, y: i64, p: &[T; 3]| {
            let i = ((((x + 1) as usize) * k + fi) * m + (y + 1) as usize) * L;
            sc.ext[i..i + L].copy_from_slice(p);
        };
        // The patch: interior rows as slices, the boundary point by point.
        for y in 1..n {
            for (x, p) in level.interior_row(f, y).iter().enumerate() {
                put(x as i64 + 1, y, p);
            }
        }
        // Corners, then each edge as a run (forward or backward in the numbering).
        let num = level.num;
        let kk = (n - 1) as usize;
        for c in 0..4u8 {
            let (x, y) = corner_at(c, n);
            put(
                x,
                y,
                &level.data[num.vertex[f as usize][c as usize] as usize],
            );
        }
        for l in 0..4u8 {
            let (e, forward, _) = num.edges[f as usize][l as usize];
            let base = num.nv + e as usize * kk;
            let (cx, cy) = corner_at(l, n);
            let (dx, dy) = TOWARD_NEXT[l as usize];
            for t in 1..n {
                let i = base + if forward { t - 1 } else { n - t - 1 } as usize;
                put(cx + t * dx, cy + t * dy, &level.data[i]);
            }
        }
        // The ring along the four edges: local edge l runs from corner l to l+1.
        for l in 0..4u8 {
            let (g, gl, back) = base.across(f, l);
            let (cx, cy) = corner_at(l, n);
            let (dx, dy) = TOWARD_NEXT[l as usize];
            // Outward normal of edge l: the opposite of the step toward corner l−1.
            let (ox, oy) = TOWARD_PREV[l as usize];
            for t in 0..=n {
                let u = if back { n - t } else { t };
                let p = if u == 0 || u == n {
                    level.inward(g, gl, u, 1)
                } else {
                    // Inside g: a row or column of its interior block, next to edge gl.
                    let (first, _) = num.index(g as usize, 1, 1);
                    let (u, k) = (u as usize, kk);
                    let i = match gl {
                        0 => first + u - 1,
                        1 => first + (u - 1) * k + (k - 1),
                        2 => first + (k - 1) * k + (k - u),
                        _ => first + (k - u) * k,
                    };
                    &level.data[i]
                };
                put(cx + t * dx - ox, cy + t * dy - oy, p);
            }
        }
        // Corners: the diagonal point across an ordinary vertex; none at an EV.
        for c in 0..4u8 {
            if let Some((g, gc)) = base.diagonal(f, c) {
                let (cx, cy) = corner_at(c, n);
                let (ax, ay) = TOWARD_NEXT[c as usize];
                let (bx, by) = TOWARD_PREV[c as usize];
                let (gx, gy) = corner_at(gc, n);
                let (hx, hy) = TOWARD_NEXT[gc as usize];
                let (kx, ky) = TOWARD_PREV[gc as usize];
                put(
                    cx - ax - bx,
                    cy - ay - by,
                    level.point(g, gx + hx + kx, gy + hy + ky),
                );
            }
        }
    }
    // Along x: slab x holds column x of every patch.
    plan.pass(scheme, &sc.ext, k * m * L, &mut sc.a);
    // Keep X' = 0..=N' and transpose to at[y][face][X'].
    let side = plan.n_new as usize + 1;
    sc.at.clear();
    sc.at.resize(m * k * side * L, T::default());
    for xn in 0..side {
        for fi in 0..k {
            let src = (xn * k + fi) * m * L;
            for y in 0..m {
                let d = ((y * k + fi) * side + xn) * L;
                sc.at[d..d + L].copy_from_slice(&sc.a[src + y * L..src + y * L + L]);
            }
        }
    }
    // Along y: slab y holds row y of every patch; rows Y' = 0..=N' are the new patches.
    plan.pass(scheme, &sc.at, k * side * L, &mut sc.b);
}

/// The range of `sc.b` holding row Y' of the j-th patch of a block of k.
fn block_row(plan: &Plan, k: usize, j: usize, yn: usize) -> std::ops::Range<usize> {
    let row = (plan.n_new as usize + 1) * 3;
    let s = (yn * k + j) * row;
    s..s + row
}

/// Patches per block: enough to make slabs long, few enough to stay in cache.
fn block_size(n: i64) -> usize {
    let m = (n + 3) as usize;
    (2048 / (m * m)).clamp(1, 64)
}
