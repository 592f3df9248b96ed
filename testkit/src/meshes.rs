//! Test meshes built from the runtime's generators.

use lsubdiv::mesh::features::Features;
use lsubdiv::mesh::polygon::{catmull_clark, PolyMesh};
use lsubdiv::mesh::QuadMesh;

/// `mesh` without the faces whose every vertex lies above `z` (a cap cut off a closed mesh,
/// leaving a boundary loop), its vertices renumbered in the order the kept faces reach them.
pub fn capless(mesh: &PolyMesh, z: f64) -> PolyMesh {
    let mut open = PolyMesh::new();
    let mut index = vec![u32::MAX; mesh.positions.len()];
    for face in mesh.faces() {
        if face.iter().all(|&v| mesh.positions[v as usize][2] > z) {
            continue;
        }
        let kept: Vec<u32> = face
            .iter()
            .map(|&v| {
                if index[v as usize] == u32::MAX {
                    index[v as usize] = open.positions.len() as u32;
                    open.positions.push(mesh.positions[v as usize]);
                }
                index[v as usize]
            })
            .collect();
        open.push_face(&kept);
    }
    open
}

/// A polygon mesh without features split into quads by one Catmull–Clark step: a triangle
/// mesh becomes a quad mesh whose every face has two EV corners.
pub fn split(mesh: &PolyMesh) -> QuadMesh {
    catmull_clark(mesh, &Features::default())
        .expect("a valid polygon mesh splits")
        .mesh
}
