//! The outside checker's arithmetic, shared by the G-code tests that read programs with
//! their own small readers (tests/core/gcode/roundtrip.rs, tests/core/gcode/dialects.rs): written here
//! from the textbook formulas, independently of the library's evaluation and measuring code.

use glam::DVec3;
use interpolab::nurbs_path::Parabola;

/// A rational B-spline as a test reader builds it from a program's words.
pub struct RawNurbs {
    /// Order p = degree + 1.
    pub order: usize,
    pub knots: Vec<f64>,
    pub points: Vec<DVec3>,
    pub weights: Vec<f64>,
}

impl RawNurbs {
    /// Cox–de Boor for order p: N_{i,1} = [k_i ≤ u < k_{i+1}], and N_{i,p} is the sum of
    /// (u−k_i)/(k_{i+p−1}−k_i)·N_{i,p−1} and (k_{i+p}−u)/(k_{i+p}−k_{i+1})·N_{i+1,p−1}, with
    /// 0/0 = 0; the end of the range belongs to the last non-empty span.
    pub fn point(&self, u: f64) -> DVec3 {
        let k = &self.knots;
        let end = k[k.len() - 1];
        let mut basis: Vec<f64> = (0..k.len() - 1)
            .map(|i| {
                let inside = k[i] <= u && u < k[i + 1];
                let last = u >= end && k[i] < k[i + 1] && k[i + 1] >= end;
                if inside || last { 1.0 } else { 0.0 }
            })
            .collect();
        for p in 2..=self.order {
            let mut next = vec![0.0; k.len() - p];
            for (i, v) in next.iter_mut().enumerate() {
                let a = if k[i + p - 1] > k[i] { (u - k[i]) / (k[i + p - 1] - k[i]) * basis[i] } else { 0.0 };
                let b = if k[i + p] > k[i + 1] { (k[i + p] - u) / (k[i + p] - k[i + 1]) * basis[i + 1] } else { 0.0 };
                *v = a + b;
            }
            basis = next;
        }
        let (mut num, mut den) = (DVec3::ZERO, 0.0);
        for i in 0..self.points.len() {
            num += basis[i] * self.weights[i] * self.points[i];
            den += basis[i] * self.weights[i];
        }
        num / den
    }

    /// The knot range.
    pub fn range(&self) -> (f64, f64) {
        (self.knots[0], self.knots[self.knots.len() - 1])
    }
}

/// Distance from p to the parabola y = a·x² (z = 0) near p: Newton on the foot condition
/// (x − X) + 2ax(ax² − Y) = 0 from x = X, clamped to the profile.
pub fn parabola_distance(para: &Parabola, p: DVec3) -> f64 {
    let a = para.a;
    let mut x = p.x.clamp(para.x0, para.x1);
    for _ in 0..60 {
        let g = (x - p.x) + 2.0 * a * x * (a * x * x - p.y);
        let gp = 1.0 + 2.0 * a * (3.0 * a * x * x - p.y);
        x = (x - g / gp).clamp(para.x0, para.x1);
    }
    ((x - p.x).powi(2) + (a * x * x - p.y).powi(2) + p.z * p.z).sqrt()
}

/// Distance from x to the segment from a to b.
pub fn seg_dist(x: DVec3, a: DVec3, b: DVec3) -> f64 {
    let ab = b - a;
    let l2 = ab.length_squared();
    let t = if l2 > 0.0 { ((x - a).dot(ab) / l2).clamp(0.0, 1.0) } else { 0.0 };
    (a + t * ab - x).length()
}

/// Points of a feed move from `pos` to `end` at most `step` mm apart: a line for G01
/// (`motion` 10, in tenths of a G number), a circular or helical arc for G02/G03 (20, 30) in
/// `plane` (17, 18 or 19) about the centre `pos + ijk`, its radius blended from start to end.
/// Returns the start and end radii of an arc.
pub fn feed_move(
    out: &mut Vec<DVec3>,
    pos: DVec3,
    end: DVec3,
    motion: i64,
    plane: i32,
    ijk: [f64; 3],
    step: f64,
) -> Option<(f64, f64)> {
    if motion == 10 {
        let n = ((end - pos).length() / step).ceil().max(1.0) as usize;
        out.extend((0..=n).map(|i| pos.lerp(end, i as f64 / n as f64)));
        None
    } else if motion == 20 || motion == 30 {
        // In-plane axes (a, b) and normal n.
        let (a, b, nn) = match plane {
            17 => (0, 1, 2),
            18 => (2, 0, 1),
            _ => (1, 2, 0),
        };
        let (ca, cb) = (pos[a] + ijk[a], pos[b] + ijk[b]);
        let (rs, re) = ((pos[a] - ca).hypot(pos[b] - cb), (end[a] - ca).hypot(end[b] - cb));
        let t0 = (pos[b] - cb).atan2(pos[a] - ca);
        let t1 = (end[b] - cb).atan2(end[a] - ca);
        let tau = std::f64::consts::TAU;
        let sweep = if motion == 30 { (t1 - t0).rem_euclid(tau) } else { -(t0 - t1).rem_euclid(tau) };
        let n = ((sweep.abs() * rs.max(re)) / step).ceil().max(8.0) as usize;
        for i in 0..=n {
            let f = i as f64 / n as f64;
            let (r, th) = (rs + (re - rs) * f, t0 + sweep * f);
            let mut p = DVec3::ZERO;
            p[a] = ca + r * th.cos();
            p[b] = cb + r * th.sin();
            p[nn] = pos[nn] + (end[nn] - pos[nn]) * f;
            out.push(p);
        }
        Some((rs, re))
    } else {
        None
    }
}
