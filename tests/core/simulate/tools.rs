//! A user's program with its own tools: tapered cutters (V, drill) against their closed forms
//! and brute force; a multi-tool program equal, ray by ray, to the union of single-tool
//! simulations of its parts (each run through the older single-cutter pipeline); the tool
//! map; tool length offsets as programmed; block times at G94, G93 and G95 feeds.
#![allow(
    clippy::unwrap_used,
    clippy::float_cmp,
    reason = "tests: an error should fail the test; exact float equality is what some assert"
)]
#[cfg(target_arch = "wasm32")]
use wasm_bindgen_test::wasm_bindgen_test as test;

use crate::support::Rng;
use glam::DVec3;
use interpolab::gcode::interp::tools::{ToolEntry, ToolShape as TableShape, ToolTable};
use interpolab::gcode::interp::{Interpreter, Options};
use interpolab::gcode::parse_program;
use interpolab::geom::Cutter;
use interpolab::simulate::canon::{CanonBuilder, CanonOptions, CanonProgram, KinematicsChoice};
use interpolab::simulate::{
    DexelStock, HeightMap, Interval, MoveKind, NO_TOOL, Program, SimMove, Simulation, ToolShape, tilted_span,
};

fn read(text: &str, tools: &ToolTable, default: Option<Cutter>) -> CanonProgram {
    let mut it = Interpreter::from_text(text, Options { tools: tools.clone(), ..Options::default() });
    let mut b = CanonBuilder::new(CanonOptions {
        machine: None,
        kinematics: KinematicsChoice::Auto,
        chord_tol_mm: 0.01,
        tools: tools.clone(),
        default_cutter: default,
    });
    assert!(b.read(&mut it, |_| true).unwrap());
    b.finish()
}

fn line(from: [f64; 3], to: [f64; 3]) -> SimMove {
    SimMove { kind: MoveKind::Line { from: DVec3::from(from), to: DVec3::from(to) }, line: 0, rapid: false }
}

fn run_moves(stock: DexelStock, cutter: &Cutter, moves: &[SimMove]) -> Simulation {
    let mut sim = Simulation::new(stock, cutter);
    sim.run(&Program { moves: moves.to_vec(), chord_error_mm: 0.0 }).unwrap();
    sim
}

#[test]
fn a_v_groove_has_the_cone_s_profile() {
    // 90° V, R 3 mm, tip at z = −2 along y = 5: a ray d from the line is cut down to
    // −2 + d·cot 45° = −2 + d while that is below the top (0).
    let c = Cutter::tapered(3.0, 90.0, 0.0).unwrap();
    let stock = DexelStock::block([0.0, 0.0, -5.0], [20.0, 10.0, 0.0], 0.1).unwrap();
    let sim = run_moves(stock, &c, &[line([-5.0, 5.0, -2.0], [25.0, 5.0, -2.0])]);
    let map = HeightMap::of(sim.stock());
    let g = map.grid;
    for j in 0..g.ny {
        let d = (g.y_mm(j) - 5.0).abs();
        for i in 0..g.nx {
            let k = j * g.nx + i;
            let want = (-2.0 + d).min(0.0);
            assert!((map.top_mm[k] - want).abs() < 1e-9, "ray ({i}, {j}) d {d}: {} vs {want}", map.top_mm[k]);
            assert_eq!(map.machined[k], d < 2.0, "ray ({i}, {j}) d {d}");
        }
    }
}

#[test]
fn a_drill_plunge_leaves_its_point() {
    // 118° drill, R 4 mm, plunged to z = −3: the hole's floor is −3 + ρ·cot 59°.
    let c = Cutter::tapered(4.0, 118.0, 0.0).unwrap();
    let stock = DexelStock::block([-6.0, -6.0, -8.0], [6.0, 6.0, 0.0], 0.1).unwrap();
    let sim = run_moves(stock, &c, &[line([0.0, 0.0, 5.0], [0.0, 0.0, -3.0])]);
    let map = HeightMap::of(sim.stock());
    let g = map.grid;
    let cot = 1.0 / 59f64.to_radians().tan();
    let mut inside = 0;
    for j in 0..g.ny {
        for i in 0..g.nx {
            let rho = g.x_mm(i).hypot(g.y_mm(j));
            let k = j * g.nx + i;
            let want = if rho <= 4.0 { (-3.0 + rho * cot).min(0.0) } else { 0.0 };
            assert!((map.top_mm[k] - want).abs() < 1e-9, "ρ {rho}: {} vs {want}", map.top_mm[k]);
            inside += usize::from(rho <= 4.0);
        }
    }
    assert!(inside > 4000, "{inside}");
    assert!(c.describe().starts_with("V R 4 mm, 118°"), "{}", c.describe());
}

#[test]
fn a_sloped_v_move_matches_a_dense_brute_force() {
    // The lowest point over the move of tip z + (ρ − r_t)·cot α, searched densely.
    for (angle, flat) in [(90.0, 0.0), (60.0, 0.0), (120.0, 0.5)] {
        let c = Cutter::tapered(2.0, angle, flat).unwrap();
        let tool = ToolShape::of(&c);
        let (a, b) = (DVec3::new(1.0, 2.0, -0.5), DVec3::new(9.0, 6.5, -3.0));
        let stock = DexelStock::block([0.0, 0.0, -10.0], [10.0, 9.0, 0.0], 0.25).unwrap();
        let sim = run_moves(stock, &c, &[line(a.to_array(), b.to_array())]);
        let map = HeightMap::of(sim.stock());
        let g = map.grid;
        let cot = 1.0 / (0.5 * f64::to_radians(angle)).tan();
        let n = 100_000;
        for j in 0..g.ny {
            for i in 0..g.nx {
                let (x, y) = (g.x_mm(i), g.y_mm(j));
                let mut low = f64::INFINITY;
                for s in 0..=n {
                    let p = a.lerp(b, f64::from(s) / f64::from(n));
                    let rho = (x - p.x).hypot(y - p.y);
                    if rho <= 2.0 {
                        low = low.min(p.z + (rho - flat).max(0.0) * cot);
                    }
                }
                let k = j * g.nx + i;
                let want = low.min(0.0);
                let got = map.top_mm[k];
                // The dense search is above the true minimum by at most its step's worth.
                assert!(got <= want + 1e-7 && want - got < 2e-4, "{angle}° ({x}, {y}): {got} vs {want}");
            }
        }
        assert!(tool.cone_mm > 0.0);
    }
}

#[test]
fn a_tilted_tapered_cutter_matches_point_membership() {
    // The ray's span against the cutter's solid of revolution sampled along the ray.
    let mut rng = Rng::new(22);
    for case in 0..60 {
        let angle = rng.range(30.0, 150.0);
        let flat = if case % 2 == 0 { 0.0 } else { rng.range(0.1, 1.5) };
        let c = Cutter::tapered(2.0, angle, flat).unwrap();
        let tool = ToolShape::of(&c);
        let tilt = rng.range(0.0, 1.2);
        let phi = rng.range(0.0, std::f64::consts::TAU);
        let axis = DVec3::new(tilt.sin() * phi.cos(), tilt.sin() * phi.sin(), tilt.cos());
        let tip = DVec3::new(rng.range(-1.0, 1.0), rng.range(-1.0, 1.0), rng.range(-1.0, 1.0));
        for _ in 0..40 {
            let (x, y) = (tip.x + rng.range(-3.0, 3.0), tip.y + rng.range(-3.0, 3.0));
            let inside = |z: f64| {
                let v = DVec3::new(x, y, z) - tip;
                let h = v.dot(axis);
                if !(0.0..=tool.top_mm).contains(&h) {
                    return false;
                }
                let rho = (v - h * axis).length();
                c.radius_at_height_mm(h).is_some_and(|r| rho <= r.min(c.radius_mm))
            };
            let step = 1e-4;
            let (mut lo, mut hi) = (f64::INFINITY, f64::NEG_INFINITY);
            let n = 400_000;
            for s in 0..=n {
                let z = tip.z - 20.0 + 40.0 * f64::from(s) / f64::from(n);
                if inside(z) {
                    lo = lo.min(z);
                    hi = hi.max(z);
                }
            }
            match tilted_span(&tool, tip, axis, x, y) {
                None => assert!(lo > hi, "case {case}: missed a ray inside ({lo}, {hi})"),
                Some((a, b)) => {
                    assert!(lo <= hi, "case {case}: hit ({a}, {b}) a ray outside");
                    assert!(
                        (a - lo).abs() < 2.0 * step && (b - hi).abs() < 2.0 * step,
                        "case {case}: ({a}, {b}) vs ({lo}, {hi})"
                    );
                }
            }
        }
    }
}

fn table() -> ToolTable {
    let mut t = ToolTable::new();
    let mut add = |number: i32, shape: TableShape, d: f64, z: f64| {
        let mut e = ToolEntry::new(number, shape, d);
        e.offset_mm.z = z;
        t.insert(e, "test").unwrap();
    };
    add(1, TableShape::Flat, 6.0, 40.0);
    add(2, TableShape::Ball, 4.0, 55.5);
    add(3, TableShape::V { tip_angle_deg: 60.0 }, 6.0, 31.25);
    t
}

/// The cutting part of each tool's section: a plunge and a few moves, all starting from a
/// rapid at z = 5 (above the stock).
const PARTS: [&str; 3] = [
    "G0 X2 Y3 Z5\nG1 Z-2 F400\nG1 X18\nG1 Y9\nG2 X12 Y15 I-6 J0\nG1 X2\n",
    "G0 X4 Y5 Z5\nG1 Z-1.5 F400\nG1 X16 Y12 Z-3\nG3 X10 Y6 I-3 J-3\nG1 X3 Y14\n",
    "G0 X1 Y8 Z5\nG1 Z-1 F400\nG1 X19 Y8\nG1 X10 Y1 Z-0.5\nG1 X10 Y16\n",
];

fn multi_tool_program() -> String {
    let mut text = String::from("G21 G90 G17\n");
    for (k, part) in PARTS.iter().enumerate() {
        let n = k + 1;
        // Tool changes high above the stock (the new tool hangs from where the spindle is).
        text.push_str(&format!("G0 Z60\nT{n} M6\nG0 G43 H{n} Z60\n{part}G0 Z5\n"));
    }
    text.push_str("M30\n");
    text
}

/// The material of each ray, intersected over several stocks.
fn intersect(a: &[Interval], b: &[Interval]) -> Vec<Interval> {
    let mut out = Vec::new();
    for x in a {
        for y in b {
            let (lo, hi) = (x.lo_mm.max(y.lo_mm), x.hi_mm.min(y.hi_mm));
            if lo < hi {
                out.push(Interval { lo_mm: lo, hi_mm: hi });
            }
        }
    }
    out
}

fn stock() -> DexelStock {
    DexelStock::block([-2.0, -2.0, -6.0], [22.0, 19.0, 0.0], 0.1).unwrap()
}

#[test]
fn a_multi_tool_program_equals_the_union_of_its_single_tool_parts_ray_by_ray() {
    let tools = table();
    let mut p = read(&multi_tool_program(), &tools, None);
    assert_eq!(p.tools.iter().map(|t| t.number).collect::<Vec<_>>(), [1, 2, 3]);
    let mut sim = Simulation::new(stock(), &p.tools[0].cutter).with_tool_map();
    assert!(p.run(&mut sim, |_| true).unwrap());
    // Each part alone, read by the older reader into one cutter's program.
    let singles: Vec<Simulation> = PARTS
        .iter()
        .enumerate()
        .map(|(k, part)| {
            let entry = tools.get(i32::try_from(k + 1).unwrap()).unwrap();
            let cutter = match entry.shape {
                TableShape::Flat => Cutter::flat(0.5 * entry.diameter_mm).unwrap(),
                TableShape::Ball => Cutter::ball(0.5 * entry.diameter_mm).unwrap(),
                TableShape::V { tip_angle_deg } => {
                    Cutter::tapered(0.5 * entry.diameter_mm, tip_angle_deg, 0.0).unwrap()
                }
                _ => unreachable!(),
            };
            let parsed = parse_program(&format!("G21 G90 G17\n{part}M30\n")).unwrap();
            let prog = Program::from_toolpath(&parsed.toolpath, DVec3::ZERO, 0.01).unwrap();
            let mut s = Simulation::new(stock(), &cutter);
            s.run(&prog).unwrap();
            s
        })
        .collect();
    let g = *sim.stock().grid();
    let mut cut_by = [0usize; 3];
    let mut removed = [0.0f64; 3];
    for k in 0..g.len() {
        let mut want = vec![Interval { lo_mm: -6.0, hi_mm: 0.0 }];
        let mut last = NO_TOOL;
        for (t, s) in singles.iter().enumerate() {
            let next = intersect(&want, s.stock().intervals(k));
            let before: f64 = want.iter().map(|iv| iv.hi_mm - iv.lo_mm).sum();
            let after: f64 = next.iter().map(|iv| iv.hi_mm - iv.lo_mm).sum();
            if after < before - 1e-12 {
                last = u16::try_from(t).unwrap();
                removed[t] += (before - after) * g.pitch_mm * g.pitch_mm;
            }
            want = next;
        }
        let got = sim.stock().intervals(k);
        assert_eq!(got.len(), want.len(), "ray {k}: {got:?} vs {want:?}");
        for (a, b) in got.iter().zip(&want) {
            assert!(
                (a.lo_mm - b.lo_mm).abs() < 1e-9 && (a.hi_mm - b.hi_mm).abs() < 1e-9,
                "ray {k}: {got:?} vs {want:?}"
            );
        }
        // The tool map names the last tool that removed material from the ray.
        assert_eq!(sim.tool_map().unwrap()[k], last, "ray {k}");
        if last != NO_TOOL {
            cut_by[usize::from(last)] += 1;
        }
    }
    assert!(cut_by.iter().all(|&n| n > 200), "{cut_by:?}");
    // Each tool's removed volume is what its part added to the union before it.
    for (t, tool) in p.tools.iter().enumerate() {
        assert!(
            (tool.removed_mm3 - removed[t]).abs() < 1e-6 * removed[t].max(1.0),
            "T{}: {} vs {}",
            tool.number,
            tool.removed_mm3,
            removed[t]
        );
    }
}

#[test]
fn tool_length_offsets_move_the_tip_as_programmed() {
    // Tool 1 is 40 mm long: a groove at Z−1 lands at −1 with G43 H1, 8.75 mm deeper with
    // H3 (tool 3's offset, 31.25 mm), 40 mm deeper without G43.
    let tools = table();
    let floor = |g43: &str| -> (f64, Vec<String>) {
        let text = format!("G21 G90\nT1 M6\n{g43}\nG0 X-5 Y5 Z45\nG0 Z5\nG1 Z-1 F300\nG1 X25\nG0 Z45\nM30\n");
        let mut p = read(&text, &tools, None);
        let mut sim =
            Simulation::new(DexelStock::block([0.0, 0.0, -60.0], [20.0, 10.0, 0.0], 0.5).unwrap(), &p.tools[0].cutter);
        p.run(&mut sim, |_| true).unwrap();
        let g = *sim.stock().grid();
        let k = g.ny / 2 * g.nx + g.nx / 2;
        // The floor: the top of the lowest material left (a tool hanging 40 mm low cuts a
        // slot inside the stock, its body's top below the stock's).
        (sim.stock().intervals(k)[0].hi_mm, p.notes.iter().map(|n| format!("{}: {}", n.loc.line, n.text)).collect())
    };
    let (ok, notes) = floor("G43 H1");
    assert!((ok + 1.0).abs() < 1e-12, "{ok}");
    assert!(notes.is_empty(), "{notes:?}");
    let (h2, notes) = floor("G43 H3");
    // Tool 3's offset is 31.25: tool 1 (40 mm) reaches 8.75 mm beyond the programmed point.
    assert!((h2 + 9.75).abs() < 1e-12, "{h2}");
    assert!(notes.iter().any(|n| n.starts_with("4:") && n.contains("8.75 mm beyond")), "{notes:?}");
    let (none, notes) = floor("");
    assert!((none + 41.0).abs() < 1e-12, "{none}");
    assert!(notes.iter().any(|n| n.contains("G43 H1 missing")), "{notes:?}");
}

#[test]
fn block_times_follow_g94_g93_and_g95() {
    let tools = table();
    let text = "G21 G90\nT1 M6 G43 H1\nG0 X0 Y0 Z5\nG1 X30 F600\nG93 G1 Y40 F20\nG95 S1000 M3 G1 X20 F0.1\n\
                G94 G1 A90 F45\nM5\nG95 G1 X0 F0.1\nM30\n";
    let p = read(text, &tools, None);
    let times: Vec<Option<f64>> = p.blocks.iter().map(|b| b.time_min).collect();
    // 30 mm at 600 mm/min; 1/20 min; 10 mm at 0.1 mm/rev × 1000 rev/min; 90° at 45°/min;
    // per revolution with the spindle stopped: no time.
    let want = [None, Some(0.05), Some(0.05), Some(0.1), Some(2.0), None];
    assert_eq!(times.len(), want.len(), "{times:?}");
    for (g, w) in times.iter().zip(want) {
        match (g, w) {
            (Some(a), Some(b)) => assert!((a - b).abs() < 1e-12, "{times:?}"),
            (a, b) => assert_eq!(*a, b, "{times:?}"),
        }
    }
    let t = &p.tools[0];
    assert!((t.feed_min - 2.2).abs() < 1e-12, "{}", t.feed_min);
    assert_eq!((t.feed_blocks, t.rapid_blocks, t.untimed_blocks), (5, 1, 1));
    assert!((t.feed_mm - (30.0 + 40.0 + 10.0 + 20.0)).abs() < 1e-12, "{}", t.feed_mm);
}

#[test]
fn tools_the_table_lacks_take_the_default_cutter_or_are_refused() {
    let tools = table();
    let text = "G21 G90\nG0 X0 Y0 Z5\nG1 Z4 F100\nT7 M6\nG1 Z-1 F100\nM30\n";
    let mut it = Interpreter::from_text(text, Options { tools: tools.clone(), ..Options::default() });
    let mut b = CanonBuilder::new(CanonOptions {
        machine: None,
        kinematics: KinematicsChoice::Auto,
        chord_tol_mm: 0.01,
        tools: tools.clone(),
        default_cutter: None,
    });
    let e = b.read(&mut it, |_| true).unwrap_err().to_string();
    assert!(e.contains("line 4: tool 7 is not in the tool table") && e.contains("--tool 7:"), "{e}");
    let p = read(text, &tools, Some(Cutter::ball(1.0).unwrap()));
    let numbers: Vec<i32> = p.tools.iter().map(|t| t.number).collect();
    // A feed move before M6 is cut with the default cutter (the leading rapid needs none);
    // then tool 7, also the default cutter.
    assert_eq!(numbers, [-1, 7]);
    assert!(p.tools[1].source.contains("tool 7 is not in the tool table"), "{}", p.tools[1].source);
}
