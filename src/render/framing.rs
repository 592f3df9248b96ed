//! The mesh brought to the picture's own units before anything is drawn: centred on its
//! bounding box and divided by the box's largest half side, so that the camera, the normals and
//! the curvature fit see coordinates of magnitude 1 whatever the mesh's scale (1e-300 or 1e300)
//! or position (translated by 1e15). Mean curvature is 1/length: it is multiplied back by
//! 1/scale for the report and the legend.

use lsubdiv::mesh::QuadMesh;

/// World = centre + scale · normalised.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Framing {
    /// Centre of the bounding box (world).
    pub centre: [f64; 3],
    /// Largest half side of the bounding box (world), positive and finite.
    pub scale: f64,
}

impl Framing {
    /// The framing of `positions` (finite), or why there is none: every vertex at one point.
    pub fn of(positions: &[[f64; 3]]) -> Result<Framing, String> {
        let (lo, hi) = positions.iter().fold(
            ([f64::INFINITY; 3], [f64::NEG_INFINITY; 3]),
            |(lo, hi), p| {
                (
                    [0, 1, 2].map(|c| lo[c].min(p[c])),
                    [0, 1, 2].map(|c| hi[c].max(p[c])),
                )
            },
        );
        // Halves first: neither the centre nor the half sides overflow.
        let centre = [0, 1, 2].map(|c| 0.5 * lo[c] + 0.5 * hi[c]);
        let scale = (0..3)
            .map(|c| 0.5 * hi[c] - 0.5 * lo[c])
            .fold(0.0, f64::max);
        if !(scale > 0.0 && scale.is_finite()) {
            return Err(format!(
                "the mesh has no extent to draw (every vertex at {:?})",
                if lo[0].is_finite() { lo } else { [0.0; 3] }
            ));
        }
        Ok(Framing { centre, scale })
    }

    /// A world point in normalised coordinates (no intermediate overflow: a difference of two
    /// huge coordinates is halved first).
    pub fn to_normalised(&self, p: [f64; 3]) -> [f64; 3] {
        [0, 1, 2].map(|c| {
            if self.scale > 1.0 {
                (0.5 * p[c] - 0.5 * self.centre[c]) / (0.5 * self.scale)
            } else {
                (p[c] - self.centre[c]) / self.scale
            }
        })
    }

    /// The mesh in normalised coordinates.
    pub fn normalise(&self, mesh: &QuadMesh) -> QuadMesh {
        QuadMesh {
            positions: mesh
                .positions
                .iter()
                .map(|&p| self.to_normalised(p))
                .collect(),
            faces: mesh.faces.clone(),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn any_scale_and_offset_maps_to_the_unit_box() {
        for (s, t) in [
            (1.0, 0.0),
            (1e-300, 0.0),
            (1e300, 0.0),
            (1.7e308, 0.0),
            (1.0, 1e15),
        ] {
            let p = [[-s + t, 0.0, 0.5 * s], [s + t, 0.25 * s, -0.5 * s]];
            let f = Framing::of(&p).unwrap();
            let q = p.map(|x| f.to_normalised(x));
            let expected = [[-1.0, -0.125, 0.5], [1.0, 0.125, -0.5]];
            for (a, b) in q.iter().flatten().zip(expected.iter().flatten()) {
                assert!((a - b).abs() < 1e-12, "{s} {t}: {q:?}");
            }
        }
        assert!(Framing::of(&[[3.0; 3], [3.0; 3]]).is_err());
        assert!(Framing::of(&[]).is_err());
    }
}
