//! The app's one scheme for work longer than a frame: a [`Job`] takes a request of a
//! [`JobKind`] (`crate::jobs`), runs it away from the UI thread, and is polled once per frame
//! for its progress and, at the end, its output. Dropping a job cancels it.
//!
//! - Natively the job runs on its own `std::thread`; cancelling sets a flag the job may look
//!   at (an abandoned job's thread finishes and its output is dropped).
//! - In the browser it runs in a Web Worker ([`WORKER_SCRIPT`], the `interpolab-worker` wasm
//!   module: the core without egui or wgpu, built by Trunk beside the app). The request and
//!   the output cross as text (`JobKind::encode_*`, numbers by their bits, so the output is
//!   the one computed). One worker per job at a time; cancelling terminates it; a worker
//!   that answered is kept for the next job (at most one kept), so a replay does not start
//!   a worker again. Once the page's first frame is shown a spare worker starts if no job
//!   has one yet ([`start_spare_worker`]), so a user's first job does not wait for the
//!   worker's wasm either, and a request is posted the moment the job starts, before the
//!   worker is ready (its script keeps it; the page used to wait for the worker's `ready`,
//!   which sat behind the page's first frames). If the worker cannot
//!   run (no script, an error inside it, an output that does not decode), the job is run on
//!   the page instead, as the app did before: slower to the eye, same result.
//!
//! The work that stays on the UI thread (the crease periods, the 5-axis plan, the fillet
//! paths, the simulation moves) is already cut into slices of a few ms under the one
//! per-frame time budget ([`super::budget::FRAME_BUDGET`]); what a single call could not cut
//! (writing a G-code program: 0.1–6 s) is a job.

use std::sync::atomic::{AtomicUsize, Ordering};

use web_time::{Duration, Instant};

use crate::jobs::JobKind;

/// Jobs finished off the UI thread / on it (the app's status element shows both).
static FINISHED: [AtomicUsize; 2] = [AtomicUsize::new(0), AtomicUsize::new(0)];

/// Jobs finished so far: `(in the background, on the UI thread)`.
#[must_use]
pub fn finished_counts() -> (usize, usize) {
    (FINISHED[0].load(Ordering::Relaxed), FINISHED[1].load(Ordering::Relaxed))
}

/// The worker's script, next to `index.html` (`web/jobs-worker.js`: loads the worker's wasm
/// and keeps the messages that arrive before it runs).
pub const WORKER_SCRIPT: &str = "./jobs-worker.js";

/// Starts a spare worker for the page's first job if no job has started one yet (the app
/// calls it once its first frame is on screen). Natively nothing: a job's thread starts at
/// once. In a browser the worker then fetches and compiles its wasm while the page idles, so
/// a job started later (a user's first run) finds it ready; started after the first frame,
/// not while the page loads, because a job that runs during the page's first frames takes
/// the CPU they need (docs/background-jobs.md, "The first job's worker").
pub fn start_spare_worker() {
    imp::start_spare();
}

/// Most cores a machine is taken to have (a bound on what the browser reports).
const MAX_CORES: usize = 64;

/// Background jobs worth running at once: the machine's cores less one, at least one. The
/// page keeps a core for itself — in a browser drawing on a CPU rasteriser (SwiftShader) the
/// GPU process needs it too: two workers on a 2-core machine starved the page (a 3.15 s frame
/// while the fillet table computed, docs/background-jobs.md).
#[must_use]
pub fn spare_cores() -> usize {
    cores().clamp(1, MAX_CORES).saturating_sub(1).max(1)
}

#[cfg(not(target_arch = "wasm32"))]
fn cores() -> usize {
    std::thread::available_parallelism().map_or(1, std::num::NonZero::get)
}

#[cfg(target_arch = "wasm32")]
fn cores() -> usize {
    let reported = web_sys::window().map_or(1.0, |w| w.navigator().hardware_concurrency());
    // Whole cores in [1, MAX_CORES]; NaN or a missing value counts as one.
    (1..=MAX_CORES).take_while(|&n| n as f64 <= reported).last().unwrap_or(1)
}

/// How often a panel waiting for a job looks again when nothing else repaints.
pub const POLL: Duration = Duration::from_millis(50);

/// How often a panel whose job runs in the background repaints to show its progress and
/// partial outputs (once a second). A job's output wakes the page at once ([`set_waker`]),
/// and the user's input repaints at once as always; only the progress bar and the partial
/// outputs (a simulation's keyframes) wait for the next look. Why not [`POLL`]: in a browser
/// drawing on a CPU rasteriser every repaint takes CPU from the worker: a frame of the
/// simulation's stock costs SwiftShader 0.27–0.37 s, and repainting every 50 ms (or on
/// every keyframe) kept one of 2 cores drawing for the whole run (docs/simulation.md, "In
/// the browser").
pub const PROGRESS_POLL: Duration = Duration::from_millis(1000);

/// The context repainted when a job gives its output.
static WAKER: std::sync::Mutex<Option<eframe::egui::Context>> = std::sync::Mutex::new(None);

/// Makes `ctx` the one woken when a job gives its output (a panel that polls jobs calls it
/// each frame; cheap).
pub fn set_waker(ctx: &eframe::egui::Context) {
    if let Ok(mut w) = WAKER.lock()
        && w.as_ref().is_none_or(|old| old != ctx)
    {
        *w = Some(ctx.clone());
    }
}

/// Asks for a repaint now: a job's output (or its worker's readiness or failure) arrived.
fn wake() {
    if let Ok(w) = WAKER.lock()
        && let Some(ctx) = w.as_ref()
    {
        ctx.request_repaint();
    }
}

/// What a poll found.
#[derive(Debug)]
pub enum Poll<T> {
    /// Still running; the fraction done if the job reports one.
    Running(Option<f64>),
    /// Finished with this output (given once).
    Done(T),
}

/// A job under way.
pub struct Job<K: JobKind> {
    started: Instant,
    progress: Option<f64>,
    /// Partial outputs arrived and not yet taken.
    partials: Vec<K::Partial>,
    inner: imp::Inner<K>,
}

impl<K: JobKind> std::fmt::Debug for Job<K> {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("Job").field("kind", &K::NAME).field("progress", &self.progress).finish_non_exhaustive()
    }
}

impl<K: JobKind> Job<K> {
    /// Starts a job.
    #[must_use]
    pub fn start(request: K::Request) -> Self {
        Self { started: Instant::now(), progress: None, partials: Vec::new(), inner: imp::Inner::start(request, false) }
    }

    /// Starts a job whose worker is worth more than the job: dropping it (a newer request
    /// supersedes it) lets a browser's worker finish the job, its output thrown away, and
    /// keeps the worker for the next job, which is posted to it at once and runs right after
    /// (the worker keeps state between jobs: the simulation's kept stocks,
    /// `jobs::simulate_run::session::Session`). For short jobs (a replay from a kept stock: a tenth of
    /// the program at most); a long one delays the next by what it has left. Natively the
    /// same as [`Job::start`] (the thread stops at its next look at the cancel flag; the
    /// state lives in the process).
    #[must_use]
    pub fn start_keeping_worker(request: K::Request) -> Self {
        Self { started: Instant::now(), progress: None, partials: Vec::new(), inner: imp::Inner::start(request, true) }
    }

    /// Takes what arrived since the last poll. After [`Poll::Done`] the job is spent: poll
    /// it no more. Partial outputs that arrived are kept for [`Job::take_partials`] (all of
    /// them before the output); a poll decodes them until the frame budget is spent, at least
    /// one, and leaves the rest for the next poll, asking for that frame at once.
    pub fn poll(&mut self) -> Poll<K::Output> {
        match self.inner.poll(&mut self.progress, &mut self.partials) {
            Some(out) => {
                let i = usize::from(!self.inner.in_background_done());
                FINISHED[i].fetch_add(1, Ordering::Relaxed);
                Poll::Done(out)
            }
            None => Poll::Running(self.progress),
        }
    }

    /// The partial outputs that arrived by the last poll, in order.
    pub fn take_partials(&mut self) -> Vec<K::Partial> {
        std::mem::take(&mut self.partials)
    }

    /// Time since the start.
    #[must_use]
    pub fn elapsed(&self) -> Duration {
        self.started.elapsed()
    }

    /// Whether it ran (or runs) off the UI thread so far: false once it had to run on the
    /// page. Unlike [`Job::in_background`], still true after a background job's output came.
    #[must_use]
    pub fn ran_in_background(&self) -> bool {
        self.inner.in_background_done()
    }

    /// Whether it runs off the UI thread (false: in the browser without a worker, where the
    /// job runs on the page when polled).
    #[must_use]
    pub fn in_background(&self) -> bool {
        self.inner.in_background()
    }
}

/// Whether decoding partial outputs since `t0` used this frame's share
/// ([`super::budget::FRAME_BUDGET`]): a poll decodes at least one waiting partial output and
/// leaves the rest for the next frames, so a job that hands back much (a long program's
/// pieces) never makes one long frame.
fn over_budget(t0: Instant) -> bool {
    t0.elapsed() >= super::budget::FRAME_BUDGET
}

/// Decodes a partial output into `partials` (one that does not decode is logged and left out:
/// a view may lack a keyframe, the output still comes).
fn push_partial<K: JobKind>(text: &str, partials: &mut Vec<K::Partial>) {
    match K::decode_partial(text) {
        Ok(p) => partials.push(p),
        Err(e) => log::warn!("{}: a partial output does not decode: {e}", K::NAME),
    }
}

/// Runs a job on the UI thread (no thread or worker could take it), keeping its partial
/// outputs.
fn run_here<K: JobKind>(request: &K::Request, partials: &mut Vec<K::Partial>) -> K::Output {
    struct Keep(Vec<String>);
    impl crate::jobs::Progress for Keep {
        fn progress(&mut self, _fraction: f64) {}
        fn cancelled(&self) -> bool {
            false
        }
        fn partial(&mut self, encoded: String) {
            self.0.push(encoded);
        }
    }
    let mut keep = Keep(Vec::new());
    let out = K::run(request, &mut keep);
    for t in &keep.0 {
        push_partial::<K>(t, partials);
    }
    out
}

#[cfg(not(target_arch = "wasm32"))]
mod imp {
    use std::sync::Arc;
    use std::sync::atomic::{AtomicBool, Ordering};
    use std::sync::mpsc;

    use crate::jobs::{JobKind, Progress};

    enum Msg<T> {
        Progress(f64),
        Partial(String),
        Done(T),
    }

    struct Reporter<T> {
        tx: mpsc::Sender<Msg<T>>,
        cancel: Arc<AtomicBool>,
    }

    impl<T> Progress for Reporter<T> {
        fn progress(&mut self, fraction: f64) {
            let _ = self.tx.send(Msg::Progress(fraction));
        }
        fn cancelled(&self) -> bool {
            self.cancel.load(Ordering::Relaxed)
        }
        fn partial(&mut self, encoded: String) {
            let _ = self.tx.send(Msg::Partial(encoded));
        }
    }

    pub struct Inner<K: JobKind> {
        rx: mpsc::Receiver<Msg<K::Output>>,
        cancel: Arc<AtomicBool>,
        /// The thread could not be started: run on the first poll.
        here: Option<K::Request>,
        ran_here: bool,
    }

    impl<K: JobKind> Inner<K> {
        pub fn start(request: K::Request, _keep_worker: bool) -> Self {
            let (tx, rx) = mpsc::channel();
            let cancel = Arc::new(AtomicBool::new(false));
            let mut reporter = Reporter { tx: tx.clone(), cancel: cancel.clone() };
            let slot = Arc::new(std::sync::Mutex::new(Some(request)));
            let slot2 = slot.clone();
            let spawned = std::thread::Builder::new().name(format!("job {}", K::NAME)).spawn(move || {
                let Some(request) = slot2.lock().ok().and_then(|mut r| r.take()) else { return };
                let out = K::run(&request, &mut reporter);
                let _ = tx.send(Msg::Done(out));
                super::wake();
            });
            // No thread (a platform without them): the request is still in its slot.
            let here = if spawned.is_err() { slot.lock().ok().and_then(|mut r| r.take()) } else { None };
            Self { rx, cancel, here, ran_here: false }
        }

        pub fn poll(&mut self, progress: &mut Option<f64>, partials: &mut Vec<K::Partial>) -> Option<K::Output> {
            if let Some(request) = self.here.take() {
                self.ran_here = true;
                return Some(super::run_here::<K>(&request, partials));
            }
            let t0 = web_time::Instant::now();
            let mut decoded = false;
            loop {
                if decoded && super::over_budget(t0) {
                    super::wake();
                    return None;
                }
                let Ok(m) = self.rx.try_recv() else { break };
                match m {
                    Msg::Progress(f) => *progress = Some(f),
                    Msg::Partial(text) => {
                        super::push_partial::<K>(&text, partials);
                        decoded = true;
                    }
                    Msg::Done(out) => return Some(out),
                }
            }
            None
        }

        pub fn in_background(&self) -> bool {
            self.here.is_none() && !self.ran_here
        }

        pub fn in_background_done(&self) -> bool {
            !self.ran_here
        }
    }

    impl<K: JobKind> Drop for Inner<K> {
        fn drop(&mut self) {
            self.cancel.store(true, Ordering::Relaxed);
        }
    }

    /// Nothing to start ahead: a job's thread starts at once.
    pub fn start_spare() {}
}

#[cfg(target_arch = "wasm32")]
mod imp {
    use std::cell::RefCell;
    use std::collections::VecDeque;
    use std::rc::Rc;

    use eframe::wasm_bindgen::JsCast;
    use eframe::wasm_bindgen::prelude::{Closure, JsValue};

    use super::WORKER_SCRIPT;
    use crate::jobs::JobKind;

    type Inbox = Rc<RefCell<VecDeque<String>>>;

    struct Running {
        worker: web_sys::Worker,
        inbox: Inbox,
        /// Answers of earlier, dropped jobs still to come before this job's messages (a
        /// worker taken over from [`DRAINING`]): their messages are skipped.
        skip: usize,
        _on_message: Closure<dyn FnMut(web_sys::MessageEvent)>,
        _on_error: Closure<dyn FnMut(web_sys::Event)>,
    }

    pub struct Inner<K: JobKind> {
        /// The encoded request (kept to run it on the page if the worker fails).
        request: String,
        running: Option<Running>,
        ran_here: bool,
        /// Dropping the job lets the worker finish it and keeps the worker ([`DRAINING`]).
        keep_worker: bool,
        _kind: std::marker::PhantomData<K>,
    }

    /// Workers kept after answering a job, at most [`MAX_IDLE`]: the next job (a replay of
    /// the move slider, the next table row) starts on one at once instead of fetching and
    /// compiling the worker's wasm again. Only a worker that has answered is kept (its last
    /// message was its output, so nothing of the old job is queued); a cancelled job's
    /// worker is terminated, as before.
    const MAX_IDLE: usize = 1;

    thread_local! {
        static IDLE: RefCell<Vec<web_sys::Worker>> = const { RefCell::new(Vec::new()) };
        /// A worker finishing a dropped job started by `Job::start_keeping_worker` (at most
        /// one: a second one replaces it, ending the older). The next job is posted to it
        /// at once and skips the dropped jobs' answers.
        static DRAINING: RefCell<Option<Running>> = const { RefCell::new(None) };
        /// The spare worker started after the page's first frame ([`start_spare`]), until a
        /// job takes it.
        static SPARE: RefCell<Option<Running>> = const { RefCell::new(None) };
        /// Whether any worker was started (by a job or as the spare): a spare is started
        /// only for a page that has none.
        static STARTED: std::cell::Cell<bool> = const { std::cell::Cell::new(false) };
    }

    impl Running {
        /// Takes `worker` for a job: installs the handlers (replacing any).
        fn attach(worker: web_sys::Worker) -> Self {
            let inbox: Inbox = Rc::default();
            let inbox2 = inbox.clone();
            let on_message = Closure::<dyn FnMut(web_sys::MessageEvent)>::new(move |e: web_sys::MessageEvent| {
                let text = e.data().as_string().unwrap_or_default();
                if text.starts_with("ready\n") {
                    // The request went already (the worker's script keeps it until then).
                    return;
                }
                // Progress and partial outputs wait for the panel's next look; the output
                // and a failure wake it.
                let shown = !(text.starts_with("progress\n") || text.starts_with("partial\n"));
                inbox2.borrow_mut().push_back(text);
                if shown {
                    super::wake();
                }
            });
            let inbox3 = inbox.clone();
            let on_error = Closure::<dyn FnMut(web_sys::Event)>::new(move |e: web_sys::Event| {
                let what = e
                    .dyn_ref::<web_sys::ErrorEvent>()
                    .map_or_else(|| "the worker could not start".to_owned(), web_sys::ErrorEvent::message);
                inbox3.borrow_mut().push_back(format!("failed\n{what}"));
                super::wake();
            });
            worker.set_onmessage(Some(on_message.as_ref().unchecked_ref()));
            worker.set_onerror(Some(on_error.as_ref().unchecked_ref()));
            Self { worker, inbox, skip: 0, _on_message: on_message, _on_error: on_error }
        }

        /// Ends the worker (the handlers are unset when `self` drops).
        fn stop(self) {
            self.worker.terminate();
        }

        /// Keeps the worker (it answered and waits for a message) for the next job, or ends
        /// it when enough are kept.
        fn park(self) {
            let kept = IDLE.with(|idle| {
                let mut idle = idle.borrow_mut();
                if idle.len() < MAX_IDLE {
                    idle.push(self.worker.clone());
                    true
                } else {
                    false
                }
            });
            if !kept {
                self.stop();
            }
        }
    }

    impl Drop for Running {
        /// Unsets the handlers: an event already queued for them must not reach a closure
        /// that is about to be dropped.
        fn drop(&mut self) {
            self.worker.set_onmessage(None);
            self.worker.set_onerror(None);
        }
    }

    /// Whether a worker reported a failure (it could not start): its inbox holds the message.
    fn failed(r: &Running) -> bool {
        r.inbox.borrow().iter().any(|m| m.starts_with("failed\n"))
    }

    /// Starts the spare worker unless a worker was ever started on this page.
    pub fn start_spare() {
        if STARTED.with(std::cell::Cell::get) {
            return;
        }
        STARTED.with(|s| s.set(true));
        match web_sys::Worker::new(WORKER_SCRIPT) {
            Ok(w) => SPARE.with(|s| *s.borrow_mut() = Some(Running::attach(w))),
            Err(e) => log::warn!("no spare Web Worker ({e:?}): the first job starts its own"),
        }
    }

    /// A worker for the next job: the one draining a dropped job, a kept one, the spare, or
    /// a new one, in that order. A spare that failed is ended (the job starts its own).
    fn spawn() -> Result<Running, JsValue> {
        STARTED.with(|s| s.set(true));
        if let Some(r) = DRAINING.with(|d| d.borrow_mut().take()) {
            return Ok(r);
        }
        if let Some(w) = IDLE.with(|idle| idle.borrow_mut().pop()) {
            return Ok(Running::attach(w));
        }
        if let Some(r) = SPARE.with(|s| s.borrow_mut().take()) {
            if !failed(&r) {
                return Ok(r);
            }
            log::warn!("the spare worker failed: a job starts its own");
            r.stop();
        }
        Ok(Running::attach(web_sys::Worker::new(WORKER_SCRIPT)?))
    }

    impl<K: JobKind> Inner<K> {
        /// Takes a worker and posts the request at once, whether or not the worker has
        /// started: its script (`web/jobs-worker.js`) keeps what arrives before its wasm
        /// runs; a worker draining a dropped job runs it right after that one.
        pub fn start(request: K::Request, keep_worker: bool) -> Self {
            let request = K::encode_request(&request);
            let running = match spawn() {
                Ok(r) => match r.worker.post_message(&JsValue::from_str(&format!("{}\n{request}", K::NAME))) {
                    Ok(()) => Some(r),
                    Err(e) => {
                        log::warn!("the request was not posted ({e:?}): {} runs on the page", K::NAME);
                        r.stop();
                        None
                    }
                },
                Err(e) => {
                    log::warn!("no Web Worker ({e:?}): {} runs on the page", K::NAME);
                    None
                }
            };
            Self { request, running, ran_here: false, keep_worker, _kind: std::marker::PhantomData }
        }

        /// Runs the job on the page (the worker failed or is missing).
        fn here(&mut self, why: &str, partials: &mut Vec<K::Partial>) -> Option<K::Output> {
            if let Some(r) = self.running.take() {
                r.stop();
                log::warn!("{} runs on the page: {why}", K::NAME);
            }
            self.ran_here = true;
            match K::decode_request(&self.request) {
                Ok(req) => Some(super::run_here::<K>(&req, partials)),
                Err(e) => {
                    log::error!("{}: {e}", K::NAME);
                    None
                }
            }
        }

        pub fn poll(&mut self, progress: &mut Option<f64>, partials: &mut Vec<K::Partial>) -> Option<K::Output> {
            let Some(r) = self.running.as_mut() else {
                return self.here("no worker", partials);
            };
            let t0 = web_time::Instant::now();
            let mut decoded = false;
            loop {
                if decoded && super::over_budget(t0) {
                    // The rest waits for the next frame, which comes at once.
                    super::wake();
                    return None;
                }
                let msg = r.inbox.borrow_mut().pop_front()?;
                let (tag, body) = msg.split_once('\n').unwrap_or((msg.as_str(), ""));
                if r.skip > 0 && tag != "failed" {
                    // A dropped job's message; its answer ends it.
                    if matches!(tag, "ok" | "err") {
                        r.skip -= 1;
                    }
                    continue;
                }
                match tag {
                    "progress" => *progress = body.parse().ok(),
                    "partial" => {
                        super::push_partial::<K>(body, partials);
                        decoded = true;
                    }
                    "ok" => {
                        return match K::decode_output(body) {
                            Ok(out) => {
                                if let Some(r) = self.running.take() {
                                    r.park();
                                }
                                Some(out)
                            }
                            Err(e) => self.here(&e.to_string(), partials),
                        };
                    }
                    _ => return self.here(body, partials),
                }
            }
        }

        pub fn in_background(&self) -> bool {
            self.running.is_some()
        }

        pub fn in_background_done(&self) -> bool {
            !self.ran_here
        }
    }

    impl<K: JobKind> Drop for Inner<K> {
        fn drop(&mut self) {
            let Some(mut r) = self.running.take() else { return };
            if self.keep_worker {
                // Let it finish: its answer is skipped by the next job on this worker.
                r.skip += 1;
                if let Some(older) = DRAINING.with(|d| d.borrow_mut().replace(r)) {
                    older.stop();
                }
            } else {
                r.stop();
            }
        }
    }
}

#[cfg(all(test, not(target_arch = "wasm32")))]
mod tests {
    use super::*;
    use crate::jobs::Progress;

    /// Counts to n, reporting progress; stops early when cancelled, and then (or at n) sets
    /// its `returned` flag.
    struct Count;
    impl JobKind for Count {
        const NAME: &'static str = "count";
        type Request =
            (u64, std::sync::Arc<std::sync::atomic::AtomicU64>, std::sync::Arc<std::sync::atomic::AtomicBool>);
        type Output = u64;
        type Partial = u64;
        fn run(r: &Self::Request, p: &mut dyn Progress) -> u64 {
            let mut i = 0;
            while i < r.0 && !p.cancelled() {
                i += 1;
                r.1.store(i, std::sync::atomic::Ordering::Relaxed);
                if i % 1000 == 0 {
                    p.progress(i as f64 / r.0 as f64);
                    if i % 5000 == 0 {
                        p.partial(i.to_string());
                    }
                    std::thread::sleep(Duration::from_micros(50));
                }
            }
            r.2.store(true, std::sync::atomic::Ordering::Release);
            i
        }
        fn encode_request(r: &Self::Request) -> String {
            r.0.to_string()
        }
        fn decode_request(_: &str) -> Result<Self::Request, crate::jobs::DecodeError> {
            Err("not used".into())
        }
        fn encode_output(o: &u64) -> String {
            o.to_string()
        }
        fn decode_output(t: &str) -> Result<u64, crate::jobs::DecodeError> {
            t.parse().map_err(|_| "not a count".into())
        }
        fn decode_partial(t: &str) -> Result<u64, crate::jobs::DecodeError> {
            t.parse().map_err(|_| "not a count".into())
        }
    }

    /// A hang guard only: how long a job of these tests may take on a loaded machine.
    const HANG_GUARD: Duration = Duration::from_secs(120);

    /// Polls until the job is done; returns its output and the progress readings taken
    /// while it ran (how many there are depends on the machine's load: none if the job
    /// finished before the first poll).
    fn wait<K: JobKind>(job: &mut Job<K>) -> (K::Output, Vec<f64>) {
        let mut readings = Vec::new();
        let t0 = Instant::now();
        while t0.elapsed() < HANG_GUARD {
            match job.poll() {
                Poll::Done(out) => return (out, readings),
                Poll::Running(p) => readings.extend(p),
            }
            std::thread::sleep(Duration::from_millis(1));
        }
        panic!("the job did not finish");
    }

    #[test]
    fn a_job_runs_off_the_thread_reports_progress_and_gives_its_output_once() {
        let seen = std::sync::Arc::new(std::sync::atomic::AtomicU64::new(0));
        let returned = std::sync::Arc::new(std::sync::atomic::AtomicBool::new(false));
        let mut job = Job::<Count>::start((20_000, seen, returned));
        assert!(job.in_background());
        let (out, readings) = wait(&mut job);
        assert_eq!(out, 20_000);
        // Progress was reported and reached the end: the last fraction the job sent (taken
        // with its output) is 1; any reading while it ran was in (0, 1] and none went back.
        assert_eq!(job.progress, Some(1.0), "progress was reported up to the end");
        assert!(readings.iter().all(|&f| f > 0.0 && f <= 1.0), "readings {readings:?}");
        assert!(readings.windows(2).all(|w| w[0] <= w[1]), "readings rise: {readings:?}");
        assert_eq!(
            job.take_partials(),
            [5000, 10_000, 15_000, 20_000],
            "partial outputs, in order, all before the output"
        );
        assert!(job.take_partials().is_empty());
    }

    #[test]
    fn dropping_a_job_cancels_it() {
        use std::sync::atomic::Ordering;
        let seen = std::sync::Arc::new(std::sync::atomic::AtomicU64::new(0));
        let returned = std::sync::Arc::new(std::sync::atomic::AtomicBool::new(false));
        let job = Job::<Count>::start((u64::MAX, seen.clone(), returned.clone()));
        let t0 = Instant::now();
        while seen.load(Ordering::Relaxed) < 2000 {
            assert!(t0.elapsed() < HANG_GUARD, "the job did not start counting");
            std::thread::sleep(Duration::from_millis(1));
        }
        drop(job);
        // Counting to u64::MAX never ends: the job returns only because it was cancelled.
        // Waited for as a state (its return), not for a time.
        while !returned.load(Ordering::Acquire) {
            assert!(t0.elapsed() < HANG_GUARD, "the job did not stop after it was dropped");
            std::thread::sleep(Duration::from_millis(1));
        }
        let a = seen.load(Ordering::Relaxed);
        assert!(a < u64::MAX, "the job stopped counting at {a}");
        std::thread::sleep(Duration::from_millis(10));
        assert_eq!(seen.load(Ordering::Relaxed), a, "the job stopped counting");
    }
}
