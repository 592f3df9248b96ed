//! A reference step on a mesh cut along its sharp edges (`Cut`) where a sharpness below 1
//! makes a rule a blend of the sharp and the smooth one (OpenSubdiv's fractional sharpness,
//! docs/real-meshes.md): an edge's phantoms are w(2P − Q) + (1 − w)R, linear in the ring, so
//! the step is w times the step cut along that edge plus 1 − w times the step without it.
//! The step runs twice, cut along every sharp edge (the refiner's own cut) and cut along the
//! edges sharp in full only (here), and each point takes the blend by the sharpness below 1
//! that reaches it; a vertex whose rule changes across the step takes its two rules' blend
//! (`vertex_child`, `Resolved::transition`).

use super::{vertex_child, Base, Cut, Numbering, Plan, Reference};
use crate::features::VertexRule;
use crate::grid::{site, Site};
use crate::real::Real;
use crate::surface::{SurfaceError, SurfaceScheme};

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

/// The smooth side of a first step's blends ([`Blend::run`]).
pub(super) struct Blend {
    /// The mesh cut along the edges sharp in full at the step.
    cut: Cut,
    reference: Reference,
    /// Per point of the level after the step, the weight of the step cut along every sharp
    /// edge (1 where no sharpness below 1 reaches the point).
    weight: Vec<f64>,
}

impl Blend {
    /// The blend of the reference step `0..1` to the level numbered `num`, none where no
    /// sharpness is below 1. A new point is reached by the edges at the corners of the faces
    /// it lies in (the reference scatter's faces); points reached by two different
    /// sharpnesses below 1 are refused (the step would be bilinear in them).
    pub(super) fn new<S: SurfaceScheme>(
        scheme: &S,
        base: &Base<'_>,
        line: Plan,
        num: &Numbering,
        threads: usize,
    ) -> Result<Option<Blend>, SurfaceError> {
        if !base.features.has_fractions() {
            return Ok(None);
        }
        let topo = base.topo;
        let smooth = base.features.without_fractions();
        let refused = |why: &str| {
            SurfaceError::Unsupported(format!(
                "the first step of scheme `{}` runs the reference driver on the mesh cut open \
                 along its sharp edges, and {why}",
                scheme.tables().name
            ))
        };
        let cut = Cut::new(topo, &smooth, line).ok_or_else(|| refused("the cut failed"))?;
        let reference = Reference::new(scheme, base, (1, num), None, Some(&cut), threads)?;
        let mut at = vec![Reach::None; topo.vertex_count()];
        for e in 0..topo.edge_count() as u32 {
            let w = base.features.edge_weight(e, 0);
            if w > 0.0 && w < 1.0 {
                for v in topo.edge_vertices(e) {
                    at[v as usize] = at[v as usize].and(Reach::One(w));
                }
            }
        }
        let mut reach = vec![Reach::None; num.len()];
        for f in 0..topo.face_count() as u32 {
            let r = (0..4).fold(Reach::None, |r, c| r.and(at[topo.vertex(f, c) as usize]));
            if r == Reach::None {
                continue;
            }
            for y in 0..=num.n {
                for x in 0..=num.n {
                    let i = num.index(f as usize, x, y).0;
                    reach[i] = reach[i].and(r);
                }
            }
        }
        if reach.contains(&Reach::Many) {
            return Err(refused(
                "two edges of different sharpness below 1 reach one face there (the step \
                 would blend in both at once)",
            ));
        }
        let weight = (reach.iter())
            .map(|r| match r {
                Reach::One(w) => *w,
                _ => 1.0,
            })
            .collect();
        Ok(Some(Blend {
            cut,
            reference,
            weight,
        }))
    }

    /// Bytes held.
    pub(super) fn bytes(&self) -> usize {
        self.reference.bytes() + self.weight.capacity() * size_of::<f64>()
    }

    /// Blends into `start` (the step cut along every sharp edge of `positions`) the step
    /// without the sharpness below 1 (in `other`), w·A + (1 − w)·B per point, then sets each
    /// special vertex whose rule changes across the step by its rules' blend; `alphas` per
    /// special vertex, `ring` the step's 1-ring weights.
    #[allow(clippy::too_many_arguments)]
    pub(super) fn run<T: Real>(
        &mut self,
        base: &Base<'_>,
        (alphas, ring): (&[f64], [f64; 2]),
        positions: &[[f64; 3]],
        num: &Numbering,
        start: &mut [[T; 3]],
        other: &mut Vec<[T; 3]>,
        threads: usize,
    ) {
        let mut level0: Vec<[f64; 3]> = (self.cut.source.iter())
            .map(|&v| positions[v as usize])
            .collect();
        self.reference.ghosts().extend(&mut level0);
        self.reference.run(&level0, other, threads);
        let alpha = |v: u32| {
            let i = base.special.binary_search(&v);
            i.map_or(0.0, |i| alphas[i])
        };
        self.cut.curves(base, (&alpha, ring), positions, num, other);
        for ((a, b), &w) in start.iter_mut().zip(other.iter()).zip(&self.weight) {
            if w < 1.0 {
                *a = std::array::from_fn(|i| {
                    T::from_f64(w * a[i].to_f64() + (1.0 - w) * b[i].to_f64())
                });
            }
        }
        // Level 0 as a face's corners (N = 1).
        let point = |f: u32, x: i64, y: i64| match site(x, y, 1, 1) {
            Site::Corner(c) => positions[base.topo.vertex(f, c) as usize].map(T::from_f64),
            _ => unreachable!("a vertex rule at N = 1 reads the faces' corners"),
        };
        let rules = base.special.iter().zip(base.vertex_rules(0)).enumerate();
        for (i, (&v, rule)) in rules {
            if let (Some(rule), Some(_)) = (rule, base.transition(v, 0)) {
                let rule: VertexRule = *rule;
                let child = (v, rule, alphas[i]);
                let plan = (&self.cut.line, ring, 0);
                start[v as usize] = vertex_child(base, child, plan, 1, point);
            }
        }
    }
}
