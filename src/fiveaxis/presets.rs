//! Ready-made five-axis cases: the paper's Example 1 and the blade section of its Table 1.

use glam::DVec3;

use super::blade::NacaProfile;
use super::machine::{Machine, MachineKind};
use super::path::{ProfileBall, ProfilePath, ToolSide};
use super::toolaxis::ToolAxisRule;
use crate::geom::Curve3;

/// A circular arc in a plane z = const, parametrised by the angle travelled (rad) from
/// `start_rad` (measured from +X toward +Y), counter-clockwise or clockwise seen from +Z.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct CircleArc {
    /// Centre (mm); the arc lies in the plane z = centre.z.
    pub centre: DVec3,
    /// Radius (mm).
    pub radius_mm: f64,
    /// Polar angle of the start point (rad).
    pub start_rad: f64,
    /// Angle travelled over the range (rad, > 0).
    pub sweep_rad: f64,
    /// Sense of travel seen from +Z.
    pub clockwise: bool,
}

impl Curve3 for CircleArc {
    fn derivatives_at(&self, s: f64) -> [DVec3; 3] {
        let s = s.clamp(0.0, self.sweep_rad);
        let k = if self.clockwise { -1.0 } else { 1.0 };
        let (sn, cs) = (self.start_rad + k * s).sin_cos();
        let r = self.radius_mm;
        [
            self.centre + DVec3::new(r * cs, r * sn, 0.0),
            DVec3::new(-r * sn, r * cs, 0.0) * k,
            DVec3::new(-r * cs, -r * sn, 0.0),
        ]
    }
    fn range(&self) -> (f64, f64) {
        (0.0, self.sweep_rad)
    }
}

/// Seed 002's Example 1: everything needed to reproduce it.
#[derive(Debug)]
pub struct Example1 {
    /// The arc of the circle from P1 to P2 as a one-surface path (the cylinder of radius
    /// 25 mm around Z, tool outside), with the tool axis turning from T1 to T2.
    pub path: ProfilePath,
    /// The dual-rotary-table machine.
    pub machine: Machine,
    /// The tolerance E (mm): the paper's chord error 0.01 mm.
    pub tol_mm: f64,
    /// P1, P2: the two contact points of the paper (mm).
    pub contacts: [DVec3; 2],
    /// T1, T2 as printed in the paper (not normalised).
    pub axes: [DVec3; 2],
}

/// Seed 002's Example 1: a circle of radius 25 mm centred on the Z axis at z = 50, contact
/// points P1 (0, 25, 50) and P2 (1.744, 24.939, 50), tool axes T1 (0, 1, 0) and
/// T2 (0.997, −0.070, 0), ball radius 5 mm, on a table-tilting A/C machine (the paper's
/// UCP710 type) with both rotary axes through the workpiece origin, A within ±120°, C
/// unlimited.
///
/// Between P1 and P2 the contact point runs clockwise along the circle (P1 at 90°, P2 at
/// about 86°) and the tool axis turns along the great circle from T1 to T2 in proportion.
/// The paper's tolerance is its chord error, 0.01 mm.
#[must_use]
pub fn example1() -> Example1 {
    let p1 = DVec3::new(0.0, 25.0, 50.0);
    let p2 = DVec3::new(1.744, 24.939, 50.0);
    let t1 = DVec3::new(0.0, 1.0, 0.0);
    let t2 = DVec3::new(0.997, -0.070, 0.0);
    let start = p1.y.atan2(p1.x);
    let sweep = start - p2.y.atan2(p2.x);
    let arc = CircleArc {
        centre: DVec3::new(0.0, 0.0, 50.0),
        radius_mm: 25.0,
        start_rad: start,
        sweep_rad: sweep,
        clockwise: true,
    };
    let rule = ToolAxisRule::Interpolated { from: t1.normalize(), to: t2.normalize() };
    Example1 {
        path: ProfilePath::new(
            Box::new(arc),
            (0.0, sweep),
            ProfileBall { side: ToolSide::Left, ball_radius_mm: 5.0, allowance_mm: 0.0 },
            rule,
        ),
        machine: Machine::default(),
        tol_mm: 0.01,
        contacts: [p1, p2],
        axes: [t1, t2],
    }
}

/// The blade-section case of the Table-1 comparison: a NACA section (chord along +X from
/// the origin, z = 0, as [`NacaProfile::to_path`] with 4000 points, parametrised by chord
/// length) cut all round from outside by a ball of radius 5 mm, tool axis the section's
/// outward normal tipped 30° up toward +Z (rule `normal1`, tilt −30°), on a table-tilting A/C
/// machine whose C axis passes through mid-chord (50, 0) and A axis 40 mm below the section
/// plane.
#[must_use]
pub fn blade_case(profile: NacaProfile) -> Option<(ProfilePath, Machine)> {
    blade_case_with_rule(profile, ToolAxisRule::Normal1 { lead_rad: 0.0, tilt_rad: -30f64.to_radians() })
}

/// [`blade_case`] with another tool-axis rule (the app's choice).
#[must_use]
pub fn blade_case_with_rule(profile: NacaProfile, rule: ToolAxisRule) -> Option<(ProfilePath, Machine)> {
    let curve = profile.to_path(4000)?;
    let range = curve.range();
    let mid = 0.5 * profile.chord_mm;
    let machine = Machine {
        kind: MachineKind::TableAC,
        pivots_mm: [DVec3::new(mid, 0.0, profile.z_mm - 40.0), DVec3::new(mid, 0.0, profile.z_mm)],
        tool_length_mm: 0.0,
        limits_rad: [Some([-120f64.to_radians(), 120f64.to_radians()]), None],
    };
    Some((
        ProfilePath::new(
            Box::new(curve),
            range,
            ProfileBall { side: ToolSide::Right, ball_radius_mm: 5.0, allowance_mm: 0.0 },
            rule,
        ),
        machine,
    ))
}
