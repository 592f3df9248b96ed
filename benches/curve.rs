//! Curve refinement throughput (output points/s): the generated specialised kernels against the
//! generic table-driven path, on the same closed polygon. Prints the ratio measured in this run.

use criterion::{criterion_group, criterion_main, BenchmarkId, Criterion, Throughput};
use lsubdiv::compiler::generic::GenericScheme;
use lsubdiv::compiler::Scheme;
use lsubdiv::{generated, resolve, Curve, CurveScheme};
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
    let mut v: Vec<f64> = (0..15)
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
        let generic = GenericScheme::new(Scheme::build(r.ls).unwrap());
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
        group.bench_with_input(BenchmarkId::new("generated", name), &coarse, |b, c| {
            b.iter(|| generated::refine_curve(name, c, steps).unwrap().unwrap())
        });
        group.bench_with_input(BenchmarkId::new("generic", name), &coarse, |b, c| {
            b.iter(|| lsubdiv::refine(&generic, c, steps).unwrap())
        });
        let tg = median_secs(|| {
            generated::refine_curve(name, &coarse, steps)
                .unwrap()
                .unwrap();
        });
        let tb = median_secs(|| {
            lsubdiv::refine(&generic, &coarse, steps).unwrap();
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

criterion_group!(benches, bench);
criterion_main!(benches);
