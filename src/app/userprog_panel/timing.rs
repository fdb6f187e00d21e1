//! The tab's "Time on a machine" section: the program's feed planned on a machine's dynamics
//! (a preset, its contour tolerance) in the background ([`ProgramTime`]), the cycle time
//! beside the time at the programmed feed, and the planned feed, acceleration or jerk along
//! the path against time. The preset's velocity, acceleration and jerk limits can be scaled
//! (every axis by the same factor, shown as the X axis' values). A change of machine,
//! limits or tolerance plans again at once.

use eframe::egui;
use egui_plot::{Line, Plot, PlotPoints};

use crate::app::jobs::{Job, Poll};
use crate::jobs::JobError;
use crate::jobs::program_time::{ProgramTime, Request, Timed};
use crate::jobs::user_program;
use crate::plan::machine::MAX_TOLERANCE_MM;
use crate::plan::{Dynamics, PRESETS};

/// A limit scale within this of 1 is the machine's own limit (the slider's rounding).
const SCALE_ONE_SLACK: f64 = 1e-12;

/// What the plot shows.
const PLOTS: [(&str, &str); 3] = [("feed", "mm/min"), ("acceleration", "mm/s²"), ("jerk", "mm/s³")];

/// The range of the limits' factors (× the preset's).
const SCALE_RANGE: std::ops::RangeInclusive<f64> = 0.1..=4.0;

/// The limits' names and the X axis' units, in [`Timing::scale`]'s order.
const LIMITS: [(&str, &str); 3] = [("velocity", "mm/min"), ("acceleration", "mm/s²"), ("jerk", "mm/s³")];

/// What a plan is for: the tab's reading of the program (its generation) and the machine.
type Key = (u64, Dynamics);

/// The section's state.
#[derive(Default)]
pub struct Timing {
    /// Index in [`PRESETS`] (default: the vertical machining centre).
    preset: Option<usize>,
    /// Contour tolerance (mm); `None`: the preset's.
    tol_mm: Option<f64>,
    /// Factors on the preset's velocity, acceleration and jerk limits (every axis); `None`:
    /// 1, 1, 1.
    scale: Option<[f64; 3]>,
    /// The plan under way and what it is for (the program's reading, the machine).
    job: Option<(Key, Job<ProgramTime>)>,
    /// The last plan and what it was for.
    done: Option<(Key, Result<Timed, JobError>)>,
    /// Index in [`PLOTS`].
    plot: usize,
    /// Planning was asked for (the button, or a setting changed after a plan).
    wanted: bool,
    /// Plans finished so far (a view drawn from the last one compares it).
    serial: u64,
}

impl Timing {
    fn preset(&self) -> usize {
        self.preset.unwrap_or(1)
    }

    fn scale(&self) -> [f64; 3] {
        self.scale.unwrap_or([1.0; 3])
    }

    /// The machine the settings give (the preset, its limits scaled, the tolerance set here).
    fn machine(&self) -> Option<Dynamics> {
        let mut m = Dynamics::preset(PRESETS[self.preset().min(PRESETS.len() - 1)])?;
        if let Some(t) = self.tol_mm {
            m.tolerance_mm = t;
        }
        let [v, a, j] = self.scale();
        if [v, a, j].iter().any(|f| (f - 1.0).abs() > SCALE_ONE_SLACK) {
            for axis in &mut m.axes {
                axis.velocity *= v;
                axis.acceleration *= a;
                axis.jerk = axis.jerk.map(|x| x * j);
            }
            m.name = format!("{} (limits × {v}, {a}, {j})", m.name);
        }
        Some(m)
    }

    /// Scales the preset's limits: `v,a,j` factors (0.1 to 4) on every axis's velocity,
    /// acceleration and jerk.
    ///
    /// # Errors
    /// Not three factors in the range, with what to give.
    pub fn set_limits(&mut self, value: &str) -> Result<(), String> {
        let bad = || {
            format!(
                "time limits \"{value}\": give three factors v,a,j from {} to {} on the preset's velocity, acceleration and jerk, e.g. 1,0.5,1",
                SCALE_RANGE.start(),
                SCALE_RANGE.end()
            )
        };
        let v: Vec<f64> =
            value.split(',').map(|x| x.trim().parse::<f64>()).collect::<Result<_, _>>().map_err(|_| bad())?;
        let [a, b, c] = v[..] else { return Err(bad()) };
        if ![a, b, c].iter().all(|x| SCALE_RANGE.contains(x)) {
            return Err(bad());
        }
        self.scale = Some([a, b, c]);
        Ok(())
    }

    /// Sets the machine by preset name.
    ///
    /// # Errors
    /// A name that is not a preset, with the names.
    pub fn set_machine(&mut self, name: &str) -> Result<(), String> {
        let i = PRESETS
            .iter()
            .position(|p| *p == name)
            .ok_or_else(|| format!("time machine \"{name}\": use one of {}", PRESETS.join(", ")))?;
        self.preset = Some(i);
        Ok(())
    }

    /// Sets the contour tolerance (mm).
    ///
    /// # Errors
    /// A value that is not a length from 0 to the planner's cap.
    pub fn set_tolerance(&mut self, value: &str) -> Result<(), String> {
        let t = value.parse::<f64>().ok().filter(|t| (0.0..=MAX_TOLERANCE_MM).contains(t)).ok_or_else(|| {
            format!(
                "time tolerance \"{value}\": give a length from 0 to {MAX_TOLERANCE_MM} mm (0 stops at every corner)"
            )
        })?;
        self.tol_mm = Some(t);
        Ok(())
    }

    /// Asks for a plan (run as soon as the program is read).
    pub fn want(&mut self) {
        self.wanted = true;
    }

    /// Plans finished so far.
    pub fn serial(&self) -> u64 {
        self.serial
    }

    /// The last plan, if it succeeded.
    pub fn timed(&self) -> Option<&Timed> {
        self.done.as_ref().and_then(|d| d.1.as_ref().ok())
    }

    /// Whether a plan runs.
    pub fn running(&self) -> bool {
        self.job.is_some()
    }

    /// Starts, polls and shows; returns the "Time it" button's rectangle. `reading`: the
    /// generation of the tab's reading of the program (`None` while none is read);
    /// `request`: the program's request (asked for only when a plan starts);
    /// `programmed_min`: its time at the programmed feed.
    pub fn ui(
        &mut self,
        ui: &mut egui::Ui,
        reading: Option<u64>,
        request: impl FnOnce() -> Option<user_program::Request>,
        programmed_min: Option<f64>,
    ) -> egui::Rect {
        ui.horizontal(|ui| {
            let mut p = self.preset();
            egui::ComboBox::from_id_salt("userprog_time_machine").selected_text(PRESETS[p]).show_ui(ui, |ui| {
                for (i, name) in PRESETS.iter().enumerate() {
                    ui.selectable_value(&mut p, i, *name);
                }
            });
            if p != self.preset() {
                self.preset = Some(p);
            }
            let mut tol = self.machine().map_or(0.0, |m| m.tolerance_mm);
            let r = ui
                .add(
                    egui::DragValue::new(&mut tol)
                        .speed(0.001)
                        .range(0.0..=MAX_TOLERANCE_MM)
                        .max_decimals(4)
                        .suffix(" mm"),
                )
                .on_hover_text("contour tolerance P (G64 P): corners are blended within it; 0 stops at every corner");
            if r.changed() {
                self.tol_mm = Some(tol);
            }
            ui.label("P");
        });
        // The limits, as factors on the preset's, with the X axis' value they give.
        let mut scale = self.scale();
        let base = Dynamics::preset(PRESETS[self.preset().min(PRESETS.len() - 1)]);
        for (k, (name, unit)) in LIMITS.iter().enumerate() {
            ui.horizontal(|ui| {
                let r = ui
                    .add(egui::Slider::new(&mut scale[k], SCALE_RANGE).logarithmic(true).max_decimals(2).prefix("× "))
                    .on_hover_text(format!("the preset's {name} limit of every axis times this"));
                if r.changed() {
                    self.scale = Some(scale);
                }
                let x = base.as_ref().map(|m| &m.axes[0]);
                let value = match k {
                    0 => x.map(|a| a.velocity),
                    1 => x.map(|a| a.acceleration),
                    _ => x.and_then(|a| a.jerk),
                };
                match value {
                    Some(v) => ui.label(format!("{name}: X {:.0} {unit}", v * scale[k])),
                    None => ui.label(format!("{name}: not limited")),
                };
            });
        }
        let key = reading.zip(self.machine());
        let button = ui.horizontal(|ui| {
            let r = ui.add_enabled(key.is_some() && self.job.is_none(), egui::Button::new("Time it"));
            if r.clicked() {
                self.wanted = true;
            }
            if self.job.is_some() {
                ui.spinner();
                ui.label("planning…");
            }
            r.rect
        });
        // Plan when asked, and again when the settings or the reading change after a plan:
        // once the plan under way is done (a drag of the tolerance plans its latest value
        // next, instead of ending the worker at every step).
        if let Some(key) = key {
            let done_for = |k: &Key| self.done.as_ref().is_some_and(|(d, _)| d == k);
            let stale = self.done.is_some() && !done_for(&key);
            if self.job.is_none() && (self.wanted || stale) && !done_for(&key) {
                if let Some(mut program) = request() {
                    program.simulate = false;
                    let req = Request { program, machine: key.1.clone() };
                    self.job = Some((key, Job::start(req)));
                }
                self.wanted = false;
            }
        }
        if let Some((key, job)) = self.job.as_mut() {
            crate::app::jobs::set_waker(ui.ctx());
            match job.poll() {
                Poll::Running(_) => ui.ctx().request_repaint_after(crate::app::jobs::POLL),
                Poll::Done(out) => {
                    self.done = Some((key.clone(), out));
                    self.job = None;
                    self.serial += 1;
                }
            }
        }
        match self.done.as_ref().map(|d| &d.1) {
            None => {}
            Some(Err(e)) => super::super::widgets::error_text(ui, e.to_string()),
            Some(Ok(t)) => {
                let t = t.clone();
                self.show(ui, &t, programmed_min);
            }
        }
        button.inner
    }

    fn show(&mut self, ui: &mut egui::Ui, t: &Timed, programmed_min: Option<f64>) {
        ui.label(format!(
            "cycle time {} on {} (P {} mm): feed {}, rapid {}",
            clock(t.total_s),
            t.machine,
            t.tolerance_mm,
            clock(t.feed_s),
            clock(t.rapid_s)
        ));
        if let Some(m) = programmed_min {
            ui.label(format!("at the programmed feed, no acceleration: {} of feed moves", clock(60.0 * m)));
        }
        ui.horizontal(|ui| {
            for (i, (name, _)) in PLOTS.iter().enumerate() {
                ui.selectable_value(&mut self.plot, i, *name);
            }
        });
        let (name, unit) = PLOTS[self.plot.min(PLOTS.len() - 1)];
        let ys = match self.plot {
            0 => &t.feed_mm_min,
            1 => &t.acc_mm_s2,
            _ => &t.jerk_mm_s3,
        };
        let pts: Vec<[f64; 2]> = t.t_s.iter().zip(ys).map(|(x, y)| [f64::from(*x), f64::from(*y)]).collect();
        Plot::new("userprog_time_plot")
            .height(150.0)
            .x_axis_label("t (s)")
            .y_axis_label(format!("{name} ({unit})"))
            .allow_scroll(false)
            .show(ui, |p| p.line(Line::new(format!("{name} ({unit})"), PlotPoints::from(pts)).width(1.5)));
    }

    /// The section's state for the tab's status.
    pub fn status(&self) -> serde_json::Value {
        let m = self.machine();
        serde_json::json!({
            "machine": m.as_ref().map(|m| m.name.clone()),
            "tolerance_mm": m.as_ref().map(|m| m.tolerance_mm),
            "limits_scale": self.scale(),
            "x_limits": m.as_ref().map(|m| serde_json::json!({
                "velocity_mm_min": m.axes[0].velocity,
                "acceleration_mm_s2": m.axes[0].acceleration,
                "jerk_mm_s3": m.axes[0].jerk,
            })),
            "for_x_velocity_mm_min": self.done.as_ref().map(|d| d.0.1.axes[0].velocity),
            "running": self.running(),
            "error": self.done.as_ref().and_then(|d| d.1.as_ref().err().map(ToString::to_string)),
            "total_s": self.done.as_ref().and_then(|d| d.1.as_ref().ok().map(|t| t.total_s)),
            "feed_s": self.done.as_ref().and_then(|d| d.1.as_ref().ok().map(|t| t.feed_s)),
            "rapid_s": self.done.as_ref().and_then(|d| d.1.as_ref().ok().map(|t| t.rapid_s)),
            "max_feed_mm_min": self.done.as_ref().and_then(|d| d.1.as_ref().ok().map(|t| t.feed_mm_min.iter().copied().fold(0.0f32, f32::max))),
            "samples": self.done.as_ref().and_then(|d| d.1.as_ref().ok().map(|t| t.t_s.len())),
            "for_tolerance_mm": self.done.as_ref().map(|d| d.0.1.tolerance_mm),
        })
    }
}

/// A duration as s.s under a minute, m:ss.s under an hour, h min s past it.
fn clock(s: f64) -> String {
    if !s.is_finite() || s < 0.0 {
        return "–".to_owned();
    }
    if s >= 3600.0 {
        let whole = s.round() as u64;
        return format!("{} h {:02} min {:02} s", whole / 3600, whole % 3600 / 60, whole % 60);
    }
    let tenths = (s * 10.0).round() as u64;
    if tenths < 600 {
        return format!("{}.{} s", tenths / 10, tenths % 10);
    }
    format!("{}:{:02}.{} min", tenths / 600, tenths % 600 / 10, tenths % 10)
}

#[cfg(test)]
mod tests {
    use super::clock;

    #[test]
    fn durations_read_as_clocks() {
        assert_eq!(clock(0.0), "0.0 s");
        assert_eq!(clock(22.94), "22.9 s");
        assert_eq!(clock(75.3), "1:15.3 min");
        assert_eq!(clock(59.97), "1:00.0 min");
        assert_eq!(clock(3725.0), "1 h 02 min 05 s");
        assert_eq!(clock(f64::NAN), "–");
    }
}
