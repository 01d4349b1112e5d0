//! Solving the timed examples end to end (parse, check, precompute, solve).

use criterion::{criterion_group, criterion_main, Criterion};
use plcsynth::timed::{compile, solve::Config, synthesize};

fn example(name: &str) -> String {
    std::fs::read_to_string(format!("{}/examples/timed/{name}.tga", env!("CARGO_MANIFEST_DIR"))).unwrap()
}

fn solving(c: &mut Criterion) {
    let mut group = c.benchmark_group("timed");
    group.sample_size(10);
    for name in ["lamp", "two_robots_14", "gear_checking", "round_table_4", "round_table_6"] {
        let source = example(name);
        group.bench_function(name, |b| {
            b.iter(|| {
                let (game, _) = compile(&source).unwrap();
                synthesize(&game, &Config::default(), &mut |_| true).solution.stats.winning
            })
        });
    }
    let rt8 = example("round_table_8");
    group.bench_function("compile round_table_8", |b| b.iter(|| compile(&rt8).unwrap().0.components.len()));
    group.finish();
}

criterion_group!(benches, solving);
criterion_main!(benches);
