//! Jobs built from a scene: the assembly step from the file's description to a paper's
//! input in internal units. It lives here, above the paper modules, so that no paper
//! imports `scene` (the crease module used to, which closed a cycle scene → fiveaxis →
//! crease → scene).

use glam::DVec3;

use super::{Scene, SceneError, build_surface};
use crate::crease::CreaseJob;
use crate::numerics::units;

impl CreaseJob {
    /// Validates the scene and converts it to internal units.
    ///
    /// # Errors
    /// The scene's first problem, with its key path.
    pub fn from_scene(scene: &Scene) -> Result<Self, SceneError> {
        scene.validate()?;
        let s0 = build_surface(&scene.surfaces[0], "surfaces[0]")?;
        let s1 = build_surface(&scene.surfaces[1], "surfaces[1]")?;
        let v = DVec3::from_array;
        Ok(Self {
            surfaces: [s0, s1],
            ball_radius_mm: scene.tool.radius,
            r_eff_mm: scene.effective_radius_mm(),
            feed_mm_per_s: units::mm_per_s_from_mm_per_min(scene.motion.feed),
            period_s: units::s_from_ms(scene.motion.period),
            feed_per_period_mm: scene.feed_per_period_mm(),
            tol_mm: [scene.tolerance.t1, scene.tolerance.t2],
            share: scene.tolerance.share,
            start: v(scene.path.start),
            end: scene.path.end.map(v),
            direction: scene.path.direction.map(v),
            max_steps: scene.path.max_steps,
        })
    }
}
