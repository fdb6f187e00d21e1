//! The interpreter's shorter way for *plain motion lines* (only axis words X Y Z A B C with
//! plain numbers, `X1`, `x-2.5 Y.5`) gives what the general reader and executor give, call
//! for call and error for error: generated programs that mix plain lines with their near
//! misses (comments, `;`, spaces inside numbers, signs, exponents, repeated words, `N`, `/`,
//! other letters) and with the modes that change what a plain line does (G91, G20, G93, arcs,
//! canned cycles, cutter compensation, G92, polar, rotation, splines) run with
//! `Options::general_only` on and off.
#![allow(
    clippy::unwrap_used,
    clippy::expect_used,
    clippy::float_cmp,
    reason = "tests: a failure should fail the test; some values are exact"
)]

#[cfg(target_arch = "wasm32")]
use wasm_bindgen_test::wasm_bindgen_test as test;

use interpolab::gcode::interp::{Interpreter, Options};

use crate::support::Rng;

fn pick<'a>(rng: &mut Rng, items: &[&'a str]) -> &'a str {
    items[((rng.next_f64() * items.len() as f64) as usize).min(items.len() - 1)]
}

fn number(rng: &mut Rng) -> String {
    let v = rng.range(-30.0, 30.0);
    match (rng.next_f64() * 10.0) as u32 {
        0 => format!("{}", v.round()),
        1 => format!("{:.3}", v),
        2 => format!("{}.", v.round()),
        3 => format!(".{}", (v.abs() * 10.0) as u32),
        4 => format!("-.{}", (v.abs() * 10.0) as u32),
        5 => format!("+{:.1}", v.abs()),
        6 => "-0".to_owned(),
        7 => format!("{:.4}", v / 7.0),
        8 => "12345678901234567890".to_owned(), // too many digits for a plain number
        _ => format!("{:.2}", v),
    }
}

fn axis(rng: &mut Rng) -> char {
    let axes = ['X', 'Y', 'Z', 'A', 'B', 'C', 'x', 'y', 'z', 'a', 'b', 'c'];
    axes[((rng.next_f64() * axes.len() as f64) as usize).min(axes.len() - 1)]
}

/// A plain line: one to four axis words, separated or not by spaces and tabs.
fn plain(rng: &mut Rng) -> String {
    let mut line = String::new();
    let n = 1 + (rng.next_f64() * 4.0) as usize;
    for _ in 0..n {
        line.push_str(pick(rng, &["", "", " ", "\t", "  "]));
        line.push(axis(rng));
        line.push_str(&number(rng));
    }
    line.push_str(pick(rng, &["", "", " ", "\t"]));
    line
}

/// A plain line spoilt one way: each is read by the general reader (or refused by it).
fn near_miss(rng: &mut Rng) -> String {
    let p = plain(rng);
    let a = axis(rng);
    let n = number(rng);
    match (rng.next_f64() * 19.0) as u32 {
        0 => format!("{p} (a comment)"),
        1 => format!("{p} ; the rest"),
        2 => format!("{a}1 2"),
        3 => format!("{a}1e3"),
        4 => format!("{a}1E-2"),
        5 => format!("{a}-"),
        6 => format!("{a}."),
        7 => format!("{a}1.2.3"),
        8 => format!("{a} {n}"),
        9 => format!("/{p}"),
        10 => format!("N{} {p}", (rng.next_f64() * 100.0) as u32),
        11 => format!("{a}{n} {a}{n}"),
        12 => format!("{a}[1+2]"),
        13 => format!("{a}#1"),
        14 => format!("{p} F{}", (rng.next_f64() * 500.0) as u32),
        15 => format!("{p} E5"),
        16 => format!("{p} U2"),
        17 => format!("{a}+-1"),
        _ => format!("{p}\u{7f}"),
    }
}

/// A line that changes the modes a plain line moves in (or moves otherwise).
fn modal(rng: &mut Rng) -> String {
    pick(
        rng,
        &[
            "G0",
            "G1 F200",
            "G91",
            "G90",
            "G20",
            "G21",
            "G93 G1 X1 F2",
            "G94 F300",
            "G2 X5 Y0 I2.5 J0 F100",
            "G3 X0 Y0 R5",
            "G17",
            "G18",
            "G19",
            "G92 X1 Y2",
            "G92.1",
            "G52 X3",
            "G55",
            "G54",
            "G10 L2 P1 X1 R30",
            "G41.1 D2 G1 X10 F100",
            "G42.1 D1",
            "G40 G1 X0",
            "G81 R2 Z-1 F100",
            "G83 R2 Z-3 Q1",
            "G80",
            "G16",
            "G15",
            "G68 X0 Y0 R45",
            "G69",
            "G5.2 X1 Y1 P1 L3",
            "G5.3",
            "G43.1 Z2",
            "G49",
            "M3 S1000",
            "M5",
            "#1=2",
            "%",
            "",
            "(just a comment)",
            "G53 G0 X1",
            "G28",
            "T1 M6",
        ],
    )
    .to_owned()
}

fn program(rng: &mut Rng) -> String {
    let mut text = String::from(pick(rng, &["G21 G90 G0 X0 Y0 Z5\nG1 F100\n", "G1 F50\n", "G0 X1\n", ""]));
    let lines = 4 + (rng.next_f64() * 14.0) as usize;
    for _ in 0..lines {
        let r = rng.next_f64();
        let line = if r < 0.55 {
            plain(rng)
        } else if r < 0.75 {
            near_miss(rng)
        } else {
            modal(rng)
        };
        text.push_str(&line);
        text.push_str(pick(rng, &["\n", "\n", "\r\n"]));
    }
    text.push_str("M30\n");
    text
}

/// Every call and error, and the reports and warnings, as text (`{:?}` tells -0 from 0).
fn run(text: &str, opts: &Options) -> Vec<String> {
    let mut it = Interpreter::from_text(text, opts.clone());
    let mut out: Vec<String> = it.by_ref().map(|c| format!("{c:?}")).collect();
    out.extend(it.reports().iter().map(|r| format!("{r:?}")));
    out.extend(it.warnings().iter().map(|w| format!("{w:?}")));
    out.push(format!("{:?} {} {}", it.state(), it.main_lines(), it.main_blocks()));
    out
}

#[test]
fn plain_lines_take_the_short_way_to_the_same_calls_as_the_general_one() {
    let mut rng = Rng::new(26);
    let (mut calls, mut plain_lines) = (0usize, 0usize);
    for case in 0..1500 {
        let text = program(&mut rng);
        for base in [
            Options::default(),
            Options { strict: true, ..Options::default() },
            Options { fanuc: true, ..Options::default() },
            Options { inch: true, block_delete: true, ..Options::default() },
        ] {
            let general = run(&text, &Options { general_only: true, ..base.clone() });
            let short = run(&text, &Options { general_only: false, ..base });
            assert_eq!(short, general, "case {case}:\n{text}");
            calls += general.len();
        }
        plain_lines += text
            .lines()
            .filter(|l| !l.is_empty() && l.trim().chars().all(|c| "XYZABCxyzabc0123456789.+- \t".contains(c)))
            .count();
    }
    // The programs do exercise both ways.
    assert!(plain_lines > 5_000 && calls > 20_000, "{plain_lines} plain lines, {calls} calls");
}

#[test]
fn a_plain_line_moves_as_written_in_the_modes_in_force() {
    // The short way still honours the modes: incremental inches after a G92 shift.
    let text = "G21 G90 G0 X0 Y0 Z0\nG1 F100\nX1 Y2\nG91 G20\nx1\ty-1 Z.5\nG90 G21 G92 X0\nX5\nM30\n";
    let ends: Vec<[f64; 3]> = Interpreter::from_text(text, Options::default())
        .filter_map(|c| c.expect("reads").end().map(|p| p.xyz.to_array()))
        .collect();
    let want = [[0.0, 0.0, 0.0], [1.0, 2.0, 0.0], [26.4, -23.4, 12.7], [31.4, -23.4, 12.7]];
    assert_eq!(ends.len(), want.len(), "{ends:?}");
    for (e, w) in ends.iter().zip(want) {
        for k in 0..3 {
            assert!((e[k] - w[k]).abs() < 1e-12, "{ends:?}");
        }
    }
}
