//! The picture commands as a user runs them (`plot`, `graph --svg`, `ev --characteristic-map`):
//! each writes a non-empty, decodable image of the requested size whose content matches the
//! scheme; bad arguments exit 2. And the characteristic map's numbers against closed forms.

mod common;

use common::cli::lsubdiv;
use lsubdiv::compiler::exact::Scheme;
use lsubdiv::generic::{GenericScheme, GenericSurface};
use lsubdiv::{Curve, CurveScheme};
use resvg::usvg;
use std::collections::BTreeSet;
use std::path::Path;
use std::process::Output;

fn ok(o: &Output) {
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
}

fn scheme(name: &str) -> Scheme {
    Scheme::build(lsubdiv_cli::resolve(name).unwrap().ls).unwrap()
}

/// Parses SVG text the way the PNG writer does and returns its size.
fn svg_size(text: &str) -> (f32, f32) {
    let tree = usvg::Tree::from_str(text, &usvg::Options::default()).expect("valid SVG");
    (tree.size().width(), tree.size().height())
}

/// Decodes a PNG: (width, height, pixels that are not white).
fn png_info(path: &Path) -> (u32, u32, usize) {
    let bytes = std::fs::read(path).unwrap();
    let decoder = png::Decoder::new(std::io::Cursor::new(bytes));
    let mut reader = decoder.read_info().expect("a PNG");
    let mut buf = vec![0; reader.output_buffer_size()];
    let info = reader.next_frame(&mut buf).expect("decodes");
    let channels = info.color_type.samples();
    let inked = buf[..info.buffer_size()]
        .chunks(channels)
        .filter(|px| px.iter().take(3).any(|&c| c < 200))
        .count();
    (info.width, info.height, inked)
}

/// The values of attribute `attr` of the elements with class `class`, in document order.
fn attrs(svg: &str, class: &str, attr: &str) -> Vec<String> {
    svg.lines()
        .filter(|l| l.contains(&format!("class=\"{class}\"")))
        .map(|l| {
            let start = l.find(&format!(" {attr}=\"")).expect("attribute") + attr.len() + 3;
            l[start..start + l[start..].find('"').unwrap()].to_string()
        })
        .collect()
}

#[test]
fn plot_draws_each_step_the_legend_and_the_limit_curve_by_interval() {
    let dir = tempfile::tempdir().unwrap();
    let svg = dir.path().join("plot.svg");
    let svg_s = svg.to_str().unwrap();
    ok(&lsubdiv(&[
        "plot",
        "fibonacci-curve",
        "--steps",
        "3",
        "-o",
        svg_s,
        "--size",
        "640x480",
    ]));
    let text = std::fs::read_to_string(&svg).unwrap();
    assert_eq!(svg_size(&text), (640.0, 480.0));
    assert_eq!(
        attrs(&text, "step", "points").len(),
        4,
        "one polygon per step 0..=3"
    );
    assert_eq!(attrs(&text, "legend-symbol", "stroke").len(), 2, "L and S");
    assert!(text.contains("L: length (1 + √5)/2") && text.contains("S: length 1"));
    // The limit curve's pieces follow the intervals of step 3: the closed hexagon's labels
    // L⁶ become (π³(L))⁶ = (SLLSL)⁶; colours name the symbols (L red, S blue).
    let colours = attrs(&text, "limit", "stroke");
    let word: String = colours
        .iter()
        .map(|c| match c.as_str() {
            "#d62728" => 'L',
            "#1f77b4" => 'S',
            other => panic!("unexpected colour {other}"),
        })
        .collect();
    assert_eq!(word.len(), 30, "{word}");
    let expected = "SLLSL".repeat(6);
    assert!(
        (0..30).any(|r| expected[r..].to_string() + &expected[..r] == word),
        "{word} is not a rotation of {expected}"
    );
    // The same as PNG, from an open polygon in a file.
    let pts = dir.path().join("open.txt");
    std::fs::write(&pts, "0 0\n1 2\n2 0\n3 2\n4 0\n5 1\n").unwrap();
    let png = dir.path().join("plot.png");
    ok(&lsubdiv(&[
        "plot",
        "fibonacci",
        "--steps",
        "2",
        pts.to_str().unwrap(),
        "-o",
        png.to_str().unwrap(),
        "--size",
        "500x400",
    ]));
    let (w, h, inked) = png_info(&png);
    assert_eq!((w, h), (500, 400));
    assert!(inked > 5_000, "{inked} inked pixels");
}

#[test]
fn limit_curve_pieces_meet_at_the_knots() {
    // Degree 2: at the knot between intervals k+1 and k+2 only points k and k+1 act, and the
    // curve is (h_{k+2} P_k + h_{k+1} P_{k+1}) / (h_{k+1} + h_{k+2}), h the interval lengths.
    let s = scheme("fibonacci-curve");
    let h: Vec<f64> = s.lengths.iter().map(|e| e.to_f64()).collect();
    let mut g = GenericScheme::new(s).unwrap();
    let curve = Curve::with_axiom(&g.tables(), lsubdiv_cli::plot::hexagon(), true);
    g.prepare(&curve).unwrap();
    let last = lsubdiv::refine(&g, &curve, 3).unwrap();
    let (p, l, m) = (&last.points, &last.labels, last.points.len());
    let knots: Vec<[f64; 2]> = (0..m)
        .map(|k| {
            let (a, b) = (h[l[(k + 1) % m] as usize], h[l[(k + 2) % m] as usize]);
            let (p0, p1) = (p[k], p[(k + 1) % m]);
            [
                (b * p0[0] + a * p1[0]) / (a + b),
                (b * p0[1] + a * p1[1]) / (a + b),
            ]
        })
        .collect();
    let pieces = lsubdiv_cli::plot::limit(&mut g, &last, 1e-3, u128::MAX).unwrap();
    assert_eq!(pieces.len(), m);
    for (i, piece) in pieces.iter().enumerate() {
        // The unrolled polygon's domain starts at interval d = 2: piece i is interval i + 2,
        // which ends at the knot after point i + 1.
        assert_eq!(piece.symbol, l[(i + 2) % m], "piece {i}");
        let end = *piece.points.last().unwrap();
        let knot = knots[(i + 1) % m];
        let miss = (end[0] - knot[0]).hypot(end[1] - knot[1]);
        if i + 1 < pieces.len() {
            assert!(miss < 3e-3, "piece {i} ends {miss} away from its knot");
        }
    }
}

#[test]
fn graph_svg_has_a_node_per_word_and_an_arrow_per_transition() {
    let s = scheme("binary-ternary");
    let o = lsubdiv(&["graph", "binary-ternary", "--svg", "--size", "700x500"]);
    ok(&o);
    let text = String::from_utf8(o.stdout).unwrap();
    assert_eq!(svg_size(&text), (700.0, 500.0));
    let nodes = text.matches("class=\"node").count();
    let transitional = text.matches("class=\"node transitional\"").count();
    assert_eq!(nodes, s.graph.words.len());
    assert_eq!(
        transitional,
        s.graph.words.iter().filter(|w| w.transitional).count()
    );
    let drawn: Vec<(usize, usize)> = text
        .split("class=\"edge e")
        .skip(1)
        .map(|t| {
            let id = &t[..t.find('"').unwrap()];
            let (a, b) = id.split_once('-').unwrap();
            (a.parse().unwrap(), b.parse().unwrap())
        })
        .collect();
    let expected: BTreeSet<(usize, usize)> = s
        .graph
        .edges
        .iter()
        .enumerate()
        .flat_map(|(i, succ)| succ.iter().map(move |&j| (i, j)))
        .collect();
    assert_eq!(drawn.len(), expected.len(), "one arrow per transition");
    assert_eq!(drawn.into_iter().collect::<BTreeSet<_>>(), expected);
    // Files: PNG by extension, DOT as on standard output.
    let dir = tempfile::tempdir().unwrap();
    let png = dir.path().join("g.png");
    ok(&lsubdiv(&[
        "graph",
        "fibonacci",
        "--svg",
        "-o",
        png.to_str().unwrap(),
        "--size",
        "600x700",
    ]));
    let (w, h, inked) = png_info(&png);
    assert_eq!((w, h), (600, 700));
    assert!(inked > 5_000, "{inked} inked pixels");
    let dot = dir.path().join("g.dot");
    ok(&lsubdiv(&[
        "graph",
        "binary-ternary",
        "--dot",
        "-o",
        dot.to_str().unwrap(),
    ]));
    let stdout = lsubdiv(&["graph", "binary-ternary", "--dot"]).stdout;
    assert_eq!(std::fs::read(&dot).unwrap(), stdout);
}

#[test]
fn characteristic_map_is_the_closed_form_eigenvector_and_regular() {
    let s = scheme("binary-ternary");
    let surface = GenericSurface::new(s).unwrap();
    let c = surface.analysis().coefficients_f64();
    let n = 5;
    let map = lsubdiv_cli::charmap::characteristic_map(&surface, n, 1, &|_| {}).unwrap();
    let lambda = c.spectrum(n).unwrap().lambda1;
    assert!(
        (map.lambda - lambda).abs() < 1e-12,
        "{} vs {lambda}",
        map.lambda
    );
    // Rotational symmetry: R_m = e^{±2πim/n}, D_m halfway between R_m and R_{m+1}, and the
    // ratio |D|/|R| of the 2×2 Fourier block's eigenvector: from its first row,
    // (a − λ) x_R + A3 (1 + e^{−iθ}) x_D = 0, a = R→r + 2 (R±1→r) cos θ.
    let theta = std::f64::consts::TAU / n as f64;
    let a = c.radial_to_radial + 2.0 * c.side_to_radial * theta.cos();
    let ratio = (lambda - a) / (c.diagonal_to_radial * 2.0 * (theta / 2.0).cos());
    let turn = map.net[1][1][0][1].atan2(map.net[1][1][0][0]).signum();
    for (m, sector) in map.net.iter().enumerate() {
        let (r, d) = (sector[1][0], sector[1][1]);
        let at = |t: f64| [t.cos(), t.sin()];
        let expect_r = at(turn * theta * m as f64);
        let expect_d = at(turn * theta * (m as f64 + 0.5));
        assert!(
            (r[0] - expect_r[0]).hypot(r[1] - expect_r[1]) < 1e-9,
            "R_{m} = {r:?}"
        );
        assert!(
            (d[0] - ratio * expect_d[0]).hypot(d[1] - ratio * expect_d[1]) < 1e-9,
            "D_{m} = {d:?}, expected {ratio} × {expect_d:?}"
        );
        assert!(sector[0][0] == [0.0, 0.0] || sector[0][0][0].hypot(sector[0][0][1]) < 1e-12);
    }
    // Regular and injective: every quad of the net and of its refinement turns the same way.
    let area = |q: [[f64; 2]; 4]| {
        (0..4)
            .map(|e| q[e][0] * q[(e + 1) % 4][1] - q[(e + 1) % 4][0] * q[e][1])
            .sum::<f64>()
    };
    let mut net = Vec::new();
    for g in &map.net {
        for i in 0..map.k {
            for j in 0..map.k {
                net.push([g[i][j], g[i + 1][j], g[i + 1][j + 1], g[i][j + 1]]);
            }
        }
    }
    assert!(map.refined.len() > net.len());
    for quads in [&net, &map.refined] {
        let signs: BTreeSet<i8> = quads.iter().map(|&q| area(q).signum() as i8).collect();
        assert_eq!(signs.len(), 1, "quads of both orientations");
    }
    let quads: Vec<[[f64; 2]; 4]> = net.iter().chain(&map.refined).copied().collect();
    let smallest = quads
        .iter()
        .map(|&q| area(q).abs())
        .fold(f64::INFINITY, f64::min);
    assert!(smallest > 1e-6, "degenerate quad, area {smallest}");
}

#[test]
fn characteristic_map_command_writes_the_picture() {
    let dir = tempfile::tempdir().unwrap();
    let png = dir.path().join("map.png");
    let png_s = png.to_str().unwrap();
    let o = lsubdiv(&[
        "ev",
        "binary-ternary",
        "--valence",
        "3",
        "--characteristic-map",
        "-o",
        png_s,
        "--size",
        "320x300",
    ]);
    ok(&o);
    assert!(String::from_utf8_lossy(&o.stdout).contains("lambda1 = 0.32310664019"));
    let (w, h, inked) = png_info(&png);
    assert_eq!((w, h), (320, 300));
    assert!(inked > 3_000, "{inked} inked pixels");
}

#[test]
fn bad_picture_arguments_exit_2_with_a_message() {
    let dir = tempfile::tempdir().unwrap();
    let out = |name: &str| dir.path().join(name).display().to_string();
    let pts = dir.path().join("p3.txt");
    std::fs::write(&pts, "0 0 0\n1 0 0\n1 1 0\n").unwrap();
    let cases: Vec<(Vec<String>, &str)> = vec![
        (
            vec!["plot".into(), "fibonacci".into(), "-o".into(), out("a.jpg")],
            ".svg or .png",
        ),
        (
            vec![
                "ev".into(),
                "binary-ternary".into(),
                "--valence".into(),
                "200".into(),
                "--characteristic-map".into(),
                "-o".into(),
                out("a.svg"),
            ],
            "valences 3 to 100",
        ),
        (
            vec![
                "plot".into(),
                "fibonacci".into(),
                "-o".into(),
                out("a.svg"),
                "--size".into(),
                "10x".into(),
            ],
            "--size",
        ),
        (
            vec![
                "plot".into(),
                "fibonacci".into(),
                pts.display().to_string(),
                "-o".into(),
                out("a.svg"),
            ],
            "2 coordinates",
        ),
        (
            vec![
                "plot".into(),
                "fibonacci".into(),
                "--labels".into(),
                "XYZ".into(),
                "-o".into(),
                out("a.svg"),
            ],
            "--labels",
        ),
        (
            vec![
                "graph".into(),
                "fibonacci".into(),
                "--svg".into(),
                "-o".into(),
                out("g.gif"),
            ],
            ".svg or .png",
        ),
        (
            vec![
                "ev".into(),
                "binary-ternary".into(),
                "--valence".into(),
                "3..5".into(),
                "--characteristic-map".into(),
                "-o".into(),
                out("m.svg"),
            ],
            "one valence",
        ),
        (
            vec![
                "ev".into(),
                "fibonacci-curve".into(),
                "--valence".into(),
                "3".into(),
                "--characteristic-map".into(),
                "-o".into(),
                out("m.svg"),
            ],
            "degree 3",
        ),
        (
            vec![
                "ev".into(),
                "binary-ternary".into(),
                "-o".into(),
                out("m.svg"),
            ],
            "characteristic-map",
        ),
    ];
    for (args, needle) in cases {
        let args: Vec<&str> = args.iter().map(String::as_str).collect();
        let o = lsubdiv(&args);
        let err = String::from_utf8_lossy(&o.stderr);
        assert_eq!(o.status.code(), Some(2), "{args:?}: {err}");
        assert!(err.contains(needle), "{args:?}: {err}");
    }
    assert_eq!(
        std::fs::read_dir(dir.path()).unwrap().count(),
        1,
        "nothing written"
    );
}
