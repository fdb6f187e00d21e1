//! Seed 001 on surfaces it has never seen: random B-spline patches (saddles, domes, ridges,
//! valleys, curvature changing sign), sphere, cylinder and torus patches, with random
//! fillet-end cutters and scallop heights, drawn from a seed. Each job's CL data is cut by an
//! independent judge — the material left at a grid of surface points by the cutter swept
//! between the CL rows as a machine moves it (tip and axis interpolated linearly), the
//! cutter's exact solid, paths not linked — over the middle 60 % of the part.
//!
//! The scallop must stay within h and no point of the swept cutter may reach below the design
//! by more than the tolerance E, between the poses as well as at them.
//!
//! Where the corrector of the side steps cannot hold the cusp, the job names the place
//! (`PathSet::scallop_flags`): points within 2·R of a flag, or of a refused CC point, are
//! counted as flagged and left out of the bounds; a job refused with its reason passes.
//!
//! CI runs a sample (`unseen_surfaces_keep_h_and_e`); the longer run draws more jobs on a
//! finer grid and prints every job's numbers:
//! `UNSEEN_JOBS=40 UNSEEN_CELLS=160 cargo test --release --no-default-features --test core -- fillet_unseen --nocapture`
//! (`UNSEEN_SEED` picks another family).

use glam::{DVec2, DVec3};
use interpolab::fillet::paths::{PathSet, iso_scallop};
use interpolab::fillet::{FinishError, FinishJob, PartSamples};
use interpolab::geom::{Cutter, ParametricSurface};
use interpolab::scene::finish::FinishScene;

use crate::fillet::depth_inside;
use crate::support::Rng;

/// The kinds of surface the family draws.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum Kind {
    Bspline,
    Sphere,
    Cylinder,
    Torus,
}

/// One drawn job: its description and the parsed scene.
struct Drawn {
    what: String,
    job: FinishJob,
}

fn f(x: f64) -> String {
    format!("{x:.6}")
}

fn cutter_json(rng: &mut Rng) -> (String, String, f64) {
    let big_r = rng.range(3.0, 8.0);
    let r = rng.range(0.5, 2.5_f64.min(big_r - 0.5));
    let h = rng.range(0.002, 0.020);
    let e = (h / 12.0).clamp(0.0003, 0.001);
    let json = format!(
        r#""cutter": {{ "radius": {}, "corner_radius": {} }}, "strategy": "matched", "scallop": {}, "tolerance": {}, "max_step": 1.0"#,
        f(big_r),
        f(r),
        f(h),
        f(e)
    );
    (json, format!("R {big_r:.2} r {r:.2} h {:.1} µm E {:.2} µm", h * 1e3, e * 1e3), h)
}

/// A random clamped bicubic B-spline patch: 4–7 control points each way (so 0–3 interior
/// knots, spaced unevenly), 30–55 × 25–45 mm, heights from a base shape (saddle, dome, ridge,
/// valley or none) plus a random bump per control point, ±0.6–2.2 mm.
fn bspline(rng: &mut Rng) -> (String, String) {
    let nu = 4 + (rng.next_f64() * 4.0) as usize;
    let nv = 4 + (rng.next_f64() * 4.0) as usize;
    let (wu, wv) = (rng.range(30.0, 55.0), rng.range(25.0, 45.0));
    let amp = rng.range(0.6, 2.2);
    let shape = (rng.next_f64() * 5.0) as usize;
    let shapes = ["flat", "saddle", "dome", "ridge", "valley"];
    let knots = |rng: &mut Rng, n: usize| {
        let inner = n - 4;
        let mut k: Vec<f64> = vec![0.0; 4];
        let mut pos: Vec<f64> =
            (0..inner).map(|i| (i as f64 + 1.0 + rng.range(-0.3, 0.3)) / (inner as f64 + 1.0)).collect();
        pos.sort_by(f64::total_cmp);
        k.extend(pos);
        k.extend([1.0; 4]);
        k
    };
    let (ku, kv) = (knots(rng, nu), knots(rng, nv));
    let mut rows = Vec::new();
    for i in 0..nu {
        let mut row = Vec::new();
        for j in 0..nv {
            let (s, t) = (i as f64 / (nu - 1) as f64 - 0.5, j as f64 / (nv - 1) as f64 - 0.5);
            let base = match shape {
                1 => 4.0 * (s * s - t * t),
                2 => -4.0 * (s * s + t * t),
                3 => -4.0 * t * t,
                4 => 4.0 * s * s,
                _ => 0.0,
            };
            let z = amp * (0.6 * base + rng.range(-1.0, 1.0));
            row.push(format!("[{}, {}, {}]", f(wu * (s + 0.5)), f(wv * (t + 0.5)), f(z)));
        }
        rows.push(format!("[{}]", row.join(", ")));
    }
    let list = |k: &[f64]| k.iter().map(|x| f(*x)).collect::<Vec<_>>().join(", ");
    (
        format!(
            r#"{{ "type": "nurbs", "degree": [3, 3], "knots_u": [{}], "knots_v": [{}], "points": [{}] }}"#,
            list(&ku),
            list(&kv),
            rows.join(", ")
        ),
        format!("B-spline {nu}×{nv} {:.0}×{:.0} mm {} ±{amp:.1} mm", wu, wv, shapes[shape]),
    )
}

/// A sphere patch around its top (polar axis along x, so no pole inside): a dome, or a bowl
/// (cutter inside) when `inward`.
fn sphere(rng: &mut Rng) -> (String, String) {
    let rho = rng.range(30.0, 80.0);
    let inward = rng.next_f64() < 0.3;
    let rho = if inward { rho.max(45.0) } else { rho };
    let (su, sv) = (rng.range(30.0, 45.0) / rho, rng.range(25.0, 40.0) / rho);
    let (su, sv) = (su.to_degrees() * 0.5, sv.to_degrees() * 0.5);
    (
        format!(
            r#"{{ "type": "sphere", "center": [0, 0, 0], "radius": {}, "axis": [1, 0, 0], "ref_dir": [0, 1, 0], "domain": {{ "u": [{}, {}], "v": [{}, {}] }}, "normal": "{}" }}"#,
            f(rho),
            f(90.0 - su),
            f(90.0 + su),
            f(-sv),
            f(sv),
            if inward { "inward" } else { "outward" }
        ),
        format!("sphere ρ {rho:.0} mm {}", if inward { "bowl" } else { "dome" }),
    )
}

/// A cylinder patch around its top (axis along x), outside or (a trough) inside.
fn cylinder(rng: &mut Rng) -> (String, String) {
    let inward = rng.next_f64() < 0.3;
    let rho = rng.range(if inward { 40.0 } else { 20.0 }, 70.0);
    let su = (rng.range(30.0, 45.0) / rho).to_degrees() * 0.5;
    let len = rng.range(25.0, 45.0);
    (
        format!(
            r#"{{ "type": "cylinder", "origin": [0, 0, 0], "axis": [1, 0, 0], "radius": {}, "ref_dir": [0, 1, 0], "domain": {{ "u": [{}, {}], "v": [0, {}] }}, "normal": "{}" }}"#,
            f(rho),
            f(90.0 - su),
            f(90.0 + su),
            f(len),
            if inward { "inward" } else { "outward" }
        ),
        format!("cylinder ρ {rho:.0} mm {}", if inward { "trough" } else { "outside" }),
    )
}

/// A torus patch (axis along y): its outer top (convex both ways) or its inner side seen from
/// the tube's inside (concave across, convex along: a saddle).
fn torus(rng: &mut Rng) -> (String, String) {
    let big = rng.range(45.0, 80.0);
    let small = rng.range(20.0, 35.0);
    let saddle = rng.next_f64() < 0.5;
    let su = (rng.range(30.0, 45.0) / big).to_degrees() * 0.5;
    let sv = (rng.range(20.0, 35.0) / small).to_degrees() * 0.5;
    let vc = if saddle { 180.0 - sv - 1.0 } else { 0.0 };
    (
        format!(
            r#"{{ "type": "torus", "center": [0, 0, 0], "axis": [0, 1, 0], "major_radius": {}, "minor_radius": {}, "ref_dir": [1, 0, 0], "domain": {{ "u": [{}, {}], "v": [{}, {}] }}, "normal": "{}" }}"#,
            f(big),
            f(small),
            f(-90.0 - su),
            f(-90.0 + su),
            f(vc - sv),
            f(vc + sv),
            if saddle { "inward" } else { "outward" }
        ),
        format!("torus {big:.0}/{small:.0} mm {}", if saddle { "saddle" } else { "outer" }),
    )
}

/// Job `index` of the family `seed`: the kinds in turn (B-splines twice as often).
fn draw(seed: u64, index: u64) -> Drawn {
    let mut rng = Rng::new(seed.wrapping_mul(1_000_003).wrapping_add(index));
    let kinds = [Kind::Bspline, Kind::Sphere, Kind::Bspline, Kind::Torus, Kind::Bspline, Kind::Cylinder];
    let kind = kinds[(index % kinds.len() as u64) as usize];
    let (surface, shape) = match kind {
        Kind::Bspline => bspline(&mut rng),
        Kind::Sphere => sphere(&mut rng),
        Kind::Cylinder => cylinder(&mut rng),
        Kind::Torus => torus(&mut rng),
    };
    let (cutter, tool, _) = cutter_json(&mut rng);
    let json = format!(
        r#"{{ "format": "interpolab-scene/1", "name": "unseen {index}", "surfaces": [{surface}], "finish": {{ {cutter} }} }}"#
    );
    let job = match FinishScene::from_json(&json).and_then(|s| s.job()) {
        Ok(j) => j,
        Err(e) => panic!("job {index} ({shape}): the drawn scene is invalid: {e}\n{json}"),
    };
    Drawn { what: format!("#{index} {shape}, {tool}"), job }
}

/// A CL row as the judge reads it.
#[derive(Clone, Copy)]
struct Row {
    tip: DVec3,
    axis: DVec3,
}

/// The swept cutters of a path set, from its CL rows alone, with the rows binned by their
/// tips for the search.
struct Judge {
    cutter: Cutter,
    paths: Vec<Vec<Row>>,
    bin: f64,
    bins: std::collections::HashMap<(i64, i64, i64), Vec<(u32, u32)>>,
}

impl Judge {
    fn new(cutter: Cutter, set: &PathSet) -> Self {
        let paths: Vec<Vec<Row>> =
            set.paths.iter().map(|p| p.nodes.iter().map(|n| Row { tip: n.tip, axis: n.axis }).collect()).collect();
        let bin = 2.0;
        let mut bins: std::collections::HashMap<(i64, i64, i64), Vec<(u32, u32)>> = std::collections::HashMap::new();
        for (k, p) in paths.iter().enumerate() {
            for (j, row) in p.iter().enumerate() {
                let key = Self::key(bin, row.tip);
                bins.entry(key).or_default().push((k as u32, j as u32));
            }
        }
        Self { cutter, paths, bin, bins }
    }

    fn key(bin: f64, p: DVec3) -> (i64, i64, i64) {
        ((p.x / bin).floor() as i64, (p.y / bin).floor() as i64, (p.z / bin).floor() as i64)
    }

    /// The material left at `p` (mm; negative: `p` lies that deep inside a swept cutter, a
    /// gouge) and the path that leaves it: the smallest distance from `p` to the cutter moved
    /// along every chord whose rows' tips lie within 2·R + 2 mm of `p` (the cutter's reach),
    /// each chord by golden section on its parameter after a bound from its ends (the
    /// distance changes along a chord by at most the tip's travel plus the axis' turn times
    /// the lever to `p`).
    fn left(&self, p: DVec3) -> Option<(f64, usize, usize, f64)> {
        let reach = 2.0 * self.cutter.radius_mm + 2.0;
        let n = (reach / self.bin).ceil() as i64;
        let (kx, ky, kz) = Self::key(self.bin, p);
        let mut near: std::collections::BTreeMap<u32, (u32, u32)> = std::collections::BTreeMap::new();
        for dx in -n..=n {
            for dy in -n..=n {
                for dz in -n..=n {
                    let Some(list) = self.bins.get(&(kx + dx, ky + dy, kz + dz)) else { continue };
                    for &(k, j) in list {
                        if (self.paths[k as usize][j as usize].tip - p).length() > reach {
                            continue;
                        }
                        let e = near.entry(k).or_insert((j, j));
                        e.0 = e.0.min(j);
                        e.1 = e.1.max(j);
                    }
                }
            }
        }
        let mut best: Option<(f64, usize, usize, f64)> = None;
        let d = |a: &Row, b: &Row, t: f64| {
            -depth_inside(&self.cutter, a.tip.lerp(b.tip, t), a.axis.lerp(b.axis, t).normalize(), p)
        };
        for (&k, &(j0, j1)) in &near {
            let rows = &self.paths[k as usize];
            let first = (j0 as usize).saturating_sub(1);
            let last = (j1 as usize + 1).min(rows.len() - 1);
            for j in first..last {
                let (a, b) = (&rows[j], &rows[j + 1]);
                let (d0, d1) = (d(a, b, 0.0), d(a, b, 1.0));
                let lever = (p - a.tip).length() + d0.abs() + self.cutter.corner_radius_mm;
                let lip = (b.tip - a.tip).length() + (b.axis - a.axis).length() * lever;
                let bound = 0.5 * (d0 + d1 - lip);
                let mut m = if d0 <= d1 { (d0, 0.0) } else { (d1, 1.0) };
                if best.is_none_or(|(bl, ..)| bound < bl) {
                    let phi = 0.5 * (5f64.sqrt() - 1.0);
                    let (mut lo, mut hi) = (0.0f64, 1.0f64);
                    for _ in 0..40 {
                        let x1 = hi - phi * (hi - lo);
                        let x2 = lo + phi * (hi - lo);
                        if d(a, b, x1) < d(a, b, x2) { hi = x2 } else { lo = x1 }
                    }
                    let t = 0.5 * (lo + hi);
                    let dt = d(a, b, t);
                    if dt < m.0 {
                        m = (dt, t);
                    }
                }
                if best.is_none_or(|(bl, ..)| m.0 < bl) {
                    best = Some((m.0, k as usize, j, m.1));
                }
            }
        }
        best
    }
}

/// What the judge measured on one job, over the middle 60 % of the domain.
struct Measured {
    points: usize,
    /// Largest material left (mm).
    max_left: f64,
    /// Its 99.9th percentile (mm).
    p999: f64,
    /// Points above 1.05·h, 1.10·h.
    over_105: usize,
    over_110: usize,
    /// Deepest point of the design inside a swept cutter (mm, ≥ 0).
    deepest: f64,
    /// Where the largest material left lies (uv) and its path.
    worst_uv: DVec2,
    worst_path: usize,
    /// Points within 2·R of a refused CC point (the job flagged them).
    near_refused: usize,
    /// The worst point's chord and place on it; the deepest point's uv, path, chord, place.
    worst_at: (usize, f64),
    deep_at: (DVec2, usize, usize, f64),
}

fn measure(job: &FinishJob, set: &PathSet, cells: usize) -> Measured {
    let judge = Judge::new(set.strategy.cutter_for(&job.cutter), set);
    let d = job.surface.domain();
    let h = job.options.scallop_mm;
    let mut left = Vec::new();
    let (mut worst_uv, mut worst_path, mut near_refused) = (DVec2::ZERO, 0, 0);
    let mut max_left = f64::NEG_INFINITY;
    let mut deepest = 0.0f64;
    let (mut deep_at, mut worst_at) = ((DVec2::ZERO, 0, 0, 0.0), (0, 0.0));
    let flag = 2.0 * job.cutter.radius_mm;
    // `UNSEEN_FLAGGED=1`: the flagged places judged too (how far over h they really are).
    let count_flagged = std::env::var("UNSEEN_FLAGGED").is_ok();
    for i in 0..=cells {
        for j in 0..=cells {
            let fu = 0.2 + 0.6 * i as f64 / cells as f64;
            let fv = 0.2 + 0.6 * j as f64 / cells as f64;
            let uv = DVec2::new(d.u.min + fu * d.u.width(), d.v.min + fv * d.v.width());
            let p = job.surface.point_at(uv);
            if set.refused.iter().any(|r| (r.point - p).length() < flag)
                || (!count_flagged && set.scallop_flags.iter().any(|r| (r.point - p).length() < flag))
            {
                near_refused += 1;
                continue;
            }
            let Some((l, k, jr, t)) = judge.left(p) else {
                // No cutter within reach: material left uncut (far more than h).
                left.push(f64::INFINITY);
                if max_left.is_finite() || max_left == f64::NEG_INFINITY {
                    max_left = f64::INFINITY;
                    worst_uv = uv;
                }
                continue;
            };
            if -l > deepest {
                deepest = -l;
                deep_at = (uv, k, jr, t);
            }
            if l > max_left {
                max_left = l;
                worst_uv = uv;
                worst_path = k;
                worst_at = (jr, t);
            }
            left.push(l);
        }
    }
    let mut sorted = left.clone();
    sorted.sort_by(f64::total_cmp);
    let p999 = sorted.get(((sorted.len() as f64 - 1.0) * 0.999).round() as usize).copied().unwrap_or(0.0);
    Measured {
        points: left.len(),
        max_left,
        p999,
        over_105: left.iter().filter(|&&l| l > 1.05 * h).count(),
        over_110: left.iter().filter(|&&l| l > 1.10 * h).count(),
        deepest,
        worst_uv,
        worst_path,
        near_refused,
        worst_at,
        deep_at,
    }
}

fn env(name: &str, default: u64) -> u64 {
    std::env::var(name).ok().and_then(|s| s.parse().ok()).unwrap_or(default)
}

/// Every job of the sample: built, then judged. The scallop over the middle within 1.05·h at
/// the 99.9th percentile and 1.10·h at the most, no point deeper than E — or the job refused
/// with a reason, or the points it could not meet flagged (refused CC points, left out).
#[test]
fn unseen_surfaces_keep_h_and_e() {
    let seed = env("UNSEEN_SEED", 24);
    // CI's sample: the jobs of family 24 that build in well under a second in release (the
    // sphere, torus and cylinder patches and two B-splines), and three of them again with the
    // matched cutter free to tilt 10° (issue 24's item 4); the B-splines with 2–8 µm
    // scallops take 2–4 s each, too long for a debug build: the long run draws them.
    // `UNSEEN_JOBS=40`: jobs 0–39; `UNSEEN_JOBS=4,35`: those two; `UNSEEN_TILT=10`: those
    // with a tilt of up to 10°.
    let tilt_deg: f64 = std::env::var("UNSEEN_TILT").ok().and_then(|s| s.parse().ok()).unwrap_or(0.0);
    let jobs: Vec<(u64, f64)> = match std::env::var("UNSEEN_JOBS") {
        Ok(s) if s.contains(',') => s.split(',').filter_map(|x| x.trim().parse().ok()).map(|j| (j, tilt_deg)).collect(),
        Ok(s) => (0..s.parse().unwrap_or(0)).map(|j| (j, tilt_deg)).collect(),
        Err(_) => {
            [1, 3, 5, 6, 7, 8, 9].map(|j| (j, tilt_deg)).into_iter().chain([3, 6, 19].map(|j| (j, 10.0))).collect()
        }
    };
    let cells = env("UNSEEN_CELLS", 40) as usize;
    let mut failures = Vec::new();
    let mut tilted_nodes = 0usize;
    for (index, tilt_deg) in jobs {
        let mut drawn = draw(seed, index);
        drawn.job.options.orient.max_azimuth_rad = tilt_deg.to_radians();
        if tilt_deg > 0.0 {
            drawn.what = format!("{} (tilt ≤ {tilt_deg}°)", drawn.what);
        }
        let job = &drawn.job;
        let part = PartSamples::new(&job.surface, job.options.part_grid);
        let clock = std::time::Instant::now();
        let built = iso_scallop(&job.setup(&part));
        let ms = clock.elapsed().as_secs_f64() * 1e3;
        let set = match built {
            Ok(set) => set,
            Err(
                e @ (FinishError::NoPath { .. }
                | FinishError::Oversized { .. }
                | FinishError::TooManyPaths { .. }
                | FinishError::TooMuchChecking { .. }),
            ) => {
                eprintln!("{}: refused: {e}", drawn.what);
                continue;
            }
            Err(e) => panic!("{}: {e}", drawn.what),
        };
        let h = job.options.scallop_mm;
        let e = job.options.gouge_tol_mm;
        let tilted = set.paths.iter().flat_map(|p| &p.nodes).filter(|n| n.pose.azimuth_rad.abs() > 1e-6).count();
        tilted_nodes += tilted;
        let m = measure(job, &set, cells);
        eprintln!(
            "{}: {} paths ({tilted} nodes tilted), {} refused, {} flagged, {ms:.0} ms; {} points: max {:.3}·h at uv {:.3} (path {}), p99.9 {:.3}·h, {} over 1.05·h, {} over 1.10·h; deepest {:.3} µm (E {:.2} µm); {} points flagged; worst on chord {:?}, deepest at {:?}",
            drawn.what,
            set.paths.len(),
            set.refused.len(),
            set.scallop_flags.len(),
            m.points,
            m.max_left / h,
            m.worst_uv,
            m.worst_path,
            m.p999 / h,
            m.over_105,
            m.over_110,
            m.deepest * 1e3,
            e * 1e3,
            m.near_refused,
            m.worst_at,
            m.deep_at
        );
        if std::env::var("UNSEEN_DIAG").is_ok() {
            for f in set.scallop_flags.iter().take(8) {
                eprintln!("  flag after path {} at uv {:.3}: {:.2}·h", f.path, f.uv, f.scallop_mm / h);
            }
        }
        if std::env::var("UNSEEN_DIAG").is_ok()
            && (m.max_left > 1.10 * h || std::env::var("UNSEEN_DIAG").as_deref() == Ok("all"))
        {
            diagnose(job, &set, m.worst_uv);
        }
        if m.p999 > 1.05 * h || m.max_left > 1.10 * h || m.deepest > e {
            failures.push(drawn.what.clone());
        }
    }
    assert!(failures.is_empty(), "{} jobs failed: {failures:?}", failures.len());
    if std::env::var("UNSEEN_JOBS").is_err() {
        assert!(tilted_nodes > 0, "no node of the tilted jobs tilted: the sample tests no tilt");
    }
}

fn diagnose(job: &FinishJob, set: &PathSet, uv: DVec2) {
    let judge = Judge::new(set.strategy.cutter_for(&job.cutter), set);
    let h = job.options.scallop_mm;
    let p = job.surface.point_at(uv);
    for (k, path) in set.paths.iter().enumerate() {
        let Some((j, n)) = path
            .nodes
            .iter()
            .enumerate()
            .min_by(|a, b| (a.1.frame.point - p).length().total_cmp(&(b.1.frame.point - p).length()))
        else {
            continue;
        };
        let dist = (n.frame.point - p).length();
        if dist < 4.0 {
            eprintln!(
                "  path {k} node {j} at {dist:.3} mm uv {:.4}: strip {:.3} side step {:?} predicted scallop {:?} α {:.2}° ψ {:.2}° adjusted {}",
                n.frame.uv,
                n.strip_mm,
                n.side_step_mm,
                n.scallop_mm.map(|s| s / h),
                n.pose.inclination_rad.to_degrees(),
                n.pose.azimuth_rad.to_degrees(),
                n.adjusted.is_some()
            );
        }
    }
    for (k, path) in set.paths.iter().enumerate() {
        let sc: Vec<f64> = path.nodes.iter().filter_map(|n| n.scallop_mm).map(|s| s / h).collect();
        let mx = sc.iter().copied().fold(0.0, f64::max);
        let over: Vec<String> = path
            .nodes
            .iter()
            .enumerate()
            .filter(|(_, n)| n.scallop_mm.is_some_and(|s| s > 1.02 * h))
            .map(|(j, n)| format!("{j}:{:.2}@{:.3}", n.scallop_mm.unwrap() / h, n.frame.uv))
            .take(6)
            .collect();
        eprintln!("  path {k} {} nodes measured max {mx:.3}·h {}", path.nodes.len(), over.join(" "));
    }
    for (k, path) in set.paths.iter().enumerate() {
        let near: Vec<String> = path
            .nodes
            .iter()
            .filter(|n| (n.frame.uv - uv).abs().max_element() < 0.04)
            .map(|n| {
                format!(
                    "({:.4},{:.4}{}{})",
                    n.frame.uv.x,
                    n.frame.uv.y,
                    n.scallop_mm.map_or(String::new(), |s| format!(" {:.2}h", s / h)),
                    if n.adjusted.is_some() { " adj" } else { "" }
                )
            })
            .collect();
        if !near.is_empty() {
            eprintln!("  path {k}: {}", near.join(" "));
        }
    }
    let d = job.surface.domain();
    let (db, is_u) = if set.along == 0 { (d.v.width(), false) } else { (d.u.width(), true) };
    for i in -30..=30 {
        let off = db * 0.004 * f64::from(i);
        let q = if is_u { uv + DVec2::new(off, 0.0) } else { uv + DVec2::new(0.0, off) };
        if let Some((l, k, j, t)) = judge.left(job.surface.point_at(q)) {
            eprintln!("    {:+.4}: {:.3}·h path {k} chord {j} t {t:.2}", off, l / h);
        }
    }
}
