//! Fast surface refinement by patches ([G] §2.2, organised for speed).
//!
//! Every initial edge carries the one-symbol axiom ω, so after s steps every face of the input
//! mesh is an (N+1)×(N+1) grid whose rows and columns are both labelled W_s = π^s(ω), a
//! symmetric word ([G] Cor. 4.4). One step of a patch is the tensor product of two 1D
//! refinements: the patch plus a ring of old points gathered from its neighbours is refined
//! along x, transposed, and refined along y. Each pass is a sequence of slab updates
//! `dst += w · src` driven by the 1D masks (`CurveScheme::axpy_mask`, specialised with constant
//! weights in generated code). A ring of width one suffices for d = 3: the halo is checked when
//! the 1D plan is built.
//!
//! At an EV corner the diagonal point of the ring does not exist (it is left zero): with contained
//! masks ([G] Prop. 4.8) it could only reach the EV child, which is then set from its 1-ring:
//! (α·P + Σ_k (E1·R_k + E2·D_k)) / (α + n(E1 + E2)). Steps whose masks are not yet contained
//! (e.g. Binary-Ternary's first) are run by the reference driver (`surface`) when the mesh has
//! EVs, on the coarse mesh, and lifted into patches: one semantics for every path.

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
    /// Per old point: its word and the new coordinate of its first mask entry.
    points: Vec<(u32, i64)>,
    /// Smallest and largest new coordinate any entry reaches.
    lo: i64,
    hi: i64,
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
        let off = |x: i64| -> i64 {
            if x >= 0 {
                (0..x).map(len).sum()
            } else {
                -(x..0).map(len).sum::<i64>()
            }
        };
        let n_new = off(n);
        let half = (d + 1) / 2;
        let mut points = Vec::new();
        let (mut lo, mut hi) = (i64::MAX, i64::MIN);
        let mut sums: HashMap<i64, f64> = HashMap::new();
        for x in -1..=n + 1 {
            let word: Vec<u8> = (x - half..x + half).map(label).collect();
            let wi = *lookup
                .get(word.as_slice())
                .ok_or_else(|| SurfaceError::UnknownWord(t.word_str(&word)))?;
            // The entry j of the mask has its middle knot at new knot Off(x − half) + j + half.
            let base = off(x - half) + half;
            let r = t.mask_range(wi as usize);
            lo = lo.min(base);
            hi = hi.max(base + r.len() as i64 - 1);
            for (j, wt) in t.mask_weights[r].iter().enumerate() {
                *sums.entry(base + j as i64).or_default() += wt;
            }
            points.push((wi, base));
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
        Ok(Plan {
            points,
            lo,
            hi,
            n_new,
        })
    }

    /// `dst[(X' − lo)·len ..] = Σ` mask entries of every old slab `src[i·len ..]`.
    fn pass<S: CurveScheme, T: Real>(&self, scheme: &S, src: &[T], len: usize, dst: &mut Vec<T>) {
        dst.clear();
        dst.resize((self.hi - self.lo + 1) as usize * len, T::default());
        for (i, &(w, base)) in self.points.iter().enumerate() {
            let at = (base - self.lo) as usize * len;
            scheme.axpy_mask(w, &src[i * len..(i + 1) * len], &mut dst[at..]);
        }
    }
}

/// Base-mesh connectivity the patches need.
struct Base {
    topo: Topology,
    /// Per face and local edge: the face across, its local edge, and whether the parameter runs
    /// backwards there.
    across: Vec<[(u32, u8, bool); 4]>,
    /// Per face corner: the diagonal (face, corner) across an ordinary vertex, if any.
    diagonal: Vec<[Option<(u32, u8)>; 4]>,
    /// Extraordinary vertices.
    evs: Vec<u32>,
}

impl Base {
    fn new(mesh: &QuadMesh) -> Result<Base, SurfaceError> {
        let topo = Topology::build(mesh)?;
        let nf = topo.face_count() as u32;
        let mut across = Vec::with_capacity(nf as usize);
        let mut diagonal = Vec::with_capacity(nf as usize);
        for f in 0..nf {
            let mut a = [(0, 0, false); 4];
            let mut dg = [None; 4];
            for l in 0..4u8 {
                let (g, gl) = topo.across(f, l);
                a[l as usize] = (g, gl, topo.vertex(f, l) != topo.vertex(g, gl));
                let v = topo.vertex(f, l);
                let rot = topo.rotation(v);
                if rot.len() == 4 {
                    let i = rot
                        .iter()
                        .position(|w| w.face == f && w.corner == l)
                        .expect("a face is in the rotation of its corners");
                    let w = rot[(i + 2) % 4];
                    dg[l as usize] = Some((w.face, w.corner));
                }
            }
            across.push(a);
            diagonal.push(dg);
        }
        let evs = (0..topo.vertex_count() as u32)
            .filter(|&v| topo.valence(v) != 4)
            .collect();
        Ok(Base {
            topo,
            across,
            diagonal,
            evs,
        })
    }
}

/// One level of patches: face f's grid point (x, y) is at `data[((f·(N+1) + y)·(N+1) + x)·3 ..]`.
struct Level<T> {
    n: i64,
    data: Vec<T>,
}

impl<T: Real> Level<T> {
    fn side(&self) -> usize {
        self.n as usize + 1
    }

    fn point(&self, f: u32, x: i64, y: i64) -> &[T] {
        let s = self.side();
        let i = ((f as usize * s + y as usize) * s + x as usize) * 3;
        &self.data[i..i + 3]
    }

    /// The point `inward` steps into face g from its local edge `gl`, at parameter u along that
    /// edge (from corner gl).
    fn inward(&self, g: u32, gl: u8, u: i64, inward: i64) -> &[T] {
        let n = self.n;
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

/// Refines a closed quad mesh `steps` times with every edge labelled by the axiom; positions of
/// type T; `threads` workers (results do not depend on it).
pub fn subdivide<S: SurfaceScheme + Sync, T: Real>(
    scheme: &S,
    mesh: &QuadMesh,
    steps: usize,
    threads: usize,
) -> Result<Refined<T>, SurfaceError> {
    let t = scheme.tables();
    let st = scheme.surface();
    let [omega] = t.axiom else {
        return Err(SurfaceError::Axiom);
    };
    let base = Base::new(mesh)?;
    let lookup: HashMap<&[u8], u32> = (0..t.word_count()).map(|i| (t.word(i), i as u32)).collect();
    let nf = mesh.faces.len();
    // Steps before masks are contained go through the reference driver when there are EVs.
    let first = if base.evs.is_empty() {
        0
    } else {
        st.contained_from.min(steps)
    };
    let lm = LabelledMesh::with_axiom(&t, mesh.clone())?;
    let (coarse, _) = refine_surface(scheme, &lm, first)?;
    let mut word = vec![*omega];
    for _ in 0..first {
        word = t_rewrite(&t, &word);
    }
    let mut level = lift(&t, &coarse.mesh, nf, first);
    let alphas: Vec<f64> = base
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
    for s in first..steps {
        let plan = Plan::new(&t, &lookup, &word)?;
        let n_new = plan.n_new;
        let side_new = n_new as usize + 1;
        let mut next = vec![T::default(); nf * side_new * side_new * 3];
        let per_face = side_new * side_new * 3;
        let workers = threads.clamp(1, nf.max(1));
        let chunk = nf.div_ceil(workers);
        std::thread::scope(|sc| {
            for (k, out) in next.chunks_mut(chunk * per_face).enumerate() {
                let (plan, base, level) = (&plan, &base, &level);
                sc.spawn(move || {
                    let mut scratch = Scratch::default();
                    for (i, patch) in out.chunks_mut(per_face).enumerate() {
                        let f = (k * chunk + i) as u32;
                        refine_patch(scheme, plan, base, level, f, &mut scratch, patch);
                    }
                });
            }
        });
        let ring = st.rings[s.min(st.rings.len() - 1)];
        let mut next_level = Level {
            n: n_new,
            data: next,
        };
        for (&v, &alpha) in base.evs.iter().zip(&alphas) {
            let p = ev_child(&base, &level, v, alpha, ring);
            for w in base.topo.rotation(v) {
                let (x, y) = corner_at(w.corner, n_new);
                let side = next_level.side();
                let i = ((w.face as usize * side + y as usize) * side + x as usize) * 3;
                next_level.data[i..i + 3].copy_from_slice(&p);
            }
        }
        level = next_level;
        word = t_rewrite(&t, &word);
    }
    Ok(assemble(&base, &level))
}

/// Patches of the base faces from a mesh refined `k` times by the reference driver, whose faces
/// come old face by old face, row by row: each face is tracked by its base face and its offset in
/// that face's grid (W_k × W_k, from corner 0).
fn lift<T: Real>(t: &CurveTables<'_>, mesh: &QuadMesh, nf: usize, k: usize) -> Level<T> {
    let mut cells: Vec<(u32, i64, i64, u8, u8)> = (0..nf as u32)
        .map(|f| (f, 0, 0, t.axiom[0], t.axiom[0]))
        .collect();
    let mut n = 1i64;
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
        n = *off.last().unwrap_or(&1);
        word = t_rewrite(t, &word);
    }
    let side = n as usize + 1;
    let mut data = vec![T::default(); nf * side * side * 3];
    for (cell, quad) in cells.iter().zip(&mesh.faces) {
        let (f, x, y, _, _) = *cell;
        for (c, (dx, dy)) in [(0, 0), (1, 0), (1, 1), (0, 1)].into_iter().enumerate() {
            let i = ((f as usize * side + (y + dy) as usize) * side + (x + dx) as usize) * 3;
            let p = mesh.positions[quad[c] as usize];
            for (d, v) in data[i..i + 3].iter_mut().zip(p) {
                *d = T::from_f64(v);
            }
        }
    }
    Level { n, data }
}

/// π(w) with the tables' rules.
fn t_rewrite(t: &CurveTables<'_>, w: &[u8]) -> Vec<u8> {
    w.iter().flat_map(|&s| t.rule(s).iter().copied()).collect()
}

/// The EV child from the old 1-ring: (α·P + Σ_k (E1·R_k + E2·D_k)) / (α + n(E1 + E2)).
fn ev_child<T: Real>(base: &Base, level: &Level<T>, v: u32, alpha: f64, ring: [f64; 2]) -> [T; 3] {
    let n = level.n;
    let rot = base.topo.rotation(v);
    let mut acc = [0.0f64; 3];
    let mut add = |p: &[T], w: f64| {
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

/// One patch: gather the ring, refine along x, transpose, refine along y.
fn refine_patch<S: CurveScheme, T: Real>(
    scheme: &S,
    plan: &Plan,
    base: &Base,
    level: &Level<T>,
    f: u32,
    sc: &mut Scratch<T>,
    out: &mut [T],
) {
    const LANES: usize = 3;
    let n = level.n;
    let m = (n + 3) as usize; // extended side: x = −1..=N+1
                              // ext is x-major: ext[(x + 1)·m + (y + 1)], three values each.
    sc.ext.clear();
    sc.ext.resize(m * m * LANES, T::default());
    let mut put = |x: i64, y: i64, p: &[T]| {
        let i = (((x + 1) as usize) * m + (y + 1) as usize) * LANES;
        sc.ext[i..i + LANES].copy_from_slice(p);
    };
    for y in 0..=n {
        for x in 0..=n {
            put(x, y, level.point(f, x, y));
        }
    }
    // The ring along the four edges: local edge l runs from corner l to l+1.
    for l in 0..4u8 {
        let (g, gl, back) = base.across[f as usize][l as usize];
        let (cx, cy) = corner_at(l, n);
        let (dx, dy) = TOWARD_NEXT[l as usize];
        // Outward normal of edge l: the opposite of the step toward corner l−1.
        let (ox, oy) = TOWARD_PREV[l as usize];
        for t in 0..=n {
            let u = if back { n - t } else { t };
            put(
                cx + t * dx - ox,
                cy + t * dy - oy,
                level.inward(g, gl, u, 1),
            );
        }
    }
    // Corners: the diagonal point across an ordinary vertex; none at an EV.
    for c in 0..4u8 {
        if let Some((g, gc)) = base.diagonal[f as usize][c as usize] {
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
    // Along x: slabs are columns (all y).
    let slab = m * LANES;
    plan.pass(scheme, &sc.ext, slab, &mut sc.a);
    // Keep X' = 0..=N' and transpose to y-major.
    let side = plan.n_new as usize + 1;
    let x0 = (-plan.lo) as usize;
    sc.at.clear();
    sc.at.resize(m * side * LANES, T::default());
    for xn in 0..side {
        for y in 0..m {
            let s = ((x0 + xn) * m + y) * LANES;
            let d = (y * side + xn) * LANES;
            sc.at[d..d + LANES].copy_from_slice(&sc.a[s..s + LANES]);
        }
    }
    // Along y: slabs are rows (all X'); rows Y' = 0..=N' are the new patch.
    plan.pass(scheme, &sc.at, side * LANES, &mut sc.b);
    let y0 = (-plan.lo) as usize * side * LANES;
    out.copy_from_slice(&sc.b[y0..y0 + side * side * LANES]);
}

/// The mesh of the last level: base vertices, then N−1 points per base edge (from its smaller
/// vertex), then (N−1)² per face; each shared point taken from one patch.
fn assemble<T: Real>(base: &Base, level: &Level<T>) -> Refined<T> {
    let topo = &base.topo;
    let n = level.n;
    let (nv, ne, nf) = (topo.vertex_count(), topo.edge_count(), topo.face_count());
    let k = (n - 1) as usize;
    let mut positions = vec![[T::default(); 3]; nv + ne * k + nf * k * k];
    let mut faces = Vec::with_capacity(nf * (n * n) as usize);
    let mut seen_edge = vec![false; ne];
    let mut seen_vertex = vec![false; nv];
    let to3 = |p: &[T]| [p[0], p[1], p[2]];
    for f in 0..nf as u32 {
        let index = |x: i64, y: i64| -> u32 {
            let corner = match (x, y) {
                (0, 0) => Some(0),
                (a, 0) if a == n => Some(1),
                (a, b) if a == n && b == n => Some(2),
                (0, b) if b == n => Some(3),
                _ => None,
            };
            if let Some(c) = corner {
                return topo.vertex(f, c);
            }
            let on_edge = |l: u8, t: i64| -> u32 {
                let e = topo.edge_of(f, l);
                let from_low = topo.vertex(f, l) == topo.edge_vertices(e)[0];
                let t = if from_low { t } else { n - t };
                (nv + e as usize * k + (t - 1) as usize) as u32
            };
            match (x, y) {
                (x, 0) => on_edge(0, x),
                (x, y) if x == n => on_edge(1, y),
                (x, y) if y == n => on_edge(2, n - x),
                (0, y) => on_edge(3, n - y),
                (x, y) => {
                    (nv + ne * k + f as usize * k * k + ((y - 1) as usize * k + (x - 1) as usize))
                        as u32
                }
            }
        };
        for y in 0..=n {
            for x in 0..=n {
                let i = index(x, y) as usize;
                let owner = if i < nv {
                    !std::mem::replace(&mut seen_vertex[i], true)
                } else if i < nv + ne * k {
                    !seen_edge[(i - nv) / k]
                } else {
                    true
                };
                if owner {
                    positions[i] = to3(level.point(f, x, y));
                }
            }
        }
        for l in 0..4u8 {
            seen_edge[topo.edge_of(f, l) as usize] = true;
        }
        for y in 0..n {
            for x in 0..n {
                faces.push([
                    index(x, y),
                    index(x + 1, y),
                    index(x + 1, y + 1),
                    index(x, y + 1),
                ]);
            }
        }
    }
    Refined { positions, faces }
}
