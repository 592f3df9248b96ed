//! A plan reused frame after frame (`lsubdiv::Plan::frames`) against a plan built for each
//! frame, through the front door, on a quad torus and on a triangle model: per frame, the
//! refinement alone, the limit, and a single shot (plan built, then refined), alternated in
//! one run, medians, with the ratios printed; on one thread and on two. `cargo bench --bench
//! frames`.

use lsubdiv::{Mesh, Refiner, Scheme};
use std::time::Instant;

/// Median seconds of `runs` calls of `f`.
fn median(runs: usize, mut f: impl FnMut()) -> f64 {
    let mut t: Vec<f64> = (0..runs)
        .map(|_| {
            let start = Instant::now();
            f();
            start.elapsed().as_secs_f64()
        })
        .collect();
    t.sort_by(f64::total_cmp);
    t[runs / 2]
}

fn main() {
    let scheme = Scheme::shipped("uniform-binary").expect("shipped");
    let torus = lsubdiv::mesh::generators::torus(128, 128);
    let torus_obj = lsubdiv::obj::format(&torus).expect("finite");
    let mut cases = vec![(
        "torus 128 × 128, 3 steps".to_string(),
        Mesh::parse("torus.obj", torus_obj.into_bytes()).expect("torus"),
        3,
    )];
    let model = std::path::Path::new("../shared/models/armadillo.obj");
    match Mesh::read(model) {
        Ok(mesh) => cases.push(("armadillo (triangles), 2 steps".into(), mesh, 2)),
        Err(_) => println!("note: {} absent, triangle case skipped", model.display()),
    }
    println!("| mesh | threads | refine / frame (ms) | limit / frame (ms) | single shot (ms) | single shot ÷ frame | limit ÷ refine |");
    println!("|---|---:|---:|---:|---:|---:|---:|");
    for ((what, mesh, steps), threads) in cases.iter().flat_map(|c| [(c, 1), (c, 2)]) {
        let build = |limit: bool| {
            Refiner::new(&scheme, mesh)
                .steps(*steps)
                .threads(threads)
                .uv(false)
                .limit(limit)
                .build()
                .expect("plan")
        };
        let (plain, on_limit) = (build(false), build(true));
        let mut frames = plain.frames().expect("frames");
        let mut limit_frames = on_limit.frames().expect("frames");
        let moved: Vec<[f64; 3]> = mesh
            .positions()
            .iter()
            .map(|p| p.map(|x| 1.01 * x))
            .collect();
        let (mut refine, mut limit, mut single) = (Vec::new(), Vec::new(), Vec::new());
        for _ in 0..5 {
            refine.push(median(5, || {
                frames.refine(&moved).expect("frame");
            }));
            limit.push(median(5, || {
                limit_frames.refine(&moved).expect("frame");
            }));
            single.push(median(5, || {
                build(false).refine().expect("single shot");
            }));
        }
        let mid = |v: &mut Vec<f64>| {
            v.sort_by(f64::total_cmp);
            v[v.len() / 2] * 1e3
        };
        let (r, l, s) = (mid(&mut refine), mid(&mut limit), mid(&mut single));
        println!(
            "| {what} | {threads} | {r:.1} | {l:.1} | {s:.1} | {:.2} | {:.2} |",
            s / r,
            l / r
        );
    }
}
