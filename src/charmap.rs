//! `lsubdiv ev --characteristic-map`: the control net of the characteristic map around an
//! extraordinary vertex of valence n (\[G\] §3.3, Fig. 4; Reif's characteristic map): the
//! eigenvector of the local subdivision matrix for the subdominant eigenvalue λ1, whose two
//! real components (Fourier index 1) give x and y, drawn as a planar quad net, and that net
//! refined by the scheme itself.
//!
//! **Numeric eigenanalysis (f64).** The local subdivision matrix is not assembled: it is
//! applied, by the runtime's reference surface step (`refine_surface`), to a closed labelled
//! mesh in which the EV's neighbourhood is already in its stationary configuration. The mesh
//! is the n-gonal trapezohedron (2n quads, two EVs of valence n, the others of valence 3)
//! refined s times, s chosen so that the labels of the first rings no longer change from one
//! step to the next (\[G\] Lemma 4.6 / Prop. 4.7) and the masks are contained (Prop. 4.8). The
//! neighbourhood is the k-ring grid of quads around the EV (n sectors of k × k quads); its
//! positions are put into the mesh with every other vertex NaN, so a new neighbourhood that
//! depended on anything outside would come out NaN (checked: k grows until it does not). The
//! trapezohedron's planar coordinates x + iy are equivariant of Fourier index 1 under the
//! rotation by one sector, so power iteration from them stays in that block and converges to
//! the eigenvector of λ1, the largest eigenvalue there. λ1 must equal the closed form of the
//! 2×2 Fourier block (`EvCoefficients::block`), which the command checks.

use crate::input_error;
use crate::picture::{bounds, Anchor, Frame, Picture, Style};
use lsubdiv::compiler::Error;
use lsubdiv::generic::GenericSurface;
use lsubdiv::mesh::surface::{refine_surface, LabelledMesh};
use lsubdiv::mesh::topology::Topology;
use lsubdiv::mesh::QuadMesh;
use std::collections::{HashMap, HashSet, VecDeque};

/// Largest ring count tried for the neighbourhood.
const MAX_RINGS: usize = 12;
/// Power iteration stops when λ changes by less than this (relative) …
const LAMBDA_TOL: f64 = 1e-15;
/// … and the eigenvector residual |Av − λv| / |Av| is below this.
const RESIDUAL_TOL: f64 = 1e-12;
/// At most this many power iterations.
const MAX_ITERATIONS: usize = 400;

/// The n-gonal trapezohedron: north pole 0 and south pole 1 (valence n), upper ring
/// u_m = 2 + m and lower ring w_m = 2 + n + m (valence 3); faces (N, u_m, w_m, u_{m+1}) and
/// (S, w_{m+1}, u_{m+1}, w_m). For n = 3 it is the cube. Planar coordinates x + iy = e^{iθm}
/// on the rings make the poles' neighbourhoods equivariant of Fourier index 1.
pub fn trapezohedron(n: usize) -> QuadMesh {
    let angle = |t: f64| std::f64::consts::TAU * t / n as f64;
    let mut positions = vec![[0.0, 0.0, 1.0], [0.0, 0.0, -1.0]];
    positions.extend((0..n).map(|m| [angle(m as f64).cos(), angle(m as f64).sin(), 0.3]));
    positions.extend((0..n).map(|m| {
        let t = angle(m as f64 + 0.5);
        [t.cos(), t.sin(), -0.3]
    }));
    let u = |m: usize| (2 + m % n) as u32;
    let w = |m: usize| (2 + n + m % n) as u32;
    let mut faces: Vec<[u32; 4]> = (0..n).map(|m| [0, u(m), w(m), u(m + 1)]).collect();
    faces.extend((0..n).map(|m| [1, w(m + 1), u(m + 1), w(m)]));
    QuadMesh { positions, faces }
}

/// The k-ring neighbourhood of a vertex: per sector (one per face around it, in rotation
/// order), the (k+1) × (k+1) grid of vertex indices; `[m][i][j]` with `[m][0][0]` the vertex,
/// the line j = 0 shared with sector m − 1 and the line i = 0 with sector m + 1.
#[derive(Clone, Debug, PartialEq)]
pub struct Rings {
    /// Number of rings k.
    pub k: usize,
    /// `grid[m][i][j]`.
    pub grid: Vec<Vec<Vec<u32>>>,
}

impl Rings {
    /// Walks the quad grid of each sector around `v` out to k rings; None when the grid is not
    /// regular there (another extraordinary vertex within k rings, sectors that do not join).
    pub fn around(topo: &Topology, v: u32, k: usize) -> Option<Rings> {
        let mut grid = Vec::new();
        for wedge in topo.rotation(v) {
            let (f, c) = (wedge.face, wedge.corner);
            // i runs along the edge shared with the previous wedge, j along the next one.
            let (along_j, along_i) = if wedge.next_is_plus {
                ((c + 1) % 4, (c + 3) % 4)
            } else {
                ((c + 3) % 4, (c + 1) % 4)
            };
            let mut at: HashMap<u32, (i64, i64)> = HashMap::new();
            at.insert(topo.vertex(f, c), (0, 0));
            at.insert(topo.vertex(f, along_i), (1, 0));
            at.insert(topo.vertex(f, along_j), (0, 1));
            at.insert(topo.vertex(f, (c + 2) % 4), (1, 1));
            let mut seen = HashSet::from([f]);
            let mut queue = VecDeque::from([f]);
            while let Some(f) = queue.pop_front() {
                for l in 0..4u8 {
                    let Some((g, gl)) = topo.across(f, l) else {
                        return None; // a boundary within k rings: not a closed neighbourhood
                    };
                    if seen.contains(&g) {
                        continue;
                    }
                    let (a, b) = (topo.vertex(f, l), topo.vertex(f, (l + 1) % 4));
                    let (a_far, b_far) = (topo.vertex(f, (l + 3) % 4), topo.vertex(f, (l + 2) % 4));
                    // In g, the corner next to a that is not b continues the line a_far → a.
                    let ga = if topo.vertex(g, gl) == a {
                        gl
                    } else {
                        (gl + 1) % 4
                    };
                    let gb = if ga == gl { (gl + 1) % 4 } else { gl };
                    let next_to = |corner: u8, other: u8| {
                        if (corner + 1) % 4 == other {
                            (corner + 3) % 4
                        } else {
                            (corner + 1) % 4
                        }
                    };
                    let (pa, pb) = (at[&a], at[&b]);
                    let (qa, qb) = (at[&a_far], at[&b_far]);
                    let na = (2 * pa.0 - qa.0, 2 * pa.1 - qa.1);
                    let nb = (2 * pb.0 - qb.0, 2 * pb.1 - qb.1);
                    let inside = |p: (i64, i64)| {
                        (0..=k as i64).contains(&p.0) && (0..=k as i64).contains(&p.1)
                    };
                    if !inside(na) || !inside(nb) {
                        continue;
                    }
                    for (corner, p) in [(next_to(ga, gb), na), (next_to(gb, ga), nb)] {
                        let vid = topo.vertex(g, corner);
                        if *at.entry(vid).or_insert(p) != p {
                            return None;
                        }
                    }
                    seen.insert(g);
                    queue.push_back(g);
                }
            }
            let mut g = vec![vec![u32::MAX; k + 1]; k + 1];
            for (&vid, &(i, j)) in &at {
                g[i as usize][j as usize] = vid;
            }
            if at.len() != (k + 1) * (k + 1) || g.iter().flatten().any(|&x| x == u32::MAX) {
                return None;
            }
            for (i, row) in g.iter().enumerate().take(k) {
                for (j, &vid) in row.iter().enumerate().take(k) {
                    if (i, j) != (0, 0) && topo.valence(vid) != 4 {
                        return None;
                    }
                }
            }
            grid.push(g);
        }
        let rings = Rings { k, grid };
        for m in 0..rings.grid.len() {
            let next = &rings.grid[(m + 1) % rings.grid.len()];
            if (0..=k).any(|t| rings.grid[m][0][t] != next[t][0]) {
                return None;
            }
        }
        Some(rings)
    }

    /// Every (sector, i, j) with its vertex.
    fn cells(&self) -> impl Iterator<Item = (usize, usize, usize, u32)> + '_ {
        self.grid.iter().enumerate().flat_map(|(m, g)| {
            g.iter()
                .enumerate()
                .flat_map(move |(i, row)| row.iter().enumerate().map(move |(j, &v)| (m, i, j, v)))
        })
    }
}

/// The characteristic map's control net and how it was found.
#[derive(Clone, Debug)]
pub struct CharacteristicMap {
    /// Valence.
    pub n: usize,
    /// Subdominant eigenvalue found numerically.
    pub lambda: f64,
    /// Rings in the neighbourhood.
    pub k: usize,
    /// Subdivision steps from the trapezohedron to the stationary labelled mesh.
    pub step: usize,
    /// Power iterations run.
    pub iterations: usize,
    /// Final residual |Av − λv| / |Av|.
    pub residual: f64,
    /// The net: `net[m][i][j]`, scaled and rotated so that R_0 = `net[0][1][0]` = (1, 0).
    pub net: Vec<Vec<Vec<[f64; 2]>>>,
    /// The net refined `refined_steps` times by the scheme: its quads whose corners all depend
    /// on the net only.
    pub refined: Vec<[[f64; 2]; 4]>,
    /// Steps of that refinement.
    pub refined_steps: usize,
}

/// The ray word π^s(ω), read from the EV (every initial edge carries ω).
fn ray(surface: &GenericSurface, s: usize) -> Vec<u8> {
    let ls = &surface.scheme().ls;
    let mut w = ls.axiom.clone();
    for _ in 0..s {
        w = ls.rewrite(&w);
    }
    w
}

/// The first step s ≥ `from` at which the first `len` ray labels equal those of step s + 1 and
/// the ray is at least `2 len` long (the mesh's other EVs lie beyond).
fn stationary_step(surface: &GenericSurface, from: usize, len: usize) -> Option<usize> {
    (from..from + 40).find(|&s| {
        let (a, b) = (ray(surface, s), ray(surface, s + 1));
        a.len() >= 2 * len && b.len() >= len && a[..len] == b[..len]
    })
}

/// One application of the local subdivision matrix: the net's positions into `mesh` (NaN
/// elsewhere), one reference step, the new neighbourhood read back. None if any of it is not
/// finite (it depends on points outside the net).
fn apply(
    surface: &GenericSurface,
    mesh: &mut LabelledMesh,
    from: &Rings,
    to: &Rings,
    v: &[[f64; 2]],
) -> Result<Option<Vec<[f64; 2]>>, Error> {
    place(&mut mesh.mesh.positions, from, v);
    let (next, _) = refine_surface(surface, mesh, 1).map_err(input_error)?;
    let out = planar(to, &next.mesh.positions);
    Ok(out.iter().flatten().all(|x| x.is_finite()).then_some(out))
}

/// Puts the net `v` (in the grid's cell order) in the plane z = 0 and NaN everywhere else, so
/// that whatever depends on points outside the net comes out NaN.
fn place(positions: &mut [[f64; 3]], grid: &Rings, v: &[[f64; 2]]) {
    positions.fill([f64::NAN; 3]);
    for ((_, _, _, id), p) in grid.cells().zip(v) {
        positions[id as usize] = [p[0], p[1], 0.0];
    }
}

/// The x, y of the grid's points, in its cell order.
fn planar(grid: &Rings, positions: &[[f64; 3]]) -> Vec<[f64; 2]> {
    grid.cells()
        .map(|(_, _, _, id)| {
            let p = positions[id as usize];
            [p[0], p[1]]
        })
        .collect()
}

fn dot(a: &[[f64; 2]], b: &[[f64; 2]]) -> f64 {
    a.iter()
        .zip(b)
        .map(|(p, q)| p[0] * q[0] + p[1] * q[1])
        .sum()
}

/// The labelled trapezohedron after `s` steps, the next step, and the k-ring grids around the
/// north pole in both; None when the grid is not regular or the net depends on more than k rings.
type Stage = (LabelledMesh, Rings, Rings, Vec<[f64; 2]>);

fn stage(surface: &GenericSurface, n: usize, s: usize, k: usize) -> Result<Option<Stage>, Error> {
    let start = LabelledMesh::with_axiom(
        &lsubdiv::runtime::CurveScheme::tables(surface),
        trapezohedron(n),
    )
    .map_err(input_error)?;
    let (mut mesh, _) = refine_surface(surface, &start, s).map_err(input_error)?;
    let (next, _) = refine_surface(surface, &mesh, 1).map_err(input_error)?;
    let topo = |m: &LabelledMesh| {
        Topology::build(&m.mesh).map_err(|e| Error::internal(None, e.to_string()))
    };
    let (Some(from), Some(to)) = (
        Rings::around(&topo(&mesh)?, 0, k),
        Rings::around(&topo(&next)?, 0, k),
    ) else {
        return Ok(None);
    };
    let v = planar(&from, &mesh.mesh.positions);
    if apply(surface, &mut mesh, &from, &to, &v)?.is_none() {
        return Ok(None);
    }
    Ok(Some((mesh, from, to, v)))
}

/// Finds the characteristic map's control net at valence `n` and refines it `refine` steps.
/// `progress` is told each power iteration.
pub fn characteristic_map(
    surface: &GenericSurface,
    n: usize,
    refine: usize,
    progress: &dyn Fn(usize),
) -> Result<CharacteristicMap, Error> {
    if n < 3 {
        return Err(Error::input(format!(
            "valence {n}: extraordinary vertices have valence ≥ 3"
        )));
    }
    let a = surface.analysis();
    let from = a.stationary_from.max(a.contained_from);
    let mut found = None;
    for k in 4..=MAX_RINGS {
        let Some(s) = stationary_step(surface, from, k + 2) else {
            continue;
        };
        if let Some(st) = stage(surface, n, s, k)? {
            found = Some((s, k, st));
            break;
        }
    }
    let (step, k, (mut mesh, rings, next_rings, mut v)) = found.ok_or_else(|| {
        Error::input(format!(
            "no stationary neighbourhood of at most {MAX_RINGS} rings found at valence {n}"
        ))
    })?;
    let norm = dot(&v, &v).sqrt();
    v.iter_mut().for_each(|p| *p = [p[0] / norm, p[1] / norm]);
    let (mut lambda, mut residual, mut iterations) = (f64::NAN, f64::INFINITY, 0);
    while iterations < MAX_ITERATIONS {
        let mut av = apply(surface, &mut mesh, &rings, &next_rings, &v)?.ok_or_else(|| {
            Error::internal(None, "the neighbourhood stopped being self-contained")
        })?;
        // Rounding leaves a trace of the translations (eigenvalue 1, Fourier index 0), which
        // power iteration would amplify: take the EV child's position off every point.
        let ev = av[0];
        av.iter_mut()
            .for_each(|p| *p = [p[0] - ev[0], p[1] - ev[1]]);
        iterations += 1;
        progress(iterations);
        let l = dot(&av, &v);
        let r: f64 = av
            .iter()
            .zip(&v)
            .map(|(p, q)| (p[0] - l * q[0]).powi(2) + (p[1] - l * q[1]).powi(2))
            .sum::<f64>()
            .sqrt();
        let size = dot(&av, &av).sqrt();
        let settled = (l - lambda).abs() <= LAMBDA_TOL * l.abs();
        lambda = l;
        residual = r / size;
        v = av.iter().map(|p| [p[0] / size, p[1] / size]).collect();
        if settled && residual < RESIDUAL_TOL {
            break;
        }
    }
    // Rotate and scale so that R_0 = (1, 0): multiplication by a complex number keeps an
    // eigenvector of the index-1 block one.
    let r0 = rings
        .cells()
        .position(|(m, i, j, _)| (m, i, j) == (0, 1, 0))
        .expect("k ≥ 1");
    let (a, b) = (v[r0][0], v[r0][1]);
    let q = a * a + b * b;
    let normal: Vec<[f64; 2]> = v
        .iter()
        .map(|p| [(p[0] * a + p[1] * b) / q, (p[1] * a - p[0] * b) / q])
        .collect();
    let mut net = vec![vec![vec![[0.0; 2]; k + 1]; k + 1]; rings.grid.len()];
    for ((m, i, j, _), p) in rings.cells().zip(&normal) {
        net[m][i][j] = *p;
    }
    // The refined net: the net alone in the mesh (NaN elsewhere), refined by the scheme.
    place(&mut mesh.mesh.positions, &rings, &normal);
    let (fine, _) = refine_surface(surface, &mesh, refine).map_err(input_error)?;
    let pos = &fine.mesh.positions;
    let refined = fine
        .mesh
        .faces
        .iter()
        .filter(|f| {
            f.iter()
                .all(|&c| pos[c as usize].iter().all(|x| x.is_finite()))
        })
        .map(|f| f.map(|c| [pos[c as usize][0], pos[c as usize][1]]))
        .collect();
    Ok(CharacteristicMap {
        n,
        lambda,
        k,
        step,
        iterations,
        residual,
        net,
        refined,
        refined_steps: refine,
    })
}

/// The picture: the refined net thin, the control net bold, the EV and its 1-ring marked.
pub fn picture(name: &str, map: &CharacteristicMap, closed_form: f64, size: (u32, u32)) -> Picture {
    let (w, h) = (f64::from(size.0), f64::from(size.1));
    let all = map.net.iter().flatten().flatten();
    let frame = Frame::fit(bounds(all, 0.03), [16.0, 62.0, w - 32.0, h - 62.0 - 44.0]);
    let mut pic = Picture::new(size.0, size.1);
    pic.text(
        [0.5 * w, 26.0],
        &format!("{name}: characteristic map at valence {}", map.n),
        16.0,
        Anchor::Middle,
        "black",
    );
    pic.text(
        [0.5 * w, 48.0],
        &format!(
            "λ1 = {:.12} (power iteration, residual {:.0e}; closed form {:.12})",
            map.lambda, map.residual, closed_form
        ),
        12.0,
        Anchor::Middle,
        "#333333",
    );
    // Refined net: each edge once, all in one path.
    let mut edges = HashSet::new();
    let mut d = String::new();
    for quad in &map.refined {
        for e in 0..4 {
            let (a, b) = (frame.map(quad[e]), frame.map(quad[(e + 1) % 4]));
            let key = |p: [f64; 2]| ((p[0] * 100.0).round() as i64, (p[1] * 100.0).round() as i64);
            let k = if key(a) < key(b) {
                (key(a), key(b))
            } else {
                (key(b), key(a))
            };
            if edges.insert(k) {
                d.push_str(&format!("M{:.1} {:.1}L{:.1} {:.1}", a[0], a[1], b[0], b[1]));
            }
        }
    }
    pic.path(&d, &Style::stroke("#9aa7b8", 0.6), "refined");
    // Control net: the grid lines of each sector.
    let bold = Style::stroke("#1f4e9c", 1.8);
    for sector in &map.net {
        for (t, line) in sector.iter().enumerate() {
            let row: Vec<[f64; 2]> = line.iter().map(|&p| frame.map(p)).collect();
            let col: Vec<[f64; 2]> = sector.iter().map(|l| frame.map(l[t])).collect();
            pic.polyline(&row, false, &bold, "net");
            pic.polyline(&col, false, &bold, "net");
        }
    }
    for (m, sector) in map.net.iter().enumerate() {
        pic.circle(
            frame.map(sector[1][0]),
            4.0,
            &Style::fill("#1f4e9c"),
            "ring",
        );
        pic.circle(frame.map(sector[1][1]), 3.0, &Style::fill("#5b8bd6"), "");
        let label_at = frame.map([1.18 * sector[1][0][0], 1.18 * sector[1][0][1]]);
        // Names where the 1-ring is large enough to hold them.
        if map.n <= 12 && frame.scale() > 60.0 {
            pic.text(
                [label_at[0], label_at[1] + 4.0],
                &format!("R{m}"),
                11.0,
                Anchor::Middle,
                "#1f4e9c",
            );
        }
    }
    pic.circle(frame.map([0.0, 0.0]), 5.0, &Style::fill("#d62728"), "ev");
    let captions = [
        format!(
            "bold: the control net, {} rings: the eigenvector of λ1 (x, y: its two real components)",
            map.k
        ),
        format!(
            "thin: that net refined {} step{} by the scheme (where it depends on the net only)",
            map.refined_steps,
            if map.refined_steps == 1 { "" } else { "s" }
        ),
    ];
    for (i, c) in captions.iter().enumerate() {
        pic.text(
            [16.0, h - 30.0 + 16.0 * i as f64],
            c,
            11.0,
            Anchor::Start,
            "#333333",
        );
    }
    pic
}
