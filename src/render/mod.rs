//! Software rendering of quad meshes (closed or open) for `lsubdiv render`: no GPU, no system library.
//!
//! A perspective camera ([`camera`]), a z-buffered rasteriser with exact edge functions and
//! supersampling ([`raster`]), deferred per-sample shading ([`shade`]) in four modes — flat,
//! smooth, the mean-curvature colour map and reflection lines, the two pictures \[G\] Fig. 6 uses
//! to judge a scheme near extraordinary vertices — and an optional wireframe of the quad edges.
//! Each quad is drawn as the triangles (0, 1, 2) and (0, 2, 3).

pub mod camera;
pub mod curvature;
pub mod framing;
pub mod image;
pub mod legend;
pub mod raster;
pub mod shade;
pub mod surface;

use camera::{Camera, View};
use framing::Framing;
use image::Image;
use lsubdiv::mesh::topology::Topology;
use lsubdiv::mesh::QuadMesh;
use raster::{clip, plane_value, ClipVertex, Frame, Vertex, EMPTY};
use rayon::prelude::*;

/// How the surface is coloured.
#[derive(Clone, Copy, Debug, PartialEq, Eq, clap::ValueEnum)]
pub enum Shading {
    /// One normal per quad, diffuse light.
    Flat,
    /// Interpolated vertex normals, diffuse and specular light.
    Smooth,
    /// Mean curvature: blue negative, green zero, red positive (\[G\] Fig. 6, fourth row).
    Curvature,
    /// Reflection lines of light lines at infinity (\[G\] Fig. 6, third row).
    Reflection,
}

/// What to draw.
#[derive(Clone, Debug)]
pub struct Options {
    /// Image width in pixels.
    pub width: usize,
    /// Image height in pixels.
    pub height: usize,
    /// Camera placement.
    pub view: View,
    /// Colouring.
    pub shading: Shading,
    /// Draw the quad edges.
    pub wireframe: bool,
    /// Colours of the curvature map span [−r, r]; default: the 98th percentile of |H| over the
    /// vertices of the faces in the picture.
    pub curvature_range: Option<f64>,
}

/// A rendered picture and what the caller may want to report.
pub struct Rendered {
    /// The picture.
    pub image: Image,
    /// The curvature values and colour span (curvature mode).
    pub curvature: Option<curvature::Range>,
}

/// A mesh ready to draw: connectivity checked, faces oriented, normals and bounding sphere, in
/// the picture's normalised coordinates ([`framing`]).
pub struct Scene<'m> {
    mesh: QuadMesh,
    topology: &'m Topology,
    oriented: surface::Oriented,
    framing: Framing,
    radius: f64,
}

/// Parses `n` comma-separated finite numbers, the value of `flag` (a `--camera`-style argument).
pub fn parse_numbers(
    flag: &str,
    text: &str,
    n: std::ops::RangeInclusive<usize>,
) -> Result<Vec<f64>, lsubdiv::Diagnostic> {
    let values: Vec<f64> = text
        .split(',')
        .map(|t| t.trim().parse::<f64>().ok().filter(|x| x.is_finite()))
        .collect::<Option<_>>()
        .filter(|v: &Vec<f64>| n.contains(&v.len()))
        .ok_or_else(|| {
            lsubdiv::Diagnostic::input(format!(
                "{flag} `{text}`: expected {} comma-separated numbers",
                if n.start() == n.end() {
                    n.start().to_string()
                } else {
                    format!("{} to {}", n.start(), n.end())
                }
            ))
        })?;
    Ok(values)
}

/// Samples per pixel side: 3 × 3 while the frame stays under ~9.4 M samples, else fewer.
pub fn supersampling(width: usize, height: usize) -> usize {
    (1..=3)
        .rev()
        .find(|s| width * height * s * s <= 9 << 20)
        .unwrap_or(1)
}

impl<'m> Scene<'m> {
    /// Orients the mesh (a 2-manifold quad mesh of topology `topology`, as for
    /// `subdivide`) and measures it. Shading and the curvature fit use `normals` (one unit
    /// normal a vertex, oriented with the face winding: the limit surface's) where given, else
    /// normals averaged from the faces ([`surface::orient`]).
    pub fn new(
        mesh: &QuadMesh,
        topology: &'m Topology,
        normals: Option<Vec<[f64; 3]>>,
    ) -> Result<Scene<'m>, String> {
        if let Some(n) = normals.as_ref().filter(|n| n.len() != mesh.positions.len()) {
            return Err(format!(
                "{} normals given for {} vertices",
                n.len(),
                mesh.positions.len()
            ));
        }
        let framing = Framing::of(&mesh.positions)?;
        let mesh = framing.normalise(mesh);
        // At most √3: the box is [−1, 1]³.
        let radius = mesh
            .positions
            .iter()
            .map(|&p| surface::dot(p, p))
            .fold(0.0, f64::max)
            .sqrt();
        // The framing moves and scales uniformly: the normals stay as they are.
        let oriented = surface::orient(&mesh, topology, normals);
        Ok(Scene {
            mesh,
            topology,
            oriented,
            framing,
            radius,
        })
    }

    /// Every component could be oriented (else the sign of the mean curvature flips across a
    /// seam).
    pub fn orientable(&self) -> bool {
        self.oriented.orientable
    }

    /// Draws the picture.
    pub fn render(&self, opts: &Options) -> Result<Rendered, String> {
        let s = supersampling(opts.width, opts.height);
        let (w, h) = (opts.width * s, opts.height * s);
        // The curvature legend gets a strip at the right; the picture is framed beside it.
        let legend = opts.shading == Shading::Curvature && legend::fits(opts.width, opts.height);
        let viewport = w - if legend { legend::WIDTH * s } else { 0 };
        let camera = Camera::new(&self.view(&opts.view), [0.0; 3], self.radius, viewport, h)?;
        let mut frame = Frame::new(w, h);
        let projected = Projected::new(&self.mesh, &camera);
        for (f, face) in self.mesh.faces.iter().enumerate() {
            for (k, tri) in [[0, 1, 2], [0, 2, 3]].iter().enumerate() {
                projected.triangle(
                    &mut frame,
                    (2 * f + k) as u32,
                    tri.map(|c| face[c] as usize),
                );
            }
        }
        self.edges(&projected, &mut frame, s, opts.wireframe);
        let (values, range) = if opts.shading == Shading::Curvature {
            let h = curvature::mean_curvature(&self.mesh, self.topology, &self.oriented.normals);
            // A given range is in the mesh's units: H scales as 1/length.
            let given = opts.curvature_range.map(|r| r * self.framing.scale);
            if given.is_some_and(|g| !(g > 0.0 && g.is_finite())) {
                return Err(format!(
                    "--curvature-range {:e} is outside the f64 range at this mesh's scale (bounding box half side {:e})",
                    opts.curvature_range.unwrap_or_default(),
                    self.framing.scale
                ));
            }
            let range = curvature::range(&self.seen(&frame, &h), given);
            (Some(h), Some(range))
        } else {
            (None, None)
        };
        let shader = shade::Shader {
            mesh: &self.mesh,
            normals: &self.oriented.normals,
            flip: self
                .oriented
                .orientable
                .then_some(self.oriented.flip.as_slice()),
            curvature: values.as_deref().zip(range.map(|r| r.span)),
            camera: &camera,
            shading: opts.shading,
        };
        let mut image = shader.resolve(&frame, s);
        let range = range.map(|r| r.in_units_of(self.framing.scale));
        if let (true, Some(r)) = (legend, &range) {
            legend::bar(&mut image, r)?;
        }
        Ok(Rendered {
            image,
            curvature: range,
        })
    }

    /// `view` with world points (`--eye`, `--target`) in normalised coordinates.
    fn view(&self, view: &View) -> View {
        match *view {
            View::LookAt { eye, target } => View::LookAt {
                eye: self.framing.to_normalised(eye),
                target: target.map(|t| self.framing.to_normalised(t)),
            },
            orbit => orbit,
        }
    }

    /// The values at the vertices of the faces seen in `frame`, each vertex once.
    fn seen(&self, frame: &Frame, values: &[f64]) -> Vec<f64> {
        let mut face = vec![false; self.mesh.faces.len()];
        for &t in &frame.triangle {
            if t != EMPTY {
                face[(t / 2) as usize] = true;
            }
        }
        let mut vertex = vec![false; values.len()];
        for (f, _) in face.iter().enumerate().filter(|(_, &seen)| seen) {
            for &v in &self.mesh.faces[f] {
                vertex[v as usize] = true;
            }
        }
        values
            .iter()
            .zip(vertex)
            .filter(|(_, seen)| *seen)
            .map(|(&h, _)| h)
            .collect()
    }

    /// Marks the boundary edges, two pixels wide, and with `wireframe` every other quad edge,
    /// one pixel wide. A sample shows the line unless a surface other than the edge's faces is
    /// in front of it by more than a small depth offset (0.2 % of the depth), which keeps lines
    /// whole over their own faces at grazing angles.
    fn edges(&self, projected: &Projected<'_>, frame: &mut Frame, s: usize, wireframe: bool) {
        for e in 0..self.topology.edge_count() as u32 {
            let [a, b] = self.topology.edge_vertices(e);
            let (first, second) = self.topology.edge_faces(e);
            let (kind, width) = match second {
                None => (raster::BOUNDARY_LINE, 2 * s),
                Some(_) if wireframe => (raster::WIRE_LINE, s),
                Some(_) => continue,
            };
            let faces = [Some(first.0), second.map(|(f, _)| f)];
            let visible = |t: u32, surface: f32, line: f64| {
                t == EMPTY || faces.contains(&Some(t / 2)) || line >= f64::from(surface) * 0.998
            };
            if let Some((pa, pb)) = projected.segment(a as usize, b as usize) {
                frame.line(pa, pb, width, kind, visible);
            }
        }
    }
}

/// The mesh's vertices in camera space, which clipping planes each is outside, and the
/// projections of those inside all of them.
struct Projected<'c> {
    camera: &'c Camera,
    planes: [[f64; 4]; 5],
    view: Vec<[f64; 3]>,
    outside: Vec<u8>,
}

impl<'c> Projected<'c> {
    fn new(mesh: &QuadMesh, camera: &'c Camera) -> Projected<'c> {
        let planes = camera.planes();
        let view: Vec<[f64; 3]> = mesh
            .positions
            .par_iter()
            .map(|&p| camera.to_view(p))
            .collect();
        let outside = view
            .par_iter()
            .map(|&v| {
                planes
                    .iter()
                    .enumerate()
                    .filter(|(_, pl)| plane_value(pl, v) < 0.0)
                    .fold(0u8, |m, (i, _)| m | 1 << i)
            })
            .collect();
        Projected {
            camera,
            planes,
            view,
            outside,
        }
    }

    fn vertex(&self, p: [f64; 3], bary: [f64; 3]) -> Vertex {
        let [x, y] = self.camera.project(p);
        Vertex {
            x,
            y,
            inv_depth: 1.0 / p[2],
            bary,
        }
    }

    /// Draws the triangle with vertices `v`, clipped.
    fn triangle(&self, frame: &mut Frame, id: u32, v: [usize; 3]) {
        let codes = v.map(|i| self.outside[i]);
        if codes[0] & codes[1] & codes[2] != 0 {
            return; // wholly outside one plane
        }
        let unit = |c: usize| {
            let mut b = [0.0; 3];
            b[c] = 1.0;
            b
        };
        if codes == [0; 3] {
            frame.triangle(id, [0, 1, 2].map(|c| self.vertex(self.view[v[c]], unit(c))));
            return;
        }
        let mut poly: Vec<ClipVertex> = (0..3)
            .map(|c| ClipVertex {
                p: self.view[v[c]],
                bary: unit(c),
            })
            .collect();
        clip(&mut poly, &self.planes);
        let fan: Vec<Vertex> = poly.iter().map(|c| self.vertex(c.p, c.bary)).collect();
        for i in 1..fan.len().saturating_sub(1) {
            frame.triangle(id, [fan[0], fan[i], fan[i + 1]]);
        }
    }

    /// The visible part of the segment between two vertices, projected.
    fn segment(&self, a: usize, b: usize) -> Option<(Vertex, Vertex)> {
        if self.outside[a] & self.outside[b] != 0 {
            return None;
        }
        let (mut t0, mut t1) = (0.0f64, 1.0f64);
        let (pa, pb) = (self.view[a], self.view[b]);
        for pl in &self.planes {
            let (da, db) = (plane_value(pl, pa), plane_value(pl, pb));
            if da < 0.0 && db < 0.0 {
                return None;
            }
            if da < 0.0 {
                t0 = t0.max(da / (da - db));
            } else if db < 0.0 {
                t1 = t1.min(da / (da - db));
            }
        }
        if t0 > t1 {
            return None;
        }
        let at = |t: f64| [0, 1, 2].map(|c| pa[c] + t * (pb[c] - pa[c]));
        Some((self.vertex(at(t0), [0.0; 3]), self.vertex(at(t1), [0.0; 3])))
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use lsubdiv::mesh::generators::cube;

    #[test]
    fn given_normals_are_one_a_vertex() {
        let m = cube();
        let topology = Topology::build(&m).unwrap();
        let e = Scene::new(&m, &topology, Some(vec![[0.0, 0.0, 1.0]; 7])).err();
        assert_eq!(e.as_deref(), Some("7 normals given for 8 vertices"));
        let normals: Vec<[f64; 3]> = m.positions.iter().map(|&p| surface::normalize(p)).collect();
        let scene = Scene::new(&m, &topology, Some(normals.clone())).unwrap();
        assert_eq!(scene.oriented.normals, normals);
    }
}
