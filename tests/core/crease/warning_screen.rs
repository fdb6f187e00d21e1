//! The b·T warning of `interpolab run` screens each row's measured error cheaply
//! ([`WorstError`]) instead of projecting fully; it must report what the full measurement
//! ([`measured_errors`] on every row) reports: the same surface, size and period whenever the
//! error exceeds b·T, and a worst value within rounding of the full one otherwise.
#[cfg(target_arch = "wasm32")]
use wasm_bindgen_test::wasm_bindgen_test as test;

use crate::support;

use interpolab::crease::{CreaseJob, InterpOptions, Method, WorstError, measured_errors, run_to_end};
use interpolab::scene::PRESETS;

/// The screened worst and the full one (largest |e_i| and its period) over a whole run.
fn both(job: &CreaseJob, method: Method) -> (WorstError, [(f64, u64); 2], usize) {
    let run = run_to_end(job.clone(), InterpOptions { method, ..InterpOptions::default() });
    assert!(run.outcome.is_ok(), "{:?}", run.outcome);
    let mut screened = WorstError::default();
    let mut full = [(0.0f64, 0u64); 2];
    for row in &run.rows {
        screened.observe(job, row);
        let e = measured_errors(job, row);
        for i in 0..2 {
            if e[i].abs() > full[i].0 {
                full[i] = (e[i].abs(), row.k);
            }
        }
    }
    (screened, full, run.rows.len())
}

#[test]
fn the_screened_worst_error_is_the_full_one_on_every_example() {
    let mut fired = 0;
    for preset in PRESETS {
        let mut job = CreaseJob::from_scene(&support::scene(preset.json)).expect("example builds");
        for method in [Method::Seed000, Method::Exact] {
            // As given (errors far below b·T: every row screened only) …
            let (s, full, rows) = both(&job, method);
            for i in 0..2 {
                assert!(
                    (s.worst[i].0 - full[i].0).abs() <= 1e-12,
                    "{} {method:?} S{}: screened {:e}, full {:e}",
                    preset.id,
                    i + 1,
                    s.worst[i].0,
                    full[i].0
                );
            }
            // … and with b·T tightened below the seed-000 errors, so that the warning fires
            // and the rows near the worst are measured in full: identical values and period.
            if method == Method::Seed000 {
                let saved = job.tol_mm;
                job.tol_mm = [full[0].0 * 0.3 / job.share, full[1].0 * 0.3 / job.share];
                let (s, full_tight, _) = both(&job, method);
                for i in 0..2 {
                    if full_tight[i].0 > job.allowed_error_mm(i) {
                        fired += 1;
                        assert_eq!(s.worst[i], full_tight[i], "{} S{}: {rows} rows", preset.id, i + 1);
                    }
                }
                job.tol_mm = saved;
            }
        }
    }
    assert!(fired >= PRESETS.len(), "the tightened runs exceed b·T on {fired} surfaces only");
}

/// The CLI hands the screen the stepper's own evaluation at each row
/// (`Interpolator::row_derivatives`): the screened worst errors are the same bits as without
/// it, and the run itself (every row) is unchanged by taking it.
#[test]
fn the_shared_evaluation_changes_neither_the_screen_nor_the_run() {
    use interpolab::crease::{Interpolator, Step};
    for preset in PRESETS {
        let job = CreaseJob::from_scene(&support::scene(preset.json)).expect("example builds");
        for method in [Method::Seed000, Method::Exact] {
            let opts = InterpOptions { method, ..InterpOptions::default() };
            let plain = run_to_end(job.clone(), opts);
            let mut it = Interpolator::new(job.clone(), opts).expect("starts");
            let (mut own, mut shared) = (WorstError::default(), WorstError::default());
            let mut rows = vec![it.first_row()];
            let mut given = 0;
            loop {
                let row = *rows.last().expect("a row");
                let derivs = it.row_derivatives();
                given += usize::from(derivs.is_some());
                own.observe(&job, &row);
                shared.observe_with(&job, &row, derivs);
                match it.step().expect("runs") {
                    Step::Row(r) => rows.push(r),
                    Step::Stopped(_) => break,
                }
            }
            assert_eq!(own.worst, shared.worst, "{} {method:?}", preset.id);
            assert_eq!(rows, plain.rows, "{} {method:?}: the rows changed", preset.id);
            if method == Method::Seed000 {
                assert!(
                    given + 1 >= rows.len(),
                    "{}: the evaluation was shared on {given} of {} rows",
                    preset.id,
                    rows.len()
                );
            }
        }
    }
}
