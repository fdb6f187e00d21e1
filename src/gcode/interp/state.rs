//! The interpreter's state between blocks: modes, offsets, the tool, and the program
//! position, with the one map from program coordinates to the machine frame.
//!
//! Frames, in the order a programmed point passes through them:
//! 1. **program** (the numbers of the block, in mm after G20 scaling; `prog`),
//! 2. FANUC `G68` rotation about its centre (XY plane),
//! 3. `+ G92/G52` offset,
//! 4. LinuxCNC's XY rotation of the coordinate system (`G10 L2 R`),
//! 5. `+ G54…G59.3` offset → **machine** (the controlled point, tool length not added).
//!
//! Steps 3–5 are `rotate_and_offset_pos` of LinuxCNC's canonical layer; the state keeps the
//! program position as LinuxCNC does, so a change of offset moves the program position, not
//! the tool.

use glam::DVec3;

use super::canon::{Feed, FeedMode, Pose};
use crate::gcode::path::Plane;

/// mm per inch.
pub const MM_PER_INCH: f64 = 25.4;

/// Six axes: X Y Z (mm) A B C (degrees).
pub type Axes = [f64; 6];

/// Coordinate systems: index 1 … 9 = G54 … G59.3 (0 unused).
pub const SYSTEMS: usize = 10;

/// The motion mode (modal group 1).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum MotionMode {
    /// G0.
    Rapid,
    /// G1.
    Linear,
    /// G2.
    ArcCw,
    /// G3.
    ArcCcw,
    /// A canned cycle (its code in tenths: 730, 810 … 890).
    Cycle(i32),
    /// A probing move G38.2 … G38.5 (tenths).
    Probe(i32),
    /// G5.2 NURBS block mode (LinuxCNC), until G5.3.
    LinuxNurbs,
    /// G6.2 NURBS (FANUC).
    FanucNurbs,
    /// G5 cubic spline.
    Cubic,
    /// G5.1 quadratic spline.
    Quadratic,
    /// Spindle-synchronised (G33, G33.1, G76): not modelled.
    Synchronised(i32),
    /// G80: no motion.
    None,
}

/// The cutter compensation side (group 7).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum CompSide {
    /// G40.
    Off,
    /// G41.
    Left,
    /// G42.
    Right,
}

/// The state between blocks.
#[derive(Clone, Debug)]
pub struct State {
    /// Inches (G20) rather than mm (G21).
    pub inch: bool,
    /// A G20 or G21 was programmed.
    pub units_given: bool,
    /// G90 (else G91).
    pub absolute: bool,
    /// G90.1: arc centres absolute (else G91.1, offsets from the start).
    pub arc_absolute: bool,
    /// G17/G18/G19.
    pub plane: Plane,
    /// Group 1.
    pub motion: MotionMode,
    /// Feed mode and rate (rate in mm/min, 1/min or mm/rev).
    pub feed: Feed,
    /// Spindle speed as programmed by S (rev/min, ≥ 0).
    pub speed_rpm: f64,
    /// Spindle direction: 1 (M3), -1 (M4), 0 (M5).
    pub spindle_dir: i32,
    /// Tool in the spindle.
    pub tool: i32,
    /// Tool selected by T (for the next M6).
    pub selected_tool: i32,
    /// Tool length offset in force (mm).
    pub tlo: DVec3,
    /// Cutter compensation side and radius (mm).
    pub comp: CompSide,
    /// Radius of the compensation in force (mm).
    pub comp_radius: f64,
    /// Active coordinate system (1 = G54 … 9 = G59.3).
    pub system: usize,
    /// G54…G59.3 offsets (mm / degrees).
    pub g5x: [Axes; SYSTEMS],
    /// Their XY rotations (degrees, `G10 L2 R`).
    pub rotation_deg: [f64; SYSTEMS],
    /// G92 / G52 offset (mm / degrees).
    pub g92: Axes,
    /// FANUC G68: centre (mm, program frame) and angle (degrees).
    pub g68: Option<([f64; 2], f64)>,
    /// FANUC G16 polar coordinate command.
    pub polar: bool,
    /// G98 (else G99, LinuxCNC's default): cycles retract to the initial level.
    pub retract_initial: bool,
    /// The program position (mm / degrees): the programmed, uncompensated point.
    pub prog: Axes,
}

impl Default for State {
    fn default() -> Self {
        Self {
            inch: false,
            units_given: false,
            absolute: true,
            arc_absolute: false,
            plane: Plane::Xy,
            motion: MotionMode::None,
            feed: Feed { mode: FeedMode::PerMinute, rate: 0.0, spindle_rpm: 0.0 },
            speed_rpm: 0.0,
            spindle_dir: 0,
            tool: 0,
            selected_tool: 0,
            tlo: DVec3::ZERO,
            comp: CompSide::Off,
            comp_radius: 0.0,
            system: 1,
            g5x: [[0.0; 6]; SYSTEMS],
            rotation_deg: [0.0; SYSTEMS],
            g92: [0.0; 6],
            g68: None,
            polar: false,
            retract_initial: false,
            prog: [0.0; 6],
        }
    }
}

fn rotate(x: f64, y: f64, deg: f64) -> (f64, f64) {
    if deg == 0.0 {
        return (x, y);
    }
    let (s, c) = deg.to_radians().sin_cos();
    (x * c - y * s, x * s + y * c)
}

impl State {
    /// Length scale of the program's numbers to mm.
    #[must_use]
    pub fn scale(&self) -> f64 {
        if self.inch { MM_PER_INCH } else { 1.0 }
    }

    /// Machine pose of a program position.
    #[must_use]
    pub fn to_machine(&self, p: &Axes) -> Pose {
        let (mut x, mut y) = (p[0], p[1]);
        if let Some(([cx, cy], a)) = self.g68 {
            let (rx, ry) = rotate(x - cx, y - cy, a);
            x = cx + rx;
            y = cy + ry;
        }
        let g = &self.g92;
        let (x, y) = rotate(x + g[0], y + g[1], self.rotation_deg[self.system]);
        let o = &self.g5x[self.system];
        Pose {
            xyz: DVec3::new(x + o[0], y + o[1], p[2] + g[2] + o[2]),
            abc: DVec3::new(p[3] + g[3] + o[3], p[4] + g[4] + o[4], p[5] + g[5] + o[5]),
        }
    }

    /// Program position of a machine pose (the inverse of [`State::to_machine`]).
    #[must_use]
    pub fn to_program(&self, m: &Pose) -> Axes {
        let o = &self.g5x[self.system];
        let g = &self.g92;
        let (x, y) = rotate(m.xyz.x - o[0], m.xyz.y - o[1], -self.rotation_deg[self.system]);
        let (mut x, mut y) = (x - g[0], y - g[1]);
        if let Some(([cx, cy], a)) = self.g68 {
            let (rx, ry) = rotate(x - cx, y - cy, -a);
            x = cx + rx;
            y = cy + ry;
        }
        [x, y, m.xyz.z - o[2] - g[2], m.abc.x - o[3] - g[3], m.abc.y - o[4] - g[4], m.abc.z - o[5] - g[5]]
    }

    /// The machine pose of the program position.
    #[must_use]
    pub fn pose(&self) -> Pose {
        self.to_machine(&self.prog)
    }

    /// Runs `change` on the offsets while keeping the tool where it is: the program position
    /// is recomputed from the machine pose.
    pub fn keep_tool(&mut self, change: impl FnOnce(&mut Self)) {
        let m = self.pose();
        change(self);
        self.prog = self.to_program(&m);
    }

    /// Total rotation of the XY plane from program to machine (degrees).
    #[must_use]
    pub fn xy_rotation_deg(&self) -> f64 {
        self.rotation_deg[self.system] + self.g68.map_or(0.0, |(_, a)| a)
    }
}

/// The modal group of a G code (tenths), as RS274/NGC and LinuxCNC number them (FANUC's
/// additions in their own groups), or `None` for a code no group holds.
#[must_use]
pub fn g_group(t: i32) -> Option<u8> {
    Some(match t {
        40 | 100 | 101 | 280 | 281 | 300 | 301 | 520 | 530 | 920 | 921 | 922 | 923 | 650 | 90 => 0,
        0
        | 10
        | 20
        | 30
        | 50
        | 51
        | 52
        | 53
        | 62
        | 330
        | 331
        | 382..=385
        | 700
        | 710
        | 711
        | 712
        | 720
        | 721
        | 722
        | 730
        | 740
        | 760
        | 800..=890 => 1,
        170 | 180 | 190 | 171 | 181 | 191 => 2,
        900 | 910 => 3,
        901 | 911 => 4,
        930 | 940 | 950 => 5,
        200 | 210 => 6,
        400 | 410 | 420 | 411 | 421 => 7,
        430 | 431 | 432 | 440 | 490 => 8,
        980 | 990 => 10,
        540 | 541 | 550 | 560 | 570 | 580 | 590 | 591 | 592 | 593 => 12,
        610 | 611 | 640 => 13,
        960 | 970 => 14,
        70 | 80 => 15,
        680 | 690 => 16,
        150 | 160 => 17,
        500 | 510 => 18,
        501 | 511 => 19,
        660 | 670 => 21,
        _ => return None,
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn machine_and_program_frames_are_inverse() {
        let mut s = State::default();
        s.g5x[2] = [10.0, -5.0, 3.0, 1.0, 2.0, 3.0];
        s.rotation_deg[2] = 30.0;
        s.system = 2;
        s.g92 = [1.0, 2.0, -1.0, 0.0, 0.0, 0.5];
        s.g68 = Some(([4.0, 4.0], 15.0));
        let p = [3.0, -7.0, 2.0, 10.0, 20.0, 30.0];
        let m = s.to_machine(&p);
        let back = s.to_program(&m);
        for i in 0..6 {
            assert!((back[i] - p[i]).abs() < 1e-12, "{i}: {back:?}");
        }
        // LinuxCNC's order: rotate (p + g92), then add g5x.
        let (x, y) = rotate(3.0 + 1.0, -7.0 + 2.0, 30.0);
        let mut s2 = s.clone();
        s2.g68 = None;
        let m2 = s2.to_machine(&p);
        assert!((m2.xyz.x - (x + 10.0)).abs() < 1e-12 && (m2.xyz.y - (y - 5.0)).abs() < 1e-12);
    }

    #[test]
    fn changing_an_offset_keeps_the_tool_still() {
        let mut s = State { prog: [1.0, 2.0, 3.0, 0.0, 0.0, 0.0], ..State::default() };
        let before = s.pose();
        s.keep_tool(|s| s.g92 = [5.0, 0.0, -2.0, 0.0, 0.0, 0.0]);
        assert_eq!(s.pose(), before);
        assert_eq!(s.prog[0], -4.0);
    }
}
