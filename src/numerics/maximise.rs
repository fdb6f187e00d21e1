//! Locating the largest value of a one-dimensional function on an interval: Brent's
//! parabolic/golden-section search on a bracket, and a sampled search that never trusts a
//! single bracket (cover the interval, then refine every candidate peak); and
//! [`max_on_interval`], a fixed grid refined by golden section, which the fitting and G-code
//! checks use (the two searches give different last digits, so they are kept apart for now).

/// Settings of [`sampled_max`].
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct MaxOptions {
    /// Equal intervals sampled first (default 8).
    pub initial_intervals: usize,
    /// Split an interval while the function's midpoint leaves the straight line between its
    /// end values by more than this fraction of the best value so far (default 0.05).
    pub coverage_rel: f64,
    /// …or by less than this absolute amount: no further split (default 1e-9).
    pub floor: f64,
    /// Deepest splitting (default 12 halvings).
    pub max_depth: u32,
    /// Peaks located to this fraction of the interval (default 1e-5).
    pub peak_rel: f64,
}

impl Default for MaxOptions {
    fn default() -> Self {
        Self {
            initial_intervals: 8,
            coverage_rel: 0.05,
            floor: crate::numerics::tolerance::MAX_FLOOR,
            max_depth: 12,
            peak_rel: crate::numerics::tolerance::PEAK_PARAM_REL,
        }
    }
}

/// Brent's method for the largest value of `f` on `[a, b]` (f unimodal there), to an
/// argument tolerance `tol_x`. Golden-section steps guarantee progress; parabolic steps
/// through the three best points converge superlinearly at a smooth peak. `seed` is a known
/// point `(x, f(x))` inside, used as the first iterate. Returns `(x, f(x), evaluations)`.
///
/// # Errors
/// The first error of `f`.
#[expect(clippy::float_cmp, reason = "Brent's bookkeeping compares stored abscissae for identity, not for nearness")]
pub fn brent_max<E>(
    mut f: impl FnMut(f64) -> Result<f64, E>,
    a: f64,
    b: f64,
    tol_x: f64,
    seed: (f64, f64),
) -> Result<(f64, f64, u32), E> {
    // Minimise g = −f.
    let golden = 0.381_966_011_250_105_2;
    let (mut lo, mut hi) = (a.min(b), a.max(b));
    let (mut x, mut gx) = if seed.0 > lo && seed.0 < hi {
        (seed.0, -seed.1)
    } else {
        let x = lo + golden * (hi - lo);
        (x, -f(x)?)
    };
    let mut evals = u32::from(!(seed.0 > lo && seed.0 < hi));
    let (mut w, mut gw, mut v, mut gv) = (x, gx, x, gx);
    let (mut d, mut e) = (0.0f64, 0.0f64);
    for _ in 0..100 {
        let m = 0.5 * (lo + hi);
        let tol1 = f64::EPSILON.sqrt() * x.abs() + tol_x / 3.0;
        let tol2 = 2.0 * tol1;
        if (x - m).abs() <= tol2 - 0.5 * (hi - lo) {
            break;
        }
        let mut parabolic = false;
        if e.abs() > tol1 {
            let r = (x - w) * (gx - gv);
            let mut q = (x - v) * (gx - gw);
            let mut p = (x - v) * q - (x - w) * r;
            q = 2.0 * (q - r);
            if q > 0.0 {
                p = -p;
            } else {
                q = -q;
            }
            if p.abs() < (0.5 * q * e).abs() && p > q * (lo - x) && p < q * (hi - x) {
                e = d;
                d = p / q;
                let u = x + d;
                if u - lo < tol2 || hi - u < tol2 {
                    d = if x < m { tol1 } else { -tol1 };
                }
                parabolic = true;
            }
        }
        if !parabolic {
            e = if x < m { hi - x } else { lo - x };
            d = golden * e;
        }
        let u = if d.abs() >= tol1 { x + d } else { x + tol1.copysign(d) };
        let gu = -f(u)?;
        evals += 1;
        if gu <= gx {
            if u < x {
                hi = x;
            } else {
                lo = x;
            }
            (v, gv, w, gw, x, gx) = (w, gw, x, gx, u, gu);
        } else {
            if u < x {
                lo = u;
            } else {
                hi = u;
            }
            if gu <= gw || w == x {
                (v, gv, w, gw) = (w, gw, u, gu);
            } else if gu <= gv || v == x || v == w {
                (v, gv) = (u, gu);
            }
        }
    }
    Ok((x, -gx, evals))
}

/// A sample `(x, f(x))`.
type Pt = (f64, f64);

/// A peak found by [`sampled_max`].
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Peak {
    /// Where.
    pub x: f64,
    /// The largest value.
    pub value: f64,
    /// Evaluations of the function.
    pub evaluations: u32,
}

/// The largest value of `f` on `[lo, hi]`: sample, split intervals where `f` bends more than
/// `coverage_rel` of the best value, then [`brent_max`] around every sampled local maximum
/// within reach of the best.
///
/// # Errors
/// The first error of `f`.
pub fn sampled_max<E>(
    mut f: impl FnMut(f64) -> Result<f64, E>,
    lo: f64,
    hi: f64,
    opts: &MaxOptions,
) -> Result<Peak, E> {
    let n = opts.initial_intervals.max(2);
    let h = (hi - lo) / n as f64;
    let mut evals = 0u32;
    let mut pts: Vec<(f64, f64)> = Vec::with_capacity(4 * n + 1);
    for i in 0..=n {
        let x = if i == n { hi } else { lo + h * i as f64 };
        pts.push((x, f(x)?));
        evals += 1;
    }
    let mut best = pts.iter().map(|p| p.1).fold(f64::NEG_INFINITY, f64::max);
    // Cover: split by a work stack, keeping samples sorted at the end.
    let mut stack: Vec<(Pt, Pt, u32)> = pts.windows(2).map(|w| (w[0], w[1], 0)).collect();
    while let Some((p0, p1, depth)) = stack.pop() {
        let xm = 0.5 * (p0.0 + p1.0);
        let fm = f(xm)?;
        evals += 1;
        best = best.max(fm);
        pts.push((xm, fm));
        let bend = (fm - 0.5 * (p0.1 + p1.1)).abs();
        if depth < opts.max_depth && bend > (opts.coverage_rel * best.abs()).max(opts.floor) {
            stack.push((p0, (xm, fm), depth + 1));
            stack.push(((xm, fm), p1, depth + 1));
        }
    }
    pts.sort_by(|a, b| a.0.total_cmp(&b.0));
    let mut top = pts.iter().copied().fold((lo, f64::NEG_INFINITY), |acc, p| if p.1 > acc.1 { p } else { acc });
    let margin = (3.0 * opts.coverage_rel * top.1.abs()).max(opts.floor);
    let tol_x = opts.peak_rel * (hi - lo);
    let last = pts.len() - 1;
    let candidates: Vec<usize> = (1..last)
        .filter(|&i| pts[i].1 >= pts[i - 1].1 && pts[i].1 >= pts[i + 1].1 && pts[i].1 + margin >= top.1)
        .collect();
    for i in candidates {
        let (x, v, e) = brent_max(&mut f, pts[i - 1].0, pts[i + 1].0, tol_x, pts[i])?;
        evals += e;
        if v > top.1 {
            top = (x, v);
        }
    }
    Ok(Peak { x: top.0, value: top.1, evaluations: evals })
}

/// The largest value of `f` on `[a, b]` and where it is: `f` is sampled at `n + 1` equally
/// spaced points, then the best sample is refined by golden-section search between its
/// neighbours (`refine` iterations; each shrinks the bracket by 0.618). For the smooth,
/// locally quadratic deviation functions of fitting this finds the peak to far below the
/// output resolution with n ≈ 16 and 20 refinements.
#[must_use]
pub fn max_on_interval(f: &mut dyn FnMut(f64) -> f64, a: f64, b: f64, n: usize, refine: usize) -> (f64, f64) {
    let n = n.max(1);
    let h = (b - a) / n as f64;
    let mut best = (a, f(a));
    let mut best_i = 0;
    for i in 1..=n {
        let t = if i == n { b } else { a + h * i as f64 };
        let v = f(t);
        if v > best.1 {
            best = (t, v);
            best_i = i;
        }
    }
    if refine == 0 || !(h > 0.0) {
        return (best.1, best.0);
    }
    let lo = if best_i == 0 { a } else { a + h * (best_i - 1) as f64 };
    let hi = if best_i == n { b } else { a + h * (best_i + 1) as f64 };
    let g = golden_bracket(f, lo, hi, 0.0, refine);
    for (t, v) in g.inner {
        if v > best.1 {
            best = (t, v);
        }
    }
    (best.1, best.0)
}

/// The end state of [`golden_bracket`]: the last bracket and its two interior points.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct GoldenBracket {
    /// Lower end of the bracket.
    pub lo: f64,
    /// Upper end of the bracket.
    pub hi: f64,
    /// The two interior points `(x, f(x))`, lower one first.
    pub inner: [(f64, f64); 2],
}

impl GoldenBracket {
    /// The better of the two interior points (the lower one on a tie).
    #[must_use]
    pub fn best_inner(&self) -> (f64, f64) {
        if self.inner[0].1 >= self.inner[1].1 { self.inner[0] } else { self.inner[1] }
    }
}

/// Golden-section search for the largest value of a unimodal `f` on `[lo, hi]`: the bracket
/// shrinks by 0.618 per step (one evaluation each) until it is at most `tol` wide or after
/// `max_steps` steps. The shared refinement of [`max_on_interval`] and of the cutting
/// simulation's convex minimisations (which maximise −f).
pub fn golden_bracket<F: FnMut(f64) -> f64 + ?Sized>(
    f: &mut F,
    lo: f64,
    hi: f64,
    tol: f64,
    max_steps: usize,
) -> GoldenBracket {
    const INV_PHI: f64 = 0.618_033_988_749_894_8;
    let (mut lo, mut hi) = (lo, hi);
    let mut x1 = hi - INV_PHI * (hi - lo);
    let mut x2 = lo + INV_PHI * (hi - lo);
    let mut f1 = f(x1);
    let mut f2 = f(x2);
    for _ in 0..max_steps {
        if hi - lo <= tol {
            break;
        }
        if f1 >= f2 {
            hi = x2;
            x2 = x1;
            f2 = f1;
            x1 = hi - INV_PHI * (hi - lo);
            f1 = f(x1);
        } else {
            lo = x1;
            x1 = x2;
            f1 = f2;
            x2 = lo + INV_PHI * (hi - lo);
            f2 = f(x2);
        }
    }
    GoldenBracket { lo, hi, inner: [(x1, f1), (x2, f2)] }
}
