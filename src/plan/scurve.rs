//! One-dimensional jerk-limited (S-curve) velocity changes and moves, in closed form.
//!
//! A *ramp* changes the speed from v₀ to v₁ with the acceleration 0 at both ends, within
//! |a| ≤ A and |ȧ| ≤ J: jerk ±J until |a| = A (if it gets there), constant A, jerk ∓J back to
//! 0. Its time is
//!
//! - T(Δv) = Δv/A + A/J when Δv ≥ A²/J (the acceleration reaches A),
//! - T(Δv) = 2√(Δv/J) otherwise,
//! - T(Δv) = Δv/A when J = ∞ (a trapezoid's ramp: the acceleration jumps),
//!
//! and its distance is (v₀ + v₁)/2 · T: the speed is point-symmetric about the ramp's middle
//! (Biagiotti & Melchiorri, *Trajectory Planning for Automatic Machines and Robots*,
//! Springer 2008, §3.4, the "double S" profile). A *segment* of length D goes from v₀ to v₁
//! (acceleration 0 at both ends) through a peak speed v_p ≤ V: ramp up, cruise, ramp down.
//! From rest to rest this is the time-optimal profile of a single axis (Ruckig gives the
//! same; `tests/reference/plan_ruckig.rs`).

use super::path::{lower, upper};

/// The peak-speed Newton is done when its residual is below this fraction of the distance
/// d: the residual's own rounding is about 1e-16 of d.
const RESIDUAL_DONE_REL: f64 = 1e-14;
/// … or when its step is below this fraction of the iterate w: Newton converges
/// quadratically, so the next iterate is within about 1e-16 of the root.
const STEP_DONE_REL: f64 = 1e-8;

/// Veltkamp's splitting constant 2^27 + 1: a double times it splits into two halves of 26
/// bits whose products are exact.
const SPLITTER: f64 = 134_217_729.0;

/// `a` as hi + lo with 26 significant bits each (|a| far below overflow).
#[inline]
fn split(a: f64) -> (f64, f64) {
    let c = SPLITTER * a;
    let hi = c - (c - a);
    (hi, a - hi)
}

/// The cube root, bit for bit `f64::cbrt` (which is correctly rounded: the compiler's libm,
/// natively and in wasm32), in fewer instructions. On a positive normal x: x = m·2^(3k) with
/// m in [1, 8); y ≈ ∛m by two Halley steps from a guess in the bits (within 29 last places);
/// then the exact residual m − y³ (y² and y·y² as exact products by Dekker's splitting, no
/// FMA needed) gives the correction (m − y³)/(3y²) in units of y's last place, u. The
/// nearest double to ∛m is y + round(u)·ulp unless u is within 1e-6 of a half (the computed
/// u is good to some 1e-12 for |u| ≤ 64, the linear step's error u²·2^-52 included; the
/// cube of a midpoint between doubles is never a double, so there is no exact tie), |u| >
/// 64, or the result leaves [1, 2): there, and for zero, negatives, subnormals, infinities
/// and NaN, `f64::cbrt` itself.
#[must_use]
pub fn cbrt(x: f64) -> f64 {
    const MANTISSA: u64 = (1 << 52) - 1;
    const ULP: f64 = f64::EPSILON; // 2^-52: the last place of y in [1, 2)
    if !(x > 0.0 && x.is_normal()) {
        return x.cbrt();
    }
    let bits = x.to_bits();
    let e = (bits >> 52) as i64 - 1023;
    let k = e.div_euclid(3);
    let r = (e - 3 * k) as u64;
    let m = f64::from_bits((bits & MANTISSA) | ((1023 + r) << 52));
    // A first guess within some 3 %: the exponent divided by three in the bits.
    let mut y = f64::from_bits(m.to_bits() / 3 + 0x2A9F_7893_7826_0000);
    for _ in 0..2 {
        // Halley: cubic convergence (3.2e-2, 2.1e-5, 6.4e-15: within 29 last places).
        let y3 = y * y * y;
        y *= (y3 + 2.0 * m) / (2.0 * y3 + m);
    }
    if !(y > 1.0 && y < 2.0) {
        return x.cbrt();
    }
    let (yh, yl) = split(y);
    let h2 = y * y;
    let l2 = ((yh * yh - h2) + 2.0 * yh * yl) + yl * yl;
    let (h2h, h2l) = split(h2);
    let h3 = y * h2;
    let l3 = (((yh * h2h - h3) + yh * h2l) + yl * h2h) + yl * h2l;
    // m − y³ = (m − h3) − l3 − y·l2; m − h3 is exact (h3 within a factor 2 of m).
    let res = ((m - h3) - l3) - y * l2;
    let u = res / (3.0 * h2) / ULP;
    // Round to the nearest integer by adding and taking off 1.5·2^52 (|u| is small): no
    // call to `round`, which the baseline x86-64 target does not have as an instruction.
    const ROUNDER: f64 = 6_755_399_441_055_744.0;
    let n = (u + ROUNDER) - ROUNDER;
    if !((u - n).abs() < 0.5 - 1e-6) || n.abs() > 64.0 {
        return x.cbrt();
    }
    let z = y + n * ULP;
    if !(1.0..2.0).contains(&z) {
        return x.cbrt();
    }
    // z·2^k: exact (x normal, so ∛x is far inside the normal range).
    z * f64::from_bits(((1023 + k) as u64) << 52)
}

/// One phase of constant jerk: the acceleration starts at `a0` (it may jump there when the
/// jerk is not limited) and changes at `j` for `dur` seconds.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Phase {
    /// Duration (s).
    pub dur: f64,
    /// Acceleration at the start of the phase (mm/s²).
    pub a0: f64,
    /// Jerk during the phase (mm/s³).
    pub j: f64,
}

/// Time of a ramp changing the speed by `dv ≥ 0` (s).
#[must_use]
pub fn ramp_time(dv: f64, a: f64, j: f64) -> f64 {
    // As `dv.max(0.0)` (a NaN gives 0), in one compare-and-select.
    let dv = upper(0.0, dv);
    if j.is_infinite() {
        dv / a
    } else if dv * j >= a * a {
        dv / a + a / j
    } else {
        2.0 * (dv / j).sqrt()
    }
}

/// Distance of a ramp from v₀ to v₁ (mm): (v₀ + v₁)/2 · T(|v₁ − v₀|).
#[must_use]
pub fn ramp_dist(v0: f64, v1: f64, a: f64, j: f64) -> f64 {
    0.5 * (v0 + v1) * ramp_time((v1 - v0).abs(), a, j)
}

/// The highest speed v₁ ≥ v₀ a ramp reaches within `d` (mm), at most `vmax`.
#[must_use]
pub fn reach(v0: f64, d: f64, a: f64, j: f64, vmax: f64) -> f64 {
    if vmax <= v0 {
        return vmax;
    }
    if ramp_dist(v0, vmax, a, j) <= d {
        return vmax;
    }
    let v1 = if j.is_infinite() {
        (v0 * v0 + 2.0 * a * d).sqrt()
    } else {
        // Acceleration reaches A: (v₁² − v₀²)/(2A) + (v₀ + v₁)A/(2J) = d, a quadratic in v₁.
        let k = a * a / j;
        let c = -v0 * v0 + v0 * k - 2.0 * a * d;
        let v1 = 0.5 * (-k + (k * k - 4.0 * c).sqrt());
        if v1 - v0 >= k {
            v1
        } else {
            // Not reached: (2v₀ + w²)·w = d√J with w = √(v₁ − v₀), a depressed cubic
            // w³ + 2v₀w − d√J = 0 with one real root (Cardano), polished by Newton.
            let p = 2.0 * v0;
            let q = d * j.sqrt();
            let big = cbrt(0.5 * q + (0.25 * q * q + p * p * p / 27.0).sqrt());
            let mut w = if big > 0.0 { big - p / (3.0 * big) } else { 0.0 };
            for _ in 0..4 {
                let f = w * w * w + p * w - q;
                let df = 3.0 * w * w + p;
                if df <= 0.0 {
                    break;
                }
                w -= f / df;
            }
            v0 + w.max(0.0) * w.max(0.0)
        }
    };
    // `vmax` is a knot's speed, never NaN: `lower` is `min`.
    lower(vmax, v1)
}

/// The peak speed of a segment of length `d` from v₀ to v₁ under `vcap` (≥ max(v₀, v₁)):
/// the largest v_p with ramp(v₀ → v_p) + ramp(v_p → v₁) ≤ d. The caller guarantees that
/// one ramp from v₀ to v₁ fits in d.
#[must_use]
pub fn peak(v0: f64, v1: f64, d: f64, a: f64, j: f64, vcap: f64) -> f64 {
    let lo = v0.max(v1);
    if vcap <= lo {
        return lo;
    }
    // The segment's length used less d, and its derivative, in w = √(v_p − lo), where it is
    // smooth (in v_p it has a √ at lo), increasing and convex (each ramp's distance is
    // convex and increasing in v_p, and v_p convex in w): Newton from above the root
    // converges monotonically; a step that leaves the bracket is replaced by a halving.
    let g = |w: f64| -> (f64, f64) {
        let vp = lo + w * w;
        let mut val = -d;
        let mut der = 0.0;
        for v in [v0, v1] {
            let dv = vp - v;
            let t = ramp_time(dv, a, j);
            // 2w·dT/dΔv, finite at w = 0.
            let dt2w = if dv * j >= a * a {
                2.0 * w / a
            } else if dv > 0.0 {
                2.0 * w / (dv * j).sqrt()
            } else {
                2.0 / j.sqrt()
            };
            val += 0.5 * (v + vp) * t;
            der += t * w + 0.5 * (v + vp) * dt2w;
        }
        (val, der)
    };
    // At w = 0 one ramp, from v₀ to v₁: when it takes all of d (the passes leave many such
    // segments) there is no rise.
    let (g0, d0) = g(0.0);
    if g0 >= 0.0 {
        return lo;
    }
    let f = |vp: f64| ramp_dist(v0, vp, a, j) + ramp_dist(vp, v1, a, j) - d;
    if f(vcap) <= 0.0 {
        return vcap;
    }
    if j.is_infinite() {
        return (a * d + 0.5 * (v0 * v0 + v1 * v1)).sqrt().clamp(lo, vcap);
    }
    // Both ramps reach A: v_p² + v_p·A²/J + A·[(v₀ + v₁)A/(2J) − (v₀² + v₁²)/(2A) − d] = 0.
    let k = a * a / j;
    let c = a * (0.5 * (v0 + v1) * a / j - 0.5 * (v0 * v0 + v1 * v1) / a - d);
    let vp = 0.5 * (-k + (k * k - 4.0 * c).sqrt());
    if vp - lo >= k && vp <= vcap {
        return vp;
    }
    let (mut lo_w, mut hi_w) = (0.0, (vcap - lo).sqrt());
    // Two starts above the root, the lower taken (at most 100 steps from it): the tangent
    // at w = 0 (g is convex, so the tangent's root is at or above g's), and where both
    // ramps would start from lo without reaching A — (2·lo + w²)·w·2/√J = d, a depressed
    // cubic (Cardano) — which ignores the longer ramp from the lower end speed. On a
    // segment whose ends differ a little and whose rise is tiny (most of them) the tangent
    // is within rounding of the root.
    let q = 0.5 * d * j.sqrt();
    let p3 = 2.0 * lo / 3.0;
    let big = cbrt(0.5 * q + (0.25 * q * q + p3 * p3 * p3).sqrt());
    let w_sym = if big > 0.0 { big - p3 / big } else { f64::INFINITY };
    let w_tan = if d0 > 0.0 { -g0 / d0 } else { f64::INFINITY };
    let start = w_sym.min(w_tan);
    let mut w = if start > 0.0 && start < hi_w { start } else { hi_w };
    for _ in 0..100 {
        let (val, der) = g(w);
        if val > 0.0 {
            hi_w = w;
        } else {
            lo_w = w;
        }
        let mut next = if der > 0.0 { w - val / der } else { f64::NAN };
        if !(next >= lo_w && next <= hi_w) {
            next = 0.5 * (lo_w + hi_w);
        }
        // Rounding in g is about 1e-16 of d: closer than that the steps are noise.
        // Done when the step no longer moves v_p = lo + w² beyond its own rounding, or g
        // is at its rounding (about 1e-16 of d).
        // Or the step is below 1e-8 of w: Newton converges quadratically, so the next
        // iterate is within about 1e-16 of the root (the check below keeps it feasible).
        let vp_ulp = 4.0 * f64::EPSILON * (lo + w * w);
        let done = val.abs() <= RESIDUAL_DONE_REL * d
            || 2.0 * w.max(next) * (next - w).abs() <= vp_ulp
            || 2.0 * hi_w * (hi_w - lo_w) <= vp_ulp
            || (next - w).abs() <= STEP_DONE_REL * w;
        w = next;
        if done {
            break;
        }
    }
    // Never above the root: a peak that overshoots by an ulp would not fit in d. Step down
    // by the Newton step (at least 4 ulp), doubling, until it fits; the last feasible iterate
    // is the floor.
    let (val, der) = g(w);
    let mut step = (if der > 0.0 { val / der } else { 0.0 }).max(4.0 * f64::EPSILON * w);
    // g at the first iterate is the one just computed.
    let mut known = Some(val);
    for _ in 0..64 {
        if w <= lo_w {
            break;
        }
        if known.take().unwrap_or_else(|| g(w).0) <= 0.0 {
            return lo + w * w;
        }
        w = (w - step).max(lo_w);
        step *= 2.0;
    }
    lo + lo_w * lo_w
}

/// Appends the phases of a ramp from v₀ to v₁.
pub fn push_ramp(v0: f64, v1: f64, a: f64, j: f64, out: &mut Vec<Phase>) {
    let dv = v1 - v0;
    if dv == 0.0 {
        return;
    }
    let s = dv.signum();
    let dv = dv.abs();
    if j.is_infinite() {
        out.push(Phase { dur: dv / a, a0: s * a, j: 0.0 });
    } else if dv * j >= a * a {
        let tj = a / j;
        out.push(Phase { dur: tj, a0: 0.0, j: s * j });
        let ta = dv / a - tj;
        if ta > 0.0 {
            out.push(Phase { dur: ta, a0: s * a, j: 0.0 });
        }
        out.push(Phase { dur: tj, a0: s * a, j: -s * j });
    } else {
        let tj = (dv / j).sqrt();
        out.push(Phase { dur: tj, a0: 0.0, j: s * j });
        out.push(Phase { dur: tj, a0: s * j * tj, j: -s * j });
    }
}

/// Appends the phases of a segment of length `d` from v₀ to v₁ through the peak
/// [`peak`]`(v₀, v₁, d, a, j, vcap)`; returns its duration (s).
pub fn push_segment(v0: f64, v1: f64, d: f64, vcap: f64, a: f64, j: f64, out: &mut Vec<Phase>) -> f64 {
    if d <= 0.0 {
        return 0.0;
    }
    let vp = peak(v0, v1, d, a, j, vcap);
    let d_up = ramp_dist(v0, vp, a, j);
    let d_down = ramp_dist(vp, v1, a, j);
    let start = out.len();
    push_ramp(v0, vp, a, j, out);
    let cruise = d - d_up - d_down;
    if cruise > 0.0 && vp > 0.0 {
        out.push(Phase { dur: cruise / vp, a0: 0.0, j: 0.0 });
    }
    push_ramp(vp, v1, a, j, out);
    out[start..].iter().map(|p| p.dur).sum()
}

/// Duration of a rest-to-rest move of length `d` with speed, acceleration and jerk limits
/// (s): the closed form of the double-S profile.
#[must_use]
pub fn rest_to_rest_time(d: f64, v: f64, a: f64, j: f64) -> f64 {
    if d <= 0.0 {
        return 0.0;
    }
    let vp = peak(0.0, 0.0, d, a, j, v);
    let t = ramp_time(vp, a, j);
    let cruise = (d - vp * t).max(0.0);
    2.0 * t + if vp > 0.0 { cruise / vp } else { 0.0 }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn integrate(v0: f64, phases: &[Phase]) -> (f64, f64, f64) {
        let (mut s, mut v, mut acc) = (0.0, v0, 0.0);
        for p in phases {
            let t = p.dur;
            s += v * t + 0.5 * p.a0 * t * t + p.j * t * t * t / 6.0;
            v += p.a0 * t + 0.5 * p.j * t * t;
            acc = p.a0 + p.j * t;
        }
        (s, v, acc)
    }

    #[test]
    fn ramps_land_on_their_speed_and_distance() {
        for &(v0, v1, a, j) in &[(0.0, 100.0, 500.0, 5000.0), (20.0, 25.0, 500.0, 5000.0), (80.0, 10.0, 300.0, 1e6)] {
            let mut ph = Vec::new();
            push_ramp(v0, v1, a, j, &mut ph);
            let (s, v, acc) = integrate(v0, &ph);
            assert!((v - v1).abs() < 1e-9, "{v} vs {v1}");
            assert!(acc.abs() < 1e-9);
            assert!((s - ramp_dist(v0, v1, a, j)).abs() < 1e-9);
        }
    }

    #[test]
    fn reach_is_the_inverse_of_ramp_distance() {
        for &(v0, d, a, j) in &[(0.0, 5.0, 500.0, 5000.0), (30.0, 0.01, 500.0, 5000.0), (10.0, 50.0, 100.0, 1e9)] {
            let v1 = reach(v0, d, a, j, f64::INFINITY);
            assert!((ramp_dist(v0, v1, a, j) - d).abs() < 1e-9 * d.max(1.0), "{v0} {d}");
        }
    }

    #[test]
    fn peaks_fill_their_segment_exactly() {
        // Every regime: both ramps reaching A, neither, one of them.
        let mut n = 0;
        for i in 0..3000 {
            let (a, j) = if i % 2 == 0 { (3000.0, 50_000.0) } else { (50.0, 25_000.0) };
            let v0 = (i % 7) as f64 * 9.0;
            let v1 = (i % 5) as f64 * 11.0;
            let d = 0.01 + (i % 13) as f64 * 0.37;
            if ramp_dist(v0, v1, a, j) > d {
                continue;
            }
            let vp = peak(v0, v1, d, a, j, 1e4);
            let used = ramp_dist(v0, vp, a, j) + ramp_dist(vp, v1, a, j);
            assert!(used <= d * (1.0 + 1e-12) && used >= d * (1.0 - 1e-12), "{v0} {v1} {d}: {used}");
            n += 1;
        }
        assert!(n > 1000);
    }

    #[test]
    fn segments_cover_their_length() {
        for &(v0, v1, d, vc, a, j) in &[
            (0.0, 0.0, 10.0, 100.0, 500.0, 5000.0),
            (40.0, 5.0, 5.0, 60.0, 500.0, 5000.0),
            (0.0, 0.0, 0.001, 1.0, 2.0, 3.0),
        ] {
            let mut ph = Vec::new();
            let t = push_segment(v0, v1, d, vc, a, j, &mut ph);
            let (s, v, _) = integrate(v0, &ph);
            assert!((s - d).abs() < 1e-9 * d.max(1.0), "{s} vs {d}");
            assert!((v - v1).abs() < 1e-9);
            assert!(t > 0.0);
        }
    }
}
