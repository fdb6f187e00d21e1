//! The planner against TOPP-RA's time-optimal bound (Pham & Pham, IEEE T-RO 2018; PyPI
//! `toppra` 0.6.10): `scripts/plan-anchors.py` computed, on the path each plan follows and
//! under the same joint velocity and acceleration limits and feeds, the times in
//! `tests/data/plan/topp_bounds.csv`. No plan may beat them (a plan that does breaks a
//! limit), and the jerk-free plan must be within 5 % of them.

use interpolab::gcode::interp::{Canon, Interpreter, Options};
use interpolab::gcode::{ProgramKind, ProgramOptions, write_program};
use interpolab::nurbs_path::Parabola;
use interpolab::plan::{Dynamics, canon_of_toolpath, time_program};

fn program(label: &str) -> Option<Vec<Canon>> {
    let kind = |k: &str| match k {
        "g01" => Some(ProgramKind::Lines),
        "arcs" => Some(ProgramKind::Arcs),
        "nurbs" => Some(ProgramKind::Nurbs),
        _ => None,
    };
    let mut words = label.split(' ');
    let (a, b) = (words.next()?, words.next());
    if a == "parabola" {
        let p = write_program(kind(b?)?, &Parabola::paper_like(), 0.01, &ProgramOptions::default().with_feed(1500.0))
            .ok()?;
        return Some(canon_of_toolpath(&p.parsed.toolpath));
    }
    let text = match a {
        "corners" => include_str!("../data/plan/corners.nc"),
        "5axis-rotary" => include_str!("../data/plan/5axis-rotary.nc"),
        _ => return None,
    };
    Some(Interpreter::from_text(text, Options::default()).map_while(Result::ok).collect())
}

/// TOPP-RA's grid leaves it a little above the continuous optimum (its first interval from
/// rest, its switch points on grid points): how far below it a plan may come before it is
/// said to beat it (relative; the script's `RTOL`).
const RTOL: f64 = 2e-4;

#[test]
fn no_plan_beats_topp_ra_and_jerk_free_plans_are_within_five_percent() {
    let data = include_str!("../data/plan/topp_bounds.csv");
    let mut checked = 0;
    for line in data.lines().skip(1) {
        let f: Vec<&str> = line.split(',').collect();
        let (label, machine, bound) = (f[0], f[1], f[2].parse::<f64>().expect("number"));
        // Scenes' crease programs are checked by the script (they need the crease run).
        let Some(canon) = program(label) else { continue };
        let m = Dynamics::preset(machine).expect("preset");
        // Motion time: TOPP-RA knows no dwell.
        let motion = |t: interpolab::plan::Timing| t.total_s() - t.path.dwell_s;
        let free = motion(time_program(canon.iter().cloned(), &m.clone().without_jerk()).expect("plans"));
        let jerk = motion(time_program(canon.iter().cloned(), &m).expect("plans"));
        assert!(
            free >= bound * (1.0 - RTOL),
            "{label} on {machine}: jerk-free plan {free} s beats TOPP-RA's {bound} s"
        );
        assert!(
            free <= 1.05 * bound,
            "{label} on {machine}: jerk-free plan {free} s, more than 5 % over TOPP-RA's {bound} s"
        );
        assert!(
            jerk >= bound * (1.0 - RTOL),
            "{label} on {machine}: jerk-limited plan {jerk} s beats TOPP-RA's {bound} s"
        );
        checked += 1;
    }
    assert!(checked >= 6, "only {checked} rows of the bounds file could be checked");
}
