//! lsubdiv side of the peer comparison (see bench/peers/README.md).
//!
//! Subcommands (all driven by bench/peers/run.sh):
//! - `meshes --dir D [--target N]`: writes torus.obj (torus:256:256), cube.obj, star.obj,
//!   grid.obj (open 8 × 8) and icosphere.obj (icosphere:4 split into quads: every face at two
//!   EVs) with `lsubdiv::bench::mesh` + `obj::format`, and creased.obj (the
//!   torus with OpenSubdiv's crease tags: `crease_tags`), and prints `MESH name path levels out_vertices` with the
//!   level count `lsubdiv bench` would use for N output vertices (default 4,200,000).
//! - `bench --obj P --name N --levels L [--runs R] [--dump F]`: times lsubdiv exactly as
//!   `lsubdiv bench` does (`lsubdiv::bench::measure`: uniform-binary, generated path, f64,
//!   1 thread, one warm-up then the median of R refinements, buffers reused); prints a RESULT
//!   line. With `--dump`, also writes the refined positions and faces (untimed).
//! - `compare --a F --b F [--tol T] [--label X]`: largest coordinate difference between two dumps,
//!   vertices matched by position (sort by x, nearest neighbour within T, default 1e-9), plus a
//!   check that the matching is one-to-one and that the face sets agree under it.
//! - `table --results F`: the markdown table of a results file (RESULT / FAILED lines).

#[path = "common.rs"]
mod common;

use common::{read_dump, report, write_dump, Args, Obj};
use lsubdiv::obj;
use lsubdiv::mesh::features::Features;
use lsubdiv::mesh::QuadMesh;
use lsubdiv::mesh::patch::{output_counts, Refiner};
use lsubdiv::mesh::surface::{SurfaceScheme, SurfaceVisitor};
use lsubdiv::mesh::topology::Topology;
use lsubdiv_cli::bench;
use lsubdiv_cli::implementation::Implementation;
use std::collections::{BTreeMap, HashSet};

const SCHEME: &str = "uniform-binary";

fn main() {
    common::run(main_inner);
}

fn main_inner(args: &[String]) -> Result<(), String> {
    let Some((cmd, rest)) = args.split_first() else {
        return Err("usage: lsubdiv-peers meshes|bench|compare|table --key value …".into());
    };
    let a = Args::parse(rest)?;
    match cmd.as_str() {
        "meshes" => meshes(&a),
        "bench" => bench_cmd(&a),
        "compare" => compare(&a),
        "table" => table(&a),
        other => Err(format!("unknown subcommand `{other}`")),
    }
}

fn meshes(a: &Args) -> Result<(), String> {
    let dir = a.req("dir")?;
    let target = a.usize("target", 4_200_000)?;
    std::fs::create_dir_all(dir).map_err(|e| format!("{dir}: {e}"))?;
    let surface = bench::surface(SCHEME)?;
    for (name, spec) in [
        ("torus", "torus:256:256"),
        ("cube", "cube"),
        ("star", "star"),
        ("grid", "grid"),
        ("creased", "torus:256:256"),
        ("icosphere", "icosphere:4"),
    ] {
        let checked = bench::mesh(spec, u64::MAX, None).map_err(|e| e.to_string())?;
        let mesh = &checked.mesh;
        let path = format!("{dir}/{name}.obj");
        let mut text = obj::format(mesh).map_err(|e| e.to_string())?;
        if name == "creased" {
            text.push_str(&crease_tags(256, 256));
        }
        std::fs::write(&path, text).map_err(|e| format!("{path}: {e}"))?;
        let levels = bench::steps_for(&surface, &checked.topology, target);
        let t = &checked.topology;
        let count = |k: usize| k as u128;
        let (vertices, _) = output_counts(
            count(t.vertex_count()),
            count(t.edge_count()),
            count(t.face_count()),
            1 << levels,
        );
        println!("MESH {name} {path} {levels} {vertices}");
    }
    Ok(())
}

/// OpenSubdiv's crease tags (`t crease 2/1/0 a b s`, vertices from 0) for crease loops on the
/// `rows` × `cols` torus (`runtime::generators::torus`, vertex i·cols + j): an infinitely sharp
/// loop around row 0 and a loop of sharpness 2 (sharp for two steps) along each of the
/// columns 0, 64, 128 and 192, so that the mesh has infinitely sharp crease vertices,
/// semi-sharp ones, and crossings of four sharp edges (corners for two steps).
fn crease_tags(rows: usize, cols: usize) -> String {
    let id = |i: usize, j: usize| (i % rows) * cols + j % cols;
    let mut t = String::new();
    for j in 0..cols {
        t += &format!("t crease 2/1/0 {} {} 10\n", id(0, j), id(0, j + 1));
    }
    for j in (0..cols).step_by(cols / 4) {
        for i in 0..rows {
            t += &format!("t crease 2/1/0 {} {} 2\n", id(i, j), id(i + 1, j));
        }
    }
    t
}

/// Refines once with the same Refiner (f64, 1 thread) and returns positions and faces.
struct Dump<'m> {
    mesh: &'m QuadMesh,
    topology: &'m Topology,
    features: &'m Features,
    steps: usize,
}

impl SurfaceVisitor for Dump<'_> {
    type Output = Result<(Vec<[f64; 3]>, Vec<[u32; 4]>), String>;
    fn visit<S: SurfaceScheme + Sync>(self, scheme: &S) -> Self::Output {
        let mut r =
            Refiner::<S, f64>::with_features(scheme, self.topology, self.features, self.steps, 1)
            .map_err(|e| e.to_string())?;
        let p = r
            .refine(&self.mesh.positions)
            .map_err(|e| e.to_string())?
            .to_vec();
        Ok((p, r.faces()))
    }
}

fn bench_cmd(a: &Args) -> Result<(), String> {
    let common::Run {
        obj,
        name,
        levels,
        runs,
    } = a.run()?;
    let checked = bench::mesh(obj, u64::MAX, None).map_err(|e| e.to_string())?;
    let (mesh, topology) = (&checked.mesh, &checked.topology);
    let surface = bench::surface(SCHEME)?;
    if a.get("dump").is_none() || runs > 0 {
        let m = bench::measure::<f64>(
            SCHEME,
            &surface,
            &checked,
            Implementation::Generated,
            bench::Run {
                threads: 1,
                steps: levels,
                runs,
                simd: lsubdiv::mesh::patch::Simd::detect(),
            },
        )?;
        report("lsubdiv", name, levels, m.output_vertices, m.median_seconds);
    }
    if let Some(path) = a.get("dump") {
        let dump = Dump {
            mesh,
            topology,
            features: &checked.features,
            steps: levels,
        };
        let (p, f) = lsubdiv::generated::visit_surface(SCHEME, dump)
            .ok_or_else(|| format!("`{SCHEME}` has no generated surface code"))??;
        write_dump(path, &p, &f)?;
    }
    Ok(())
}

/// For every point of `a`, the nearest point of `b` (max-norm) among those whose x is within
/// `tol`: (index in b or None, distance).
fn match_points(a: &[[f64; 3]], b: &[[f64; 3]], tol: f64) -> Vec<(Option<usize>, f64)> {
    let mut order: Vec<usize> = (0..b.len()).collect();
    order.sort_by(|&i, &j| {
        b[i][0]
            .total_cmp(&b[j][0])
            .then(b[i][1].total_cmp(&b[j][1]))
            .then(b[i][2].total_cmp(&b[j][2]))
    });
    let xs: Vec<f64> = order.iter().map(|&i| b[i][0]).collect();
    a.iter()
        .map(|p| {
            let lo = xs.partition_point(|&x| x < p[0] - tol);
            let mut best = (None, f64::INFINITY);
            for k in lo..xs.len() {
                if xs[k] > p[0] + tol {
                    break;
                }
                let q = &b[order[k]];
                let d = (0..3).map(|c| (p[c] - q[c]).abs()).fold(0.0, f64::max);
                if d < best.1 {
                    best = (Some(order[k]), d);
                }
            }
            if best.1 > tol {
                (None, best.1)
            } else {
                best
            }
        })
        .collect()
}

/// A quad up to rotation (orientation kept): the rotation starting at its smallest index.
fn canonical(f: [u32; 4]) -> [u32; 4] {
    let k = (0..4).min_by_key(|&k| f[k]).unwrap();
    std::array::from_fn(|i| f[(k + i) % 4])
}

fn compare(a: &Args) -> Result<(), String> {
    let label = a.get("label").unwrap_or("compare");
    let tol = a.f64("tol", 1e-9)?;
    let (x, y): (Obj, Obj) = (read_dump(a.req("a")?)?, read_dump(a.req("b")?)?);
    if x.positions.len() != y.positions.len() {
        println!(
            "ACCURACY label={label} vertices_differ a={} b={}",
            x.positions.len(),
            y.positions.len()
        );
        return Ok(());
    }
    let m = match_points(&x.positions, &y.positions, tol);
    let unmatched = m.iter().filter(|(j, _)| j.is_none()).count();
    let max_diff = m
        .iter()
        .filter(|(j, _)| j.is_some())
        .map(|&(_, d)| d)
        .fold(0.0, f64::max);
    let mut used = vec![false; y.positions.len()];
    let mut duplicates = 0;
    for &(j, _) in &m {
        if let Some(j) = j {
            if std::mem::replace(&mut used[j], true) {
                duplicates += 1;
            }
        }
    }
    let faces = if unmatched > 0 || duplicates > 0 {
        "unchecked".to_string()
    } else if x.faces.len() != y.faces.len() {
        format!("count-differs({}/{})", x.faces.len(), y.faces.len())
    } else {
        let set: HashSet<[u32; 4]> = y.faces.iter().map(|&f| canonical(f)).collect();
        let mapped = |f: &[u32; 4]| f.map(|i| m[i as usize].0.unwrap() as u32);
        let same = x.faces.iter().all(|f| set.contains(&canonical(mapped(f))));
        let flipped = x.faces.iter().all(|f| {
            let [p, q, r, s] = mapped(f);
            set.contains(&canonical([s, r, q, p]))
        });
        match (same, flipped) {
            (true, _) => "identical".to_string(),
            (false, true) => "identical-up-to-orientation".to_string(),
            _ => "differ".to_string(),
        }
    };
    println!(
        "ACCURACY label={label} vertices={} tol={tol:e} max_abs_diff={max_diff:.3e} \
         unmatched={unmatched} duplicates={duplicates} faces={faces}",
        x.positions.len()
    );
    Ok(())
}

#[derive(Default)]
struct Row {
    levels: String,
    out_vertices: String,
    mvps: Vec<f64>,
    failed: Vec<String>,
}

fn field<'l>(line: &'l str, key: &str) -> Option<&'l str> {
    line.split_whitespace()
        .find_map(|t| t.strip_prefix(key)?.strip_prefix('='))
}

fn median(v: &[f64]) -> f64 {
    let mut s = v.to_vec();
    s.sort_by(f64::total_cmp);
    let n = s.len();
    if n % 2 == 1 {
        s[n / 2]
    } else {
        0.5 * (s[n / 2 - 1] + s[n / 2])
    }
}

fn table(a: &Args) -> Result<(), String> {
    let path = a.req("results")?;
    let text = std::fs::read_to_string(path).map_err(|e| format!("{path}: {e}"))?;
    let mut meshes: Vec<String> = Vec::new();
    let mut impls: Vec<String> = Vec::new();
    let mut rows: BTreeMap<(String, String), Row> = BTreeMap::new();
    for line in text.lines() {
        let ok = line.starts_with("RESULT ");
        if !ok && !line.starts_with("FAILED ") {
            continue;
        }
        let (Some(imp), Some(mesh)) = (field(line, "impl"), field(line, "mesh")) else {
            continue;
        };
        if !meshes.iter().any(|m| m == mesh) {
            meshes.push(mesh.to_string());
        }
        if !impls.iter().any(|i| i == imp) {
            impls.push(imp.to_string());
        }
        let row = rows.entry((mesh.into(), imp.into())).or_default();
        if ok {
            row.levels = field(line, "levels").unwrap_or("?").into();
            row.out_vertices = field(line, "out_vertices").unwrap_or("?").into();
            if let Some(v) = field(line, "mvps").and_then(|v| v.parse().ok()) {
                row.mvps.push(v);
            }
        } else {
            row.failed
                .push(field(line, "reason").unwrap_or("failed").into());
        }
    }
    println!(
        "| mesh | levels | output vertices | implementation | M output vertices/s (median) \
         | min–max over rounds | rounds | lsubdiv / peer |"
    );
    println!("|---|---:|---:|---|---:|---:|---:|---:|");
    for mesh in &meshes {
        let base = rows
            .get(&(mesh.clone(), "lsubdiv".into()))
            .filter(|r| !r.mvps.is_empty())
            .map(|r| median(&r.mvps));
        for imp in &impls {
            let Some(r) = rows.get(&(mesh.clone(), imp.clone())) else {
                continue;
            };
            if r.mvps.is_empty() {
                println!(
                    "| {mesh} | | | {imp} | failed ({}) | | 0 | |",
                    r.failed.first().map(String::as_str).unwrap_or("?")
                );
                continue;
            }
            let med = median(&r.mvps);
            let lo = r.mvps.iter().cloned().fold(f64::INFINITY, f64::min);
            let hi = r.mvps.iter().cloned().fold(0.0, f64::max);
            let ratio = match (imp.as_str(), base) {
                ("lsubdiv", _) => "1.00".to_string(),
                (_, Some(b)) => format!("{:.2}", b / med),
                _ => "n/a".to_string(),
            };
            let fails = if r.failed.is_empty() {
                String::new()
            } else {
                format!(" (+{} failed)", r.failed.len())
            };
            println!(
                "| {mesh} | {} | {} | {imp} | {med:.2} | {lo:.2}–{hi:.2} | {}{fails} | {ratio} |",
                r.levels,
                r.out_vertices,
                r.mvps.len()
            );
        }
    }
    Ok(())
}
