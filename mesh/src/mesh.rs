//! The mesh type of the runtime: a quad mesh, closed or open, what the refiners read and write.
//!
//! Its connectivity is checked and indexed by [`crate::topology::Topology`]; files (OBJ, PLY)
//! are read and written by the facade (`lsubdiv::obj`, `lsubdiv::ply`).

/// A polygonal mesh with quad faces (corner order as given), positions of scalar type `T`:
/// f64 for input meshes, f64 or f32 for refined ones.
#[derive(Clone, Debug, PartialEq)]
pub struct QuadMesh<T = f64> {
    /// Vertex positions.
    pub positions: Vec<[T; 3]>,
    /// Faces: four 0-based vertex indices each, in corner order.
    pub faces: Vec<[u32; 4]>,
}
