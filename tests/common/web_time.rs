//! `std::time::Instant` natively; `performance.now()` under Node (no std clock on wasm32):
//! the benchmarks that run both natively and as wasm32 include this file.

#[cfg(not(target_arch = "wasm32"))]
pub use std::time::Instant;

#[cfg(target_arch = "wasm32")]
pub struct Instant(f64);
#[cfg(target_arch = "wasm32")]
impl Instant {
    pub fn now() -> Self {
        Self(now_ms())
    }
    pub fn elapsed(&self) -> std::time::Duration {
        std::time::Duration::from_secs_f64((now_ms() - self.0) / 1000.0)
    }
}
#[cfg(target_arch = "wasm32")]
fn now_ms() -> f64 {
    #[wasm_bindgen::prelude::wasm_bindgen]
    extern "C" {
        #[wasm_bindgen(js_namespace = performance, js_name = now)]
        fn performance_now() -> f64;
    }
    performance_now()
}
