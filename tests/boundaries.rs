//! Open meshes (issue 15): a boundary is a line of odd symmetry, so an open regular grid
//! refined by any scheme with interpolated corners (edge-and-corner) is exactly the tensor
//! product of the 1D refinements of its rows and columns with interpolated ends
//! (`runtime::ends`), and a tube's boundary loops are the closed-curve refinement of the
//! boundary polygons.

use lsubdiv::compiler::exact::symmetry::rule_mirror;
use lsubdiv::compiler::exact::Scheme;
use lsubdiv::generic::{GenericScheme, GenericSurface};
use lsubdiv::runtime::mesh::QuadMesh;
use lsubdiv::runtime::patch::Refiner;
use lsubdiv::runtime::topology::Topology;
use lsubdiv::{refine_ends, CurveScheme, EndCurve};
use lsubdiv_cli::resolve;

/// The shipped schemes that refine surfaces (every one symmetric).
const SCHEMES: [&str; 7] = [
    "uniform-binary",
    "fibonacci",
    "fibonacci-alt",
    "binary-ternary",
    "found-cubic",
    "low-ratio",
    "remark-5-3",
];

fn surface(name: &str) -> GenericSurface {
    let r = resolve(name).expect("shipped scheme");
    GenericSurface::new(Scheme::build(r.ls).expect("compiles")).expect("a surface scheme")
}

fn curve(name: &str) -> (GenericScheme, Vec<u8>) {
    let r = resolve(name).expect("shipped scheme");
    let sigma = rule_mirror(&r.ls).expect("symmetric");
    (
        GenericScheme::new(Scheme::build(r.ls).expect("compiles")).expect("tabulates"),
        sigma,
    )
}

/// An open grid of rows × cols quads, bumped out of its plane so that no two points agree:
/// vertex i·(cols + 1) + j at (j, i, z(i, j)); face (i, j) has corner 0 at vertex (i, j) and
/// edge 0 along j.
fn grid(rows: usize, cols: usize) -> QuadMesh {
    let id = |i: usize, j: usize| (i * (cols + 1) + j) as u32;
    let positions = (0..=rows)
        .flat_map(|i| {
            (0..=cols).map(move |j| {
                let (x, y) = (j as f64, i as f64);
                [
                    x + 0.1 * y * y,
                    y - 0.05 * x,
                    (0.7 * x).sin() + 0.3 * (1.3 * y).cos(),
                ]
            })
        })
        .collect();
    let faces = (0..rows)
        .flat_map(|i| {
            (0..cols).map(move |j| [id(i, j), id(i, j + 1), id(i + 1, j + 1), id(i + 1, j)])
        })
        .collect();
    QuadMesh { positions, faces }
}

/// The refined grid by its global grid coordinates (I, J), from the refiner's faces: base face
/// (i, j) becomes N × N quads, row y, column x, corner 0 at (i·N + y, j·N + x).
fn by_grid(
    cols: usize,
    n: usize,
    faces: &[[u32; 4]],
) -> std::collections::HashMap<(usize, usize), u32> {
    let mut at = std::collections::HashMap::new();
    for (q, quad) in faces.iter().enumerate() {
        let (f, r) = (q / (n * n), q % (n * n));
        let (i, j) = (f / cols, f % cols);
        let (y, x) = (r / n, r % n);
        let (gi, gj) = (i * n + y, j * n + x);
        for (c, (di, dj)) in [(0, 0), (0, 1), (1, 1), (1, 0)].into_iter().enumerate() {
            let old = at.insert((gi + di, gj + dj), quad[c]);
            assert!(
                old.is_none() || old == Some(quad[c]),
                "one vertex per grid point"
            );
        }
    }
    at
}

/// Rows, then columns, refined as open curves with interpolated ends.
fn tensor(
    s: &mut GenericScheme,
    sigma: &[u8],
    p: &[Vec<[f64; 3]>],
    steps: usize,
) -> Vec<Vec<[f64; 3]>> {
    let mut one = |points: Vec<[f64; 3]>| {
        let c = EndCurve::with_axiom(&s.tables(), points);
        s.prepare(&c.extended(&s.tables(), sigma).unwrap()).unwrap();
        refine_ends(s, sigma, &c, steps).unwrap().points
    };
    let rows: Vec<Vec<[f64; 3]>> = p.iter().map(|r| one(r.clone())).collect();
    let cols: Vec<Vec<[f64; 3]>> = (0..rows[0].len())
        .map(|j| one(rows.iter().map(|r| r[j]).collect()))
        .collect();
    (0..cols[0].len())
        .map(|i| cols.iter().map(|c| c[i]).collect())
        .collect()
}

#[test]
fn an_open_grid_is_the_tensor_product_of_its_rows_and_columns() {
    let (rows, cols) = (3, 4);
    let mesh = grid(rows, cols);
    let topo = Topology::build(&mesh).unwrap();
    let p: Vec<Vec<[f64; 3]>> = (0..=rows)
        .map(|i| {
            (0..=cols)
                .map(|j| mesh.positions[i * (cols + 1) + j])
                .collect()
        })
        .collect();
    for name in SCHEMES {
        let s = surface(name);
        let (mut c, sigma) = curve(name);
        for steps in 1..=3 {
            let mut r = Refiner::<_, f64>::new(&s, &topo, steps, 2)
                .unwrap_or_else(|e| panic!("{name}: {e}"));
            let out = r.refine(&mesh.positions).unwrap().to_vec();
            let faces = r.faces();
            let n = s.tables().image_len(s.tables().axiom, steps) as usize;
            let at = by_grid(cols, n, &faces);
            let want = tensor(&mut c, &sigma, &p, steps);
            assert_eq!(want.len(), rows * n + 1);
            assert_eq!(
                at.len(),
                out.len(),
                "{name}: every output vertex on the grid"
            );
            let mut worst = 0.0f64;
            for (&(i, j), &v) in &at {
                for k in 0..3 {
                    worst = worst.max((out[v as usize][k] - want[i][j][k]).abs());
                }
            }
            assert!(worst < 1e-12, "{name} steps={steps}: off by {worst:e}");
        }
    }
}
