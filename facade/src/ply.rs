//! PLY output of quad meshes (ASCII).

use lsubdiv_runtime::mesh::QuadMesh;
use std::fmt::Write as _;

/// Writes `mesh` to `path` as ASCII PLY ([`format`]), whole or not at all.
pub fn write(path: &std::path::Path, mesh: &QuadMesh) -> Result<(), crate::Error> {
    crate::write_atomic(path, format(mesh)?.as_bytes())
}

/// ASCII PLY: vertex x y z as double (round-trip precision), faces as a `uchar int` list; a
/// non-finite coordinate is refused ([`crate::points::finite`]).
pub fn format(mesh: &QuadMesh) -> Result<String, crate::Error> {
    crate::points::finite("vertex", &mesh.positions)?;
    let mut s = String::with_capacity(32 * mesh.positions.len() + 24 * mesh.faces.len() + 256);
    let _ = write!(
        s,
        "ply\nformat ascii 1.0\ncomment lsubdiv quad mesh\nelement vertex {}\n\
         property double x\nproperty double y\nproperty double z\nelement face {}\n\
         property list uchar int vertex_indices\nend_header\n",
        mesh.positions.len(),
        mesh.faces.len()
    );
    for p in &mesh.positions {
        let _ = writeln!(s, "{:?} {:?} {:?}", p[0], p[1], p[2]);
    }
    for f in &mesh.faces {
        let _ = writeln!(s, "4 {} {} {} {}", f[0], f[1], f[2], f[3]);
    }
    Ok(s)
}

#[cfg(test)]
mod tests {
    use super::*;
    use lsubdiv_runtime::generators::cube;

    #[test]
    fn ply_header_and_body() {
        let m = cube();
        let ply = format(&m).unwrap();
        let lines: Vec<&str> = ply.lines().collect();
        assert_eq!(
            &lines[..10],
            &[
                "ply",
                "format ascii 1.0",
                "comment lsubdiv quad mesh",
                "element vertex 8",
                "property double x",
                "property double y",
                "property double z",
                "element face 6",
                "property list uchar int vertex_indices",
                "end_header",
            ]
        );
        assert_eq!(lines.len(), 10 + 8 + 6);
        assert_eq!(lines[10], "-1.0 -1.0 -1.0");
        let f0 = m.faces[0];
        assert_eq!(
            lines[18],
            format!("4 {} {} {} {}", f0[0], f0[1], f0[2], f0[3])
        );
        for (line, p) in lines[10..18].iter().zip(&m.positions) {
            let xs: Vec<f64> = line.split(' ').map(|t| t.parse().unwrap()).collect();
            assert_eq!(xs, p.to_vec());
        }
    }
}
