//! Shared helpers of the integration tests, native and wasm32.
//!
//! Each test file starts with
//! `#[cfg(target_arch = "wasm32")] use wasm_bindgen_test::wasm_bindgen_test as test;`
//! so that one `#[test]` source runs natively and, compiled to wasm32, under Node.
#![allow(dead_code)]

pub mod outside;
/// LinuxCNC's `rs274` as the reference interpreter (native only: it runs a program).
#[cfg(not(target_arch = "wasm32"))]
pub mod rs274;

use interpolab::crease::CreaseJob;
use interpolab::scene::Scene;

/// A tiny deterministic generator (xorshift64*) so tests draw the same "random" parameters
/// on every platform without a dependency.
pub struct Rng(u64);

impl Rng {
    pub fn new(seed: u64) -> Self {
        Self(seed.wrapping_mul(0x9E37_79B9_7F4A_7C15) | 1)
    }
    /// Uniform in [0, 1).
    pub fn next_f64(&mut self) -> f64 {
        self.0 ^= self.0 >> 12;
        self.0 ^= self.0 << 25;
        self.0 ^= self.0 >> 27;
        let x = self.0.wrapping_mul(0x2545_F491_4F6C_DD1D);
        (x >> 11) as f64 / (1u64 << 53) as f64
    }
    /// Uniform in [a, b).
    pub fn range(&mut self, a: f64, b: f64) -> f64 {
        a + (b - a) * self.next_f64()
    }
}

/// Parses a scene that must be valid.
pub fn scene(json: &str) -> Scene {
    match Scene::from_json(json) {
        Ok(s) => s,
        Err(e) => panic!("scene should be valid: {e}"),
    }
}

/// Parses a scene and builds its job.
pub fn job(json: &str) -> CreaseJob {
    match CreaseJob::from_scene(&scene(json)) {
        Ok(j) => j,
        Err(e) => panic!("scene should build: {e}"),
    }
}
