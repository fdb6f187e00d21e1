//! Number text: the shortest round-trip decimal ([`fmt_num`]) every output prints, and the
//! fixed-decimals form ([`fmt_fixed`]) of G-code words. Here, under the paper modules, so a
//! paper's error message or a G-code writer formats numbers without importing the run
//! report (which itself imports the crease).

/// Formats a number as the shortest decimal that parses back to the same value
/// (`4` for 4.0, `0.1` for 0.1, `2.5e-10` for tiny magnitudes); non-finite values print as an
/// empty field.
#[must_use]
pub fn fmt_num(x: f64) -> String {
    let mut s = String::new();
    push_num(&mut s, x);
    s
}

/// Appends [`fmt_num`]`(x)` to `out` without allocating (beyond `out` growing): the shortest
/// round-trip digits come from the `zmij` crate (Schubfach), laid out exactly as Rust's
/// `{}` (for 1e-5 ≤ |x| < 1e16) or `{:e}` (otherwise) would print them.
/// When x lies exactly halfway between two shortest candidates, Rust prints the upper one
/// and zmij the even one; `is_exact_tie` finds that case and takes the upper one too.
pub fn push_num(out: &mut String, x: f64) {
    if !x.is_finite() {
        return;
    }
    if x == 0.0 {
        out.push('0');
        return;
    }
    let mut buf = zmij::Buffer::new();
    if !tie_possible(x) {
        // zmij uses Rust's positional range (1e-5 ≤ |x| < 1e16) and exponent style; only its
        // `.0` on whole numbers differs.
        let text = buf.format_finite(x);
        out.push_str(text.strip_suffix(".0").unwrap_or(text));
        return;
    }
    let text = buf.format_finite(x.abs()).as_bytes();
    // zmij prints `d.ddd`, `0.000ddd`, `ddd0.0` or `d.ddde±x`; read it as the digit string
    // d1…dn (no leading or trailing zeros) and `point`, with |x| = 0.d1…dn × 10^point.
    let (mantissa, exp) = match text.iter().position(|&b| b == b'e' || b == b'E') {
        Some(at) => (&text[..at], parse_exponent(&text[at + 1..])),
        None => (text, 0),
    };
    let mut digits = [0u8; 32];
    let mut n = 0usize;
    let mut point = exp;
    let mut before_point = true;
    for &b in mantissa {
        match b {
            b'.' => before_point = false,
            b'0'..=b'9' => {
                if n == 0 && b == b'0' {
                    // A leading zero: before the point it carries nothing, after it it
                    // moves the point one place left.
                    if !before_point {
                        point -= 1;
                    }
                    continue;
                }
                if n < digits.len() {
                    digits[n] = b;
                    n += 1;
                }
                if before_point {
                    point += 1;
                }
            }
            _ => {}
        }
    }
    while n > 1 && digits[n - 1] == b'0' {
        n -= 1;
    }
    if n < digits.len() && (digits[n - 1] - b'0').is_multiple_of(2) && is_exact_tie(x, &digits[..n], point) {
        // zmij rounded a tie to the even digit; Rust's formatter rounds it up (an even
        // digit + 1 never carries).
        digits[n - 1] += 1;
    }
    let digits = &digits[..n];
    // Laid out on the stack, appended once.
    let mut line = Line { bytes: [0; 64], len: 0 };
    if x < 0.0 {
        line.push(b"-");
    }
    // Display range of Rust's positional `{}` form (not a tolerance): outside it, an exponent.
    if (1e-5..1e16).contains(&x.abs()) {
        // Rust's `{}`: positional, no exponent, no trailing `.0`.
        if point <= 0 {
            line.push(b"0.");
            (0..-point).for_each(|_| line.push(b"0"));
            line.push(digits);
        } else if (point as usize) < n {
            line.push(&digits[..point as usize]);
            line.push(b".");
            line.push(&digits[point as usize..]);
        } else {
            line.push(digits);
            (n..point as usize).for_each(|_| line.push(b"0"));
        }
    } else {
        // Rust's `{:e}`: `d.ddde-x` / `de16`, no `+` sign.
        line.push(&digits[..1]);
        if n > 1 {
            line.push(b".");
            line.push(&digits[1..]);
        }
        line.push(b"e");
        let e = point - 1;
        if e < 0 {
            line.push(b"-");
        }
        let a = e.unsigned_abs();
        for div in [100, 10, 1] {
            if a >= div || div == 1 {
                line.push(&[b'0' + ((a / div) % 10) as u8]);
            }
        }
    }
    out.push_str(std::str::from_utf8(&line.bytes[..line.len]).unwrap_or_default());
}

/// A short ASCII text on the stack (bytes beyond its capacity are dropped; a number needs
/// at most 25).
struct Line {
    bytes: [u8; 64],
    len: usize,
}

impl Line {
    fn push(&mut self, b: &[u8]) {
        let end = (self.len + b.len()).min(self.bytes.len());
        self.bytes[self.len..end].copy_from_slice(&b[..end - self.len]);
        self.len = end;
    }
}

/// zmij's decimal exponent (`-7`, `16`, `+16`).
fn parse_exponent(b: &[u8]) -> i32 {
    let (neg, digits) = match b.first() {
        Some(b'-') => (true, &b[1..]),
        Some(b'+') => (false, &b[1..]),
        _ => (false, b),
    };
    let v = digits.iter().take(4).fold(0i32, |acc, &d| acc * 10 + i32::from(d.wrapping_sub(b'0') % 10));
    if neg { -v } else { v }
}

/// |x| = m·2^e with m odd.
fn odd_significand(x: f64) -> (u64, i32) {
    let bits = x.abs().to_bits();
    let (frac, biased) = (bits & ((1u64 << 52) - 1), (bits >> 52) as i32);
    let (m, e) = if biased == 0 { (frac, -1074) } else { (frac | (1u64 << 52), biased - 1075) };
    if m == 0 {
        return (0, 0);
    }
    let tz = m.trailing_zeros();
    (m >> tz, e + tz as i32)
}

/// Whether x could lie halfway between two shortest candidates (see [`is_exact_tie`]):
/// that needs N = m·5^(−e) < 10^18 for some N, impossible once −e > 25 (5^26 > 10^18), which
/// excludes almost every number with a full 53-bit significand below 2^27.
fn tie_possible(x: f64) -> bool {
    odd_significand(x).1 >= -25
}

/// Whether |x| is exactly 0.d1…dn5 × 10^point, halfway between the n-digit decimals
/// 0.d1…dn and 0.d1…(dn+1) (× 10^point). Exact, in integers: with |x| = m·2^e (m odd) and
/// N = d1…dn5 (odd), N·10^s = m·2^e holds only if s = e and N·5^s = m (s ≥ 0) or
/// N = m·5^(−s) (s < 0).
fn is_exact_tie(x: f64, digits: &[u8], point: i32) -> bool {
    if digits.len() > 17 {
        return false;
    }
    let n_dec = digits.iter().fold(0u64, |acc, &b| acc * 10 + u64::from(b - b'0')) * 10 + 5;
    let s = point - digits.len() as i32 - 1;
    let (m, e) = odd_significand(x);
    if m == 0 || e != s {
        return false;
    }
    let pow5 = |k: u32| 5u128.checked_pow(k);
    if s >= 0 {
        pow5(s.unsigned_abs()).and_then(|p| p.checked_mul(u128::from(n_dec))) == Some(u128::from(m))
    } else {
        pow5(s.unsigned_abs()).and_then(|p| p.checked_mul(u128::from(m))) == Some(u128::from(n_dec))
    }
}

/// Formats a number rounded to `decimals` digits after the point, for G-code and other
/// fixed-resolution output: trailing zeros are dropped but one digit after the point is always
/// kept, so every value carries a decimal point (`10.0`, `-0.125`, `1.5`) — a controller
/// reading `X10` without a point may take it as 10 least input increments. A value that rounds
/// to zero prints as `0.0`, never `-0.0`. Rounding is that of the exact binary value (Rust's
/// `{:.N}`), so the same f64 always gives the same text. Non-finite values print as an empty
/// field.
#[must_use]
pub fn fmt_fixed(x: f64, decimals: usize) -> String {
    if !x.is_finite() {
        return String::new();
    }
    let mut s = format!("{x:.decimals$}");
    if s.contains('.') {
        while s.ends_with('0') {
            s.pop();
        }
        if s.ends_with('.') {
            s.push('0');
        }
    } else {
        s.push_str(".0");
    }
    if s.starts_with('-') && s[1..].bytes().all(|b| b == b'0' || b == b'.') {
        s.remove(0);
    }
    s
}
