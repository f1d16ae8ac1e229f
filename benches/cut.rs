//! Cutting capsule voids from a sliced part: the judge's step for every design it weighs, and
//! the optimizer's for every correction of its smooth capsule term. The example T printed on
//! its slanted facet with PrusaSlicer's settings (381 × 70 cells, 287 layers), with one
//! capsule and with five, beside the baseline measured in the same process.
//!
//! Run with `cargo bench --bench cut`.

mod support;

use std::hint::black_box;
use std::time::Duration;

use ballast::balance::slicing;
use ballast::geometry::{load_mesh, MeshSelector, PrintRaster, Void};
use ballast::spec::model::{Print, Units};
use criterion::{criterion_group, criterion_main, Criterion};
use nalgebra::{Point3, Rotation3, Vector3};
use support::{manifest, sum_coordinates};

/// A void from `from` to `to` (millimetres, the T's frame) of radius `radius`.
fn void(from: [f64; 3], to: [f64; 3], radius: f64) -> Void {
    Void {
        from: Point3::from(from),
        to: Point3::from(to),
        radius,
    }
}

fn cut(c: &mut Criterion) {
    let path = manifest().join("examples/meshes/t_shape.obj");
    let mesh = load_mesh(&path, &MeshSelector::Whole).expect("the example T");
    let down = Vector3::new(0.6, 0.0, -0.8);
    let to_print = Rotation3::rotation_between(&down, &-Vector3::z()).expect("a rotation");
    let raster = PrintRaster::new(
        &mesh,
        &slicing(&Print::defaults(Units::Millimetre), to_print),
    );
    // The example's five capsules, the large one alone too.
    let one = vec![void([15.6, 0.0, 28.8], [-15.4, 0.0, 30.5], 8.2)];
    let five = vec![
        void([59.7, -4.6, 35.8], [31.4, -4.6, 34.2], 3.0),
        void([58.3, 5.2, 34.2], [30.4, 4.5, 35.8], 3.0),
        void([-25.4, -5.9, 34.1], [-60.5, -5.4, 36.1], 2.7),
        one[0],
        void([-27.9, 4.4, 35.8], [-56.1, 4.0, 34.2], 3.0),
    ];
    eprintln!("t_shape: {raster:?}");
    let mut group = c.benchmark_group("cut");
    group
        .sample_size(10)
        .warm_up_time(Duration::from_secs(1))
        .measurement_time(Duration::from_secs(5));
    group.bench_function("t_shape/baseline", |b| {
        b.iter(|| sum_coordinates(black_box(&mesh)))
    });
    group.bench_function("t_shape/one_capsule", |b| {
        b.iter(|| raster.volumes_with_voids(black_box(&one)))
    });
    group.bench_function("t_shape/five_capsules", |b| {
        b.iter(|| raster.volumes_with_voids(black_box(&five)))
    });
    group.finish();
}

criterion_group!(benches, cut);
criterion_main!(benches);
