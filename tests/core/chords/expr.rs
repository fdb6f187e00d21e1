//! The expression language of typed curves (`chords::expr`): values, precedence, every
//! error with its column and what to write instead, and typed curves giving the same
//! equal-error chords as the built-in ones.
#![allow(clippy::unwrap_used, reason = "tests: an error should fail the test")]
#[cfg(target_arch = "wasm32")]
use wasm_bindgen_test::wasm_bindgen_test as test;

use interpolab::chords::equal_error_chords;
use interpolab::chords::expr::{CurveExprError, Expr, parametric_curve};
use interpolab::chords::planar::seed003_ellipse;
use interpolab::geom::Curve3;

fn value(text: &str, t: f64) -> f64 {
    match Expr::parse(text) {
        Ok(e) => e.eval(t),
        Err(e) => panic!("{text}: {e}"),
    }
}

fn error(text: &str) -> (usize, String) {
    match Expr::parse(text) {
        Ok(_) => panic!("{text} should not parse"),
        Err(e) => (e.column, e.message),
    }
}

fn close(a: f64, b: f64) -> bool {
    (a - b).abs() <= 1e-12 * (1.0 + b.abs())
}

#[test]
fn numbers_t_pi_and_functions_evaluate() {
    let t = 0.7;
    let cases: [(&str, f64); 16] = [
        ("42", 42.0),
        ("0.5", 0.5),
        (".25", 0.25),
        ("1e-3", 1e-3),
        ("2.5E+2", 250.0),
        ("t", t),
        ("pi", std::f64::consts::PI),
        ("sin(t)", t.sin()),
        ("cos(t)", t.cos()),
        ("tan(t)", t.tan()),
        ("exp(t)", t.exp()),
        ("ln(t)", t.ln()),
        ("sqrt(t)", t.sqrt()),
        ("abs(-t)", t),
        ("  60 * cos( t ) ", 60.0 * t.cos()),
        ("0.025*t^2", 0.025 * t * t),
    ];
    for (text, want) in cases {
        let got = value(text, t);
        assert!(close(got, want), "{text}: {got} ≠ {want}");
    }
}

#[test]
fn precedence_and_associativity_follow_the_usual_rules() {
    let cases: [(&str, f64); 12] = [
        ("1 + 2*3", 7.0),
        ("(1 + 2)*3", 9.0),
        ("8 / 4 / 2", 1.0),
        ("10 - 4 - 3", 3.0),
        ("2^3^2", 512.0),
        ("-2^2", -4.0),
        ("(-2)^2", 4.0),
        ("2^-1", 0.5),
        ("--3", 3.0),
        ("+3 - -3", 6.0),
        ("2*3^2", 18.0),
        ("-t^2 + 1", 1.0 - 9.0),
    ];
    for (text, want) in cases {
        let got = value(text, 3.0);
        assert!(close(got, want), "{text}: {got} ≠ {want}");
    }
    // Whole powers of negative bases are defined; fractional ones are not.
    assert!(close(value("t^3", -2.0), -8.0));
    assert!(value("t^0.5", -2.0).is_nan());
}

#[test]
fn unicode_minus_times_and_pi_are_accepted() {
    assert!(close(value("2×π − 1", 0.0), 2.0 * std::f64::consts::PI - 1.0));
    assert!(close(value("3·t", 2.0), 6.0));
}

#[test]
fn errors_name_the_column_and_what_to_write() {
    let cases: [(&str, usize, &str); 14] = [
        ("", 1, "empty"),
        ("2t", 2, "write 2*t"),
        ("t sin(t)", 3, "write * for a product"),
        ("(t+1)(t-1)", 6, "write * for a product"),
        ("1 +", 4, "ends too early"),
        ("sin(t", 6, "never closed"),
        ("(1 + 2", 7, "the \"(\" at column 1 is never closed"),
        ("1 + 2)", 6, "without a matching"),
        ("sinn(t)", 1, "unknown name \"sinn\""),
        ("x + 1", 1, "unknown name \"x\""),
        ("sin t", 4, "sin needs its argument in parentheses"),
        ("2 $ 3", 3, "\"$\" is not allowed"),
        ("1.2.3", 1, "is not a number"),
        ("* 2", 1, "expected a number, t or \"(\" before \"*\""),
    ];
    for (text, column, part) in cases {
        let (c, m) = error(text);
        assert_eq!(c, column, "{text}: {m}");
        assert!(m.contains(part), "{text}: {m:?} should contain {part:?}");
    }
    // The Display form starts with the column.
    assert_eq!(Expr::parse("2t").unwrap_err().to_string(), "column 2: a number followed by \"t\" — write 2*t");
}

#[test]
fn a_typed_curve_reports_bad_expressions_ranges_and_undefined_points() {
    match parametric_curve("t", "2t", 0.0, 1.0) {
        Err(e @ CurveExprError::Parse { which: "y", .. }) => {
            assert!(e.to_string().starts_with("y(t), column 2"), "{e}")
        }
        other => panic!("{other:?}"),
    }
    assert!(matches!(parametric_curve("t", "t", 1.0, 1.0), Err(CurveExprError::Range { .. })));
    assert!(matches!(parametric_curve("t", "t", 0.0, f64::NAN), Err(CurveExprError::Range { .. })));
    match parametric_curve("t", "sqrt(t)", -1.0, 1.0) {
        Err(e @ CurveExprError::Undefined { which: "y", t }) => {
            assert!(t < 0.0);
            assert!(e.to_string().contains("change the expression or the range"), "{e}");
        }
        other => panic!("{other:?}"),
    }
    assert!(matches!(parametric_curve("1/(t-0.5)", "t", 0.0, 1.0), Err(CurveExprError::Undefined { which: "x", .. })));
    assert!(matches!(parametric_curve("3", "4", 0.0, 1.0), Err(CurveExprError::Degenerate { .. })));
}

#[test]
fn a_typed_ellipse_gives_the_nodes_of_the_built_in_one() {
    let typed = parametric_curve("60*cos(t)", "30*sin(t)", 0.0, std::f64::consts::FRAC_PI_2).unwrap();
    let built_in = seed003_ellipse();
    for s in [0.0, 0.3, 1.2, std::f64::consts::FRAC_PI_2] {
        assert!((typed.point_at(s) - built_in.point_at(s)).length() < 1e-12);
    }
    for tol in [0.05, 0.01] {
        let a = equal_error_chords(&typed, tol).unwrap();
        let b = equal_error_chords(&built_in, tol).unwrap();
        // docs/chords.md: 17 nodes at 0.05 mm, 37 at 0.01 mm.
        assert_eq!(a.len(), b.len(), "d = {tol}");
        assert_eq!(a.len(), if tol > 0.02 { 17 } else { 37 });
    }
}
