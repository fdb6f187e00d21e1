//! The CSV/JSON number format is a contract: `report::fmt_num` (now laid out from the `zmij`
//! crate's shortest digits, without allocation) must print exactly what Rust's own shortest
//! round-trip formatting printed before — `{}` for 1e-5 ≤ |x| < 1e16, `{:e}` otherwise — and
//! every printed number must read back to the same f64.
#[cfg(target_arch = "wasm32")]
use wasm_bindgen_test::wasm_bindgen_test as test;

use crate::support::Rng;
use interpolab::report::{fmt_num, push_num};

/// The formatter as it was, on `core::fmt` (the reference).
fn reference(x: f64) -> String {
    if !x.is_finite() {
        return String::new();
    }
    if x == 0.0 {
        return "0".to_owned();
    }
    let a = x.abs();
    if !(1e-5..1e16).contains(&a) { format!("{x:e}") } else { format!("{x}") }
}

fn check(x: f64) {
    let got = fmt_num(x);
    assert_eq!(got, reference(x), "bits {:#018x}", x.to_bits());
    if x.is_finite() {
        let back: f64 = got.parse().expect("a printed number parses");
        assert!(back.to_bits() == x.to_bits() || (x == 0.0 && back == 0.0), "{got} reads back as {back}, not {x:e}");
    } else {
        assert!(got.is_empty());
    }
}

#[test]
fn special_and_boundary_values() {
    let mut xs = vec![
        0.0,
        -0.0,
        1.0,
        -1.0,
        0.1,
        0.2 + 0.1,
        4.0,
        1e-5,
        1e16,
        1e15,
        123456789012345680.0,
        2.5e-10,
        f64::MAX,
        f64::MIN,
        f64::MIN_POSITIVE,
        f64::EPSILON,
        5e-324,
        f64::NAN,
        f64::INFINITY,
        f64::NEG_INFINITY,
        100.0,
        1234.5,
        0.000123,
        1e16f64.next_down(),
        1.0 + 2f64.powi(-17),
        f64::from_bits(0x4314_7cc8_2d04_32dd), // 1441674681191607.25
        f64::from_bits(0x42ea_df79_0edb_2984), // 236376888367436.125
    ];
    for e in -320..=308 {
        let p = 10f64.powi(e);
        xs.extend([p, -p, p.next_up(), p.next_down(), 1.5 * p, 7.0 * p]);
    }
    for x in xs {
        check(x);
    }
}

#[test]
fn random_values_match_the_reference() {
    let mut rng = Rng::new(12);
    for _ in 0..200_000 {
        // Any finite bit pattern…
        let bits = (rng.next_f64() * (1u64 << 53) as f64) as u64 ^ ((rng.next_f64() * 2048.0) as u64) << 52;
        let x = f64::from_bits(bits);
        if x.is_finite() {
            check(x);
        }
        // …and values like a run's coordinates, parameters and errors.
        let y = rng.range(-1.0, 1.0) * 10f64.powf(rng.range(-12.0, 5.0));
        check(y);
        check((y * 1e4).round() / 1e4);
        // …and dyadic numbers with few significant bits, whose exact decimal expansion is
        // short enough to fall halfway between two shortest candidates (a tie: Rust prints
        // the upper one, e.g. 236376888367436.13 for …436.125).
        let bits_kept = rng.range(20.0, 54.0) as u32;
        let m = ((rng.next_f64() * (1u64 << 53) as f64) as u64 | (1 << 52)) >> (53 - bits_kept) << (53 - bits_kept);
        let z = m as f64 * 2f64.powi(rng.range(-80.0, 20.0) as i32);
        check(z);
        check(-z);
    }
}

#[test]
fn push_num_appends_to_what_is_there() {
    let mut s = String::from("x=");
    push_num(&mut s, -2.5e-10);
    s.push(',');
    push_num(&mut s, f64::NAN);
    s.push(',');
    push_num(&mut s, 0.1);
    assert_eq!(s, "x=-2.5e-10,,0.1");
}
