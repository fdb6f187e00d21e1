//! A small expression language for curves typed by hand: `x(t)`, `y(t)` of a plane
//! parametric curve (seed 003 in the app: "any parametric curve").
//!
//! Grammar (usual precedence, `^` binds tighter than unary minus and is right-associative,
//! so `-t^2 = -(t^2)` and `2^3^2 = 2^9`):
//!
//! ```text
//! expr    = term { ("+" | "-") term }
//! term    = unary { ("*" | "/") unary }
//! unary   = ("-" | "+") unary | power
//! power   = atom [ "^" unary ]
//! atom    = number | "t" | "pi" | name "(" expr ")" | "(" expr ")"
//! number  = digits [ "." digits ] [ ("e" | "E") [ "+" | "-" ] digits ]   (also ".5")
//! name    = sin | cos | tan | exp | ln | sqrt | abs
//! ```
//!
//! Angles are in radians. Errors give the 1-based column (in characters) and say what to
//! write instead, e.g. `column 2: a number followed by "t" — write 2*t`.

use glam::DVec2;
use thiserror::Error;

use super::planar::FnCurve;

/// A parse error: where (1-based column, in characters) and what to change.
#[derive(Clone, Debug, Error, PartialEq, Eq)]
#[error("column {column}: {message}")]
pub struct ExprError {
    /// 1-based column of the offending character (one past the end for a missing part).
    pub column: usize,
    /// What is wrong and what to write instead.
    pub message: String,
}

/// The functions an expression may call.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum Func {
    Sin,
    Cos,
    Tan,
    Exp,
    Ln,
    Sqrt,
    Abs,
}

impl Func {
    const ALL: [(&'static str, Self); 7] = [
        ("sin", Self::Sin),
        ("cos", Self::Cos),
        ("tan", Self::Tan),
        ("exp", Self::Exp),
        ("ln", Self::Ln),
        ("sqrt", Self::Sqrt),
        ("abs", Self::Abs),
    ];

    fn apply(self, x: f64) -> f64 {
        match self {
            Self::Sin => x.sin(),
            Self::Cos => x.cos(),
            Self::Tan => x.tan(),
            Self::Exp => x.exp(),
            Self::Ln => x.ln(),
            Self::Sqrt => x.sqrt(),
            Self::Abs => x.abs(),
        }
    }
}

#[derive(Clone, Debug, PartialEq)]
enum Node {
    Num(f64),
    T,
    Neg(Box<Node>),
    Add(Box<Node>, Box<Node>),
    Sub(Box<Node>, Box<Node>),
    Mul(Box<Node>, Box<Node>),
    Div(Box<Node>, Box<Node>),
    Pow(Box<Node>, Box<Node>),
    Call(Func, Box<Node>),
}

impl Node {
    fn eval(&self, t: f64) -> f64 {
        match self {
            Self::Num(v) => *v,
            Self::T => t,
            Self::Neg(a) => -a.eval(t),
            Self::Add(a, b) => a.eval(t) + b.eval(t),
            Self::Sub(a, b) => a.eval(t) - b.eval(t),
            Self::Mul(a, b) => a.eval(t) * b.eval(t),
            Self::Div(a, b) => a.eval(t) / b.eval(t),
            Self::Pow(a, b) => {
                let (x, y) = (a.eval(t), b.eval(t));
                // Whole exponents by repeated multiplication: exact for t^2, t^3 and
                // defined for negative bases.
                if y.fract() == 0.0 && y.abs() <= 64.0 { x.powi(y as i32) } else { x.powf(y) }
            }
            Self::Call(f, a) => f.apply(a.eval(t)),
        }
    }
}

/// A parsed expression in the variable `t`.
#[derive(Clone, Debug, PartialEq)]
pub struct Expr {
    root: Node,
    text: String,
}

impl Expr {
    /// Parses `text` (module docs for the grammar).
    ///
    /// ```
    /// # use interpolab::chords::expr::Expr;
    /// let e = Expr::parse("60*cos(t) + 2^3").unwrap();
    /// assert_eq!(e.eval(0.0), 68.0);
    /// assert_eq!(Expr::parse("2t").unwrap_err().to_string(), "column 2: a number followed by \"t\" — write 2*t");
    /// ```
    ///
    /// # Errors
    /// [`ExprError`] with the column and what to write instead.
    pub fn parse(text: &str) -> Result<Self, ExprError> {
        let tokens = lex(text)?;
        let mut p = Parser { tokens: &tokens, pos: 0, end_column: text.chars().count() + 1 };
        if tokens.is_empty() {
            return Err(ExprError { column: 1, message: "the expression is empty; write e.g. 0.025*t^2".into() });
        }
        let root = p.expr()?;
        if let Some(tok) = p.peek() {
            let message = match tok.kind {
                Tok::Close => "a \")\" without a matching \"(\"; remove it or add the \"(\"".to_owned(),
                _ => format!("expected an operator (+ - * / ^) before {}; write * for a product", describe(&tok.kind)),
            };
            return Err(ExprError { column: tok.column, message });
        }
        Ok(Self { root, text: text.to_owned() })
    }

    /// The value at `t` (NaN or ±∞ where the expression is undefined, e.g. `ln(0)`).
    #[must_use]
    pub fn eval(&self, t: f64) -> f64 {
        self.root.eval(t)
    }

    /// The text it was parsed from.
    #[must_use]
    pub fn text(&self) -> &str {
        &self.text
    }
}

/// Why a typed parametric curve cannot be used.
#[derive(Clone, Debug, Error, PartialEq)]
pub enum CurveExprError {
    /// An expression does not parse.
    #[error("{which}(t), {source}")]
    Parse {
        /// `x` or `y`.
        which: &'static str,
        /// The parse error.
        source: ExprError,
    },
    /// The parameter range is empty or not finite.
    #[error("the range of t must have t0 < t1 (both finite), got [{t0}, {t1}]; change t0 or t1")]
    Range {
        /// Start.
        t0: f64,
        /// End.
        t1: f64,
    },
    /// The curve is undefined somewhere on the range.
    #[error(
        "{which}(t) is not defined at t = {t:.6} (a division by zero, sqrt or ln of a negative number, or an overflow); change the expression or the range of t"
    )]
    Undefined {
        /// `x` or `y`.
        which: &'static str,
        /// Where.
        t: f64,
    },
    /// The curve does not move.
    #[error("the curve is a single point over [{t0}, {t1}]; make x(t) or y(t) depend on t")]
    Degenerate {
        /// Start.
        t0: f64,
        /// End.
        t1: f64,
    },
}

/// The plane curve (x(t), y(t)) for t in `[t0, t1]` from two typed expressions, checked at
/// 1025 equally spaced parameters for being defined and not a single point.
///
/// # Errors
/// [`CurveExprError`]: an expression that does not parse (with its column), an empty range,
/// a curve undefined somewhere on the range or one that does not move.
pub fn parametric_curve(x: &str, y: &str, t0: f64, t1: f64) -> Result<FnCurve, CurveExprError> {
    let ex = Expr::parse(x).map_err(|source| CurveExprError::Parse { which: "x", source })?;
    let ey = Expr::parse(y).map_err(|source| CurveExprError::Parse { which: "y", source })?;
    if !(t0.is_finite() && t1.is_finite() && t1 > t0) {
        return Err(CurveExprError::Range { t0, t1 });
    }
    let n = 1024;
    let mut extent = 0.0f64;
    let first = DVec2::new(ex.eval(t0), ey.eval(t0));
    for i in 0..=n {
        let t = if i == n { t1 } else { t0 + (t1 - t0) * f64::from(i) / f64::from(n) };
        for (which, e) in [("x", &ex), ("y", &ey)] {
            if !e.eval(t).is_finite() {
                return Err(CurveExprError::Undefined { which, t });
            }
        }
        extent = extent.max((DVec2::new(ex.eval(t), ey.eval(t)) - first).length());
    }
    if extent <= crate::numerics::tolerance::MIN_CURVE_EXTENT_MM {
        return Err(CurveExprError::Degenerate { t0, t1 });
    }
    Ok(FnCurve::new(move |t| DVec2::new(ex.eval(t), ey.eval(t)), (t0, t1)))
}

#[derive(Clone, Debug, PartialEq)]
enum Tok {
    Num(f64),
    Name(String),
    Op(char),
    Open,
    Close,
}

#[derive(Clone, Debug, PartialEq)]
struct Token {
    kind: Tok,
    column: usize,
}

fn describe(t: &Tok) -> String {
    match t {
        Tok::Num(v) => format!("the number {v}"),
        Tok::Name(n) => format!("\"{n}\""),
        Tok::Op(c) => format!("\"{c}\""),
        Tok::Open => "\"(\"".into(),
        Tok::Close => "\")\"".into(),
    }
}

fn lex(text: &str) -> Result<Vec<Token>, ExprError> {
    let chars: Vec<char> = text.chars().collect();
    let mut out = Vec::new();
    let mut i = 0;
    while i < chars.len() {
        let c = chars[i];
        let column = i + 1;
        if c.is_whitespace() {
            i += 1;
            continue;
        }
        if c.is_ascii_digit() || c == '.' {
            let start = i;
            while i < chars.len() && (chars[i].is_ascii_digit() || chars[i] == '.') {
                i += 1;
            }
            // An exponent: e or E, an optional sign, then digits (otherwise "e" is a name).
            if i < chars.len() && (chars[i] == 'e' || chars[i] == 'E') {
                let mut j = i + 1;
                if j < chars.len() && (chars[j] == '+' || chars[j] == '-') {
                    j += 1;
                }
                if j < chars.len() && chars[j].is_ascii_digit() {
                    while j < chars.len() && chars[j].is_ascii_digit() {
                        j += 1;
                    }
                    i = j;
                }
            }
            let s: String = chars[start..i].iter().collect();
            let v: f64 = s.parse().map_err(|_| ExprError {
                column,
                message: format!("\"{s}\" is not a number; write e.g. 0.5 or 1e-3"),
            })?;
            out.push(Token { kind: Tok::Num(v), column });
            continue;
        }
        if c.is_alphabetic() || c == '_' {
            let start = i;
            while i < chars.len() && (chars[i].is_alphanumeric() || chars[i] == '_') {
                i += 1;
            }
            out.push(Token { kind: Tok::Name(chars[start..i].iter().collect()), column });
            continue;
        }
        let kind = match c {
            '+' | '-' | '*' | '/' | '^' => Tok::Op(c),
            '−' => Tok::Op('-'),
            '×' | '·' => Tok::Op('*'),
            '(' => Tok::Open,
            ')' => Tok::Close,
            _ => {
                return Err(ExprError {
                    column,
                    message: format!(
                        "\"{c}\" is not allowed; use numbers, t, pi, + - * / ^, parentheses and sin cos tan exp ln sqrt abs"
                    ),
                });
            }
        };
        out.push(Token { kind, column });
        i += 1;
    }
    Ok(out)
}

struct Parser<'a> {
    tokens: &'a [Token],
    pos: usize,
    end_column: usize,
}

impl Parser<'_> {
    fn peek(&self) -> Option<&Token> {
        self.tokens.get(self.pos)
    }

    fn at_op(&self, ops: &[char]) -> Option<char> {
        match self.peek() {
            Some(Token { kind: Tok::Op(c), .. }) if ops.contains(c) => Some(*c),
            _ => None,
        }
    }

    fn expr(&mut self) -> Result<Node, ExprError> {
        self.left_assoc(['+', '-'], Self::term, |first, l, r| if first { Node::Add(l, r) } else { Node::Sub(l, r) })
    }

    fn term(&mut self) -> Result<Node, ExprError> {
        self.left_assoc(['*', '/'], Self::unary, |first, l, r| if first { Node::Mul(l, r) } else { Node::Div(l, r) })
    }

    /// One level of left-associative binary operators `ops` over operands read by `operand`;
    /// `node(is_first_op, left, right)` builds the node.
    fn left_assoc(
        &mut self,
        ops: [char; 2],
        operand: fn(&mut Self) -> Result<Node, ExprError>,
        node: fn(bool, Box<Node>, Box<Node>) -> Node,
    ) -> Result<Node, ExprError> {
        let mut left = operand(self)?;
        while let Some(op) = self.at_op(&ops) {
            self.pos += 1;
            let right = operand(self)?;
            left = node(op == ops[0], left.into(), right.into());
        }
        Ok(left)
    }

    fn unary(&mut self) -> Result<Node, ExprError> {
        match self.at_op(&['-', '+']) {
            Some(op) => {
                self.pos += 1;
                let inner = self.unary()?;
                Ok(if op == '-' { Node::Neg(inner.into()) } else { inner })
            }
            None => self.power(),
        }
    }

    fn power(&mut self) -> Result<Node, ExprError> {
        let base = self.atom()?;
        if self.at_op(&['^']).is_some() {
            self.pos += 1;
            let exponent = self.unary()?;
            return Ok(Node::Pow(base.into(), exponent.into()));
        }
        Ok(base)
    }

    fn missing(&self, what: &str) -> ExprError {
        ExprError { column: self.end_column, message: format!("the expression ends too early; {what}") }
    }

    fn atom(&mut self) -> Result<Node, ExprError> {
        let Some(tok) = self.peek().cloned() else {
            return Err(self.missing("add a number, t or a parenthesis"));
        };
        self.pos += 1;
        let node = match &tok.kind {
            Tok::Num(v) => Node::Num(*v),
            Tok::Open => {
                let inner = self.expr()?;
                self.close(tok.column)?;
                inner
            }
            Tok::Name(name) => self.name(name, tok.column)?,
            Tok::Close => {
                return Err(ExprError {
                    column: tok.column,
                    message: "expected a number, t or \"(\" before \")\"".into(),
                });
            }
            Tok::Op(c) => {
                return Err(ExprError {
                    column: tok.column,
                    message: format!("expected a number, t or \"(\" before \"{c}\""),
                });
            }
        };
        // Juxtaposition (2t, 2(t+1), t sin(t)) is not a product here: say so.
        if let Some(next) = self.peek()
            && matches!(next.kind, Tok::Num(_) | Tok::Name(_) | Tok::Open)
        {
            let left = match &tok.kind {
                Tok::Num(_) => "a number".to_owned(),
                Tok::Name(n) => format!("\"{n}\""),
                _ => "\")\"".to_owned(),
            };
            let right = match &next.kind {
                Tok::Name(n) => format!("\"{n}\""),
                Tok::Num(v) => format!("{v}"),
                _ => "\"(\"".to_owned(),
            };
            let example = match (&tok.kind, &next.kind) {
                (Tok::Num(v), Tok::Name(n)) => format!(" — write {v}*{n}"),
                _ => "; write * for a product".to_owned(),
            };
            return Err(ExprError { column: next.column, message: format!("{left} followed by {right}{example}") });
        }
        Ok(node)
    }

    fn close(&mut self, open_column: usize) -> Result<(), ExprError> {
        match self.peek() {
            Some(Token { kind: Tok::Close, .. }) => {
                self.pos += 1;
                Ok(())
            }
            Some(t) => Err(ExprError {
                column: t.column,
                message: format!(
                    "expected \")\" to close the \"(\" at column {open_column}, found {}",
                    describe(&t.kind)
                ),
            }),
            None => Err(ExprError {
                column: self.end_column,
                message: format!("the \"(\" at column {open_column} is never closed; add \")\""),
            }),
        }
    }

    fn name(&mut self, name: &str, column: usize) -> Result<Node, ExprError> {
        match name {
            "t" => return Ok(Node::T),
            "pi" | "π" => return Ok(Node::Num(std::f64::consts::PI)),
            _ => {}
        }
        let Some(&(_, f)) = Func::ALL.iter().find(|(n, _)| *n == name) else {
            return Err(ExprError {
                column,
                message: format!(
                    "unknown name \"{name}\"; use t, pi or a function: sin cos tan exp ln sqrt abs (write * for a product)"
                ),
            });
        };
        match self.peek() {
            Some(Token { kind: Tok::Open, column: open }) => {
                let open = *open;
                self.pos += 1;
                let arg = self.expr()?;
                self.close(open)?;
                Ok(Node::Call(f, arg.into()))
            }
            _ => Err(ExprError {
                column: column + name.chars().count(),
                message: format!("{name} needs its argument in parentheses, e.g. {name}(t)"),
            }),
        }
    }
}
