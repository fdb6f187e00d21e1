//! Speed of the G-code interpreter: canonical calls per second on programs of the kinds users
//! bring — a CAM raster of G1 lines, arcs, and a macro program whose O-word loop makes its
//! moves — and the whole read into the path `replay` and the simulation take.
#![allow(missing_docs)]

use std::fmt::Write as _;
use std::hint::black_box;
use std::time::Duration;

use criterion::{Criterion, Throughput, criterion_group, criterion_main};
use interpolab::gcode::interp::{Interpreter, Options};
use interpolab::gcode::{Dialect, read_program};

/// `n` G1 lines of a zig-zag raster with 3-decimal numbers, as a CAM post writes them.
fn raster(n: usize) -> String {
    let mut s = String::from("G21 G90 G17\nG0 X0 Y0 Z5\nG1 Z-1 F800\n");
    for i in 0..n {
        let x = (i % 200) as f64 * 0.5;
        let y = (i / 200) as f64 * 0.25;
        let _ = writeln!(s, "G1 X{x:.3} Y{y:.3} Z{:.3}", -1.0 - 0.001 * (i % 7) as f64);
    }
    s.push_str("M30\n");
    s
}

/// `n` quarter arcs by I J.
fn arcs(n: usize) -> String {
    let mut s = String::from("G21 G90 G17\nG0 X10 Y0 Z0\nF500\n");
    for i in 0..n {
        let (x, y, ii, jj) = match i % 4 {
            0 => (0.0, 10.0, -10.0, 0.0),
            1 => (-10.0, 0.0, 0.0, -10.0),
            2 => (0.0, -10.0, 10.0, 0.0),
            _ => (10.0, 0.0, 0.0, 10.0),
        };
        let _ = writeln!(s, "G3 X{x:.3} Y{y:.3} I{ii:.3} J{jj:.3}");
    }
    s.push_str("M2\n");
    s
}

/// An O-word loop of `n` turns computing its moves with expressions.
fn macro_loop(n: usize) -> String {
    format!(
        "G21 G90\nF600\n#1 = 0\no100 while [#1 LT {n}]\n  G1 X[10 * cos[#1 * 3.6]] Y[10 * sin[#1 * 3.6]] Z[-0.001 * #1]\n  #1 = [#1 + 1]\no100 endwhile\nM2\n"
    )
}

fn bench(c: &mut Criterion) {
    let mut g = c.benchmark_group("interp");
    g.measurement_time(Duration::from_secs(4)).sample_size(10);
    for (name, text, calls) in [
        ("raster_100k", raster(100_000), 100_000u64),
        ("arcs_100k", arcs(100_000), 100_000),
        ("macro_100k", macro_loop(100_000), 100_000),
    ] {
        g.throughput(Throughput::Elements(calls));
        g.bench_function(format!("canon/{name}"), |b| {
            b.iter(|| black_box(Interpreter::from_text(black_box(&text), Options::default()).count()));
        });
    }
    let text = raster(100_000);
    g.throughput(Throughput::Elements(100_000));
    g.bench_function("read_program/raster_100k", |b| {
        b.iter(|| {
            black_box(
                read_program(black_box(&text), Dialect::LinuxCnc, &Options::default()).map(|p| p.toolpath.blocks.len()),
            )
        });
    });
    g.finish();
}

criterion_group!(benches, bench);
criterion_main!(benches);
