//! Seed 001 (fillet-end finishing): every formula of `src/fillet/` against an independent
//! brute-force computation.

use glam::{DVec2, DVec3};
use interpolab::fillet::contact::{ContactFrame, CrossProfile, Pose, effective_curvature, gouge_margin, place};
use interpolab::fillet::orient::{OrientOptions, Strategy, pose_at};
use interpolab::fillet::paths::{FinishOptions, PathSet, iso_scallop};
use interpolab::fillet::{PartSamples, gouge};
use interpolab::geom::{Cutter, LocalGeometry, ParametricSurface, Plane, ProjectOptions, Surface, project_point};
use interpolab::scene::finish::{FINISH_PRESETS, FinishJob, FinishScene};

fn plane() -> Surface {
    Surface::Plane(Plane::new(DVec3::ZERO, DVec3::Z, DVec3::X, [-50.0, 50.0], [-50.0, 50.0]))
}

/// Whether the point lies inside the cutter solid (by the shared profile function only).
fn inside(cutter: &Cutter, tip: DVec3, axis: DVec3, p: DVec3) -> bool {
    let w = p - tip;
    let z = w.dot(axis);
    let rho = (w - z * axis).length();
    match cutter.bottom_height_mm(rho) {
        Some(h) => z >= h && z <= cutter.flute_length_mm,
        None => false,
    }
}

/// Height above the tangent plane of the cutter's lower boundary in the normal section of
/// direction t at distance s: bisection between the tangent plane and 1 mm above it.
fn section_height(cutter: &Cutter, tip: DVec3, axis: DVec3, q: DVec3, n: DVec3, t: DVec3, s: f64) -> f64 {
    let (mut lo, mut hi) = (-1e-3, 1.0);
    assert!(inside(cutter, tip, axis, q + s * t + hi * n), "1 mm above the contact is not inside the cutter");
    for _ in 0..80 {
        let mid = 0.5 * (lo + hi);
        if inside(cutter, tip, axis, q + s * t + mid * n) {
            hi = mid;
        } else {
            lo = mid;
        }
    }
    0.5 * (lo + hi)
}

#[test]
fn effective_curvature_matches_the_numerical_envelope() {
    let surf = plane();
    let mut checked = 0;
    for (big_r, r) in [(5.0, 1.0), (5.0, 2.5), (3.0, 0.5), (8.0, 2.0), (5.0, 5.0)] {
        let cutter = Cutter::fillet(big_r, r).unwrap();
        for lead_deg in [1.0f64, 3.0, 8.0, 15.0, 30.0] {
            for tilt_deg in [-10.0f64, 0.0, 5.0, 20.0] {
                let pose = Pose::from_lead_tilt(lead_deg.to_radians(), tilt_deg.to_radians());
                let frame = ContactFrame::new(&surf, DVec2::new(1.0, 2.0), DVec3::new(1.0, 0.3, 0.0)).unwrap();
                let (tip, axis) = place(&cutter, &frame, &pose);
                for k in 0..12 {
                    let theta = std::f64::consts::PI * f64::from(k) / 12.0;
                    let t = frame.direction(theta);
                    let kappa = effective_curvature(&cutter, &pose, theta);
                    // Symmetric second difference cancels the cubic term; Richardson the quartic.
                    // Within the corner's arc between the contact and the flat bottom (r·α).
                    let s = 0.04f64.min(0.25 * r * pose.inclination_rad);
                    let k_of = |s: f64| {
                        let zp = section_height(&cutter, tip, axis, frame.point, frame.normal, t, s);
                        let zm = section_height(&cutter, tip, axis, frame.point, frame.normal, t, -s);
                        (zp + zm) / (s * s)
                    };
                    let num = (4.0 * k_of(0.5 * s) - k_of(s)) / 3.0;
                    assert!(
                        (num - kappa).abs() <= 2e-3 * kappa + 2e-5,
                        "R {big_r} r {r} lead {lead_deg} tilt {tilt_deg} θ {:.1}°: closed form {kappa}, envelope {num}",
                        theta.to_degrees()
                    );
                    checked += 1;
                }
            }
        }
    }
    assert_eq!(checked, 5 * 5 * 4 * 12);
}

#[test]
fn ball_is_round_and_flat_gives_sin_lead_over_r() {
    let ball = Cutter::ball(4.0).unwrap();
    let flat = Cutter::flat(6.0).unwrap();
    for lead_deg in [2.0f64, 10.0, 25.0] {
        let lead = lead_deg.to_radians();
        let pose = Pose::from_lead_tilt(lead, 0.0);
        for k in 0..36 {
            let th = f64::from(k) * 5f64.to_radians();
            assert!((effective_curvature(&ball, &pose, th) - 0.25).abs() < 1e-12);
        }
        let across = effective_curvature(&flat, &pose, std::f64::consts::FRAC_PI_2);
        assert!((across - lead.sin() / 6.0).abs() < 1e-12, "{across}");
        // Along the feed the rim is a sharp edge.
        assert!(effective_curvature(&flat, &pose, 0.0) > 1e5);
    }
}

#[test]
fn lead_and_tilt_round_trip_and_place_the_contact_on_the_cutter() {
    let surf = plane();
    let cutter = Cutter::fillet(5.0, 1.5).unwrap();
    for (l, w) in [(3.0f64, 0.0f64), (10.0, -7.0), (25.0, 15.0)] {
        let p = Pose::from_lead_tilt(l.to_radians(), w.to_radians());
        assert!((p.lead_rad().to_degrees() - l).abs() < 1e-9);
        assert!((p.tilt_rad().to_degrees() - w).abs() < 1e-9);
        let frame = ContactFrame::new(&surf, DVec2::ZERO, DVec3::X).unwrap();
        let (tip, axis) = place(&cutter, &frame, &p);
        // The contact is on the cutter's surface: inside just above, outside just below.
        assert!(inside(&cutter, tip, axis, frame.point + 1e-7 * DVec3::Z));
        assert!(!inside(&cutter, tip, axis, frame.point - 1e-7 * DVec3::Z));
        // And nothing of the cutter is below the plane (dense sample of the lower surface).
        for i in 0..360 {
            let phi = f64::from(i).to_radians();
            let e1 = interpolab::geom::any_perpendicular(axis);
            let e = phi.cos() * e1 + phi.sin() * axis.cross(e1);
            for j in 0..=20 {
                let b = f64::from(j) / 20.0 * std::f64::consts::FRAC_PI_2;
                let pnt = tip + (3.5 + 1.5 * b.sin()) * e + 1.5 * (1.0 - b.cos()) * axis;
                assert!(pnt.z > -1e-12, "{pnt}");
            }
        }
    }
}

#[test]
fn ball_on_a_plane_gives_the_textbook_strip() {
    let surf = plane();
    for (big_r, h) in [(5.0, 0.01), (3.0, 0.001), (10.0, 0.005)] {
        let ball = Cutter::ball(big_r).unwrap();
        let frame = ContactFrame::new(&surf, DVec2::ZERO, DVec3::X).unwrap();
        let prof = CrossProfile::new(&ball, &surf, frame, &Pose { inclination_rad: 0.0, azimuth_rad: 0.0 });
        let w = prof.reach(h, 1.0) + prof.reach(h, -1.0);
        let textbook = 2.0 * (2.0 * big_r * h).sqrt();
        assert!((w - textbook).abs() < 1e-3 * textbook, "R {big_r} h {h}: {w} vs {textbook}");
    }
}

fn job(id: &str) -> FinishJob {
    let p = FINISH_PRESETS.iter().find(|p| p.id == id).unwrap();
    FinishScene::from_json(p.json).unwrap().job().unwrap()
}

fn paths(job: &FinishJob, strategy: Strategy) -> PathSet {
    let part = PartSamples::new(&job.surface, job.options.part_grid);
    iso_scallop(&job.surface, &job.cutter, strategy, &job.options, &part).unwrap()
}

#[test]
fn quick_numbers() {
    for p in FINISH_PRESETS {
        let j = job(p.id);
        for s in [Strategy::Matched, Strategy::Ball] {
            let t = std::time::Instant::now();
            let ps = paths(&j, s);
            let st = ps.stats(1000.0);
            eprintln!("{} {}: {:?} {:?} refused {}", p.id, s.name(), st, t.elapsed(), ps.refused.len());
        }
    }
}
