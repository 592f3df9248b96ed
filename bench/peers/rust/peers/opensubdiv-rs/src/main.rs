//! Peer harness: the `opensubdiv-rs` crate, a Rust port of OpenSubdiv's Far layer (see
//! bench/peers/README.md).
//!
//!   peer-opensubdiv-rs --obj M.obj --name N --levels L [--runs R] [--dump F]
//!
//! `TopologyDescriptor` from the OBJ quads, `TopologyRefinerFactory::create(…, Catmark,
//! Options::default())`, `refine_uniform(L)`; then times only `PrimvarRefiner::interpolate` of
//! levels 1..L on `[f64; 3]` positions into buffers allocated once (the OpenSubdiv harness's
//! protocol): one warm-up, then the median of R runs. Prints a RESULT line.

#[path = "../../../src/common.rs"]
mod common;

use common::{read_obj, report, write_dump, Args, Run};
use opensubdiv_rs::far::{PrimvarRefiner, TopologyDescriptor, TopologyRefinerFactory, UniformOptions};
use opensubdiv_rs::sdc;

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
    let verts_per_face = vec![4usize; obj.faces.len()];
    let face_verts: Vec<u32> = obj.faces.iter().flatten().copied().collect();
    let descriptor = TopologyDescriptor::new(obj.positions.len(), &verts_per_face, &face_verts);
    let mut refiner = TopologyRefinerFactory::create(
        descriptor,
        sdc::SchemeType::Catmark,
        sdc::Options::default(),
    )
    .map_err(|e| format!("TopologyRefinerFactory::create: {e:?}"))?;
    refiner.refine_uniform(UniformOptions::new(levels));
    eprintln!("opensubdiv-rs setup (topology): {:.3} s", setup.elapsed().as_secs_f64());

    let primvar = PrimvarRefiner::new(&refiner);
    let mut bufs: Vec<Vec<[f64; 3]>> = vec![obj.positions.clone()];
    for l in 1..=levels {
        bufs.push(vec![[0.0; 3]; refiner.level(l).num_vertices()]);
    }
    let t = common::median_time(runs, || {
        for l in 1..=levels {
            let (src, dst) = bufs.split_at_mut(l);
            primvar.interpolate(l, &src[l - 1], &mut dst[0]);
        }
        std::hint::black_box(&bufs);
    });
    let out_vertices = bufs[levels].len();
    report("opensubdiv-rs", name, levels, out_vertices, t);

    if let Some(path) = a.get("dump") {
        let last = refiner.level(levels);
        let mut faces = Vec::with_capacity(last.num_faces());
        for f in 0..last.num_faces() {
            let fv = last.face_vertices(f);
            let [p, q, r, s] = fv[..] else {
                return Err("refined mesh has non-quad faces".into());
            };
            faces.push([p, q, r, s]);
        }
        write_dump(path, &bufs[levels], &faces)?;
    }
    Ok(())
}
