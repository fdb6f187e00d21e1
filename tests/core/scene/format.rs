//! Scene files: every example parses and round-trips; every class of bad input is refused
//! with the key path of the problem and a fix.
#[cfg(target_arch = "wasm32")]
use wasm_bindgen_test::wasm_bindgen_test as test;

use crate::support;

use interpolab::crease::CreaseJob;
use interpolab::scene::{PRESETS, Scene, SceneError};

const BASE: &str = include_str!("../../../examples/floor-round-wall.json");

#[test]
fn every_example_round_trips_through_the_writer() {
    for (name, text) in PRESETS.iter().map(|p| (p.id, p.json)) {
        let scene = support::scene(text);
        let written = scene.to_json();
        let again = Scene::from_json(&written).unwrap_or_else(|e| panic!("{name}: written scene does not parse: {e}"));
        assert_eq!(scene, again, "{name}: pretty round trip");
        let compact = Scene::from_json(&scene.to_json_compact()).expect("compact parses");
        assert_eq!(scene, compact, "{name}: compact round trip");
        // Writing is deterministic and a fixed point after one round.
        assert_eq!(written, again.to_json(), "{name}: writer is a fixed point");
    }
}

#[test]
fn every_example_builds_a_job_with_the_papers_feed_per_period_formula() {
    for (name, text) in PRESETS.iter().map(|p| (p.id, p.json)) {
        let s = support::scene(text);
        let job = CreaseJob::from_scene(&s).unwrap_or_else(|e| panic!("{name}: {e}"));
        let f = s.motion.feed * s.motion.period / 60_000.0;
        assert!((job.feed_per_period_mm - f).abs() < 1e-15, "{name}");
    }
    // The paper's own settings: F = 1.5 m/min, Ts = 4 ms → f = 0.1 mm.
    let s = support::scene(BASE);
    assert_eq!((s.motion.feed, s.motion.period), (1500.0, 4.0));
    assert!((s.feed_per_period_mm() - 0.1).abs() < 1e-15);
}

/// Applies a JSON edit to the base scene and returns the error it must produce.
fn error_after(edit: impl FnOnce(&mut serde_json::Value)) -> SceneError {
    let mut v: serde_json::Value = serde_json::from_str(BASE).expect("base is JSON");
    edit(&mut v);
    match Scene::from_json(&v.to_string()) {
        Ok(_) => panic!("edited scene should be refused: {v}"),
        Err(e) => e,
    }
}

fn assert_error(e: &SceneError, path: &str, problem_has: &str) {
    assert_eq!(e.path, path, "wrong key path in: {e}");
    assert!(e.problem.contains(problem_has), "problem should mention {problem_has:?}: {e}");
    assert!(!e.fix.is_empty(), "every error says what to change: {e}");
}

#[test]
fn unknown_keys_are_refused_with_a_suggestion() {
    let e = error_after(|v| {
        v["tool"]["radus"] = 3.0.into();
    });
    assert_error(&e, "tool.radus", "unknown key");
    assert!(e.fix.contains("did you mean \"radius\""), "{e}");
    let e = error_after(|v| {
        v["surfaces"][1]["colour"] = "red".into();
    });
    assert_error(&e, "surfaces[1].colour", "unknown key");
    let e = error_after(|v| {
        v["extra"] = 1.into();
    });
    assert_error(&e, "extra", "unknown key");
}

#[test]
fn missing_keys_are_named() {
    let e = error_after(|v| {
        v["motion"].as_object_mut().expect("object").remove("period");
    });
    assert_error(&e, "motion.period", "missing");
    let e = error_after(|v| {
        v["surfaces"][1].as_object_mut().expect("object").remove("normal");
    });
    assert_error(&e, "surfaces[1].normal", "missing");
    let e = error_after(|v| {
        v.as_object_mut().expect("object").remove("path");
    });
    assert_error(&e, "path", "missing");
}

#[test]
fn wrong_types_are_named() {
    let e = error_after(|v| v["tool"]["radius"] = "5".into());
    assert_error(&e, "tool.radius", "string");
    let e = error_after(|v| v["path"]["start"] = serde_json::json!([1, 2]));
    assert_error(&e, "path.start", "3 numbers");
    let e = error_after(|v| v["surfaces"][0]["origin"][2] = true.into());
    assert_error(&e, "surfaces[0].origin[2]", "boolean");
    let e = error_after(|v| v["surfaces"] = serde_json::json!({}));
    assert_error(&e, "surfaces", "array");
    let e = error_after(|v| v["surfaces"][1]["type"] = "cone".into());
    assert_error(&e, "surfaces[1].type", "cone");
    let e = error_after(|v| v["format"] = "interpolab-scene/2".into());
    assert_error(&e, "format", "interpolab-scene/2");
}

#[test]
fn non_finite_numbers_are_refused() {
    // JSON has no NaN or infinity; a literal that overflows f64 is the way one arrives.
    let text = BASE.replace("\"radius\": 5.0", "\"radius\": 1e999");
    let e = Scene::from_json(&text).expect_err("overflowing number");
    assert!(e.to_string().contains("line"), "syntax-level errors give the line: {e}");
}

#[test]
fn non_positive_values_are_refused() {
    for (path, edit) in [
        ("surfaces[1].radius", serde_json::json!(-3.0)),
        ("tool.radius", serde_json::json!(0.0)),
        ("motion.feed", serde_json::json!(0.0)),
        ("motion.period", serde_json::json!(-4.0)),
        ("tolerance.t1", serde_json::json!(0.0)),
        ("tolerance.t2", serde_json::json!(-0.01)),
    ] {
        let keys: Vec<String> = path.replace(']', "").split(['.', '[']).map(str::to_owned).collect();
        let e = error_after(|v| {
            let mut node = v;
            for k in &keys {
                node = match k.parse::<usize>() {
                    Ok(i) => &mut node[i],
                    Err(_) => &mut node[k.as_str()],
                };
            }
            *node = edit.clone();
        });
        assert_error(&e, path, "> 0");
    }
    let e = error_after(|v| v["tool"]["allowance"] = (-6.0).into());
    assert_error(&e, "tool.allowance", "not positive");
}

#[test]
fn share_must_lie_in_zero_one() {
    for bad in [0.0, -0.5, 1.5] {
        let e = error_after(|v| v["tolerance"]["share"] = bad.into());
        assert_error(&e, "tolerance.share", "(0, 1]");
    }
    let ok: serde_json::Value = {
        let mut v: serde_json::Value = serde_json::from_str(BASE).expect("json");
        v["tolerance"]["share"] = 1.0.into();
        v
    };
    assert!(Scene::from_json(&ok.to_string()).is_ok(), "share = 1 is allowed");
}

#[test]
fn degenerate_directions_are_refused() {
    let e = error_after(|v| v["surfaces"][1]["axis"] = serde_json::json!([0, 0, 0]));
    assert_error(&e, "surfaces[1].axis", "zero length");
    let e = error_after(|v| v["surfaces"][0]["u_axis"] = serde_json::json!([1, 0, 0.5]));
    assert_error(&e, "surfaces[0].u_axis", "perpendicular");
    let e = error_after(|v| v["surfaces"][1]["ref_dir"] = serde_json::json!([0, 0, 1]));
    assert_error(&e, "surfaces[1].ref_dir", "perpendicular");
    let e = error_after(|v| v["path"]["direction"] = serde_json::json!([0, 0, 0]));
    assert_error(&e, "path.direction", "zero length");
    let e = error_after(|v| v["surfaces"][1]["domain"]["u"] = serde_json::json!([0, 400]));
    assert_error(&e, "surfaces[1].domain.u", "more than one turn");
    let e = error_after(|v| v["surfaces"][0]["domain"]["v"] = serde_json::json!([10, -10]));
    assert_error(&e, "surfaces[0].domain.v", "empty or reversed");
}

const NURBS: &str = include_str!("../../../examples/rational-nurbs-vault.json");

fn nurbs_error(edit: impl FnOnce(&mut serde_json::Value)) -> SceneError {
    let mut v: serde_json::Value = serde_json::from_str(NURBS).expect("json");
    edit(&mut v);
    Scene::from_json(&v.to_string()).expect_err("edited NURBS should be refused")
}

#[test]
fn bad_knot_vectors_and_weights_are_refused() {
    let e = nurbs_error(|v| v["surfaces"][0]["knots_u"] = serde_json::json!([0, 0, 0, 0.5, 1, 1, 1]));
    assert_error(&e, "surfaces[0].knots_u", "knots given");
    let e = nurbs_error(|v| v["surfaces"][0]["knots_u"] = serde_json::json!([0, 0, 0, 0.7, 0.5, 1, 1, 1]));
    assert_error(&e, "surfaces[0].knots_u", "non-decreasing");
    let e = nurbs_error(|v| v["surfaces"][0]["knots_v"] = serde_json::json!([0, 0.1, 1, 1]));
    assert_error(&e, "surfaces[0].knots_v", "clamped");
    let e = nurbs_error(|v| v["surfaces"][0]["weights"][1][0] = 0.0.into());
    assert_error(&e, "surfaces[0].weights", "weights must be > 0");
    let e = nurbs_error(|v| v["surfaces"][0]["weights"][2][1] = (-1.0).into());
    assert_error(&e, "surfaces[0].weights", "weights must be > 0");
    let e = nurbs_error(|v| {
        v["surfaces"][0]["points"][3].as_array_mut().expect("row").pop();
    });
    assert_error(&e, "surfaces[0].points", "rectangular");
    let e = nurbs_error(|v| v["surfaces"][0]["degree"] = serde_json::json!([12, 1]));
    assert_error(&e, "surfaces[0].degree[0]", "not supported");
}

#[test]
fn torus_must_not_cross_its_axis() {
    let mut v: serde_json::Value =
        serde_json::from_str(include_str!("../../../examples/torus-plane.json")).expect("json");
    v["surfaces"][0]["major_radius"] = 10.0.into();
    let e = Scene::from_json(&v.to_string()).expect_err("spindle torus");
    assert_error(&e, "surfaces[0].major_radius", "not larger than minor_radius");
}

#[test]
fn syntax_errors_name_line_and_column() {
    let e = Scene::from_json("{ \"format\": \"interpolab-scene/1\", ").expect_err("truncated");
    assert_eq!(e.path, "(file)");
    assert!(e.problem.contains("line 1"), "{e}");
}

#[test]
fn base64url_round_trips_every_length_and_byte() {
    use interpolab::scene::link::{base64url_decode, base64url_encode};
    let bytes: Vec<u8> = (0..=255u8).chain((0..=255u8).rev()).collect();
    for n in 0..bytes.len() {
        let enc = base64url_encode(&bytes[..n]);
        assert_eq!(enc.len(), (n * 4).div_ceil(3), "no padding");
        assert!(enc.bytes().all(|c| c.is_ascii_alphanumeric() || c == b'-' || c == b'_'), "URL-safe: {enc}");
        assert_eq!(base64url_decode(&enc).as_deref(), Some(&bytes[..n]), "length {n}");
    }
    // RFC 4648 test vector, and padding / standard alphabet accepted on input.
    assert_eq!(base64url_encode(b"foobar"), "Zm9vYmFy");
    assert_eq!(base64url_decode("Zm9vYg==").as_deref(), Some(&b"foob"[..]));
    assert_eq!(base64url_decode("-_+/"), base64url_decode("-_-_"));
    assert_eq!(base64url_decode("abc!"), None);
    assert_eq!(base64url_decode("abcde"), None, "a lone sixth bit group is impossible");
}

#[test]
fn share_links_carry_every_example_exactly() {
    for p in interpolab::scene::PRESETS {
        let scene = support::scene(p.json);
        let frag = scene.to_link_fragment();
        assert!(frag.starts_with("scene="));
        let back = Scene::from_link_fragment(&format!("#{frag}")).expect("decodes").expect("has a scene");
        assert_eq!(back, scene, "{}", p.id);
    }
    assert_eq!(Scene::from_link_fragment("#view=top").expect("no scene"), None);
    assert_eq!(Scene::from_link_fragment("").expect("no scene"), None);
}

#[test]
fn broken_share_links_are_refused_with_a_reason() {
    let scene = support::scene(BASE);
    let frag = scene.to_link_fragment();
    let cut = &frag[..frag.len() / 2];
    let e = Scene::from_link_fragment(cut).expect_err("truncated link");
    assert!(e.path == "(link)" || e.path == "(file)", "{e}");
    let e = Scene::from_link_fragment("scene=%%%").expect_err("not base64");
    assert_eq!(e.path, "(link)");
    // A valid encoding of an invalid scene names the scene's key.
    let mut bad = scene.clone();
    bad.tool.radius = -1.0;
    let e = Scene::from_link_fragment(&bad.to_link_fragment()).expect_err("invalid scene");
    assert_eq!(e.path, "tool.radius");
}
