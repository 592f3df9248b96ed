//! A reference step on a level cut along its sharp edges (`Cut`) where a sharpness below 1
//! makes a rule a blend of the sharp and the smooth one (OpenSubdiv's fractional sharpness,
//! docs/real-meshes.md): an edge's phantoms are w(2P − Q) + (1 − w)R, linear in the ring, so
//! the step is w times the step cut along that edge plus 1 − w times the step without it.
//! The step runs twice, cut along every sharp edge (the refiner's own cut) and cut along the
//! edges sharp in full only (here), and each point takes the blend by the sharpness below 1
//! that reaches it; a vertex whose rule changes across the step takes its two rules' blend
//! (`vertex_child`, `Resolved::transition`).

use super::{vertex_child, Base, CutStep, Numbering};
use crate::features::VertexRule;
use crate::real::Real;
use crate::stencil::Stencil;
use crate::surface::{SurfaceError, SurfaceScheme};
use crate::topology::Topology;

/// What of a sharpness below 1 reaches a point: none, one value, or several.
#[derive(Clone, Copy, PartialEq)]
enum Reach {
    None,
    One(f64),
    Many,
}

impl Reach {
    fn and(self, other: Reach) -> Reach {
        match (self, other) {
            (Reach::None, r) | (r, Reach::None) => r,
            (Reach::One(a), Reach::One(b)) if a == b => Reach::One(a),
            _ => Reach::Many,
        }
    }
}

/// The smooth side of a reference step's blends ([`Blend::run`]).
pub(super) struct Blend {
    /// The step on the level cut along the edges sharp in full at the step, and its map.
    step: CutStep,
    map: Stencil,
    /// Per point of the level after the step, the weight of the step cut along every sharp
    /// edge (1 where no sharpness below 1 reaches the point).
    weight: Vec<f64>,
    /// The level after the step without the sharpness below 1, and the level before it cut
    /// open, during a `refine`.
    other: Vec<[f64; 3]>,
    extended: Vec<[f64; 3]>,
}

impl Blend {
    /// The blend of reference step k on the level numbered `num` (connectivity `level`, face
    /// labels `labels`, label word `word`) to the level numbered `next`, none where no
    /// sharpness is below 1 at k. A new point is reached by the edges at the corners of the
    /// base faces it lies in; points reached by two different sharpnesses below 1 are refused
    /// (the step would be bilinear in them).
    pub(super) fn new<S: SurfaceScheme>(
        scheme: &S,
        base: &Base<'_>,
        (k, level, labels): (usize, &Topology, &[[u8; 2]]),
        (num, next): (&Numbering, &Numbering),
        word: &[u8],
        threads: usize,
    ) -> Result<Option<Blend>, SurfaceError> {
        if !base.features.has_fractions(k) {
            return Ok(None);
        }
        let topo = base.topo;
        let smooth = base.features.without_fractions(k);
        let level = (k, level, labels.to_vec());
        let (step, map) = CutStep::new(scheme, base, &smooth, level, (num, next), word, threads)?;
        let mut at = vec![Reach::None; topo.vertex_count()];
        for e in 0..topo.edge_count() as u32 {
            let w = base.features.edge_weight(e, k);
            if w > 0.0 && w < 1.0 {
                for v in topo.edge_vertices(e) {
                    at[v as usize] = at[v as usize].and(Reach::One(w));
                }
            }
        }
        let mut reach = vec![Reach::None; next.len()];
        for f in 0..topo.face_count() as u32 {
            let r = (0..4).fold(Reach::None, |r, c| r.and(at[topo.vertex(f, c) as usize]));
            if r == Reach::None {
                continue;
            }
            for y in 0..=next.n {
                for x in 0..=next.n {
                    let i = next.index(f as usize, x, y).0;
                    reach[i] = reach[i].and(r);
                }
            }
        }
        if reach.contains(&Reach::Many) {
            return Err(SurfaceError::Unsupported(format!(
                "step {} of scheme `{}` runs the reference driver on the mesh cut open along \
                 its sharp edges, and two edges of different sharpness below 1 reach one face \
                 there (the step would blend in both at once)",
                k + 1,
                scheme.tables().name
            )));
        }
        let weight = (reach.iter())
            .map(|r| match r {
                Reach::One(w) => *w,
                _ => 1.0,
            })
            .collect();
        Ok(Some(Blend {
            step,
            map,
            weight,
            other: Vec::new(),
            extended: Vec::new(),
        }))
    }

    /// Bytes held.
    pub(super) fn bytes(&self) -> usize {
        let points = self.other.capacity() + self.extended.capacity();
        self.map.bytes()
            + self.step.ghosts.bytes()
            + self.weight.capacity() * size_of::<f64>()
            + points * size_of::<[f64; 3]>()
    }

    /// Blends into `next` (the step cut along every sharp edge of `level`, numbered `num`)
    /// the step without the sharpness below 1, w·A + (1 − w)·B per point, then sets each
    /// special vertex whose rule changes across the step by its rules' blend; `alphas` per
    /// special vertex, `ring` the step's 1-ring weights.
    pub(super) fn run<T: Real>(
        &mut self,
        base: &Base<'_>,
        (alphas, ring): (&[f64], [f64; 2]),
        (level, num): (&[[f64; 3]], &Numbering),
        next_num: &Numbering,
        next: &mut [[T; 3]],
        threads: usize,
    ) {
        let (step, other) = (&self.step, &mut self.other);
        step.apply(&self.map, level, &mut self.extended, other, threads);
        let cut = &step.cut;
        cut.curves(base, (alphas, ring), (level, num), next_num, other);
        for ((a, b), &w) in next.iter_mut().zip(other.iter()).zip(&self.weight) {
            if w < 1.0 {
                *a = std::array::from_fn(|i| T::from_f64(w * a[i].to_f64() + (1.0 - w) * b[i]));
            }
        }
        let point = |f: u32, x: i64, y: i64| level[num.index(f as usize, x, y).0];
        let k = cut.k;
        let rules = base.special.iter().zip(base.vertex_rules(k)).enumerate();
        for (i, (&v, rule)) in rules {
            if let (Some(rule), Some(_)) = (rule, base.transition(v, k)) {
                let rule: VertexRule = *rule;
                let child = (v, rule, alphas[i]);
                let plan = (&cut.line, ring, k);
                next[v as usize] = vertex_child(base, child, plan, num.n, point).map(T::from_f64);
            }
        }
    }
}
