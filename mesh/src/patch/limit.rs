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

use super::{ring_layout, spoke, sub3, Refiner};
use crate::features::{CornerKind, Features, Resolved, VertexRule};
use crate::grid::{corner_at, TOWARD_NEXT, TOWARD_PREV};
use crate::real::Real;
use crate::surface::{SurfaceError, SurfaceScheme};
use crate::topology::Topology;
use std::f64::consts::TAU;

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
    [
        a[1] * b[2] - a[2] * b[1],
        a[2] * b[0] - a[0] * b[2],
        a[0] * b[1] - a[1] * b[0],
    ]
}

#[inline(always)]
fn unit(a: V3) -> V3 {
    let len = a.iter().map(|x| x * x).sum::<f64>().sqrt();
    if len > 0.0 && len.is_finite() {
        a.map(|x| x / len)
    } else {
        [0.0; 3]
    }
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
        let at = |i: usize| output[i].map(Real::to_f64);
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
        let exact_corner = |f: u32, c: u8| exact[f as usize * 4 + c as usize];
        let layout = ring_layout(n, true);
        let mut patch = vec![0.0f64; layout.side * layout.side * 3];
        for f in 0..topo.face_count() as u32 {
            patch.fill(0.0);
            num.gather(base, f, |x, y, i| {
                let j = layout.at(x, y);
                patch[j..j + 3].copy_from_slice(&at(i));
            });
            base.load_phantoms((f, n, k), layout, &mut patch);
            let p = |x: i64, y: i64| -> V3 {
                let j = layout.at(x, y);
                [patch[j], patch[j + 1], patch[j + 2]]
            };
            for y in 0..=n {
                for x in 0..=n {
                    let (i, owner) = num.index(f as usize, x, y);
                    let corner = (x == 0 || x == n) && (y == 0 || y == n);
                    // A base vertex whose child a rule sets: the vertex pass below.
                    let ruled = corner && special[i];
                    if ruled {
                        let c = (0..4u8).find(|&c| corner_at(c, n, n) == (x, y));
                        if !c.is_some_and(|c| exact_corner(f, c)) {
                            continue;
                        }
                    }
                    let ((pu, du), (pv, dv)) = (masks[x as usize], masks[y as usize]);
                    let (mut pos, mut tu, mut tv) = ([0.0; 3], [0.0; 3], [0.0; 3]);
                    for (b, (&wv, &dvb)) in pv.iter().zip(&dv).enumerate() {
                        for (a, (&wu, &dua)) in pu.iter().zip(&du).enumerate() {
                            let q = p(x + a as i64 - 1, y + b as i64 - 1);
                            add(&mut pos, q, wu * wv);
                            add(&mut tu, q, dua * wv);
                            add(&mut tv, q, wu * dvb);
                        }
                    }
                    if owner && !ruled {
                        positions[i] = pos;
                    }
                    add(&mut normals[i], unit(cross(tu, tv)), 1.0);
                }
            }
        }

        // The vertices a rule sets: positions first (the fallback normals read the limit
        // positions of their neighbours).
        let mut approximate = Vec::new();
        let mut fallback = Vec::new();
        for v in (0..nv).filter(|&v| special[v as usize]) {
            let rot = topo.rotation(v);
            let point = |w: usize, (dx, dy): (i64, i64)| {
                let wedge = rot[w];
                let (cx, cy) = corner_at(wedge.corner, n, n);
                at(num.index(wedge.face as usize, cx + dx, cy + dy).0)
            };
            let centre = at(v as usize);
            let vi = v as usize;
            match rule(v) {
                VertexRule::Smooth => {
                    let l = st.ev_limit(rot.len()).map_err(SurfaceError::Ev)?;
                    let (mut pos, mut t1, mut t2) =
                        (centre.map(|x| l.centre * x), [0.0; 3], [0.0; 3]);
                    let theta = TAU / rot.len() as f64;
                    for (i, wedge) in rot.iter().enumerate() {
                        let (nx, ny) = TOWARD_NEXT[wedge.corner as usize];
                        let (px, py) = TOWARD_PREV[wedge.corner as usize];
                        let radial = point(i, spoke(topo, v, i).1);
                        let diagonal = point(i, (nx + px, ny + py));
                        add(&mut pos, radial, l.radial);
                        add(&mut pos, diagonal, l.diagonal);
                        let (a, b) = (theta * i as f64, theta * (i as f64 + 0.5));
                        add(&mut t1, radial, a.cos());
                        add(&mut t1, diagonal, l.tangent * b.cos());
                        add(&mut t2, radial, a.sin());
                        add(&mut t2, diagonal, l.tangent * b.sin());
                    }
                    // The rotation runs against the winding when its next edges are c → c+1.
                    let sign = if rot[0].next_is_plus { -1.0 } else { 1.0 };
                    positions[vi] = pos;
                    normals[vi] = unit(cross(t1, t2)).map(|x| sign * x);
                    if topo.spokes(v).any(|e| features.edge_sharp(e, k)) {
                        approximate.push(v);
                    }
                    // Valence 2: no tangent plane from the 1-ring (EvCoefficients::tangent_weight).
                    if rot.len() == 2 {
                        approximate.push(v);
                        fallback.push(v);
                    }
                }
                VertexRule::Crease => {
                    let (pw, _) = masks[0];
                    let mut pos = centre.map(|x| pw[1] * x);
                    let sharp = topo
                        .spokes(v)
                        .enumerate()
                        .filter(|&(_, e)| features.edge_sharp(e, k));
                    for (i, _) in sharp {
                        let (w, dir) = spoke(topo, v, i);
                        add(&mut pos, point(w, dir), pw[0]);
                    }
                    positions[vi] = pos;
                    approximate.push(v);
                    fallback.push(v);
                }
                VertexRule::Corner => {
                    positions[vi] = centre;
                    let exact = rot.iter().all(|w| exact_corner(w.face, w.corner));
                    if !exact {
                        approximate.push(v);
                        fallback.push(v);
                    }
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
        Ok(SurfaceLimit {
            positions: positions.into_iter().map(|p| p.map(T::from_f64)).collect(),
            normals: normals
                .into_iter()
                .map(|m| unit(m).map(T::from_f64))
                .collect(),
            approximate,
        })
    }
}
