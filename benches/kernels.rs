//! Criterion benchmarks of the surface kernel: `Refiner::refine` (positions only, buffers
//! reused) on a 64×64 torus, generated against generic kernels, f64 and f32.
#![allow(missing_docs)] // criterion_group! defines a public function it does not document

use criterion::{criterion_group, criterion_main, BenchmarkId, Criterion, Throughput};
use lsubdiv::mesh::generators::torus;
use lsubdiv::mesh::patch::Refiner;
use lsubdiv::mesh::real::Real;
use lsubdiv::mesh::surface::{SurfaceScheme, SurfaceVisitor};
use lsubdiv::mesh::topology::Topology;
use lsubdiv::mesh::QuadMesh;
use std::time::Duration;

/// Benchmarks `Refiner::refine` for one scheme type.
struct Bench<'a, 'c, T> {
    group: &'a mut criterion::BenchmarkGroup<'c, criterion::measurement::WallTime>,
    id: BenchmarkId,
    mesh: &'a QuadMesh,
    steps: usize,
    _t: std::marker::PhantomData<T>,
}

impl<T: Real> SurfaceVisitor for Bench<'_, '_, T> {
    type Output = ();
    fn visit<S: SurfaceScheme + Sync>(self, scheme: &S) {
        let topo = Topology::build(self.mesh).expect("a closed mesh");
        let mut r = Refiner::<S, T>::new(scheme, &topo, self.steps, 1).expect("refiner");
        r.refine(&self.mesh.positions).expect("refines");
        self.group
            .throughput(Throughput::Elements(r.output_vertices() as u64));
        self.group.bench_function(self.id, |b| {
            b.iter(|| {
                r.refine(&self.mesh.positions)
                    .map(|p| p.len())
                    .expect("refines")
            })
        });
    }
}

/// The generated and the generic refiner of one scheme, positions of type T.
fn both<T: Real>(
    group: &mut criterion::BenchmarkGroup<'_, criterion::measurement::WallTime>,
    mesh: &QuadMesh,
    name: &str,
    steps: usize,
    scalar: &str,
) {
    let generic = lsubdiv_cli::bench::surface(name).expect("surface scheme");
    for path in ["generated", "generic"] {
        let b = Bench::<T> {
            group: &mut *group,
            id: BenchmarkId::new(format!("{path}/{scalar}"), name),
            mesh,
            steps,
            _t: std::marker::PhantomData,
        };
        if path == "generated" {
            lsubdiv::generated::visit_surface(name, b).expect("generated scheme");
        } else {
            b.visit(&generic);
        }
    }
}

fn kernels(c: &mut Criterion) {
    let mesh = torus(64, 64);
    let mut group = c.benchmark_group("surface");
    group
        .measurement_time(Duration::from_secs(3))
        .sample_size(20);
    for (name, steps) in [
        ("uniform-binary", 3),
        ("binary-ternary", 2),
        ("fibonacci", 4),
    ] {
        both::<f64>(&mut group, &mesh, name, steps, "f64");
        both::<f32>(&mut group, &mesh, name, steps, "f32");
    }
    group.finish();
}

criterion_group!(benches, kernels);
criterion_main!(benches);
