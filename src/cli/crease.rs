//! `run` and `check`: the crease interpolation of seed 000.

use std::fs;
use std::io::{self, BufWriter, Write};
use std::path::Path;
use std::process::ExitCode;

use super::{Fatal, MethodArg, OutFormat};

use interpolab::crease::{CreaseJob, InterpOptions, Interpolator, Method, Step, WorstError, diagnose};
use interpolab::report::{Format, RowWriter, fmt_num, one_line};
use interpolab::scene::Scene;

pub(super) fn load(path: &Path) -> Result<(Scene, CreaseJob), Fatal> {
    let text = super::read_capped(path, interpolab::numerics::limits::MAX_SCENE_BYTES, "scene")
        .map_err(|e| Fatal(format!("cannot read scene file {}: {e}", path.display())))?;
    let scene = Scene::from_json(&text).map_err(|e| Fatal(format!("{}: {e}", path.display())))?;
    let job = CreaseJob::from_scene(&scene).map_err(|e| Fatal(format!("{}: {e}", path.display())))?;
    Ok((scene, job))
}

pub(super) fn run(
    path: &Path,
    format: OutFormat,
    out: Option<&Path>,
    errors: bool,
    method: MethodArg,
    turns: u32,
) -> Result<ExitCode, Fatal> {
    let (scene, job) = load(path)?;
    let sink: Box<dyn Write> = match out {
        Some(p) => Box::new(BufWriter::with_capacity(
            1 << 16,
            fs::File::create(p).map_err(|e| Fatal(format!("cannot create {}: {e}", p.display())))?,
        )),
        None => Box::new(BufWriter::with_capacity(1 << 16, io::stdout().lock())),
    };
    let format = match format {
        OutFormat::Csv => Format::Csv,
        OutFormat::Json => Format::Json,
    };
    let io_err = |e: io::Error| {
        if e.kind() == io::ErrorKind::BrokenPipe {
            std::process::exit(0);
        }
        Fatal(format!("cannot write the output: {e}"))
    };
    let mut writer = RowWriter::new(sink, format, errors, &job, &scene.name, scene.motion.period).map_err(io_err)?;
    let opts = InterpOptions {
        method: match method {
            MethodArg::Seed000 => Method::Seed000,
            MethodArg::Exact => Method::Exact,
        },
        turns: turns.max(1),
        ..InterpOptions::default()
    };
    let mut note = None;
    // The largest measured |e_i| (mm) and the period where it occurred, for the b·T warning.
    let mut worst = WorstError::default();
    let outcome = Interpolator::new(job.clone(), opts).and_then(|mut it| {
        // `derivs`: both surfaces at the row's contacts, the evaluation the next period
        // starts from (`Interpolator::row_derivatives`), so the screen does not repeat it.
        let mut emit = |row: &interpolab::crease::Row, shortened: bool, derivs| -> Result<(), io::Error> {
            let d = if errors { diagnose(&job, row) } else { None };
            // Measured on every row (screened cheaply, see `WorstError`), so a run whose feed
            // is too long for the crease's curvature says so.
            match &d {
                Some(d) => worst.observe_measured(d.measured, row.k),
                None => worst.observe_with(&job, row, derivs),
            }
            if shortened { writer.final_row(&job, row, d.as_ref()) } else { writer.row(&job, row, d.as_ref()) }
        };
        let first = it.first_row();
        let derivs = if errors { None } else { it.row_derivatives() };
        if let Err(e) = emit(&first, false, derivs) {
            write_failed(&e);
        }
        loop {
            match it.step()? {
                Step::Row(r) => {
                    // The final period of a run ending on an exact point is shorter; the
                    // interpolator says so as soon as it has produced that row.
                    let derivs = if errors { None } else { it.row_derivatives() };
                    if let Err(e) = emit(&r, it.final_period_s().is_some(), derivs) {
                        write_failed(&e);
                    }
                }
                Step::Stopped(reason) => {
                    note = it.end_not_reached().map(|n| n.to_string());
                    return Ok(reason);
                }
            }
        }
    });
    let final_period_ms = writer.final_period_ms();
    writer.finish_exact(&outcome, note.as_deref(), final_period_ms).map_err(io_err)?;
    match outcome {
        Ok(reason) => {
            let _ = writeln!(io::stderr(), "interpolab: {}: stopped: {reason}", path.display());
            if let Some(note) = note {
                let _ = writeln!(io::stderr(), "interpolab: {}: note: {note}", path.display());
            }
            for (i, (e, k)) in worst.worst.iter().enumerate() {
                let allowed = job.allowed_error_mm(i);
                if *e > allowed {
                    let _ = writeln!(
                        io::stderr(),
                        "interpolab: {}: warning: the measured error on surface {} reaches {:.3e} mm at period {k}, above b·T{} = {} mm; lower motion.feed or motion.period (the paper's error grows with the feed per period), or use --method exact",
                        path.display(),
                        i + 1,
                        e,
                        i + 1,
                        fmt_num(allowed)
                    );
                }
            }
            Ok(ExitCode::SUCCESS)
        }
        Err(e) => Err(Fatal(format!("{}: {e}", path.display()))),
    }
}

/// Ends the program when the output cannot be written. A closed pipe (`| head`) is the
/// reader's choice, not an error: exit quietly.
fn write_failed(e: &io::Error) -> ! {
    if e.kind() == io::ErrorKind::BrokenPipe {
        std::process::exit(0);
    }
    let _ = writeln!(io::stderr(), "interpolab: cannot write the output: {e}");
    std::process::exit(2);
}

pub(super) fn check(path: &Path) -> Result<ExitCode, Fatal> {
    let (scene, job) = load(path)?;
    let mut it = Interpolator::new(job.clone(), InterpOptions::default())
        .map_err(|e| Fatal(format!("{}: {e}", path.display())))?;
    let start_shift = (it.first_row().p - job.start).length();
    let mut n = 0u64;
    let mut k_range = [[f64::INFINITY, f64::NEG_INFINITY]; 2];
    let mut worst_est = [0.0f64; 2];
    let mut est_missing = [false; 2];
    let mut worst_meas = [0.0f64; 2];
    let mut angle = [f64::INFINITY, f64::NEG_INFINITY];
    let mut observe = |row: &interpolab::crease::Row| {
        if let Some(d) = diagnose(&job, row) {
            for i in 0..2 {
                k_range[i][0] = k_range[i][0].min(d.k_t[i]);
                k_range[i][1] = k_range[i][1].max(d.k_t[i]);
                worst_meas[i] = worst_meas[i].max(d.measured[i].abs());
                match d.est16[i] {
                    Some(e) => worst_est[i] = worst_est[i].max(e),
                    None => est_missing[i] = true,
                }
            }
            angle[0] = angle[0].min(d.crease_angle_deg);
            angle[1] = angle[1].max(d.crease_angle_deg);
        }
    };
    let mut t_last_s = 0.0;
    let outcome = it.run(|r| {
        n = r.k;
        t_last_s = r.t_s;
        observe(r);
    });
    let f = job.feed_per_period_mm;
    let mut o = io::stdout().lock();
    let w = |o: &mut io::StdoutLock<'_>, s: String| {
        let _ = writeln!(o, "{s}");
    };
    w(
        &mut o,
        format!(
            "scene        {} ({})",
            one_line(if scene.name.is_empty() { "(unnamed)" } else { &scene.name }),
            one_line(&path.display().to_string())
        ),
    );
    w(
        &mut o,
        format!(
            "surfaces     S1 {}, S2 {}; ball R = {} mm, allowance C = {} mm, R' = {} mm",
            job.surfaces[0].type_name(),
            job.surfaces[1].type_name(),
            fmt_num(job.ball_radius_mm),
            fmt_num(scene.tool.allowance),
            fmt_num(job.r_eff_mm)
        ),
    );
    w(
        &mut o,
        format!(
            "motion       F = {} mm/min, Ts = {} ms, feed per period f = {} mm",
            fmt_num(scene.motion.feed),
            fmt_num(scene.motion.period),
            fmt_num(f)
        ),
    );
    w(&mut o, format!("start        moved {start_shift:.6} mm onto the crease"));
    let status = match &outcome {
        Ok(reason) => format!("stopped: {reason}"),
        Err(e) => format!("ERROR: {e}"),
    };
    w(&mut o, format!("periods      {n} ({status})"));
    if let Some(note) = it.end_not_reached() {
        w(&mut o, format!("note         {note}"));
    }
    w(
        &mut o,
        // The last period may be the shorter final one: the time says how far the path went.
        format!("length       {:.4} mm, machining time {:.3} s", t_last_s / job.period_s * f, t_last_s),
    );
    w(&mut o, format!("crease angle {:.3}° to {:.3}° between the normals", angle[0], angle[1]));
    let mut exceeded = false;
    for i in 0..2 {
        let allowed = job.allowed_error_mm(i);
        w(
            &mut o,
            format!(
                "S{}           normal curvature along the crease {:.6} to {:.6} 1/mm",
                i + 1,
                k_range[i][0],
                k_range[i][1]
            ),
        );
        let est = if est_missing[i] {
            "unbounded (outside the validity of (16))".to_owned()
        } else {
            format!("{:.3e} mm", worst_est[i])
        };
        let ok_est = !est_missing[i] && worst_est[i] <= allowed;
        let ok_meas = worst_meas[i] <= allowed;
        exceeded |= !(ok_est && ok_meas);
        w(
            &mut o,
            format!(
                "             worst estimate (16) {est}, worst measured |e{}| {:.3e} mm, allowed b·T{} = {} mm: {}",
                i + 1,
                worst_meas[i],
                i + 1,
                fmt_num(allowed),
                if ok_est && ok_meas { "within" } else { "EXCEEDED" }
            ),
        );
    }
    drop(o);
    if let Err(e) = outcome {
        return Err(Fatal(format!("{}: {e}", path.display())));
    }
    Ok(if exceeded { ExitCode::from(1) } else { ExitCode::SUCCESS })
}
