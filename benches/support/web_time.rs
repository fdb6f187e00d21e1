//! `std::time::Instant` natively; `performance.now()` under Node (no std clock on wasm32),
//! and a line printed to standard output natively or to Node's console: the benchmarks that
//! run both natively and as wasm32 include this file.

/// Prints one line of a benchmark's report (wasm32 under Node: the console).
pub fn print(line: &str) {
    #[cfg(target_arch = "wasm32")]
    wasm_bindgen_test::console_log!("{line}");
    #[cfg(not(target_arch = "wasm32"))]
    println!("{line}");
}

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
