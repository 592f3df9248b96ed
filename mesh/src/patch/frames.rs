//! One topology refined frame after frame, as OpenSubdiv's `PrimvarRefiner` is applied to each
//! frame of an animation: the refiner (its plans, composed patches and reference maps), the
//! output quads and the renumbering that drops the holes' vertices are built once; a frame is
//! one [`Refiner::refine`] and, asked, its limit ([`Refiner::limit`]).

use super::{keep, kept_limit, renumbered, used, Refiner, SurfaceLimit};
use crate::features::{Creasing, Features};
use crate::real::Real;
use crate::surface::{SurfaceError, SurfaceScheme};
use crate::topology::Topology;

/// A refinement of one quad mesh topology (with its features), reused for new positions.
pub struct Frames<'s, S, T> {
    refiner: Refiner<'s, S, T>,
    faces: Vec<[u32; 4]>,
    /// With holes, each output vertex's index once the vertices only holes use are dropped.
    kept: Option<Vec<u32>>,
}

impl<'s, S: SurfaceScheme + Sync, T: Real> Frames<'s, S, T> {
    /// `steps` steps of `scheme` on the mesh of topology `topo` with `features`
    /// ([`Refiner::with_features`]). Chaikin creasing takes each step from a new base mesh
    /// (`patch::subdivide_with`), so it is refused here past one step.
    pub fn new(
        scheme: &'s S,
        topo: &'s Topology,
        features: &Features,
        steps: usize,
        threads: usize,
    ) -> Result<Self, SurfaceError> {
        if features.creasing == Creasing::Chaikin && steps > 1 {
            return Err(SurfaceError::Unsupported(
                "Chaikin creasing refines from a new base mesh each step: refine each frame \
                 whole (`patch::subdivide_with`)"
                    .into(),
            ));
        }
        let refiner = Refiner::with_features(scheme, topo, features, steps, threads)?;
        let faces = refiner.faces();
        let kept = used(
            &faces,
            refiner.output_vertices(),
            refiner.base.features.has_holes(),
        );
        let faces = renumbered(&kept, faces);
        Ok(Frames {
            refiner,
            faces,
            kept,
        })
    }

    /// The refined quads, the same for every frame (holes dropped).
    pub fn faces(&self) -> &[[u32; 4]] {
        &self.faces
    }

    /// The number of refined vertices (holes' dropped).
    pub fn vertices(&self) -> usize {
        match &self.kept {
            None => self.refiner.output_vertices(),
            Some(kept) => kept.iter().filter(|&&k| k != u32::MAX).count(),
        }
    }

    /// The frame `positions` (one per base vertex) refined.
    pub fn refine(&mut self, positions: &[[f64; 3]]) -> Result<Vec<[T; 3]>, SurfaceError> {
        let fine = self.refiner.refine(positions)?;
        Ok(keep(&self.kept, fine.to_vec()))
    }

    /// The frame `positions` refined, then taken to the limit surface with normals.
    pub fn limit(&mut self, positions: &[[f64; 3]]) -> Result<SurfaceLimit<T>, SurfaceError> {
        self.refiner.refine(positions)?;
        Ok(kept_limit(&self.kept, self.refiner.limit()?))
    }
}
