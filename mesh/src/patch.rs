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
//! **Boundaries and sharp features** ([`crate::features`], docs/real-meshes.md). Across an edge
//! that is sharp at a step (every boundary edge) a face's ring is the face's own odd reflection,
//! phantoms 2P − Q, and each corner's diagonal is set by its
//! [`CornerKind`](crate::features::CornerKind); refining keeps phantoms phantoms, so faces whose
//! corners are all regular run depth first with their phantoms set once. Faces at a vertex whose
//! rule the patches do not give (interior EVs, darts, creases and corners in other sectors, every
//! corner) or whose sharpness changes (semi-sharp creases) run in lock-step: after each step the
//! vertex children are set by their rule and the rings refreshed from the neighbours' new patches
//! and from the next step's phantoms. A step the reference driver must take (masks not contained
//! where a corner has no diagonal) runs, on a mesh with features, on its level cut open along the
//! edges sharp at that step and extended by ghost faces (`Cut`, `Ghosts`), as many such steps as
//! the scheme needs.

use crate::features::{Creasing, Features, Resolved, VertexRule};
use crate::grid::{along_edge, corner_at, TOWARD_NEXT};
use crate::mesh::QuadMesh;
use crate::real::Real;
use crate::surface::{SurfaceError, SurfaceScheme, SurfaceVisitor};
use crate::threads::in_threads;
use crate::topology::{Topology, TopologyError};
use lsubdiv_runtime::curve::{rewrite, CurveTables};
use std::time::Instant;

mod base;
mod blend;
mod composed;
mod cut;
mod direct;
mod footprint;
mod frames;
mod handoff;
mod limit;
mod near;
mod numbering;
mod plan;
mod rebase;
mod reference;
mod stream;
mod vertices;
use base::{Base, FaceRules};
use blend::Blend;
use composed::{Composed, Faces, Rows};
use cut::{Cut, Ghosts};
pub use footprint::{footprint, output_counts, Footprint};
pub use frames::Frames;
use handoff::{CornerPoint, Handoff, Offsets};
pub use limit::{limit_available, SurfaceLimit};
use near::Near;
use numbering::{lifted, Numbering, SharedOut};
use plan::Plan;
use reference::{CutStep, Reference};
use stream::{Stream, Writers, STREAM_BYTES, WRITERS};
use vertices::{ev_child, holders, spoke, turning_line, vertex_child, Spot};

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
/// (the history of docs/benchmarks.md).
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

/// How a refinement runs, decided from the label words and the base mesh before anything is
/// built: what the [`Refiner`] builds and what [`footprint()`] counts.
struct Schedule<'t> {
    /// Each word of the tables by its letters.
    lookup: std::collections::HashMap<&'t [u8], u32>,
    /// W_0 = ω, …, W_steps.
    words: Vec<Vec<u8>>,
    /// Steps before this one run by the reference driver: masks not yet contained (with EVs),
    /// a ring that does not sustain itself, or N' = 1 with EVs.
    first: usize,
    /// The 1D plans of the depth-first steps, from step `first` on.
    plans: Vec<Plan>,
    /// How many of those run level by level (a mesh of small fans, `patch/direct.rs`).
    lead: usize,
}

impl<'t> Schedule<'t> {
    fn new(
        t: &CurveTables<'t>,
        contained_from: usize,
        base: &Base<'_>,
        steps: usize,
    ) -> Result<Schedule<'t>, SurfaceError> {
        let [omega] = t.axiom else {
            return Err(SurfaceError::Axiom);
        };
        // Output quads index vertices with u32: refuse a result that would not fit, before
        // building anything (the words grow with the output's side).
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
        let lookup = t.word_index();
        let mut words = vec![vec![*omega]];
        for s in 0..steps {
            let mut next = Vec::new();
            rewrite(t, &words[s], &mut next);
            words.push(next);
        }
        let special = !base.special.is_empty();
        let mut first = if base.needs_containment {
            contained_from.min(steps)
        } else {
            0
        };
        let mut plans = Vec::new();
        for (s, w) in words.iter().enumerate().take(steps).skip(first) {
            let plan = Plan::new(t, &lookup, w, i64::from(s + 1 < steps))?;
            if plan.complete && (plan.n_new >= 2 || !special) {
                plans.push(plan);
            } else {
                plans.clear();
                first = s + 1;
            }
        }
        let fan_faces = (0..base.topo.face_count() as u32)
            .filter(|&f| !base.ordinary(f))
            .count();
        let lead = direct::leading(base, fan_faces, plans.iter().map(|p| p.n_new));
        Ok(Schedule {
            lookup,
            words,
            first,
            plans,
            lead,
        })
    }

    /// The level the patches start from.
    fn start_level(&self) -> usize {
        self.first + self.lead
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
    #[cfg_attr(not(feature = "tuning"), allow(dead_code))]
    phase_seconds: Phases,
    /// One scratch per worker, kept across steps and calls (no fresh pages per step).
    scratch: Vec<Scratch<T>>,
    /// Worker time per depth-first step of the last `refine`.
    #[cfg_attr(not(feature = "tuning"), allow(dead_code))]
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
        let resolved = Resolved::new(topo, features).map_err(SurfaceError::Features)?;
        if resolved.chaikin() && steps > 1 {
            return Err(SurfaceError::Unsupported(
                "Chaikin creasing is refined one step at a time: each refiner takes one \
                 (`patch::subdivide_with` and `patch::limit_with` take the others)"
                    .into(),
            ));
        }
        let base = Base::new(topo, resolved, steps)?;
        let plain = base.features.is_plain();
        let schedule = Schedule::new(&t, st.contained_from, &base, steps)?;
        let start_level = schedule.start_level();
        let Schedule {
            lookup,
            words,
            first,
            mut plans,
            lead,
        } = schedule;
        // Those steps run by the reference driver: on a mesh with features each level cut
        // open along its sharp edges and extended by ghost faces ([`Cut`], [`Ghosts`]), a
        // sharpness below 1 at a step blending the step cut along it with the step without it.
        let mut near = (first > 0 && plain)
            .then(|| Near::new(&t, &lookup, &base, &words[first - 1]))
            .flatten();
        let reference = (first > 0)
            .then(|| {
                let num = Numbering::new(base.topo, words[first].len() as i64);
                let levels = (&words[..=first], &num);
                Reference::new(scheme, &base, levels, near.as_mut(), threads.max(1))
            })
            .transpose()?;
        // The first depth-first steps of a mesh of small fans, level by level.
        let nf = topo.face_count();
        let (ordinary, fan_faces): (Vec<u32>, Vec<u32>) =
            (0..nf as u32).partition(|&f| base.ordinary(f));
        let direct: Vec<direct::Step> = (first..)
            .zip(plans.drain(..lead))
            .map(|(k, plan)| {
                let ring = st.rings[k.min(st.rings.len() - 1)];
                direct::Step::new(&base, plan, (words[k].len() as i64, k), ring)
            })
            .collect();
        let start_num = Numbering::new(base.topo, words[start_level].len() as i64);
        let out_num = start_num.with_n(words[steps].len() as i64);
        let m = ring_layout(start_num.n, true);
        let start_gather = start_num.gather_table(&base);
        // α for the special vertices that are interior and extraordinary (unused otherwise).
        let alphas = base
            .special
            .iter()
            .map(|&v| match base.topo.valence(v) {
                n if n < 2 || n == 4 || base.topo.is_boundary(v) => Ok(0.0),
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

    #[cfg(feature = "tuning")]
    /// Scratch per strip of a step of a large patch (default 512 KiB, half this machine's
    /// L2): smaller strips use less memory, and 1 makes every strip one point wide.
    /// The output does not depend on it.
    pub fn set_strip_bytes(&mut self, bytes: usize) {
        self.strip_bytes = bytes;
    }

    #[cfg(feature = "tuning")]
    /// Output size in bytes from which the faces' interiors (and an ordinary face's edges) go
    /// out in whole cache lines with non-temporal stores (default 8 MiB: larger than the
    /// caches a core writes into, where reading a line before writing it costs as much as
    /// writing it). The output does not depend on it.
    pub fn set_stream_bytes(&mut self, bytes: usize) {
        self.stream_bytes = bytes;
    }

    #[cfg(feature = "tuning")]
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
    /// `refine` to the next, and [`footprint()`] bounds them.
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

    #[cfg(feature = "tuning")]
    /// Wall time of the phases of the last `refine`.
    pub fn phase_seconds(&self) -> Phases {
        self.phase_seconds
    }

    #[cfg(feature = "tuning")]
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
            let reference = self.reference.as_mut().expect("reference steps have maps");
            let level0 = (positions, &self.alphas[..]);
            reference.run(&self.base, level0, &mut self.start, self.threads);
            if let Some(near) = &self.near {
                near.far_faces(reference.before(positions), &mut self.start);
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
        // written once more per call, 1.3× on the 256 × 256 torus, the history of docs/benchmarks.md).
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
            let at = |f: u32, x: i64, y: i64| match gathered {
                true => *fans.point(f, x, y),
                // The start level's point, by the kernel's table (x-major).
                false => {
                    let at = ring_layout(n, true).at(x, y) / 3;
                    start[table[f as usize * m * m + at] as usize]
                }
            };
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
                            _ => vertex_child(base, (v, rule, alpha), (plan, ring, k), n, at),
                        })
                    })
                    .collect::<Vec<_>>()
                },
            )
            .into_iter()
            .flatten()
            .collect();
            // Where a crease turns inside one face, its points near the turn by the curve.
            let turns: Vec<(u32, u32, i64, [T; 3])> = (base.special.iter())
                .zip(base.vertex_rules(k))
                .filter(|(_, r)| **r == Some(VertexRule::Crease))
                .flat_map(|(&v, _)| {
                    let line = turning_line(base, plan, (v, k), n, &at);
                    line.into_iter().map(move |(e, t, p)| (v, e, t, p))
                })
                .collect();
            if last {
                for (&v, child) in base.special.iter().zip(&children) {
                    if let Some(child) = child {
                        // SAFETY: the workers are done; nothing else writes the output now.
                        unsafe { out.write(v as usize, child) };
                    }
                }
                for &(v, e, t, p) in &turns {
                    if let Some((f, (x, y))) = holders(base.topo, (v, e, t), n_new).next() {
                        let (i, _) = self.out_num.index(f as usize, x, y);
                        // SAFETY: as above.
                        unsafe { out.write(i, &p) };
                    }
                }
            } else {
                let layout = layouts.1;
                for &(v, e, t, p) in &turns {
                    for (f, (x, y)) in holders(base.topo, (v, e, t), n_new) {
                        let at = self.fan_slot[f as usize] as usize * new_len + layout.at(x, y);
                        new[at..at + 3].copy_from_slice(&p);
                    }
                }
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
        self.quads(false)
    }

    /// [`Refiner::faces`], with the holes' children where `holes`.
    fn quads(&self, holes: bool) -> Vec<[u32; 4]> {
        let num = &self.out_num;
        let n = num.n;
        let nf = self.base.topo.face_count();
        let mut faces = Vec::with_capacity(nf * (n * n) as usize);
        for f in (0..nf).filter(|&f| holes || !self.base.features.is_hole(f as u32)) {
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
    refined(
        scheme,
        (mesh, topo, features),
        steps,
        threads,
        |r, faces| {
            let kept = used(&faces, r.output_vertices(), r.base.features.has_holes());
            Ok(QuadMesh {
                positions: keep(&kept, r.into_positions()),
                faces: renumbered(&kept, faces),
            })
        },
    )
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
    if features.creasing == Creasing::Chaikin {
        limit::sharp_until(features.semi_sharp_steps(), steps)?;
    }
    refined(
        scheme,
        (mesh, topo, features),
        steps,
        threads,
        |r, faces| {
            let limit = r.limit()?;
            let kept = used(&faces, limit.positions.len(), r.base.features.has_holes());
            let SurfaceLimit {
                positions,
                normals,
                approximate,
            } = kept_limit(&kept, limit);
            Ok(Refined {
                mesh: QuadMesh {
                    positions,
                    faces: renumbered(&kept, faces),
                },
                normals,
                approximate,
            })
        },
    )
}

/// Hands `finish` a refiner that has refined `mesh` `steps` times (the steps but the last one
/// at a time under Chaikin creasing, [`rebase`]) and its quads, in one refinement's order
/// ([`rebase::Level::in_base_order`]).
fn refined<S: SurfaceScheme + Sync, T: Real, R>(
    scheme: &S,
    base: (&QuadMesh, &Topology, &Features),
    steps: usize,
    threads: usize,
    finish: impl FnOnce(Refiner<'_, S, T>, Vec<[u32; 4]>) -> Result<R, SurfaceError>,
) -> Result<R, SurfaceError> {
    let level = rebase::before_last(scheme, base, steps, threads)?;
    let ((mesh, topo, features), steps) = rebase::remaining(&level, base, steps);
    let mut r = Refiner::with_features(scheme, topo, features, steps, threads)?;
    r.refine(&mesh.positions)?;
    let faces = match &level {
        Some(level) => level.in_base_order(r.faces()),
        None => r.faces(),
    };
    finish(r, faces)
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

/// A limit with the vertices [`used`] keeps, renumbered.
fn kept_limit<T>(map: &Option<Vec<u32>>, limit: SurfaceLimit<T>) -> SurfaceLimit<T> {
    let approximate = match map {
        Some(map) => (limit.approximate.into_iter())
            .map(|v| map[v as usize])
            .filter(|&v| v != u32::MAX)
            .collect(),
        None => limit.approximate,
    };
    SurfaceLimit {
        positions: keep(map, limit.positions),
        normals: keep(map, limit.normals),
        approximate,
    }
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
