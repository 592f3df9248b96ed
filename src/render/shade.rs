//! Shading of the visible samples and their reduction to pixels (box filter over each pixel's
//! s × s samples).
//!
//! Every mode is two-sided: normals are turned towards the viewer per triangle, so meshes with
//! inconsistent windings or no orientation at all shade like oriented ones. On an orientable
//! mesh the back of the surface (seen through an open boundary or a hole) has its own, warmer
//! material; boundary edges are drawn in their own colour.

use super::camera::Camera;
use super::image::Image;
use super::raster::{Frame, BOUNDARY_LINE, EMPTY, WIRE_LINE};
use super::surface::{cross, dot, normalize, quad_area_vector, scale, sub};
use super::{curvature, Shading};
use lsubdiv::mesh::QuadMesh;
use rayon::prelude::*;

const BACKGROUND: [f64; 3] = [1.0, 1.0, 1.0];
const WIRE: [f64; 3] = [0.08, 0.08, 0.1];
const MATERIAL: [f64; 3] = [0.72, 0.76, 0.82];
/// The back of an oriented surface.
const BACK_MATERIAL: [f64; 3] = [0.86, 0.66, 0.5];
/// Boundary edges.
const BOUNDARY: [f64; 3] = [0.85, 0.25, 0.1];
/// Light and dark stripe pairs of the reflection lines across the environment.
const STRIPES: f64 = 12.0;

/// What the shader reads.
pub struct Shader<'a> {
    /// The mesh drawn.
    pub mesh: &'a QuadMesh,
    /// Unit vertex normals (any sign per vertex).
    pub normals: &'a [[f64; 3]],
    /// Per face, whether its winding is reversed to orient the mesh; none when the mesh is not
    /// orientable (no back side).
    pub flip: Option<&'a [bool]>,
    /// Mean curvature per vertex and the span of the colour map (curvature mode).
    pub curvature: Option<(&'a [f64], f64)>,
    /// The camera that made the frame.
    pub camera: &'a Camera,
    /// The mode.
    pub shading: Shading,
}

/// `n` turned to the side of `towards`.
fn align(n: [f64; 3], towards: [f64; 3]) -> [f64; 3] {
    if dot(n, towards) < 0.0 {
        scale(n, -1.0)
    } else {
        n
    }
}

impl Shader<'_> {
    /// Lights in world space: a key light above left of the camera and a weaker fill from the
    /// right, both towards the scene.
    fn lights(&self) -> [[f64; 3]; 2] {
        let [r, u, f] = self.camera.axes();
        let mix =
            |a: f64, b: f64, c: f64| normalize([0, 1, 2].map(|i| a * r[i] + b * u[i] + c * f[i]));
        [mix(-0.45, 0.6, -1.0), mix(0.8, -0.1, -0.6)]
    }

    /// Colour of one sample.
    fn sample(&self, frame: &Frame, s: usize, lights: &[[f64; 3]; 2]) -> [f64; 3] {
        match frame.wire[s] {
            BOUNDARY_LINE => return BOUNDARY,
            WIRE_LINE => return WIRE,
            _ => {}
        }
        let t = frame.triangle[s];
        if t == EMPTY {
            return BACKGROUND;
        }
        let face = (t / 2) as usize;
        let corners = if t & 1 == 0 { [0, 1, 2] } else { [0, 2, 3] };
        let ids = corners.map(|c| self.mesh.faces[face][c] as usize);
        let p = ids.map(|v| self.mesh.positions[v]);
        let [b1, b2] = frame.bary[s].map(f64::from);
        let w = [1.0 - b1 - b2, b1, b2];
        let mix =
            |x: [[f64; 3]; 3]| [0, 1, 2].map(|c| w[0] * x[0][c] + w[1] * x[1][c] + w[2] * x[2][c]);
        let at = mix(p);
        let ray = normalize(sub(at, self.camera.eye));
        // The triangle's own normal, turned towards the viewer.
        let front = align(cross(sub(p[1], p[0]), sub(p[2], p[0])), scale(ray, -1.0));
        let n = match self.shading {
            Shading::Flat => align(quad_area_vector(self.mesh, face), front),
            _ => mix(ids.map(|v| align(self.normals[v], front))),
        };
        let n = match normalize(n) {
            [0.0, 0.0, 0.0] => normalize(front),
            n => n,
        };
        let diffuse = 0.18 + 0.7 * dot(n, lights[0]).max(0.0) + 0.2 * dot(n, lights[1]).max(0.0);
        // The oriented face normal points away from the viewer: the back is seen.
        let back = self.flip.is_some_and(|flip| {
            let outward = quad_area_vector(self.mesh, face);
            (dot(outward, ray) > 0.0) != flip[face]
        });
        let material = if back { BACK_MATERIAL } else { MATERIAL };
        match self.shading {
            Shading::Flat => material.map(|c| (c * diffuse).min(1.0)),
            Shading::Smooth => {
                let half = normalize(sub(lights[0], ray));
                let specular = 0.3 * dot(n, half).max(0.0).powi(48);
                material.map(|c| (c * diffuse + specular).min(1.0))
            }
            Shading::Curvature => {
                let value = self.curvature.map(|(h, span)| {
                    (w[0] * h[ids[0]] + w[1] * h[ids[1]] + w[2] * h[ids[2]]) / span
                });
                let base = match value {
                    Some(t) if t.is_finite() => curvature::colour(t),
                    _ => [0.5; 3], // no area at a corner: no value
                };
                base.map(|c| (c * (0.45 + 0.6 * diffuse)).min(1.0))
            }
            Shading::Reflection => {
                // The reflected ray looks up a striped environment through the sphere map (the
                // classic reflection-line / zebra lookup): its bisector with the direction back
                // to the camera, up component, picks a stripe. The environment's one singular
                // direction, straight away from the camera, is only reflected at silhouettes.
                let r = sub(ray, scale(n, 2.0 * dot(ray, n)));
                let [right, up, forward] = self.camera.axes();
                let bisector = [dot(r, right), dot(r, up), 1.0 - dot(r, forward)];
                let u = bisector[1] / dot(bisector, bisector).sqrt().max(1e-12);
                let light = if (std::f64::consts::PI * STRIPES * u).sin() >= 0.0 {
                    0.97
                } else {
                    0.12
                };
                [light * (0.85 + 0.15 * diffuse.min(1.0)); 3]
            }
        }
    }

    /// The image: each pixel the mean of its `s` × `s` samples.
    pub fn resolve(&self, frame: &Frame, s: usize) -> Image {
        let (width, height) = (frame.width / s, frame.height / s);
        let lights = self.lights();
        let mut pixels = vec![[0u8; 3]; width * height];
        pixels
            .par_chunks_mut(width)
            .enumerate()
            .for_each(|(y, row)| {
                for (x, px) in row.iter_mut().enumerate() {
                    let mut sum = [0.0; 3];
                    for sy in 0..s {
                        for sx in 0..s {
                            let c = self.sample(
                                frame,
                                (y * s + sy) * frame.width + x * s + sx,
                                &lights,
                            );
                            sum = [sum[0] + c[0], sum[1] + c[1], sum[2] + c[2]];
                        }
                    }
                    let k = 255.0 / (s * s) as f64;
                    *px = sum.map(|c| (c * k).round().clamp(0.0, 255.0) as u8);
                }
            });
        Image {
            width,
            height,
            pixels,
        }
    }
}
