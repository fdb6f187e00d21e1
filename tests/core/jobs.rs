//! `src/jobs/`: the comparison row's time on a machine (`jobs::program_row`), the number the
//! NURBS & G-code tab shows as "time on <machine>" and `interpolab compare --machine` prints.
#[cfg(target_arch = "wasm32")]
use wasm_bindgen_test::wasm_bindgen_test as test;

use interpolab::gcode::{CompareOptions, ProgramKind, ProgramOptions, parse_program_in};
use interpolab::jobs::program_row::{CycleTime, DesignSpec, ProgramRow, Request};
use interpolab::jobs::{JobKind, NoProgress};
use interpolab::plan::{Dynamics, canon_of_toolpath, time_program};

/// The three programs of seed 004's parabola at 0.01 mm and the profile's own feed
/// (1500 mm/min, as the tab and `interpolab compare --profile parabola` use it), timed by the
/// job on `machine`.
fn timed_rows(machine: &str) -> Vec<(ProgramKind, String, CycleTime)> {
    let m = Dynamics::preset(machine).unwrap();
    let options = CompareOptions {
        program: ProgramOptions::default().with_feed(1500.0).with_title("parabola"),
        period_ms: 4.0,
        chord_tol_mm: None,
    };
    ProgramKind::ALL
        .into_iter()
        .map(|kind| {
            let req = Request {
                design: DesignSpec::Parabola,
                kind,
                tol_mm: 0.01,
                options: options.clone(),
                machine: Some(m.clone()),
            };
            // Through the text encoding, as the request crosses into a worker and back.
            let req = ProgramRow::decode_request(&ProgramRow::encode_request(&req)).unwrap();
            let out = ProgramRow::decode_output(&ProgramRow::encode_output(&ProgramRow::run(&req, &mut NoProgress)))
                .unwrap()
                .unwrap();
            (kind, out.row.program.text.clone(), out.time.unwrap().unwrap())
        })
        .collect()
}

/// Each row's time is the planner's on that program, computed here from the program's text
/// read again (bit for bit: the job adds nothing); on the VMC and on the hobby router the
/// G06.2 program is no slower than the G01 program of the same tolerance (docs/feed-planning.md,
/// "Seed 004's claim"), in cycle time and in the feed moves' time.
#[test]
fn the_rows_time_is_the_planners_and_the_g06_2_program_is_no_slower_than_g01() {
    for machine in ["vmc", "hobby-router"] {
        let m = Dynamics::preset(machine).unwrap();
        let rows = timed_rows(machine);
        for (kind, text, t) in &rows {
            let parsed = parse_program_in(text, interpolab::gcode::Dialect::Fanuc).unwrap();
            let plan = time_program(canon_of_toolpath(&parsed.toolpath), &m).unwrap();
            let (feed_s, _) = plan.feed_rapid_s();
            let cut: f64 = plan.path.blocks.iter().filter(|b| !b.rapid).map(|b| b.len).sum();
            assert_eq!(t.machine, machine);
            assert_eq!(t.total_s.to_bits(), plan.total_s().to_bits(), "{machine} {}", kind.label());
            assert_eq!(t.feed_s.to_bits(), feed_s.to_bits(), "{machine} {}", kind.label());
            assert_eq!(t.cut_mm.to_bits(), cut.to_bits(), "{machine} {}", kind.label());
            let mean = t.mean_feed_mm_min().unwrap();
            // The mean feed over the cut never passes the programmed feed.
            assert!(mean > 0.0 && mean <= 1500.0 * (1.0 + 1e-9), "{machine} {}: {mean}", kind.label());
        }
        let (lines, nurbs) = (&rows[0].2, &rows[2].2);
        assert!(nurbs.total_s <= lines.total_s, "{machine}: G06.2 {} s, G01 {} s", nurbs.total_s, lines.total_s);
        assert!(nurbs.feed_s <= lines.feed_s, "{machine}: G06.2 {} s, G01 {} s", nurbs.feed_s, lines.feed_s);
    }
}
