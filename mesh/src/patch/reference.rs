//! The reference driver's steps of a refiner, their maps built once.
//!
//! Steps whose masks are not yet contained at the EVs (\[G\] Prop. 4.8: Binary-Ternary's
//! first) run by the reference driver (`surface`). Its scatter's weights depend on the labels
//! and the connectivity only, so each step is built once, with the refiner, as a map of the
//! level before ([`Stencil`], OpenSubdiv's stencil table), and a `refine` only sums it: on
//! the icosphere every face is near an EV, and the scatter took 47 of Binary-Ternary's 77 ms
//! there (the history of docs/benchmarks.md). The sums keep the scatter's order and divisors: the same bits.
//!
//! The last step scatters only the vertices near the EVs when some faces are far from them
//! (`patch/near.rs`: those faces take the step by its 1D plan). On a mesh with features every
//! step runs on its level cut open along the edges sharp at that step and extended by three
//! layers of ghost faces (`Cut`, `Ghosts`): the outer ghosts are not scattered, the extended
//! level's boundary vertices are scattered over the faces they have, and only the real faces'
//! new points are kept, numbered as the base mesh's points at that level (`Numbering`), where
//! the sharp lines take the scheme's curve and the corners stay.

use super::cut::Extended;
use super::numbering::level_mesh;
use super::{lifted, output_counts, Base, Blend, Cut, Ghosts, Near, Numbering, Plan};
use crate::features::{Resolved, VertexRule};
use crate::mesh::QuadMesh;
use crate::real::Real;
use crate::stencil::Stencil;
use crate::surface::{step_map, weights_per_corner, SurfaceError, SurfaceScheme};
use crate::threads::in_threads;
use crate::topology::Topology;
use lsubdiv_runtime::curve::CurveTables;

/// The maps of the reference steps `0..first` and the levels between them.
pub(super) struct Reference {
    /// Per step, its map of the level before (on a mesh with features: of that level cut along
    /// its sharp edges, with its ghosts); the last one's points in the start numbering
    /// ([`lifted`](super::lifted)), those of the faces far from the EVs left to
    /// `Near::far_faces` (no weights).
    maps: Vec<Stencil>,
    /// On a mesh with features, per step: its cut ([`CutStep`]) and the smooth side of its
    /// blends where a sharpness is below 1 at the step; none else.
    cuts: Vec<(CutStep, Option<Blend>)>,
    /// The numbering of each level `0..=first` on a mesh with features (its levels are kept
    /// in it).
    nums: Vec<Numbering>,
    /// Per step, the EVs' 1-ring weights.
    rings: Vec<[f64; 2]>,
    /// The levels of the last `refine` between the steps.
    levels: Vec<Vec<[f64; 3]>>,
    /// The level before a step cut open with its ghosts, during a `refine`.
    extended: Vec<[f64; 3]>,
}

/// A reference step on a level cut along its sharp edges: the cut and how its ghosts are made.
pub(super) struct CutStep {
    pub(super) cut: Cut,
    pub(super) ghosts: Ghosts,
}

impl CutStep {
    /// Step k on the level numbered `num` (connectivity `level`, face labels `labels`) cut
    /// along the edges `features` makes sharp at k, and its map to the level numbered `next`.
    #[allow(clippy::too_many_arguments)]
    pub(super) fn new<S: SurfaceScheme>(
        scheme: &S,
        base: &Base<'_>,
        features: &Resolved,
        (k, level, labels): (usize, &Topology, Vec<[u8; 2]>),
        (num, next): (&Numbering, &Numbering),
        word: &[u8],
        threads: usize,
    ) -> Result<(CutStep, Stencil), SurfaceError> {
        let t = scheme.tables();
        let line = Plan::new(&t, &t.word_index(), word, 0)?;
        let cut =
            Cut::new(base.topo, features, (k, level, num), labels, line).ok_or_else(|| {
                SurfaceError::Unsupported(format!(
                    "step {} of scheme `{}` runs the reference driver on the mesh cut open along \
                 its sharp edges, and the cut is not a manifold",
                    k + 1,
                    t.name
                ))
            })?;
        let extended = Extended::new(&cut, scheme.surface().sigma, word);
        let topo = Topology::build(&shape(extended.faces, extended.outer.len()))?;
        let skip = Some(&extended.outer[..]);
        let (map, _) = step_map(scheme, &extended.labels, &topo, skip, threads)?;
        let order = lifted(&t, &map.faces, k + 1, next);
        let step = CutStep {
            cut,
            ghosts: extended.ghosts,
        };
        Ok((step, map.stencil.pick(&order)))
    }

    /// `map` on the level `level` cut open with its ghosts (in `extended`) into `next`.
    pub(super) fn apply<T: Real>(
        &self,
        map: &Stencil,
        level: &[[f64; 3]],
        extended: &mut Vec<[f64; 3]>,
        next: &mut Vec<[T; 3]>,
        threads: usize,
    ) {
        extended.clear();
        extended.extend(self.cut.source.iter().map(|&v| level[v as usize]));
        self.ghosts.extend(extended);
        apply(map, extended, next, threads);
    }
}

impl Reference {
    /// The maps of the steps `0..first` of `base` (`first` ≥ 1, `words` the label words of
    /// levels `0..=first`) to the level numbered `num`: the last one near the EVs only with
    /// `near` on a mesh without features; each level cut along its sharp edges, with its
    /// ghosts, on a mesh with features; each scattered by up to `threads` workers.
    pub(super) fn new<S: SurfaceScheme>(
        scheme: &S,
        base: &Base<'_>,
        (words, num): (&[Vec<u8>], &Numbering),
        near: Option<&mut Near>,
        threads: usize,
    ) -> Result<Reference, SurfaceError> {
        let first = words.len() - 1;
        let rings = scheme.surface().rings;
        let rings = (0..first).map(|k| rings[k.min(rings.len() - 1)]).collect();
        let levels = vec![Vec::new(); first - 1];
        if base.features.is_plain() {
            return Ok(Reference {
                maps: closed_maps(scheme, base, (first, num), near, threads)?,
                cuts: Vec::new(),
                nums: Vec::new(),
                rings,
                levels,
                extended: Vec::new(),
            });
        }
        let t = scheme.tables();
        let nums: Vec<Numbering> = (0..=first)
            .map(|k| num.with_n(words[k].len() as i64))
            .collect();
        let (mut maps, mut cuts) = (Vec::with_capacity(first), Vec::with_capacity(first));
        for k in 0..first {
            let (faces, labels) = level_mesh(&t, k, &nums[k]);
            let built;
            let level = if k == 0 {
                base.topo
            } else {
                built = Topology::build(&shape(faces, nums[k].len()))?;
                &built
            };
            let nums = (&nums[k], &nums[k + 1]);
            let blend = Blend::new(scheme, base, (k, level, &labels), nums, &words[k], threads)?;
            let features = &base.features;
            let level = (k, level, labels);
            let (step, map) =
                CutStep::new(scheme, base, features, level, nums, &words[k], threads)?;
            maps.push(map);
            cuts.push((step, blend));
        }
        Ok(Reference {
            maps,
            cuts,
            nums,
            rings,
            levels,
            extended: Vec::new(),
        })
    }

    /// Runs the steps on the base mesh's `positions` with `threads` workers (`alphas` per
    /// special vertex); the last level goes to `start`.
    pub(super) fn run<T: Real>(
        &mut self,
        base: &Base<'_>,
        (positions, alphas): (&[[f64; 3]], &[f64]),
        start: &mut Vec<[T; 3]>,
        threads: usize,
    ) {
        let first = self.maps.len();
        let mut levels = std::mem::take(&mut self.levels);
        for k in 0..first {
            let (done, next) = levels.split_at_mut(k.min(first - 1));
            let level = done.last().map_or(positions, Vec::as_slice);
            if k + 1 < first {
                self.step(base, (k, level, alphas), &mut next[0], threads);
            } else {
                self.step(base, (k, level, alphas), start, threads);
            }
        }
        self.levels = levels;
    }

    /// Step k from `level` into `next`: its map, and on a mesh with features the sharp lines'
    /// curves, the darts, the blends and the corners.
    fn step<T: Real>(
        &mut self,
        base: &Base<'_>,
        (k, level, alphas): (usize, &[[f64; 3]], &[f64]),
        next: &mut Vec<[T; 3]>,
        threads: usize,
    ) {
        let Some((step, blend)) = self.cuts.get_mut(k) else {
            apply(&self.maps[k], level, next, threads);
            return;
        };
        step.apply(&self.maps[k], level, &mut self.extended, next, threads);
        let ring = self.rings[k];
        let (num, next_num) = (&self.nums[k], &self.nums[k + 1]);
        step.cut
            .curves(base, (alphas, ring), (level, num), next_num, next);
        if let Some(blend) = blend {
            let level = (level, num);
            blend.run(base, (alphas, ring), level, next_num, next, threads);
        }
        // Corners stay exactly (the ghosts' double reflection gives them up to rounding);
        // every corner is a special vertex, its rule set at every step. A corner whose rule
        // changes across the step took its rules' blend.
        let rules = base.special.iter().zip(base.vertex_rules(k));
        let corners = rules.filter(|(_, r)| **r == Some(VertexRule::Corner));
        for (&v, _) in corners.filter(|(&v, _)| base.transition(v, k).is_none()) {
            next[v as usize] = level[v as usize].map(T::from_f64);
        }
    }

    /// The level before the last step in the last [`Reference::run`] on `positions`.
    pub(super) fn before<'a>(&'a self, positions: &'a [[f64; 3]]) -> &'a [[f64; 3]] {
        self.levels.last().map_or(positions, Vec::as_slice)
    }

    /// Bytes held: the maps, the cuts' ghosts and blends, and the levels.
    pub(super) fn bytes(&self) -> usize {
        let maps: usize = self.maps.iter().map(Stencil::bytes).sum();
        let cuts: usize = (self.cuts.iter())
            .map(|(c, b)| c.ghosts.bytes() + b.as_ref().map_or(0, Blend::bytes))
            .sum();
        let levels: usize = self.levels.iter().map(Vec::capacity).sum();
        let levels = levels + self.extended.capacity();
        maps + cuts + levels * size_of::<[f64; 3]>()
    }
}

/// The maps of the steps `0..first` of the closed mesh `base` to the level numbered `num`, the
/// last one near the EVs only with `near`.
fn closed_maps<S: SurfaceScheme>(
    scheme: &S,
    base: &Base<'_>,
    (first, num): (usize, &Numbering),
    mut near: Option<&mut Near>,
    threads: usize,
) -> Result<Vec<Stencil>, SurfaceError> {
    let t = scheme.tables();
    let [axiom] = t.axiom else {
        return Err(SurfaceError::Axiom);
    };
    let mut mesh = shape(base.topo.faces().to_vec(), base.topo.vertex_count());
    let mut labels = vec![[*axiom; 2]; mesh.faces.len()];
    let mut maps = Vec::with_capacity(first);
    for k in 0..first {
        let level;
        let topo = if k == 0 {
            base.topo
        } else {
            level = Topology::build(&mesh)?;
            &level
        };
        topo.require_closed()?;
        let last = k + 1 == first;
        let skip = (near.as_deref())
            .filter(|_| last)
            .map(|near| near.skip(&mesh.faces, topo.vertex_count()));
        let (map, _) = step_map(scheme, &labels, topo, skip.as_deref(), threads)?;
        if let Some(near) = near.as_deref_mut().filter(|_| last) {
            // Where the faces far from the EVs read the level before and write theirs.
            near.index(&t, base, (&mesh.faces, first), num);
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
    Ok(maps)
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
