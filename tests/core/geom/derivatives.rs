//! Every surface type's first and second partial derivatives against central finite
//! differences of its own point evaluation, at random parameters; normals against the rule
//! of the scene format.
#[cfg(target_arch = "wasm32")]
use wasm_bindgen_test::wasm_bindgen_test as test;

use crate::support;

use crate::support::Rng;
use glam::{DVec2, DVec3};
use interpolab::geom::{ParametricSurface, Surface};
use interpolab::scene::{PRESETS, SurfaceSpec, build_surface};

/// One surface of each type, plus a rational NURBS and a non-uniform bicubic.
fn surfaces() -> Vec<(&'static str, Surface)> {
    let scene = |json: &str| support::scene(json);
    let mut out = Vec::new();
    for (name, text) in PRESETS.iter().map(|p| (p.id, p.json)) {
        let s = scene(text);
        for (i, spec) in s.surfaces.iter().enumerate() {
            let built = build_surface(spec, &format!("surfaces[{i}]")).expect("example surfaces are valid");
            out.push((name, built));
        }
    }
    // A tilted, offset torus with a reference direction, inward.
    let torus = SurfaceSpec::Torus {
        center: [1.0, -2.0, 3.0],
        axis: [0.3, -0.4, 1.0],
        major_radius: 30.0,
        minor_radius: 7.0,
        ref_dir: None,
        domain: None,
        normal: interpolab::scene::Orientation::Inward,
    };
    out.push(("tilted torus", build_surface(&torus, "t").expect("valid")));
    // A rational bicubic with non-uniform knots and uneven weights.
    let mut pts = Vec::new();
    let mut wts = Vec::new();
    for i in 0..5 {
        let mut row = Vec::new();
        let mut wrow = Vec::new();
        for j in 0..6 {
            let (x, y) = (i as f64 * 10.0, j as f64 * 8.0);
            row.push([x, y, 3.0 * ((x * 0.07).sin() + (y * 0.05).cos())]);
            wrow.push(0.6 + 0.1 * ((i * 7 + j * 3) % 5) as f64);
        }
        pts.push(row);
        wts.push(wrow);
    }
    let nurbs = SurfaceSpec::Nurbs {
        degree: [3, 3],
        knots_u: vec![0.0, 0.0, 0.0, 0.0, 0.3, 1.0, 1.0, 1.0, 1.0],
        knots_v: vec![-1.0, -1.0, -1.0, -1.0, 0.2, 0.5, 2.0, 2.0, 2.0, 2.0],
        points: pts,
        weights: Some(wts),
        flip_normal: false,
    };
    out.push(("rational bicubic", build_surface(&nurbs, "n").expect("valid")));
    out
}

fn random_uv(s: &Surface, rng: &mut Rng) -> DVec2 {
    let d = s.domain();
    // Keep away from the ends (central differences need room) and from sphere poles.
    let margin_u = 0.05 * d.u.width();
    let margin_v = 0.05 * d.v.width();
    DVec2::new(rng.range(d.u.min + margin_u, d.u.max - margin_u), rng.range(d.v.min + margin_v, d.v.max - margin_v))
}

/// Central difference of `f` along `dir` with step `h`.
fn central(f: impl Fn(DVec2) -> DVec3, uv: DVec2, dir: DVec2, h: f64) -> DVec3 {
    (f(uv + dir * h) - f(uv - dir * h)) / (2.0 * h)
}

#[test]
fn first_and_second_derivatives_match_central_differences() {
    let mut rng = Rng::new(7);
    for (name, s) in surfaces() {
        let scale = s.derivatives_at(random_uv(&s, &mut rng)).du.length().max(1.0);
        for _ in 0..200 {
            let uv = random_uv(&s, &mut rng);
            let d = s.derivatives_at(uv);
            let (eu, ev) = (DVec2::X, DVec2::Y);
            let w = s.domain();
            // Step relative to the parameter range: h³ truncation vs rounding / h.
            let (hu, hv) = (1e-5 * w.u.width(), 1e-5 * w.v.width());
            let p = |x: DVec2| s.point_at(x);
            let tol = 2e-6 * scale.max(d.du.length()).max(d.dv.length());
            let fd_u = central(p, uv, eu, hu);
            let fd_v = central(p, uv, ev, hv);
            assert!(
                (fd_u - d.du).length() <= tol * (1.0 + d.du.length()),
                "{name}: r_u {:?} vs fd {:?} at {uv:?}",
                d.du,
                fd_u
            );
            assert!(
                (fd_v - d.dv).length() <= tol * (1.0 + d.dv.length()),
                "{name}: r_v {:?} vs fd {:?} at {uv:?}",
                d.dv,
                fd_v
            );
            // Second derivatives: differences of the analytic first derivatives.
            let du = |x: DVec2| s.derivatives_at(x).du;
            let dv = |x: DVec2| s.derivatives_at(x).dv;
            let fd_uu = central(du, uv, eu, hu);
            let fd_uv = central(du, uv, ev, hv);
            let fd_vu = central(dv, uv, eu, hu);
            let fd_vv = central(dv, uv, ev, hv);
            let tol2 = 1e-5 * (1.0 + d.duu.length() + d.dvv.length() + d.duv.length());
            assert!((fd_uu - d.duu).length() <= tol2, "{name}: r_uu {:?} vs fd {:?}", d.duu, fd_uu);
            assert!((fd_vv - d.dvv).length() <= tol2, "{name}: r_vv {:?} vs fd {:?}", d.dvv, fd_vv);
            assert!((fd_uv - d.duv).length() <= tol2, "{name}: r_uv {:?} vs fd {:?}", d.duv, fd_uv);
            assert!((fd_vu - d.duv).length() <= tol2, "{name}: r_vu {:?} vs fd {:?}", d.duv, fd_vu);
        }
    }
}

#[test]
fn normals_are_unit_and_follow_each_types_rule() {
    let mut rng = Rng::new(11);
    for (name, s) in surfaces() {
        for _ in 0..100 {
            let uv = random_uv(&s, &mut rng);
            let d = s.derivatives_at(uv);
            assert!((d.normal.length() - 1.0).abs() < 1e-12, "{name}: |n| = {}", d.normal.length());
            let cross = d.du.cross(d.dv).normalize();
            let along = d.normal.dot(cross);
            assert!((along.abs() - 1.0).abs() < 1e-9, "{name}: normal not ⊥ tangent plane");
            match &s {
                Surface::Plane(p) => assert!((d.normal - p.frame.a).length() < 1e-15),
                Surface::Cylinder(c) => {
                    let radial = d.point - c.origin - c.frame.a * (d.point - c.origin).dot(c.frame.a);
                    assert!((d.normal - c.sign * radial.normalize()).length() < 1e-12, "{name}");
                }
                Surface::Sphere(sp) => {
                    assert!((d.normal - sp.sign * (d.point - sp.center).normalize()).length() < 1e-12, "{name}");
                }
                Surface::Torus(t) => {
                    // Away from the nearest point of the tube's centre circle.
                    let rel = d.point - t.center;
                    let planar = rel - t.frame.a * rel.dot(t.frame.a);
                    let ring = t.center + planar.normalize() * t.major_radius;
                    assert!((d.normal - t.sign * (d.point - ring).normalize()).length() < 1e-12, "{name}");
                }
                Surface::Nurbs(n) => {
                    let sign = if n.flipped() { -1.0 } else { 1.0 };
                    assert!((d.normal - sign * cross).length() < 1e-12, "{name}");
                }
            }
        }
    }
}

#[test]
fn analytic_surfaces_lie_where_their_definitions_say() {
    let mut rng = Rng::new(3);
    for (name, s) in surfaces() {
        for _ in 0..100 {
            let uv = random_uv(&s, &mut rng);
            let x = s.point_at(uv);
            match &s {
                Surface::Cylinder(c) => {
                    let rel = x - c.origin;
                    let radial = rel - c.frame.a * rel.dot(c.frame.a);
                    assert!((radial.length() - c.radius).abs() < 1e-12 * c.radius.max(1.0) * 10.0, "{name}");
                    assert!((rel.dot(c.frame.a) - uv.y).abs() < 1e-12, "{name}: v is the axial position");
                }
                Surface::Sphere(sp) => assert!(((x - sp.center).length() - sp.radius).abs() < 1e-11, "{name}"),
                Surface::Torus(t) => {
                    let rel = x - t.center;
                    let h = rel.dot(t.frame.a);
                    let rho = (rel - t.frame.a * h).length();
                    let tube = ((rho - t.major_radius).powi(2) + h * h).sqrt();
                    assert!((tube - t.minor_radius).abs() < 1e-11, "{name}: distance to the centre circle");
                }
                _ => {}
            }
        }
    }
}

/// `first_order_at` gives `derivatives_at`'s point, first derivatives and normal to the last
/// bit on every surface type (a NURBS by its own first-derivative sums), and a contact frame
/// built from it (`ContactFrame::first_order`, what a finishing program's planner places the
/// cutter on) equals the full frame in everything but the second form, `None` at the same
/// places: a planner that switched to it plans the same steps.
#[test]
fn first_order_evaluation_agrees_with_the_full_one_to_the_bit() {
    use interpolab::fillet::ContactFrame;
    let mut rng = Rng::new(29);
    for (name, s) in surfaces() {
        for _ in 0..300 {
            let uv = random_uv(&s, &mut rng);
            let (d, f) = (s.derivatives_at(uv), s.first_order_at(uv));
            assert_eq!((d.point, d.du, d.dv, d.normal), (f.point, f.du, f.dv, f.normal), "{name} at {uv}");
            let hint = DVec3::new(rng.range(-1.0, 1.0), rng.range(-1.0, 1.0), rng.range(-1.0, 1.0));
            let (full, light) = (ContactFrame::new(&s, uv, hint), ContactFrame::first_order(&s, uv, hint));
            assert_eq!(full.is_some(), light.is_some(), "{name} at {uv}");
            if let (Some(a), Some(b)) = (full, light) {
                assert_eq!(
                    (a.uv, a.point, a.normal, a.feed, a.cross),
                    (b.uv, b.point, b.normal, b.feed, b.cross),
                    "{name}"
                );
            }
        }
        // A hint along the normal leaves (almost) no tangential part: both frames alike.
        let uv = random_uv(&s, &mut rng);
        let n = s.derivatives_at(uv).normal;
        let (full, light) = (ContactFrame::new(&s, uv, n), ContactFrame::first_order(&s, uv, n));
        assert_eq!(full.map(|a| (a.feed, a.cross)), light.map(|b| (b.feed, b.cross)), "{name}");
    }
}
