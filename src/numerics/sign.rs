//! The one sign convention for machining error in the core: **overcut (gouge) positive**.
//!
//! A machining error e (mm) of a cutter against a design surface is positive where the
//! cutter cuts into the surface (overcut, gouge: material removed that the part needed) and
//! negative where it leaves stock (undercut). For a ball of effective radius R' = R + C whose
//! centre lies at signed distance d from the surface (positive on the cutter's side),
//! e = R' − d ([`overcut_mm`]).
//!
//! Why this sign: a gouge is the error that scraps a part — stock can be taken off by another
//! pass, a gouge cannot be put back — so the one-sided checks every paper makes ("no gouge
//! deeper than E") read as `e ≤ E` and the gouge depth is `max(e, 0)`; and seed 002's step
//! selection, the one algorithm where the sign changes the result (the chord error δt and the
//! nonlinear error δn add or cancel by sign), states its formulas in it, so they stay verbatim.
//!
//! Papers with the other sign map at their formula, with a comment there: seed 000's
//! measured error e_i = dist(p, S_i) − R' (`crease::estimate`, negative = gouge). Outputs whose
//! sign the contract fixes keep it, mapped at the edge by [`stock_positive`]: the `e1`, `e2`
//! columns of `interpolab run --errors` (docs/scene-format.md: negative means the ball cuts
//! into the surface) and the crease view's error plot.

/// The machining error (mm, overcut positive) of a ball of effective radius `r_eff_mm` whose
/// centre lies at signed distance `distance_mm` (positive on the cutter's side) from a surface.
#[must_use]
pub fn overcut_mm(distance_mm: f64, r_eff_mm: f64) -> f64 {
    r_eff_mm - distance_mm
}

/// An error in the core's convention (overcut positive) in the stock-positive convention of
/// an output that prints it so (seed 000's e = d − R'). Written `0 − e` so a zero error stays
/// +0 (and prints as `0`, not `-0`); for every other value it is exactly −e, and
/// `stock_positive(overcut_mm(d, r))` is bit for bit `d − r`.
#[must_use]
pub fn stock_positive(overcut_mm: f64) -> f64 {
    0.0 - overcut_mm
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_ball_closer_than_its_radius_gouges() {
        // Centre 4.9 mm from the surface, R' = 5 mm: the ball cuts 0.1 mm into it.
        assert!((overcut_mm(4.9, 5.0) - 0.1).abs() < 1e-12);
        // 5.2 mm away: 0.2 mm of stock, a negative error.
        assert!((overcut_mm(5.2, 5.0) + 0.2).abs() < 1e-12);
    }

    #[test]
    fn the_stock_positive_form_is_seed_000s_e_bit_for_bit() {
        for (d, r) in [(4.9, 5.0), (5.2, 5.0), (5.0, 5.0), (3.000_000_000_000_001, 3.0), (1e-300, 0.0)] {
            let e000: f64 = d - r;
            let mapped = stock_positive(overcut_mm(d, r));
            assert_eq!(mapped.to_bits(), e000.to_bits(), "d = {d}, r = {r}");
        }
    }
}
