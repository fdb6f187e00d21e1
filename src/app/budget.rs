//! The app's one frame-budget policy: how much wall time per frame the UI thread may spend
//! on work that is cut into slices (the crease periods, the 5-axis plan, the NURBS panel's
//! design path and real-time runs, the fillet paths, the simulation's moves).
//!
//! [`FRAME_BUDGET`] is a fixed 8 ms. At 60 Hz a frame lasts 16.7 ms; 8 ms of work leaves
//! about half of it to lay out and draw, so a fast machine keeps its frame rate while a
//! computation runs. The aim is that no frame takes longer than 50 ms: on a slow renderer
//! (a CPU rasteriser, where drawing alone may take tens of ms) the work stays at 8 ms and
//! the computation is spread over more frames instead of making each frame longer, as the
//! earlier schemes did (half the last frame, up to 60 ms; a fixed 25 ms).
//!
//! Only one panel works per frame besides the crease computation, so a frame spends at
//! most about twice the budget on work, plus the overshoot of one slice (one step of the
//! slowest kind; each work module documents its own). What does not fit in slices (writing
//! a G-code program) runs away from the UI thread as a job ([`super::jobs`]).

use web_time::Duration;

/// Wall time per frame the UI thread may spend on one computation's slices (8 ms; see the
/// module documentation for why).
pub const FRAME_BUDGET: Duration = Duration::from_millis(8);
