//! The example scenes shipped with the project (`examples/*.json`), compiled in so the app,
//! the tests and the benchmarks share them without a filesystem.

/// One example scene.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Preset {
    /// File stem in `examples/` (also its id in the app).
    pub id: &'static str,
    /// The scene JSON.
    pub json: &'static str,
}

/// Every example, in the order the app lists them (the paper's own setting first).
pub const PRESETS: &[Preset] = &[
    Preset { id: "floor-round-wall", json: include_str!("../../examples/floor-round-wall.json") },
    Preset { id: "sphere-plane", json: include_str!("../../examples/sphere-plane.json") },
    Preset { id: "crossing-cylinders", json: include_str!("../../examples/crossing-cylinders.json") },
    Preset { id: "torus-plane", json: include_str!("../../examples/torus-plane.json") },
    Preset { id: "bspline-floor-wall", json: include_str!("../../examples/bspline-floor-wall.json") },
    Preset { id: "rational-nurbs-vault", json: include_str!("../../examples/rational-nurbs-vault.json") },
];
