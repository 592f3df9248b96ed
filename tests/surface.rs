//! Surfaces (\[G\]): Catmull–Clark on the torus, tensor products of the curve schemes, affine
//! invariance, convexity, counts from the words, EV meshes for 1..6 steps, generic = generated.

mod common;

use lsubdiv::compiler::exact::Scheme;
use lsubdiv::generic::{GenericScheme, GenericSurface};
use lsubdiv::mesh::generators::{cube, grid_cube, icosphere, klein_bottle, prism, star, torus};
use lsubdiv::mesh::surface::{refine_surface, LabelledMesh, StepStats};
use lsubdiv::mesh::topology::Topology;
use lsubdiv::mesh::QuadMesh;
use lsubdiv::{generated, Curve, CurveScheme};
use lsubdiv_cli::resolve;
use lsubdiv_testkit::catmull_clark::catmull_clark_steps;
use lsubdiv_testkit::meshes::{capless, split};
use lsubdiv_testkit::points::same_points;

fn surface(name: &str) -> GenericSurface {
    let r = resolve(name).unwrap();
    GenericSurface::new(Scheme::build(r.ls).unwrap()).unwrap_or_else(|e| panic!("{e}"))
}

fn refine(s: &GenericSurface, mesh: QuadMesh, steps: usize) -> (QuadMesh, Vec<StepStats>) {
    let lm = LabelledMesh::with_axiom(&s.tables(), mesh).unwrap();
    let (out, stats) = refine_surface(s, &lm, steps).unwrap_or_else(|e| panic!("{e}"));
    (out.mesh, stats)
}

#[test]
fn uniform_binary_on_the_torus_is_catmull_clark() {
    let s = surface("uniform-binary");
    let t = torus(6, 8);
    for steps in 1..=3 {
        let (ours, stats) = refine(&s, t.clone(), steps);
        let cc = catmull_clark_steps(&t, steps);
        let d = same_points(&ours.positions, &cc.positions);
        assert!(d < 1e-12, "step {steps}: {d:e}");
        assert!(
            stats.iter().all(|st| *st == StepStats::default()),
            "{stats:?}"
        );
    }
}

/// Refines a periodic grid of points as closed curves along rows, then along columns.
fn tensor_product(name: &str, grid: &[Vec<[f64; 3]>], steps: usize) -> Vec<[f64; 3]> {
    let r = resolve(name).unwrap();
    let g = GenericScheme::new(Scheme::build(r.ls).unwrap()).unwrap();
    let rows: Vec<Vec<[f64; 3]>> = grid
        .iter()
        .map(|row| {
            let c = Curve::with_axiom(&g.tables(), row.clone(), true);
            lsubdiv::refine(&g, &c, steps).unwrap().points
        })
        .collect();
    let mut out = Vec::new();
    for j in 0..rows[0].len() {
        let col: Vec<[f64; 3]> = rows.iter().map(|r| r[j]).collect();
        let c = Curve::with_axiom(&g.tables(), col, true);
        out.extend(lsubdiv::refine(&g, &c, steps).unwrap().points);
    }
    out
}

#[test]
fn schemes_on_the_torus_are_tensor_products_of_their_curves() {
    let (rows, cols) = (5, 7);
    let t = torus(rows, cols);
    // The generator numbers vertex (i, j) as i * cols + j.
    let grid: Vec<Vec<[f64; 3]>> = (0..rows)
        .map(|i| (0..cols).map(|j| t.positions[i * cols + j]).collect())
        .collect();
    for (name, steps) in [
        ("binary-ternary", 2),
        ("fibonacci", 4),
        ("low-ratio", 4),
        ("remark-5-3", 4),
        ("fibonacci-alt", 4),
        // Found by `lsubdiv search` and shipped as a scheme file.
        ("found-cubic", 4),
    ] {
        let (ours, stats) = refine(&surface(name), t.clone(), steps);
        let d = same_points(&ours.positions, &tensor_product(name, &grid, steps));
        assert!(d < 1e-12, "{name}: {d:e}");
        assert!(
            stats.iter().all(|st| st.normalised == 0 && st.dropped == 0),
            "{name}: {stats:?}"
        );
    }
}

fn affine(p: &[f64; 3]) -> [f64; 3] {
    [
        0.8 * p[0] - 0.6 * p[1] + 0.1 * p[2] + 3.0,
        0.6 * p[0] + 0.8 * p[1] - 0.2 * p[2] - 1.0,
        0.3 * p[0] + 1.7 * p[2] + 0.5,
    ]
}

#[test]
fn refinement_is_affine_invariant_and_convex() {
    for name in generated::SURFACE_NAMES {
        let s = surface(name);
        for mesh in [star(), cube()] {
            let mut moved = mesh.clone();
            moved.positions.iter_mut().for_each(|p| *p = affine(p));
            let steps = if *name == "binary-ternary" { 2 } else { 3 };
            let (a, _) = refine(&s, mesh.clone(), steps);
            let (b, _) = refine(&s, moved, steps);
            for (p, q) in a.positions.iter().zip(&b.positions) {
                let t = affine(p);
                let err = (0..3).map(|c| (t[c] - q[c]).abs()).fold(0.0, f64::max);
                assert!(err < 1e-12, "{name}: {err:e}");
            }
            // Masks are non-negative, so every new point is a convex combination: no linear
            // functional exceeds its range over the old points.
            for k in 0..16 {
                let u = [
                    (k as f64 * 0.7).cos(),
                    (k as f64 * 1.3).sin(),
                    (k as f64 * 0.4).cos() - 0.5,
                ];
                let dot = |p: &[f64; 3]| u[0] * p[0] + u[1] * p[1] + u[2] * p[2];
                let (lo, hi) = mesh
                    .positions
                    .iter()
                    .map(dot)
                    .fold((f64::MAX, f64::MIN), |(l, h), x| (l.min(x), h.max(x)));
                for p in &a.positions {
                    let x = dot(p);
                    assert!(x >= lo - 1e-12 && x <= hi + 1e-12, "{name}: not convex");
                }
            }
        }
    }
}

/// |π^s(ω)|: sub-edges of one initial edge after s steps.
fn edge_split(s: &GenericSurface, steps: usize) -> usize {
    let ls = &s.scheme().ls;
    let mut w = ls.axiom.clone();
    for _ in 0..steps {
        w = ls.rewrite(&w);
    }
    w.len()
}

#[test]
fn counts_follow_from_the_words() {
    // [G] §3.3: one initial edge becomes 17 sub-edges after 3 Binary-Ternary steps and 16 after
    // 5 Fibonacci steps (and 16 after 4 Catmull–Clark steps).
    assert_eq!(edge_split(&surface("binary-ternary"), 3), 17);
    assert_eq!(edge_split(&surface("fibonacci"), 5), 16);
    assert_eq!(edge_split(&surface("uniform-binary"), 4), 16);
}

#[test]
fn ev_meshes_refine_for_one_to_six_steps() {
    for name in generated::SURFACE_NAMES {
        let s = surface(name);
        for (label, mesh) in [("cube", cube()), ("prism 9", prism(9)), ("star", star())] {
            let topo = Topology::build(&mesh).unwrap();
            let evs = (0..topo.vertex_count() as u32)
                .filter(|&v| topo.valence(v) != 4)
                .count();
            let max_steps = match (*name, label) {
                ("binary-ternary", "cube") => 6,
                ("binary-ternary", _) => 4,
                ("uniform-binary", _) => 5,
                _ => 6,
            };
            let (fine, stats) = refine(&s, mesh.clone(), max_steps);
            let l = edge_split(&s, max_steps);
            let (v0, e0, f0) = (mesh.positions.len(), topo.edge_count(), mesh.faces.len());
            assert_eq!(fine.faces.len(), f0 * l * l, "{name} {label}");
            assert_eq!(
                fine.positions.len(),
                v0 + e0 * (l - 1) + f0 * (l - 1) * (l - 1),
                "{name} {label}"
            );
            let t = Topology::build(&fine).unwrap_or_else(|e| panic!("{name} {label}: {e}"));
            // EVs keep their valence; every new vertex is ordinary.
            let new_evs = (0..t.vertex_count() as u32)
                .filter(|&v| t.valence(v) != 4)
                .count();
            assert_eq!(new_evs, evs);
            assert!(fine.positions.iter().flatten().all(|x| x.is_finite()));
            for (k, st) in stats.iter().enumerate() {
                assert_eq!(st.ev_children, evs, "{name} {label} step {k}");
            }
            // Once masks are contained, only EV children need normalising ([G] §3.1.3).
            let a = s.analysis();
            for st in &stats[a.contained_from..] {
                assert_eq!(
                    (st.normalised, st.dropped),
                    (0, 0),
                    "{name} {label}: {stats:?}"
                );
            }
        }
    }
}

#[test]
fn binary_ternary_first_step_normalises_only_near_evs() {
    let s = surface("binary-ternary");
    assert_eq!(s.analysis().contained_from, 1);
    let (_, stats) = refine(&s, prism(9), 1);
    assert!(stats[0].dropped > 0 && stats[0].normalised > 0, "{stats:?}");
    let (_, stats) = refine(&s, torus(4, 5), 1);
    assert_eq!(stats[0], StepStats::default());
}

#[test]
fn non_orientable_meshes_refine() {
    for name in ["fibonacci", "binary-ternary"] {
        let (fine, _) = refine(&surface(name), klein_bottle(6, 7), 2);
        Topology::build(&fine).unwrap();
    }
}

/// The generic path, the generated registry's visitor and a shipped scheme kept as a value
/// (`AnySurface`, chosen by name) refine alike, bit for bit, on any number of threads.
#[test]
fn generic_and_generated_surfaces_are_identical() {
    use generated::AnySurface;
    use lsubdiv::mesh::features::Features;
    use lsubdiv::mesh::patch::{subdivide, Subdivide};
    use lsubdiv::mesh::topology::Topology;
    let mesh = star();
    let topology = Topology::build(&mesh).unwrap();
    let bits = |p: &[[f64; 3]]| p.iter().flatten().map(|x| x.to_bits()).collect::<Vec<_>>();
    assert_eq!(AnySurface::ALL.len(), generated::SURFACE_NAMES.len());
    for name in generated::SURFACE_NAMES {
        let s = surface(name);
        let a = subdivide::<_, f64>(&s, &mesh, 3, 1).unwrap();
        let job = Subdivide {
            mesh: &mesh,
            topology: &topology,
            features: &Features::default(),
            steps: 3,
            threads: 2,
            limit: false,
        };
        let b = generated::visit_surface(name, job).unwrap().unwrap().mesh;
        let kept = AnySurface::named(name).expect("a shipped surface scheme");
        assert_eq!(kept.name(), *name);
        let c = subdivide::<_, f64>(&kept, &mesh, 3, 3).unwrap();
        for (other, how) in [(&b, "the registry's visitor"), (&c, "AnySurface")] {
            assert_eq!(a.faces, other.faces, "{name}: {how}");
            assert_eq!(
                bits(&a.positions),
                bits(&other.positions),
                "{name}: generic 1 thread vs {how}"
            );
        }
    }
    assert_eq!(AnySurface::named("fibonacci-curve"), None);
    assert!(generated::AnyCurve::named("fibonacci-curve").is_some());
}

#[test]
fn valences_beyond_the_table_use_the_same_solver() {
    // α is tabulated for n ≤ 32 (computed at build time by the runtime's solver); a 40-valent EV
    // gets it from that same solver at run time.
    let g = generated::binary_ternary::SURFACE;
    assert_eq!(g.alpha.len(), 30);
    for n in 3..=32 {
        assert_eq!(
            g.alpha[n - 3].to_bits(),
            g.ev.alpha(n).unwrap().to_bits(),
            "n = {n}"
        );
    }
    let s = surface("binary-ternary");
    let (fine, stats) = refine(&s, prism(40), 2);
    assert_eq!(stats[1].ev_children, 2 + 80);
    assert!(fine.positions.iter().flatten().all(|x| x.is_finite()));
}

#[test]
fn patch_path_matches_the_reference_driver() {
    use lsubdiv::mesh::patch::{subdivide, Refiner};
    for name in generated::SURFACE_NAMES {
        let s = surface(name);
        for (label, mesh) in [
            ("cube", cube()),
            ("star", star()),
            ("prism 9", prism(9)),
            ("grid cube", grid_cube(4)),
            ("torus", torus(3, 4)),
            ("klein", klein_bottle(4, 5)),
        ] {
            let steps = if *name == "binary-ternary" { 2 } else { 3 };
            let (reference, _) = refine(&s, mesh.clone(), steps);
            for threads in [1, 2] {
                let fast = subdivide::<_, f64>(&s, &mesh, steps, threads).unwrap();
                assert_eq!(fast.faces.len(), reference.faces.len());
                let d = same_points(&fast.positions, &reference.positions);
                assert!(d < 1e-12, "{name} {label}: {d:e}");
                // Strips one point wide (every edge and corner split across strips) give the
                // same bits as the default, whole-patch strips of these small patches.
                let topo = Topology::build(&mesh).unwrap();
                let mut r = Refiner::<_, f64>::new(&s, &topo, steps, threads).unwrap();
                r.set_strip_bytes(1);
                let narrow = r.refine(&mesh.positions).unwrap();
                assert!(
                    narrow == &fast.positions[..],
                    "{name} {label}: narrow strips"
                );
                Topology::build(&fast).unwrap_or_else(|e| panic!("{name} {label}: {e}"));
            }
        }
    }
}

/// A triangle mesh split into quads has every face at an EV (the triangle's centre, valence 3,
/// and its corner): after its first steps, level by level, every face advances in lock-step
/// and hands its neighbours their ring points and its EVs their 1-rings through the handoff's
/// box (`patch/handoff.rs`): the reference driver's points on one, two and three threads, the
/// same bits on each; and with more fan faces (3,840) than one worker takes between levels, so
/// that the box is given and taken in several shares, the same bits as one share.
#[test]
fn a_triangle_mesh_hands_its_rings_on() {
    use lsubdiv::mesh::patch::Refiner;
    let lockstep =
        |r: &Refiner<'_, _, f64>, steps: usize| steps - r.reference_steps() - r.level_steps();
    let small = split_icosphere(1);
    let topo = Topology::build(&small).unwrap();
    for name in generated::SURFACE_NAMES {
        let s = surface(name);
        let steps = 5;
        let (reference, _) = refine(&s, small.clone(), steps);
        let mut one = None;
        for threads in [1, 2, 3] {
            let mut r = Refiner::<_, f64>::new(&s, &topo, steps, threads).unwrap();
            // At least two lock-step levels, so that a ring is handed on between them.
            assert!(lockstep(&r, steps) >= 2, "{name}");
            let points = r.refine(&small.positions).unwrap().to_vec();
            let d = same_points(&points, &reference.positions);
            assert!(d < 1e-12, "{name}, {threads} threads: {d:e}");
            let one = one.get_or_insert_with(|| points.clone());
            assert!(*one == points, "{name}: {threads} threads against one");
        }
    }
    let large = split_icosphere(3);
    let topo = Topology::build(&large).unwrap();
    assert_eq!(large.faces.len(), 3840);
    let s = surface("uniform-binary");
    let steps = 4;
    let mut one = None;
    for threads in [1, 2, 3] {
        let mut r = Refiner::<_, f64>::new(&s, &topo, steps, threads).unwrap();
        assert!(lockstep(&r, steps) >= 2);
        let points = r.refine(&large.positions).unwrap().to_vec();
        let one = one.get_or_insert_with(|| points.clone());
        assert!(*one == points, "{threads} threads against one");
    }
}

/// The first steps of a mesh whose faces are mostly at EVs run level by level, each face
/// computing the points it owns from the level before (`patch/direct.rs`): every step of the
/// split icosphere refined once or twice by uniform binary, some of them for the other
/// schemes; the reference driver's points in f64 and f32, on one to three threads, bit for bit
/// the same. A mesh of mostly ordinary faces has none past side 2.
#[test]
fn a_mesh_of_small_fans_starts_level_by_level() {
    use lsubdiv::mesh::patch::Refiner;
    let mesh = split_icosphere(3);
    let topo = Topology::build(&mesh).unwrap();
    assert_eq!(mesh.faces.len(), 3840);
    for name in generated::SURFACE_NAMES {
        let s = surface(name);
        for steps in 1..=2 {
            let (reference, _) = refine(&s, mesh.clone(), steps);
            let mut one = None;
            for threads in [1, 2, 3] {
                let mut r = Refiner::<_, f64>::new(&s, &topo, steps, threads).unwrap();
                if *name == "uniform-binary" {
                    assert_eq!(r.level_steps(), steps, "{name}, {steps} steps");
                }
                let points = r.refine(&mesh.positions).unwrap().to_vec();
                let d = same_points(&points, &reference.positions);
                assert!(d < 1e-12, "{name}, {steps} steps, {threads} threads: {d:e}");
                let one = one.get_or_insert_with(|| points.clone());
                assert!(*one == points, "{name}, {steps} steps: {threads} threads");
            }
            // f32: the f64 points, point for point, to f32 rounding.
            let mut r = Refiner::<_, f32>::new(&s, &topo, steps, 2).unwrap();
            let narrow = r.refine(&mesh.positions).unwrap();
            let wide = one.as_ref().unwrap();
            assert_eq!(narrow.len(), wide.len());
            let d = narrow
                .iter()
                .zip(wide)
                .flat_map(|(p, q)| (0..3).map(move |c| (f64::from(p[c]) - q[c]).abs()));
            let d = d.fold(0.0, f64::max);
            assert!(d < 1e-5, "{name}, {steps} steps, f32: {d:e}");
        }
        // Past side 2, to which every mesh runs level by level.
        let mostly_ordinary = Topology::build(&grid_cube(4)).unwrap();
        let level_steps = Refiner::<_, f64>::new(&s, &mostly_ordinary, 2, 1)
            .unwrap()
            .level_steps();
        let side = s.tables().image_len(s.tables().axiom, 2);
        assert!(side <= 2 || level_steps == 0, "{name}: {level_steps}");
    }
}

/// A triangle mesh, split into quads (every face at two EVs: the triangle's centre, valence 3,
/// and its vertex, valence 5 or 6).
fn split_icosphere(level: usize) -> QuadMesh {
    split(&icosphere(level))
}

/// Where the first steps run by the reference driver (Binary-Ternary's masks are contained at
/// EVs from its second step), the last of them scatters only near the EVs and the faces away
/// from them take that step by its 1D plan (`patch/near.rs`): the whole reference's points to
/// rounding, on one and two threads, alone and before a depth-first step.
#[test]
fn reference_step_near_the_evs_only() {
    use lsubdiv::mesh::patch::Refiner;
    let s = surface("binary-ternary");
    let mesh = grid_cube(12);
    let topo = Topology::build(&mesh).unwrap();
    for steps in 1..=2 {
        let (reference, _) = refine(&s, mesh.clone(), steps);
        for threads in [1, 2] {
            let mut r = Refiner::<_, f64>::new(&s, &topo, steps, threads).unwrap();
            assert_eq!(r.reference_steps(), 1);
            // The faces whose four corners are five rings or more from the cube's corners
            // (the scheme's masks reach 2 base edges, its words 2 more) take the plan.
            assert_eq!(r.reference_faces(), 8 * 3 * 5 * 5, "{steps} steps");
            let d = same_points(r.refine(&mesh.positions).unwrap(), &reference.positions);
            assert!(d < 1e-12, "{steps} steps, {threads} threads: {d:e}");
        }
    }
}

/// The mesh's vertices moved apart: a map of its points that is not affine.
fn moved(mesh: &QuadMesh) -> Vec<[f64; 3]> {
    let scale = |i: usize| 1.0 + 0.01 * (i % 7) as f64;
    let at = mesh.positions.iter().enumerate();
    at.map(|(i, p)| p.map(|x| x * scale(i))).collect()
}

/// A scheme whose masks are contained near EVs only from its third step: the first label out
/// of an EV splits into three at steps 0 and 1 (C → X C Z, X → Y C W), into two from step 2
/// on (Y → Y C), \[G\] Prop. 4.8. No shipped scheme has more than one reference step, and
/// none of 3,000 drawn by `common::surface_systems` had.
const CONTAINED_FROM_TWO: &str = r#"
name = "contained-from-two"
degree = 3
axiom = "C"

[rules]
C = "XCZ"
X = "YCW"
Z = "YCW"
Y = "YC"
W = "CW"

[symmetry]
X = "Z"
Y = "W"
"#;

/// Two reference steps (`patch/reference.rs`: the maps chained, the last one's level before
/// read by the faces far from the EVs, `patch/near.rs`): the reference driver's points on
/// the grid cube (faces far from its corners) and on the split icosphere (every face near an
/// EV), alone and before a depth-first step, on one and two threads, and again on moved
/// positions after a first refine.
#[test]
fn two_reference_steps_chain_their_maps() {
    use lsubdiv::compiler::exact::scheme;
    use lsubdiv::mesh::patch::Refiner;
    use lsubdiv::mesh::surface::SurfaceScheme;
    let ls = scheme::parse("contained-from-two.toml", CONTAINED_FROM_TWO).unwrap();
    let s = GenericSurface::new(Scheme::build(ls).unwrap()).unwrap();
    assert_eq!(s.surface().contained_from, 2);
    for (label, mesh, far) in [
        ("grid cube", grid_cube(12), true),
        ("icosphere", split_icosphere(1), false),
    ] {
        let topo = Topology::build(&mesh).unwrap();
        let moved = moved(&mesh);
        for steps in 2..=3 {
            let moved_mesh = QuadMesh {
                positions: moved.clone(),
                ..mesh.clone()
            };
            let (reference, _) = refine(&s, moved_mesh, steps);
            let mut outputs = Vec::new();
            for threads in [1, 2] {
                let mut r = Refiner::<_, f64>::new(&s, &topo, steps, threads).unwrap();
                assert_eq!(r.reference_steps(), 2, "{label}");
                let all = r.reference_faces() == mesh.faces.len();
                assert_eq!(all, !far, "{label}: faces far from the EVs");
                r.refine(&mesh.positions).unwrap();
                let out = r.refine(&moved).unwrap().to_vec();
                let d = same_points(&out, &reference.positions);
                assert!(
                    d < 1e-12,
                    "{label}, {steps} steps, {threads} threads: {d:e}"
                );
                outputs.push(out);
            }
            assert_eq!(outputs[0], outputs[1], "{label}, {steps} steps: threads");
        }
    }
}

/// The reference steps are maps built with the refiner (`patch/reference.rs`): a `refine` on
/// new positions gives the reference driver's points for those positions, whether the map
/// was first summed on others or not, and the same bits on one and two threads (the start
/// level of the split icosphere(4), 138,242 points, goes to two workers). On the open
/// icosphere (its step on the mesh cut along its boundary, with ghost layers) a refine after
/// one on other positions gives a fresh refiner's bits.
#[test]
fn reference_steps_are_maps_of_any_positions() {
    use lsubdiv::mesh::patch::Refiner;
    let s = surface("binary-ternary");
    let refined = |mesh: &QuadMesh, threads: usize, first: Option<&[[f64; 3]]>| {
        let topo = Topology::build(mesh).unwrap();
        let mut r = Refiner::<_, f64>::new(&s, &topo, 1, threads).unwrap();
        assert_eq!(r.reference_steps(), 1);
        if let Some(first) = first {
            r.refine(first).unwrap();
        }
        r.refine(&moved(mesh)).unwrap().to_vec()
    };
    let mesh = split_icosphere(4);
    let positions = moved(&mesh);
    let (reference, _) = refine(
        &s,
        QuadMesh {
            positions,
            ..mesh.clone()
        },
        1,
    );
    let outputs = [1, 2].map(|threads| {
        let out = refined(&mesh, threads, Some(&mesh.positions));
        let d = same_points(&out, &reference.positions);
        assert!(d < 1e-12, "{threads} threads: {d:e}");
        out
    });
    assert_eq!(outputs[0], outputs[1], "one and two threads differ");
    let open = split(&capless(&icosphere(2), 0.6));
    assert_eq!(
        refined(&open, 1, Some(&open.positions)),
        refined(&open, 1, None),
        "the open icosphere"
    );
}

/// Faces around EVs too large for their interior to be staged whole (63² points after six
/// steps of the cube) go out row by row, one writer per row: the reference driver's points,
/// streamed or not, on one or two threads.
#[test]
fn large_fan_faces_go_out_row_by_row() {
    use lsubdiv::mesh::patch::Refiner;
    let s = surface("uniform-binary");
    let mesh = cube();
    let steps = 6;
    let (reference, _) = refine(&s, mesh.clone(), steps);
    let topo = Topology::build(&mesh).unwrap();
    for (threads, stream) in [(1, 0), (2, 0), (1, usize::MAX)] {
        let mut r = Refiner::<_, f64>::new(&s, &topo, steps, threads).unwrap();
        r.set_stream_bytes(stream);
        let d = same_points(r.refine(&mesh.positions).unwrap(), &reference.positions);
        assert!(
            d < 1e-12,
            "{threads} threads, stream from {stream} bytes: {d:e}"
        );
    }
}

/// Ordinary faces whose final rows do not fit one band (65 rows of 224 values after six steps
/// of uniform binary; Binary-Ternary's 4 steps, 36 rows) are handed to the writers band by
/// band: the reference driver's points, streamed or not, on one or two threads, in f64 and
/// f32, and every SIMD path this CPU has.
#[test]
fn large_ordinary_faces_go_out_in_bands() {
    use lsubdiv::mesh::patch::{Refiner, Simd};
    for (name, steps) in [("uniform-binary", 6), ("binary-ternary", 4)] {
        let s = surface(name);
        for (label, mesh) in [("torus", torus(3, 4)), ("klein", klein_bottle(4, 5))] {
            let (reference, _) = refine(&s, mesh.clone(), steps);
            let topo = Topology::build(&mesh).unwrap();
            for simd in Simd::available() {
                for (threads, stream) in [(1, 0), (2, 0), (1, usize::MAX)] {
                    let mut r = Refiner::<_, f64>::new(&s, &topo, steps, threads).unwrap();
                    r.set_simd(simd);
                    r.set_stream_bytes(stream);
                    let d = same_points(r.refine(&mesh.positions).unwrap(), &reference.positions);
                    assert!(
                        d < 1e-12,
                        "{name} {label} {}, {threads} threads, stream from {stream} bytes: {d:e}",
                        simd.name()
                    );
                }
                // f32 (16 values to a cache line, so the bands' runs split lines elsewhere).
                let d = f32_off(&s, (&mesh, &topo), steps, simd, 2);
                assert!(d < 1e-5, "{name} {label} {} f32: {d:e}", simd.name());
            }
        }
    }
}

/// How far `mesh` refined in f32 (whole lines streamed, on `threads` threads) is from f64 on
/// one thread, point by point, both on the SIMD path `simd`.
fn f32_off(
    s: &GenericSurface,
    (mesh, topo): (&QuadMesh, &Topology),
    steps: usize,
    simd: lsubdiv::mesh::patch::Simd,
    threads: usize,
) -> f64 {
    use lsubdiv::mesh::patch::Refiner;
    let mut double = Refiner::<_, f64>::new(s, topo, steps, 1).unwrap();
    double.set_simd(simd);
    let mut single = Refiner::<_, f32>::new(s, topo, steps, threads).unwrap();
    single.set_simd(simd);
    single.set_stream_bytes(0);
    single
        .refine(&mesh.positions)
        .unwrap()
        .iter()
        .flatten()
        .zip(double.refine(&mesh.positions).unwrap().iter().flatten())
        .fold(0.0f64, |m, (&a, b)| m.max((f64::from(a) - b).abs()))
}

/// A scheme whose axiom refines to one symbol (ω → A, A → AA: uniform binary delayed by a
/// step) makes faces of N' = 1 after its first step, with no interior points: the fast path
/// still gives the reference driver's points, closed and open.
#[test]
fn one_symbol_images_refine_by_the_patches() {
    use lsubdiv::compiler::exact::scheme::parse;
    use lsubdiv::mesh::generators::open_grid;
    use lsubdiv::mesh::patch::subdivide;
    let text = "name = \"delayed\"\ndegree = 3\naxiom = \"S\"\n[rules]\nS = \"A\"\nA = \"AA\"\n";
    let s =
        GenericSurface::new(Scheme::build(parse("delayed.toml", text).unwrap()).unwrap()).unwrap();
    for steps in 1..=3 {
        let mesh = torus(3, 4);
        let (reference, _) = refine(&s, mesh.clone(), steps);
        for threads in [1, 2] {
            let fast = subdivide::<_, f64>(&s, &mesh, steps, threads).unwrap();
            let d = same_points(&fast.positions, &reference.positions);
            assert!(d < 1e-12, "{steps} steps: {d:e}");
        }
        let grid = open_grid(2, 3);
        let fast = subdivide::<_, f64>(&s, &grid, steps, 1).unwrap();
        assert!(fast.positions.iter().flatten().all(|x| x.is_finite()));
        Topology::build(&fast).unwrap();
    }
}

/// Faces whose point N' straddles two of the kernel's 32-value tiles (N' = 19: its values
/// 62..=64; N' = 30: 95..=97), whose inner rows keep both tiles for the column edge: the
/// reference driver's points on every SIMD path, one and two threads. (ω → A^N', A → AA.)
#[test]
fn point_n_across_two_tiles() {
    use lsubdiv::compiler::exact::scheme::parse;
    use lsubdiv::mesh::patch::{Refiner, Simd};
    for k in [19, 30] {
        let text = format!(
            "name = \"wide\"\ndegree = 3\naxiom = \"S\"\n[rules]\nS = \"{}\"\nA = \"AA\"\n",
            "A".repeat(k)
        );
        let s = GenericSurface::new(Scheme::build(parse("wide.toml", &text).unwrap()).unwrap())
            .unwrap();
        for (label, mesh) in [("torus", torus(3, 4)), ("klein", klein_bottle(4, 5))] {
            let (reference, _) = refine(&s, mesh.clone(), 1);
            let topo = Topology::build(&mesh).unwrap();
            for simd in Simd::available() {
                for threads in [1, 2] {
                    let mut r = Refiner::<_, f64>::new(&s, &topo, 1, threads).unwrap();
                    r.set_simd(simd);
                    assert_eq!(r.reference_steps(), 0, "N' = {k}: composed");
                    let d = same_points(r.refine(&mesh.positions).unwrap(), &reference.positions);
                    assert!(d < 1e-12, "N' = {k} {label} {}: {d:e}", simd.name());
                }
            }
        }
    }
}

#[test]
fn every_contained_step_runs_depth_first() {
    use lsubdiv::mesh::patch::Refiner;
    use lsubdiv::mesh::surface::SurfaceScheme;
    for name in generated::SURFACE_NAMES {
        let s = surface(name);
        let contained = s.surface().contained_from;
        for steps in 1..=5 {
            let (t, st) = (Topology::build(&torus(4, 5)), Topology::build(&star()));
            let (t, st) = (t.unwrap(), st.unwrap());
            let torus = Refiner::<_, f64>::new(&s, &t, steps, 1).unwrap();
            assert_eq!(torus.reference_steps(), 0, "{name}, {steps} steps, torus");
            let star = Refiner::<_, f64>::new(&s, &st, steps, 1).unwrap();
            assert_eq!(
                star.reference_steps(),
                contained.min(steps),
                "{name}, {steps} steps, star"
            );
        }
    }
}

#[test]
fn results_beyond_u32_indices_are_refused_not_wrapped() {
    use lsubdiv::mesh::patch::Refiner;
    let s = surface("uniform-binary");
    // 2^17 sub-edges per edge of the cube: 6·2^34 quads, more than u32 can index.
    let topo = Topology::build(&cube()).unwrap();
    let e = Refiner::<_, f32>::new(&s, &topo, 17, 1)
        .err()
        .expect("refused");
    assert!(e.to_string().contains("too large"), "{e}");
}

/// The refiner's buffers stay within what `footprint` counts for them, and a second `refine`
/// holds no more than the first: each buffer of the fans keeps its levels (with an odd number
/// of steps, the level s − 2 buffer once grew to level s − 1 on the next call, 28 MB past the
/// bound on the star with Fibonacci).
#[test]
fn refined_again_the_buffers_stay_within_the_footprint() {
    use lsubdiv::mesh::features::Features;
    use lsubdiv::mesh::patch::{footprint, Refiner};
    use lsubdiv::mesh::surface::SurfaceScheme;
    let plain = |mesh: QuadMesh| (mesh, Features::default());
    // A crease of sharpness s around one face: a reference step below 1 runs twice.
    let creased = |mesh: QuadMesh, s: f64| {
        let f = mesh.faces[0];
        let s = lsubdiv::mesh::features::Sharpness::from_f64(s).unwrap();
        let creases = (0..4).map(|i| ([f[i], f[(i + 1) % 4]], s)).collect();
        let features = Features {
            creases,
            ..Features::default()
        };
        (mesh, features)
    };
    let fractional = |mesh| creased(mesh, 0.5);
    let one_and_a_half = |mesh| creased(mesh, 1.5);
    // Schemes that take two and three reference steps on a mesh with features, each on its
    // level cut open with ghost layers, a fraction blending at the second.
    let delayed = common::DELAYED.map(|text| common::text_surface(text.into()).unwrap().2);
    let open = || split(&capless(&icosphere(3), 0.6));
    let shipped = [
        ("binary-ternary", fractional(split_icosphere(3)), 2),
        ("fibonacci", plain(star()), 7),
        ("fibonacci", plain(cube()), 6),
        ("binary-ternary", plain(star()), 3),
        ("uniform-binary", plain(torus(8, 8)), 3),
        ("uniform-binary", plain(split_icosphere(1)), 1),
        ("uniform-binary", plain(split_icosphere(1)), 2),
        ("uniform-binary", plain(split_icosphere(1)), 4),
        ("fibonacci", plain(split_icosphere(1)), 4),
        // A reference step on the icosphere's every face, and on it open, cut along its
        // boundary with ghost layers (`patch/reference.rs`).
        ("binary-ternary", plain(split_icosphere(3)), 2),
        ("binary-ternary", plain(open()), 2),
    ]
    .map(|(name, mesh, steps)| (name, surface(name), mesh, steps));
    let [once, twice] = delayed;
    let delayed = [
        ("delayed-once", once.clone(), plain(open()), 3),
        ("delayed-once", once, one_and_a_half(open()), 3),
        ("delayed-twice", twice, plain(open()), 4),
    ];
    for (name, s, (mesh, features), steps) in shipped.into_iter().chain(delayed) {
        let topo = Topology::build(&mesh).unwrap();
        let fp = footprint(
            &CurveScheme::tables(&s),
            s.surface().contained_from,
            &topo,
            &features,
            steps,
            8,
            1,
        );
        let mut r = Refiner::<_, f64>::with_features(&s, &topo, &features, steps, 1).unwrap();
        let reference = s.surface().contained_from.min(steps);
        assert!(
            name == "fibonacci" || name == "uniform-binary" || r.reference_steps() == reference,
            "{name}, {steps} steps: {reference} reference steps"
        );
        r.refine(&mesh.positions).unwrap();
        let once = r.buffer_bytes();
        r.refine(&mesh.positions).unwrap();
        let twice = r.buffer_bytes();
        assert_eq!(
            once, twice,
            "{name}, {steps} steps: buffers grew on a second refine"
        );
        // `refining` also counts the output quads (16 bytes each), which `refine` does not make.
        let bound = fp.refining - fp.quads * 16;
        assert!(
            twice as u128 <= bound,
            "{name}, {steps} steps: {twice} bytes held, footprint {bound}"
        );
    }
}

/// Random symmetric surface schemes (`common::surface_systems`): the patch path (composed
/// patches on the torus and the Klein bottle, fans around the cube's EVs, the split
/// icosphere's faces level by level and then in lock-step, their last step composed) gives
/// the reference driver's points on every SIMD path, the same bits on one and two threads,
/// and f32 gives f64's to 1e-5, for as many steps as keep the output small. The composed
/// kernel meets N', band widths and tile layouts no shipped scheme has.
mod random_surfaces {
    use super::*;
    use lsubdiv::mesh::patch::{Refiner, Simd};
    use proptest::prelude::*;

    /// Refined points of a mesh at most (faces × N'²).
    const MAX_POINTS: usize = 20_000;

    proptest! {
        // Each case compiles a scheme exactly (small systems: milliseconds), then refines
        // three meshes.
        #![proptest_config(ProptestConfig { cases: 64, ..ProptestConfig::default() })]

        #[test]
        fn patch_path_matches_the_reference_driver(sys in common::surface_systems()) {
            let Some((text, _, s)) = common::drawn_surface(&sys) else {
                return Ok(());
            };
            for (label, mesh) in [
                ("torus", torus(3, 4)),
                ("klein", klein_bottle(4, 5)),
                ("cube", cube()),
                ("grid cube", grid_cube(3)),
                // Every face at two EVs: level by level, then the fans' lock-step.
                ("icosphere", split_icosphere(1)),
            ] {
                let topo = Topology::build(&mesh).unwrap();
                for steps in 1..=4 {
                    let side = s.tables().image_len(&s.scheme().ls.axiom, steps);
                    if (mesh.faces.len() as u128) * side * side > MAX_POINTS as u128 {
                        break;
                    }
                    let (reference, _) = refine(&s, mesh.clone(), steps);
                    for simd in Simd::available() {
                        // Streamed (whole lines non-temporal) on one thread, plain on two:
                        // the same bits.
                        let mut outputs = Vec::new();
                        for (threads, stream) in [(1, 0), (2, usize::MAX)] {
                            let mut r = Refiner::<_, f64>::new(&s, &topo, steps, threads).unwrap();
                            r.set_simd(simd);
                            r.set_stream_bytes(stream);
                            let out = r.refine(&mesh.positions).unwrap().to_vec();
                            let d = same_points(&out, &reference.positions);
                            prop_assert!(
                                d < 1e-12,
                                "{label}, {steps} steps, {}, {threads} threads: {d:e}\n{text}",
                                simd.name()
                            );
                            outputs.push(out);
                        }
                        prop_assert!(
                            outputs[0] == outputs[1],
                            "{label}, {steps} steps, {}: threads changed bits\n{text}",
                            simd.name()
                        );
                        let d = f32_off(&s, (&mesh, &topo), steps, simd, 1);
                        prop_assert!(d < 1e-5, "{label}, {steps} steps, {} f32: {d:e}\n{text}", simd.name());
                    }
                }
            }
            // A scheme whose first steps the reference driver takes runs the last of them only
            // near the EVs where faces are far from them (`patch/near.rs`), as on the 16 × 16-grid
            // cube.
            let mesh = grid_cube(16);
            let topo = Topology::build(&mesh).unwrap();
            let steps = Refiner::<_, f64>::new(&s, &topo, 4, 1).unwrap().reference_steps();
            let side = s.tables().image_len(&s.scheme().ls.axiom, steps);
            if steps > 0 && (mesh.faces.len() as u128) * side * side <= 4 * MAX_POINTS as u128 {
                let mut r = Refiner::<_, f64>::new(&s, &topo, steps, 1).unwrap();
                let d = same_points(r.refine(&mesh.positions).unwrap(), &refine(&s, mesh.clone(), steps).0.positions);
                prop_assert!(d < 1e-12, "grid cube 16, {steps} reference steps, {} faces by the reference: {d:e}\n{text}", r.reference_faces());
            }
        }
    }
}
