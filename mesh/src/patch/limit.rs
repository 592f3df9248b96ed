//! The limit surface at the refined vertices: every output vertex taken to the
//! point of the limit surface it converges to, with the unit normal there.
//!
//! **Patches.** Away from the vertices a rule sets, the surface is a tensor-product
//! non-uniform B-spline, so the limit of point (x, y) of a face's last patch is the tensor
//! product of the 1D limit masks of its two words ([`lsubdiv_runtime::CurveTables::limit_mask`], the
//! word of knot x as the patch plan reads it) on its 3×3 neighbourhood, and the partial
//! derivatives are the derivative mask one way times the position mask the other. This holds
//! at any level: the limit at a knot is a B-spline identity, and the three B-splines alive at
//! a knot refine into the three alive there, by the masks of the same 3×3 points. The last
//! patch with its ring holds that neighbourhood for every point; across the edges sharp for
//! good it holds the phantoms the refinement uses, so boundaries, creases with two faces each
//! side and corners with one face come out of the same formula (on an odd reflection the
//! cross mask leaves the curve's limit mask along the sharp edge). A point several faces hold
//! gets the mean of their unit normals: one normal on smooth surface, the bisector of the two
//! sides' normals on a crease.
//!
//! **Vertex rules.** A base vertex whose child a rule sets takes its limit from that rule:
//! - an interior EV: the stationary 1-ring's left eigenvectors ([`lsubdiv_runtime::ev::EvLimit`],
//!   numeric as α is), valid from the step where the EV configuration is stationary;
//! - a dart: the same smooth weights, as OpenSubdiv's `Sdc` does for its darts;
//! - a crease with a sector other than two faces: the curve's limit mask along its two sharp
//!   edges (exact: the crease is refined as the scheme's curve, `tests/boundaries.rs`);
//! - a corner: the vertex itself.
//!
//! What is not derived is listed in [`SurfaceLimit::approximate`]: a dart's point and normal
//! (its neighbours are refined by phantoms that do not describe the whole 1-ring), and the
//! normals of those creases and of corners with a sector of more than one face; there the
//! normal is the mean normal of the vertex's limit 1-ring faces.

use super::{ring_layout, spoke, sub3, Refiner, Simd};
use crate::features::{CornerKind, Features, Resolved, VertexRule};
use crate::grid::{corner_at, TOWARD_NEXT, TOWARD_PREV};
use crate::real::Real;
use crate::surface::{SurfaceError, SurfaceScheme};
use crate::threads::in_threads;
use crate::topology::Topology;
use lsubdiv_runtime::ev::EvLimit;
use lsubdiv_runtime::surface::SurfaceTables;
use std::f64::consts::TAU;
use std::ops::Range;

/// Limit positions and unit normals of a refined mesh's vertices, in the output's order.
#[derive(Clone, Debug, PartialEq)]
pub struct SurfaceLimit<T = f64> {
    /// The limit point of each vertex.
    pub positions: Vec<[T; 3]>,
    /// The unit normal there, oriented with the face winding (zero where the tangents are
    /// parallel: a degenerate control mesh has no normal).
    pub normals: Vec<[T; 3]>,
    /// Vertices whose limit normal (a dart's: and point) is not derived in closed form (see
    /// the module documentation), ascending.
    pub approximate: Vec<u32>,
}

type V3 = [f64; 3];

#[inline(always)]
fn cross(a: V3, b: V3) -> V3 {
    let [[x], [y], [z]] = cross_lanes(a.map(|x| [x]), b.map(|x| [x]));
    [x, y, z]
}

#[inline(always)]
fn unit(a: V3) -> V3 {
    let [[x], [y], [z]] = unit_lanes(a.map(|x| [x]));
    [x, y, z]
}

/// [`cross`] of L pairs of vectors at once, by coordinate.
#[inline(always)]
fn cross_lanes<const L: usize>(a: [[f64; L]; 3], b: [[f64; L]; 3]) -> [[f64; L]; 3] {
    let mut c = [[0.0; L]; 3];
    for l in 0..L {
        c[0][l] = a[1][l] * b[2][l] - a[2][l] * b[1][l];
        c[1][l] = a[2][l] * b[0][l] - a[0][l] * b[2][l];
        c[2][l] = a[0][l] * b[1][l] - a[1][l] * b[0][l];
    }
    c
}

/// L vectors (by coordinate) made unit, a zero-length or non-finite one zero ([`unit`]).
#[inline(always)]
fn unit_lanes<const L: usize>(mut a: [[f64; L]; 3]) -> [[f64; L]; 3] {
    for l in 0..L {
        let len = (a[0][l] * a[0][l] + a[1][l] * a[1][l] + a[2][l] * a[2][l]).sqrt();
        let keep = (len > 0.0) & len.is_finite();
        for c in &mut a {
            c[l] = if keep { c[l] / len } else { 0.0 };
        }
    }
    a
}

#[inline(always)]
fn add(a: &mut V3, b: V3, w: f64) {
    for (x, y) in a.iter_mut().zip(b) {
        *x += w * y;
    }
}

/// The position and derivative weights of one knot's limit mask (on its points −1, 0, 1).
type Mask = ([f64; 3], [f64; 3]);

/// Whether the limit after `steps` steps of `scheme` on the mesh of topology `topo` with
/// `features` can be taken ([`Refiner::limit`] refuses the same, with the same reasons):
/// to decide before refining.
pub fn limit_available<S: SurfaceScheme>(
    scheme: &S,
    topo: &Topology,
    features: &Features,
    steps: usize,
) -> Result<(), SurfaceError> {
    let resolved = Resolved::new(topo, features).map_err(SurfaceError::Features)?;
    ruled(scheme, topo, &resolved, steps).map(|_| ())
}

/// Refused where a semi-sharp crease or corner is sharp for `changing` steps, more than
/// `steps`: its limit depends on steps not taken.
pub(super) fn sharp_until(changing: usize, steps: usize) -> Result<(), SurfaceError> {
    if changing <= steps {
        return Ok(());
    }
    Err(SurfaceError::Unsupported(format!(
        "the limit after {steps} step{}: a semi-sharp crease or corner is still sharp (for \
         {changing} steps), so the limit depends on steps not taken; refine at least {changing} \
         steps",
        if steps == 1 { "" } else { "s" },
    )))
}

/// Per base vertex, whether its child is set by a rule at the limit; refused, naming the
/// reason, for a degree without limit masks, a semi-sharp feature still sharp after the last
/// step (its limit depends on steps not taken), and interior EVs before their configuration
/// is stationary.
fn ruled<S: SurfaceScheme>(
    scheme: &S,
    topo: &Topology,
    features: &Resolved,
    steps: usize,
) -> Result<Vec<bool>, SurfaceError> {
    let (t, st) = (scheme.tables(), scheme.surface());
    let unsupported = |m: String| Err(SurfaceError::Unsupported(m));
    if t.limit_mask(0).is_none() {
        return unsupported(format!(
            "scheme `{}` has degree {}: no limit masks (they exist for odd degrees)",
            t.name, t.degree
        ));
    }
    let after = format!("after {steps} step{}", if steps == 1 { "" } else { "s" });
    sharp_until(features.changing_steps(), steps)?;
    let special: Vec<bool> = (0..topo.vertex_count() as u32)
        .map(|v| {
            if features.is_plain() {
                topo.valence(v) != 4
            } else {
                features.needs_rule(topo, v, steps)
            }
        })
        .collect();
    let smooth = |v: usize| rule(topo, features, v as u32, steps) == VertexRule::Smooth;
    if steps < st.stationary_from() && (0..special.len()).any(|v| special[v] && smooth(v)) {
        return unsupported(format!(
            "the limit at extraordinary vertices {after} of `{}`: the configuration around \
             them is stationary from step {} ([G] Lemma 4.6), and their limit weights hold \
             from there; refine at least {} steps",
            t.name,
            st.stationary_from(),
            st.stationary_from()
        ));
    }
    Ok(special)
}

/// The rule of vertex v at step k (smooth everywhere on a plain mesh).
fn rule(topo: &Topology, features: &Resolved, v: u32, k: usize) -> VertexRule {
    if features.is_plain() {
        VertexRule::Smooth
    } else {
        features.vertex_rule(topo, v, k)
    }
}

impl<S: SurfaceScheme + Sync, T: Real> Refiner<'_, S, T> {
    /// The limit positions and normals of the last [`Refiner::refine`]'s output vertices (in
    /// its numbering, holes' points included); refused as [`limit_available`] says.
    pub fn limit(&self) -> Result<SurfaceLimit<T>, SurfaceError> {
        let (t, st) = (self.scheme.tables(), self.scheme.surface());
        let (base, topo) = (&self.base, self.base.topo);
        let features = &base.features;
        let steps = self.start_level() + self.plans.len();
        let special = ruled(self.scheme, topo, features, steps)?;
        let (k, nv) = (steps, topo.vertex_count() as u32);
        let rule = |v: u32| rule(topo, features, v, k);
        // W_s, and the limit mask of every knot of a face's side.
        let word = t.iterate(t.axiom, steps);
        let n = word.len() as i64;
        let lookup = t.word_index();
        let masks: Vec<Mask> = (0..=n)
            .map(|x| {
                let w: Vec<u8> = (x - 2..x + 2)
                    .map(|i| word[i.rem_euclid(n) as usize])
                    .collect();
                let i = *lookup
                    .get(w.as_slice())
                    .ok_or_else(|| SurfaceError::UnknownWord(t.word_str(&w)))?;
                let (p, d) = t.limit_mask(i as usize).expect("odd degree 3");
                Ok((p.try_into().expect("3"), d.try_into().expect("3")))
            })
            .collect::<Result<_, SurfaceError>>()?;

        let output = self.positions();
        let num = &self.out_num;
        let mut positions = vec![[0.0; 3]; output.len()];
        let mut normals = vec![[0.0; 3]; output.len()];
        // Special corners whose patch describes their sector exactly (a corner's one-face
        // sectors, doubly reflected) add their patch normal too: per face corner, a corner
        // vertex's kinds computed once for its whole rotation.
        let mut exact = vec![false; 4 * topo.face_count()];
        for v in (0..nv).filter(|&v| special[v as usize] && rule(v) == VertexRule::Corner) {
            for (wedge, kind) in topo
                .rotation(v)
                .iter()
                .zip(features.corner_kinds(topo, v, k))
            {
                exact[wedge.face as usize * 4 + wedge.corner as usize] = kind == CornerKind::Both;
            }
        }
        self.patch_limits(
            &Weights::new(&masks),
            (&special, &exact),
            &mut positions,
            &mut normals,
        );

        // The vertices a rule sets, on the refiner's threads: positions first (the fallback
        // normals read the limit positions of their neighbours).
        let by_rule: Vec<u32> = (0..nv).filter(|&v| special[v as usize]).collect();
        let per = by_rule.len().div_ceil(self.threads).max(1);
        let vertex = VertexPass {
            topo,
            features,
            k,
            num,
            output,
            exact: &exact,
            crease: masks[0].0,
        };
        let found = in_threads(by_rule.chunks(per), |vs| {
            let mut cache = Vec::new();
            vs.iter()
                .map(|&v| vertex.limit(v, &st, &mut cache))
                .collect::<Result<Vec<_>, _>>()
        });
        let (mut approximate, mut fallback) = (Vec::new(), Vec::new());
        for found in found {
            for Ruled {
                v,
                position,
                normal,
                approximate: approx,
                fallback: fall,
            } in found?
            {
                positions[v as usize] = position;
                if let Some(normal) = normal {
                    normals[v as usize] = normal;
                }
                if approx {
                    approximate.push(v);
                }
                if fall {
                    fallback.push(v);
                }
            }
        }
        // The mean normal of the limit 1-ring faces: at each face corner, the cross product of
        // the limit edges toward the next and the previous corner.
        for &v in &fallback {
            let mut sum = [0.0; 3];
            for w in topo.rotation(v) {
                let (cx, cy) = corner_at(w.corner, n, n);
                let (nx, ny) = TOWARD_NEXT[w.corner as usize];
                let (px, py) = TOWARD_PREV[w.corner as usize];
                let limit = |dx, dy| positions[num.index(w.face as usize, cx + dx, cy + dy).0];
                let o = positions[v as usize];
                let a = sub3(limit(nx, ny), o);
                let b = sub3(limit(px, py), o);
                add(&mut sum, cross(a, b), 1.0);
            }
            normals[v as usize] = sum;
        }
        let per = normals.len().div_ceil(self.threads).max(1);
        in_threads(normals.chunks_mut(per), |normals| {
            for m in normals {
                *m = unit(*m);
            }
        });
        Ok(SurfaceLimit {
            positions: positions.into_iter().map(|p| p.map(T::from_f64)).collect(),
            normals: normals.into_iter().map(|m| m.map(T::from_f64)).collect(),
            approximate,
        })
    }
}

/// A base vertex a rule sets, at the limit: its point, its normal where the rule gives one,
/// whether that is not derived in closed form, and whether the normal is the mean of its limit
/// 1-ring faces' ([`Refiner::limit`]).
struct Ruled {
    v: u32,
    position: V3,
    normal: Option<V3>,
    approximate: bool,
    fallback: bool,
}

/// What [`VertexPass::limit`] reads: the mesh, its features at step k, the refined points in
/// the output's numbering, which face corners a corner's patch describes exactly, and the
/// curve's limit mask at a crease vertex.
struct VertexPass<'a, T> {
    topo: &'a Topology,
    features: &'a Resolved,
    k: usize,
    num: &'a super::numbering::Numbering,
    output: &'a [[T; 3]],
    exact: &'a [bool],
    crease: [f64; 3],
}

/// Per valence, its EV limit weights and each wedge's cos and sin at its radial and diagonal
/// angles.
type EvCache = Vec<Option<(EvLimit, Vec<[f64; 4]>)>>;

impl<T: Real> VertexPass<'_, T> {
    /// Vertex v's limit by its rule (the module documentation), with a worker's `cache`.
    fn limit(
        &self,
        v: u32,
        st: &SurfaceTables<'_>,
        cache: &mut EvCache,
    ) -> Result<Ruled, SurfaceError> {
        let (topo, features, k, num) = (self.topo, self.features, self.k, self.num);
        let n = num.n;
        let at = |i: usize| self.output[i].map(Real::to_f64);
        let rot = topo.rotation(v);
        let point = |w: usize, (dx, dy): (i64, i64)| {
            let wedge = rot[w];
            let (cx, cy) = corner_at(wedge.corner, n, n);
            at(num.index(wedge.face as usize, cx + dx, cy + dy).0)
        };
        let centre = at(v as usize);
        let mut found = Ruled {
            v,
            position: centre,
            normal: None,
            approximate: false,
            fallback: false,
        };
        match rule(topo, features, v, k) {
            VertexRule::Smooth => {
                let valence = rot.len();
                if cache.len() <= valence {
                    cache.resize(valence + 1, None);
                }
                if cache[valence].is_none() {
                    let theta = TAU / valence as f64;
                    let trig = (0..valence)
                        .map(|i| {
                            let (a, b) = (theta * i as f64, theta * (i as f64 + 0.5));
                            [a.cos(), b.cos(), a.sin(), b.sin()]
                        })
                        .collect();
                    cache[valence] = Some((st.ev_limit(valence).map_err(SurfaceError::Ev)?, trig));
                }
                let (l, trig) = cache[valence].as_ref().expect("filled");
                let (mut pos, mut t1, mut t2) = (centre.map(|x| l.centre * x), [0.0; 3], [0.0; 3]);
                for (i, (wedge, [cos_a, cos_b, sin_a, sin_b])) in rot.iter().zip(trig).enumerate() {
                    let (nx, ny) = TOWARD_NEXT[wedge.corner as usize];
                    let (px, py) = TOWARD_PREV[wedge.corner as usize];
                    let radial = point(i, spoke(topo, v, i).1);
                    let diagonal = point(i, (nx + px, ny + py));
                    add(&mut pos, radial, l.radial);
                    add(&mut pos, diagonal, l.diagonal);
                    add(&mut t1, radial, *cos_a);
                    add(&mut t1, diagonal, l.tangent * cos_b);
                    add(&mut t2, radial, *sin_a);
                    add(&mut t2, diagonal, l.tangent * sin_b);
                }
                // The rotation runs against the winding when its next edges are c → c+1.
                let sign = if rot[0].next_is_plus { -1.0 } else { 1.0 };
                found.position = pos;
                found.normal = Some(unit(cross(t1, t2)).map(|x| sign * x));
                // Valence 2: no tangent plane from the 1-ring (EvCoefficients::tangent_weight).
                found.fallback = valence == 2;
                found.approximate =
                    found.fallback || topo.spokes(v).any(|e| features.edge_sharp(e, k));
            }
            VertexRule::Crease => {
                let pw = self.crease;
                let mut pos = centre.map(|x| pw[1] * x);
                let sharp = topo
                    .spokes(v)
                    .enumerate()
                    .filter(|&(_, e)| features.edge_sharp(e, k));
                for (i, _) in sharp {
                    let (w, dir) = spoke(topo, v, i);
                    add(&mut pos, point(w, dir), pw[0]);
                }
                found.position = pos;
                (found.approximate, found.fallback) = (true, true);
            }
            VertexRule::Corner => {
                let exact = |f: u32, c: u8| self.exact[f as usize * 4 + c as usize];
                let exact = rot.iter().all(|w| exact(w.face, w.corner));
                (found.approximate, found.fallback) = (!exact, !exact);
            }
        }
        Ok(found)
    }
}

/// Faces one worker takes at a time: their side and corner points wait for the sum in face
/// order (`Refiner::patch_limits`), so memory stays bounded whatever the mesh.
const FACES_PER_WORKER: usize = 512;

/// Points [`face_kernel`] takes at once: the sums of a block stay in registers (nine vectors
/// of 512 bits).
const LANES: usize = 8;

/// The tensor-product limit masks of every point (x, y) ∈ [0, N]² of a face, laid out for
/// [`face_kernel`]: per neighbour (x + a − 1, y + b − 1), (b, a) ∈ 3 × 3 in that order, the
/// weight at each point (x, y), at x · M + y (M = N + 3, the side of the patch with its ring;
/// zero for y > N and for the padding to whole blocks of [`LANES`]), for the position, ∂/∂x and
/// ∂/∂y (the 1D masks' products).
struct Weights {
    n: usize,
    /// Points per neighbour, padded: (N + 1) · M rounded up to [`LANES`].
    len: usize,
    position: Vec<f64>,
    along_x: Vec<f64>,
    along_y: Vec<f64>,
}

impl Weights {
    fn new(masks: &[Mask]) -> Weights {
        let n = masks.len() - 1;
        let m = n + 3;
        let len = ((n + 1) * m).next_multiple_of(LANES);
        let mut w = Weights {
            n,
            len,
            position: vec![0.0; 9 * len],
            along_x: vec![0.0; 9 * len],
            along_y: vec![0.0; 9 * len],
        };
        for b in 0..3 {
            for a in 0..3 {
                for (x, (pu, du)) in masks.iter().enumerate() {
                    for (y, (pv, dv)) in masks.iter().enumerate() {
                        let t = (b * 3 + a) * len + x * m + y;
                        w.position[t] = pu[a] * pv[b];
                        w.along_x[t] = du[a] * pv[b];
                        w.along_y[t] = pu[a] * dv[b];
                    }
                }
            }
        }
        w
    }

    /// Values per coordinate of a patch laid out for [`face_kernel`]: its M² points and the
    /// padding the last block reads past them.
    fn patch_len(&self) -> usize {
        let m = self.n + 3;
        self.len + 2 * m + 2
    }
}

/// A worker's buffers, kept from face to face and round to round: a face's patch as loaded
/// (point-major), the same by coordinate (then x, then y: [`Weights::patch_len`] each), per
/// coordinate the limit point and unit normal at each point as [`Weights`] lays them out, and
/// the side points of the worker's faces.
#[derive(Default)]
struct Scratch {
    patch: Vec<f64>,
    by_coordinate: Vec<f64>,
    positions: Vec<f64>,
    normals: Vec<f64>,
    /// The face's side and corner points, for the sum in face order.
    sides: Vec<Side>,
}

/// A point on a face's sides or corners: its index, its limit point where this face writes it,
/// and this face's unit normal there.
type Side = (usize, Option<V3>, V3);

/// The limit point and unit normal of every point of one face ([`Weights`]). With both laid
/// out at x · M + y, neighbour (a, b) of a point is a constant offset a · M + b away in the
/// patch, so a block of [`LANES`] consecutive points (padding included: weights zero, results
/// unread) reads consecutive values. For each point, coordinate and quantity (position,
/// ∂/∂x, ∂/∂y) the neighbours are added in the order (b, a); the normal is the cross product of
/// the two derivatives, normalised ([`unit`]).
#[inline(always)]
fn face_kernel(w: &Weights, by_coordinate: &[f64], positions: &mut [f64], normals: &mut [f64]) {
    let (m, len, stride) = (w.n + 3, w.len, w.patch_len());
    let lanes = |v: &[f64], at: usize| -> [f64; LANES] { v[at..at + LANES].try_into().unwrap() };
    for t in (0..len).step_by(LANES) {
        // [coordinate][position, ∂/∂x, ∂/∂y]
        let mut sums = [[[0.0; LANES]; 3]; 3];
        for b in 0..3 {
            for a in 0..3 {
                let at = (b * 3 + a) * len + t;
                let weights = [&w.position, &w.along_x, &w.along_y].map(|v| lanes(v, at));
                for (c, sums) in sums.iter_mut().enumerate() {
                    let q = lanes(by_coordinate, c * stride + a * m + b + t);
                    for (sum, weight) in sums.iter_mut().zip(&weights) {
                        for l in 0..LANES {
                            sum[l] += weight[l] * q[l];
                        }
                    }
                }
            }
        }
        let along = |quantity: usize| [0, 1, 2].map(|c| sums[c][quantity]);
        let normal = unit_lanes(cross_lanes(along(1), along(2)));
        for c in 0..3 {
            positions[c * len + t..][..LANES].copy_from_slice(&sums[c][0]);
            normals[c * len + t..][..LANES].copy_from_slice(&normal[c]);
        }
    }
}

#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx2")]
unsafe fn face_kernel_avx2(w: &Weights, patch: &[f64], positions: &mut [f64], normals: &mut [f64]) {
    face_kernel(w, patch, positions, normals);
}

#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx512f")]
unsafe fn face_kernel_avx512(
    w: &Weights,
    patch: &[f64],
    positions: &mut [f64],
    normals: &mut [f64],
) {
    face_kernel(w, patch, positions, normals);
}

impl<S: SurfaceScheme + Sync, T: Real> Refiner<'_, S, T> {
    /// The limit point and normal of every point of every face's last patch (the module
    /// documentation's tensor product), on the refiner's threads. A point inside a face is
    /// written by its face; those on sides and corners are handed back and summed in face
    /// order, so the result does not depend on the threads. `special` and `exact` as in
    /// [`Refiner::limit`]: a base vertex a rule sets is left to it, but for the normal of a
    /// corner the patch describes exactly.
    fn patch_limits(
        &self,
        weights: &Weights,
        (special, exact): (&[bool], &[bool]),
        positions: &mut [V3],
        normals: &mut [V3],
    ) {
        let num = &self.out_num;
        let inside = ((num.n - 1) * (num.n - 1)) as usize;
        let nf = self.base.topo.face_count();
        let round = FACES_PER_WORKER * self.threads;
        // Each worker's buffers, kept from round to round.
        let mut scratch: Vec<Scratch> = (0..self.threads).map(|_| Scratch::default()).collect();
        for first in (0..nf).step_by(round) {
            let last = (first + round).min(nf);
            let (from, to) = (num.interior(first), num.interior(last));
            let (mut pos, mut nrm) = (&mut positions[from..to], &mut normals[from..to]);
            let per = (last - first).div_ceil(self.threads);
            let work: Vec<_> = (first..last)
                .step_by(per)
                .map(|f| {
                    let faces = f..(f + per).min(last);
                    let len = faces.len() * inside;
                    let (p, rest) = std::mem::take(&mut pos).split_at_mut(len);
                    pos = rest;
                    let (n, rest) = std::mem::take(&mut nrm).split_at_mut(len);
                    nrm = rest;
                    (faces, p, n)
                })
                .collect();
            let workers = work.len();
            in_threads(work.into_iter().zip(&mut scratch), |((faces, p, n), s)| {
                self.face_limits(weights, faces, (p, n), (special, exact), s)
            });
            for &(i, position, normal) in scratch[..workers].iter().flat_map(|s| &s.sides) {
                if let Some(p) = position {
                    positions[i] = p;
                }
                add(&mut normals[i], normal, 1.0);
            }
        }
    }

    /// [`Refiner::patch_limits`] for one worker's `faces`: the points inside them written into
    /// `inside` (positions, normals; from the first face's first inside point on), the others
    /// into `scratch.sides`, in order.
    fn face_limits(
        &self,
        weights: &Weights,
        faces: Range<usize>,
        inside: (&mut [V3], &mut [V3]),
        (special, exact): (&[bool], &[bool]),
        scratch: &mut Scratch,
    ) {
        let (base, num, k) = (
            &self.base,
            &self.out_num,
            self.start_level() + self.plans.len(),
        );
        let n = num.n;
        let layout = ring_layout(n, true);
        let (m, len, stride) = (layout.side, weights.len, weights.patch_len());
        let output = self.positions();
        let offset = num.interior(faces.start);
        let k_inside = (n - 1) as usize;
        scratch.patch.resize(m * m * 3, 0.0);
        scratch.by_coordinate.resize(stride * 3, 0.0);
        scratch.positions.resize(3 * len, 0.0);
        scratch.normals.resize(3 * len, 0.0);
        scratch.sides.clear();
        let Scratch {
            patch,
            by_coordinate,
            positions,
            normals,
            sides,
        } = scratch;
        for f in faces {
            patch.fill(0.0);
            num.gather(base, f as u32, |x, y, i| {
                let j = layout.at(x, y);
                patch[j..j + 3].copy_from_slice(&output[i].map(Real::to_f64));
            });
            base.load_phantoms((f as u32, n, k), layout, patch);
            for (c, to) in by_coordinate.chunks_exact_mut(stride).enumerate() {
                for (t, p) in to.iter_mut().zip(patch.chunks_exact(3)) {
                    *t = p[c];
                }
            }
            match self.simd {
                #[cfg(target_arch = "x86_64")]
                // SAFETY: `Simd::Avx512` is only handed out where the CPU has AVX-512F.
                Simd::Avx512 => unsafe {
                    face_kernel_avx512(weights, by_coordinate, positions, normals)
                },
                #[cfg(target_arch = "x86_64")]
                // SAFETY: `Simd::Avx2` is only handed out where the CPU has AVX2.
                Simd::Avx2 => unsafe {
                    face_kernel_avx2(weights, by_coordinate, positions, normals)
                },
                _ => face_kernel(weights, by_coordinate, positions, normals),
            }
            let point = |x: i64, y: i64| {
                let t = x as usize * m + y as usize;
                let at = |v: &[f64]| [0, 1, 2].map(|c| v[c * len + t]);
                (at(positions), at(normals))
            };
            // Inside: this face's own points, row by row from (1, 1).
            let first = num.interior(f) - offset;
            for y in 1..n {
                let row = first + (y - 1) as usize * k_inside;
                for x in 1..n {
                    let (pos, normal) = point(x, y);
                    let i = row + (x - 1) as usize;
                    inside.0[i] = pos;
                    // `add` to the zero the normal starts from, without reading it: a first
                    // touch that writes (a read would map the zero page, and the write after it
                    // copy it, flushing every thread's TLB).
                    inside.1[i] = normal.map(|x| 0.0 + 1.0 * x);
                }
            }
            // The sides and corners, in the same order (y, then x).
            for y in 0..=n {
                let across = y == 0 || y == n;
                let xs = (0..=n).filter(|&x| across || x == 0 || x == n);
                for x in xs {
                    let (i, owner) = num.index(f, x, y);
                    let corner = (x == 0 || x == n) && (y == 0 || y == n);
                    // A base vertex whose child a rule sets: `Refiner::limit`'s vertex pass.
                    let ruled = corner && special[i];
                    if ruled {
                        let c = (0..4u8).find(|&c| corner_at(c, n, n) == (x, y));
                        if !c.is_some_and(|c| exact[f * 4 + c as usize]) {
                            continue;
                        }
                    }
                    let (pos, normal) = point(x, y);
                    sides.push((i, (owner && !ruled).then_some(pos), normal));
                }
            }
        }
    }
}
