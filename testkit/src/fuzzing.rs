//! Checks shared by the fuzz targets (`fuzz/fuzz_targets/`) and the corpus test
//! (`tests/fuzz_corpus.rs`), and the small random L-systems of the fuzzer and the property tests.
//!
//! Each check takes raw bytes and must never panic. `Ok` means the input was processed through
//! the whole path and passed the check's invariants; `Err` says why it was refused (a bad-input
//! error, or a bound on the work so that the fuzzer keeps exploring instead of timing out). An
//! invariant that fails is a bug and panics, so the fuzzer reports it.

use crate::points::same_points;
use arbitrary::{Arbitrary, Unstructured};
use lsubdiv::compiler::exact::lsystem::{LSystem, Source};
use lsubdiv::compiler::exact::{scheme, symmetry, validity, Scheme};
use lsubdiv::compiler::Error;
use lsubdiv::generic::{GenericScheme, GenericSurface};
use lsubdiv::mesh::surface::{refine_surface, LabelledMesh};
use lsubdiv::mesh::{generators, patch};
use lsubdiv::{refine, Curve, CurveScheme};

/// File name the checks give the scheme parser (errors must name it).
pub const SCHEME_FILE: &str = "fuzz.toml";

/// Refused inputs: the error message.
pub type Outcome = Result<(), String>;

/// Largest alphabet whose analysis the scheme check runs (the exact characteristic polynomial
/// and factorisation grow fast with n; the parser itself sees every alphabet).
const MAX_ANALYSED_SYMBOLS: usize = 16;

/// A compiler error, after checking that it names the scheme file at a line of the text.
fn scheme_error(e: Error, text: &str) -> String {
    let shown = e.to_string();
    if let (false, Some(at)) = (e.is_internal(), &e.at) {
        assert_eq!(at.file, SCHEME_FILE, "{shown}");
        let line = at.line.expect("scheme errors name a line");
        assert!(
            line >= 1 && line <= text.lines().count().max(1) + 1,
            "line out of the text: {shown}"
        );
    }
    shown
}

/// Scheme text → [`scheme::parse`] → [`symmetry::involutions`] → [`validity::analyse`]: errors
/// name the file and a line of the text, the involutions found make the system symmetric and
/// include a declared σ that does, and a valid system's lengths are positive.
pub fn check_scheme(data: &[u8]) -> Outcome {
    let text = std::str::from_utf8(data).map_err(|e| e.to_string())?;
    let ls = scheme::parse(SCHEME_FILE, text).map_err(|e| scheme_error(e, text))?;
    let found = symmetry::involutions(&ls);
    assert!(found.iter().all(|s| symmetry::is_symmetry(&ls, s)));
    if let Some(sigma) = &ls.symmetry {
        let complete = found.len() < symmetry::MAX_INVOLUTIONS;
        if complete && symmetry::is_symmetry(&ls, sigma) {
            assert!(found.contains(sigma), "declared σ not found");
        }
    }
    if ls.n() > MAX_ANALYSED_SYMBOLS {
        return Err(format!("{} symbols: analysis not fuzzed", ls.n()));
    }
    let a = validity::analyse(&ls).map_err(|e| scheme_error(e, text))?;
    if let Some((lengths, _)) = &a.lengths {
        assert!(a.valid, "lengths for an invalid system");
        assert!(
            lengths.iter().all(|l| l.signum() > 0),
            "non-positive length"
        );
    }
    Ok(())
}

/// OBJ text → [`lsubdiv::obj::parse`] → [`Parsed::check`](lsubdiv::mesh_file::Parsed::check)
/// (its errors placed at their lines): faces index existing vertices, and the 2-manifold it is
/// made (non-manifold places separated, split into quads when it has other faces) has
/// 2E = 4F + B, B its boundary edges.
pub fn check_obj(data: &[u8]) -> Outcome {
    let text = std::str::from_utf8(data).map_err(|e| e.to_string())?;
    let parsed = lsubdiv::obj::parse("fuzz.obj", text).map_err(|e| e.to_string())?;
    let n = parsed.mesh.positions.len();
    let all_quads = parsed.mesh.faces().all(|f| f.len() == 4);
    let checked = parsed.check("fuzz.obj").map_err(|e| e.to_string())?;
    let topo = &checked.topology;
    edges_and_faces(topo);
    assert_eq!(checked.split, !all_quads);
    // A file needing no separation (no non-manifold or unused vertex) keeps its vertices.
    if all_quads && checked.weld.is_none() {
        assert_eq!(topo.vertex_count(), n);
    }
    Ok(())
}

/// Every edge has one or two faces: twice the edges are four per quad and one per boundary
/// edge.
fn edges_and_faces(topo: &lsubdiv::mesh::topology::Topology) {
    let boundary = (0..topo.face_count() as u32)
        .flat_map(|f| (0..4).map(move |l| (f, l)))
        .filter(|&(f, l)| topo.is_boundary_edge(f, l))
        .count();
    assert_eq!(
        2 * topo.edge_count(),
        4 * topo.face_count() + boundary,
        "2E ≠ 4F + B"
    );
}

/// File name the PLY check gives the reader (errors must name it).
pub const PLY_FILE: &str = "fuzz.ply";

/// PLY bytes → [`lsubdiv::ply::parse`] → [`Parsed::check`](lsubdiv::mesh_file::Parsed::check):
/// errors name the file; what is read has finite coordinates and faces that index existing
/// vertices; a quad 2-manifold has 2E = 4F + B; and what is accepted, written back by
/// lsubdiv's ASCII and binary (both byte orders) writers, reads back bit for bit.
pub fn check_ply(data: &[u8]) -> Outcome {
    let named = |e: Error| {
        assert_eq!(
            e.at.as_ref().map(|l| l.file.as_str()),
            Some(PLY_FILE),
            "{e}"
        );
        e.to_string()
    };
    let parsed = lsubdiv::ply::parse(PLY_FILE, data).map_err(named)?;
    let n = parsed.mesh.positions.len();
    assert!(parsed
        .mesh
        .positions
        .iter()
        .flatten()
        .all(|x| x.is_finite()));
    let checked = parsed.check(PLY_FILE).map_err(named)?;
    let mesh = &checked.mesh;
    assert!(mesh
        .faces
        .iter()
        .flatten()
        .all(|&v| (v as usize) < mesh.positions.len()));
    let topo = &checked.topology;
    edges_and_faces(topo);
    if !checked.split && checked.weld.is_none() {
        assert_eq!(topo.vertex_count(), n);
    }
    let bits = |m: &lsubdiv::mesh::QuadMesh| -> Vec<u64> {
        m.positions.iter().flatten().map(|x| x.to_bits()).collect()
    };
    for (how, bytes) in [
        (
            "ASCII",
            lsubdiv::ply::format(mesh).expect("finite").into_bytes(),
        ),
        (
            "little-endian",
            lsubdiv::ply::binary(mesh, false).expect("finite"),
        ),
        (
            "big-endian",
            lsubdiv::ply::binary(mesh, true).expect("finite"),
        ),
    ] {
        let back = lsubdiv::mesh_file::parse_checked(PLY_FILE, bytes)
            .unwrap_or_else(|e| panic!("{how} PLY written by lsubdiv does not read back: {e}"));
        assert_eq!(back.mesh.faces, mesh.faces, "{how}");
        assert_eq!(bits(&back.mesh), bits(mesh), "{how}");
    }
    Ok(())
}

/// A small L-system as the fuzzer and the property tests draw it: symbols `A`, `B`, … .
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct SmallSystem {
    /// Spline degree.
    pub degree: usize,
    /// π(a) for every symbol a.
    pub rules: Vec<Vec<u8>>,
    /// The axiom.
    pub axiom: Vec<u8>,
    /// σ, declared in the scheme text, when the system was made symmetric.
    pub sigma: Option<Vec<u8>>,
}

/// The involution of 0..n that pairs each symbol not yet paired, in order, with the
/// `picks[i] mod (choices)`-th unpaired symbol from itself on (itself: fixed).
pub fn involution(n: usize, picks: &[usize]) -> Vec<u8> {
    let mut sigma: Vec<Option<u8>> = vec![None; n];
    let mut picks = picks.iter().copied().cycle();
    for a in 0..n {
        if sigma[a].is_some() {
            continue;
        }
        let free: Vec<usize> = (a..n).filter(|&b| sigma[b].is_none()).collect();
        let b = free[picks.next().unwrap_or(0) % free.len()];
        sigma[a] = Some(b as u8);
        sigma[b] = Some(a as u8);
    }
    sigma.into_iter().map(|s| s.unwrap_or(0)).collect()
}

/// σ̄(w) (\[G\] eq. (12)): w read backwards, each symbol replaced by its twin.
fn mirror(sigma: &[u8], w: &[u8]) -> Vec<u8> {
    w.iter().rev().map(|&s| sigma[s as usize]).collect()
}

/// A word w with σ̄(w) = w of the same length: the first half of `w`, its middle symbol (if
/// odd, replaced by `fixed` unless σ fixes it) and the mirror of the first half.
fn palindrome(sigma: &[u8], w: &[u8], fixed: u8) -> Vec<u8> {
    let half = &w[..w.len() / 2];
    let mut out = half.to_vec();
    if w.len() % 2 == 1 {
        let m = w[w.len() / 2];
        out.push(if sigma[m as usize] == m { m } else { fixed });
    }
    out.extend(mirror(sigma, half));
    out
}

impl SmallSystem {
    /// Number of symbols.
    pub fn n(&self) -> usize {
        self.rules.len()
    }

    /// The system made symmetric under σ (\[G\] eq. (14), Proposition 4.2): the first symbol a
    /// of each pair keeps its rule and its twin gets σ̄(π(a)); a fixed symbol's rule and the
    /// axiom become σ-palindromes of the same length. Rule lengths are kept.
    pub fn symmetrised(mut self, sigma: Vec<u8>) -> SmallSystem {
        for a in 0..self.n() {
            let b = sigma[a] as usize;
            if b == a {
                self.rules[a] = palindrome(&sigma, &self.rules[a], a as u8);
            } else if a < b {
                self.rules[b] = mirror(&sigma, &self.rules[a]);
            }
        }
        let fixed = (0..sigma.len()).find(|&a| sigma[a] as usize == a);
        // Some symbol is fixed when the axiom has odd length and none when n is even and all
        // are paired: then the axiom's middle needs one, so use an even-length axiom.
        match fixed {
            Some(f) => self.axiom = palindrome(&sigma, &self.axiom, f as u8),
            None => {
                let h = self.axiom[..self.axiom.len().div_ceil(2)].to_vec();
                self.axiom = h.iter().copied().chain(mirror(&sigma, &h)).collect();
            }
        }
        self.sigma = Some(sigma);
        self
    }

    /// The scheme file text (symbols `A`, `B`, …; named `small`).
    pub fn to_toml(&self) -> String {
        let n = self.rules.len();
        scheme::to_toml(&LSystem {
            name: "small".into(),
            degree: self.degree,
            symbols: (0..n as u8)
                .map(|a| char::from(b'A' + a).to_string())
                .collect(),
            rules: self.rules.clone(),
            axiom: self.axiom.clone(),
            symmetry: self.sigma.clone(),
            lengths: None,
            source: Source::default(),
        })
    }

    /// Draws a system with 1..=`symbols` symbols, rules of length 1..=`rule_len`, degree
    /// 1..=`degree`, an axiom of length 1..=3, made symmetric half of the time. One draw in
    /// three aims at the surface conditions (\[G\] §4): degree 3, a one-symbol axiom, symmetric.
    pub fn draw(
        u: &mut Unstructured<'_>,
        symbols: usize,
        rule_len: usize,
        degree: usize,
    ) -> arbitrary::Result<SmallSystem> {
        let n = u.int_in_range(1..=symbols)?;
        let surface = u.ratio(1u8, 3)?;
        let degree = if surface {
            3
        } else {
            u.int_in_range(1..=degree)?
        };
        let word = |u: &mut Unstructured<'_>, max: usize| -> arbitrary::Result<Vec<u8>> {
            let len = u.int_in_range(1..=max)?;
            (0..len).map(|_| u.int_in_range(0..=n as u8 - 1)).collect()
        };
        let rules = (0..n)
            .map(|_| word(u, rule_len))
            .collect::<arbitrary::Result<_>>()?;
        let axiom = word(u, if surface { 1 } else { 3 })?;
        let s = SmallSystem {
            degree,
            rules,
            axiom,
            sigma: None,
        };
        Ok(if surface || bool::arbitrary(u)? {
            let picks = (0..n)
                .map(|_| u.int_in_range(0..=n - 1))
                .collect::<arbitrary::Result<Vec<_>>>()?;
            s.symmetrised(involution(n, &picks))
        } else {
            s
        })
    }
}

/// Largest refined curve (points) and mesh (faces) the pipeline check builds.
const MAX_CURVE_POINTS: usize = 5_000;
const MAX_FACES: usize = 20_000;

/// A small structured input → scheme text → [`scheme::parse`] → [`Scheme::build`] → generic
/// curve refinement, and, when the scheme passes the surface conditions, the patch path on the
/// cube or a split icosphere. Invariants: the generated text parses; label and point counts agree; a constant
/// polygon stays constant (partition of unity); refined points and vertices are finite, and
/// the patch path's points are the reference driver's.
pub fn check_pipeline(data: &[u8]) -> Outcome {
    let mut u = Unstructured::new(data);
    let sys = SmallSystem::draw(&mut u, 4, 4, 4).map_err(|e| e.to_string())?;
    let text = sys.to_toml();
    let ls = scheme::parse(SCHEME_FILE, &text)
        .unwrap_or_else(|e| panic!("generated text does not parse: {e}\n{text}"));
    let d = ls.degree;
    let max_rule = ls.rules.iter().map(Vec::len).max().unwrap_or(1);
    let scheme = Scheme::build(ls).map_err(|e| e.to_string())?;

    // The polygon: d+1..=d+6 points with small integer coordinates, labels from the axiom or
    // drawn, 0..=3 steps.
    let m = d + 1 + u.int_in_range(0..=5usize).map_err(|e| e.to_string())?;
    let closed = bool::arbitrary(&mut u).map_err(|e| e.to_string())?;
    let steps = u.int_in_range(0..=3usize).map_err(|e| e.to_string())?;
    let points: Vec<[f64; 2]> = (0..m)
        .map(|_| -> arbitrary::Result<[f64; 2]> {
            Ok([
                f64::from(i8::arbitrary(&mut u)?),
                f64::from(i8::arbitrary(&mut u)?),
            ])
        })
        .collect::<arbitrary::Result<_>>()
        .map_err(|e| e.to_string())?;
    if m * max_rule.pow(steps as u32) > MAX_CURVE_POINTS {
        return Err("refined curve too large".into());
    }
    let mut generic = GenericScheme::new(scheme.clone()).map_err(|e| e.to_string())?;
    let mut curve = Curve::with_axiom(&generic.tables(), points, closed);
    if bool::arbitrary(&mut u).map_err(|e| e.to_string())? {
        let n = scheme.ls.n() as u8;
        for l in &mut curve.labels {
            *l = u.int_in_range(0..=n - 1).map_err(|e| e.to_string())?;
        }
    }
    generic.prepare(&curve).map_err(|e| e.to_string())?;
    let fine = refine(&generic, &curve, steps).map_err(|e| e.to_string())?;
    let extra = if closed { 0 } else { d };
    assert_eq!(fine.labels.len(), fine.points.len() + extra, "label count");
    assert!(fine.points.iter().flatten().all(|x| x.is_finite()));
    let constant = Curve {
        points: vec![[0.5, -2.0]; m],
        ..curve
    };
    for p in refine(&generic, &constant, steps)
        .expect("same labels refine")
        .points
    {
        assert!(
            (p[0] - 0.5).abs() < 1e-12 && (p[1] + 2.0).abs() < 1e-12,
            "partition of unity: {p:?}"
        );
    }

    let Ok(surface) = GenericSurface::new(scheme) else {
        return Ok(());
    };
    let steps = u.int_in_range(1..=2usize).map_err(|e| e.to_string())?;
    // The cube (fans around its EVs, composed patches elsewhere), or a triangle mesh split
    // into quads, every face at two EVs (level by level, lock-step, the last step composed).
    let mesh = if bool::arbitrary(&mut u).map_err(|e| e.to_string())? {
        crate::meshes::split(&generators::icosphere(1))
    } else {
        generators::cube()
    };
    let side = surface.scheme().ls.axiom.len() * max_rule.pow(steps as u32);
    if mesh.faces.len() * side * side > MAX_FACES {
        return Err("refined mesh too large".into());
    }
    let fine = patch::subdivide::<_, f64>(&surface, &mesh, steps, 1).map_err(|e| e.to_string())?;
    let nv = fine.positions.len();
    assert!(fine.faces.iter().flatten().all(|&v| (v as usize) < nv));
    assert!(fine.positions.iter().flatten().all(|x| x.is_finite()));
    // The reference driver (level by level, the whole mesh) makes the same points.
    let labelled = LabelledMesh::with_axiom(&surface.tables(), mesh).map_err(|e| e.to_string())?;
    let (reference, _) = refine_surface(&surface, &labelled, steps).map_err(|e| e.to_string())?;
    let d = same_points(&fine.positions, &reference.mesh.positions);
    assert!(d < 1e-12, "patch path off the reference driver by {d:e}");
    Ok(())
}
