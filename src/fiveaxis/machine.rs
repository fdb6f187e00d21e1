//! Kinematic models of four five-axis machine structures, with forward and inverse
//! kinematics between joint values and the tool pose in workpiece coordinates.
//!
//! # Frames and conventions (also in `docs/fiveaxis.md`)
//!
//! - **Machine frame M**: right-handed X, Y, Z of the linear axes. With every rotary axis at
//!   0 the tool axis is +Z_M.
//! - **Workpiece frame W**: fixed to the part (to the table for table-rotating axes). With
//!   every rotary axis at 0, W coincides with M.
//! - **Tool axis** T: unit vector from the tool tip toward the spindle.
//! - **Tool tip**: the programmed point, the bottom of the ball (`tip = centre − R·T`).
//! - **Rotation sense**: a joint angle θ turns its *moving element* (the table or the head)
//!   by +θ about the +X (A), +Y (B) or +Z (C) direction by the right-hand rule. (No ISO
//!   "primed" reversal for tables: the workpiece itself turns by +θ.)
//! - **Linear joints** X, Y, Z: table machines — the tool tip in M (tool length compensated,
//!   the tool stays parallel to Z_M); head machines — the head's *control point* Q in M, a
//!   point on the outer head axis (for `head-bc` on the C axis; for `head-a-table-c` the
//!   point the A offset is measured from).
//!
//! | kind | axes | chain, workpiece → machine | tool in M |
//! |---|---|---|---|
//! | `table-ac` | A (table, about X), C (table on A, about its own Z) | `x_M = A(a)·C(c)·x_W` | T_M = Z, tip_M = (X,Y,Z) |
//! | `table-bc` | B (table, about Y), C (table on B) | `x_M = B(b)·C(c)·x_W` | T_M = Z, tip_M = (X,Y,Z) |
//! | `head-bc` | C (head, about Z), B (on C, about Y) | `x_M = x_W` | T_M = Rz(c)Ry(b)Z, tip = Q + Rz(c)·o_B − L·T_M |
//! | `head-a-table-c` | A (head, about X), C (table, about Z) | `x_M = C(c)·x_W` | T_M = Rx(a)Z, tip_M = Q + o_A − L·T_M |
//!
//! `A(a)` is the rotation by a about the line through the A pivot p_A parallel to X:
//! `x ↦ p_A + Rx(a)(x − p_A)`; likewise B (∥ Y), C (∥ Z). Table pivots are points on the axes
//! in W at zero angles; head offsets o_A, o_B are vectors from Q to a point of that axis at
//! zero angles; L is the tool length from that head axis to the tool tip.

use glam::{DMat3, DVec3};
use thiserror::Error;

use crate::numerics::tolerance;

/// The four machine structures.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Default)]
pub enum MachineKind {
    /// Table-tilting A/C: A trunnion about X carries a C rotary table (the paper's UCP710
    /// type).
    #[default]
    TableAC,
    /// Table-tilting B/C: B trunnion about Y carries a C rotary table.
    TableBC,
    /// Spindle-tilting head: C about Z carries B about Y; the table does not turn.
    HeadBC,
    /// Mixed: the head tilts about X (A), the table turns about Z (C).
    HeadATableC,
}

impl MachineKind {
    /// All kinds.
    pub const ALL: [Self; 4] = [Self::TableAC, Self::TableBC, Self::HeadBC, Self::HeadATableC];

    /// The scene-file name (`table-ac`, `table-bc`, `head-bc`, `head-a-table-c`).
    #[must_use]
    pub fn as_str(self) -> &'static str {
        match self {
            Self::TableAC => "table-ac",
            Self::TableBC => "table-bc",
            Self::HeadBC => "head-bc",
            Self::HeadATableC => "head-a-table-c",
        }
    }

    /// The kind with this scene-file name.
    #[must_use]
    pub fn from_name(name: &str) -> Option<Self> {
        Self::ALL.into_iter().find(|k| k.as_str() == name)
    }

    /// Names of the two rotary axes, tilting axis first: `["A", "C"]` or `["B", "C"]`.
    #[must_use]
    pub fn axis_names(self) -> [&'static str; 2] {
        match self {
            Self::TableAC | Self::HeadATableC => ["A", "C"],
            Self::TableBC | Self::HeadBC => ["B", "C"],
        }
    }

    /// Whether the tool length enters the kinematics (head machines).
    #[must_use]
    pub fn uses_tool_length(self) -> bool {
        matches!(self, Self::HeadBC | Self::HeadATableC)
    }

    /// Which pivots the kind reads, by rotary axis: `[tilt, C]`. `head-bc` has no C pivot (Q
    /// lies on the C axis by definition).
    #[must_use]
    pub fn has_pivot(self) -> [bool; 2] {
        match self {
            Self::HeadBC => [true, false],
            _ => [true, true],
        }
    }
}

/// A five-axis machine: structure, pivots, tool length and rotary travel.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Machine {
    /// Structure.
    pub kind: MachineKind,
    /// Pivots of the two rotary axes `[tilt, C]` (mm): table axes — a point on the axis in
    /// workpiece coordinates at zero angles; head axes — the offset from the control point Q
    /// to a point on the axis at zero angles. See the module table.
    pub pivots_mm: [DVec3; 2],
    /// Head machines: distance along the spindle from the last head axis to the tool tip
    /// (mm). Table machines ignore it (tool length compensation).
    pub tool_length_mm: f64,
    /// Travel of the two rotary axes `[tilt, C]` (rad), `None` for unlimited.
    pub limits_rad: [Option<[f64; 2]>; 2],
}

impl Default for Machine {
    /// A table-tilting A/C machine with both axes through the workpiece origin, A within
    /// ±120°, C unlimited — the machine used when a scene names none.
    fn default() -> Self {
        Self {
            kind: MachineKind::TableAC,
            pivots_mm: [DVec3::ZERO; 2],
            tool_length_mm: 0.0,
            limits_rad: [Some([-120f64.to_radians(), 120f64.to_radians()]), None],
        }
    }
}

/// Joint values of one block: the three linear axes and the two rotary axes.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Joints {
    /// X, Y, Z (mm) — see the module docs for the point they position.
    pub xyz_mm: DVec3,
    /// Rotary axes `[tilt, C]` (rad), named by [`MachineKind::axis_names`].
    pub rotary_rad: [f64; 2],
}

impl Joints {
    /// Linear interpolation of every joint, as the machine moves between two blocks:
    /// `self + τ·(other − self)`.
    #[must_use]
    pub fn lerp(&self, other: &Self, tau: f64) -> Self {
        Self {
            xyz_mm: self.xyz_mm.lerp(other.xyz_mm, tau),
            rotary_rad: [
                self.rotary_rad[0] + tau * (other.rotary_rad[0] - self.rotary_rad[0]),
                self.rotary_rad[1] + tau * (other.rotary_rad[1] - self.rotary_rad[1]),
            ],
        }
    }
}

/// Where the tool is, in workpiece coordinates.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ToolPose {
    /// The tool tip (mm).
    pub tip_in_workpiece: DVec3,
    /// Unit tool axis, tip → spindle.
    pub axis_in_workpiece: DVec3,
}

/// Why a tool pose has no joint values on this machine.
#[derive(Clone, Debug, Error, PartialEq)]
pub enum KinematicsError {
    /// The tool axis is (almost) zero or not finite.
    #[error("the tool axis {axis:?} is zero or not finite; give a non-zero direction")]
    DegenerateAxis {
        /// The vector given.
        axis: [f64; 3],
    },
    /// Every solution needs a rotary angle outside its travel.
    #[error("the tool axis ({:.4}, {:.4}, {:.4}) needs {} outside its travel [{:.3}°, {:.3}°]; change the tool-axis rule (lead/tilt) so {axis_name} stays within travel, or widen machine.limits", tool_axis[0], tool_axis[1], tool_axis[2], needed(axis_name, needed_deg), limits_deg[0], limits_deg[1])]
    OutOfTravel {
        /// `A`, `B` or `C`.
        axis_name: &'static str,
        /// The angles the solution branches need (deg).
        needed_deg: Vec<f64>,
        /// The axis' travel (deg).
        limits_deg: [f64; 2],
        /// The tool axis asked for (workpiece coordinates).
        tool_axis: [f64; 3],
    },
    /// The tool tip is not finite.
    #[error("the tool tip {tip:?} is not finite")]
    NonFinite {
        /// The point given.
        tip: [f64; 3],
    },
}

fn needed(name: &str, deg: &[f64]) -> String {
    let list: Vec<String> = deg.iter().map(|d| format!("{d:.3}°")).collect();
    format!("{name} = {}", list.join(" or "))
}

fn rot(axis_index: usize, angle: f64) -> DMat3 {
    match axis_index {
        0 => DMat3::from_rotation_x(angle),
        1 => DMat3::from_rotation_y(angle),
        _ => DMat3::from_rotation_z(angle),
    }
}

/// Rotation by `angle` about the line through `pivot` along world axis `axis_index`.
fn turn_about(axis_index: usize, pivot: DVec3, angle: f64, x: DVec3) -> DVec3 {
    pivot + rot(axis_index, angle) * (x - pivot)
}

/// `angle` shifted by whole turns to lie nearest `near`.
fn nearest_turn(angle: f64, near: f64) -> f64 {
    let tau = std::f64::consts::TAU;
    angle + tau * ((near - angle) / tau).round()
}

/// The representatives of `angle` (mod 2π) inside `limits`, nearest `near` first; or the one
/// nearest `near` when unlimited.
fn admissible(angle: f64, near: f64, limits: Option<[f64; 2]>) -> Vec<f64> {
    let tau = std::f64::consts::TAU;
    let base = nearest_turn(angle, near);
    match limits {
        None => vec![base],
        Some([lo, hi]) => {
            let slack = tolerance::ANGLE_LIMIT_SLACK_RAD;
            let mut v: Vec<f64> = (-3..=3)
                .map(|k| base + tau * f64::from(k))
                .filter(|a| *a >= lo - slack && *a <= hi + slack)
                .map(|a| a.clamp(lo, hi))
                .collect();
            v.sort_by(|x, y| (x - near).abs().total_cmp(&(y - near).abs()));
            v
        }
    }
}

impl Machine {
    /// Names of the two rotary axes (`["A", "C"]` or `["B", "C"]`).
    #[must_use]
    pub fn axis_names(&self) -> [&'static str; 2] {
        self.kind.axis_names()
    }

    /// Index (0 = X, 1 = Y, 2 = Z) of the direction of the tilting axis.
    fn tilt_axis_index(&self) -> usize {
        match self.kind {
            MachineKind::TableAC | MachineKind::HeadATableC => 0,
            MachineKind::TableBC | MachineKind::HeadBC => 1,
        }
    }

    /// `machine_from_workpiece` for the table axes at these angles (identity for head-bc).
    fn machine_from_workpiece(&self, angles: [f64; 2], x_w: DVec3) -> DVec3 {
        let [p_tilt, p_c] = self.pivots_mm;
        match self.kind {
            MachineKind::TableAC | MachineKind::TableBC => {
                let on_c = turn_about(2, p_c, angles[1], x_w);
                turn_about(self.tilt_axis_index(), p_tilt, angles[0], on_c)
            }
            MachineKind::HeadBC => x_w,
            MachineKind::HeadATableC => turn_about(2, p_c, angles[1], x_w),
        }
    }

    /// Inverse of [`Self::machine_from_workpiece`].
    fn workpiece_from_machine(&self, angles: [f64; 2], x_m: DVec3) -> DVec3 {
        let [p_tilt, p_c] = self.pivots_mm;
        match self.kind {
            MachineKind::TableAC | MachineKind::TableBC => {
                let on_c = turn_about(self.tilt_axis_index(), p_tilt, -angles[0], x_m);
                turn_about(2, p_c, -angles[1], on_c)
            }
            MachineKind::HeadBC => x_m,
            MachineKind::HeadATableC => turn_about(2, p_c, -angles[1], x_m),
        }
    }

    /// Rotation part of `machine_from_workpiece`.
    fn machine_from_workpiece_rot(&self, angles: [f64; 2]) -> DMat3 {
        match self.kind {
            MachineKind::TableAC | MachineKind::TableBC => rot(self.tilt_axis_index(), angles[0]) * rot(2, angles[1]),
            MachineKind::HeadBC => DMat3::IDENTITY,
            MachineKind::HeadATableC => rot(2, angles[1]),
        }
    }

    /// Tool axis in the machine frame.
    fn axis_in_machine(&self, angles: [f64; 2]) -> DVec3 {
        match self.kind {
            MachineKind::TableAC | MachineKind::TableBC => DVec3::Z,
            MachineKind::HeadBC => rot(2, angles[1]) * (rot(1, angles[0]) * DVec3::Z),
            MachineKind::HeadATableC => rot(0, angles[0]) * DVec3::Z,
        }
    }

    /// Tool tip minus the linear joints (X, Y, Z), in the machine frame.
    fn tip_offset_in_machine(&self, angles: [f64; 2]) -> DVec3 {
        let l = self.tool_length_mm;
        match self.kind {
            MachineKind::TableAC | MachineKind::TableBC => DVec3::ZERO,
            MachineKind::HeadBC => rot(2, angles[1]) * self.pivots_mm[0] - l * self.axis_in_machine(angles),
            MachineKind::HeadATableC => self.pivots_mm[0] - l * self.axis_in_machine(angles),
        }
    }

    /// Forward kinematics: the tool pose in workpiece coordinates for these joints.
    #[must_use]
    pub fn pose_from_joints(&self, j: &Joints) -> ToolPose {
        let tip_m = j.xyz_mm + self.tip_offset_in_machine(j.rotary_rad);
        let axis_m = self.axis_in_machine(j.rotary_rad);
        ToolPose {
            tip_in_workpiece: self.workpiece_from_machine(j.rotary_rad, tip_m),
            axis_in_workpiece: self.machine_from_workpiece_rot(j.rotary_rad).transpose() * axis_m,
        }
    }

    /// The two orientation solutions `(tilt, c)` for a unit tool axis in W (before whole
    /// turns and limits), and whether the axis is on the singular direction (c free).
    fn orientation_branches(&self, t: DVec3, c_prev: f64) -> [[f64; 2]; 2] {
        let rho = t.x.hypot(t.y);
        let tilt = t.z.clamp(-1.0, 1.0).acos();
        let singular = rho < tolerance::SINGULAR_AXIS_SIN;
        let phi = t.y.atan2(t.x);
        let half_pi = std::f64::consts::FRAC_PI_2;
        let pi = std::f64::consts::PI;
        // c for the branch tilt = +acos(Tz) and for tilt = −acos(Tz) (derivations in the
        // module docs / docs/fiveaxis.md).
        let (c_plus, c_minus) = match self.kind {
            // Rx(a)·Rz(c)·T = Z  ⇒ Rz(c)(Tx, Ty) = (0, sin a).
            MachineKind::TableAC => (half_pi - phi, -half_pi - phi),
            // Ry(b)·Rz(c)·T = Z  ⇒ Rz(c)(Tx, Ty) = (−sin b, 0).
            MachineKind::TableBC => (pi - phi, -phi),
            // T = Rz(c)·Ry(b)·Z = (sin b cos c, sin b sin c, cos b).
            MachineKind::HeadBC => (phi, phi + pi),
            // Rx(a)·Z = Rz(c)·T  ⇒ Rz(c)(Tx, Ty) = (0, −sin a).
            MachineKind::HeadATableC => (-half_pi - phi, half_pi - phi),
        };
        if singular { [[tilt, c_prev], [-tilt, c_prev]] } else { [[tilt, c_plus], [-tilt, c_minus]] }
    }

    /// Whether some solution branch puts the tool along `axis_in_workpiece` (any length) with
    /// every rotary angle at least `margin_rad` inside its travel. The tip does not matter,
    /// nor the previous joints (an angle lies within travel at some whole turn or at none);
    /// an axis that is zero or not finite is not judged here (`true`: the planner names it).
    /// [`Self::joints_from_pose`] finds a solution wherever this holds with a margin of 0.
    #[must_use]
    pub fn reaches_axis(&self, axis_in_workpiece: DVec3, margin_rad: f64) -> bool {
        let Some(t) = axis_in_workpiece.try_normalize() else {
            return true;
        };
        let inside = |angle: f64, limits: Option<[f64; 2]>| match limits {
            None => true,
            Some([lo, hi]) => (-3..=3).any(|k| {
                let a = angle + std::f64::consts::TAU * f64::from(k);
                a >= lo + margin_rad - tolerance::ANGLE_LIMIT_SLACK_RAD
                    && a <= hi - margin_rad + tolerance::ANGLE_LIMIT_SLACK_RAD
            }),
        };
        self.orientation_branches(t, 0.0)
            .iter()
            .any(|&[tilt, c]| inside(tilt, self.limits_rad[0]) && inside(c, self.limits_rad[1]))
    }

    /// The unit axis nearest `axis_in_workpiece` whose tilt (the angle from the C axis,
    /// `acos(z)`, every structure's) lies at least `margin_rad` inside the tilting axis'
    /// travel: the axis turned toward or away from +z in its own vertical plane, its C kept.
    /// `None` when the axis is zero or not finite, or the result is still out of reach (a
    /// limited C, or a travel narrower than twice the margin). Along a path of smooth axes
    /// the result is smooth: the least change that brings each within reach.
    #[must_use]
    pub fn nearest_reachable_axis(&self, axis_in_workpiece: DVec3, margin_rad: f64) -> Option<DVec3> {
        let t = axis_in_workpiece.try_normalize()?;
        let polar = t.z.clamp(-1.0, 1.0).acos();
        let pi = std::f64::consts::PI;
        // The tilts a branch can take: [lo, hi] and, the other branch, [−hi, −lo], within [0, π].
        let (ranges, n): ([[f64; 2]; 2], usize) = match self.limits_rad[0] {
            None => ([[0.0, pi]; 2], 1),
            Some([lo, hi]) => ([[lo, hi], [-hi, -lo]], 2),
        };
        let mut best: Option<f64> = None;
        for &[lo, hi] in &ranges[..n] {
            let (lo, hi) = ((lo + margin_rad).max(0.0), (hi - margin_rad).min(pi));
            if lo > hi {
                continue;
            }
            let p = polar.clamp(lo, hi);
            if best.is_none_or(|b| (p - polar).abs() < (b - polar).abs()) {
                best = Some(p);
            }
        }
        let p = best?;
        let rho = t.x.hypot(t.y);
        // On the C axis itself any horizontal direction is as near: +X.
        let (cx, cy) = if rho > 0.0 { (t.x / rho, t.y / rho) } else { (1.0, 0.0) };
        let out = DVec3::new(p.sin() * cx, p.sin() * cy, p.cos());
        self.reaches_axis(out, 0.0).then_some(out)
    }

    /// Inverse kinematics: joint values putting the tool tip at `tip_in_workpiece` with unit
    /// axis `axis_in_workpiece`, choosing among the solution branches (tilt = ±acos, C plus
    /// whole turns) the one within travel nearest `previous` (sum of rotary moves); without
    /// a previous block, nearest zero. On the singular direction (tool axis along the C axis)
    /// C keeps its previous value.
    ///
    /// # Errors
    /// [`KinematicsError`]: a zero or non-finite axis or tip, or no branch within travel.
    pub fn joints_from_pose(
        &self,
        tip_in_workpiece: DVec3,
        axis_in_workpiece: DVec3,
        previous: Option<&Joints>,
    ) -> Result<Joints, KinematicsError> {
        let t = axis_in_workpiece;
        if !(t.is_finite() && t.length() > tolerance::MIN_DIRECTION_LENGTH) {
            return Err(KinematicsError::DegenerateAxis { axis: t.to_array() });
        }
        if !tip_in_workpiece.is_finite() {
            return Err(KinematicsError::NonFinite { tip: tip_in_workpiece.to_array() });
        }
        let t = t.normalize();
        let prev = previous.map_or([0.0, 0.0], |p| p.rotary_rad);
        let branches = self.orientation_branches(t, prev[1]);
        let mut best: Option<([f64; 2], f64)> = None;
        let mut tilt_ok = false;
        for [tilt, c] in branches {
            let tilts = admissible(tilt, prev[0], self.limits_rad[0]);
            if tilts.is_empty() {
                continue;
            }
            tilt_ok = true;
            let cs = admissible(c, prev[1], self.limits_rad[1]);
            if let (Some(&a), Some(&c)) = (tilts.first(), cs.first()) {
                let cost = (a - prev[0]).abs() + (c - prev[1]).abs();
                if best.is_none_or(|(_, b)| cost < b) {
                    best = Some(([a, c], cost));
                }
            }
        }
        let Some((angles, _)) = best else {
            let names = self.axis_names();
            let (i, name) = if tilt_ok { (1, names[1]) } else { (0, names[0]) };
            let needed_deg = branches.iter().map(|b| b[i].to_degrees()).collect();
            let limits = self.limits_rad[i].unwrap_or([f64::NEG_INFINITY, f64::INFINITY]);
            return Err(KinematicsError::OutOfTravel {
                axis_name: name,
                needed_deg,
                limits_deg: [limits[0].to_degrees(), limits[1].to_degrees()],
                tool_axis: t.to_array(),
            });
        };
        let tip_m = self.machine_from_workpiece(angles, tip_in_workpiece);
        Ok(Joints { xyz_mm: tip_m - self.tip_offset_in_machine(angles), rotary_rad: angles })
    }

    /// The joints that put the tool tip at `tip_in_workpiece` with the rotary axes at
    /// `rotary_rad` (`[tilt, C]`): the angles as given, the linear joints from the inverse of
    /// the forward kinematics at those angles. This is what a controller under
    /// tool-centre-point control (`G43.4`, LinuxCNC's TCP kinematics) commands for a
    /// programmed tip and rotary position; [`Self::pose_from_joints`] of the result gives the
    /// tip back.
    #[must_use]
    pub fn joints_at_angles(&self, tip_in_workpiece: DVec3, rotary_rad: [f64; 2]) -> Joints {
        let tip_m = self.machine_from_workpiece(rotary_rad, tip_in_workpiece);
        Joints { xyz_mm: tip_m - self.tip_offset_in_machine(rotary_rad), rotary_rad }
    }

    /// Whether these rotary angles are within travel.
    #[must_use]
    pub fn within_travel(&self, j: &Joints) -> bool {
        (0..2).all(|i| {
            self.limits_rad[i].is_none_or(|[lo, hi]| {
                j.rotary_rad[i] >= lo - tolerance::ANGLE_LIMIT_SLACK_RAD
                    && j.rotary_rad[i] <= hi + tolerance::ANGLE_LIMIT_SLACK_RAD
            })
        })
    }
}
