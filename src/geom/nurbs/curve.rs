//! A NURBS curve in 3D, evaluated with its first and second derivatives.

use glam::{DVec3, DVec4};

use super::{NurbsError, basis_derivatives, find_span, validate_knots};

/// A NURBS curve of any degree up to [`MAX_DEGREE`](super::MAX_DEGREE) in 3D (mm).
#[derive(Clone, Debug, PartialEq)]
pub struct NurbsCurve {
    degree: usize,
    knots: Vec<f64>,
    /// Homogeneous control points (w·P, w).
    control: Vec<DVec4>,
}

impl NurbsCurve {
    /// A curve from its degree, clamped knot vector, control points (mm) and optional
    /// weights (all 1 when `None`).
    ///
    /// # Errors
    /// [`NurbsError`] naming the first broken rule.
    pub fn try_new(
        degree: usize,
        knots: Vec<f64>,
        points: &[DVec3],
        weights: Option<&[f64]>,
    ) -> Result<Self, NurbsError> {
        validate_knots(&knots, points.len(), degree)?;
        if let Some(w) = weights {
            if w.len() != points.len() {
                return Err(NurbsError::WeightShape);
            }
            if let Some((index, &value)) = w.iter().enumerate().find(|(_, w)| !(w.is_finite() && **w > 0.0)) {
                return Err(NurbsError::Weight { index, value });
            }
        }
        let control = points
            .iter()
            .enumerate()
            .map(|(i, p)| {
                let w = weights.map_or(1.0, |w| w[i]);
                (*p * w).extend(w)
            })
            .collect();
        Ok(Self { degree, knots, control })
    }

    /// The degree p.
    #[must_use]
    pub fn degree(&self) -> usize {
        self.degree
    }
    /// The knot vector.
    #[must_use]
    pub fn knots(&self) -> &[f64] {
        &self.knots
    }
    /// Number of control points.
    #[must_use]
    pub fn len(&self) -> usize {
        self.control.len()
    }
    /// Never true: a valid curve has at least degree + 1 control points.
    #[must_use]
    pub fn is_empty(&self) -> bool {
        self.control.is_empty()
    }
    /// Control point `i` in mm (Euclidean, not homogeneous).
    #[must_use]
    pub fn control_point(&self, i: usize) -> DVec3 {
        self.control[i].truncate() / self.control[i].w
    }
    /// Weight of control point `i`.
    #[must_use]
    pub fn weight(&self, i: usize) -> f64 {
        self.control[i].w
    }
    /// Parameter range `[knots[p], knots[n+1]]`.
    #[must_use]
    pub fn range(&self) -> (f64, f64) {
        (self.knots[self.degree], self.knots[self.control.len()])
    }

    /// C(u) (mm).
    #[must_use]
    pub fn point_at(&self, u: f64) -> DVec3 {
        self.derivatives_at(u)[0]
    }

    /// `[C, C', C'']` at u (mm, mm per unit u, mm per unit u²).
    #[must_use]
    pub fn derivatives_at(&self, u: f64) -> [DVec3; 3] {
        let p = self.degree;
        let span = find_span(&self.knots, self.control.len(), p, u);
        let n = basis_derivatives(&self.knots, span, p, u);
        let mut aw = [DVec4::ZERO; 3];
        for j in 0..=p {
            let cp = self.control[span - p + j];
            for (k, acc) in aw.iter_mut().enumerate() {
                *acc += n[k][j] * cp;
            }
        }
        let w = aw[0].w;
        let c0 = aw[0].truncate() / w;
        let c1 = (aw[1].truncate() - aw[1].w * c0) / w;
        let c2 = (aw[2].truncate() - 2.0 * aw[1].w * c1 - aw[2].w * c0) / w;
        [c0, c1, c2]
    }
}
