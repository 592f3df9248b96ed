//! Curve refinement throughput (output points/s): the generated specialised stencils against the
//! generic table-driven ones, on the same closed polygon, and one step of a 10 M-point polygon
//! against the memory-bandwidth bound. Prints the ratios measured in this run.
#![allow(missing_docs)] // criterion_group! defines a public function it does not document

use criterion::{criterion_group, criterion_main, BenchmarkId, Criterion, Throughput};
use lsubdiv::compiler::exact::Scheme;
use lsubdiv::generic::GenericScheme;
use lsubdiv::{Curve, CurveRefiner, CurveScheme};
use lsubdiv_cli::resolve;
use std::time::{Duration, Instant};

fn polygon(n: usize) -> Vec<[f64; 3]> {
    (0..n)
        .map(|i| {
            let t = std::f64::consts::TAU * i as f64 / n as f64;
            [t.cos(), t.sin(), (3.0 * t).sin() * 0.2]
        })
        .collect()
}

fn median_secs(mut f: impl FnMut()) -> f64 {
    let mut v: Vec<f64> = (0..7)
        .map(|_| {
            let t = Instant::now();
            f();
            t.elapsed().as_secs_f64()
        })
        .collect();
    v.sort_by(f64::total_cmp);
    v[v.len() / 2]
}

fn bench(c: &mut Criterion) {
    let mut group = c.benchmark_group("curve");
    group
        .measurement_time(Duration::from_secs(3))
        .sample_size(20);
    for name in ["fibonacci", "binary-ternary", "uniform-binary"] {
        let r = resolve(name).unwrap();
        let generic = GenericScheme::new(Scheme::build(r.ls).unwrap()).unwrap();
        let coarse = Curve::with_axiom(&generic.tables(), polygon(1000), true);
        // Enough steps for ~1e6 output points.
        let mut steps = 0;
        let mut out = coarse.points.len();
        while out < 1_000_000 {
            steps += 1;
            out = lsubdiv::refine(&generic, &coarse, steps)
                .unwrap()
                .points
                .len();
        }
        group.throughput(Throughput::Elements(out as u64));
        // Buffers reused across runs (as an application refining every frame would), so that
        // the kernels are compared, not the kernel's page faults.
        let (mut rg, mut rb) = (CurveRefiner::default(), CurveRefiner::default());
        group.bench_with_input(BenchmarkId::new("generated", name), &coarse, |b, c| {
            b.iter(|| refine_generated(name, &mut rg, c, steps))
        });
        group.bench_with_input(BenchmarkId::new("generic", name), &coarse, |b, c| {
            b.iter(|| rb.refine(&generic, c, steps).unwrap().points.len())
        });
        let tg = median_secs(|| {
            refine_generated(name, &mut rg, &coarse, steps);
        });
        let tb = median_secs(|| {
            rb.refine(&generic, &coarse, steps).unwrap();
        });
        println!(
            "{name}: {out} output points in {steps} steps; generated {:.1} M points/s, generic {:.1} M points/s, ratio generated/generic = {:.2}",
            out as f64 / tg / 1e6,
            out as f64 / tb / 1e6,
            tb / tg
        );
    }
    group.finish();
}

/// A closed 10 M-point polygon refined once, against the memory-bandwidth bound measured in
/// the same run (a large copy: read + write bytes per second).
fn bandwidth(_: &mut Criterion) {
    let n = 10_000_000;
    let src: Vec<[f64; 3]> = polygon(n);
    let mut dst = vec![[0.0f64; 3]; n];
    let copy = median_secs(|| dst.copy_from_slice(std::hint::black_box(&src)));
    let bytes_per_s = 2.0 * (n * 24) as f64 / copy;
    for name in ["uniform-binary", "binary-ternary", "fibonacci"] {
        let r = resolve(name).unwrap();
        let generic = GenericScheme::new(Scheme::build(r.ls).unwrap()).unwrap();
        let coarse = Curve::with_axiom(&generic.tables(), src.clone(), true);
        // Buffers reused across runs, as an application refining every frame would.
        let mut refiner = CurveRefiner::default();
        let mut out = 0;
        let t = median_secs(|| {
            out = refine_generated(name, &mut refiner, &coarse, 1);
        });
        // Bound: read the input once, write the output once.
        let bound = ((n + out) * 24) as f64 / bytes_per_s;
        println!(
            "{name}: 10 M-point closed polygon → {out} points in {:.1} ms; bandwidth bound {:.1} ms (copy at {:.1} GB/s); {:.0}% of the bound",
            t * 1e3,
            bound * 1e3,
            bytes_per_s / 1e9,
            100.0 * bound / t
        );
    }
}

/// `steps` steps of the generated kernel of `name` with a reused refiner.
fn refine_generated(name: &str, r: &mut CurveRefiner<3>, c: &Curve<3>, steps: usize) -> usize {
    use lsubdiv::generated::{binary_ternary, fibonacci, uniform_binary};
    let out = match name {
        "uniform-binary" => r.refine(&uniform_binary::Scheme, c, steps),
        "binary-ternary" => r.refine(&binary_ternary::Scheme, c, steps),
        _ => r.refine(&fibonacci::Scheme, c, steps),
    };
    out.unwrap().points.len()
}

criterion_group!(benches, bench, bandwidth);
criterion_main!(benches);
