//! Knot-vector helpers shared by the fitting, G-code and simulation code.

/// The distinct span boundaries `[u_p, …, u_{n+1}]` of a clamped knot vector of degree `p`
/// (the knot values inside the curve's range, each once, increasing). A knot vector shorter
/// than `2p` has no range and gives an empty list.
#[must_use]
pub fn span_breaks(knots: &[f64], p: usize) -> Vec<f64> {
    let inner = knots.get(p..knots.len().saturating_sub(p)).unwrap_or(&[]);
    let mut out: Vec<f64> = Vec::with_capacity(inner.len());
    for &k in inner {
        if out.last().is_none_or(|&l| k > l) {
            out.push(k);
        }
    }
    out
}

#[cfg(test)]
mod tests {
    use super::span_breaks;

    #[test]
    fn clamped_cubic_with_a_double_knot() {
        let knots = [0.0, 0.0, 0.0, 0.0, 0.25, 0.5, 0.5, 1.0, 1.0, 1.0, 1.0];
        assert_eq!(span_breaks(&knots, 3), vec![0.0, 0.25, 0.5, 1.0]);
    }

    #[test]
    fn bezier_has_one_span_and_short_vectors_none() {
        assert_eq!(span_breaks(&[0.0, 0.0, 0.0, 2.0, 2.0, 2.0], 2), vec![0.0, 2.0]);
        assert!(span_breaks(&[0.0, 1.0], 3).is_empty());
    }
}
