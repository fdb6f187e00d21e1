//! The five-axis panel's computation, spread over frames within a time budget: the design
//! path of the chosen source, the step plan node by node ([`StepPlanner`]), the swept tool
//! of every segment sampled for drawing, the iteration counts of every root method, and the
//! swept tip's distance from the design tip path. Everything is a call into the core; this
//! file only schedules the calls and keeps their results.

use std::rc::Rc;

use glam::DVec3;
use web_time::{Duration, Instant};

use crate::crease::{CreaseCurve, CreaseJob};
use crate::fiveaxis::{
    Block, CreasePath, CutterLocation, DesignPath, Example1, FiveAxisError, Machine, NacaProfile, ProfilePath,
    StepNode, StepOptions, StepPlanner, ToolAxisRule, blade_case, block_at, evaluate_nodes, example1,
    tip_design_deviation,
};
use crate::numerics::maximise::MaxOptions;
use crate::numerics::roots::RootMethod;
use crate::plan::steps::dynamics_of;
use crate::plan::{StepsFeed, StepsTime, time_steps};

/// What the panel plans along.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Default)]
pub enum Source {
    /// The paper's Example 1 (seed 002).
    #[default]
    Example1,
    /// The crease of the current scene.
    Scene,
    /// The NACA 2412 blade section of the paper's Table 1.
    Blade,
}

impl Source {
    /// Label for the selector.
    pub fn label(self) -> &'static str {
        match self {
            Self::Example1 => "Example 1 of the paper",
            Self::Scene => "crease of the current scene",
            Self::Blade => "NACA 2412 blade section",
        }
    }
}

/// Everything a plan depends on.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Inputs {
    /// The source.
    pub source: Source,
    /// The scene computation's generation (source `Scene`), else 0.
    pub generation: u64,
    /// The machine.
    pub machine: Machine,
    /// The tool-axis rule (ignored by Example 1, whose axes are the paper's data).
    pub rule: ToolAxisRule,
    /// The tolerance E (mm).
    pub tol_mm: f64,
    /// Root method of the plan shown.
    pub method: RootMethod,
    /// Example 1: the single block P1 → P2 instead of the plan.
    pub before: bool,
    /// Also hold the swept tip within E of the design tip path ([`StepOptions::bound_tip`]).
    pub bound_tip: bool,
    /// Feed F of the tool tip relative to the workpiece (mm/min) for the plans' time: the
    /// scene's `motion.feed`, or [`crate::plan::steps::DEFAULT_FEED_MM_PER_MIN`].
    pub feed_mm_per_min: f64,
}

impl Inputs {
    /// Whether a plan for `self` has the same "before" block as one for `other`: Example 1's
    /// single block P1 → P2 and its swept samples depend on the design and the machine, not
    /// on the tolerance E, the root method or the tip bound (only the iteration comparison
    /// and the tip's distance from the design, computed in slices, do).
    pub fn same_single_block(&self, other: &Self) -> bool {
        self.before
            && other.before
            && self.source == other.source
            && self.generation == other.generation
            && self.machine == other.machine
            && self.rule == other.rule
    }
}

/// Where the design came from, for the 3D view's surfaces.
#[derive(Clone, Debug)]
pub enum Shape {
    /// The two surfaces of the scene's crease.
    Crease(Box<CreaseJob>),
    /// Example 1's boss: a cylinder about Z of this radius, the contact circle at height z.
    Cylinder {
        /// Radius (mm).
        radius_mm: f64,
        /// Height of the contact circle (mm).
        z_mm: f64,
    },
    /// A planar profile extruded along Z: contact points and unit normals toward the tool.
    Extrusion(Vec<(DVec3, DVec3)>),
}

/// A design path and what is drawn of it.
pub struct Design {
    /// The source, the scene generation and the rule it was built for.
    pub key: (Source, u64, ToolAxisRule),
    /// The path.
    pub path: Box<dyn DesignPath>,
    /// Unit of the path parameter s (`mm` or `rad`).
    pub s_unit: &'static str,
    /// Cutter locations sampled along the path (for drawing the design centre and tip
    /// paths and the thin tool axes).
    pub samples: Vec<CutterLocation>,
    /// The surfaces to draw.
    pub shape: Shape,
    /// The paper's data of Example 1.
    pub example1: Option<Example1Data>,
}

/// Example 1's printed data.
#[derive(Clone, Copy, Debug)]
pub struct Example1Data {
    /// P1, P2 (mm).
    pub contacts: [DVec3; 2],
    /// T1, T2 as printed.
    pub axes: [DVec3; 2],
}

impl std::fmt::Debug for Design {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("Design").field("key", &self.key).field("samples", &self.samples.len()).finish_non_exhaustive()
    }
}

/// Locations sampled along the design path for drawing.
const DESIGN_SAMPLES: usize = 400;

fn sample_design(path: &dyn DesignPath) -> Result<Vec<CutterLocation>, FiveAxisError> {
    let (a, b) = path.range();
    (0..=DESIGN_SAMPLES).map(|i| path.location_at(a + (b - a) * i as f64 / DESIGN_SAMPLES as f64)).collect()
}

/// The NACA 2412 case with another tool-axis rule (`blade_case` fixes normal1, tilt −30°).
fn blade_with_rule(rule: ToolAxisRule) -> Option<(ProfilePath, Machine)> {
    crate::fiveaxis::presets::blade_case_with_rule(NacaProfile::naca2412(), rule)
}

/// The default machine and rule of a source (the scene's keys for the crease).
pub fn blade_defaults() -> (Machine, ToolAxisRule) {
    let machine = blade_case(NacaProfile::naca2412()).map(|(_, m)| m).unwrap_or_default();
    (machine, ToolAxisRule::Normal1 { lead_rad: 0.0, tilt_rad: -30f64.to_radians() })
}

/// Builds the design of a source. `crease` is the scene's crease curve (source `Scene`).
///
/// # Errors
/// A message naming the problem (a design location that cannot be computed).
pub fn build_design(
    source: Source,
    generation: u64,
    rule: ToolAxisRule,
    crease: Option<&CreaseCurve>,
) -> Result<Design, String> {
    let key = (source, generation, rule);
    let (path, s_unit, shape, ex): (Box<dyn DesignPath>, _, _, _) = match source {
        Source::Example1 => {
            let Example1 { path, contacts, axes, .. } = example1();
            let radius_mm = contacts[0].truncate().length();
            let shape = Shape::Cylinder { radius_mm, z_mm: contacts[0].z };
            (Box::new(path), "rad", shape, Some(Example1Data { contacts, axes }))
        }
        Source::Blade => {
            let (path, _) = blade_with_rule(rule).ok_or("the blade section could not be sampled")?;
            (Box::new(path), "mm", Shape::Extrusion(Vec::new()), None)
        }
        Source::Scene => {
            let curve = crease.ok_or("the crease of the scene is not computed yet")?;
            let job = curve.job().clone();
            (Box::new(CreasePath::new(curve.clone(), rule)), "mm", Shape::Crease(Box::new(job)), None)
        }
    };
    let samples = sample_design(path.as_ref()).map_err(|e| e.to_string())?;
    let shape = match shape {
        Shape::Extrusion(_) => {
            let r = path.effective_radius_mm();
            Shape::Extrusion(samples.iter().map(|l| (l.centre - r * l.normals[0], l.normals[0])).collect())
        }
        other => other,
    };
    Ok(Design { key, path, s_unit, samples, shape, example1: ex })
}

/// One point of the swept tool of a segment.
#[derive(Clone, Copy, Debug)]
pub struct Sample {
    /// Fraction of the segment.
    pub tau: f64,
    /// Swept tool tip (mm).
    pub tip: DVec3,
    /// Swept ball centre (mm).
    pub centre: DVec3,
    /// The programmed tip chord at τ (mm).
    pub tip_chord: DVec3,
    /// The programmed centre chord at τ (mm).
    pub centre_chord: DVec3,
    /// Signed error of the swept ball there (largest magnitude over the surfaces; mm,
    /// overcut +).
    pub delta_mm: f64,
}

/// The swept tool of one segment, sampled.
#[derive(Clone, Debug, Default)]
pub struct SegView {
    /// Equally spaced in τ, both ends included.
    pub samples: Vec<Sample>,
}

/// Iterations of one root method at the current tolerance.
#[derive(Clone, Debug, PartialEq)]
pub enum CompareRow {
    /// Not computed yet.
    Pending,
    /// δ evaluations, nodes, wall time (ms, this device).
    Done {
        /// δ evaluations, bracketing included.
        iterations: u64,
        /// Nodes.
        nodes: usize,
        /// Wall time on this device (ms).
        ms: f64,
    },
    /// The plan failed.
    Failed(String),
}

/// A plan failure: the message and where along the path (s), when known.
#[derive(Clone, Debug)]
pub struct PlanError {
    /// The core's message.
    pub message: String,
    /// Path parameter of the failure.
    pub s: Option<f64>,
}

fn error_s(e: &FiveAxisError) -> Option<f64> {
    match e {
        FiveAxisError::Kinematics { s, .. }
        | FiveAxisError::ToolAxis { s, .. }
        | FiveAxisError::Crease { s }
        | FiveAxisError::NotFinite { s }
        | FiveAxisError::Underflow { s, .. }
        | FiveAxisError::NoConvergence { s, .. }
        | FiveAxisError::TooManyNodes { s, .. }
        | FiveAxisError::TooMuchWork { s, .. } => Some(*s),
        FiveAxisError::BadTolerance { .. } | FiveAxisError::EmptyPath { .. } => None,
    }
}

/// Samples of the swept tool per segment; the single block of Example 1's "before" gets more.
const SAMPLES_PER_SEGMENT: usize = 16;
const SAMPLES_SINGLE_BLOCK: usize = 120;

/// A plan being computed (or done).
pub struct Plan {
    /// Its inputs.
    pub inputs: Inputs,
    /// The design it plans along.
    pub design: Rc<Design>,
    /// Serial number (views compare it to know what to rebuild).
    pub serial: u64,
    planner: Option<StepPlanner>,
    /// Nodes so far (blocks, δ, reports, iterations).
    pub nodes: Vec<StepNode>,
    /// Swept samples of segments `0..segs.len()`.
    pub segs: Vec<SegView>,
    /// The planner has finished (or failed).
    pub planned: bool,
    /// Why it failed.
    pub error: Option<PlanError>,
    /// Swept tip's largest distance from the design tip path, per segment (mm).
    pub tip_design_mm: Vec<f64>,
    /// Iterations per method, in [`RootMethod::ALL`] order.
    pub compare: Vec<CompareRow>,
    compare_run: Option<(usize, StepPlanner, f64)>,
    /// Wall time spent on the main plan (ms, this device).
    pub plan_ms: f64,
    /// Example 1 with "before" shown: the blocks of the plan after steps, from the comparison
    /// run of this plan's method (reports do not change the nodes).
    after_blocks: Option<Vec<Block>>,
    /// The time on the machine's dynamics preset, computed last (`None` until then).
    pub times: Option<Times>,
}

/// The time of the plans on the dynamics preset of the machine's structure
/// ([`crate::plan::steps`]), at [`Inputs::feed_mm_per_min`] of the tool tip.
#[derive(Clone, Debug, PartialEq)]
pub struct Times {
    /// Example 1: the single block P1 → P2 (the "before" plan); `None` for other sources.
    pub before: Option<Result<StepsTime, String>>,
    /// The plan with steps: Example 1's "after", or the plan of the other sources.
    pub after: Result<StepsTime, String>,
}

/// Times a plan's blocks on the preset of the machine's structure.
fn time_of(inputs: &Inputs, blocks: &[Block]) -> Result<StepsTime, String> {
    let kind = inputs.machine.kind;
    time_steps(kind, blocks, inputs.feed_mm_per_min, StepsFeed::Tip, &dynamics_of(kind)).map_err(|e| e.to_string())
}

impl std::fmt::Debug for Plan {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("Plan").field("inputs", &self.inputs).field("nodes", &self.nodes.len()).finish_non_exhaustive()
    }
}

fn options(inputs: &Inputs, method: RootMethod, reports: bool) -> StepOptions {
    StepOptions { reports, ..StepOptions::new(inputs.tol_mm).with_method(method).with_tip_bound(inputs.bound_tip) }
}

impl Plan {
    /// Starts a plan (the first block is computed here). Example 1's single "before" block
    /// is taken from `earlier` when that plan holds the same one ([`Inputs::same_single_block`]):
    /// its evaluation (the swept error maximised over the whole gouging block, 13.5 ms
    /// natively) does not fit in a frame, and dragging E does not change it.
    pub fn new(inputs: Inputs, design: Rc<Design>, serial: u64, earlier: Option<&Self>) -> Self {
        let mut plan = Self {
            inputs,
            design,
            serial,
            planner: None,
            nodes: Vec::new(),
            segs: Vec::new(),
            planned: false,
            error: None,
            tip_design_mm: Vec::new(),
            compare: vec![CompareRow::Pending; RootMethod::ALL.len()],
            compare_run: None,
            plan_ms: 0.0,
            after_blocks: None,
            times: None,
        };
        let reusable = earlier.filter(|e| {
            e.inputs.same_single_block(&inputs)
                && Rc::ptr_eq(&e.design, &plan.design)
                && e.planned
                && e.error.is_none()
                && e.nodes.len() == 2
                && e.segs.len() == 1
        });
        if let Some(e) = reusable.filter(|_| plan.design.example1.is_some()) {
            plan.nodes.clone_from(&e.nodes);
            plan.segs.clone_from(&e.segs);
            plan.planned = true;
            plan.plan_ms = e.plan_ms;
            return plan;
        }
        let t0 = Instant::now();
        let path = plan.design.path.as_ref();
        let machine = &inputs.machine;
        if inputs.before && plan.design.example1.is_some() {
            let (a, b) = path.range();
            match evaluate_nodes(machine, path, &[a, b], &MaxOptions::default()) {
                Ok(nodes) => plan.nodes = nodes,
                Err(e) => plan.fail(&e),
            }
            plan.planned = true;
        } else {
            match StepPlanner::new(machine, path, &options(&inputs, inputs.method, true)) {
                Ok(p) => {
                    plan.nodes = p.nodes().to_vec();
                    plan.planner = Some(p);
                }
                Err(e) => {
                    plan.fail(&e);
                    plan.planned = true;
                }
            }
        }
        plan.plan_ms += t0.elapsed().as_secs_f64() * 1e3;
        plan
    }

    fn fail(&mut self, e: &FiveAxisError) {
        self.error = Some(PlanError { message: e.to_string(), s: error_s(e) });
    }

    /// The plan and the swept samples are complete (the comparison may still run).
    pub fn shown_complete(&self) -> bool {
        self.planned && self.segs.len() + 1 >= self.nodes.len()
    }

    /// Nothing left to compute.
    pub fn finished(&self) -> bool {
        self.shown_complete()
            && self.compare.iter().all(|r| *r != CompareRow::Pending)
            && self.tip_design_mm.len() + 1 >= self.nodes.len()
            && self.times.is_some()
    }

    /// Works for at most `budget`; returns whether anything changed.
    pub fn advance(&mut self, budget: Duration) -> bool {
        let t_end = Instant::now() + budget;
        let mut changed = false;
        while !self.finished() && Instant::now() < t_end {
            changed = true;
            if self.segs.len() + 1 < self.nodes.len() {
                self.sample_next_segment();
            } else if !self.planned {
                self.plan_next_node();
            } else if self.compare.contains(&CompareRow::Pending) {
                self.compare_step();
            } else if self.tip_design_mm.len() + 1 < self.nodes.len() {
                self.tip_design_next();
            } else {
                self.times = Some(self.compute_times());
            }
        }
        changed
    }

    fn plan_next_node(&mut self) {
        let t0 = Instant::now();
        let Some(planner) = self.planner.as_mut() else {
            self.planned = true;
            return;
        };
        let (machine, path) = (&self.inputs.machine, self.design.path.as_ref());
        match planner.next_node(machine, path) {
            Ok(node) => {
                self.nodes.push(node);
                if planner.is_done() {
                    self.planned = true;
                }
            }
            Err(e) => {
                self.fail(&e);
                self.planned = true;
            }
        }
        self.plan_ms += t0.elapsed().as_secs_f64() * 1e3;
    }

    fn sample_next_segment(&mut self) {
        let k = self.segs.len();
        let (a, b) = (&self.nodes[k].block, &self.nodes[k + 1].block);
        let n = if self.nodes.len() == 2 && self.planned { SAMPLES_SINGLE_BLOCK } else { SAMPLES_PER_SEGMENT };
        let path = self.design.path.as_ref();
        let r = path.ball_radius_mm();
        let (la, lb) = (&a.location, &b.location);
        let samples = (0..=n)
            .map(|i| {
                let tau = i as f64 / n as f64;
                let pose = self.inputs.machine.pose_from_joints(&a.joints.lerp(&b.joints, tau));
                let (tip, axis) = (pose.tip_in_workpiece, pose.axis_in_workpiece);
                let centre = tip + r * axis;
                let delta_mm = path
                    .surface_errors(centre, la, lb, tau)
                    .into_iter()
                    .flatten()
                    .fold(0.0f64, |m, e| if e.abs() > m.abs() { e } else { m });
                Sample {
                    tau,
                    tip,
                    centre,
                    tip_chord: la.tip.lerp(lb.tip, tau),
                    centre_chord: la.centre.lerp(lb.centre, tau),
                    delta_mm,
                }
            })
            .collect();
        self.segs.push(SegView { samples });
    }

    fn compare_step(&mut self) {
        let Some(i) = self.compare.iter().position(|r| *r == CompareRow::Pending) else {
            return;
        };
        let method = RootMethod::ALL[i];
        let (machine, path) = (&self.inputs.machine, self.design.path.as_ref());
        // The plan shown already counts its method's iterations (reports do not change them).
        if method == self.inputs.method && !self.inputs.before && self.planned {
            self.compare[i] = match &self.error {
                None => CompareRow::Done {
                    iterations: self.nodes.iter().map(|n| u64::from(n.evaluations)).sum(),
                    nodes: self.nodes.len(),
                    ms: self.plan_ms,
                },
                Some(e) => CompareRow::Failed(e.message.clone()),
            };
            return;
        }
        let t0 = Instant::now();
        if self.compare_run.as_ref().is_none_or(|(j, _, _)| *j != i) {
            match StepPlanner::new(machine, path, &options(&self.inputs, method, false)) {
                Ok(p) => self.compare_run = Some((i, p, 0.0)),
                Err(e) => {
                    self.compare[i] = CompareRow::Failed(e.to_string());
                    return;
                }
            }
        }
        let Some((_, planner, ms)) = self.compare_run.as_mut() else {
            return;
        };
        let step = planner.next_node(machine, path);
        *ms += t0.elapsed().as_secs_f64() * 1e3;
        match step {
            Err(e) => {
                self.compare[i] = CompareRow::Failed(e.to_string());
                self.compare_run = None;
            }
            Ok(_) if planner.is_done() => {
                let nodes = planner.nodes();
                if method == self.inputs.method && self.inputs.before {
                    self.after_blocks = Some(nodes.iter().map(|n| n.block).collect());
                }
                self.compare[i] = CompareRow::Done {
                    iterations: nodes.iter().map(|n| u64::from(n.evaluations)).sum(),
                    nodes: nodes.len(),
                    ms: *ms,
                };
                self.compare_run = None;
            }
            Ok(_) => {}
        }
    }

    fn tip_design_next(&mut self) {
        let k = self.tip_design_mm.len();
        if k + 1 >= self.nodes.len() {
            return;
        }
        let (a, b) = (&self.nodes[k].block, &self.nodes[k + 1].block);
        let opts = MaxOptions {
            floor: crate::numerics::tolerance::SWEPT_FLOOR_REL_TOL * self.inputs.tol_mm,
            ..MaxOptions::default()
        };
        let d = tip_design_deviation(&self.inputs.machine, self.design.path.as_ref(), a, b, &opts).unwrap_or(f64::NAN);
        self.tip_design_mm.push(d);
    }

    /// The plans' times: Example 1's before and after (one of them the plan shown, the other
    /// its single block or the comparison run's nodes), or the plan shown.
    fn compute_times(&self) -> Times {
        let shown = || -> Result<StepsTime, String> {
            match &self.error {
                Some(e) => Err(format!("no complete plan to time: {}", e.message)),
                None => time_of(&self.inputs, &self.nodes.iter().map(|n| n.block).collect::<Vec<_>>()),
            }
        };
        if self.design.example1.is_none() {
            return Times { before: None, after: shown() };
        }
        if self.inputs.before {
            let after = match &self.after_blocks {
                Some(b) => time_of(&self.inputs, b),
                None => Err(self.compare_error().unwrap_or_else(|| "the plan with steps was not made".to_owned())),
            };
            return Times { before: Some(shown()), after };
        }
        let (machine, path) = (&self.inputs.machine, self.design.path.as_ref());
        let (a, b) = path.range();
        let before = block_at(machine, path, a, None)
            .and_then(|first| Ok(vec![first, block_at(machine, path, b, Some(&first.joints))?]))
            .map_err(|e| e.to_string())
            .and_then(|blocks| time_of(&self.inputs, &blocks));
        Times { before: Some(before), after: shown() }
    }

    /// The comparison run's failure for the plan's own method.
    fn compare_error(&self) -> Option<String> {
        let i = RootMethod::ALL.iter().position(|m| *m == self.inputs.method)?;
        match &self.compare[i] {
            CompareRow::Failed(e) => Some(e.clone()),
            _ => None,
        }
    }

    /// Total δ evaluations of the plan so far.
    pub fn iterations(&self) -> u64 {
        self.nodes.iter().map(|n| u64::from(n.evaluations)).sum()
    }

    /// Largest |δ| over the segments so far (mm), with its sign.
    pub fn worst_delta_mm(&self) -> Option<f64> {
        self.nodes.iter().filter_map(|n| n.total_mm).fold(None, |m: Option<f64>, d| match m {
            Some(x) if x.abs() >= d.abs() => Some(x),
            _ => Some(d),
        })
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn inputs(tol_mm: f64, method: RootMethod) -> Inputs {
        Inputs {
            source: Source::Example1,
            generation: 0,
            machine: example1().machine,
            rule: ToolAxisRule::Bisector,
            tol_mm,
            method,
            before: true,
            bound_tip: false,
            feed_mm_per_min: crate::plan::steps::DEFAULT_FEED_MM_PER_MIN,
        }
    }

    /// Advances a plan to its end (bounded: a plan of Example 1 takes well under a second).
    fn finish(mut plan: Plan) -> Plan {
        for _ in 0..10_000 {
            if plan.finished() {
                return plan;
            }
            plan.advance(Duration::from_millis(50));
        }
        panic!("the plan did not finish: {plan:?}");
    }

    #[test]
    fn the_single_block_is_shared_only_where_e_method_and_tip_bound_differ() {
        let a = inputs(0.01, RootMethod::Secant);
        let mut b = inputs(0.05, RootMethod::AndersonBjorck);
        b.bound_tip = true;
        assert!(a.same_single_block(&b) && b.same_single_block(&a));
        let mut other_machine = a;
        other_machine.machine.pivots_mm[0].x += 1.0;
        assert!(!a.same_single_block(&other_machine));
        let mut after = a;
        after.before = false;
        assert!(!a.same_single_block(&after) && !after.same_single_block(&after));
        let mut scene = a;
        scene.source = Source::Scene;
        assert!(!a.same_single_block(&scene));
        let mut rule = a;
        rule.rule = ToolAxisRule::Normal1 { lead_rad: 0.0, tilt_rad: 0.1 };
        assert!(!a.same_single_block(&rule));
    }

    /// A plan whose "before" block is taken from the plan at another E gives what a plan
    /// computed from nothing gives: the same block, swept samples, comparison and tip errors.
    #[test]
    fn a_reused_single_block_gives_the_plan_computed_anew() {
        let design = Rc::new(build_design(Source::Example1, 0, ToolAxisRule::Bisector, None).expect("example 1"));
        let first = finish(Plan::new(inputs(0.01, RootMethod::Secant), design.clone(), 1, None));
        let at = inputs(0.05, RootMethod::AndersonBjorck);
        let reused = Plan::new(at, design.clone(), 2, Some(&first));
        // Taken over whole, before any slice: the frame that starts it does no evaluation.
        assert!(reused.shown_complete(), "{reused:?}");
        assert!(reused.compare.iter().all(|r| *r == CompareRow::Pending) && reused.tip_design_mm.is_empty());
        let reused = finish(reused);
        let anew = finish(Plan::new(at, design, 3, None));
        assert_eq!(reused.nodes, anew.nodes);
        assert_eq!(reused.segs.len(), 1);
        assert_eq!(reused.segs[0].samples.len(), anew.segs[0].samples.len());
        for (x, y) in reused.segs[0].samples.iter().zip(&anew.segs[0].samples) {
            assert_eq!((x.tau, x.tip, x.centre, x.delta_mm), (y.tau, y.tip, y.centre, y.delta_mm));
            assert_eq!((x.tip_chord, x.centre_chord), (y.tip_chord, y.centre_chord));
        }
        assert_eq!(reused.tip_design_mm, anew.tip_design_mm);
        let iterations = |p: &Plan| -> Vec<Option<(u64, usize)>> {
            p.compare
                .iter()
                .map(|r| match r {
                    CompareRow::Done { iterations, nodes, .. } => Some((*iterations, *nodes)),
                    _ => None,
                })
                .collect()
        };
        assert_eq!(iterations(&reused), iterations(&anew));
        assert!(iterations(&reused).iter().all(Option::is_some));
        // The comparison depends on E: it is not carried over from the first plan.
        assert_ne!(iterations(&reused), iterations(&first));
    }
}
