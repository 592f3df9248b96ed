//! A pinhole camera: look-at from an eye to a target, perspective projection to image samples.
//!
//! World up is +z (the axis of the shipped torus and prisms). Image x grows to the right, y
//! downwards; the field of view spans the shorter image side.

use super::surface::{cross, dot, normalize, scale, sub};

/// Field of view across the shorter image side, in degrees.
pub const FOV_DEGREES: f64 = 30.0;

/// Where the camera is.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum View {
    /// On a sphere around the mesh's bounding-sphere centre: azimuth about +z from +x and
    /// elevation above the xy-plane, in degrees; distance in bounding-sphere radii (default:
    /// the whole bounding sphere in view).
    Orbit {
        /// Degrees about +z, from +x towards +y.
        azimuth: f64,
        /// Degrees above the xy-plane (−90 to 90).
        elevation: f64,
        /// From the centre, in radii of the bounding sphere; `None` fits the sphere.
        distance: Option<f64>,
    },
    /// From `eye` towards `target` (default: the bounding-sphere centre), world coordinates.
    LookAt {
        /// Camera position.
        eye: [f64; 3],
        /// Looked-at point.
        target: Option<[f64; 3]>,
    },
}

impl Default for View {
    /// A three-quarter view from above.
    fn default() -> Self {
        View::Orbit {
            azimuth: 35.0,
            elevation: 25.0,
            distance: None,
        }
    }
}

/// A camera for an image of `width` × `height` samples.
#[derive(Clone, Debug)]
pub struct Camera {
    /// Centre of projection.
    pub eye: [f64; 3],
    right: [f64; 3],
    up: [f64; 3],
    forward: [f64; 3],
    /// Focal length in samples.
    focal: f64,
    centre: [f64; 2],
    /// Nearest depth drawn.
    pub near: f64,
}

/// The distance at which a sphere of radius 1 fills the field of view with a little margin.
fn fit_distance() -> f64 {
    1.1 / (FOV_DEGREES.to_radians() / 2.0).sin()
}

impl Camera {
    /// The camera for `view` of a mesh with bounding sphere (`centre`, `radius`), framed in the
    /// leftmost `width` × `height` samples of the image.
    pub fn new(
        view: &View,
        centre: [f64; 3],
        radius: f64,
        width: usize,
        height: usize,
    ) -> Result<Camera, String> {
        let (eye, forward, up_hint) = match *view {
            View::Orbit {
                azimuth,
                elevation,
                distance,
            } => {
                if !(-90.0..=90.0).contains(&elevation) || !azimuth.is_finite() {
                    return Err(format!(
                        "camera elevation {elevation} is outside −90..90 degrees (or azimuth {azimuth} is not finite)"
                    ));
                }
                let d = distance.unwrap_or_else(fit_distance);
                if !(d > 0.0 && d.is_finite()) {
                    return Err(format!("camera distance {d} is not a positive number"));
                }
                let (a, e) = (azimuth.to_radians(), elevation.to_radians());
                let out = [e.cos() * a.cos(), e.cos() * a.sin(), e.sin()];
                // Moving up in the image is increasing the elevation: never degenerate.
                let up = [-e.sin() * a.cos(), -e.sin() * a.sin(), e.cos()];
                let eye = [0, 1, 2].map(|c| centre[c] + d * radius * out[c]);
                (eye, scale(out, -1.0), up)
            }
            View::LookAt { eye, target } => {
                let target = target.unwrap_or(centre);
                let f = normalize(sub(target, eye));
                if f == [0.0; 3] {
                    return Err("the eye and the target are the same point".into());
                }
                let up = if cross(f, [0.0, 0.0, 1.0]) == [0.0; 3] {
                    [0.0, 1.0, 0.0]
                } else {
                    [0.0, 0.0, 1.0]
                };
                (eye, f, up)
            }
        };
        let right = normalize(cross(forward, up_hint));
        let up = cross(right, forward);
        let focal = 0.5 * width.min(height) as f64 / (FOV_DEGREES.to_radians() / 2.0).tan();
        Ok(Camera {
            eye,
            right,
            up,
            forward,
            focal,
            centre: [0.5 * width as f64, 0.5 * height as f64],
            near: 1e-4 * radius,
        })
    }

    /// Camera coordinates of a world point: (right, up, depth along the view direction).
    pub fn to_view(&self, p: [f64; 3]) -> [f64; 3] {
        let d = sub(p, self.eye);
        [dot(d, self.right), dot(d, self.up), dot(d, self.forward)]
    }

    /// Image position (samples, y down) of a camera-space point in front of the camera.
    pub fn project(&self, v: [f64; 3]) -> [f64; 2] {
        [
            self.centre[0] + self.focal * v[0] / v[2],
            self.centre[1] - self.focal * v[1] / v[2],
        ]
    }

    /// The clipping planes as (a, b, c) with a·x + b·y + c·z ≥ 0 inside (camera space): the
    /// near plane (with offset, see [`Camera::near`]) and four sides a guard band of one image
    /// size beyond the image, so that projected coordinates stay small.
    pub fn planes(&self) -> [[f64; 4]; 5] {
        let [cx, cy] = self.centre;
        let f = self.focal;
        // x_s = cx + f x / z ∈ [−2cx, 4cx]  ⇔  f x + 3cx z ≥ 0 and −f x + 3cx z ≥ 0.
        [
            [0.0, 0.0, 1.0, -self.near],
            [f, 0.0, 3.0 * cx, 0.0],
            [-f, 0.0, 3.0 * cx, 0.0],
            [0.0, f, 3.0 * cy, 0.0],
            [0.0, -f, 3.0 * cy, 0.0],
        ]
    }

    /// World direction of the camera's right, up and forward axes.
    pub fn axes(&self) -> [[f64; 3]; 3] {
        [self.right, self.up, self.forward]
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_target_projects_to_the_image_centre_and_axes_are_right() {
        let c = Camera::new(
            &View::LookAt {
                eye: [0.0, -5.0, 0.0],
                target: Some([0.0; 3]),
            },
            [0.0; 3],
            1.0,
            800,
            600,
        )
        .unwrap();
        assert_eq!(c.project(c.to_view([0.0; 3])), [400.0, 300.0]);
        // Looking along +y with z up: +x is to the right, +z up (smaller image y).
        let [x, y] = c.project(c.to_view([1.0, 0.0, 0.0]));
        assert!(x > 400.0 && (y - 300.0).abs() < 1e-9);
        let [x, y] = c.project(c.to_view([0.0, 0.0, 1.0]));
        assert!((x - 400.0).abs() < 1e-9 && y < 300.0);
        // A point at depth 5 and height tan(15°)·5 lands on the top edge (fov spans 600 rows).
        let h = 5.0 * (15f64).to_radians().tan();
        let [_, y] = c.project(c.to_view([0.0, 0.0, h]));
        assert!(y.abs() < 1e-9, "{y}");
    }

    #[test]
    fn the_fitted_orbit_keeps_the_bounding_sphere_in_view() {
        for (azimuth, elevation) in [(35.0, 25.0), (0.0, 90.0), (200.0, -90.0), (-10.0, 0.0)] {
            let view = View::Orbit {
                azimuth,
                elevation,
                distance: None,
            };
            let centre = [1.0, 2.0, 3.0];
            let c = Camera::new(&view, centre, 2.0, 640, 480).unwrap();
            let d = sub(c.eye, centre);
            assert!((dot(d, d).sqrt() - 2.0 * fit_distance()).abs() < 1e-9);
            for dir in [[1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0]] {
                for s in [-2.0, 2.0] {
                    let p = [0, 1, 2].map(|i| centre[i] + s * dir[i]);
                    let [x, y] = c.project(c.to_view(p));
                    assert!(
                        (0.0..640.0).contains(&x) && (0.0..480.0).contains(&y),
                        "{p:?}"
                    );
                }
            }
        }
        let view = View::Orbit {
            azimuth: 0.0,
            elevation: 91.0,
            distance: None,
        };
        assert!(Camera::new(&view, [0.0; 3], 1.0, 10, 10).is_err());
    }
}
