//! Triangle and line rasterisation into a z-buffered frame of samples that remembers, per sample,
//! which triangle is visible and where in it (perspective-correct barycentric coordinates), so
//! that shading runs once per visible sample ("deferred" shading).
//!
//! Triangles are rasterised over their bounding box with exact integer edge functions on vertex
//! positions snapped to 1/256 sample, and a fill rule that gives a sample on a shared edge to
//! exactly one of the two triangles: no cracks, no double hits. Both windings are drawn.

/// Sub-sample precision of snapped vertex positions.
const SUB: i64 = 256;

/// No triangle at this sample.
pub const EMPTY: u32 = u32::MAX;

/// A projected vertex: image position in samples, 1/depth, and its barycentric coordinates in the
/// triangle it came from (a corner of it, or a point on an edge after clipping).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Vertex {
    /// Image x in samples.
    pub x: f64,
    /// Image y in samples (down).
    pub y: f64,
    /// 1 / camera depth.
    pub inv_depth: f64,
    /// Coordinates in the original triangle.
    pub bary: [f64; 3],
}

/// A z-buffered frame of `width` × `height` samples.
pub struct Frame {
    /// Samples per row.
    pub width: usize,
    /// Rows.
    pub height: usize,
    /// 1 / depth of the nearest surface (0: none).
    pub inv_depth: Vec<f32>,
    /// Triangle seen, or [`EMPTY`].
    pub triangle: Vec<u32>,
    /// Perspective-correct weights of the seen triangle's corners 1 and 2.
    pub bary: Vec<[f32; 2]>,
    /// Which line covers the sample: [`NO_LINE`], [`WIRE_LINE`] or [`BOUNDARY_LINE`] (the
    /// larger wins).
    pub wire: Vec<u8>,
}

/// No line covers the sample.
pub const NO_LINE: u8 = 0;
/// A wireframe line.
pub const WIRE_LINE: u8 = 1;
/// A boundary edge (drawn over the wireframe).
pub const BOUNDARY_LINE: u8 = 2;

/// Twice the signed area of (a, b, c), in snapped units; positive when c is on the interior side
/// of a → b for the orientation used here.
fn edge(a: [i64; 2], b: [i64; 2], c: [i64; 2]) -> i64 {
    (b[0] - a[0]) * (c[1] - a[1]) - (b[1] - a[1]) * (c[0] - a[0])
}

/// Whether samples exactly on edge a → b belong to its triangle. Reversing the edge reverses
/// the answer, so the two triangles sharing an edge never both (or neither) take such a sample.
fn owns(a: [i64; 2], b: [i64; 2]) -> bool {
    let (dx, dy) = (b[0] - a[0], b[1] - a[1]);
    dy > 0 || (dy == 0 && dx < 0)
}

/// The steps k in 0..=last where every edge function `w[i] + step[i] · k` is ≥ 0, exactly: the
/// row's span inside the triangle (empty: start > end).
fn inside(w: [i64; 3], step: [i64; 3], last: i64) -> std::ops::RangeInclusive<i64> {
    let (mut lo, mut hi) = (0, last);
    for i in 0..3 {
        match step[i].signum() {
            1 => {
                lo = lo
                    .max((-w[i]).div_euclid(step[i]) + i64::from((-w[i]).rem_euclid(step[i]) != 0))
            }
            -1 => hi = hi.min(w[i].div_euclid(-step[i])),
            _ if w[i] < 0 => hi = -1,
            _ => {}
        }
    }
    lo..=hi
}

/// Index range of the sample centres (i + ½) inside [lo, hi] (snapped units), within 0..n.
fn centres(lo: i64, hi: i64, n: usize) -> std::ops::RangeInclusive<i64> {
    let first = (lo - SUB / 2 + SUB - 1).div_euclid(SUB).max(0);
    let last = (hi - SUB / 2).div_euclid(SUB).min(n as i64 - 1);
    first..=last
}

impl Frame {
    /// An empty frame.
    pub fn new(width: usize, height: usize) -> Frame {
        let n = width * height;
        Frame {
            width,
            height,
            inv_depth: vec![0.0; n],
            triangle: vec![EMPTY; n],
            bary: vec![[0.0; 2]; n],
            wire: vec![NO_LINE; n],
        }
    }

    /// Draws triangle `id`, keeping the nearest surface at each sample. The caller clips to the
    /// camera's planes first, so coordinates are within a few image sizes.
    pub fn triangle(&mut self, id: u32, mut v: [Vertex; 3]) {
        let snap = |v: &Vertex| {
            [
                (v.x * SUB as f64).round() as i64,
                (v.y * SUB as f64).round() as i64,
            ]
        };
        let mut p = [snap(&v[0]), snap(&v[1]), snap(&v[2])];
        let mut area = edge(p[0], p[1], p[2]);
        if area == 0 {
            return;
        }
        if area < 0 {
            v.swap(1, 2);
            p.swap(1, 2);
            area = -area;
        }
        let xs = centres(
            p.iter().map(|q| q[0]).min().unwrap_or(0),
            p.iter().map(|q| q[0]).max().unwrap_or(0),
            self.width,
        );
        let ys = centres(
            p.iter().map(|q| q[1]).min().unwrap_or(0),
            p.iter().map(|q| q[1]).max().unwrap_or(0),
            self.height,
        );
        if xs.is_empty() || ys.is_empty() {
            return;
        }
        // Edge i is opposite corner i: from corner i+1 to i+2.
        let ends = [(p[1], p[2]), (p[2], p[0]), (p[0], p[1])];
        let bias = ends.map(|(a, b)| if owns(a, b) { 0 } else { -1 });
        let step_x = ends.map(|(a, b)| -(b[1] - a[1]) * SUB);
        let step_y = ends.map(|(a, b)| (b[0] - a[0]) * SUB);
        let start = [*xs.start() * SUB + SUB / 2, *ys.start() * SUB + SUB / 2];
        let mut row = [0, 1, 2].map(|i| edge(ends[i].0, ends[i].1, start) + bias[i]);
        let inv_area = 1.0 / area as f64;
        let x0 = *xs.start();
        for y in ys {
            // Only the row's covered span is visited: a long thin triangle's box is mostly empty.
            let span = inside(row, step_x, xs.end() - x0);
            let mut w = [0, 1, 2].map(|i| row[i] + step_x[i] * span.start());
            let base = y as usize * self.width;
            for x in span.map(|k| x0 + k) {
                if w[0] | w[1] | w[2] >= 0 {
                    let l = [0, 1, 2].map(|i| (w[i] - bias[i]) as f64 * inv_area);
                    let inv = l[0] * v[0].inv_depth + l[1] * v[1].inv_depth + l[2] * v[2].inv_depth;
                    let s = base + x as usize;
                    if inv as f32 > self.inv_depth[s] {
                        self.inv_depth[s] = inv as f32;
                        self.triangle[s] = id;
                        let m = [0, 1, 2].map(|i| l[i] * v[i].inv_depth / inv);
                        let b = |c: usize| {
                            (m[0] * v[0].bary[c] + m[1] * v[1].bary[c] + m[2] * v[2].bary[c]) as f32
                        };
                        self.bary[s] = [b(1), b(2)];
                    }
                }
                for i in 0..3 {
                    w[i] += step_x[i];
                }
            }
            for i in 0..3 {
                row[i] += step_y[i];
            }
        }
    }

    /// Marks the samples of a line `width` samples wide from a to b with `kind` where
    /// `visible` (given the sample's triangle, its 1/depth and the line's) says the surface
    /// does not hide it.
    pub fn line(
        &mut self,
        a: Vertex,
        b: Vertex,
        width: usize,
        kind: u8,
        visible: impl Fn(u32, f32, f64) -> bool,
    ) {
        let x_major = (b.x - a.x).abs() >= (b.y - a.y).abs();
        // (major, minor) coordinates: one sample step along the major axis at a time.
        let coords = |v: &Vertex| if x_major { (v.x, v.y) } else { (v.y, v.x) };
        let (mut a, mut b) = (a, b);
        if coords(&a).0 > coords(&b).0 {
            std::mem::swap(&mut a, &mut b);
        }
        let ((a0, m0), (a1, m1)) = (coords(&a), coords(&b));
        let (n_major, n_minor) = if x_major {
            (self.width, self.height)
        } else {
            (self.height, self.width)
        };
        let first = ((a0 - 0.5).ceil() as i64).max(0);
        let last = ((a1 - 0.5).floor() as i64).min(n_major as i64 - 1);
        for i in first..=last {
            let t = if a1 > a0 {
                (i as f64 + 0.5 - a0) / (a1 - a0)
            } else {
                0.0
            };
            let m = m0 + t * (m1 - m0);
            let inv = a.inv_depth + t * (b.inv_depth - a.inv_depth);
            let lo = (m - 0.5 * width as f64).round() as i64;
            for k in lo.max(0)..(lo + width as i64).min(n_minor as i64) {
                let s = if x_major {
                    k as usize * self.width + i as usize
                } else {
                    i as usize * self.width + k as usize
                };
                if visible(self.triangle[s], self.inv_depth[s], inv) {
                    self.wire[s] = self.wire[s].max(kind);
                }
            }
        }
    }
}

/// A point in camera space with its barycentric coordinates in the triangle being clipped.
#[derive(Clone, Copy, Debug)]
pub struct ClipVertex {
    /// Camera coordinates (right, up, depth).
    pub p: [f64; 3],
    /// Coordinates in the original triangle.
    pub bary: [f64; 3],
}

/// Value of plane `(a, b, c, d)` at `p`: inside when ≥ 0.
pub fn plane_value(plane: &[f64; 4], p: [f64; 3]) -> f64 {
    plane[0] * p[0] + plane[1] * p[1] + plane[2] * p[2] + plane[3]
}

/// Clips a convex polygon against planes (Sutherland–Hodgman), interpolating the barycentric
/// coordinates linearly (camera space is an affine image of world space).
pub fn clip(polygon: &mut Vec<ClipVertex>, planes: &[[f64; 4]]) {
    let mut out = Vec::with_capacity(polygon.len() + planes.len());
    for plane in planes {
        out.clear();
        for i in 0..polygon.len() {
            let (a, b) = (polygon[i], polygon[(i + 1) % polygon.len()]);
            let (da, db) = (plane_value(plane, a.p), plane_value(plane, b.p));
            if da >= 0.0 {
                out.push(a);
            }
            if (da >= 0.0) != (db >= 0.0) {
                let t = da / (da - db);
                let lerp = |x: [f64; 3], y: [f64; 3]| [0, 1, 2].map(|c| x[c] + t * (y[c] - x[c]));
                out.push(ClipVertex {
                    p: lerp(a.p, b.p),
                    bary: lerp(a.bary, b.bary),
                });
            }
        }
        std::mem::swap(polygon, &mut out);
        if polygon.is_empty() {
            return;
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn vertex(x: f64, y: f64, corner: usize) -> Vertex {
        let mut bary = [0.0; 3];
        bary[corner] = 1.0;
        Vertex {
            x,
            y,
            inv_depth: 1.0,
            bary,
        }
    }

    fn covered(f: &Frame) -> Vec<(usize, usize)> {
        (0..f.width * f.height)
            .filter(|&s| f.triangle[s] != EMPTY)
            .map(|s| (s % f.width, s / f.width))
            .collect()
    }

    #[test]
    fn a_right_triangle_covers_the_sample_centres_inside_it() {
        // Corners (0,0), (4,0), (0,4): centres (x+½, y+½) with x + y + 1 < 4, plus those on the
        // hypotenuse x + y + 1 = 4 that the fill rule gives this triangle.
        for flip in [false, true] {
            let mut f = Frame::new(6, 6);
            let mut v = [
                vertex(0.0, 0.0, 0),
                vertex(4.0, 0.0, 1),
                vertex(0.0, 4.0, 2),
            ];
            if flip {
                v.swap(1, 2);
            }
            f.triangle(7, v);
            let mut expected: Vec<(usize, usize)> = (0..6)
                .flat_map(|y| (0..6).map(move |x| (x, y)))
                .filter(|&(x, y)| x + y + 1 < 4)
                .collect();
            let on_edge: Vec<(usize, usize)> = (0..4).map(|x| (x, 3 - x)).collect();
            let got = covered(&f);
            let edge_taken: Vec<_> = got.iter().filter(|p| on_edge.contains(p)).collect();
            assert!(edge_taken.is_empty() || edge_taken.len() == on_edge.len());
            expected.extend(edge_taken.into_iter().copied());
            expected.sort_by_key(|&(x, y)| (y, x));
            assert_eq!(got, expected);
            assert!(f.triangle.iter().all(|&t| t == EMPTY || t == 7));
            // The barycentric coordinates reproduce the sample position.
            let (x, y) = (1, 0);
            let [b1, b2] = f.bary[y * 6 + x];
            assert!((b1 as f64 * 4.0 - 1.5).abs() < 1e-6 && (b2 as f64 * 4.0 - 0.5).abs() < 1e-6);
        }
    }

    #[test]
    fn two_triangles_sharing_an_edge_cover_every_sample_once() {
        // A quad split along a diagonal through sample centres, at many offsets.
        for k in 0..20 {
            let o = k as f64 * 0.37;
            let q = [
                (0.5 + o, 0.5),
                (9.5, 0.5 + o),
                (9.5 - o, 9.5),
                (0.5, 9.5 - o),
            ];
            let v = |i: usize, c: usize| vertex(q[i].0, q[i].1, c);
            let mut hits = vec![0; 100];
            for (id, tri) in [[0, 1, 2], [0, 2, 3]].iter().enumerate() {
                let mut g = Frame::new(10, 10);
                g.triangle(id as u32, [v(tri[0], 0), v(tri[1], 1), v(tri[2], 2)]);
                for (h, &t) in hits.iter_mut().zip(&g.triangle) {
                    *h += usize::from(t != EMPTY);
                }
            }
            assert!(hits.iter().all(|&h| h <= 1), "double hit at offset {o}");
            // Every sample strictly inside the quad is hit.
            let inside = |x: f64, y: f64| {
                (0..4).all(|i| {
                    let (a, b) = (q[i], q[(i + 1) % 4]);
                    (b.0 - a.0) * (y - a.1) - (b.1 - a.1) * (x - a.0) > 1e-9
                })
            };
            for (s, &h) in hits.iter().enumerate() {
                let (x, y) = ((s % 10) as f64 + 0.5, (s / 10) as f64 + 0.5);
                if inside(x, y) {
                    assert_eq!(h, 1, "hole at ({x}, {y}), offset {o}");
                }
            }
        }
    }

    #[test]
    fn row_spans_are_the_samples_every_edge_function_accepts() {
        let mut seed = 12345u64;
        let mut next = |m: i64| {
            seed = seed
                .wrapping_mul(6364136223846793005)
                .wrapping_add(1442695040888963407);
            (seed >> 33) as i64 % (2 * m + 1) - m
        };
        for _ in 0..2000 {
            let (w, step, last) = (
                [next(500), next(500), next(500)],
                [next(40), next(40), next(3)],
                next(30).abs(),
            );
            let scan: Vec<i64> = (0..=last)
                .filter(|&k| (0..3).all(|i| w[i] + step[i] * k >= 0))
                .collect();
            let span: Vec<i64> = inside(w, step, last).collect();
            assert_eq!(span, scan, "{w:?} {step:?} {last}");
        }
    }

    #[test]
    fn the_nearer_triangle_wins() {
        let mut f = Frame::new(4, 4);
        let far = |c| Vertex {
            inv_depth: 0.5,
            ..vertex(0.0, 0.0, c)
        };
        let tri = |id, inv: f64, f: &mut Frame| {
            let v = [(0.0, 0.0), (8.0, 0.0), (0.0, 8.0)];
            f.triangle(
                id,
                [0, 1, 2].map(|c| Vertex {
                    x: v[c].0,
                    y: v[c].1,
                    inv_depth: inv,
                    ..far(c)
                }),
            );
        };
        tri(1, 0.5, &mut f);
        tri(2, 0.25, &mut f);
        assert!(f.triangle.iter().all(|&t| t == 1));
        tri(3, 1.0, &mut f);
        assert!(f.triangle.iter().all(|&t| t == 3));
    }

    #[test]
    fn clipping_keeps_the_inside_and_its_coordinates() {
        let mut poly = vec![
            ClipVertex {
                p: [0.0, 0.0, -1.0],
                bary: [1.0, 0.0, 0.0],
            },
            ClipVertex {
                p: [0.0, 0.0, 1.0],
                bary: [0.0, 1.0, 0.0],
            },
            ClipVertex {
                p: [1.0, 0.0, 1.0],
                bary: [0.0, 0.0, 1.0],
            },
        ];
        clip(&mut poly, &[[0.0, 0.0, 1.0, 0.0]]);
        assert_eq!(poly.len(), 4);
        assert!(poly.iter().all(|v| v.p[2] >= 0.0));
        assert_eq!(poly[3].bary, [0.5, 0.0, 0.5]);
        clip(&mut poly, &[[0.0, 0.0, -1.0, -2.0]]);
        assert!(poly.is_empty());
    }
}
