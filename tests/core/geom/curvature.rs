//! Differential geometry against closed forms: spheres, cylinders and tori (principal
//! curvatures, Euler's formula, geodesic torsion) and the Weingarten normal derivatives
//! against finite differences of the normal.
#[cfg(target_arch = "wasm32")]
use wasm_bindgen_test::wasm_bindgen_test as test;

use crate::support;

use crate::support::Rng;
use glam::{DVec2, DVec3};
use interpolab::geom::{LocalGeometry, ParametricSurface, Surface};
use interpolab::scene::{Orientation, SurfaceSpec, build_surface};

fn build(spec: SurfaceSpec) -> Surface {
    build_surface(&spec, "s").expect("valid surface")
}

fn geo(s: &Surface, uv: DVec2) -> LocalGeometry {
    LocalGeometry::try_new(s.derivatives_at(uv)).expect("regular point")
}

/// A unit tangent at angle `phi` from r_u's direction, in the tangent plane.
fn tangent(g: &LocalGeometry, phi: f64) -> DVec3 {
    let e1 = g.d.du.normalize();
    let e2 = g.d.normal.cross(e1);
    phi.cos() * e1 + phi.sin() * e2
}

#[test]
fn sphere_curvature_is_minus_one_over_radius_in_every_direction_outward() {
    let mut rng = Rng::new(1);
    for (orientation, sign) in [(Orientation::Outward, -1.0), (Orientation::Inward, 1.0)] {
        let s = build(SurfaceSpec::Sphere {
            center: [3.0, 1.0, -2.0],
            radius: 17.0,
            axis: Some([1.0, 1.0, 0.5]),
            ref_dir: None,
            domain: None,
            normal: orientation,
        });
        for _ in 0..100 {
            let uv = DVec2::new(rng.range(-3.0, 3.0), rng.range(-1.4, 1.4));
            let g = geo(&s, uv);
            let (kmax, kmin) = g.principal_curvatures();
            assert!((kmax - sign / 17.0).abs() < 1e-12 && (kmin - sign / 17.0).abs() < 1e-12);
            let t = tangent(&g, rng.range(0.0, std::f64::consts::TAU));
            assert!((g.normal_curvature(t) - sign / 17.0).abs() < 1e-12);
            assert!(g.geodesic_torsion(t).abs() < 1e-12, "umbilic: no geodesic torsion");
        }
    }
}

#[test]
fn cylinder_follows_eulers_formula_and_the_torsion_formula() {
    let rho = 8.0;
    let mut rng = Rng::new(2);
    for (orientation, sign) in [(Orientation::Outward, -1.0), (Orientation::Inward, 1.0)] {
        let s = build(SurfaceSpec::Cylinder {
            origin: [0.0, 0.0, 0.0],
            axis: [0.0, 1.0, 1.0],
            radius: rho,
            ref_dir: None,
            domain: interpolab::scene::DomainSpec { u: [0.0, 360.0], v: [-50.0, 50.0] },
            normal: orientation,
        });
        for _ in 0..100 {
            let uv = DVec2::new(rng.range(0.0, std::f64::consts::TAU), rng.range(-40.0, 40.0));
            let g = geo(&s, uv);
            let p = g.principal();
            // Around the axis: ∓1/ρ; along it: 0.
            let around = sign / rho;
            let (k_big, k_small) = if around > 0.0 { (around, 0.0) } else { (0.0, around) };
            assert!((p.k_max - k_big).abs() < 1e-12 && (p.k_min - k_small).abs() < 1e-12);
            // Principal direction of the around-curvature is r_u's direction.
            let around_dir = if around > 0.0 { p.dir_max } else { p.dir_min };
            assert!(around_dir.dot(g.d.du.normalize()).abs() > 1.0 - 1e-12);
            let phi = rng.range(0.0, std::f64::consts::TAU);
            let t = phi.cos() * p.dir_max + phi.sin() * p.dir_min;
            let euler = p.k_max * phi.cos().powi(2) + p.k_min * phi.sin().powi(2);
            assert!((g.normal_curvature(t) - euler).abs() < 1e-12, "Euler's formula");
            let torsion = (p.k_min - p.k_max) * phi.sin() * phi.cos();
            assert!((g.geodesic_torsion(t) - torsion).abs() < 1e-12, "τ_g = (k_min − k_max) sin φ cos φ");
        }
    }
}

#[test]
fn torus_principal_curvatures_match_the_closed_form() {
    let (big, small) = (40.0, 15.0);
    let s = build(SurfaceSpec::Torus {
        center: [0.0; 3],
        axis: [0.0, 0.0, 1.0],
        major_radius: big,
        minor_radius: small,
        ref_dir: None,
        domain: None,
        normal: Orientation::Outward,
    });
    let mut rng = Rng::new(4);
    for _ in 0..200 {
        let uv = DVec2::new(rng.range(-3.1, 3.1), rng.range(-3.1, 3.1));
        let g = geo(&s, uv);
        // Outward: around the tube −1/r0 (v direction); around the axis −cos v/(R0 + r0 cos v).
        let k_tube = -1.0 / small;
        let k_ring = -uv.y.cos() / (big + small * uv.y.cos());
        let (kmax, kmin) = g.principal_curvatures();
        assert!(
            (kmax - k_tube.max(k_ring)).abs() < 1e-12 && (kmin - k_tube.min(k_ring)).abs() < 1e-12,
            "at {uv:?}: {kmax} {kmin}"
        );
        assert!((g.normal_curvature(g.d.dv) - k_tube).abs() < 1e-12);
        assert!((g.normal_curvature(g.d.du) - k_ring).abs() < 1e-12);
        assert!((g.gaussian_curvature() - k_tube * k_ring).abs() < 1e-14);
    }
}

#[test]
fn weingarten_normal_derivatives_match_finite_differences() {
    let text = include_str!("../../../examples/bspline-floor-wall.json");
    let scene = support::scene(text);
    let s = build_surface(&scene.surfaces[0], "s").expect("valid");
    let torus = build(SurfaceSpec::Torus {
        center: [0.0; 3],
        axis: [1.0, 2.0, 3.0],
        major_radius: 20.0,
        minor_radius: 6.0,
        ref_dir: None,
        domain: None,
        normal: Orientation::Inward,
    });
    let mut rng = Rng::new(6);
    for surf in [s, torus] {
        let d = surf.domain();
        for _ in 0..100 {
            let uv = DVec2::new(
                rng.range(d.u.min + 0.1 * d.u.width(), d.u.max - 0.1 * d.u.width()),
                rng.range(d.v.min + 0.1 * d.v.width(), d.v.max - 0.1 * d.v.width()),
            );
            let g = geo(&surf, uv);
            let (nu, nv) = g.normal_derivatives();
            let h = 1e-6 * d.u.width();
            let fd_u = (surf.derivatives_at(uv + DVec2::X * h).normal - surf.derivatives_at(uv - DVec2::X * h).normal)
                / (2.0 * h);
            let hv = 1e-6 * d.v.width();
            let fd_v = (surf.derivatives_at(uv + DVec2::Y * hv).normal
                - surf.derivatives_at(uv - DVec2::Y * hv).normal)
                / (2.0 * hv);
            assert!((fd_u - nu).length() < 1e-6 * (1.0 + nu.length()), "n_u {nu:?} vs {fd_u:?}");
            assert!((fd_v - nv).length() < 1e-6 * (1.0 + nv.length()), "n_v {nv:?} vs {fd_v:?}");
        }
    }
}
