//! The core stays free of GUI, GPU and browser dependencies (so it builds for wasm32 and
//! natively with `--no-default-features`, and the app stays a thin layer over it): no file
//! outside `src/app`, `src/render`, `src/cli`, `src/main.rs` and the browser worker's entry
//! `src/worker_main.rs` may name them, and none may
//! use a clock or threads (which do not exist on wasm32).
#![cfg(not(target_arch = "wasm32"))]

use std::path::{Path, PathBuf};

fn rust_files(dir: &Path, out: &mut Vec<PathBuf>) {
    for entry in std::fs::read_dir(dir).expect("readable source tree") {
        let path = entry.expect("entry").path();
        if path.is_dir() {
            rust_files(&path, out);
        } else if path.extension().is_some_and(|e| e == "rs") {
            out.push(path);
        }
    }
}

#[test]
fn core_sources_do_not_use_gui_gpu_browser_clock_or_threads() {
    let src = Path::new(env!("CARGO_MANIFEST_DIR")).join("src");
    let mut files = Vec::new();
    rust_files(&src, &mut files);
    let outside_core = ["app", "render", "cli"];
    let forbidden = [
        "egui",
        "eframe",
        "wgpu",
        "web_sys",
        "js_sys",
        "wasm_bindgen",
        "std::time::Instant",
        "SystemTime",
        "std::thread",
        "std::fs",
        "web_time",
    ];
    let mut core_files = 0;
    for f in &files {
        let rel = f.strip_prefix(&src).expect("under src");
        let first = rel.components().next().and_then(|c| c.as_os_str().to_str()).unwrap_or("");
        if outside_core.contains(&first.trim_end_matches(".rs"))
            || rel == Path::new("main.rs")
            || rel == Path::new("worker_main.rs")
        {
            continue;
        }
        core_files += 1;
        let text = std::fs::read_to_string(f).expect("readable");
        for (n, line) in text.lines().enumerate() {
            let code = line.split("//").next().unwrap_or("");
            for word in forbidden {
                assert!(!code.contains(word), "{}:{}: the core must not use `{word}`: {line}", rel.display(), n + 1);
            }
        }
    }
    assert!(core_files > 20, "found only {core_files} core files; is the source tree where the test expects it?");
}

// No program writer builds a comment itself (user text enters programs one way).
#[path = "boundary/comments.rs"]
mod comments;
