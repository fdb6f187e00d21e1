//! The dexel cutting simulation against closed forms and brute force: interval subtraction
//! exhaustively, grooves of ball, flat and fillet cutters, plunges, the textbook scallop of
//! two ball passes, an arc, tilted cutters against a point-membership scan, 5-axis sampling,
//! and bit-identical rays run after run (and across platforms, by a checksum).
#![allow(
    clippy::unwrap_used,
    clippy::float_cmp,
    reason = "tests: an error should fail the test; exact float equality is what some assert"
)]
#[cfg(target_arch = "wasm32")]
use wasm_bindgen_test::wasm_bindgen_test as test;

use crate::support::Rng;
use glam::DVec3;
use interpolab::fiveaxis::{Joints, Machine};
use interpolab::gcode::parse_program;
use interpolab::geom::{BodySpec, Cutter};
use interpolab::simulate::{
    BallSegment, Design, DexelStock, HeightMap, MoveKind, Program, SimMove, SimStats, Simulation, ToolShape,
    tilted_span,
};

fn line(from: [f64; 3], to: [f64; 3]) -> SimMove {
    SimMove { kind: MoveKind::Line { from: DVec3::from(from), to: DVec3::from(to) }, line: 0, rapid: false }
}

fn run(stock: DexelStock, cutter: &Cutter, moves: &[SimMove]) -> Simulation {
    let mut sim = Simulation::new(stock, cutter);
    sim.run(&Program { moves: moves.to_vec(), chord_error_mm: 0.0 }).unwrap();
    sim
}

/// Maximal runs of set cells of a mask over unit cells [k, k+1), k < n.
fn runs(mask: u32, n: u32) -> Vec<(f64, f64)> {
    let mut out = Vec::new();
    let mut k = 0;
    while k < n {
        if mask & (1 << k) != 0 {
            let s = k;
            while k < n && mask & (1 << k) != 0 {
                k += 1;
            }
            out.push((f64::from(s), f64::from(k)));
        } else {
            k += 1;
        }
    }
    out
}

fn cells(c: u32, d: u32) -> u32 {
    (c..d).fold(0, |m, k| m | (1 << k))
}

#[test]
fn interval_subtraction_exhaustive_on_eight_cells() {
    // Every material pattern of 8 unit cells, then every pair of spans with integer ends:
    // the ray must equal the maximal runs of the cells left (split, trim, remove, and the
    // spill list growing and shrinking back to one interval), and report the length removed.
    const N: u32 = 8;
    let spans: Vec<(u32, u32)> = (0..=N).flat_map(|c| (c + 1..=N).map(move |d| (c, d))).collect();
    let mut checked = 0u64;
    for mask in 0..(1u32 << N) {
        for &(c1, d1) in &spans {
            for &(c2, d2) in spans.iter().step_by(3) {
                let mut stock = DexelStock::block([0.0, 0.0, 0.0], [1.0, 1.0, f64::from(N)], 1.0).unwrap();
                for (a, b) in runs(!mask & ((1 << N) - 1), N) {
                    stock.subtract(0, a, b);
                }
                assert_eq!(stock.intervals(0).iter().map(|iv| (iv.lo_mm, iv.hi_mm)).collect::<Vec<_>>(), runs(mask, N));
                let mut m = mask;
                for (c, d) in [(c1, d1), (c2, d2)] {
                    let removed = stock.subtract(0, f64::from(c), f64::from(d));
                    let cut = m & cells(c, d);
                    assert_eq!(removed, f64::from(cut.count_ones()), "mask {mask:08b} span ({c}, {d})");
                    m &= !cut;
                    let got: Vec<(f64, f64)> = stock.intervals(0).iter().map(|iv| (iv.lo_mm, iv.hi_mm)).collect();
                    assert_eq!(got, runs(m, N), "mask {mask:08b} after ({c}, {d})");
                    checked += 1;
                }
            }
        }
    }
    assert!(checked > 100_000);
    // Spans at non-integer ends keep exactly those ends; an empty span removes nothing.
    let mut stock = DexelStock::block([0.0, 0.0, 0.0], [1.0, 1.0, 8.0], 1.0).unwrap();
    assert_eq!(stock.subtract(0, 2.25, 2.25), 0.0);
    stock.subtract(0, 2.25, 3.5);
    stock.subtract(0, 5.125, 9.0);
    let got: Vec<(f64, f64)> = stock.intervals(0).iter().map(|iv| (iv.lo_mm, iv.hi_mm)).collect();
    assert_eq!(got, vec![(0.0, 2.25), (3.5, 5.125)]);
}

/// Height a horizontal 3-axis move of a cutter at tip height z leaves at distance d from its
/// line: the tip plus the bottom profile, capped by the stock top.
fn groove(c: &Cutter, z: f64, d: f64, top: f64) -> f64 {
    c.bottom_height_mm(d).map_or(top, |b| (z + b).min(top))
}

#[test]
fn horizontal_grooves_of_ball_flat_and_fillet_match_the_profile() {
    for c in [Cutter::ball(3.0).unwrap(), Cutter::flat(3.0).unwrap(), Cutter::fillet(3.0, 1.0).unwrap()] {
        let stock = DexelStock::block([0.0, 0.0, 0.0], [40.0, 20.0, 10.0], 0.1).unwrap();
        let sim = run(stock, &c, &[line([-10.0, 10.02, 7.0], [50.0, 10.02, 7.0])]);
        let map = HeightMap::of(sim.stock());
        let g = map.grid;
        assert_eq!((g.nx, g.ny), (400, 200));
        for j in 0..g.ny {
            for i in 0..g.nx {
                let want = groove(&c, 7.0, (g.y_mm(j) - 10.02).abs(), 10.0);
                let got = map.top_mm[j * g.nx + i];
                assert!((got - want).abs() < 1e-9, "{} at ({i}, {j}): {got} vs {want}", c.describe());
            }
        }
        // Removed volume: the groove's cross-section × length, to the pitch's resolution.
        let area: f64 = (0..g.ny).map(|j| 10.0 - groove(&c, 7.0, (g.y_mm(j) - 10.02).abs(), 10.0)).sum::<f64>() * 0.1;
        let v = sim.counters().removed_mm3;
        assert!((v - area * 40.0).abs() < 1e-6 * v, "{v} vs {}", area * 40.0);
    }
}

/// Brute force: the lowest point over a dense sampling of the move of tip + bottom profile.
fn sloped_brute(c: &Cutter, a: DVec3, b: DVec3, x: f64, y: f64, n: usize) -> Option<f64> {
    (0..=n)
        .filter_map(|k| {
            let p = a.lerp(b, k as f64 / n as f64);
            c.bottom_height_mm((x - p.x).hypot(y - p.y)).map(|h| p.z + h)
        })
        .reduce(f64::min)
}

#[test]
fn sloped_moves_match_a_dense_brute_force_envelope() {
    let (a, b) = (DVec3::new(2.0, 3.0, 9.0), DVec3::new(17.0, 11.0, 4.0));
    for c in [Cutter::ball(2.5).unwrap(), Cutter::flat(2.5).unwrap(), Cutter::fillet(2.5, 1.0).unwrap()] {
        let stock = DexelStock::block([0.0, 0.0, 0.0], [20.0, 15.0, 10.0], 0.25).unwrap();
        let sim = run(stock, &c, &[line(a.to_array(), b.to_array())]);
        let map = HeightMap::of(sim.stock());
        let g = map.grid;
        let n = 200_000;
        // The sampled minimum over-estimates by at most the tip's drop over one sample step
        // plus the profile's change over it; bound both by |b − a|/n times the largest slope
        // met (≤ 10 away from the rim, so compare 0.05 mm inside it).
        let step = (b - a).length() / n as f64;
        let mut compared = 0;
        for j in (0..g.ny).step_by(3) {
            for i in (0..g.nx).step_by(3) {
                let (x, y) = (g.x_mm(i), g.y_mm(j));
                let got = map.top_mm[j * g.nx + i];
                let inner = Cutter::fillet(c.radius_mm - 0.05, c.corner_radius_mm.min(c.radius_mm - 0.05)).unwrap();
                let Some(want) = sloped_brute(&c, a, b, x, y, n) else { continue };
                if sloped_brute(&inner, a, b, x, y, 2_000).is_none() {
                    continue;
                }
                let want = want.min(10.0);
                assert!(got <= want + 1e-7, "{}: ({x}, {y}) {got} above {want}", c.describe());
                assert!(got >= want - 20.0 * step - 1e-7, "{}: ({x}, {y}) {got} below {want}", c.describe());
                compared += 1;
            }
        }
        assert!(compared > 150, "{compared}");
    }
}

#[test]
fn a_plunge_leaves_a_hole_of_the_cutter_profile() {
    for c in [Cutter::ball(2.0).unwrap(), Cutter::flat(2.0).unwrap(), Cutter::fillet(2.0, 0.5).unwrap()] {
        let stock = DexelStock::block([0.0, 0.0, 0.0], [10.0, 10.0, 10.0], 0.1).unwrap();
        let sim = run(stock, &c, &[line([5.0, 5.0, 15.0], [5.0, 5.0, 6.0])]);
        let map = HeightMap::of(sim.stock());
        let g = map.grid;
        for j in 0..g.ny {
            for i in 0..g.nx {
                let d = (g.x_mm(i) - 5.0).hypot(g.y_mm(j) - 5.0);
                let want = groove(&c, 6.0, d, 10.0);
                assert!((map.top_mm[j * g.nx + i] - want).abs() < 1e-9, "{} d {d}", c.describe());
            }
        }
    }
}

#[test]
fn two_ball_passes_leave_the_textbook_scallop() {
    // Passes at y = 10 ± w/2; a ray runs exactly midway (y0 = −0.05 puts one at y = 10).
    let big_r = 3.0;
    for w in [0.5, 1.0, 2.0, 3.0] {
        let stock = DexelStock::block([0.0, -0.05, 0.0], [20.0, 20.0, 10.0], 0.1).unwrap();
        let c = Cutter::ball(big_r).unwrap();
        let ya = 10.0 - w / 2.0;
        let yb = 10.0 + w / 2.0;
        let sim = run(stock, &c, &[line([-5.0, ya, 5.0], [25.0, ya, 5.0]), line([25.0, yb, 5.0], [-5.0, yb, 5.0])]);
        let map = HeightMap::of(sim.stock());
        let stats = SimStats::of(&map, sim.stock(), &Design::PlaneZ(5.0));
        let h = big_r - (big_r * big_r - w * w / 4.0).sqrt();
        let g = map.grid;
        let j = ((10.0f64 + 0.05) / 0.1 - 0.5).round() as usize;
        assert!((g.y_mm(j) - 10.0).abs() < 1e-9);
        // Between the passes the highest ray is the midway one, at exactly h.
        let between = (0..g.ny).filter(|&j| g.y_mm(j) > ya && g.y_mm(j) < yb);
        let peak = between.map(|j| map.top_mm[j * g.nx + 50] - 5.0).fold(f64::MIN, f64::max);
        assert!((peak - h).abs() < 1e-9, "w {w}: {peak} vs {h}");
        assert!((map.top_mm[j * g.nx + 50] - 5.0 - h).abs() < 1e-9);
        assert_eq!(stats.gouge_rays, 0);
        assert!(stats.worst_gouge.is_none());
    }
}

#[test]
fn a_circular_arc_cuts_the_closed_form_ring_within_the_chord_tolerance() {
    // A full G02 circle of radius 8 around (10, 10), tip at z = 6, ball R 1.5.
    let text = "G21 G90 G17\nG00 X18 Y10 Z20\nG01 Z6 F500\nG02 X18 Y10 I-8 J0\nG00 Z20\n";
    let parsed = parse_program(text).unwrap();
    let pitch = 0.1;
    let tol = pitch / 10.0;
    let program = Program::from_toolpath(&parsed.toolpath, DVec3::ZERO, tol).unwrap();
    assert!(
        program.chord_error_mm <= tol * (1.0 + 1e-9) && program.chord_error_mm > 0.5 * tol,
        "{}",
        program.chord_error_mm
    );
    let c = Cutter::ball(1.5).unwrap();
    let stock = DexelStock::block([0.0, 0.0, 0.0], [20.0, 20.0, 10.0], pitch).unwrap();
    let mut sim = Simulation::new(stock, &c);
    sim.run(&program).unwrap();
    let map = HeightMap::of(sim.stock());
    let g = map.grid;
    let mut checked = 0;
    for j in 0..g.ny {
        for i in 0..g.nx {
            let d = ((g.x_mm(i) - 10.0).hypot(g.y_mm(j) - 10.0) - 8.0).abs();
            // The chords lie inside the circle by at most tol: the height equals the profile
            // at some distance within [d − tol, d + tol] of the exact ring.
            let got = map.top_mm[j * g.nx + i];
            if (d - 18.0).abs() < 1.5 + tol {
                continue; // near the plunge at (18, 10) the entry cuts deeper
            }
            let hi = groove(&c, 6.0, d + tol, 10.0);
            let lo = groove(&c, 6.0, (d - tol).max(0.0), 10.0);
            let near_entry = (g.x_mm(i) - 18.0).hypot(g.y_mm(j) - 10.0) < 1.6;
            if near_entry {
                continue;
            }
            assert!(got >= lo - 1e-9 && got <= hi + 1e-9, "({i}, {j}) d {d}: {got} not in [{lo}, {hi}]");
            checked += 1;
        }
    }
    assert!(checked > 30_000);
}

/// Whether a point lies in the simulated tool, from the cutter's own profile functions.
fn inside(c: &Cutter, tip: DVec3, axis: DVec3, p: DVec3) -> bool {
    let v = p - tip;
    let h = v.dot(axis);
    let rho = (v - h * axis).length();
    let top = ToolShape::of(c).top_mm;
    if !(0.0..=top).contains(&h) {
        return false;
    }
    if h >= c.corner_radius_mm {
        return rho <= c.radius_mm;
    }
    c.radius_at_height_mm(h).is_some_and(|r| rho <= r)
}

#[test]
fn tilted_cutters_cross_a_ray_where_a_point_scan_says() {
    let mut rng = Rng::new(7);
    for c in [Cutter::ball(2.0).unwrap(), Cutter::flat(2.0).unwrap(), Cutter::fillet(2.0, 0.6).unwrap()] {
        let tool = ToolShape::of(&c);
        let mut hits = 0;
        for _ in 0..400 {
            let axis = DVec3::new(rng.range(-1.0, 1.0), rng.range(-1.0, 1.0), rng.range(0.05, 1.0)).normalize();
            let tip = DVec3::new(rng.range(-0.5, 0.5), rng.range(-0.5, 0.5), 0.0);
            let (x, y) = (rng.range(-3.0, 3.0), rng.range(-3.0, 3.0));
            let span = tilted_span(&tool, tip, axis, x, y);
            // Scan z from −5 to 20 at 1e-3 mm.
            let step = 1e-3;
            let scan: Vec<f64> = (0..25_000)
                .map(|k| -5.0 + k as f64 * step)
                .filter(|&z| inside(&c, tip, axis, DVec3::new(x, y, z)))
                .collect();
            match (span, scan.first(), scan.last()) {
                (None, None, None) => {}
                (Some((lo, hi)), Some(&a), Some(&b)) => {
                    assert!((lo - a).abs() <= step + 1e-6, "{}: lo {lo} vs scan {a}", c.describe());
                    assert!((hi - b).abs() <= step + 1e-6, "{}: hi {hi} vs scan {b}", c.describe());
                    hits += 1;
                }
                (s, a, _) => {
                    // A graze thinner than the scan step may be seen by one and not the other.
                    if let Some((lo, hi)) = s {
                        assert!(hi - lo < 2.0 * step, "{}: span {lo}..{hi} but the scan finds nothing", c.describe());
                    } else {
                        assert!(scan.len() <= 2, "{}: scan finds {a:?}.. but no span", c.describe());
                    }
                }
            }
        }
        assert!(hits > 100, "{hits}");
    }
}

fn table_ac() -> Machine {
    Machine { limits_rad: [None, None], ..Machine::default() }
}

#[test]
fn a_five_axis_move_with_a_fixed_vertical_axis_matches_the_three_axis_closed_form() {
    // Table A/C at A = C = 0: the tip is (X, Y, Z), the axis +Z.
    let m = table_ac();
    let from = Joints { xyz_mm: DVec3::new(-4.0, 5.0, 6.0), rotary_rad: [0.0, 0.0] };
    let to = Joints { xyz_mm: DVec3::new(24.0, 5.0, 6.0), rotary_rad: [0.0, 0.0] };
    let pitch = 0.1;
    for c in [Cutter::ball(2.0).unwrap(), Cutter::flat(2.0).unwrap(), Cutter::fillet(2.0, 0.5).unwrap()] {
        let stock = || DexelStock::block([0.0, 0.0, 0.0], [20.0, 10.0, 10.0], pitch).unwrap();
        let five =
            run(stock(), &c, &[SimMove { kind: MoveKind::Joints { machine: m, from, to }, line: 0, rapid: false }]);
        let three = run(stock(), &c, &[line([-4.0, 5.0, 6.0], [24.0, 5.0, 6.0])]);
        let (a, b) = (HeightMap::of(five.stock()), HeightMap::of(three.stock()));
        // Samples at most s = one pitch apart: a ray at distance d from the move's line is
        // at most √(d² + s²/4) from the nearest sample's axis, so its height lies between
        // the profile at d (the exact envelope) and the profile there.
        let g = a.grid;
        let mut floor_worst: f64 = 0.0;
        for j in 0..g.ny {
            let d = (g.y_mm(j) - 5.0).abs();
            for i in 0..g.nx {
                let k = j * g.nx + i;
                assert!(a.top_mm[k] >= b.top_mm[k] - 1e-7, "{}: sampled cut deeper at ({i}, {j})", c.describe());
                let hi = groove(&c, 6.0, (d * d + pitch * pitch / 4.0).sqrt(), 10.0);
                assert!(a.top_mm[k] <= hi + 1e-7, "{}: ({i}, {j}) {} above {hi}", c.describe(), a.top_mm[k]);
                if d < 1.0 {
                    floor_worst = floor_worst.max(a.top_mm[k] - b.top_mm[k]);
                }
            }
        }
        // On the floor of a ball's groove that is the textbook cusp p²/(8R) at most.
        if c.corner_radius_mm == c.radius_mm {
            assert!(floor_worst <= pitch * pitch / (8.0 * 2.0) * 1.01, "{floor_worst}");
        }
    }
}

#[test]
fn five_axis_sampling_error_stays_within_the_documented_bound() {
    // Table A/C, A turning 0 → 30° while X runs: compare the ball's closed-form swept
    // segments (default tolerance: half a pitch) and the flat end mill's pose sampling (no
    // body point moves more than a pitch between samples) with a 20× denser pose sampling.
    let m = table_ac();
    let from = Joints { xyz_mm: DVec3::new(2.0, 5.0, 7.0), rotary_rad: [0.0, 0.0] };
    let to = Joints { xyz_mm: DVec3::new(18.0, 5.0, 7.0), rotary_rad: [30f64.to_radians(), 0.0] };
    let pitch = 0.2;
    let mv = SimMove { kind: MoveKind::Joints { machine: m, from, to }, line: 0, rapid: false };
    let stock = || DexelStock::block([-10.0, -15.0, 0.0], [30.0, 25.0, 10.0], pitch).unwrap();
    // Flutes longer than the stock is deep: the whole sweep cuts (with the default 3·R the
    // flutes' top edge would leave a slab whose edge is a wall the test cannot tell).
    let long = BodySpec { flute_mm: Some(12.0), ..BodySpec::default() };
    for c in [Cutter::ball(2.0).unwrap(), Cutter::flat(2.0).unwrap()].map(|c| c.with_body(&long).unwrap()) {
        let mut coarse = Simulation::new(stock(), &c);
        let tol = coarse.sweep_tol_mm();
        assert_eq!(tol.is_some(), c.corner_radius_mm == c.radius_mm);
        coarse.apply(&mv);
        let mut fine = Simulation::new(stock(), &c).with_sample_step(pitch / 20.0);
        fine.apply(&mv);
        assert!(fine.counters().samples > 15 * coarse.counters().samples);
        let (a, b) = (HeightMap::of(coarse.stock()), HeightMap::of(fine.stock()));
        // Hausdorff within e (the sweep tolerance, or the sample step) plus the reference's own
        // cusp: off the walls (rays whose reference neighbours lie within one pitch in height,
        // a slope of at most 1) the heights agree within √2·e. On a wall a sideways error of e
        // is a vertical one of any size, so those rays are only counted.
        let e = tol.unwrap_or(pitch);
        let g = a.grid;
        let (mut worst, mut walls, mut machined): (f64, usize, usize) = (0.0, 0, 0);
        for j in 1..g.ny - 1 {
            for i in 1..g.nx - 1 {
                let k = j * g.nx + i;
                if b.top_mm[k] >= 10.0 {
                    continue;
                }
                machined += 1;
                let steep =
                    [k - 1, k + 1, k - g.nx, k + g.nx].iter().any(|&n| (b.top_mm[n] - b.top_mm[k]).abs() > pitch);
                if steep {
                    walls += 1;
                } else {
                    worst = worst.max((a.top_mm[k] - b.top_mm[k]).abs());
                }
            }
        }
        assert!(machined - walls > 500, "{}: {walls} of {machined}", c.describe());
        assert!(worst > 0.0 && worst <= std::f64::consts::SQRT_2 * e, "{}: {worst} (e = {e})", c.describe());
        // Removed volumes agree to the band of width e around the cut's surface.
        let (va, vb) = (coarse.counters().removed_mm3, fine.counters().removed_mm3);
        assert!((va - vb).abs() < e * 0.1 * vb, "{}: {va} vs {vb}", c.describe());
        eprintln!(
            "{}: worst {worst:.4} mm off the walls (e = {e}), {walls} wall rays of {machined}, volumes {va:.3} / {vb:.3} mm³, sagitta {:.2e}",
            c.describe(),
            coarse.counters().sweep_sagitta_mm
        );
    }
}

#[test]
fn ball_segments_of_a_straight_tilted_move_are_exact() {
    // A fixed tilted axis and a straight tip path (table A/C at A = 20°, C = 0: linear joints
    // give a linear workpiece motion): the envelope is exactly the points within R of the
    // parallelogram the axis sweeps, so the one-segment sweep and a dense pose sampling agree
    // up to the sampling's own cusp, and the swept result never cuts less than any pose.
    let m = table_ac();
    let a = 20f64.to_radians();
    let from = Joints { xyz_mm: DVec3::new(1.0, 3.0, 8.0), rotary_rad: [a, 0.0] };
    let to = Joints { xyz_mm: DVec3::new(12.0, 4.0, 7.5), rotary_rad: [a, 0.0] };
    let pitch = 0.1;
    let c = Cutter::ball(1.5).unwrap();
    let mv = SimMove { kind: MoveKind::Joints { machine: m, from, to }, line: 0, rapid: false };
    let stock = || DexelStock::block([-5.0, -8.0, 0.0], [20.0, 12.0, 6.0], pitch).unwrap();
    let mut seg = Simulation::new(stock(), &c);
    seg.apply(&mv);
    assert_eq!(seg.counters().samples, 2, "one segment");
    let step = pitch / 20.0;
    let mut dense = Simulation::new(stock(), &c).with_sample_step(step);
    dense.apply(&mv);
    let (s, d) = (HeightMap::of(seg.stock()), HeightMap::of(dense.stock()));
    let cusp = step * step / (8.0 * 1.5) + 1e-9;
    let mut n = 0;
    for k in 0..s.top_mm.len() {
        assert!(s.top_mm[k] <= d.top_mm[k] + 1e-9, "segment cut less at {k}: {} > {}", s.top_mm[k], d.top_mm[k]);
        let flat =
            [k.wrapping_sub(1), k + 1].iter().all(|&q| q < d.top_mm.len() && (d.top_mm[q] - d.top_mm[k]).abs() < pitch);
        if flat && d.top_mm[k] < 6.0 {
            assert!(d.top_mm[k] - s.top_mm[k] <= 4.0 * cusp, "{k}: {} vs {}", s.top_mm[k], d.top_mm[k]);
            n += 1;
        }
    }
    assert!(n > 500, "{n}");
}

#[test]
fn deviation_from_a_scene_surface_matches_the_plane_and_a_sphere_in_closed_form() {
    // A ball groove at tip height 7 through a block; the design as a plane surface z = 7.5
    // (normal +Z, through the projection code) must give height − 7.5 on every machined ray,
    // and a sphere of radius 40 centred 40 below (7.5 at its top) |p − c| − 40.
    use interpolab::geom::{Domain, Frame, ParamRange, ParamUnit, Plane, Sphere, Surface};
    let c = Cutter::ball(2.0).unwrap();
    let stock = DexelStock::block([0.0, 0.0, 0.0], [10.0, 6.0, 8.0], 0.1).unwrap();
    let sim = run(stock, &c, &[line([-3.0, 3.0, 7.0], [13.0, 3.0, 7.0])]);
    let map = HeightMap::of(sim.stock());
    let plane = Surface::Plane(Plane::new(DVec3::new(0.0, 0.0, 7.5), DVec3::Z, DVec3::X, [-20.0, 20.0], [-20.0, 20.0]));
    let centre = DVec3::new(5.0, 3.0, 7.5 - 40.0);
    // Polar axis along X so the sphere's top (along e2 = X × Y = Z) lies on its equator,
    // away from the parametrisation's poles.
    let sphere = Surface::Sphere(Sphere {
        center: centre,
        frame: Frame::from_axis(DVec3::X, Some(DVec3::Y)),
        radius: 40.0,
        sign: 1.0,
        domain: Domain {
            u: ParamRange::new(-std::f64::consts::PI, std::f64::consts::PI, ParamUnit::Angle),
            v: ParamRange::new(-1.5, 1.5, ParamUnit::Angle),
        },
    });
    let by_plane = SimStats::of(&map, sim.stock(), &Design::Surfaces(vec![plane]));
    let by_z = SimStats::of(&map, sim.stock(), &Design::PlaneZ(7.5));
    let by_sphere = SimStats::of(&map, sim.stock(), &Design::Surfaces(vec![sphere]));
    let g = map.grid;
    let mut n = 0;
    for k in 0..g.len() {
        let (Some(a), Some(b)) = (by_plane.deviation_mm[k], by_z.deviation_mm[k]) else {
            assert!(by_plane.deviation_mm[k].is_none() && by_z.deviation_mm[k].is_none());
            continue;
        };
        assert!((a - b).abs() < 1e-9, "{a} vs {b}");
        let p = DVec3::new(g.x_mm(k % g.nx), g.y_mm(k / g.nx), map.top_mm[k]);
        let s = by_sphere.deviation_mm[k].unwrap();
        assert!((s - ((p - centre).length() - 40.0)).abs() < 1e-7, "{s}");
        n += 1;
    }
    assert!(n > 1000);
    assert!(by_z.gouge_rays > 0 && by_z.worst_gouge.unwrap().0 < -0.49);
}

fn checksum(stock: &DexelStock) -> u64 {
    // FNV-1a over every interval's bits.
    let mut h: u64 = 0xcbf2_9ce4_8422_2325;
    for k in 0..stock.grid().len() {
        for iv in stock.intervals(k) {
            for v in [iv.lo_mm.to_bits(), iv.hi_mm.to_bits(), k as u64] {
                h ^= v;
                h = h.wrapping_mul(0x0000_0100_0000_01b3);
            }
        }
    }
    h
}

#[test]
fn the_same_program_gives_identical_rays() {
    // Lines only (no sin/cos: only IEEE-exact operations and sqrt), three cutters, sloped,
    // horizontal and plunging moves — bit-identical on every platform.
    let moves = [
        line([-2.0, 1.0, 8.0], [12.0, 9.0, 5.5]),
        line([12.0, 9.0, 5.5], [3.0, 4.0, 5.5]),
        line([3.0, 4.0, 5.5], [3.0, 4.0, 2.0]),
        line([6.0, 2.0, 9.0], [1.0, 7.5, 6.25]),
    ];
    let mut sums = Vec::new();
    for c in [Cutter::ball(1.5).unwrap(), Cutter::flat(1.5).unwrap(), Cutter::fillet(1.5, 0.5).unwrap()] {
        let a = run(DexelStock::block([0.0, 0.0, 0.0], [10.0, 10.0, 8.0], 0.05).unwrap(), &c, &moves);
        let b = run(DexelStock::block([0.0, 0.0, 0.0], [10.0, 10.0, 8.0], 0.05).unwrap(), &c, &moves);
        assert_eq!(checksum(a.stock()), checksum(b.stock()));
        sums.push(checksum(a.stock()));
    }
    // Tilted cutters (the 5-axis sample) at fixed poses: only arithmetic and sqrt too.
    let mut h: u64 = 0xcbf2_9ce4_8422_2325;
    for c in [Cutter::ball(1.5).unwrap(), Cutter::flat(1.5).unwrap(), Cutter::fillet(1.5, 0.5).unwrap()] {
        let tool = ToolShape::of(&c);
        let axis = DVec3::new(0.3, -0.2, 0.9).normalize();
        for k in 0..4096 {
            let (x, y) = (f64::from(k % 64) * 0.06 - 1.9, f64::from(k / 64) * 0.06 - 1.9);
            if let Some((lo, hi)) = tilted_span(&tool, DVec3::new(0.1, 0.2, 0.3), axis, x, y) {
                for v in [lo.to_bits(), hi.to_bits()] {
                    h ^= v;
                    h = h.wrapping_mul(0x0000_0100_0000_01b3);
                }
            }
        }
    }
    sums.push(h);
    // The ball's closed-form swept segment (a 5-axis move's piece) between fixed poses: only
    // arithmetic and sqrt too (the poses' sin/cos are left out: libm may differ per platform).
    let mut h: u64 = 0xcbf2_9ce4_8422_2325;
    let (a0, a1) = (DVec3::new(0.3, -0.2, 0.9).normalize(), DVec3::new(-0.1, 0.25, 0.95).normalize());
    let seg = BallSegment::new(1.5, DVec3::new(0.1, 0.2, 1.8), a0, DVec3::new(0.9, -0.4, 1.6), a1, 2.5, 0.01);
    let mut hits = 0;
    for k in 0..4096 {
        let (x, y) = (f64::from(k % 64) * 0.08 - 2.2, f64::from(k / 64) * 0.08 - 2.6);
        if let Some((lo, hi)) = seg.span(x, y) {
            hits += 1;
            for v in [lo.to_bits(), hi.to_bits()] {
                h ^= v;
                h = h.wrapping_mul(0x0000_0100_0000_01b3);
            }
        }
    }
    assert!(hits > 1000 && hits < 4096, "{hits}");
    sums.push(h);
    // Native x86-64 values; the wasm32 build under Node must reproduce them bit for bit.
    assert_eq!(sums, EXPECTED_SUMS, "ray checksums differ from the native run");
}

const EXPECTED_SUMS: [u64; 5] = [
    14_732_471_149_034_804_484,
    16_391_303_642_899_386_748,
    8_957_791_105_948_524_568,
    2_068_440_001_761_538_239,
    15_668_402_580_591_005_269,
];

#[test]
fn bad_stock_and_huge_grids_are_refused_with_a_message() {
    let e = DexelStock::block([0.0, 0.0, 0.0], [10.0, 10.0, 10.0], 0.0).unwrap_err();
    assert!(e.to_string().contains("pitch"), "{e}");
    let e = DexelStock::block([0.0, 0.0, 5.0], [10.0, 10.0, 5.0], 0.1).unwrap_err();
    assert!(e.to_string().contains("z range"), "{e}");
    let e = DexelStock::block([0.0, 0.0, 0.0], [1000.0, 1000.0, 10.0], 0.01).unwrap_err();
    assert!(e.to_string().contains("raise the pitch"), "{e}");
    let stock = DexelStock::block([0.0, 0.0, 0.0], [1024.0, 1024.0, 10.0], 1.0).unwrap();
    assert_eq!(stock.grid().len(), 1 << 20);
    assert!(stock.memory_bytes() < 64 << 20, "{}", stock.memory_bytes());
}

#[test]
fn the_deviation_is_the_signed_distance_to_the_union_of_the_torus_and_the_plate() {
    // examples/torus-plate-head-bc.json: a torus (centre circle ρ = 40 in z = 0, tube 15,
    // material inside the tube) standing on a tilted plate (through (0, 0, 4), normal
    // n = (0, −0.2079, 0.9781), material below). The part is their union.
    use interpolab::simulate::part_signed_distance;
    // Compiled in, so the wasm32 build (no file system) runs it too.
    let scene =
        interpolab::scene::Scene::from_json(include_str!("../../../examples/torus-plate-head-bc.json")).unwrap();
    let surfaces = interpolab::crease::CreaseJob::from_scene(&scene).unwrap().surfaces.to_vec();
    let n = DVec3::new(0.0, -0.207_911_690_817_759_37, 0.978_147_600_733_805_6);
    let plate = |p: DVec3| n.dot(p - DVec3::new(0.0, 0.0, 4.0));
    let tube = |p: DVec3| (glam::DVec2::new(p.truncate().length() - 40.0, p.z)).length() - 15.0;
    let union = |p: DVec3| plate(p).min(tube(p));
    // 1. Just above the plate but 1.4 mm inside the ring: the nearest surface (the plate,
    //    +3 µm) would call it stock left; the part says a 1.4 mm gouge of the ring.
    let p1 = DVec3::new(53.0, 0.0, 4.0 + 0.003 / n.z);
    assert!(plate(p1) > 0.0 && plate(p1) < 0.004 && tube(p1) < -1.3);
    // 2. Outside both, nearer the plate; 3. above the ring's top; 4. beside the ring on the
    //    far side of the plate's tilt, nearer the ring.
    let points = [p1, DVec3::new(60.0, 0.0, 6.0), DVec3::new(0.0, 40.0, 15.2), DVec3::new(-57.0, -3.0, 5.5)];
    for (k, p) in points.into_iter().enumerate() {
        let mut guesses = vec![None; surfaces.len()];
        let d = part_signed_distance(&surfaces, p, &mut guesses).unwrap();
        assert!((d - union(p)).abs() < 1e-6, "point {k}: {d} vs {}", union(p));
    }
    // A walk of 0.1 mm steps from beside the ring, up its outer side, over its top and down
    // into the hole, each step seeded by the previous one (as the scan does ray by ray):
    // every step on the closed form, nearest-surface switches and the tube's sides included.
    let mut seeds = vec![None; surfaces.len()];
    let mut switched = [false; 2];
    for k in 0..=700 {
        let t = f64::from(k) / 700.0;
        let p = DVec3::new(62.0 - 40.0 * t, 1.0, 5.0 + 12.0 * (std::f64::consts::PI * t).sin());
        let d = part_signed_distance(&surfaces, p, &mut seeds).unwrap();
        assert!((d - union(p)).abs() < 1e-6, "step {k} at {p}: {d} vs {}", union(p));
        switched[usize::from(plate(p) < tube(p))] = true;
    }
    assert!(switched[0] && switched[1], "the walk meets both surfaces nearest");
}

/// A replay of the move slider from a stock the worker kept
/// (`jobs::simulate_run::session::Session`) gives the stock of a fresh run to the same move bit
/// for bit — natively and in the wasm32 build the browser's worker runs.
#[test]
fn a_replay_from_a_kept_stock_is_the_fresh_run_bit_for_bit() {
    use interpolab::jobs::NoProgress;
    use interpolab::jobs::simulate_run::request::Request;
    use interpolab::jobs::simulate_run::run::run_in_session;
    use interpolab::simulate::bench::BenchKind;
    let first = Request::benchmark(BenchKind::FiveAxis, 200, 0.8).unwrap();
    let session = std::sync::Mutex::new(None);
    let whole = run_in_session(&first, &mut NoProgress, &session).unwrap();
    assert_eq!(whole.resumed_from, 0);
    // 64 × 64 rays: eight stocks kept, every ⌈200 / 9⌉ = 23 moves.
    for (k, from) in [(57, 46), (150, 138), (199, 184)] {
        let replay = Request { target: Some(k), resume: true, ..first.clone() };
        let fast = run_in_session(&replay, &mut NoProgress, &session).unwrap();
        let fresh = run_in_session(&Request { resume: false, ..replay }, &mut NoProgress, &std::sync::Mutex::new(None))
            .unwrap();
        assert_eq!((fast.resumed_from, fresh.resumed_from), (from, 0), "move {k}");
        assert_eq!(fast.counters.moves, k);
        assert_eq!(fast.counters.ray_updates, fresh.counters.ray_updates);
        assert_eq!(fast.counters.removed_mm3.to_bits(), fresh.counters.removed_mm3.to_bits());
        assert_eq!(fast.map.machined, fresh.map.machined);
        assert!(fast.map.top_mm.iter().zip(&fresh.map.top_mm).all(|(a, b)| a.to_bits() == b.to_bits()), "move {k}");
        assert_eq!(fast.stats, fresh.stats);
    }
}
