//! Micro-benchmarks of the hot DBM operations on dim 4 and 8 (3 and 7 clocks).

use criterion::{criterion_group, criterion_main, BatchSize, Criterion};
use plcsynth::zone::{Bound, Dbm};
use std::hint::black_box;

/// A zone with finite bounds on most entries, as met during exploration:
/// clocks reset at different times, then bounded by an invariant.
fn sample_zone(dim: usize) -> Dbm {
    let mut z = Dbm::zero(dim);
    for x in 1..dim {
        z.up();
        z.constrain(0, x, Bound::le(-(x as i32)));
        z.reset(x);
    }
    z.up();
    z.constrain(1, 0, Bound::lt(5 * dim as i32));
    z
}

fn bench_dim(c: &mut Criterion, dim: usize) {
    let z = sample_zone(dim);
    assert!(!z.is_empty());
    let mut g = c.benchmark_group(format!("dbm{dim}"));
    // An upper bound on the last clock that is tighter than the current one.
    let tight = Bound::le(z.get(dim - 1, 0).constant() - 1);
    g.bench_function("constrain", |b| {
        b.iter_batched_ref(
            || z.clone(),
            |z| black_box(z.constrain(dim - 1, 0, black_box(tight))),
            BatchSize::SmallInput,
        )
    });
    g.bench_function("up", |b| b.iter_batched_ref(|| z.clone(), |z| z.up(), BatchSize::SmallInput));
    g.bench_function("reset", |b| b.iter_batched_ref(|| z.clone(), |z| z.reset(black_box(2)), BatchSize::SmallInput));
    g.bench_function("close", |b| b.iter_batched_ref(|| z.clone(), |z| black_box(z.close()), BatchSize::SmallInput));
    let max: Vec<i32> = (0..dim as i32).map(|c| c + 1).collect();
    g.bench_function("extrapolate_max", |b| {
        b.iter_batched_ref(|| z.clone(), |z| z.extrapolate_max(black_box(&max)), BatchSize::SmallInput)
    });
    let mut guard = Dbm::unconstrained(dim);
    guard.constrain_interval(1, Bound::le(-1), Bound::le(3 * dim as i32));
    g.bench_function("intersect_guard", |b| {
        b.iter_batched_ref(|| z.clone(), |z| black_box(z.intersect(black_box(&guard))), BatchSize::SmallInput)
    });
    let bigger = {
        let mut y = z.clone();
        y.up();
        y
    };
    g.bench_function("includes", |b| b.iter(|| black_box(black_box(&bigger).includes(black_box(&z)))));
    g.finish();
}

fn benches(c: &mut Criterion) {
    bench_dim(c, 4);
    bench_dim(c, 8);
}

criterion_group!(zone_benches, benches);
criterion_main!(zone_benches);
