//! The reference driver's steps of a refiner, their maps built once.
//!
//! Steps whose masks are not yet contained at the EVs (\[G\] Prop. 4.8: Binary-Ternary's
//! first) run by the reference driver (`surface`). Its scatter's weights depend on the labels
//! and the connectivity only, so each step is built once, with the refiner, as a map of the
//! level before ([`Stencil`], OpenSubdiv's stencil table), and a `refine` only sums it: on
//! the icosphere every face is near an EV, and the scatter took 47 of Binary-Ternary's 77 ms
//! there (docs/benchmarks.md). The sums keep the scatter's order and divisors: the same bits.
//!
//! The last step scatters only the vertices near the EVs when some faces are far from them
//! (`patch/near.rs`: those faces take the step by its 1D plan); on a mesh with features it
//! runs on the mesh cut open along its sharp edges and extended by two layers of ghost faces
//! (`Cut`, `Ghosts`): the outer ghosts are not scattered, the extended mesh's boundary
//! vertices are scattered over the faces they have, and only the real faces' new points are
//! kept.

use super::{lifted, output_counts, Base, Cut, Ghosts, Near, Numbering};
use crate::curve::CurveTables;
use crate::mesh::QuadMesh;
use crate::real::Real;
use crate::stencil::Stencil;
use crate::surface::{step_map, weights_per_corner, SurfaceError, SurfaceScheme};
use crate::threads::in_threads;
use crate::topology::Topology;

/// The maps of the reference steps `0..first` and the levels between them.
pub(super) struct Reference {
    /// Per step, its map of the level before; the last one's points in the start numbering
    /// ([`lifted`](super::lifted)), those of the faces far from the EVs left to
    /// `Near::far_faces` (no weights).
    maps: Vec<Stencil>,
    /// How level 0's ghosts are made on a mesh cut along its sharp edges (none else).
    ghosts: Ghosts,
    /// The levels of the last `refine` between the steps.
    levels: Vec<Vec<[f64; 3]>>,
}

impl Reference {
    /// The maps of the steps `0..first` of `base` (`first` ≥ 1) to the level numbered `num`:
    /// the last one near the EVs only with `near`, on the cut mesh with its ghosts with `cut`;
    /// each scattered by up to `threads` workers.
    pub(super) fn new<S: SurfaceScheme>(
        scheme: &S,
        base: &Base<'_>,
        (first, num): (usize, &Numbering),
        mut near: Option<&mut Near>,
        cut: Option<&Cut>,
        threads: usize,
    ) -> Result<Reference, SurfaceError> {
        let t = scheme.tables();
        let [axiom] = t.axiom else {
            return Err(SurfaceError::Axiom);
        };
        // Level 0: the base mesh, or the cut mesh with its ghost layers.
        let (mut mesh, outer, built, ghosts) = match cut {
            None => (
                shape(base.topo.faces().to_vec(), base.topo.vertex_count()),
                None,
                None,
                Ghosts::default(),
            ),
            Some(cut) => {
                let (ghosts, faces, outer) = Ghosts::new(&cut.topo);
                let mesh = shape(faces, outer.len());
                let topo = Topology::build(&mesh)?;
                (mesh, Some(outer), Some(topo), ghosts)
            }
        };
        let mut labels = vec![[*axiom; 2]; mesh.faces.len()];
        let mut maps = Vec::with_capacity(first);
        for k in 0..first {
            let level;
            let topo = match (k, &built) {
                (0, Some(topo)) => topo,
                (0, None) => base.topo,
                _ => {
                    level = Topology::build(&mesh)?;
                    &level
                }
            };
            if cut.is_none() {
                topo.require_closed()?;
            }
            let last = k + 1 == first;
            let near_skip = (near.as_deref())
                .filter(|_| last)
                .map(|near| near.skip(&mesh.faces, topo.vertex_count()));
            let skip = near_skip.as_deref().or(outer.as_deref());
            let (map, _) = step_map(scheme, &labels, topo, skip, threads)?;
            if let Some(near) = near.as_deref_mut().filter(|_| last) {
                // Where the faces far from the EVs read the level before and write theirs.
                let before = if k > 0 {
                    &mesh.faces
                } else {
                    base.topo.faces()
                };
                near.index(&t, base, (before, first), num);
            }
            mesh = shape(map.faces, map.stencil.len());
            labels = map.labels;
            maps.push(map.stencil);
        }
        // The last map's points in the start numbering, but those the far faces write.
        let mut order = lifted(&t, &mesh.faces, first, num);
        for &i in near.map_or(&[][..], |near| near.written()) {
            order[i as usize] = u32::MAX;
        }
        let last = maps.pop().expect("first ≥ 1");
        maps.push(last.pick(&order));
        Ok(Reference {
            maps,
            ghosts,
            levels: vec![Vec::new(); first - 1],
        })
    }

    /// Runs the steps on the positions of level 0 (the base mesh's, or the cut mesh's with its
    /// ghosts) with `threads` workers; the last level goes to `start`.
    pub(super) fn run<T: Real>(
        &mut self,
        level0: &[[f64; 3]],
        start: &mut Vec<[T; 3]>,
        threads: usize,
    ) {
        let (last, maps) = self.maps.split_last().expect("first ≥ 1");
        for (k, map) in maps.iter().enumerate() {
            let (done, next) = self.levels.split_at_mut(k);
            apply(
                map,
                done.last().map_or(level0, Vec::as_slice),
                &mut next[0],
                threads,
            );
        }
        apply(last, self.before(level0), start, threads);
    }

    /// How level 0's ghosts are made from the cut mesh's points (none without a cut).
    pub(super) fn ghosts(&self) -> &Ghosts {
        &self.ghosts
    }

    /// The level before the last step in the last [`Reference::run`] on `level0`.
    pub(super) fn before<'a>(&'a self, level0: &'a [[f64; 3]]) -> &'a [[f64; 3]] {
        self.levels.last().map_or(level0, Vec::as_slice)
    }

    /// Bytes held: the maps, the ghosts' making and the levels.
    pub(super) fn bytes(&self) -> usize {
        let maps: usize = self.maps.iter().map(Stencil::bytes).sum();
        let levels: usize = self.levels.iter().map(Vec::capacity).sum();
        maps + self.ghosts.bytes() + levels * size_of::<[f64; 3]>()
    }
}

/// Points a worker takes at least: a point's sum is short (~10 ns), a scoped thread starts
/// and joins in ~47 µs on the 2-vCPU VM (`patch/direct.rs`).
const PER_WORKER: usize = 32768;

/// `map` of `old` into `new` by up to `threads` workers, each a run of rows (the same bits).
fn apply<T: Real>(map: &Stencil, old: &[[f64; 3]], new: &mut Vec<[T; 3]>, threads: usize) {
    new.clear();
    new.resize(map.len(), [T::default(); 3]);
    let share = map
        .len()
        .div_ceil(threads.clamp(1, map.len().div_ceil(PER_WORKER).max(1)));
    in_threads(new.chunks_mut(share.max(1)).enumerate(), |(i, run)| {
        map.apply_rows(i * share, old, run)
    });
}

/// A level's connectivity: its quads over `vertices` vertices (positions of no size).
fn shape(faces: Vec<[u32; 4]>, vertices: usize) -> QuadMesh<()> {
    QuadMesh {
        positions: vec![[(); 3]; vertices],
        faces,
    }
}

/// A bound on [`Reference::bytes`], and on what building it holds at once (each step's
/// scatter beside its map, then the map beside the last one's rows picked), for the steps
/// `0..first` on a level 0 of `vertices`, `edges` and `faces` whose edges all carry the axiom.
pub(super) fn bound(
    t: &CurveTables<'_>,
    (vertices, edges, faces): (u128, u128, u128),
    first: usize,
) -> u128 {
    // A vertex scatters its centre and at most `weights_per_corner` per face corner at it.
    let per_corner = weights_per_corner(t) as u128;
    let n = |k: usize| t.image_len(t.axiom, k);
    (0..first).fold(0u128, |a, k| {
        let (v, f) = output_counts(vertices, edges, faces, n(k));
        let (new_v, new_f) = output_counts(vertices, edges, faces, n(k + 1));
        let weights = v.saturating_add(f.saturating_mul(4).saturating_mul(per_corner));
        // Each weight: its point and weight in the map (12 bytes), and in the scatter or the
        // picked rows (12). Per new point: its row twice, its divisor twice, its weight sum
        // and its position; per old vertex its run's end; per new quad its corners and labels.
        a.saturating_add(weights.saturating_mul(24))
            .saturating_add(new_v.saturating_mul(8 * 4 + 8 + 24))
            .saturating_add(v.saturating_mul(8))
            .saturating_add(new_f.saturating_mul(16 + 2))
    })
}
