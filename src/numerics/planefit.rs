//! The best-fit plane of a point cloud: its centroid and the two largest principal
//! directions, the eigenvectors of the points' covariance matrix found by Jacobi rotations
//! (exact for a symmetric 3×3 matrix after a few sweeps).

use glam::DVec3;

/// Most Jacobi rotations (a 3×3 symmetric matrix converges in well under 20).
pub const JACOBI_MAX_ROTATIONS: usize = 50;

/// Rotations stop once the largest off-diagonal entry is below this fraction of the trace's
/// magnitude (|a00| + |a11| + |a22|).
pub const JACOBI_OFFDIAG_REL: f64 = 1e-15;

/// Smallest scale the stopping test uses, so an all-zero matrix stops at once.
const JACOBI_SCALE_FLOOR: f64 = 1e-300;

/// Eigenvalues and eigenvectors of the symmetric matrix `a` (both triangles are rotated, so
/// it must be symmetric). Returns `(values, vectors)`, unsorted; eigenvector k is column k of
/// `vectors` (`vectors[i][k]`).
#[must_use]
pub fn symmetric_eigen3(mut a: [[f64; 3]; 3]) -> ([f64; 3], [[f64; 3]; 3]) {
    let mut v = [[1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0]];
    for _ in 0..JACOBI_MAX_ROTATIONS {
        let (mut p, mut q, mut big) = (0, 1, 0.0f64);
        for (i, j) in [(0, 1), (0, 2), (1, 2)] {
            if a[i][j].abs() > big {
                (p, q, big) = (i, j, a[i][j].abs());
            }
        }
        if big < JACOBI_OFFDIAG_REL * (a[0][0].abs() + a[1][1].abs() + a[2][2].abs()).max(JACOBI_SCALE_FLOOR) {
            break;
        }
        let theta = 0.5 * (2.0 * a[p][q]).atan2(a[q][q] - a[p][p]);
        let (s, co) = theta.sin_cos();
        for row in &mut a {
            let (akp, akq) = (row[p], row[q]);
            row[p] = co * akp - s * akq;
            row[q] = s * akp + co * akq;
        }
        for k in 0..3 {
            let (apk, aqk) = (a[p][k], a[q][k]);
            a[p][k] = co * apk - s * aqk;
            a[q][k] = s * apk + co * aqk;
        }
        for row in &mut v {
            let (vp, vq) = (row[p], row[q]);
            row[p] = co * vp - s * vq;
            row[q] = s * vp + co * vq;
        }
    }
    ([a[0][0], a[1][1], a[2][2]], v)
}

/// A plane through `origin` spanned by the orthonormal directions `u` (largest spread of the
/// points) and `v` (second largest); all in mm.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct PlaneFit {
    /// The points' centroid (mm).
    pub origin: DVec3,
    /// First principal direction (unit).
    pub u: DVec3,
    /// Second principal direction, perpendicular to `u` (unit).
    pub v: DVec3,
}

/// The plane through the centroid of `points` spanned by the two largest principal
/// directions (eigenvectors of their covariance). An empty slice gives the XY plane through
/// the origin; collinear points give their line and a perpendicular.
#[must_use]
pub fn best_fit_plane(points: &[DVec3]) -> PlaneFit {
    let n = points.len().max(1) as f64;
    let c = points.iter().copied().sum::<DVec3>() / n;
    let mut a = [[0.0f64; 3]; 3];
    for p in points {
        let d = (*p - c).to_array();
        for (i, row) in a.iter_mut().enumerate() {
            for (j, x) in row.iter_mut().enumerate() {
                *x += d[i] * d[j] / n;
            }
        }
    }
    let (values, v) = symmetric_eigen3(a);
    let column = |k: usize| DVec3::new(v[0][k], v[1][k], v[2][k]);
    let mut order = [0usize, 1, 2];
    order.sort_by(|&i, &j| values[j].total_cmp(&values[i]));
    let u = column(order[0]).normalize_or(DVec3::X);
    let w = column(order[1]).normalize_or(DVec3::Y);
    PlaneFit { origin: c, u, v: u.cross(w).cross(u).normalize_or(w) }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn eigen_of_known_matrix() {
        // [[2,1,0],[1,2,0],[0,0,5]]: eigenvalues 1 (x − y), 3 (x + y), 5 (z).
        let (values, v) = symmetric_eigen3([[2.0, 1.0, 0.0], [1.0, 2.0, 0.0], [0.0, 0.0, 5.0]]);
        let mut sorted = values;
        sorted.sort_by(f64::total_cmp);
        for (got, want) in sorted.iter().zip([1.0, 3.0, 5.0]) {
            assert!((got - want).abs() < 1e-12, "{values:?}");
        }
        let a = [[2.0, 1.0, 0.0], [1.0, 2.0, 0.0], [0.0, 0.0, 5.0]];
        for k in 0..3 {
            let x = DVec3::new(v[0][k], v[1][k], v[2][k]);
            let ax = DVec3::new(
                a[0][0] * x.x + a[0][1] * x.y + a[0][2] * x.z,
                a[1][0] * x.x + a[1][1] * x.y + a[1][2] * x.z,
                a[2][0] * x.x + a[2][1] * x.y + a[2][2] * x.z,
            );
            assert!((x.length() - 1.0).abs() < 1e-12);
            assert!((ax - values[k] * x).length() < 1e-12, "column {k}");
        }
    }

    #[test]
    fn ellipse_in_tilted_plane() {
        // x(θ) = c + a cos θ e1 + b sin θ e2 over a full turn: covariance eigenvalues a²/2,
        // b²/2, 0 with eigenvectors e1, e2, e1 × e2.
        let c = DVec3::new(3.0, -2.0, 7.0);
        let e1 = DVec3::new(1.0, 2.0, 2.0) / 3.0;
        let e2 = DVec3::new(2.0, 1.0, -2.0) / 3.0;
        let (a, b) = (5.0, 2.0);
        let n = 360;
        let pts: Vec<DVec3> = (0..n)
            .map(|i| {
                let t = std::f64::consts::TAU * f64::from(i) / f64::from(n);
                c + a * t.cos() * e1 + b * t.sin() * e2
            })
            .collect();
        let fit = best_fit_plane(&pts);
        assert!((fit.origin - c).length() < 1e-12);
        assert!((fit.u.dot(e1).abs() - 1.0).abs() < 1e-12, "u = {}", fit.u);
        assert!((fit.v.dot(e2).abs() - 1.0).abs() < 1e-12, "v = {}", fit.v);
        assert!(fit.u.dot(fit.v).abs() < 1e-12);
        for p in &pts {
            assert!((*p - fit.origin).dot(fit.u.cross(fit.v)).abs() < 1e-12);
        }
    }
}
