//! Render time of thin meshes against normal ones of the same size, measured in the same run:
//! two tori of 16 384 quads each, one of 128 × 128 quads and two of very long, narrow quads
//! (4 × 4096 and 4096 × 4: each quad a quarter of one circle long and 1/4096 of the other
//! wide), drawn at 800 × 600 (3 × 3 samples per pixel) in the default view. Prints the median
//! of 5 draws each and the thin/normal ratios.
//!
//! `cargo bench --bench render` (set LSUBDIV_BENCH_QUICK=1 for one draw each).

use lsubdiv::mesh::generators::torus;
use lsubdiv::mesh::topology::Topology;
use lsubdiv_cli::render::{camera::View, Options, Scene, Shading};
use std::time::Instant;

/// Median seconds of `runs` draws of a `rows` × `cols` torus (the scene is built once).
fn draw(rows: usize, cols: usize, runs: usize) -> f64 {
    let mesh = torus(rows, cols);
    let topology = Topology::build(&mesh).expect("a torus is a closed manifold");
    let scene = Scene::new(&mesh, &topology, None).expect("the torus has an extent");
    let opts = Options {
        width: 800,
        height: 600,
        view: View::default(),
        shading: Shading::Smooth,
        wireframe: false,
        curvature_range: None,
    };
    let mut times: Vec<f64> = (0..runs)
        .map(|_| {
            let start = Instant::now();
            std::hint::black_box(scene.render(&opts).expect("draws"));
            start.elapsed().as_secs_f64()
        })
        .collect();
    times.sort_by(f64::total_cmp);
    times[times.len() / 2]
}

fn main() {
    let runs = if std::env::var_os("LSUBDIV_BENCH_QUICK").is_some() {
        1
    } else {
        5
    };
    let normal = draw(128, 128, runs);
    println!("| torus (16 384 quads) | render 800x600 (ms) | thin / normal |");
    println!("|---|---|---|");
    println!("| 128 × 128 (normal) | {:.1} | 1 |", normal * 1e3);
    for (rows, cols) in [(4, 4096), (4096, 4)] {
        let t = draw(rows, cols, runs);
        println!(
            "| {rows} × {cols} (thin) | {:.1} | {:.2} |",
            t * 1e3,
            t / normal
        );
    }
}
