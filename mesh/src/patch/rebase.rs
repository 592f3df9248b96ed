//! Chaikin creasing (OpenSubdiv's `CREASE_CHAIKIN`, [`Creasing::Chaikin`]): a sharp edge's two
//! children take different sharpness (each averaged with the semi-sharp edges at its end), so
//! the sharpness varies along a file edge from step to step, where the refiner keeps one per
//! edge and step. A scheme whose axiom rewrites to two copies of itself has every level a
//! base mesh of its own (its edges all labelled by the axiom again): the steps before the last
//! run one at a time, each level's features its children's, and the last by the refiner.

use super::{Refiner, SurfaceError, SurfaceScheme};
use crate::features::{Creasing, Features};
use crate::mesh::QuadMesh;
use crate::topology::Topology;

/// A level taken one step at a time: its mesh (every face, holes included), topology and
/// features.
pub(super) struct Level {
    pub(super) mesh: QuadMesh,
    pub(super) topo: Topology,
    pub(super) features: Features,
    /// Steps taken.
    steps: usize,
}

/// The level before the last of `steps` steps of `scheme` on `mesh` under Chaikin creasing,
/// each step a refiner's one on the level before (none under uniform creasing, or for one
/// step). Refused for a scheme whose levels are not base meshes.
pub(super) fn before_last<S: SurfaceScheme + Sync>(
    scheme: &S,
    (mesh, topo, features): (&QuadMesh, &Topology, &Features),
    steps: usize,
    threads: usize,
) -> Result<Option<Level>, SurfaceError> {
    if features.creasing != Creasing::Chaikin || steps <= 1 {
        return Ok(None);
    }
    let t = scheme.tables();
    if !matches!(t.axiom, [w] if t.rule(*w) == [*w, *w]) {
        return Err(SurfaceError::Unsupported(format!(
            "Chaikin creasing makes the sharpness vary along an edge from step to step; \
             lsubdiv takes such steps one at a time, each level a base mesh, which needs a \
             scheme whose axiom rewrites to two copies of itself (uniform binary); the levels \
             of `{}` are not",
            t.name
        )));
    }
    let mut level: Option<Level> = None;
    for _ in 1..steps {
        let ((mesh, topo, features), _) = remaining(&level, (mesh, topo, features), 1);
        let mut r = Refiner::<S, f64>::with_features(scheme, topo, features, 1, threads)?;
        r.refine(&mesh.positions)?;
        let faces = r.quads(true);
        // A file edge's children meet at its edge point, after the vertices (N = 2).
        let nv = topo.vertex_count() as u32;
        let edge_point = |[a, b]: [u32; 2]| {
            nv + topo
                .edge_between(a, b)
                .expect("a resolved crease is an edge")
        };
        let features = features.stepped(edge_point, |f| 4 * f..4 * f + 4);
        let mesh = QuadMesh {
            positions: r.into_positions(),
            faces,
        };
        let topo = Topology::build(&mesh)?;
        let steps = level.as_ref().map_or(1, |l| l.steps + 1);
        level = Some(Level {
            mesh,
            topo,
            features,
            steps,
        });
    }
    Ok(level)
}

/// What the refiner takes: the level before the last step and that step where the steps
/// before it were taken one at a time ([`before_last`]), else the mesh and every step.
pub(super) fn remaining<'a>(
    level: &'a Option<Level>,
    mesh: (&'a QuadMesh, &'a Topology, &'a Features),
    steps: usize,
) -> ((&'a QuadMesh, &'a Topology, &'a Features), usize) {
    match level {
        Some(l) => ((&l.mesh, &l.topo, &l.features), 1),
        None => (mesh, steps),
    }
}

impl Level {
    /// The last step's quads (a block of 2 × 2 per face of this level, row by row) in the
    /// order one refinement of all the steps gives them: per face of the base mesh its
    /// 2^s × 2^s quads row by row, each level's children in their parent's frame.
    pub(super) fn in_base_order(&self, faces: Vec<[u32; 4]>) -> Vec<[u32; 4]> {
        let levels = self.steps + 1;
        let n = 1usize << levels;
        let block = n * n;
        let mut out = vec![[0u32; 4]; faces.len()];
        for (i, quad) in faces.into_iter().enumerate() {
            let (first, mut at) = (i - i % block, i % block);
            // From the last level up: the child's place in its parent's 2 × 2 block.
            let (mut x, mut y) = (0, 0);
            for l in 0..levels {
                let child = at % 4;
                x |= (child % 2) << l;
                y |= (child / 2) << l;
                at /= 4;
            }
            out[first + y * n + x] = quad;
        }
        out
    }
}
