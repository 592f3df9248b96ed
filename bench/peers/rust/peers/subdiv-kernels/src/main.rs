//! Peer harness: the `subdiv-kernels` crate (see bench/peers/README.md).
//!
//!   peer-subdiv-kernels --obj M.obj --name N --levels L [--runs R] [--dump F]
//!
//! Builds the crate's `topology::Mesh` from the OBJ quads (edges listed once, no creases),
//! `Refiner::new(mesh, Scheme::CatmullClark, SchemeOptions::default())` and
//! `refine_uniform(levels)`; then times, on `[f64; 3]` positions (the crate's weights are f32,
//! as OpenSubdiv's):
//! - `subdiv-kernels` — the per-level `StencilTable`s (`level_stencils`) applied level by level
//!   with `StencilTable::interpolate_rows` over all rows into buffers allocated once (the same
//!   protocol as the OpenSubdiv harness);
//! - `subdiv-kernels(alloc)` — the crate's one-shot `RefinementResult::interpolate`, which
//!   allocates each level's output.
//!
//! One warm-up, then the median of R runs; prints RESULT lines (setup time is untimed).

#[path = "../../../src/common.rs"]
mod common;

use common::{read_obj, report, write_dump, Args, Run};
use std::collections::HashMap;
use std::num::NonZeroU8;
use subdiv_kernels::topology::Mesh;
use subdiv_kernels::{Refiner, Scheme, SchemeOptions, UniformRefine};

fn main() {
    common::run(main_inner);
}

fn main_inner(args: &[String]) -> Result<(), String> {
    let a = Args::parse(args)?;
    let Run {
        obj: obj_path,
        name,
        levels,
        runs,
    } = a.run()?;
    let obj = read_obj(obj_path)?;

    let setup = std::time::Instant::now();
    let mut edges: HashMap<[u32; 2], usize> = HashMap::new();
    let mut edge_vertices = Vec::new();
    for f in &obj.faces {
        for k in 0..4 {
            let (u, v) = (f[k], f[(k + 1) % 4]);
            let key = [u.min(v), u.max(v)];
            edges.entry(key).or_insert_with(|| {
                edge_vertices.push(key);
                edge_vertices.len() - 1
            });
        }
    }
    let nv = obj.positions.len() as u32;
    let mesh = Mesh {
        vertex_count: nv,
        face_vertex_counts: vec![4; obj.faces.len()],
        face_vertex_indices: obj.faces.iter().flatten().copied().collect(),
        edge_creases: vec![0.0; edge_vertices.len()],
        edge_vertices,
        vertex_corners: vec![0.0; nv as usize],
    };
    let refiner = Refiner::new(mesh, Scheme::CatmullClark, SchemeOptions::default())
        .map_err(|e| format!("Refiner::new: {e}"))?;
    let levels_nz = u8::try_from(levels)
        .ok()
        .and_then(NonZeroU8::new)
        .ok_or("--levels must be 1..=255")?;
    let result = refiner
        .refine_uniform(&UniformRefine::from(levels_nz))
        .map_err(|e| format!("refine_uniform: {e}"))?;
    let out_vertices = result.topology.vertex_count as usize;
    eprintln!("subdiv-kernels setup (topology + stencils): {:.3} s", setup.elapsed().as_secs_f64());

    // Preallocated protocol: one buffer per level, every row of every level.
    let stencils = &result.level_stencils;
    let mut bufs: Vec<Vec<[f64; 3]>> = vec![obj.positions.clone()];
    for s in stencils {
        bufs.push(vec![[0.0; 3]; s.output_count()]);
    }
    let rows: Vec<Vec<u32>> = stencils
        .iter()
        .map(|s| (0..s.output_count() as u32).collect())
        .collect();
    let t = common::median_time(runs, || {
        for (l, s) in stencils.iter().enumerate() {
            let (src, dst) = bufs.split_at_mut(l + 1);
            s.interpolate_rows(&src[l], &rows[l], &mut dst[0]);
        }
        std::hint::black_box(&bufs);
    });
    report("subdiv-kernels", name, levels, out_vertices, t);

    // The crate's one-shot path (allocates every level).
    let t = common::median_time(runs, || {
        std::hint::black_box(result.interpolate(std::hint::black_box(&obj.positions)));
    });
    report("subdiv-kernels(alloc)", name, levels, out_vertices, t);

    if let Some(path) = a.get("dump") {
        let p = result.interpolate(&obj.positions);
        let idx = &result.topology.face_vertex_indices;
        if result.topology.face_vertex_counts.iter().any(|&c| c != 4) {
            return Err("refined mesh has non-quad faces".into());
        }
        let faces: Vec<[u32; 4]> = idx
            .chunks_exact(4)
            .map(|c| [c[0], c[1], c[2], c[3]])
            .collect();
        write_dump(path, &p, &faces)?;
    }
    Ok(())
}
