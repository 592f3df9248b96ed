//! What a refinement makes and holds, counted before it runs: the output's exact size and
//! every buffer's bound, for the size guard (`lsubdiv --max-memory`) and the benchmarks'
//! memory ratios.

use super::cut::{Ghost, LAYERS};
use super::numbering::FaceNumbering;
use super::{handoff, reference, Base, FaceRules, Schedule};
use crate::features::{Features, Resolved, VertexRule};
use crate::topology::Topology;
use lsubdiv_runtime::curve::CurveTables;

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

/// Vertices and quads [`subdivide_with`](super::subdivide_with) writes when every edge splits
/// into n and the holes' points that no other face uses are dropped: each vertex, edge and
/// face counted once if a
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

/// What a refinement by [`Refiner`](super::Refiner) makes and holds, in bytes at most (see
/// [`footprint()`]).
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
/// `contained_from`) on `mesh` by a [`Refiner`](super::Refiner) with `threads` workers and
/// positions of `scalar_bytes` bytes, predicted from the label words before anything is built
/// (saturating).
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
    // The refiner's own schedule (without one, it refuses: the conservative split below).
    let schedule = base
        .as_ref()
        .and_then(|b| Schedule::new(t, contained_from, b, steps).ok());
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
    // The steps run by the reference driver, those level by level (`patch/direct.rs`), and
    // the level the patches start from.
    let (first, lead, start_level) = match &schedule {
        Some(s) => (s.first, s.lead, s.start_level()),
        None => (contained_from.min(steps), 0, contained_from.min(steps)),
    };
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
    // A reference step on a mesh with features runs on its level cut along the edges sharp
    // at that step (at most those sharp at step 0), with its ghost layers ([`Cut`], [`Ghosts`]):
    // per side of a sharp edge at most two ghost pairs of `LAYERS` points and `LAYERS` faces
    // per sub-edge, and per sector of one face (a face corner between two sharp edges) a
    // quadrant of `LAYERS`² faces and points.
    let cut = match &base {
        Some(b) if first > 0 && !b.features.is_plain() => {
            let sharp = |e: u32| b.features.edge_sharp(e, 0);
            let edges = (0..topo.edge_count() as u32).filter(|&e| sharp(e)).count() as u128;
            let quadrants = (0..topo.face_count() as u32)
                .flat_map(|f| (0..4u8).map(move |c| (f, c)))
                .filter(|&(f, c)| sharp(topo.edge_of(f, c)) && sharp(topo.edge_of(f, (c + 3) % 4)))
                .count() as u128;
            let l = LAYERS as u128;
            Some((
                edges,
                4 * l * edges + l * l * quadrants,
                2 * l * edges + l * l * quadrants,
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
        // The level before a step cut open with its ghosts, as positions (the largest, before
        // the last step).
        let (lv, le, lf) = level0;
        let extended = cut.map_or(0, |_| {
            output_counts(lv, le, lf, n(first - 1)).0.saturating_mul(24)
        });
        let one = reference::bound(t, level0, first)
            .saturating_add(f0.saturating_mul(near))
            .saturating_add(made)
            .saturating_add(extended);
        // A sharpness below 1 at a reference step runs it twice (`patch/blend.rs`): a second
        // cut (along fewer edges) and its maps, its level after the step and a weight per
        // point.
        let fractions = |b: &Base<'_>| (0..first).any(|k| b.features.has_fractions(k));
        let blends = cut.is_some() && base.as_ref().is_some_and(fractions);
        let second = output_counts(v0, e0, f0, n(first))
            .0
            .saturating_add(ghosts)
            .saturating_mul(24 + 8);
        match blends {
            true => one.saturating_mul(2).saturating_add(second),
            false => one,
        }
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
