//! The crease as a curve: the interpolated cutter centres with their contact data, usable
//! wherever the core needs a design curve (chords, 5-axis step selection, NURBS fitting,
//! G-code). Positions between rows come from a C¹ Hermite path through the rows with the
//! exact crease tangents; [`CreaseCurve::exact_at`] projects onto the exact crease by Newton
//! when contact data (normals, contact points) must be exact too.

use glam::{DVec2, DVec3};

use super::newton::{self, Constraint, NewtonOptions};
use super::{CreaseJob, Row};
use crate::geom::{Curve3, HermitePath, ParametricSurface};

/// Exact contact data at one point of the crease.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct CreaseFrame {
    /// Cutter centre (mm).
    pub center: DVec3,
    /// Contact points q1, q2 on S1, S2 (mm).
    pub contact: [DVec3; 2],
    /// Unit normals at the contact points.
    pub normal: [DVec3; 2],
    /// Unit tangent of the crease, oriented along the travel.
    pub tangent: DVec3,
    /// Contact parameters (internal units).
    pub uv: [DVec2; 2],
}

/// The crease path of a run as a [`Curve3`] parametrised by chord length (mm).
#[derive(Clone, Debug)]
pub struct CreaseCurve {
    job: CreaseJob,
    path: HermitePath,
    uv: Vec<[DVec2; 2]>,
}

impl CreaseCurve {
    /// Builds the curve from a run's rows (at least two). Tangents are the exact crease
    /// tangents `±n1 × n2` at each row, oriented along the travel. `None` if fewer than two
    /// rows or a row sits at a singular point.
    #[must_use]
    pub fn from_rows(job: &CreaseJob, rows: &[Row]) -> Option<Self> {
        if rows.len() < 2 {
            return None;
        }
        let mut points = Vec::with_capacity(rows.len());
        let mut tangents = Vec::with_capacity(rows.len());
        for (i, r) in rows.iter().enumerate() {
            let n1 = job.surfaces[0].derivatives_at(r.uv[0]).normal;
            let n2 = job.surfaces[1].derivatives_at(r.uv[1]).normal;
            let mut t = n1.cross(n2).normalize_or_zero();
            let travel = if i + 1 < rows.len() { rows[i + 1].p - r.p } else { r.p - rows[i - 1].p };
            if t.dot(travel) < 0.0 {
                t = -t;
            }
            if t == DVec3::ZERO {
                return None;
            }
            points.push(r.p);
            tangents.push(t);
        }
        let path = HermitePath::new(points, tangents)?;
        Some(Self { job: job.clone(), path, uv: rows.iter().map(|r| r.uv).collect() })
    }

    /// The job the rows came from.
    #[must_use]
    pub fn job(&self) -> &CreaseJob {
        &self.job
    }

    /// The underlying Hermite path.
    #[must_use]
    pub fn path(&self) -> &HermitePath {
        &self.path
    }

    /// Exact contact data at chord-length parameter s: Newton from the Hermite point and the
    /// rows' parameters. `None` if Newton fails there.
    #[must_use]
    pub fn exact_at(&self, s: f64) -> Option<CreaseFrame> {
        let (a, b) = self.path.range();
        let s = s.clamp(a, b);
        let i = self.path.segment(s);
        let params = self.path.params();
        let x = (s - params[i]) / (params[i + 1] - params[i]);
        let guess = [self.uv[i][0].lerp(self.uv[i + 1][0], x), self.uv[i][1].lerp(self.uv[i + 1][1], x)];
        // Periodic parameters may wrap between rows; fall back to the nearer row's values.
        let guess = if (self.uv[i + 1][0] - self.uv[i][0]).length() > 1.0
            || (self.uv[i + 1][1] - self.uv[i][1]).length() > 1.0
        {
            if x < 0.5 { self.uv[i] } else { self.uv[i + 1] }
        } else {
            guess
        };
        let target = self.path.point_at(s);
        let cp = newton::solve(&self.job, guess, Constraint::NearestTo(target), NewtonOptions::default()).ok()?;
        let d = [self.job.surfaces[0].derivatives_at(cp.uv[0]), self.job.surfaces[1].derivatives_at(cp.uv[1])];
        let mut t = cp.tangent;
        if t.dot(self.path.derivatives_at(s)[1]) < 0.0 {
            t = -t;
        }
        Some(CreaseFrame { center: cp.p, contact: [d[0].point, d[1].point], normal: cp.n, tangent: t, uv: cp.uv })
    }
}

impl Curve3 for CreaseCurve {
    fn derivatives_at(&self, s: f64) -> [DVec3; 3] {
        self.path.derivatives_at(s)
    }
    fn range(&self) -> (f64, f64) {
        self.path.range()
    }
}
