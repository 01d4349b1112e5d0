//! Criterion benchmarks of the supervisory-control engine: incremental synthesis on the
//! transfer-line family (Göbe 2019, table 7.1) and classic SupCon on textbook problems.
//! `plcsynth bench sct` prints the same figures beside the thesis's and libFAUDES's.

use criterion::{criterion_group, criterion_main, Criterion};
use plcsynth::benchmarks::textbook::{transfer_line, transfer_lines_classic};
use plcsynth::benchmarks::transfer::transfer_lines;
use plcsynth::sct::classic::supcon;
use plcsynth::sct::compile;
use plcsynth::sct::model::{synthesize, Config, Method};
use std::hint::black_box;

fn incremental(c: &mut Criterion) {
    for (k, m) in [(2, 2), (5, 2), (50, 4)] {
        let (l, _) = compile(&transfer_lines(k, m, 2)).unwrap_or_else(|d| panic!("{d:?}"));
        let p = l.project;
        let cfg = Config { method: Method::Incremental, ..Config::default() };
        c.bench_function(&format!("sct incremental transfer lines {k}x{m}"), |b| {
            b.iter(|| {
                for i in 0..p.specs.len() {
                    black_box(synthesize(&p, i, &cfg).expect("no conflicts"));
                }
            })
        });
    }
}

fn classic(c: &mut Criterion) {
    let (plant, spec, ev) = transfer_line(3, 1);
    c.bench_function("sct supcon transfer line 3/1", |b| {
        b.iter(|| black_box(supcon(&plant, &spec, &ev, true).unwrap()))
    });
    let (plant, spec, ev) = transfer_lines_classic(2, 2, 2);
    c.bench_function("sct supcon transfer lines 2x2", |b| {
        b.iter(|| black_box(supcon(&plant, &spec, &ev, true).unwrap()))
    });
}

criterion_group!(benches, incremental, classic);
criterion_main!(benches);
