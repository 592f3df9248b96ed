//! Fast surface refinement by patches (\[G\] §2.2, organised for speed).
//!
//! Every initial edge carries the one-symbol axiom ω, so after s steps every face of the input
//! mesh is an (N+1)×(N+1) grid whose rows and columns are both labelled W_s = π^s(ω), a
//! symmetric word (\[G\] Cor. 4.4). One step of a patch is the tensor product of two 1D
//! refinements: the patch plus a ring of old points is refined along one axis, then along the
//! other. Each pass applies the level's 1D plan, the masks in gather form (`Plan`: per new
//! point its parents and weights), to whole slabs of points at once.
//!
//! **Depth first.** A step also refines the ring itself (new points −1..=N'+1, checked when
//! the 1D plan is built), so a patch carries its own ring from step to step: the ring is
//! gathered once from the start level, every step runs in cache, and only the last level is
//! written, in its final numbering (`Numbering`: base vertices, edge points, face interiors).
//! No intermediate level is ever stored. Faces whose four corners are ordinary are independent
//! and go through all steps at once: the plans compose into one matrix M and the face's last
//! level is M · P · Mᵀ of its start patch P (`patch/composed.rs`), written in whole cache
//! lines (`patch/stream.rs`); faces around EVs are large patches, refined one at a time
//! (pass, transpose, pass, in strips that stay in cache; the last step hands its rows
//! straight to the output).
//!
//! **EVs.** At an EV corner the diagonal point of the ring does not exist (it is kept zero):
//! with contained masks (\[G\] Prop. 4.8) it only reaches the EV child and the two ring points
//! next to the corner. Faces with an EV corner therefore advance in lock-step: after each step
//! the EV child is set from its old 1-ring, (α·P + Σ_k (E1·R_k + E2·D_k)) / (α + n(E1 + E2)),
//! and those two ring points are copied from the neighbouring faces of the fan, which own them
//! (each face hands its corners' 1-ring points on right after its step, and those ring points
//! too where it has no other phantom, `patch/handoff.rs`).
//! On a mesh whose faces are mostly at EVs (a triangle mesh split into quads)
//! the first such steps, while patches are small, run level by level instead, each face
//! computing only the points it owns (`patch/direct.rs`).
//! An EV child can only enter another face's ring when N' = 1; such steps, and steps whose
//! masks are not yet contained (e.g. Binary-Ternary's first) or whose ring is not
//! self-sustaining, run by the reference driver (`surface`) on the coarse mesh, lifted into the
//! start numbering: one semantics for every path. The last of them scatters only near the EVs
//! where some faces are far enough from them to take it by its 1D plan (`patch/near.rs`).
//!
//! **Boundaries and sharp features** ([`crate::features`], docs/real-meshes.md). Across an
//! edge that is sharp at a step (every boundary edge) a face's ring is the face's own odd
//! reflection, phantoms 2P − Q, and each corner's diagonal is set by its
//! [`CornerKind`]; refining keeps phantoms phantoms, so faces whose corners are all regular
//! run depth first with their phantoms set once. Faces at a vertex whose rule the patches do
//! not give (interior EVs, darts, creases and corners in other sectors, every corner) or
//! whose sharpness changes (semi-sharp creases) run in lock-step: after each step the vertex
//! children are set by their rule and the rings refreshed from the neighbours' new patches and
//! from the next step's phantoms. A step the reference driver must take (masks not contained
//! where a corner has no diagonal) runs, on a mesh with features, on the mesh cut open along
//! its sharp edges and extended by ghost faces (`Cut`, `Ghosts`); a scheme that needs
//! more than one such step is refused there with that reason.

use crate::curve::{rewrite, CurveTables};
use crate::features::{CornerKind, Features, Resolved, VertexRule};
use crate::grid::{along_edge, corner_at, site, Site, TOWARD_NEXT, TOWARD_PREV};
use crate::mesh::QuadMesh;
use crate::real::{axpy_slab, Real};
use crate::surface::{SurfaceError, SurfaceScheme, SurfaceVisitor};
use crate::threads::in_threads;
use crate::topology::{Topology, TopologyError};
use std::collections::HashMap;
use std::time::Instant;

mod composed;
mod direct;
mod handoff;
mod limit;
mod near;
mod reference;
mod stream;
use composed::{Composed, Faces, Rows};
use handoff::{CornerPoint, Handoff, Offsets};
pub use limit::{limit_available, SurfaceLimit};
use near::Near;
use reference::Reference;
use stream::{Stream, Writers, STREAM_BYTES, WRITERS};

/// The 1D refinement of one extended row (old points x = −1..=N+1) for one step, producing the
/// new points −h..=N'+h: h = 1 (the ring of the next step) except in the last step. It is kept
/// in gather form: per new point, its parents among the old points and their weights, summed
/// in the order of the old points (as the scattered masks would add them).
struct Plan {
    /// Per new point X' = −h..=N'+h: the range of its parents in `parents`.
    rows: Vec<std::ops::Range<usize>>,
    /// (old point index x + 1, weight).
    parents: Vec<(usize, f64)>,
    /// Old side N + 3 (ring included).
    old_side: usize,
    /// New side N'.
    n_new: i64,
    /// Whether every new point −h..=N'+h has all its parents among the old points −1..=N+1.
    complete: bool,
    /// The instruction set its passes run with.
    simd: Simd,
}

impl Plan {
    fn new(
        t: &CurveTables<'_>,
        lookup: &HashMap<&[u8], u32>,
        w: &[u8],
        h: i64,
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
        // Scatter every old point's mask, keeping the entries that land on −h..=N'+h.
        let mut by_new: Vec<Vec<(usize, f64)>> = vec![Vec::new(); (n_new + 1 + 2 * h) as usize];
        for x in -1..=n + 1 {
            let word: Vec<u8> = (x - half..x + half).map(label).collect();
            let wi = *lookup
                .get(word.as_slice())
                .ok_or_else(|| SurfaceError::UnknownWord(t.word_str(&word)))?;
            // The entry j of the mask has its middle knot at new knot Off(x − half) + j + half.
            let base = off(x - half) + half;
            for (j, &wt) in t.mask_weights[t.mask_range(wi as usize)].iter().enumerate() {
                let xn = base + j as i64 + h;
                if (0..by_new.len() as i64).contains(&xn) {
                    by_new[xn as usize].push(((x + 1) as usize, wt));
                }
            }
        }
        // Mask weights are non-negative and sum to one at every new point (the compiler's
        // partition-of-unity certificate), so a sum of one means no parent is missing.
        let complete = by_new
            .iter()
            .all(|p| (p.iter().map(|&(_, w)| w).sum::<f64>() - 1.0).abs() <= 1e-9);
        let mut rows = Vec::with_capacity(by_new.len());
        let mut parents = Vec::new();
        for p in by_new {
            rows.push(parents.len()..parents.len() + p.len());
            parents.extend(p);
        }
        Ok(Plan {
            rows,
            parents,
            old_side: (n + 3) as usize,
            n_new,
            complete,
            simd: Simd::detect(),
        })
    }

    /// Per new point, its parents (old point index x + 1, weight).
    fn parent_rows(&self) -> Vec<&[(usize, f64)]> {
        self.rows.iter().map(|r| &self.parents[r.clone()]).collect()
    }

    /// Side of the new patch, ring included.
    fn new_side(&self) -> usize {
        self.rows.len()
    }

    /// `dst[X'·len ..][..len] = Σ w · src[x·len ..][..len]` over the parents (x, w) of every new
    /// point X' (slabs of `len` values: whole rows of a patch at once). Compiled for the
    /// baseline and AVX2 (the plan's [`Simd`]): the same operations in the same order, so the
    /// same bits, only wider vectors.
    fn pass<T: Real>(&self, src: &[T], len: usize, dst: &mut [T]) {
        self.pass_rows(src, len, 0, dst);
    }

    /// [`Plan::pass`] for the new points X' = `first`, `first` + 1, … that `dst` holds.
    fn pass_rows<T: Real>(&self, src: &[T], len: usize, first: usize, dst: &mut [T]) {
        match self.simd {
            // AVX-512 runs the AVX2 pass: compiled for AVX-512 it was slower on the cube
            // (123–131 against 136–137 M vertices/s, docs/benchmarks.md).
            #[cfg(target_arch = "x86_64")]
            // SAFETY: `Simd::Avx2` and `Simd::Avx512` are only handed out where the CPU has AVX2.
            Simd::Avx2 | Simd::Avx512 => unsafe { self.pass_avx2(src, len, first, dst) },
            _ => self.pass_any(src, len, first, dst),
        }
    }

    #[cfg(target_arch = "x86_64")]
    #[target_feature(enable = "avx2")]
    unsafe fn pass_avx2<T: Real>(&self, src: &[T], len: usize, first: usize, dst: &mut [T]) {
        self.pass_any(src, len, first, dst);
    }

    /// The pass with slabs of a small patch's common lengths made constants (points of
    /// sides 4 to 11), so that a row's sums unroll: a fan face's patch is that small in its
    /// first steps, where the calls and loops per row cost more than the sums.
    #[inline(always)]
    fn pass_any<T: Real>(&self, src: &[T], len: usize, first: usize, dst: &mut [T]) {
        match len {
            12 => self.pass_sized::<T, 12>(src, first, dst),
            15 => self.pass_sized::<T, 15>(src, first, dst),
            18 => self.pass_sized::<T, 18>(src, first, dst),
            21 => self.pass_sized::<T, 21>(src, first, dst),
            24 => self.pass_sized::<T, 24>(src, first, dst),
            27 => self.pass_sized::<T, 27>(src, first, dst),
            30 => self.pass_sized::<T, 30>(src, first, dst),
            33 => self.pass_sized::<T, 33>(src, first, dst),
            _ => self.pass_len(src, len, first, dst),
        }
    }

    #[inline(always)]
    fn pass_sized<T: Real, const L: usize>(&self, src: &[T], first: usize, dst: &mut [T]) {
        self.pass_len(src, L, first, dst);
    }

    #[inline(always)]
    fn pass_len<T: Real>(&self, src: &[T], len: usize, first: usize, dst: &mut [T]) {
        for (row, d) in self.rows[first..].iter().zip(dst.chunks_exact_mut(len)) {
            let slab = |x: usize| &src[x * len..(x + 1) * len];
            let w = |i: usize| T::from_f64(self.parents[row.start + i].1);
            match self.parents[row.clone()] {
                [(a, _)] => combine(d, [w(0)], [slab(a)]),
                [(a, _), (b, _)] => combine(d, [w(0), w(1)], [slab(a), slab(b)]),
                [(a, _), (b, _), (c, _)] => {
                    combine(d, [w(0), w(1), w(2)], [slab(a), slab(b), slab(c)])
                }
                [(a, _), (b, _), (c, _), (e, _)] => combine(
                    d,
                    [w(0), w(1), w(2), w(3)],
                    [slab(a), slab(b), slab(c), slab(e)],
                ),
                ref ps => {
                    d.fill(T::default());
                    for &(x, wt) in ps {
                        axpy_slab(d, T::from_f64(wt), slab(x));
                    }
                }
            }
        }
    }

    /// One step of one large patch: `src` ([a][b], side N+3) is refined along a, transposed,
    /// and refined along b into `dst` ([b'][a'], side `new_side`), strip by strip
    /// ([`Plan::strips`]).
    fn step_transposing<T: Real>(
        &self,
        src: &[T],
        p: &mut Passes<T>,
        strip_bytes: usize,
        dst: &mut [T],
    ) {
        let side = self.new_side();
        let dst = &mut dst[..side * side * 3];
        self.strips(src, p, strip_bytes, |a0, w, at, _| {
            if w == side {
                // One strip: the new rows are the whole of `dst`, in one pass.
                self.pass(at, side * 3, dst);
                return;
            }
            for b in 0..side {
                self.pass_rows(at, w * 3, b, &mut dst[(b * side + a0) * 3..][..w * 3]);
            }
        });
    }

    /// [`Plan::step_transposing`] handing each new row b' of each strip to
    /// `each(a0, b', row)` (new points a0.., b') instead of storing the new patch: the last
    /// step of a large patch, whose scratch is then two strips and a row.
    fn step_strips<T: Real>(
        &self,
        src: &[T],
        p: &mut Passes<T>,
        strip_bytes: usize,
        mut each: impl FnMut(usize, usize, &[T]),
    ) {
        let side = self.new_side();
        self.strips(src, p, strip_bytes, |a0, w, at, row| {
            let row = grown(row, w * 3);
            for b in 0..side {
                self.pass_rows(at, w * 3, b, row);
                each(a0, b, row);
            }
        });
    }

    /// For each strip of new points a0..a0 + w along a: `f(a0, w, at, row)` with the strip
    /// refined along a and transposed ([`Plan::strip_transposed`]) and the row buffer.
    fn strips<T: Real>(
        &self,
        src: &[T],
        p: &mut Passes<T>,
        strip_bytes: usize,
        mut f: impl FnMut(usize, usize, &[T], &mut Vec<T>),
    ) {
        let side = self.new_side();
        let strip = self.strip_width::<T>(strip_bytes);
        for a0 in (0..side).step_by(strip) {
            let w = strip.min(side - a0);
            let at = self.strip_transposed(src, &mut p.a, &mut p.at, a0, w);
            f(a0, w, at, &mut p.row);
        }
    }

    /// New points along a per strip: as many as `strip_bytes` of rows refined along a hold
    /// (at least one), so that a strip and its transpose stay in cache.
    fn strip_width<T>(&self, strip_bytes: usize) -> usize {
        (strip_bytes / (self.old_side * 3 * size_of::<T>())).max(1)
    }

    /// The new rows a0..a0 + w refined along a (into `a`), transposed into `at` ([b][a'],
    /// N+3 rows of w points).
    fn strip_transposed<'p, T: Real>(
        &self,
        src: &[T],
        a: &mut Vec<T>,
        at: &'p mut Vec<T>,
        a0: usize,
        w: usize,
    ) -> &'p [T] {
        const L: usize = 3;
        let m = self.old_side;
        let a = grown(a, w * m * L);
        self.pass_rows(src, m * L, a0, a);
        let at = grown(at, m * w * L);
        for (xn, column) in a.chunks_exact(m * L).enumerate() {
            for (y, q) in column.chunks_exact(L).enumerate() {
                let d = (y * w + xn) * L;
                at[d..d + L].copy_from_slice(q);
            }
        }
        at
    }
}

/// Faces (or special vertices) a worker takes between two lock-step levels at least: less
/// work than that does not pay for a thread (the cube's 24 fan faces over 10 levels ran 8 %
/// slower on two threads split finer).
const BETWEEN: usize = 1024;

/// Old side (ring included) up to which the fan faces' last step runs by the composed kernel
/// (`patch/composed.rs`, its matrix the last plan's) rather than by strips, where its rows
/// fill their tiles ([`Composed::fills_tiles`]): the tensor product of one step is a composed
/// patch of one plan, and a fan face's EV corners change nothing there (their missing
/// diagonals reach none of its points, \[G\] Prop. 4.8; the children are set afterwards). On
/// the split icosphere(3), one thread, alternated, the last level took 15–20 % less time
/// under uniform binary at sides 7 and 11 (3 and 4 steps: N' = 8 and 16, tiles filled to
/// 100 and 88 %) and the same at side 19 (5 steps, the x pass's m columns a row outweigh
/// the strips' band); under Fibonacci 40 % more at N' = 10 (59 %).
const FAN_COMPOSED_SIDE: usize = 16;

/// Values of a fan face's interior staged before they are written (64 KiB of f64).
const STAGE: usize = 8192;

/// Faces in a chain of stacked faces at most (`Base::chains`; the kernel may take fewer at
/// once: `composed::Composed`).
const STACK_FACES: usize = 16;

/// The same for a chain whose faces are not consecutive in the order: on a grid ordered along
/// x a chain is a column of faces, each continuing its own runs of the output. Chains of 16
/// (32 runs written at once) were slower there than no chains, 4 the best of 2 to 16
/// (docs/benchmarks.md).
const STACK_FACES_APART: usize = 4;

/// Default bytes of one strip of a large patch refined along a ([`Plan::strip_width`]): half
/// the L2 cache of this machine's cores.
const STRIP_BYTES: usize = 512 << 10;

/// The instruction sets the patch kernels are compiled for, chosen at run time
/// (`is_x86_feature_detected!`). Every path runs the same operations in the same order; the
/// composed patches' sums (`patch/composed.rs`) are fused multiply-adds on AVX2 and AVX-512, so those
/// two give the same bits and differ from the baseline by rounding only (≤ 1e-14 relative).
#[derive(Clone, Copy, Debug, PartialEq, Eq, PartialOrd, Ord, Hash)]
pub enum Simd {
    /// The target's baseline (SSE2 on x86-64).
    Baseline,
    /// AVX2 and FMA: 256-bit vectors.
    Avx2,
    /// AVX-512F (with FMA): 512-bit vectors.
    Avx512,
}

impl Simd {
    /// The widest path this CPU runs.
    pub fn detect() -> Simd {
        #[cfg(target_arch = "x86_64")]
        {
            if std::is_x86_feature_detected!("avx512f") {
                return Simd::Avx512;
            }
            if std::is_x86_feature_detected!("avx2") && std::is_x86_feature_detected!("fma") {
                return Simd::Avx2;
            }
        }
        Simd::Baseline
    }

    /// Every path this CPU runs, narrowest first.
    pub fn available() -> Vec<Simd> {
        let best = Simd::detect();
        [Simd::Baseline, Simd::Avx2, Simd::Avx512]
            .into_iter()
            .filter(|&s| s <= best)
            .collect()
    }

    /// Its name: `avx512`, `avx2` or `baseline`.
    pub fn name(self) -> &'static str {
        match self {
            Simd::Baseline => "baseline",
            Simd::Avx2 => "avx2",
            Simd::Avx512 => "avx512",
        }
    }
}

/// The first n values of `v`, grown (never shrunk) to hold them: buffers keep their pages.
fn grown<T: Real>(v: &mut Vec<T>, n: usize) -> &mut [T] {
    if v.len() < n {
        // Exactly n: a buffer holds one level's patch, and the doubling of `resize` would
        // leave up to twice that, past what `footprint` counts.
        v.reserve_exact(n - v.len());
        v.resize(n, T::default());
    }
    &mut v[..n]
}

/// `d = Σ_i w_i · s_i`, element-wise, summed in order i = 0, 1, … (vectorises; one store per
/// element).
#[inline(always)]
fn combine<T: Real, const P: usize>(d: &mut [T], w: [T; P], s: [&[T]; P]) {
    for (e, out) in d.iter_mut().enumerate() {
        let mut acc = w[0] * s[0][e];
        for i in 1..P {
            acc += w[i] * s[i][e];
        }
        *out = acc;
    }
}

/// Base-mesh connectivity the patches need: the topology and its features, and per face
/// corner the diagonal corner across an ordinary interior vertex, packed as face·4 + corner
/// (`u32::MAX`: none).
struct Base<'t> {
    topo: &'t Topology,
    features: Resolved,
    diagonal: Vec<[u32; 4]>,
    /// Vertices whose child is set by their vertex rule after some step (interior EVs, and
    /// the boundary and crease configurations the patches alone do not give).
    special: Vec<u32>,
    /// Per vertex: its faces are refined in lock-step (special, or its sharpness changes).
    lockstep: Vec<bool>,
    /// Per vertex: its place in `special` (`u32::MAX` if it is not special).
    special_at: Vec<u32>,
    /// Some face corner has no diagonal ring point at some step ([`CornerKind::Ev`]): the
    /// depth-first steps need masks contained there (\[G\] Prop. 4.8).
    needs_containment: bool,
    /// Per step k < `decided` (the rules of the last hold for every later step), per face:
    /// its [`FaceRules`], at `k · F + f`. Resolved once here, so that setting a patch's
    /// phantoms reads eight bytes instead of walking the corners' rotations.
    rules: Vec<FaceRules>,
    /// Per step k < `decided`, per special vertex (at `k · special.len() + i`): its vertex
    /// rule if its child needs it after step k.
    vertex_rules: Vec<Option<VertexRule>>,
    decided: usize,
}

/// What a face's phantom points at a step are made from: which of its edges are sharp, and
/// what holds the ring point diagonal to each corner.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
struct FaceRules {
    sharp: [bool; 4],
    corners: [CornerKind; 4],
}

impl FaceRules {
    /// No phantom: no edge sharp, every diagonal a real point.
    fn is_plain(&self) -> bool {
        self.sharp == [false; 4] && self.corners == [CornerKind::Real; 4]
    }

    /// A phantom other than an EV corner's missing diagonal: an edge sharp, or a corner set
    /// by its kind.
    fn has_phantoms_beside_evs(&self) -> bool {
        let set = |c: &CornerKind| !matches!(c, CornerKind::Real | CornerKind::Ev);
        self.sharp.contains(&true) || self.corners.iter().any(set)
    }
}

impl<'t> Base<'t> {
    fn new(topo: &'t Topology, features: Resolved, steps: usize) -> Result<Base<'t>, SurfaceError> {
        topo.check_valences()?;
        let diagonal = (0..topo.face_count() as u32)
            .map(|f| {
                [0u8, 1, 2, 3].map(|c| {
                    let v = topo.vertex(f, c);
                    let rot = topo.rotation(v);
                    let i = rot.iter().position(|w| w.face == f && w.corner == c);
                    match i {
                        Some(i) if rot.len() == 4 && !topo.is_boundary(v) => {
                            let w = rot[(i + 2) % 4];
                            w.face * 4 + u32::from(w.corner)
                        }
                        _ => u32::MAX,
                    }
                })
            })
            .collect();
        // Sharpness changes only in the first `changing_steps` steps: the rules of the last
        // of them hold for every later step.
        let decided = steps.min(features.changing_steps() + 1).max(1);
        let nv = topo.vertex_count() as u32;
        let plain = features.is_plain();
        // On a plain mesh the special vertices are the EVs, without resolving every rule.
        let special: Vec<u32> = (0..nv)
            .filter(|&v| {
                if plain {
                    topo.valence(v) != 4
                } else {
                    (0..decided).any(|k| features.needs_rule(topo, v, k))
                }
            })
            .collect();
        let mut lockstep = vec![false; nv as usize];
        let mut special_at = vec![u32::MAX; nv as usize];
        for (i, &v) in special.iter().enumerate() {
            lockstep[v as usize] = true;
            special_at[v as usize] = i as u32;
        }
        for v in (0..nv).filter(|_| !plain) {
            if features.changes_at(topo, v) {
                lockstep[v as usize] = true;
            }
        }
        let rules: Vec<FaceRules> = (0..decided)
            .flat_map(|k| {
                let features = &features;
                (0..topo.face_count() as u32).map(move |f| FaceRules {
                    sharp: [0, 1, 2, 3].map(|l| features.edge_sharp(topo.edge_of(f, l), k)),
                    corners: [0, 1, 2, 3].map(|c| features.corner_kind(topo, f, c, k)),
                })
            })
            .collect();
        let vertex_rules = (0..decided)
            .flat_map(|k| {
                let features = &features;
                special.iter().map(move |&v| {
                    features
                        .needs_rule(topo, v, k)
                        .then(|| features.vertex_rule(topo, v, k))
                })
            })
            .collect();
        // A plain mesh's corners lack their diagonal exactly at its EVs.
        let needs_containment = if plain {
            !special.is_empty()
        } else {
            rules.iter().any(|r| r.corners.contains(&CornerKind::Ev))
        };
        Ok(Base {
            topo,
            features,
            diagonal,
            special,
            lockstep,
            special_at,
            needs_containment,
            rules,
            vertex_rules,
            decided,
        })
    }

    /// The rule of each special vertex whose child needs it after step k.
    fn vertex_rules(&self, k: usize) -> &[Option<VertexRule>] {
        let k = k.min(self.decided - 1);
        &self.vertex_rules[k * self.special.len()..][..self.special.len()]
    }

    /// Face f's rules at step k.
    fn rules(&self, f: u32, k: usize) -> FaceRules {
        let k = k.min(self.decided - 1);
        self.rules[k * self.topo.face_count() + f as usize]
    }

    /// The face across local edge l of face f, its local edge, and whether the parameter runs
    /// backwards there; none across a boundary edge.
    fn across(&self, f: u32, l: u8) -> Option<(u32, u8, bool)> {
        let (g, gl) = self.topo.across(f, l)?;
        Some((g, gl, self.topo.vertex(f, l) != self.topo.vertex(g, gl)))
    }

    /// The diagonal (face, corner) across corner c of face f when that vertex is an ordinary
    /// interior vertex.
    fn diagonal(&self, f: u32, c: u8) -> Option<(u32, u8)> {
        let d = self.diagonal[f as usize][c as usize];
        (d != u32::MAX).then_some((d / 4, (d % 4) as u8))
    }

    /// Whether face g stacks on face f for the composed kernel at start step k (`composed`,
    /// `Faces::load`): g's edge 0 is f's edge 2 in the same direction (g's corners 0 and 1
    /// are f's corners 3 and 2), and neither has a phantom, so that g's start patch is f's
    /// moved up by N₀ rows.
    fn stacks(&self, f: u32, g: u32, k: usize) -> bool {
        let t = self.topo;
        t.across(f, 2) == Some((g, 0))
            && (t.vertex(g, 0), t.vertex(g, 1)) == (t.vertex(f, 3), t.vertex(f, 2))
            && self.rules(f, k).is_plain()
            && self.rules(g, k).is_plain()
    }

    /// The faces of `ordinary` (in their order) in chains of faces each stacking on the one
    /// before ([`Base::stacks`]), at most [`STACK_FACES`] long ([`STACK_FACES_APART`] if not
    /// consecutive in the order), each chain through the first face not yet taken, up from it
    /// or, if it cannot go up, down: a grid's faces in stacks whichever way their order runs
    /// (along y: consecutive faces; along x: a column at a time, a band of rows after the
    /// other). Also per face: whether the next one stacks on it.
    fn chains(&self, ordinary: &[u32], k: usize) -> (Vec<u32>, Vec<bool>) {
        let nf = self.topo.face_count();
        let mut free = vec![false; nf];
        for &f in ordinary {
            free[f as usize] = true;
        }
        let (mut order, mut stacks) = (Vec::with_capacity(ordinary.len()), Vec::new());
        let mut chain = Vec::with_capacity(STACK_FACES);
        for &f in ordinary {
            if !std::mem::replace(&mut free[f as usize], false) {
                continue;
            }
            chain.clear();
            chain.push(f);
            // Up from f (across edge 2): a chain of faces that follow each other in the order
            // writes one run, and may be as long as the kernel takes.
            let mut consecutive = true;
            while let Some(&top) = chain.last() {
                let Some((g, 0)) = self.topo.across(top, 2) else {
                    break;
                };
                consecutive &= g == top + 1;
                let most = if consecutive {
                    STACK_FACES
                } else {
                    STACK_FACES_APART
                };
                if !free[g as usize] || chain.len() >= most || !self.stacks(top, g, k) {
                    break;
                }
                free[g as usize] = false;
                chain.push(g);
            }
            // Else down from f (across edge 0), where the faces' y runs against the order.
            if chain.len() == 1 {
                while chain.len() < STACK_FACES_APART {
                    let Some((h, 2)) = self.topo.across(chain[0], 0) else {
                        break;
                    };
                    if !free[h as usize] || !self.stacks(h, chain[0], k) {
                        break;
                    }
                    free[h as usize] = false;
                    chain.insert(0, h);
                }
            }
            order.extend_from_slice(&chain);
            stacks.extend((1..=chain.len()).map(|i| i < chain.len()));
        }
        (order, stacks)
    }

    /// Whether face f is refined depth first on its own: no corner at a lock-step vertex.
    fn ordinary(&self, f: u32) -> bool {
        (0..4).all(|c| !self.lockstep[self.topo.vertex(f, c) as usize])
    }

    /// Points t = 0..=N of face f's ring across its local edge l (which runs from corner l to
    /// l+1; side N): each one's place in f's frame, and the (face, x, y) that owns it, one
    /// step inside the neighbour (none across a boundary edge).
    fn ring(&self, f: u32, l: u8, n: i64) -> impl Iterator<Item = RingPoint> {
        let (cx, cy) = corner_at(l, n, n);
        let (dx, dy) = TOWARD_NEXT[l as usize];
        // Outward normal of edge l: the opposite of the step toward corner l−1.
        let (ox, oy) = TOWARD_PREV[l as usize];
        let across = self.across(f, l);
        (0..=n).map(move |t| {
            let owner = across.map(|(g, gl, back)| {
                let u = if back { n - t } else { t };
                let (gx, gy) = inward_xy(gl, u, 1, n);
                (g, gx, gy)
            });
            ((cx + t * dx - ox, cy + t * dy - oy), owner)
        })
    }

    /// The phantom points of face f's patch (side N) at step k, in the order they must be
    /// computed: the ring across every edge sharp at step k is the odd reflection of the
    /// face (2P − Q, P on the edge), then each corner's diagonal by its [`CornerKind`].
    fn phantoms(&self, f: u32, n: i64, k: usize, mut each: impl FnMut(Phantom)) {
        let rules = self.rules(f, k);
        if rules.is_plain() {
            return;
        }
        for l in 0..4u8 {
            if !rules.sharp[l as usize] {
                continue;
            }
            let (ix, iy) = TOWARD_PREV[l as usize];
            for ((x, y), _) in self.ring(f, l, n) {
                let on = (x + ix, y + iy);
                let inside = (on.0 + ix, on.1 + iy);
                each(Phantom::new((x, y), &[(on, 2.0), (inside, -1.0)]));
            }
        }
        for c in 0..4u8 {
            let at = |i: i8, j: i8| CornerPoint::new(c, i, j).xy(n);
            let terms: &[((i64, i64), f64)] = match rules.corners[c as usize] {
                CornerKind::Real => continue,
                CornerKind::Ev => &[],
                CornerKind::Both => &[
                    (at(0, 0), 4.0),
                    (at(1, 0), -2.0),
                    (at(0, 1), -2.0),
                    (at(1, 1), 1.0),
                ],
                // The edge toward corner c − 1 (along b) is sharp: reflect the ring across
                // edge c (the row j = −1) over the line i = 0.
                CornerKind::OneSide(true) => &[(at(0, -1), 2.0), (at(1, -1), -1.0)],
                CornerKind::OneSide(false) => &[(at(-1, 0), 2.0), (at(-1, 1), -1.0)],
            };
            each(Phantom::new(at(-1, -1), terms));
        }
    }
}

impl Base<'_> {
    /// Sets the phantom points of face f's patch (side N, for step k) in `buf`; nothing
    /// where the face has none ([`FaceRules::is_plain`]).
    fn load_phantoms<T: Real>(&self, (f, n, k): (u32, i64, usize), layout: Layout, buf: &mut [T]) {
        self.phantoms(f, n, k, |p| p.apply(layout, buf));
    }

    /// After a step, the ring of lock-step face f (side N, `layout`) from its lock-step
    /// neighbours' new patches: every row across an edge not sharp at step k, and the
    /// diagonal across each ordinary interior corner. Rows toward faces that are not in
    /// lock-step keep the values f's own step gave them (exact there: nothing at those points
    /// changes between steps). On a mesh without features, or where f had no phantom but its
    /// EV corners' diagonals in the step before, f's own step gives every ring point but the
    /// two next to each EV corner (its diagonal is missing, and with contained masks it
    /// reaches only those and the EV child, \[G\] Prop. 4.8): only those are copied.
    fn refresh_ring<T: Real>(
        &self,
        (f, n, k): (u32, i64, usize),
        layout: Layout,
        slot: &[u32],
        patches: &[T],
        put: &mut impl FnMut(usize, [T; 3]),
    ) {
        let patches = (patches, patch_len(n));
        // Point (x, y) of a lock-step face's patch, as its offset.
        let at = |(x, y): (i64, i64)| layout.at(x, y) as isize;
        let rules = self.rules(f, k);
        // Each edge's ring row is the row next to the edge in the face across: both run with
        // a constant step, so the row is copied point by point at two strides. The points
        // read are inside their face and those written outside f, so none is both.
        // A face with no phantom beside its EV corners' diagonals in the step just taken
        // (k − 1; nor after it: sharpness only decays) computed its whole new ring itself, as
        // on a mesh without features, but the two points next to each EV corner.
        let plain = self.features.is_plain() || !self.rules(f, k - 1).has_phantoms_beside_evs();
        let ev = |c: u8| self.lockstep[self.topo.vertex(f, c % 4) as usize];
        for l in 0..4u8 {
            let Some((g, gl, back)) = self.across(f, l).filter(|_| !rules.sharp[l as usize]) else {
                continue;
            };
            let (cx, cy) = corner_at(l, n, n);
            let ((dx, dy), (ox, oy)) = (TOWARD_NEXT[l as usize], TOWARD_PREV[l as usize]);
            let to_at = |t: i64| at((cx + t * dx - ox, cy + t * dy - oy));
            let from_at = |t: i64| at(inward_xy(gl, if back { n - t } else { t }, 1, n));
            let row = |(t, count): (i64, i64)| {
                let (from, to) = (from_at(t), to_at(t));
                let steps = (from_at(t + 1) - from, to_at(t + 1) - to);
                ((g, from, steps.0), (to, steps.1), count)
            };
            if !plain {
                let (from, to, count) = row((0, n + 1));
                copy_points(patches, slot, from, to, count, put);
                continue;
            }
            for t in [(ev(l), 0), (ev(l + 1), n)].into_iter().filter(|e| e.0) {
                let (from, to, count) = row((t.1, 1));
                copy_points(patches, slot, from, to, count, put);
            }
        }
        for c in (0..4u8).filter(|_| !plain) {
            let (Some((g, gc)), CornerKind::Real) =
                (self.diagonal(f, c), rules.corners[c as usize])
            else {
                continue;
            };
            // g's point diagonal to its corner gc, to f's ring point diagonal to corner c.
            let from = at(CornerPoint::new(gc, 1, 1).xy(n));
            let to = at(CornerPoint::new(c, -1, -1).xy(n));
            copy_points(patches, slot, (g, from, 0), (to, 0), 1, put);
        }
    }
}

/// Hands `count` points of face g's patch (offset `from`, then every `from_step` values; the
/// level's patches one after the other, `len` values each) to `put` with their offsets in the
/// patch being refreshed (`at`, then every `to_step`); nothing if g is not in lock-step (no
/// slot).
fn copy_points<T: Copy>(
    (patches, len): (&[T], usize),
    slot: &[u32],
    (g, from, from_step): (u32, isize, isize),
    (at, to_step): (isize, isize),
    count: i64,
    put: &mut impl FnMut(usize, [T; 3]),
) {
    let Some(&src) = slot.get(g as usize).filter(|&&s| s != u32::MAX) else {
        return;
    };
    let patch = &patches[src as usize * len..][..len];
    for t in 0..count as isize {
        let (i, j) = ((from + t * from_step) as usize, (at + t * to_step) as usize);
        put(j, [patch[i], patch[i + 1], patch[i + 2]]);
    }
}

/// A ring point of a face: (x, y) in that face, and (face, x, y) of its owner (none across a
/// boundary).
type RingPoint = ((i64, i64), Option<(u32, i64, i64)>);

/// A point of a patch that is an affine combination of other points of the same patch (a
/// phantom across a sharp edge, or a corner's diagonal), or zero with no terms.
#[derive(Clone, Copy, Debug)]
struct Phantom {
    at: (i64, i64),
    terms: [((i64, i64), f64); 4],
    len: u8,
}

impl Phantom {
    fn new(at: (i64, i64), terms: &[((i64, i64), f64)]) -> Phantom {
        let mut t = [((0, 0), 0.0); 4];
        t[..terms.len()].copy_from_slice(terms);
        Phantom {
            at,
            terms: t,
            len: terms.len() as u8,
        }
    }

    /// Sets the point in the patch `buf` (in `layout`).
    fn apply<T: Real>(&self, layout: Layout, buf: &mut [T]) {
        let mut p = [T::default(); 3];
        for &((x, y), w) in &self.terms[..self.len as usize] {
            let i = layout.at(x, y);
            for (o, q) in p.iter_mut().zip(&buf[i..i + 3]) {
                *o += T::from_f64(w) * *q;
            }
        }
        let i = layout.at(self.at.0, self.at.1);
        buf[i..i + 3].copy_from_slice(&p);
    }
}

/// The point `inward` steps into a face from its local edge `gl`, at parameter u along that
/// edge (from corner gl), in the face's frame (side N).
fn inward_xy(gl: u8, u: i64, inward: i64, n: i64) -> (i64, i64) {
    match gl {
        0 => (u, inward),
        1 => (n - inward, u),
        2 => (n - u, n - inward),
        _ => (inward, n - u),
    }
}

/// Where a patch of side `side` (its ring included) keeps its points: point (x, y),
/// x, y = −1..=side−2, is at `3 · (a·side + b)` with (a, b) = (x + 1, y + 1), or (y + 1, x + 1)
/// when the patch is stored transposed.
#[derive(Clone, Copy)]
struct Layout {
    side: usize,
    a_is_x: bool,
}

impl Layout {
    fn at(self, x: i64, y: i64) -> usize {
        let (along_x, along_y) = self.strides();
        (x + 1) as usize * along_x + (y + 1) as usize * along_y
    }

    /// Values from a point to the next along x, and along y.
    fn strides(self) -> (usize, usize) {
        if self.a_is_x {
            (3 * self.side, 3)
        } else {
            (3, 3 * self.side)
        }
    }
}

/// The layout of a patch of side N with its ring.
fn ring_layout(n: i64, a_is_x: bool) -> Layout {
    Layout {
        side: (n + 3) as usize,
        a_is_x,
    }
}

/// The patches (ring included) of the faces with an EV corner at one level, one after the
/// other in their slots' order.
struct Fans<'a, T> {
    /// Face → its slot (`u32::MAX`: an ordinary face).
    slot: &'a [u32],
    patches: &'a [T],
    n: i64,
    a_is_x: bool,
}

/// Values of a fan face's patch of side N, its ring included.
fn patch_len(n: i64) -> usize {
    let m = (n + 3) as usize;
    m * m * 3
}

/// `buf` cut into `count` consecutive pieces of `len` values (the last ones shorter or empty):
/// one per worker.
fn pieces<T>(mut buf: &mut [T], len: usize, count: usize) -> Vec<&mut [T]> {
    (0..count)
        .map(|_| {
            let at = len.min(buf.len());
            let (piece, rest) = std::mem::take(&mut buf).split_at_mut(at);
            buf = rest;
            piece
        })
        .collect()
}

impl<T> Fans<'_, T> {
    fn point(&self, f: u32, x: i64, y: i64) -> &[T; 3] {
        let i = ring_layout(self.n, self.a_is_x).at(x, y);
        let len = patch_len(self.n);
        let p = &self.patches[self.slot[f as usize] as usize * len..][..len];
        p[i..i + 3].try_into().expect("three coordinates")
    }
}

/// The buffers between one step's two passes, and one new row.
#[derive(Default)]
struct Passes<T> {
    a: Vec<T>,
    at: Vec<T>,
    row: Vec<T>,
}

/// Scratch buffers of one worker: an ordinary face's, and a fan patch's passes' buffers.
/// Buffers only grow, so a worker touches fresh pages only once.
#[derive(Default)]
struct Scratch<T> {
    /// An ordinary face's start patch and its rows ([`Composed::scratch_len`]).
    face: Vec<T>,
    /// A fan face's last interior, staged (`Refiner::fan_faces`).
    interior: Vec<T>,
    /// An ordinary face's edge runs, reversed or gathered from a column (`Ordinary`).
    spare: Vec<T>,
    p: Passes<T>,
}

/// Where the points of a patch go in the final numbering: base vertices, then N−1 points per
/// base edge (from its smaller vertex), then (N−1)² per face, row by row.
struct Numbering {
    n: i64,
    nv: usize,
    ne: usize,
    /// Per face, its edges and corners in the numbering. Shared by every level.
    faces: std::sync::Arc<[FaceNumbering]>,
}

/// A face's edges and corners in the [`Numbering`]: one record of 36 bytes, read once per face.
#[derive(Clone, Copy, Debug)]
struct FaceNumbering {
    /// Edge id of local edge l (from corner l to l + 1).
    edge: [u32; 4],
    /// Vertex of corner l.
    vertex: [u32; 4],
    /// Per l: [`FaceNumbering::FORWARD`], [`FaceNumbering::OWNS_EDGE`],
    /// [`FaceNumbering::OWNS_CORNER`].
    bits: [u8; 4],
}

impl FaceNumbering {
    /// Edge l's points run from corner l (its smaller vertex).
    const FORWARD: u8 = 1;
    /// This face writes edge l's points (the first face of the edge does).
    const OWNS_EDGE: u8 = 2;
    /// This face writes corner l's vertex (its first face does).
    const OWNS_CORNER: u8 = 4;

    /// Local edge l: its edge id, whether its points run from corner l, and whether this face
    /// writes them.
    #[inline(always)]
    fn edge(&self, l: usize) -> (u32, bool, bool) {
        let b = self.bits[l];
        (
            self.edge[l],
            b & Self::FORWARD != 0,
            b & Self::OWNS_EDGE != 0,
        )
    }

    /// Whether this face writes the vertex of corner c.
    #[inline(always)]
    fn owns_corner(&self, c: usize) -> bool {
        self.bits[c] & Self::OWNS_CORNER != 0
    }
}

impl Numbering {
    fn new(topo: &Topology, n: i64) -> Numbering {
        let nf = topo.face_count();
        let mut edge_done = vec![false; topo.edge_count()];
        let mut vertex_done = vec![false; topo.vertex_count()];
        let faces = (0..nf as u32)
            .map(|f| {
                let mut r = FaceNumbering {
                    edge: [0; 4],
                    vertex: [0; 4],
                    bits: [0; 4],
                };
                for l in 0..4u8 {
                    let (e, v, i) = (topo.edge_of(f, l), topo.vertex(f, l), l as usize);
                    let bit = |yes: bool, b: u8| if yes { b } else { 0 };
                    (r.edge[i], r.vertex[i]) = (e, v);
                    r.bits[i] = bit(topo.from_smaller(f, l), FaceNumbering::FORWARD)
                        | bit(
                            !std::mem::replace(&mut edge_done[e as usize], true),
                            FaceNumbering::OWNS_EDGE,
                        )
                        | bit(
                            !std::mem::replace(&mut vertex_done[v as usize], true),
                            FaceNumbering::OWNS_CORNER,
                        );
                }
                r
            })
            .collect();
        Numbering {
            n,
            nv: topo.vertex_count(),
            ne: topo.edge_count(),
            faces,
        }
    }

    /// The same mesh's numbering at another N (the ownership tables are shared).
    fn with_n(&self, n: i64) -> Numbering {
        Numbering {
            n,
            nv: self.nv,
            ne: self.ne,
            faces: self.faces.clone(),
        }
    }

    fn len(&self) -> usize {
        let k = (self.n - 1) as usize;
        self.nv + self.ne * k + self.faces.len() * k * k
    }

    /// The index of point (x, y) of face f, and whether face f writes it.
    fn index(&self, f: usize, x: i64, y: i64) -> (usize, bool) {
        let n = self.n;
        let k = (n - 1) as usize;
        match site(x, y, n, n) {
            Site::Corner(c) => (
                self.faces[f].vertex[c as usize] as usize,
                self.faces[f].owns_corner(c as usize),
            ),
            Site::Edge(l, t) => {
                let (e, forward, owner) = self.faces[f].edge(l as usize);
                (self.nv + e as usize * k + along_edge(t, n, forward), owner)
            }
            Site::Inside(i) => (self.interior(f) + i, true),
        }
    }

    /// The index of face f's first interior point (x, y) = (1, 1); the others follow row by
    /// row.
    #[inline(always)]
    fn interior(&self, f: usize) -> usize {
        let k = (self.n - 1) as usize;
        self.nv + self.ne * k + f * k * k
    }
}

impl Numbering {
    /// Every face's patch with its ring as indices into this numbering, x-major ([`load`]),
    /// `u32::MAX` where a point does not exist ([`Numbering::gather`]).
    fn gather_table(&self, base: &Base<'_>) -> Vec<u32> {
        let m = ring_layout(self.n, true);
        let mut table = vec![u32::MAX; base.topo.face_count() * m.side * m.side];
        for (f, t) in table.chunks_exact_mut(m.side * m.side).enumerate() {
            self.gather(base, f as u32, |x, y, i| t[m.at(x, y) / 3] = i as u32);
        }
        table
    }

    /// Face f's patch with its ring (side N+3): `put(x, y, i)` for each point and its index
    /// in this numbering; ring points across a boundary and the diagonal point at an
    /// extraordinary corner do not exist and are not handed.
    fn gather(&self, base: &Base<'_>, f: u32, mut put: impl FnMut(i64, i64, usize)) {
        let n = self.n;
        let kk = (n - 1) as usize;
        let fu = f as usize;
        // The patch: interior rows, then corners, then each edge as a run (forward or backward
        // in the numbering).
        let (inner, _) = self.index(fu, 1, 1);
        for y in 1..n {
            for x in 1..n {
                put(x, y, inner + (y - 1) as usize * kk + (x - 1) as usize);
            }
        }
        for c in 0..4u8 {
            let (x, y) = corner_at(c, n, n);
            put(x, y, self.faces[fu].vertex[c as usize] as usize);
        }
        for l in 0..4u8 {
            let (e, forward, _) = self.faces[fu].edge(l as usize);
            let first = self.nv + e as usize * kk;
            let (cx, cy) = corner_at(l, n, n);
            let (dx, dy) = TOWARD_NEXT[l as usize];
            for t in 1..n {
                put(cx + t * dx, cy + t * dy, first + along_edge(t, n, forward));
            }
        }
        // The ring along the four edges (none across a boundary: phantoms, set after loading).
        for l in 0..4u8 {
            for ((x, y), owner) in base.ring(f, l, n) {
                if let Some((g, gx, gy)) = owner {
                    put(x, y, self.index(g as usize, gx, gy).0);
                }
            }
        }
        // Corners: the diagonal point across an ordinary vertex; none elsewhere.
        for c in 0..4u8 {
            if let Some((g, gc)) = base.diagonal(f, c) {
                let (cx, cy) = corner_at(c, n, n);
                let (ax, ay) = TOWARD_NEXT[c as usize];
                let (bx, by) = TOWARD_PREV[c as usize];
                let (gx, gy) = corner_at(gc, n, n);
                let (hx, hy) = TOWARD_NEXT[gc as usize];
                let (kx, ky) = TOWARD_PREV[gc as usize];
                let i = self.index(g as usize, gx + hx + kx, gy + hy + ky).0;
                put(cx - ax - bx, cy - ay - by, i);
            }
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
    fn new(v: &mut [[T; 3]]) -> SharedOut<T> {
        SharedOut {
            ptr: v.as_mut_ptr(),
            len: v.len(),
        }
    }

    /// Writes point i.
    ///
    /// # Safety
    /// No other thread reads or writes index i during the call.
    unsafe fn write(&self, i: usize, p: &[T; 3]) {
        assert!(i < self.len, "output index in range");
        // SAFETY: in range (checked); exclusive to this caller (the function's contract).
        unsafe { self.ptr.add(i).write(*p) };
    }

    /// Points i..i + len, to write.
    ///
    /// # Safety
    /// No other thread reads or writes them while the slice lives.
    #[allow(clippy::mut_from_ref)]
    unsafe fn run(&self, i: usize, len: usize) -> &mut [[T; 3]] {
        assert!(i + len <= self.len, "output run in range");
        // SAFETY: in range (checked); exclusive to this caller (the function's contract).
        unsafe { std::slice::from_raw_parts_mut(self.ptr.add(i), len) }
    }

    /// A writer of runs of the output's values ([`Stream::new`]: non-temporal where
    /// `streaming`, with the vectors of `simd`).
    ///
    /// # Safety
    /// No other thread or writer reads or writes the indices it is handed until
    /// [`Stream::finish`] and a `stream::fence` on this thread; `simd` only a path the CPU has.
    unsafe fn stream(&self, streaming: bool, simd: Simd) -> Stream<'_, T>
    where
        T: Default,
    {
        // SAFETY: the buffer holds `len` points of three values and outlives `self`; the rest
        // is the caller's contract.
        unsafe { Stream::new(self.ptr.cast::<T>(), self.len * 3, streaming, simd) }
    }
}

/// Refines one quad mesh topology (closed or open, with its features) again and again (new
/// positions, same connectivity), reusing every buffer: the analogue of OpenSubdiv's topology
/// refiner + primvar refiner.
pub struct Refiner<'s, S, T> {
    scheme: &'s S,
    /// The base mesh's connectivity (positions come with each `refine`).
    base: Base<'s>,
    /// Steps run by the reference driver before the depth-first ones.
    first: usize,
    /// The depth-first steps after them that run level by level (`patch/direct.rs`).
    direct: Vec<direct::Step>,
    /// One plan per depth-first step.
    plans: Vec<Plan>,
    /// The plans composed, for the ordinary faces (none without depth-first steps).
    composed: Option<Composed<T>>,
    /// The fan faces' last step as a composed patch of one plan where their patches are
    /// small ([`FAN_COMPOSED_SIDE`]; the steps before it run in lock-step, their EV children
    /// and rings set between them).
    fan_last: Option<Composed<T>>,
    /// The instruction set the kernels run with.
    simd: Simd,
    alphas: Vec<f64>,
    /// Numbering of the start level (after the reference steps) and of the output.
    start_num: Numbering,
    out_num: Numbering,
    /// Per face, its start patch (ring included) as indices into the start level, in the
    /// gathered layout ([`load`]).
    start_gather: Vec<u32>,
    /// The mesh cut along its sharp edges, when a reference step runs on a mesh with features.
    cut: Option<Cut>,
    /// Where the last reference step runs on a mesh without features, when some faces are far
    /// from its EVs.
    near: Option<Near>,
    /// The reference steps' maps (none without reference steps).
    reference: Option<Reference>,

    /// Faces whose four corners are ordinary, and the others (the fans of the EVs) with the
    /// slot of each face among them.
    ordinary: Vec<u32>,
    /// Per ordinary face (in the order of their chains, [`Base::chains`]): whether the next
    /// one stacks on it.
    stacks: Vec<bool>,
    fan_faces: Vec<u32>,
    fan_slot: Vec<u32>,
    /// What the fan faces hand each other between levels (the 1-rings, and the ring points
    /// of faces without other phantoms), and its box ([`Handoff`]).
    handoff: Option<Handoff>,
    handed: Vec<[T; 3]>,
    threads: usize,
    /// Scratch per strip of a large patch's step ([`Refiner::set_strip_bytes`]).
    strip_bytes: usize,
    /// Output size from which whole lines go out non-temporally ([`Refiner::set_stream_bytes`]).
    stream_bytes: usize,
    /// Ordinary faces refined as one stack at most ([`Refiner::set_stack`]).
    stack: usize,
    start: Vec<[T; 3]>,
    /// The level before `start` while the level-by-level steps run.
    level: Vec<[T; 3]>,
    output: Vec<[T; 3]>,
    /// The fans' patches at the current and the next level, each level's one after the
    /// other (read and written in order, level by level).
    fans: [Vec<T>; 2],
    /// Wall time of the phases of the last `refine`.
    phase_seconds: Phases,
    /// One scratch per worker, kept across steps and calls (no fresh pages per step).
    scratch: Vec<Scratch<T>>,
    /// Worker time per depth-first step of the last `refine`.
    level_seconds: Vec<f64>,
}

/// Wall time of the phases of one refinement, in seconds.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Phases {
    /// The start level: lifting the input, the reference driver's steps and the level-by-level
    /// steps (`patch/direct.rs`) if any.
    pub start: f64,
    /// Every step of the faces with four ordinary corners, depth first.
    pub ordinary: f64,
    /// Every step of the faces around EVs, in lock-step.
    pub fans: f64,
}

impl<'s, S: SurfaceScheme + Sync, T: Real> Refiner<'s, S, T> {
    /// Prepares `steps` steps of `scheme` on the mesh of topology `topo` (every edge labelled
    /// by the axiom; boundaries refined edge-and-corner, nothing else sharp) with `threads`
    /// workers (results do not depend on it).
    pub fn new(
        scheme: &'s S,
        topo: &'s Topology,
        steps: usize,
        threads: usize,
    ) -> Result<Self, SurfaceError> {
        Self::with_features(scheme, topo, &Features::default(), steps, threads)
    }

    /// [`Refiner::new`] with sharp features and a boundary rule ([`crate::features`]).
    pub fn with_features(
        scheme: &'s S,
        topo: &'s Topology,
        features: &Features,
        steps: usize,
        threads: usize,
    ) -> Result<Self, SurfaceError> {
        let t = scheme.tables();
        let st = scheme.surface();
        let [omega] = t.axiom else {
            return Err(SurfaceError::Axiom);
        };
        let resolved = Resolved::new(topo, features).map_err(SurfaceError::Features)?;
        let base = Base::new(topo, resolved, steps)?;
        let plain = base.features.is_plain();
        let lookup = t.word_index();
        // Output quads index vertices with u32: refuse a result that would not fit, before
        // building anything.
        let (out_v, out_f) = output_counts(
            base.topo.vertex_count() as u128,
            base.topo.edge_count() as u128,
            base.topo.face_count() as u128,
            t.image_len(&[*omega], steps),
        );
        if out_v > u128::from(u32::MAX) || out_f > u128::from(u32::MAX) {
            return Err(SurfaceError::Topology(TopologyError::TooLarge {
                vertices: usize::try_from(out_v).unwrap_or(usize::MAX),
                faces: usize::try_from(out_f).unwrap_or(usize::MAX),
            }));
        }
        let mut words = vec![vec![*omega]];
        for s in 0..steps {
            let mut next = Vec::new();
            rewrite(&t, &words[s], &mut next);
            words.push(next);
        }
        // Depth-first steps start after the last step that cannot run that way: masks not yet
        // contained (with EVs), a ring that does not sustain itself, or N' = 1 with EVs.
        let special = !base.special.is_empty();
        let mut first = if base.needs_containment {
            st.contained_from.min(steps)
        } else {
            0
        };
        let mut plans = Vec::new();
        for (s, w) in words.iter().enumerate().take(steps).skip(first) {
            let plan = Plan::new(&t, &lookup, w, i64::from(s + 1 < steps))?;
            if plan.complete && (plan.n_new >= 2 || !special) {
                plans.push(plan);
            } else {
                plans.clear();
                first = s + 1;
            }
        }
        // Those steps run by the reference driver, which refines closed meshes, and one step
        // of a mesh with features cut open along its sharp edges and extended by ghost faces
        // ([`Cut`], [`Ghosts`]).
        let cut = if first == 1 && !plain {
            Cut::new(topo, &base.features, Plan::new(&t, &lookup, &[*omega], 0)?)
        } else {
            None
        };
        if first > 0 && !plain && cut.is_none() {
            return Err(SurfaceError::Unsupported(format!(
                "{} step{} of scheme `{}` on this mesh need the reference driver (masks not \
                 yet contained near its extraordinary, boundary or crease vertices, [G] \
                 Prop. 4.8); on a mesh with boundaries or sharp features it takes one such \
                 step (on the mesh cut open along its sharp edges, with ghost faces), not more",
                first,
                if first == 1 { "" } else { "s" },
                t.name
            )));
        }
        let mut near = (first > 0 && plain)
            .then(|| Near::new(&t, &lookup, &base, &words[first - 1]))
            .flatten();
        let reference = (first > 0)
            .then(|| {
                let num = Numbering::new(base.topo, words[first].len() as i64);
                let (near, cut) = (near.as_mut(), cut.as_ref());
                Reference::new(scheme, &base, (first, &num), near, cut, threads.max(1))
            })
            .transpose()?;
        // The first depth-first steps of a mesh of small fans, level by level.
        let nf = topo.face_count();
        let (ordinary, fan_faces): (Vec<u32>, Vec<u32>) =
            (0..nf as u32).partition(|&f| base.ordinary(f));
        let lead = direct::leading(&base, fan_faces.len(), plans.iter().map(|p| p.n_new));
        let direct: Vec<direct::Step> = (first..)
            .zip(plans.drain(..lead))
            .map(|(k, plan)| {
                let ring = st.rings[k.min(st.rings.len() - 1)];
                direct::Step::new(&base, plan, (words[k].len() as i64, k), ring)
            })
            .collect();
        let start_level = first + lead;
        let start_num = Numbering::new(base.topo, words[start_level].len() as i64);
        let out_num = start_num.with_n(words[steps].len() as i64);
        let m = ring_layout(start_num.n, true);
        let start_gather = start_num.gather_table(&base);
        // α for the special vertices that are interior and extraordinary (unused otherwise).
        let alphas = base
            .special
            .iter()
            .map(|&v| match base.topo.valence(v) {
                n if n < 3 || n == 4 || base.topo.is_boundary(v) => Ok(0.0),
                n => st.alpha(n).map_err(SurfaceError::Ev),
            })
            .collect::<Result<_, _>>()?;
        let (ordinary, stacks) = base.chains(&ordinary, start_level);
        let composed = (!plans.is_empty()).then(|| {
            Composed::new(
                m.side,
                &composed::compose(m.side, plans.iter().map(Plan::parent_rows)),
            )
        });
        let fan_last = plans
            .last()
            .filter(|p| !fan_faces.is_empty() && p.old_side <= FAN_COMPOSED_SIDE);
        let fan_last = fan_last
            .map(|p| {
                Composed::new(
                    p.old_side,
                    &composed::compose(p.old_side, [p.parent_rows()]),
                )
            })
            .filter(Composed::fills_tiles);
        let mut fan_slot = vec![u32::MAX; nf];
        for (i, &f) in fan_faces.iter().enumerate() {
            fan_slot[f as usize] = i as u32;
        }
        let handoff = Handoff::new(&base, &fan_faces, &fan_slot);
        Ok(Refiner {
            scheme,
            base,
            first,
            direct,
            plans,
            composed,
            fan_last,
            simd: Simd::detect(),
            alphas,
            start_num,
            out_num,
            start_gather,
            cut,
            near,
            reference,
            ordinary,
            stacks,
            handoff,
            handed: Vec::new(),
            fan_faces,
            fan_slot,
            threads: threads.max(1),
            strip_bytes: STRIP_BYTES,
            stream_bytes: STREAM_BYTES,
            stack: usize::MAX,
            start: Vec::new(),
            level: Vec::new(),
            output: Vec::new(),
            fans: [Vec::new(), Vec::new()],
            phase_seconds: Phases::default(),
            scratch: Vec::new(),
            level_seconds: Vec::new(),
        })
    }

    /// Number of output vertices.
    pub fn output_vertices(&self) -> usize {
        self.out_num.len()
    }

    /// Scratch per strip of a step of a large patch (default 512 KiB, half this machine's
    /// L2): smaller strips use less memory, and 1 makes every strip one point wide.
    /// The output does not depend on it.
    pub fn set_strip_bytes(&mut self, bytes: usize) {
        self.strip_bytes = bytes;
    }

    /// Output size in bytes from which the faces' interiors (and an ordinary face's edges) go
    /// out in whole cache lines with non-temporal stores (default 8 MiB: larger than the
    /// caches a core writes into, where reading a line before writing it costs as much as
    /// writing it). The output does not depend on it.
    pub fn set_stream_bytes(&mut self, bytes: usize) {
        self.stream_bytes = bytes;
    }

    /// Ordinary faces refined as one stack at most (default: the chains' length, 16, or 4 for
    /// faces not consecutive in the order; 1: each face alone). Faces each on the one before
    /// (`Base::stacks`, `Base::chains`) share their start rows in the composed kernel, so
    /// each start row is refined along x once. The output does not depend on it, to the bit.
    pub fn set_stack(&mut self, faces: usize) {
        self.stack = faces.max(1);
    }

    /// Whether the output is large enough for whole lines to go out non-temporally
    /// ([`Refiner::set_stream_bytes`]).
    fn streams_output(&self) -> bool {
        self.output.len() * size_of::<[T; 3]>() >= self.stream_bytes
    }

    /// Runs the kernels with `simd`, or the widest path this CPU has below it; returns the
    /// path set. Every path gives the same points ([`Simd`]).
    pub fn set_simd(&mut self, simd: Simd) -> Simd {
        self.simd = simd.min(Simd::detect());
        for plan in self
            .plans
            .iter_mut()
            .chain(self.near.as_mut().map(|n| &mut n.plan))
        {
            plan.simd = self.simd;
        }
        self.simd
    }

    /// The instruction set the kernels run with ([`Refiner::set_simd`]).
    pub fn simd(&self) -> Simd {
        self.simd
    }

    /// Steps run by the reference driver before the depth-first ones (see the module docs).
    pub fn reference_steps(&self) -> usize {
        self.first
    }

    /// Steps after the reference steps that run level by level, every level stored whole
    /// (see `patch/direct.rs`): the first steps of a mesh of small fans.
    pub fn level_steps(&self) -> usize {
        self.direct.len()
    }

    /// The level the patches start from: after the reference and the level-by-level steps.
    pub(super) fn start_level(&self) -> usize {
        self.first + self.direct.len()
    }

    /// Base faces whose points after the reference steps the reference driver gives: every
    /// face, or those near the EVs (`patch/near.rs`); none without reference steps.
    pub fn reference_faces(&self) -> usize {
        match (&self.near, self.first) {
            (_, 0) => 0,
            (Some(near), _) => self.base.topo.face_count() - near.far().len(),
            (None, _) => self.base.topo.face_count(),
        }
    }

    /// Bytes the refiner's position buffers hold now (their capacity): the start level, the
    /// fans' two levels, every worker's scratch and the output. They are kept from one
    /// `refine` to the next, and [`footprint`] bounds them.
    pub fn buffer_bytes(&self) -> usize {
        let values = |v: &Vec<T>| v.capacity();
        let fans: usize = self.fans.iter().map(values).sum();
        let scratch: usize = self
            .scratch
            .iter()
            .map(|s| {
                [&s.face, &s.interior, &s.spare, &s.p.a, &s.p.at, &s.p.row]
                    .into_iter()
                    .map(values)
                    .sum::<usize>()
            })
            .sum();
        let points = [&self.start, &self.level, &self.output]
            .map(Vec::capacity)
            .iter()
            .sum::<usize>()
            + self.handed.capacity();
        (fans + scratch + 3 * points) * size_of::<T>()
            + self.reference.as_ref().map_or(0, Reference::bytes)
            + self.near.as_ref().map_or(0, Near::bytes)
    }

    /// Wall time of the phases of the last `refine`.
    pub fn phase_seconds(&self) -> Phases {
        self.phase_seconds
    }

    /// Time of each depth-first step of the last `refine` (after [`Refiner::reference_steps`]):
    /// the level-by-level steps first ([`Refiner::level_steps`], wall time each), then the
    /// others summed over the workers, so with several threads they exceed the wall time: the
    /// fans' steps each in its own (the EV fix-up after a step in that step), the ordinary
    /// faces' composed steps all in the last.
    pub fn level_seconds(&self) -> &[f64] {
        &self.level_seconds
    }

    /// The positions of the last `refine` (without a copy).
    pub fn into_positions(self) -> Vec<[T; 3]> {
        if self.plans.is_empty() {
            self.start
        } else {
            self.output
        }
    }

    /// The last [`Refiner::refine`]'s output positions.
    pub fn positions(&self) -> &[[T; 3]] {
        if self.plans.is_empty() {
            &self.start
        } else {
            &self.output
        }
    }

    /// Refines new positions of the base vertices; returns the output positions.
    pub fn refine(&mut self, positions: &[[f64; 3]]) -> Result<&[[T; 3]], SurfaceError> {
        let clock = Instant::now();
        // The level after the reference steps: the patches' start level, or the first of the
        // level-by-level steps.
        let num = self.direct.first().map_or(&self.start_num, |d| d.old());
        // Each level-by-level step swaps the two levels: after an odd count, swap back, so that
        // every `refine` puts the same levels in the same buffer (none grows a second time).
        if self.direct.len() % 2 == 1 {
            std::mem::swap(&mut self.start, &mut self.level);
        }
        if self.first == 0 {
            // The base mesh itself: its vertices in their order (N = 1: nothing but corners).
            self.start.clear();
            self.start
                .extend(positions.iter().map(|p| p.map(T::from_f64)));
        } else {
            // Level 0: the base mesh, or the cut mesh with its ghost layers.
            let reference = self.reference.as_mut().expect("reference steps have maps");
            let extended;
            let level0 = match &self.cut {
                None => positions,
                Some(cut) => {
                    let mut at: Vec<[f64; 3]> =
                        cut.source.iter().map(|&v| positions[v as usize]).collect();
                    reference.ghosts().extend(&mut at);
                    extended = at;
                    &extended
                }
            };
            reference.run(level0, &mut self.start, self.threads);
            if let Some(near) = &self.near {
                near.far_faces(reference.before(level0), &mut self.start);
            }
            if let Some(cut) = &self.cut {
                let ring = self.scheme.surface().rings[0];
                let alpha = |v: u32| {
                    let i = self.base.special.binary_search(&v);
                    i.map_or(0.0, |i| self.alphas[i])
                };
                cut.curves(&self.base, (&alpha, ring), positions, num, &mut self.start);
            }
            // Corners stay exactly (the ghosts' double reflection gives them up to rounding);
            // every corner is a special vertex, its rule set at every step.
            let rules = self.base.special.iter().zip(self.base.vertex_rules(0));
            for (&v, _) in rules.filter(|(_, r)| **r == Some(VertexRule::Corner)) {
                self.start[v as usize] = positions[v as usize].map(T::from_f64);
            }
        }
        self.level_seconds.clear();
        self.level_seconds
            .resize(self.direct.len() + self.plans.len(), 0.0);
        for (step, seconds) in self.direct.iter().zip(&mut self.level_seconds) {
            let clock = Instant::now();
            step.run(
                &self.base,
                &self.alphas,
                &self.start,
                &mut self.level,
                (self.threads, self.simd),
            );
            std::mem::swap(&mut self.start, &mut self.level);
            *seconds = clock.elapsed().as_secs_f64();
        }
        self.phase_seconds = Phases {
            start: clock.elapsed().as_secs_f64(),
            ..Phases::default()
        };
        if self.plans.is_empty() {
            return Ok(&self.start);
        }
        // Every output point is written by the face that owns it: a buffer of the right
        // length from an earlier call is reused as it is (no zero-fill: 24 bytes a point
        // written once more per call, 1.3× on the 256 × 256 torus, docs/benchmarks.md).
        if self.output.len() != self.out_num.len() {
            self.output = vec![[T::default(); 3]; self.out_num.len()];
        }
        self.scratch.resize_with(self.threads, Scratch::default);
        let clock = Instant::now();
        self.ordinary_faces();
        self.phase_seconds.ordinary = clock.elapsed().as_secs_f64();
        let clock = Instant::now();
        self.fan_faces();
        self.phase_seconds.fans = clock.elapsed().as_secs_f64();
        Ok(&self.output)
    }

    /// Every step of the ordinary faces at once ([`composed`]), each worker a run of faces.
    /// Faces are taken in order, and each owns its interior and the edges it meets first
    /// (`Numbering`), so a worker's interiors and its edges are two ascending runs of the
    /// output, written in whole lines ([`Stream`]); corners are written as they come.
    fn ordinary_faces(&mut self) {
        let Some(composed) = &self.composed else {
            return;
        };
        let streaming = self.streams_output();
        let out = SharedOut::new(&mut self.output);
        let (out, start, simd, most) = (&out, &self.start, self.simd, self.stack);
        let num = &self.out_num;
        let (n0, first, n) = (self.start_num.n, self.start_level(), num.n as usize);
        let k = n - 1;
        let table = &self.start_gather;
        let base = &self.base;
        let chunk = self.ordinary.len().div_ceil(self.threads).max(1);
        let work = self
            .ordinary
            .chunks(chunk)
            .zip(self.stacks.chunks(chunk))
            .zip(&mut self.scratch);
        let times = in_threads(work, |((faces, stacks), scratch)| {
            let clock = Instant::now();
            let buf = grown(&mut scratch.face, composed.scratch_len());
            // SAFETY: the interior points and the points of the edges of these faces are written
            // by this worker only, each by one writer of the pools.
            let writers = |_| unsafe { out.stream(streaming, simd) };
            let (interiors, edges) = (
                Writers::new(WRITERS, writers),
                Writers::new(WRITERS, writers),
            );
            let mut w = Ordinary {
                faces,
                stacks,
                i: 0,
                most,
                source: Source::Start {
                    table,
                    start,
                    first,
                    phantoms: true,
                },
                give: None,
                base,
                num,
                out,
                layout: ring_layout(n0, false),
                spare: grown(&mut scratch.spare, 3 * k * 3),
                interiors,
                edges,
            };
            composed.run(simd, buf, &mut w);
            w.interiors.finish();
            w.edges.finish();
            if streaming {
                stream::fence();
            }
            clock.elapsed().as_secs_f64()
        });
        if let Some(last) = self.level_seconds.last_mut() {
            *last += times.iter().sum::<f64>();
        }
    }

    /// Every step of the faces around EVs, in lock-step: each step refines every fan patch,
    /// then sets the EV children and the ring points next to them (see the module docs).
    fn fan_faces(&mut self) {
        if self.fan_faces.is_empty() {
            return;
        }
        let st = self.scheme.surface();
        let start_level = self.start_level();
        // Each step transposes: start so that the last level comes out row-major, which
        // the scatter reads best, or where the composed kernel takes the last step, so that
        // the level before it is (the kernel's start rows are the patch's rows).
        let mut a_is_x = (self.plans.len() % 2 == 1) != self.fan_last.is_some();
        let m = (self.start_num.n + 3) as usize;
        let streaming = self.streams_output();
        let [old, new] = &mut self.fans;
        let faces = self.fan_faces.len();
        let hands_rings = self.handoff.as_ref().is_some_and(Handoff::hands_rings);
        // With one step, taken by the composed kernel, the kernel gathers each fan face's
        // patch from the start level itself, as it does an ordinary face's; else they are
        // gathered here, for the lock-step.
        let gathered = !(self.plans.len() == 1 && self.fan_last.is_some());
        let start = grown(old, if gathered { faces * m * m * 3 } else { 0 });
        let chunks = start.chunks_exact_mut(m * m * 3).zip(&self.fan_faces);
        for (s, (patch, &f)) in chunks.enumerate() {
            let t = &self.start_gather[f as usize * m * m..][..m * m];
            let layout = ring_layout(self.start_num.n, a_is_x);
            // A point the start level does not have (an EV's diagonal) loads as zero: for a
            // face whose box hands its ring that is every phantom.
            load(t, &self.start, layout, patch);
            if !self.handoff.as_ref().is_some_and(|h| h.hands_ring(s)) {
                self.base
                    .load_phantoms((f, self.start_num.n, start_level), layout, patch);
            }
        }
        let mut n = self.start_num.n;
        let out = SharedOut::new(&mut self.output);
        let handoff = self.handoff.as_ref();
        let (fan_last, base, simd) = (self.fan_last.as_ref(), &self.base, self.simd);
        let (table, start) = (&self.start_gather[..], &self.start[..]);
        let handed = &mut self.handed;
        handed.resize(handoff.map_or(0, Handoff::len), [T::default(); 3]);
        for (s, plan) in self.plans.iter().enumerate() {
            let last = s + 1 == self.plans.len();
            let chunk = self.fan_faces.len().div_ceil(self.threads).max(1);
            let (out, out_num, strip_bytes) = (&out, &self.out_num, self.strip_bytes);
            let streaming = last && streaming;
            let (n_new, new_a_is_x) = (plan.n_new, !a_is_x);
            let layouts = (ring_layout(n, a_is_x), ring_layout(n_new, new_a_is_x));
            let offsets = (Offsets::new(n, layouts.0), Offsets::new(n_new, layouts.1));
            let gives = &SharedOut::new(handed);
            // Each worker's faces' patches, old and new (none kept after the last step).
            let (old_len, new_len) = (patch_len(n), if last { 0 } else { patch_len(n_new) });
            let olds = &old[..if gathered { faces * old_len } else { 0 }];
            let news = pieces(grown(new, faces * new_len), chunk * new_len, self.threads);
            let work = self
                .fan_faces
                .chunks(chunk)
                .zip(
                    olds.chunks(chunk * old_len)
                        .chain(std::iter::repeat(&[][..])),
                )
                .zip(news)
                .zip(&mut self.scratch)
                .enumerate();
            let times = in_threads(work, |(i, (((faces, old), new), scratch))| {
                let mut clock = Instant::now();
                if let Some(kernel) = fan_last.filter(|_| last) {
                    // (Row-major: the kernel's start rows are rows of the patch.)
                    assert!(!layouts.0.a_is_x, "the fans' last level comes row-major");
                    let k = (out_num.n - 1) as usize;
                    let buf = grown(&mut scratch.face, kernel.scratch_len());
                    // SAFETY: as for the ordinary faces.
                    let writers = |_| unsafe { out.stream(streaming, simd) };
                    let mut w = Ordinary {
                        faces,
                        stacks: &[],
                        i: 0,
                        most: 1,
                        source: if gathered {
                            Source::Fans(old)
                        } else {
                            Source::Start {
                                table,
                                start,
                                first: start_level,
                                phantoms: !hands_rings,
                            }
                        },
                        give: handoff.map(|h| (h, &offsets.0, gives, i * chunk)),
                        base,
                        num: out_num,
                        out,
                        layout: layouts.0,
                        spare: grown(&mut scratch.spare, 3 * k * 3),
                        interiors: Writers::new(WRITERS, writers),
                        edges: Writers::new(WRITERS, writers),
                    };
                    kernel.run(simd, buf, &mut w);
                    w.interiors.finish();
                    w.edges.finish();
                    if streaming {
                        stream::fence();
                    }
                    return lap(&mut clock);
                }
                // The last level's interior of a face: staged whole, if it fits the stage, and
                // written as one run (consecutive faces' runs continue each other); else one
                // writer per row (a row's strips continue each other, so only a row's two ends
                // are partial lines).
                let k = (out_num.n - 1) as usize;
                let whole = k * k * 3;
                let staged = last && whole <= STAGE;
                let stage = grown(&mut scratch.interior, if staged { whole } else { 0 });
                // SAFETY: the interior points of these faces are written by this worker only,
                // by this writer or (one per row) those below.
                let mut interiors = unsafe { out.stream(streaming, Simd::Baseline) };
                let mut rows = Vec::new();
                // (None kept after the last step: every `dst` empty.)
                let mut news = new.chunks_exact_mut(new_len.max(1));
                for (q, (&f, src)) in faces.iter().zip(old.chunks_exact(old_len)).enumerate() {
                    let dst = news.next().unwrap_or_default();
                    if last {
                        if !staged {
                            rows.extend((0..=out_num.n).map(|_| {
                                // SAFETY: as above, each row by its own writer.
                                unsafe { out.stream(streaming, Simd::Baseline) }
                            }));
                        }
                        // Edges 1 (x = N', t = y) and 3 (x = 0, t = N' − y) where face f owns
                        // them: the run of each, for the inner rows' end points.
                        let sides = [1, 3].map(|l| {
                            let (e, forward, owner) = out_num.faces[f as usize].edge(l);
                            owner.then_some((out_num.nv + e as usize * k, forward))
                        });
                        // Strips of rows y (the parity chosen above), x from a0: the interior
                        // points as a run, the border by ownership (an inner row's two ends
                        // straight to their edges).
                        let each = |a0: usize, y: usize, row: &[T]| {
                            let point = |x: i64, _| {
                                let i = (x as usize - a0) * 3;
                                [row[i], row[i + 1], row[i + 2]]
                            };
                            let (x0, y) = (a0 as i64, y as i64);
                            let xs = x0..=x0 + (row.len() / 3) as i64 - 1;
                            let n = out_num.n;
                            let (lo, hi) = ((*xs.start()).max(1), (*xs.end()).min(n - 1));
                            if (1..n).contains(&y) && lo <= hi {
                                let (a, b) = ((lo - x0) as usize * 3, (hi - x0 + 1) as usize * 3);
                                if staged {
                                    let at = ((y - 1) as usize * k + (lo - 1) as usize) * 3;
                                    stage[at..at + b - a].copy_from_slice(&row[a..b]);
                                } else {
                                    let (first, _) = out_num.index(f as usize, lo, y);
                                    // SAFETY: face f's interior is written by face f only.
                                    unsafe { rows[y as usize].run(first * 3, &row[a..b]) };
                                }
                            }
                            if y == 0 || y == n {
                                scatter_border(out_num, f as usize, &xs, &(y..=y), point, out);
                                return;
                            }
                            for ((x, t), side) in [(n, y), (0, n - y)].into_iter().zip(sides) {
                                if let Some((run, forward)) = side.filter(|_| xs.contains(&x)) {
                                    let i = run + along_edge(t, n, forward);
                                    // SAFETY: face f is the only writer of an edge it owns.
                                    unsafe { out.write(i, &point(x, y)) };
                                }
                            }
                        };
                        plan.step_strips(src, &mut scratch.p, strip_bytes, each);
                        if staged {
                            let at = out_num.interior(f as usize) * 3;
                            // SAFETY: face f's interior is written by face f only.
                            unsafe { interiors.run(at, &stage[..whole]) };
                        }
                        rows.drain(..).for_each(Stream::finish);
                    } else {
                        plan.step_transposing(src, &mut scratch.p, strip_bytes, dst);
                    }
                    if let Some(h) = handoff {
                        let new = (!last).then_some((&dst[..], &offsets.1));
                        // SAFETY: each point of the box has one giver; nothing reads the box
                        // until the workers are done.
                        unsafe { h.give(i * chunk + q, (src, &offsets.0), new, gives) };
                    }
                }
                interiors.finish();
                if streaming {
                    stream::fence();
                }
                lap(&mut clock)
            });
            let mut clock = Instant::now();
            let ring = st.rings[(start_level + s).min(st.rings.len() - 1)];
            let fans = Fans {
                slot: &self.fan_slot,
                patches: olds,
                n,
                a_is_x,
            };
            let k = start_level + s;
            // The vertex children from the level before, the special vertices split among the
            // workers.
            let base = &self.base;
            let per = base.special.len().div_ceil(self.threads).max(BETWEEN);
            let specials = base.special.chunks(per).zip(self.alphas.chunks(per));
            let handed = &*handed;
            let children: Vec<Option<[T; 3]>> = in_threads(
                specials.zip(base.vertex_rules(k).chunks(per)).enumerate(),
                |(c, ((vs, alphas), rules))| {
                    let each = vs.iter().zip(alphas).zip(rules).enumerate();
                    each.map(|(q, ((&v, &alpha), rule))| {
                        let ev = base.topo.valence(v) != 4;
                        rule.map(|rule| match (rule, handoff) {
                            (VertexRule::Smooth, Some(h)) if ev => {
                                let one = h.ring(c * per + q, handed);
                                ev_child(base.topo, v, (alpha, ring), |k, _, spot| {
                                    one.point(k, spot)
                                })
                            }
                            _ => {
                                let at = |f: u32, x: i64, y: i64| match gathered {
                                    true => *fans.point(f, x, y),
                                    // The start level's point, by the kernel's table (x-major).
                                    false => {
                                        let at = ring_layout(n, true).at(x, y) / 3;
                                        start[table[f as usize * m * m + at] as usize]
                                    }
                                };
                                vertex_child(base, (v, rule, alpha), (plan, ring, k), n, at)
                            }
                        })
                    })
                    .collect::<Vec<_>>()
                },
            )
            .into_iter()
            .flatten()
            .collect();
            if last {
                for (&v, child) in base.special.iter().zip(&children) {
                    if let Some(child) = child {
                        // SAFETY: the workers are done; nothing else writes the output now.
                        unsafe { out.write(v as usize, child) };
                    }
                }
            } else {
                let layout = layouts.1;
                let (faces, slot) = (&self.fan_faces, &self.fan_slot);
                // The ring points each face takes from its neighbours, all read before any
                // patch changes (they are inside the neighbours, where nothing below writes);
                // those of a face without phantoms beside its EV corners were handed on
                // during the step.
                let chunk = faces.len().div_ceil(self.threads).max(BETWEEN);
                let new_level = &new[..faces.len() * new_len];
                let rings = if hands_rings {
                    Vec::new()
                } else {
                    in_threads(faces.chunks(chunk), |faces| {
                        let mut got = Vec::new();
                        let handed = |f: u32| {
                            handoff.is_some_and(|h| h.hands_ring(slot[f as usize] as usize))
                        };
                        for &f in faces.iter().filter(|&&f| !handed(f)) {
                            let mut put = |at, p| got.push((f, at, p));
                            let new = new_level;
                            base.refresh_ring((f, n_new, k + 1), layout, slot, new, &mut put);
                        }
                        got
                    })
                };
                let rings = rings.into_iter().chain(std::iter::repeat_with(Vec::new));
                // Then each face's own patch: the children at its corners, those ring points,
                // its phantoms.
                let patches = new[..faces.len() * new_len].chunks_mut(chunk * new_len);
                let work = faces.chunks(chunk).zip(patches).zip(rings);
                in_threads(work.enumerate(), |(i, ((faces, patches), got))| {
                    let mut got = got.into_iter().peekable();
                    let patches = patches.chunks_exact_mut(new_len);
                    for (q, (&f, patch)) in faces.iter().zip(patches).enumerate() {
                        for c in 0..4u8 {
                            let i = base.special_at[base.topo.vertex(f, c) as usize];
                            if let Some(&Some(child)) = children.get(i as usize) {
                                let (x, y) = corner_at(c, n_new, n_new);
                                let at = layout.at(x, y);
                                patch[at..at + 3].copy_from_slice(&child);
                            }
                        }
                        while let Some((_, at, p)) = got.next_if(|g| g.0 == f) {
                            patch[at..at + 3].copy_from_slice(&p);
                        }
                        match handoff.filter(|h| h.hands_ring(i * chunk + q)) {
                            Some(h) => h.take(i * chunk + q, &offsets.1, handed, patch),
                            None => base.load_phantoms((f, n_new, k + 1), layout, patch),
                        }
                    }
                });
            }
            std::mem::swap(old, new);
            self.level_seconds[self.direct.len() + s] +=
                times.iter().sum::<f64>() + lap(&mut clock);
            n = n_new;
            a_is_x = new_a_is_x;
        }
        // Each step swapped the two levels: after an odd count, swap back, so that every
        // `refine` puts the same levels in the same buffer. Otherwise the next one would grow
        // the buffer of level s − 2 to level s − 1 as well, past what `footprint` counts.
        if self.plans.len() % 2 == 1 {
            self.fans.swap(0, 1);
        }
    }

    /// The output quads: every face of the base mesh but the holes becomes an N × N grid.
    pub fn faces(&self) -> Vec<[u32; 4]> {
        let num = &self.out_num;
        let n = num.n;
        let nf = self.base.topo.face_count();
        let mut faces = Vec::with_capacity(nf * (n * n) as usize);
        for f in (0..nf).filter(|&f| !self.base.features.is_hole(f as u32)) {
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

/// A worker's run of faces for [`Composed::run`] (ordinary faces, or fan faces at their last
/// step): where their start patches are ([`Source`]) and where their points go. Each face owns
/// its interior and the edges it meets first (`Numbering`), and faces are taken in order, so
/// a worker's interiors and its edges are two ascending runs of the output ([`Stream`]);
/// corners are written as they come (a fan face's corners at special vertices are written
/// again by their children afterwards).
struct Ordinary<'a, 'w, T> {
    faces: &'a [u32],
    /// Per face: whether the next face stacks on it ([`Faces::load`]); a stack ends with the
    /// worker's faces.
    stacks: &'a [bool],
    /// The first face (in `faces`) of the stack loaded last.
    i: usize,
    /// Faces in a stack at most ([`Refiner::set_stack`]).
    most: usize,
    source: Source<'a, T>,
    /// Where each face loaded hands its corners' 1-ring points on ([`Handoff::give`]: the
    /// handoff, the offsets of the loaded patch, the box, the slot of the first face).
    give: Option<(&'a Handoff, &'a Offsets, &'a SharedOut<T>, usize)>,
    base: &'a Base<'a>,
    num: &'a Numbering,
    out: &'a SharedOut<T>,
    layout: Layout,
    /// Room for three edge runs: columns 1 and 3 gathered, and a row reversed.
    spare: &'w mut [T],
    interiors: Writers<'a, T>,
    edges: Writers<'a, T>,
}

impl<T: Real> Faces<T> for Ordinary<'_, '_, T> {
    fn count(&self) -> usize {
        self.faces.len()
    }

    /// Face i, and the faces after it that stack on it, their start rows shared: each face
    /// after the first adds its rows y = 2..=N₀+1 (those above the face below).
    #[inline(always)]
    fn load(&mut self, i: usize, most: usize, patch: &mut [T]) -> usize {
        let m = self.layout.side;
        let n0 = m - 3;
        let stack = match self.source {
            Source::Start {
                table,
                start,
                first,
                phantoms,
            } => {
                let mut stack = 1;
                let most = most.min(self.most);
                while stack < most && i + stack < self.faces.len() && self.stacks[i + stack - 1] {
                    stack += 1;
                }
                for q in 0..stack {
                    let f = self.faces[i + q] as usize;
                    let table = &table[f * m * m..][..m * m];
                    let from = if q == 0 { 0 } else { 3 };
                    load_rows(
                        table,
                        start,
                        self.layout,
                        &mut patch[q * n0 * m * 3..],
                        from,
                    );
                }
                if stack == 1 && phantoms {
                    let f = self.faces[i];
                    self.base
                        .load_phantoms((f, n0 as i64, first), self.layout, patch);
                }
                stack
            }
            Source::Fans(patches) => {
                let len = m * m * 3;
                patch[..len].copy_from_slice(&patches[i * len..][..len]);
                1
            }
        };
        if let Some((handoff, offsets, to, slot)) = self.give {
            // SAFETY: each point of the box has one giver, and nothing reads it until the
            // workers are done (`Refiner::fan_faces`).
            unsafe { handoff.give(slot + i, (&patch[..m * m * 3], offsets), None, to) };
        }
        self.i = i;
        stack
    }

    /// Face f's rows 0 and N' hold edge 0 and edge 2 and the corners: only if f owns one of
    /// them.
    #[inline(always)]
    fn wants(&self, q: usize, y: usize) -> bool {
        let f = self.faces[self.i + q] as usize;
        // (No closure here: in the kernel it would be a call, `composed::madd`.)
        let (edge, [c, d]) = if y == 0 { (0, [0, 1]) } else { (2, [3, 2]) };
        let r = &self.num.faces[f];
        r.edge(edge).2 || r.owns_corner(c) || r.owns_corner(d)
    }

    /// Point 0 of rows 1..N' − 1 is edge 3's.
    #[inline(always)]
    fn wants_left(&self, q: usize) -> bool {
        self.num.faces[self.faces[self.i + q] as usize].edge(3).2
    }

    /// Writes the points of a band of face q's rows: its interior, the corners and edges it
    /// owns (edge 0 with the first band, the others with the last, a column's points set out
    /// band by band).
    #[inline(always)]
    fn face(&mut self, q: usize, rows: Rows<'_, T>) {
        let f = self.faces[self.i + q] as usize;
        // The face's numbering, read once: the stores below go through raw pointers, after
        // which every field read through `self` would be read again.
        let num = self.num;
        let r = num.faces[f];
        let (nv, interior) = (num.nv, num.interior(f));
        let n = num.n as usize;
        let (k, ys) = (n - 1, rows.ys());
        let len = k * 3;
        // Corners: c = 0..4 at (0, 0), (N', 0), (N', N'), (0, N').
        for (c, (y, x)) in [(0, 0), (0, n), (n, n), (n, 0)].into_iter().enumerate() {
            if r.owns_corner(c) && ys.contains(&y) {
                let b = &rows.row(y)[x * 3..x * 3 + 3];
                // SAFETY: face f is the only writer of a corner it owns.
                unsafe { self.out.write(r.vertex[c] as usize, &[b[0], b[1], b[2]]) };
            }
        }
        // Edge l's points t = 1..N'−1 from corner l: along row 0 (x = t), column N' (y = t),
        // row N' (x = N' − t) and column 0 (y = N' − t); its run starts at its smaller
        // vertex, so it goes along increasing x or y if `forward == (l < 2)`. Columns 1 and
        // 3 are set out in `spare` band by band.
        let inner = rows.inner();
        for l in [1, 3] {
            let (_, forward, owner) = r.edge(l);
            if owner {
                let x = if l == 1 { n } else { 0 };
                let column = &mut self.spare[l / 2 * len..][..len];
                for y in inner.clone() {
                    let t = if forward == (l < 2) { y - 1 } else { k - y };
                    column[t * 3..t * 3 + 3].copy_from_slice(&rows.row(y)[x * 3..x * 3 + 3]);
                }
            }
        }
        for l in 0..4 {
            let (e, forward, owner) = r.edge(l);
            let ready = if l == 0 {
                ys.start == 0
            } else {
                ys.end == n + 1
            };
            if !owner || !ready {
                continue;
            }
            let run = match l {
                0 | 2 => {
                    let line = &rows.row(if l == 0 { 0 } else { n })[3..3 + len];
                    if forward == (l < 2) {
                        line
                    } else {
                        reversed(line, &mut self.spare[2 * len..])
                    }
                }
                _ => &self.spare[l / 2 * len..][..len],
            };
            let at = (nv + e as usize * k) * 3;
            // SAFETY: face f is the only writer of the points of an edge it owns.
            unsafe { self.edges.run(at, run) };
        }
        // The interior, rows 1..N' − 1 one after the other: one run over the bands.
        if !inner.is_empty() {
            let at = (interior + (inner.start - 1) * k) * 3;
            // SAFETY: face f's interior is written by face f only.
            unsafe { self.interiors.run(at, rows.inside()) };
        }
    }
}

/// Where the composed kernel's faces take their patches from.
#[derive(Clone, Copy)]
enum Source<'a, T> {
    /// Gathered from the start level by its table (a missing point as zero), phantoms set by
    /// step `first`'s rules if `phantoms` (ordinary faces, every depth-first step composed;
    /// fan faces whose only step is the last).
    Start {
        table: &'a [u32],
        start: &'a [[T; 3]],
        first: usize,
        phantoms: bool,
    },
    /// The fan faces' patches of the level before the last, one after the other, phantoms
    /// set, row-major (their last step).
    Fans(&'a [T]),
}

/// The points of `line` in reverse order, in `spare`.
#[inline(always)]
fn reversed<'s, T: Copy>(line: &[T], spare: &'s mut [T]) -> &'s [T] {
    for (d, s) in spare.chunks_exact_mut(3).zip(line.chunks_exact(3).rev()) {
        d.copy_from_slice(s);
    }
    &spare[..line.len()]
}

/// Writes the points (x, y) ∈ `xs` × `ys` of face f's final patch (`point(x, y)`) on the
/// border of the face that face f owns ([`owned_border`]).
fn scatter_border<T: Real>(
    num: &Numbering,
    f: usize,
    xs: &std::ops::RangeInclusive<i64>,
    ys: &std::ops::RangeInclusive<i64>,
    point: impl Fn(i64, i64) -> [T; 3],
    out: &SharedOut<T>,
) {
    owned_border(num, f, xs, ys, |x, y, i| {
        // SAFETY: face f is the only writer of the points of an edge or corner it owns.
        unsafe { out.write(i, &point(x, y)) }
    });
}

/// The points (x, y) ∈ `xs` × `ys` on the border of face f that face f owns, points of
/// owned edges and owned corners, as `put(x, y, index)`.
fn owned_border(
    num: &Numbering,
    f: usize,
    xs: &std::ops::RangeInclusive<i64>,
    ys: &std::ops::RangeInclusive<i64>,
    mut put: impl FnMut(i64, i64, usize),
) {
    let n = num.n;
    let k = (n - 1) as usize;
    let inner = |r: &std::ops::RangeInclusive<i64>| (*r.start()).max(1)..(*r.end()).min(n - 1) + 1;
    let (ix, iy) = (inner(xs), inner(ys));
    for (l, &(dx, dy)) in TOWARD_NEXT.iter().enumerate() {
        let (e, forward, owner) = num.faces[f].edge(l);
        let (cx, cy) = corner_at(l as u8, n, n);
        if owner {
            // Points t = 1..N−1 of edge l (from corner l) inside the rectangle.
            let ts = match l {
                0 if ys.contains(&0) => ix.clone(),
                2 if ys.contains(&n) => n - ix.end + 1..n - ix.start + 1,
                1 if xs.contains(&n) => iy.clone(),
                3 if xs.contains(&0) => n - iy.end + 1..n - iy.start + 1,
                _ => 0..0,
            };
            let base = num.nv + e as usize * k;
            for t in ts {
                put(cx + t * dx, cy + t * dy, base + along_edge(t, n, forward));
            }
        }
        if num.faces[f].owns_corner(l) && xs.contains(&cx) && ys.contains(&cy) {
            put(cx, cy, num.faces[f].vertex[l] as usize);
        }
    }
}

/// Seconds since `clock`, which is reset to now.
fn lap(clock: &mut Instant) -> f64 {
    let now = Instant::now();
    let t = (now - *clock).as_secs_f64();
    *clock = now;
    t
}

/// Vertices and quads of a quad mesh of V vertices, E edges and F quads after every edge is
/// split into n: V + E(n − 1) + F(n − 1)², and F n² (saturating).
pub fn output_counts(vertices: u128, edges: u128, faces: u128, n: u128) -> (u128, u128) {
    let k = n.saturating_sub(1);
    (
        vertices
            .saturating_add(edges.saturating_mul(k))
            .saturating_add(faces.saturating_mul(k).saturating_mul(k)),
        faces.saturating_mul(n).saturating_mul(n),
    )
}

/// Vertices and quads [`subdivide_with`] writes when every edge splits into n and the holes'
/// points that no other face uses are dropped: each vertex, edge and face counted once if a
/// face that is not a hole has it.
fn written_counts(topo: &Topology, features: &Resolved, n: u128) -> (u128, u128) {
    let kept = |f: u32| !features.is_hole(f);
    let faces = (0..topo.face_count() as u32).filter(|&f| kept(f)).count() as u128;
    let mut edge = vec![false; topo.edge_count()];
    let mut vertex = vec![false; topo.vertex_count()];
    for f in (0..topo.face_count() as u32).filter(|&f| kept(f)) {
        for l in 0..4 {
            edge[topo.edge_of(f, l) as usize] = true;
            vertex[topo.vertex(f, l) as usize] = true;
        }
    }
    let count = |v: &[bool]| v.iter().filter(|&&b| b).count() as u128;
    output_counts(count(&vertex), count(&edge), faces, n)
}

/// What a refinement by [`Refiner`] makes and holds, in bytes at most (see [`footprint`]).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Footprint {
    /// Output vertices, exactly ([`output_counts`]).
    pub vertices: u128,
    /// Output quads, exactly.
    pub quads: u128,
    /// The input: its positions (f64), its quads and its [`Topology`].
    pub input: u128,
    /// The refiner's buffers at their peak: the start level and its patch table, its
    /// per-element tables, the fans' two levels, each worker's scratch, and the output.
    pub refining: u128,
    /// The output mesh alone (positions and quads), what remains after refining.
    pub output: u128,
}

/// The footprint of `steps` steps of a scheme (tables `t`, masks contained near EVs from step
/// `contained_from`) on `mesh` by a [`Refiner`] with `threads` workers and positions of
/// `scalar_bytes` bytes, predicted from the label words before anything is built (saturating).
/// It follows the refiner's plan: the steps before masks are contained run on the whole mesh
/// when it has EVs, the first steps of a mesh of small fans level by level
/// (`patch/direct.rs`), then faces with an EV corner are refined as whole patches in
/// lock-step, the others composed (`patch/composed.rs`), with a face's scratch per worker.
pub fn footprint(
    t: &CurveTables<'_>,
    contained_from: usize,
    topo: &Topology,
    features: &Features,
    steps: usize,
    scalar_bytes: u128,
    threads: usize,
) -> Footprint {
    let n = |s: usize| t.image_len(t.axiom, s);
    let (v0, e0, f0) = (
        topo.vertex_count() as u128,
        topo.edge_count() as u128,
        topo.face_count() as u128,
    );
    // The refiner's split of the faces (every face in lock-step if the features do not
    // resolve: the refiner refuses them, and the bound stays a bound).
    let base = Resolved::new(topo, features)
        .ok()
        .and_then(|r| Base::new(topo, r, steps).ok());
    let (vertices, quads) = match &base {
        Some(b) if b.features.has_holes() => written_counts(topo, &b.features, n(steps)),
        _ => output_counts(v0, e0, f0, n(steps)),
    };
    let fan_faces = match &base {
        Some(b) => (0..topo.face_count() as u32)
            .filter(|&f| !b.ordinary(f))
            .count() as u128,
        None => f0,
    };
    let first = if base.as_ref().is_some_and(|b| !b.needs_containment) {
        0
    } else {
        contained_from.min(steps)
    };
    // The depth-first steps run level by level (`patch/direct.rs`), and the level the
    // patches start from.
    let lead = base.as_ref().map_or(0, |b| {
        let sides = (first..steps).map(|s| i64::try_from(n(s + 1)).unwrap_or(i64::MAX));
        direct::leading(b, usize::try_from(fan_faces).unwrap_or(usize::MAX), sides)
    });
    let start_level = first + lead;
    let point = 3 * scalar_bytes;
    // Points of a patch with its ring after s steps.
    let side = |s: usize| {
        let m = n(s).saturating_add(3);
        m.saturating_mul(m)
    };
    let input = v0 * 24 + f0 * 16 + f0 * 160;
    // The start level, every face's start patch as u32 indices, and the faces' rules.
    // An open mesh's reference step runs on it with its ghost layers ([`Ghosts`]): two
    // vertices and two faces per boundary vertex and edge, six and four more per corner.
    // A reference step on a mesh with features runs on it cut along its sharp edges, with its
    // ghost layers ([`Cut`], [`Ghosts`]): at most two ghost vertices and faces per side of
    // each sharp edge, six and four more per corner sector.
    let cut = match &base {
        Some(b) if first > 0 && !b.features.is_plain() => {
            let sharp = (0..topo.edge_count() as u32)
                .filter(|&e| b.features.edge_sharp(e, 0))
                .count() as u128;
            let corners = (0..topo.vertex_count() as u32)
                .filter(|&v| b.features.vertex_rule(topo, v, 0) == VertexRule::Corner)
                .count() as u128;
            // A corner has a quadrant of ghosts per sector: at most one per face.
            let per_corner = corners.saturating_mul(4);
            Some((
                sharp,
                4 * sharp + 6 * per_corner,
                4 * sharp + 4 * per_corner,
            ))
        }
        _ => None,
    };
    let ghosts = cut.map_or(0, |(_, gv, gf)| output_counts(gv, 4 * gf, gf, n(first)).0);
    // The reference steps' maps and levels (`patch/reference.rs`): on the base mesh, or on the
    // mesh cut along its sharp edges (a vertex gets a copy per sector past its first, at most
    // two per sharp edge; each sharp edge one) with its ghosts.
    let level0 = cut.map_or((v0, e0, f0), |(sharp, gv, gf)| {
        (v0 + 2 * sharp + gv, e0 + sharp + 4 * gf, f0 + gf)
    });
    // And, where the last one runs near the EVs only (`patch/near.rs`), per base face at
    // most: its flag, its place in the far list, its patch at the level before and its new
    // points as indices.
    let reference = if first > 0 {
        // How the ghosts are made: each way makes two points or more.
        let made = cut.map_or(0, |(_, gv, _)| gv * size_of::<Ghost>() as u128);
        let new = n(first).saturating_add(1);
        let near = new.saturating_mul(new).saturating_add(side(first - 1));
        let near = near.saturating_mul(4).saturating_add(5);
        reference::bound(t, level0, first)
            .saturating_add(f0.saturating_mul(near))
            .saturating_add(made)
    } else {
        0
    };
    // Each face's and special vertex's rules per step until they settle (`Base::rules`).
    let rules = base.as_ref().map_or(0, |b| {
        let faces = (b.rules.len() * size_of::<FaceRules>()) as u128;
        faces.saturating_add((b.vertex_rules.len() * size_of::<Option<VertexRule>>()) as u128)
    });
    // The per-element tables: each face's numbering, diagonals, slot among the ordinary or
    // the fan faces and in `fan_slot`, chain link and hole flag; each edge's sharpness; each
    // vertex's sharpness, lock-step flag and place among the special vertices.
    let per_face = size_of::<FaceNumbering>() + size_of::<[u32; 4]>() + 2 * size_of::<u32>() + 2;
    let tables = f0
        .saturating_mul(per_face as u128)
        .saturating_add(e0)
        .saturating_add(6 * v0);
    let start = output_counts(v0, e0, f0, n(start_level))
        .0
        .saturating_add(ghosts)
        .saturating_mul(point)
        .saturating_add(f0.saturating_mul(side(start_level)).saturating_mul(4))
        .saturating_add(rules)
        .saturating_add(tables);
    // The fans' two levels (the last step writes straight to the output), and each worker's
    // scratch: bounded by two patches of the last level (a fan step's strips and staged
    // interior; an ordinary stack's rows refined along x, a band of a face's final rows and
    // its edge runs; at least 8192 points).
    // The level-by-level steps: the level before the start level (a buffer as large as it at
    // most), and per step its tables: each face's patch as indices, the border points it
    // owns (index pairs), each EV's 1-ring (its vertex and two points per face corner at it).
    let direct = if lead > 0 {
        (first..start_level).fold(
            output_counts(v0, e0, f0, n(start_level))
                .0
                .saturating_mul(point),
            |a, k| {
                let border = f0.saturating_mul(n(k + 1).saturating_mul(4).saturating_add(5)) * 8;
                let rings = (2 * v0 + 8 * f0 + 1) * 4;
                a.saturating_add(f0.saturating_mul(side(k)).saturating_mul(4))
                    .saturating_add(border)
                    .saturating_add(rings)
            },
        )
    } else {
        0
    };
    let fans = if steps > start_level {
        let before = |k: usize| side(steps.saturating_sub(k).max(start_level));
        fan_faces
            .saturating_mul(before(1).saturating_add(before(2)))
            .saturating_mul(point)
    } else {
        0
    };
    // What the fan faces hand each other between levels, and its box ([`Handoff`]).
    let handoff = fan_faces.saturating_mul(handoff::bytes_per_fan_face(point));
    let workers = (threads.max(1) as u128)
        .saturating_mul(side(steps).max(8192))
        .saturating_mul(2 * point);
    let output = vertices
        .saturating_mul(point)
        .saturating_add(quads.saturating_mul(16));
    Footprint {
        vertices,
        quads,
        input,
        refining: [start, reference, direct, fans, handoff, workers, output]
            .iter()
            .fold(0u128, |a, &b| a.saturating_add(b)),
        output,
    }
}

/// Refines a quad mesh once (boundaries edge-and-corner, nothing sharp): [`Topology::build`],
/// then [`subdivide_with`].
pub fn subdivide<S: SurfaceScheme + Sync, T: Real>(
    scheme: &S,
    mesh: &QuadMesh,
    steps: usize,
    threads: usize,
) -> Result<QuadMesh<T>, SurfaceError> {
    let topo = Topology::build(mesh)?;
    subdivide_with(scheme, mesh, &topo, &Features::default(), steps, threads)
}

/// Refines a quad mesh once, its topology `topo` at hand: `Refiner::with_features`,
/// `refine`, `faces`; with holes, the vertices only holes used are dropped (the others keep
/// their order).
pub fn subdivide_with<S: SurfaceScheme + Sync, T: Real>(
    scheme: &S,
    mesh: &QuadMesh,
    topo: &Topology,
    features: &Features,
    steps: usize,
    threads: usize,
) -> Result<QuadMesh<T>, SurfaceError> {
    let mut r = Refiner::with_features(scheme, topo, features, steps, threads)?;
    r.refine(&mesh.positions)?;
    let faces = r.faces();
    let kept = used(&faces, r.output_vertices(), r.base.features.has_holes());
    Ok(QuadMesh {
        positions: keep(&kept, r.into_positions()),
        faces: renumbered(&kept, faces),
    })
}

/// A refined mesh on its limit surface ([`limit_with`]).
#[derive(Clone, Debug, PartialEq)]
pub struct Refined<T = f64> {
    /// The refined mesh, each vertex at its limit point.
    pub mesh: QuadMesh<T>,
    /// The unit limit normal of each vertex ([`SurfaceLimit::normals`]).
    pub normals: Vec<[T; 3]>,
    /// The vertices whose limit normal (a dart's: and point) is not derived in closed form
    /// ([`SurfaceLimit::approximate`]).
    pub approximate: Vec<u32>,
}

/// [`subdivide_with`], then every vertex taken to its limit point, with its limit normal
/// ([`Refiner::limit`]).
pub fn limit_with<S: SurfaceScheme + Sync, T: Real>(
    scheme: &S,
    mesh: &QuadMesh,
    topo: &Topology,
    features: &Features,
    steps: usize,
    threads: usize,
) -> Result<Refined<T>, SurfaceError> {
    let mut r = Refiner::with_features(scheme, topo, features, steps, threads)?;
    r.refine(&mesh.positions)?;
    let SurfaceLimit {
        positions,
        normals,
        approximate,
    } = r.limit()?;
    let faces = r.faces();
    let kept = used(&faces, positions.len(), r.base.features.has_holes());
    let approximate = match &kept {
        Some(map) => approximate
            .into_iter()
            .map(|v| map[v as usize])
            .filter(|&v| v != u32::MAX)
            .collect(),
        None => approximate,
    };
    Ok(Refined {
        mesh: QuadMesh {
            positions: keep(&kept, positions),
            faces: renumbered(&kept, faces),
        },
        normals: keep(&kept, normals),
        approximate,
    })
}

/// With holes, each vertex's index once the vertices no face uses are dropped (`u32::MAX`:
/// dropped, the others in their order); without, none: every vertex is used.
fn used(faces: &[[u32; 4]], vertices: usize, holes: bool) -> Option<Vec<u32>> {
    holes.then(|| renumbering(faces.iter().flatten().copied(), vertices))
}

/// Each of `len` items' index among the items `indices` names, in their order (`u32::MAX`:
/// never named).
pub(crate) fn renumbering(indices: impl Iterator<Item = u32>, len: usize) -> Vec<u32> {
    let mut map = vec![u32::MAX; len];
    for v in indices {
        map[v as usize] = 0;
    }
    for (next, m) in map.iter_mut().filter(|m| **m == 0).enumerate() {
        *m = next as u32;
    }
    map
}

/// The entries of the vertices [`used`] keeps.
fn keep<X>(map: &Option<Vec<u32>>, values: Vec<X>) -> Vec<X> {
    match map {
        None => values,
        Some(map) => values
            .into_iter()
            .zip(map)
            .filter(|(_, &m)| m != u32::MAX)
            .map(|(x, _)| x)
            .collect(),
    }
}

/// Faces in the numbering [`used`] keeps.
fn renumbered(map: &Option<Vec<u32>>, faces: Vec<[u32; 4]>) -> Vec<[u32; 4]> {
    match map {
        None => faces,
        Some(map) => faces.iter().map(|f| f.map(|v| map[v as usize])).collect(),
    }
}

/// [`subdivide_with`] or [`limit_with`] as a [`SurfaceVisitor`]: for a scheme known only by
/// name (the generated registry's `visit_surface`) as for one at hand (`job.visit(&scheme)`).
#[derive(Clone, Copy, Debug)]
pub struct Subdivide<'m> {
    /// The mesh.
    pub mesh: &'m QuadMesh,
    /// Its topology.
    pub topology: &'m Topology,
    /// Its sharp features and boundary rule.
    pub features: &'m Features,
    /// Refinement steps.
    pub steps: usize,
    /// Worker threads (the result does not depend on it).
    pub threads: usize,
    /// Whether to take the vertices to the limit surface, with normals ([`limit_with`]).
    pub limit: bool,
}

impl SurfaceVisitor for Subdivide<'_> {
    type Output = Result<Refined, SurfaceError>;
    fn visit<S: SurfaceScheme + Sync>(self, scheme: &S) -> Self::Output {
        let (m, topo, features) = (self.mesh, self.topology, self.features);
        if self.limit {
            return limit_with(scheme, m, topo, features, self.steps, self.threads);
        }
        Ok(Refined {
            mesh: subdivide_with(scheme, m, topo, features, self.steps, self.threads)?,
            normals: Vec::new(),
            approximate: Vec::new(),
        })
    }
}

/// Per point of the numbering `num`, its index in a mesh refined `k` ≥ 1 times by the
/// reference driver (its quads `quads`; `u32::MAX` for none). Its faces come old face by old
/// face, each base face's as a block of W_k × W_k cells in the same order ([`cells`]); each
/// point is taken from the one cell whose corner 0 it is, or, on the face's last row and
/// column, from the cell beside it.
fn lifted(t: &CurveTables<'_>, quads: &[[u32; 4]], k: usize, num: &Numbering) -> Vec<u32> {
    let cells = cells(t, k);
    let n = num.n;
    let mut from = vec![u32::MAX; num.len()];
    // (A mesh with ghost faces has them after the base faces: they are left out.)
    let faces = quads.chunks_exact(cells.len()).take(num.faces.len());
    for (f, quads) in faces.enumerate() {
        for (&(x, y), quad) in cells.iter().zip(quads) {
            let last = (x + 1 == n, y + 1 == n);
            for c in [0u8, 1, 2, 3] {
                let wanted = match c {
                    0 => true,
                    1 => last.0,
                    2 => last.0 && last.1,
                    _ => last.1,
                };
                if wanted {
                    let (dx, dy) = corner_at(c, 1, 1);
                    from[num.index(f, x + dx, y + dy).0] = quad[c as usize];
                }
            }
        }
    }
    from
}

/// The cells of a base face refined `k` times by the reference driver, in the order it makes
/// them: each cell of step k − 1 becomes its rule's block, row by row; (x, y) of each cell's
/// corner 0 in the face's grid (every base face alike: its edges all carry the axiom).
fn cells(t: &CurveTables<'_>, k: usize) -> Vec<(i64, i64)> {
    let mut cells = vec![(0i64, 0i64, t.axiom[0], t.axiom[0])];
    let mut word = t.axiom.to_vec();
    for _ in 0..k {
        let mut off = vec![0i64];
        for &a in &word {
            off.push(off.last().copied().unwrap_or(0) + t.rule(a).len() as i64);
        }
        cells = cells
            .iter()
            .flat_map(|&(x, y, a, b)| {
                let (ra, rb) = (t.rule(a), t.rule(b));
                let (x0, y0) = (off[x as usize], off[y as usize]);
                rb.iter().enumerate().flat_map(move |(j, &lb)| {
                    ra.iter()
                        .enumerate()
                        .map(move |(i, &la)| (x0 + i as i64, y0 + j as i64, la, lb))
                })
            })
            .collect();
        let mut next = Vec::new();
        rewrite(t, &word, &mut next);
        word = next;
    }
    cells.into_iter().map(|(x, y, _, _)| (x, y)).collect()
}

/// A mesh cut open along the edges sharp at its first step, for the reference driver's step
/// with ghost faces ([`Ghosts`]): each vertex gets one copy per sector (faces between sharp
/// edges), so a crease is a boundary for both sides. `source[i]` is the vertex copy i came
/// from; the faces are the mesh's, in order.
struct Cut {
    topo: Topology,
    source: Vec<u32>,
    /// The 1D plan of the step (no ring): new points 0..=N' of an old interval from the
    /// points −1..=2 around it.
    line: Plan,
    /// Per edge sharp at step 0: the edge, its ends a and b, and the vertex beyond each end
    /// along the sharp line through it (none: the reflection 2a − b).
    sharp: Vec<(u32, [u32; 2], [Option<u32>; 2])>,
    /// The darts: smooth vertices with a sharp edge.
    darts: Vec<u32>,
}

impl Cut {
    /// The cut of `topo` (none if it is not a manifold). At a dart (one sharp edge at an
    /// interior vertex) the cut is at most a slit: the dart keeps one copy, whose child
    /// [`Cut::curves`] sets by the smooth rule.
    fn new(topo: &Topology, features: &Resolved, line: Plan) -> Option<Cut> {
        let mut faces = topo.faces().to_vec();
        let mut source: Vec<u32> = (0..topo.vertex_count() as u32).collect();
        for v in 0..topo.vertex_count() as u32 {
            let sharp = features.sharp_spokes(topo, v, 0);
            let interior = !topo.is_boundary(v);
            // Wedge w lies between spokes w and w + 1; its sector is the number of sharp
            // spokes up to it, less one (at a boundary vertex spoke 0 is the boundary; at an
            // interior one the wedges before the first sharp spoke close the last sector).
            let count = sharp.iter().filter(|&&s| s).count();
            if count == 0 {
                continue;
            }
            let first_copy = source.len() as u32;
            let sectors = if interior { count } else { count - 1 };
            source.extend(std::iter::repeat_n(v, sectors.saturating_sub(1)));
            let mut seen = 0;
            for (w, wedge) in topo.rotation(v).iter().enumerate() {
                seen += usize::from(sharp[w]);
                let sector = (seen + count - 1) % count;
                if sector > 0 {
                    faces[wedge.face as usize][wedge.corner as usize] =
                        first_copy + sector as u32 - 1;
                }
            }
        }
        let mesh = QuadMesh {
            positions: vec![[0.0f64; 3]; source.len()],
            faces,
        };
        let cut = Topology::build(&mesh).ok()?;
        // The vertex beyond a, away from b, along the sharp line through a (edge e).
        let beyond = |a: u32, e: u32| {
            let next = match features.vertex_rule(topo, a, 0) {
                VertexRule::Crease => topo
                    .spokes(a)
                    .find(|&s| s != e && features.edge_sharp(s, 0)),
                VertexRule::Smooth if topo.valence(a) == 4 && !topo.is_boundary(a) => {
                    let spokes: Vec<u32> = topo.spokes(a).collect();
                    spokes
                        .iter()
                        .position(|&s| s == e)
                        .map(|i| spokes[(i + 2) % 4])
                }
                _ => None,
            };
            next.map(|s| topo.other_end(s, a))
        };
        let sharp = (0..topo.edge_count() as u32)
            .filter(|&e| features.edge_sharp(e, 0))
            .map(|e| {
                let [a, b] = topo.edge_vertices(e);
                (e, [a, b], [beyond(a, e), beyond(b, e)])
            })
            .collect();
        let darts = (0..topo.vertex_count() as u32)
            .filter(|&v| {
                features.vertex_rule(topo, v, 0) == VertexRule::Smooth
                    && features.sharp_spokes(topo, v, 0).contains(&true)
            })
            .collect();
        Some(Cut {
            topo: cut,
            source,
            line,
            sharp,
            darts,
        })
    }

    /// After the step: every point on a line sharp at step 0 set to the scheme's curve
    /// refinement of that line (a boundary is the scheme's curve, docs/real-meshes.md), the
    /// 1D plan on the points along it: beyond a crease vertex the line continues along its
    /// other sharp edge, beyond a dart of valence 4 straight on (the line is sharp, the vertex
    /// smooth, as in OpenSubdiv), elsewhere it is odd-reflected. A dart's child is its smooth
    /// rule on its 1-ring ([`dart_child`]). The scatter near a boundary EV drops the entries
    /// that pass through it; on the lines, the principle decides.
    fn curves<T: Real>(
        &self,
        base: &Base<'_>,
        (alpha, ring): (&dyn Fn(u32) -> f64, [f64; 2]),
        positions: &[[f64; 3]],
        num: &Numbering,
        start: &mut [[T; 3]],
    ) {
        let at = |v: u32| positions[v as usize];
        let n = self.line.n_new;
        let k = (n - 1) as usize;
        for &(e, [a, b], [beyond_a, beyond_b]) in &self.sharp {
            let beyond = |v: Option<u32>, a: u32, b: u32| match v {
                Some(v) => at(v),
                None => std::array::from_fn(|i| 2.0 * at(a)[i] - at(b)[i]),
            };
            let old = [beyond(beyond_a, a, b), at(a), at(b), beyond(beyond_b, b, a)];
            for (xn, row) in self.line.rows.iter().enumerate() {
                let mut p = [0.0f64; 3];
                for &(x, w) in &self.line.parents[row.clone()] {
                    for (o, q) in p.iter_mut().zip(old[x]) {
                        *o += w * q;
                    }
                }
                let i = match xn as i64 {
                    0 => a as usize,
                    x if x == n => b as usize,
                    x => num.nv + e as usize * k + x as usize - 1,
                };
                start[i] = p.map(T::from_f64);
            }
        }
        for &v in &self.darts {
            let rule = (alpha(v), ring);
            start[v as usize] =
                dart_child(base.topo, &self.line, rule, positions, v).map(T::from_f64);
        }
    }
}

/// The child of a dart v (a smooth interior vertex with one sharp edge) by the smooth rule on
/// its 1-ring of base positions ([`one_ring`]): the tensor product of the vertex mask at
/// valence 4, the EV rule with `rule` = (α, [E1, E2]) at other valences.
fn dart_child(
    topo: &Topology,
    line: &Plan,
    rule: (f64, [f64; 2]),
    positions: &[[f64; 3]],
    v: u32,
) -> [f64; 3] {
    let rule = if topo.valence(v) == 4 {
        vertex_rule_weights(line)
    } else {
        rule
    };
    one_ring(topo, v, rule, |_, w, spot| {
        let c = match spot {
            Spot::Centre => w.corner,
            Spot::Spoke if w.next_is_plus => (w.corner + 3) % 4,
            Spot::Spoke => (w.corner + 1) % 4,
            Spot::Diagonal => (w.corner + 2) % 4,
        };
        positions[topo.vertex(w.face, c) as usize]
    })
}

/// The mesh extended past its boundary by two layers of ghost faces, for a step of the
/// reference driver on an open mesh whose boundary vertices have two faces, or one (a corner):
/// across each boundary edge a → b of face (a, b, c, d) the quads (b, a, a₁, b₁) and
/// (b₁, a₁, a₂, b₂), with a₁ = 2a − d, b₁ = 2b − c (the odd reflection the patches use; a
/// vertex with two faces shares its ghosts between its two boundary edges) and a₂ = 3a − 2d;
/// at a corner, the four quads of the diagonal quadrant, the first at the double reflection
/// 4a − 2b − 2d + c. The outer layer only makes the first one's vertices interior and
/// ordinary: in a complete step (every patch's new ring has its parents in the old ring) its
/// points reach no real new point, and the driver does not scatter them. Real vertices and
/// faces keep their indices; the ghosts follow. Found once ([`Ghosts::new`]); each refine
/// only makes the ghosts' points ([`Ghosts::extend`]).
#[derive(Default)]
struct Ghosts {
    /// The ghosts in the order they are made, each from points made before it.
    made: Vec<Ghost>,
}

/// How ghosts are made ([`Ghosts`]).
enum Ghost {
    /// a₁ = 2a − p and a₂ = 3a − 2p, from [a, p].
    Pair([u32; 2]),
    /// A corner's diagonal quadrant from its face [a, b, c, d] and its ghosts [g_out, g_in]
    /// across its outgoing and incoming boundary edges.
    Corner([u32; 4], [u32; 2]),
}

impl Ghosts {
    /// The ghost layers of `topo`: how the ghosts are made, the extended mesh's quads, and
    /// its outer ghosts (per point of the extended mesh).
    fn new(topo: &Topology) -> (Ghosts, Vec<[u32; 4]>, Vec<bool>) {
        let mut ghosts = Ghosts::default();
        let mut next = topo.vertex_count() as u32;
        let mut faces = topo.faces().to_vec();
        let mut shared: HashMap<u32, u32> = HashMap::new();
        // The ghost pairs made once per edge (not shared), and each corner's first diagonal
        // ghost.
        let mut pairs: Vec<u32> = Vec::new();
        let mut diagonals: Vec<u32> = Vec::new();
        // Per corner: its ghost across its outgoing boundary edge and across its incoming one.
        let mut corners: HashMap<u32, [u32; 2]> = HashMap::new();
        for f in 0..topo.face_count() as u32 {
            for l in (0..4u8).filter(|&l| topo.is_boundary_edge(f, l)) {
                let v = |k: u8| topo.vertex(f, (l + k) % 4);
                let (a, b, c, d) = (v(0), v(1), v(2), v(3));
                let mut pair = |a, p| {
                    if let Some(&g) = shared.get(&a) {
                        return g;
                    }
                    // Once per vertex with two faces (both its boundary edges reflect across
                    // the same line), once per edge otherwise.
                    let g = next;
                    ghosts.made.push(Ghost::Pair([a, p]));
                    next += 2;
                    if topo.valence(a) == 2 {
                        shared.insert(a, g);
                    }
                    g
                };
                let (a1, b1) = (pair(a, d), pair(b, c));
                for (v, g) in [(a, a1), (b, b1)] {
                    if topo.valence(v) != 2 {
                        pairs.push(g);
                    }
                }
                faces.push([b, a, a1, b1]);
                faces.push([b1, a1, a1 + 1, b1 + 1]);
                if topo.valence(a) == 1 {
                    corners.entry(a).or_insert([u32::MAX; 2])[0] = a1;
                }
                if topo.valence(b) == 1 {
                    corners.entry(b).or_insert([u32::MAX; 2])[1] = b1;
                }
            }
        }
        let mut corners: Vec<(u32, [u32; 2])> = corners.into_iter().collect();
        corners.sort_unstable();
        for (a, [g_out, g_in]) in corners {
            // The corner's face (a, b, c, d): g_out = 2a − d (across a → b), g_in = 2a − b.
            let w = topo.rotation(a)[0];
            let face = [0, 1, 2, 3].map(|i| topo.vertex(w.face, (w.corner + i) % 4));
            ghosts.made.push(Ghost::Corner(face, [g_out, g_in]));
            let (d11, d21, d12, d22) = (next, next + 1, next + 2, next + 3);
            next += 4;
            diagonals.push(d11);
            faces.push([g_out, a, g_in, d11]);
            faces.push([g_out + 1, g_out, d11, d21]);
            faces.push([d11, g_in, g_in + 1, d12]);
            faces.push([d21, d11, d12, d22]);
        }
        // The outer layer: every a₂ (a ghost pair's second) and each corner's outer three.
        let mut outer = vec![false; next as usize];
        for &g in shared.values().chain(&pairs) {
            outer[g as usize + 1] = true;
        }
        for &d11 in &diagonals {
            outer[d11 as usize + 1..d11 as usize + 4].fill(true);
        }
        (ghosts, faces, outer)
    }

    /// Bytes it holds.
    fn bytes(&self) -> usize {
        self.made.capacity() * size_of::<Ghost>()
    }

    /// Appends the ghosts' points to the mesh's `points`, in the order [`Ghosts::new`] made
    /// them.
    fn extend(&self, points: &mut Vec<[f64; 3]>) {
        for ghost in &self.made {
            match *ghost {
                Ghost::Pair([a, p]) => {
                    let (pa, pp) = (points[a as usize], points[p as usize]);
                    points.push(std::array::from_fn(|i| 2.0 * pa[i] - pp[i]));
                    points.push(std::array::from_fn(|i| 3.0 * pa[i] - 2.0 * pp[i]));
                }
                Ghost::Corner(face, [g_out, g_in]) => {
                    let [pa, pb, pc, pd] = face.map(|v| points[v as usize]);
                    let g = |i: u32| points[i as usize];
                    let d11: [f64; 3] =
                        std::array::from_fn(|i| 4.0 * pa[i] - 2.0 * pb[i] - 2.0 * pd[i] + pc[i]);
                    let along_out = sub3(g(g_out + 1), g(g_out));
                    let along_in = sub3(g(g_in + 1), g(g_in));
                    let d21 = add3(d11, along_out);
                    points.extend([d11, d21, add3(d11, along_in), add3(d21, along_in)]);
                }
            }
        }
    }
}

fn add3(a: [f64; 3], b: [f64; 3]) -> [f64; 3] {
    std::array::from_fn(|i| a[i] + b[i])
}

fn sub3(a: [f64; 3], b: [f64; 3]) -> [f64; 3] {
    std::array::from_fn(|i| a[i] - b[i])
}

/// Copies a start patch (`table`: its indices into `start`, x-major with side m, `u32::MAX`
/// for the missing diagonal at an EV corner, which reads as zero) into `dst` in `layout`.
#[inline(always)]
fn load<T: Real>(table: &[u32], start: &[[T; 3]], layout: Layout, dst: &mut [T]) {
    load_rows(table, start, layout, dst, 0);
}

/// [`load`], the rows y = `from` − 1.. only.
#[inline(always)]
fn load_rows<T: Real>(table: &[u32], start: &[[T; 3]], layout: Layout, dst: &mut [T], from: usize) {
    let m = layout.side;
    let (along_x, along_y) = layout.strides();
    let (table, dst) = (&table[..m * m], &mut dst[..3 * m * m]);
    for (x, column) in table.chunks_exact(m).enumerate() {
        let mut d = x * along_x + from * along_y;
        for &i in &column[from..] {
            let p = start.get(i as usize).copied().unwrap_or([T::default(); 3]);
            dst[d..d + 3].copy_from_slice(&p);
            d += along_y;
        }
    }
}

/// The child of special vertex v by its rule after step k (`plan`, the EVs' 1-ring weights
/// `ring`), from the old level (side N) as `point(face, x, y)` reads it: a corner stays, a
/// crease takes its curve rule ([`crease_child`]), a smooth vertex its 1-ring rule (the
/// tensor vertex mask at valence 4, α's elsewhere, \[G\] §3).
fn vertex_child<T: Real>(
    base: &Base<'_>,
    (v, rule, alpha): (u32, VertexRule, f64),
    (plan, ring, k): (&Plan, [f64; 2], usize),
    n: i64,
    point: impl Fn(u32, i64, i64) -> [T; 3],
) -> [T; 3] {
    let topo = base.topo;
    let spot = |_, w: crate::topology::Wedge, spot| {
        let (x, y) = CornerPoint::of_ring(w, spot).xy(n);
        point(w.face, x, y)
    };
    match rule {
        VertexRule::Corner => {
            let w = topo.rotation(v)[0];
            let (cx, cy) = corner_at(w.corner, n, n);
            point(w.face, cx, cy)
        }
        VertexRule::Crease => crease_child(base, plan, (v, k), n, point),
        VertexRule::Smooth if topo.valence(v) == 4 => {
            ev_child(topo, v, vertex_rule_weights(plan), spot)
        }
        VertexRule::Smooth => ev_child(topo, v, (alpha, ring), spot),
    }
}

/// The child of a crease vertex: the curve rule along its two sharp edges, the 1D plan's
/// weights for its new point X' = 0 (the mask of its word, which is a palindrome: the word
/// at a vertex of the symmetric W_s, \[G\] Cor. 4.4) on the points at distance |x| along
/// the two sharp edges of the old level (side N, `point(face, x, y)`).
fn crease_child<T: Real>(
    base: &Base<'_>,
    plan: &Plan,
    (v, k): (u32, usize),
    n: i64,
    point: impl Fn(u32, i64, i64) -> [T; 3],
) -> [T; 3] {
    let rot = base.topo.rotation(v);
    let sharp = base.features.sharp_spokes(base.topo, v, k);
    let mut along = sharp.iter().enumerate().filter(|&(_, &s)| s).map(|(i, _)| {
        let (w, dir) = spoke(base.topo, v, i);
        (rot[w], dir)
    });
    let (behind, ahead) = (along.next(), along.next());
    let (Some(behind), Some(ahead)) = (behind, ahead) else {
        unreachable!("a crease vertex has two sharp edges");
    };
    let h = (plan.rows.len() - plan.n_new as usize - 1) / 2;
    let mut acc = [0.0f64; 3];
    for &(x, wt) in &plan.parents[plan.rows[h].clone()] {
        let x = x as i64 - 1;
        let (w, (dx, dy)) = if x < 0 { behind } else { ahead };
        let (cx, cy) = corner_at(w.corner, n, n);
        let p = point(w.face, cx + x.abs() * dx, cy + x.abs() * dy);
        for (a, q) in acc.iter_mut().zip(p) {
            *a += wt * q.to_f64();
        }
    }
    acc.map(T::from_f64)
}

/// Spoke i of v's rotation (wedge i's previous edge; the last spoke of a boundary vertex is
/// the last wedge's next edge): the wedge that holds it, and the unit step along it from the
/// vertex in that wedge's face.
fn spoke(topo: &Topology, v: u32, i: usize) -> (usize, (i64, i64)) {
    let rot = topo.rotation(v);
    let (w, prev) = if i < rot.len() {
        (i, true)
    } else {
        (rot.len() - 1, false)
    };
    let c = rot[w].corner as usize;
    let dir = if prev == rot[w].next_is_plus {
        TOWARD_PREV[c]
    } else {
        TOWARD_NEXT[c]
    };
    (w, dir)
}

/// Where a point of a vertex's 1-ring lies, seen from one wedge of its rotation.
#[derive(Clone, Copy)]
enum Spot {
    /// The vertex.
    Centre,
    /// The far end of the wedge's edge shared with the previous wedge.
    Spoke,
    /// The wedge face's corner opposite the vertex.
    Diagonal,
}

impl Spot {
    /// Its place, seen from wedge k, in a vertex's 1-ring laid out in the order [`one_ring`]
    /// reads it: the vertex, then per wedge its spoke and its diagonal.
    fn in_ring(self, k: usize) -> usize {
        match self {
            Spot::Centre => 0,
            Spot::Spoke => 1 + 2 * k,
            Spot::Diagonal => 2 + 2 * k,
        }
    }
}

/// The rule (α·P + Σ_k (E1·R_k + E2·D_k)) / (α + n(E1 + E2)) on v's 1-ring, `point(w, spot)`
/// reading it: the EV child (\[G\] §3) with `(α, [E1, E2])` from the tables, and the
/// tensor-product vertex rule at valence 4 with [`vertex_rule_weights`].
fn one_ring(
    topo: &Topology,
    v: u32,
    (alpha, ring): (f64, [f64; 2]),
    point: impl Fn(usize, crate::topology::Wedge, Spot) -> [f64; 3],
) -> [f64; 3] {
    let rot = topo.rotation(v);
    let mut acc = point(0, rot[0], Spot::Centre).map(|x| alpha * x);
    for (k, &w) in rot.iter().enumerate() {
        for (spot, weight) in [(Spot::Spoke, ring[0]), (Spot::Diagonal, ring[1])] {
            for (a, x) in acc.iter_mut().zip(point(k, w, spot)) {
                *a += weight * x;
            }
        }
    }
    let norm = alpha + rot.len() as f64 * (ring[0] + ring[1]);
    acc.map(|a| a / norm)
}

/// The tensor product of the vertex mask (the plan's new point 0 from old points 0 and ±1, a
/// palindrome) as [`one_ring`] weights: (w0², [w0·w1, w1²]).
fn vertex_rule_weights(plan: &Plan) -> (f64, [f64; 2]) {
    let h = (plan.rows.len() - plan.n_new as usize - 1) / 2;
    let weight = |x: usize| {
        plan.parents[plan.rows[h].clone()]
            .iter()
            .find(|&&(i, _)| i == x)
            .map_or(0.0, |&(_, w)| w)
    };
    let (w0, w1) = (weight(1), weight(2));
    (w0 * w0, [w0 * w1, w1 * w1])
}

/// The child of v from its old 1-ring ([`one_ring`]), `point(k, wedge, spot)` reading it
/// (from the old level's patches, [`Fans::spot`], or the handoff's box).
fn ev_child<T: Real>(
    topo: &Topology,
    v: u32,
    rule: (f64, [f64; 2]),
    point: impl Fn(usize, crate::topology::Wedge, Spot) -> [T; 3],
) -> [T; 3] {
    let child = one_ring(topo, v, rule, |k, w, spot| {
        point(k, w, spot).map(|c| c.to_f64())
    });
    child.map(T::from_f64)
}
