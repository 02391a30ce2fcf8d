//! Python expressions of `.lpy` files, read into a small tree and written
//! as `.ls` formulas.
//!
//! The tree keeps Python's precedence (`-x ** 2` is `-(x ** 2)`, `not a <
//! b` is `not (a < b)`, comparisons chain), and every operation is written
//! in parentheses, so the `.ls` parser's precedence never decides. Python
//! names map onto the expression language: `**` is `^`, `%` is `mod` (the
//! divisor's sign), `//` is `floor(a / b)`, `a if c else b` is `c ? a : b`,
//! `math.sin` and `sin` are `sin`, `random()` is `rand()`, `gauss` is
//! `normal`, `getIterationNb()` is `iteration`, and a small `def` function
//! is written out at every call.

use super::text::{Out, outside};
use genform_core::{Diagnostic, Span};

/// Deepest nesting of brackets and function inlining read.
pub(super) const MAX_DEPTH: usize = 64;

/// A Python expression.
#[derive(Clone, Debug)]
pub(super) enum Py {
    /// A number as written.
    Num(String, usize),
    /// A name, dotted names included (`math.pi`).
    Name(String, usize),
    /// A call of a (dotted) name.
    Call(String, usize, Vec<Py>),
    /// `-x`.
    Neg(usize, Box<Py>),
    /// `not x`.
    Not(usize, Box<Py>),
    /// A binary operation: `+ - * / // % ** and or`.
    Bin(&'static str, usize, Box<Py>, Box<Py>),
    /// A comparison chain `a < b <= c`.
    Cmp(Box<Py>, Vec<(&'static str, usize, Py)>),
    /// `a if c else b`: (c, a, b).
    Cond(Box<Py>, Box<Py>, Box<Py>),
}

#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum Kind {
    Num,
    Name,
    Str,
    Op,
}

#[derive(Clone, Debug)]
struct Tok<'a> {
    kind: Kind,
    text: &'a str,
    at: usize,
}

const OPS: &[&str] = &[
    "**", "//", "==", "!=", "<=", ">=", "<<", ">>", "->", "<", ">", "+", "-", "*", "/", "%", "(", ")", ",", ".", "[",
    "]", "{", "}", ":", "=", "~", "&", "|", "^", "@",
];

fn lex(s: &str, at: usize) -> Result<Vec<Tok<'_>>, Diagnostic> {
    let b = s.as_bytes();
    let mut toks = Vec::new();
    let mut i = 0;
    while i < b.len() {
        let c = b[i];
        if c.is_ascii_whitespace() {
            i += 1;
            continue;
        }
        let start = i;
        let kind = if c.is_ascii_digit() || (c == b'.' && b.get(i + 1).is_some_and(u8::is_ascii_digit)) {
            while i < b.len() && (b[i].is_ascii_digit() || b[i] == b'.' || b[i] == b'_') {
                i += 1;
            }
            if i < b.len() && (b[i] == b'e' || b[i] == b'E') {
                let mut j = i + 1;
                if j < b.len() && (b[j] == b'+' || b[j] == b'-') {
                    j += 1;
                }
                if j < b.len() && b[j].is_ascii_digit() {
                    i = j;
                    while i < b.len() && b[i].is_ascii_digit() {
                        i += 1;
                    }
                }
            }
            Kind::Num
        } else if matches!(c, b'u' | b'r' | b'b' | b'f' | b'U' | b'R' | b'B' | b'F')
            && matches!(b.get(i + 1), Some(b'\'' | b'"'))
        {
            // A prefixed string (`u'é'`).
            let q = b[i + 1];
            i += 2;
            while i < b.len() && b[i] != q {
                i += 1;
            }
            i = (i + 1).min(b.len());
            Kind::Str
        } else if c.is_ascii_alphabetic() || c == b'_' {
            while i < b.len() && (b[i].is_ascii_alphanumeric() || b[i] == b'_') {
                i += 1;
            }
            Kind::Name
        } else if c == b'\'' || c == b'"' {
            i += 1;
            while i < b.len() && b[i] != c {
                i += 1;
            }
            i = (i + 1).min(b.len());
            Kind::Str
        } else if let Some(op) = OPS.iter().find(|op| b[i..].starts_with(op.as_bytes())) {
            i += op.len();
            Kind::Op
        } else {
            let len = s[i..].chars().next().map_or(1, char::len_utf8);
            return Err(Diagnostic::error(
                Span::new(at + i, at + i + len),
                "unexpected character in a Python expression",
            ));
        };
        toks.push(Tok { kind, text: &s[start..i], at: at + start });
    }
    Ok(toks)
}

struct Parser<'a> {
    toks: Vec<Tok<'a>>,
    pos: usize,
    end: usize,
    depth: usize,
}

type R<T> = Result<T, Diagnostic>;

impl<'a> Parser<'a> {
    fn peek(&self) -> Option<&Tok<'a>> {
        self.toks.get(self.pos)
    }

    fn is(&self, text: &str) -> bool {
        self.peek().is_some_and(|t| t.text == text && t.kind != Kind::Str)
    }

    fn here(&self) -> usize {
        self.peek().map_or(self.end, |t| t.at)
    }

    fn next(&mut self) -> Option<Tok<'a>> {
        let t = self.toks.get(self.pos).cloned();
        self.pos += 1;
        t
    }

    fn expect(&mut self, text: &str) -> R<()> {
        if self.is(text) {
            self.pos += 1;
            Ok(())
        } else {
            Err(Diagnostic::error(Span::new(self.here(), self.here() + 1), format!("expected `{text}`")))
        }
    }

    fn expr(&mut self) -> R<Py> {
        self.depth += 1;
        if self.depth > MAX_DEPTH {
            return Err(Diagnostic::error(Span::new(self.here(), self.here() + 1), "expression nested too deeply"));
        }
        if self.is("lambda") {
            return Err(outside(self.here(), 6, "a Python `lambda`"));
        }
        let a = self.or()?;
        let r = if self.is("if") {
            self.pos += 1;
            let c = self.or()?;
            self.expect("else")?;
            let b = self.expr()?;
            Py::Cond(Box::new(c), Box::new(a), Box::new(b))
        } else {
            a
        };
        self.depth -= 1;
        Ok(r)
    }

    fn or(&mut self) -> R<Py> {
        self.left_assoc("or", Self::and)
    }

    fn and(&mut self) -> R<Py> {
        self.left_assoc("and", Self::not)
    }

    /// `a op b op c …` as `(a op b) op c`, each operand read by `operand`.
    fn left_assoc(&mut self, op: &'static str, operand: fn(&mut Self) -> R<Py>) -> R<Py> {
        let mut a = operand(self)?;
        while self.is(op) {
            let at = self.here();
            self.pos += 1;
            a = Py::Bin(op, at, Box::new(a), Box::new(operand(self)?));
        }
        Ok(a)
    }

    fn not(&mut self) -> R<Py> {
        if self.is("not") {
            let at = self.here();
            self.pos += 1;
            self.depth += 1;
            if self.depth > MAX_DEPTH {
                return Err(Diagnostic::error(Span::new(at, at + 3), "expression nested too deeply"));
            }
            let e = self.not()?;
            self.depth -= 1;
            return Ok(Py::Not(at, Box::new(e)));
        }
        self.comparison()
    }

    fn comparison(&mut self) -> R<Py> {
        let a = self.arith()?;
        let mut rest = Vec::new();
        loop {
            let at = self.here();
            let op = match self.peek().map(|t| t.text) {
                Some(op @ ("<" | ">" | "==" | "!=" | "<=" | ">="))
                    if self.peek().is_some_and(|t| t.kind == Kind::Op) =>
                {
                    match op {
                        "<" => "<",
                        ">" => ">",
                        "==" => "==",
                        "!=" => "!=",
                        "<=" => "<=",
                        _ => ">=",
                    }
                }
                Some(w @ ("in" | "is")) if self.peek().is_some_and(|t| t.kind == Kind::Name) => {
                    return Err(outside(at, w.len(), &format!("the Python operator `{w}`")));
                }
                _ => break,
            };
            self.pos += 1;
            rest.push((op, at, self.arith()?));
        }
        Ok(if rest.is_empty() { a } else { Py::Cmp(Box::new(a), rest) })
    }

    fn arith(&mut self) -> R<Py> {
        let mut a = self.term()?;
        loop {
            let at = self.here();
            let op = if self.is("+") {
                "+"
            } else if self.is("-") {
                "-"
            } else {
                break;
            };
            self.pos += 1;
            a = Py::Bin(op, at, Box::new(a), Box::new(self.term()?));
        }
        Ok(a)
    }

    fn term(&mut self) -> R<Py> {
        let mut a = self.factor()?;
        loop {
            let at = self.here();
            let op = ["*", "/", "//", "%"].into_iter().find(|op| self.is(op));
            let Some(op) = op else { break };
            self.pos += 1;
            a = Py::Bin(op, at, Box::new(a), Box::new(self.factor()?));
        }
        Ok(a)
    }

    fn factor(&mut self) -> R<Py> {
        let at = self.here();
        if self.is("-") || self.is("+") {
            let neg = self.is("-");
            self.pos += 1;
            self.depth += 1;
            if self.depth > MAX_DEPTH {
                return Err(Diagnostic::error(Span::new(at, at + 1), "expression nested too deeply"));
            }
            let e = self.factor()?;
            self.depth -= 1;
            return Ok(if neg { Py::Neg(at, Box::new(e)) } else { e });
        }
        if self.is("~") {
            return Err(outside(at, 1, "the Python operator `~`"));
        }
        let a = self.primary()?;
        if self.is("**") {
            let at = self.here();
            self.pos += 1;
            let b = self.factor()?;
            return Ok(Py::Bin("**", at, Box::new(a), Box::new(b)));
        }
        Ok(a)
    }

    fn primary(&mut self) -> R<Py> {
        let at = self.here();
        let Some(t) = self.next() else {
            return Err(Diagnostic::error(Span::new(at, at + 1), "expected a Python expression"));
        };
        let e = match t.kind {
            Kind::Num => Py::Num(t.text.replace('_', ""), t.at),
            Kind::Str => return Err(outside(t.at, t.text.len(), "a Python string")),
            Kind::Name => {
                let mut name = t.text.to_string();
                while self.is(".") && self.toks.get(self.pos + 1).is_some_and(|n| n.kind == Kind::Name) {
                    name.push('.');
                    name.push_str(self.toks[self.pos + 1].text);
                    self.pos += 2;
                }
                if self.is("(") {
                    self.pos += 1;
                    let mut args = Vec::new();
                    while !self.is(")") {
                        if self.peek().is_none() {
                            return Err(Diagnostic::error(Span::new(t.at, t.at + name.len()), "`(` never closed"));
                        }
                        if self.toks.get(self.pos + 1).is_some_and(|n| n.text == "=")
                            && self.peek().is_some_and(|p| p.kind == Kind::Name)
                        {
                            return Err(outside(self.here(), 1, "a Python keyword argument"));
                        }
                        args.push(self.expr()?);
                        if !self.is(")") {
                            self.expect(",")?;
                        }
                    }
                    self.pos += 1;
                    Py::Call(name, t.at, args)
                } else {
                    Py::Name(name, t.at)
                }
            }
            Kind::Op if t.text == "(" => {
                let e = self.expr()?;
                if self.is(",") {
                    return Err(outside(t.at, 1, "a Python tuple"));
                }
                self.expect(")")?;
                e
            }
            Kind::Op if t.text == "[" => return Err(outside(t.at, 1, "a Python list")),
            Kind::Op if t.text == "{" => return Err(outside(t.at, 1, "a Python dictionary or set")),
            Kind::Op => {
                return Err(Diagnostic::error(
                    Span::new(t.at, t.at + t.text.len()),
                    format!("expected a Python expression, found `{}`", t.text),
                ));
            }
        };
        // Attributes and subscripts of values are Python objects.
        if self.is("[") {
            return Err(outside(self.here(), 1, "a Python subscript"));
        }
        if self.is(".") {
            return Err(outside(self.here(), 1, "a Python attribute of a value"));
        }
        Ok(e)
    }
}

/// Parses the whole of `s` (at file offset `at`) as one expression.
pub(super) fn parse(s: &str, at: usize) -> R<Py> {
    let mut p = Parser { toks: lex(s, at)?, pos: 0, end: at + s.len(), depth: 0 };
    let e = p.expr()?;
    if let Some(t) = p.peek() {
        let what = if t.text == "," { "a Python tuple".to_string() } else { format!("`{}`", t.text) };
        return Err(if t.text == "," {
            outside(t.at, 1, &what)
        } else {
            Diagnostic::error(Span::new(t.at, t.at + t.text.len()), format!("unexpected {what} after the expression"))
        });
    }
    Ok(e)
}

/// Parses `s` as comma-separated expressions (a module's parameters).
pub(super) fn parse_list(s: &str, at: usize) -> R<Vec<Py>> {
    let mut p = Parser { toks: lex(s, at)?, pos: 0, end: at + s.len(), depth: 0 };
    let mut out = Vec::new();
    while p.peek().is_some() {
        out.push(p.expr()?);
        if p.peek().is_some() {
            p.expect(",")?;
        }
    }
    Ok(out)
}

/// A small function: `def f(a, b): return expr` (the body reduced to one
/// expression).
#[derive(Clone, Debug)]
pub(super) struct Func {
    pub name: String,
    pub params: Vec<String>,
    /// The expression, or why the body is not one.
    pub body: Result<Py, Diagnostic>,
}

/// What names mean when written as `.ls` formulas.
#[derive(Clone, Debug, Default)]
pub(super) struct Names {
    /// Small functions, written out at each call.
    pub funcs: Vec<Func>,
    /// Prefixes of the `random` module (`random`, `rd`).
    pub random: Vec<String>,
    /// Prefixes of the `math` module.
    pub math: Vec<String>,
    /// Python names renamed in the `.ls` text (they clash with its words).
    pub renamed: Vec<(String, String)>,
    /// Declared module names of more than one character, as the `.ls`
    /// lexer reads them.
    pub modules: Vec<String>,
}

/// `math` functions the expression language has, with its name.
pub(super) const MATH: &[(&str, &str)] = &[
    ("sin", "sin"),
    ("cos", "cos"),
    ("tan", "tan"),
    ("asin", "asin"),
    ("acos", "acos"),
    ("atan", "atan"),
    ("atan2", "atan2"),
    ("sqrt", "sqrt"),
    ("exp", "exp"),
    ("log", "ln"),
    ("log10", "log10"),
    ("log2", "log2"),
    ("floor", "floor"),
    ("ceil", "ceil"),
    ("fabs", "abs"),
    ("pow", "pow"),
    ("radians", "rad"),
    ("degrees", "deg"),
    ("hypot", "hypot"),
    ("trunc", "trunc"),
];

/// Python built-ins the expression language has.
const BUILTIN: &[(&str, &str)] = &[("abs", "abs"), ("int", "trunc"), ("round", "round"), ("pow", "pow")];

impl Names {
    /// The function a (dotted) name calls, with its module prefix removed
    /// when it is `math` or `random`: (`"math"` | `"random"` | `""`, rest).
    pub(super) fn module_of<'n>(&self, name: &'n str) -> (&'static str, &'n str) {
        if let Some((pre, rest)) = name.rsplit_once('.') {
            if self.math.iter().any(|m| m == pre) {
                return ("math", rest);
            }
            if self.random.iter().any(|m| m == pre) {
                return ("random", rest);
            }
            return ("?", name);
        }
        ("", name)
    }

    /// Writes `e` as a `.ls` formula.
    pub fn emit(&self, e: &Py, out: &mut Out, errors: &mut Vec<Diagnostic>) {
        self.write(e, out, errors, 0);
    }

    fn write(&self, e: &Py, out: &mut Out, errors: &mut Vec<Diagnostic>, depth: usize) {
        if depth > MAX_DEPTH {
            errors.push(Diagnostic::error(Span::new(at_of(e), at_of(e) + 1), "functions call each other too deeply"));
            return;
        }
        let w = |e: &Py, out: &mut Out, errors: &mut Vec<Diagnostic>| self.write(e, out, errors, depth + 1);
        match e {
            Py::Num(n, at) => out.push(n, *at),
            Py::Name(n, at) => {
                let (module, rest) = self.module_of(n);
                match (module, rest) {
                    ("", "True") => out.push("1", *at),
                    ("", "False") => out.push("0", *at),
                    ("math" | "", "pi") => out.push("pi", *at),
                    ("math" | "", "e") => out.push("e", *at),
                    ("", _) => match self.renamed.iter().find(|(p, _)| p == n) {
                        Some((_, to)) => out.push(to, *at),
                        None => out.push(n, *at),
                    },
                    _ => errors.push(outside(*at, n.len(), &format!("the Python name `{n}`"))),
                }
            }
            Py::Neg(at, x) => {
                out.push("(-", *at);
                w(x, out, errors);
                out.push(")", *at);
            }
            Py::Not(at, x) => {
                out.push("(not ", *at);
                w(x, out, errors);
                out.push(")", *at);
            }
            Py::Bin(op, at, a, b) => {
                let (open, mid, close) = match *op {
                    "**" => ("(", " ^ ", ")"),
                    "%" => ("mod(", ", ", ")"),
                    "//" => ("floor(", " / ", ")"),
                    "and" => ("(", " and ", ")"),
                    "or" => ("(", " or ", ")"),
                    "+" => ("(", " + ", ")"),
                    "-" => ("(", " - ", ")"),
                    "*" => ("(", " * ", ")"),
                    _ => ("(", " / ", ")"),
                };
                out.push(open, *at);
                w(a, out, errors);
                out.push(mid, *at);
                w(b, out, errors);
                out.push(close, *at);
            }
            Py::Cmp(first, rest) => {
                out.push("(", at_of(first));
                let mut left = first.as_ref();
                for (k, (op, at, right)) in rest.iter().enumerate() {
                    if k > 0 {
                        out.push(" and ", *at);
                    }
                    out.push("(", *at);
                    w(left, out, errors);
                    out.push(&format!(" {op} "), *at);
                    w(right, out, errors);
                    out.push(")", *at);
                    left = right;
                }
                out.push(")", at_of(first));
            }
            Py::Cond(c, a, b) => {
                out.push("(", at_of(c));
                w(c, out, errors);
                out.push(" ? ", at_of(c));
                w(a, out, errors);
                out.push(" : ", at_of(c));
                w(b, out, errors);
                out.push(")", at_of(c));
            }
            Py::Call(name, at, args) => self.call(name, *at, args, out, errors, depth),
        }
    }

    fn call(&self, name: &str, at: usize, args: &[Py], out: &mut Out, errors: &mut Vec<Diagnostic>, depth: usize) {
        let (module, f) = self.module_of(name);
        let arity = |n: usize, errors: &mut Vec<Diagnostic>| {
            let ok = args.len() == n;
            if !ok {
                errors.push(Diagnostic::error(
                    Span::new(at, at + name.len()),
                    format!("`{name}` takes {n} argument{}, not {}", if n == 1 { "" } else { "s" }, args.len()),
                ));
            }
            ok
        };
        let plain = |to: &str, out: &mut Out, errors: &mut Vec<Diagnostic>| {
            out.push(to, at);
            out.push("(", at);
            for (k, a) in args.iter().enumerate() {
                if k > 0 {
                    out.push(", ", at);
                }
                self.write(a, out, errors, depth + 1);
            }
            out.push(")", at);
        };
        // A user function first: it may shadow a built-in.
        if module.is_empty()
            && let Some(func) = self.funcs.iter().find(|f| f.name == name)
        {
            match &func.body {
                Ok(body) if args.len() == func.params.len() => {
                    let e = substitute(body, &func.params, args);
                    self.write(&e, out, errors, depth + 1);
                }
                Ok(_) => {
                    arity(func.params.len(), errors);
                }
                Err(why) => {
                    let mut d = outside(at, name.len(), &format!("the Python function `{name}`"));
                    d.message = format!("{} ({})", d.message, why.message);
                    errors.push(d);
                }
            }
            return;
        }
        let random = module == "random" || module.is_empty();
        let math = module == "math" || module.is_empty();
        match f {
            "getIterationNb" if module.is_empty() && arity(0, errors) => out.push("iteration", at),
            "getGroup" if module.is_empty() && arity(0, errors) => out.push(super::names::GROUP, at),
            "random" if random && arity(0, errors) => out.push("rand()", at),
            "uniform" if random && arity(2, errors) => plain("uniform", out, errors),
            "gauss" | "normalvariate" if random && arity(2, errors) => plain("normal", out, errors),
            "randint" if random && arity(2, errors) => {
                out.push("floor(uniform(", at);
                self.write(&args[0], out, errors, depth + 1);
                out.push(", ", at);
                self.write(&args[1], out, errors, depth + 1);
                out.push(" + 1))", at);
            }
            "min" | "max" if module.is_empty() && args.len() >= 2 => {
                // Python's n-ary min/max, nested.
                for _ in 1..args.len() {
                    out.push(f, at);
                    out.push("(", at);
                }
                self.write(&args[0], out, errors, depth + 1);
                for a in &args[1..] {
                    out.push(", ", at);
                    self.write(a, out, errors, depth + 1);
                    out.push(")", at);
                }
            }
            // `float(x)` is x; `str(x)` (a `Label`'s text) is the number x.
            "float" | "str" if module.is_empty() && arity(1, errors) => self.write(&args[0], out, errors, depth + 1),
            "fmod" if math && arity(2, errors) => {
                out.push("(", at);
                self.write(&args[0], out, errors, depth + 1);
                out.push(" % ", at);
                self.write(&args[1], out, errors, depth + 1);
                out.push(")", at);
            }
            _ => {
                let known = MATH
                    .iter()
                    .filter(|_| math)
                    .chain(BUILTIN.iter().filter(|_| module.is_empty()))
                    .find(|(p, _)| *p == f);
                match known {
                    Some((_, to)) => plain(to, out, errors),
                    None => errors.push(outside(at, name.len(), &format!("the Python call `{name}(…)`"))),
                }
            }
        }
    }
}

/// The value `name op= value` assigns (`value` for a plain `=`).
pub(super) fn compound(name: &str, at: usize, op: Option<char>, value: Py) -> Py {
    let op = match op {
        None => return value,
        Some('+') => "+",
        Some('-') => "-",
        Some('*') => "*",
        Some(_) => "/",
    };
    Py::Bin(op, at, Box::new(Py::Name(name.to_string(), at)), Box::new(value))
}

/// The offset an expression starts at (about).
pub(super) fn at_of(e: &Py) -> usize {
    match e {
        Py::Num(_, at) | Py::Name(_, at) | Py::Call(_, at, _) | Py::Neg(at, _) | Py::Not(at, _) => *at,
        Py::Bin(_, _, a, _) | Py::Cmp(a, _) => at_of(a),
        Py::Cond(_, a, _) => at_of(a),
    }
}

/// `e` with the names `params` replaced by `args`.
pub(super) fn substitute(e: &Py, params: &[String], args: &[Py]) -> Py {
    let s = |x: &Py| substitute(x, params, args);
    match e {
        Py::Name(n, _) => match params.iter().position(|p| p == n) {
            Some(i) => args.get(i).cloned().unwrap_or_else(|| e.clone()),
            None => e.clone(),
        },
        Py::Num(..) => e.clone(),
        Py::Call(n, at, a) => Py::Call(n.clone(), *at, a.iter().map(s).collect()),
        Py::Neg(at, x) => Py::Neg(*at, Box::new(s(x))),
        Py::Not(at, x) => Py::Not(*at, Box::new(s(x))),
        Py::Bin(op, at, a, b) => Py::Bin(op, *at, Box::new(s(a)), Box::new(s(b))),
        Py::Cmp(a, rest) => Py::Cmp(Box::new(s(a)), rest.iter().map(|(op, at, x)| (*op, *at, s(x))).collect()),
        Py::Cond(c, a, b) => Py::Cond(Box::new(s(c)), Box::new(s(a)), Box::new(s(b))),
    }
}

/// The value of a constant expression over `consts` (module-level
/// numbers), or `None` when it calls, draws or names anything else.
pub(super) fn constant(e: &Py, consts: &[(String, f64)]) -> Option<f64> {
    let c = |x: &Py| constant(x, consts);
    let truth = |v: f64| v != 0.0 && !v.is_nan();
    Some(match e {
        Py::Num(n, _) => n.parse().ok()?,
        Py::Name(n, _) => match n.as_str() {
            "pi" | "math.pi" => std::f64::consts::PI,
            "True" => 1.0,
            "False" => 0.0,
            _ => consts.iter().rev().find(|(k, _)| k == n)?.1,
        },
        Py::Call(..) => return None,
        Py::Neg(_, x) => -c(x)?,
        Py::Not(_, x) => f64::from(!truth(c(x)?)),
        Py::Bin(op, _, a, b) => {
            let (a, b) = (c(a)?, c(b)?);
            match *op {
                "+" => a + b,
                "-" => a - b,
                "*" => a * b,
                "/" => a / b,
                "//" => (a / b).floor(),
                "%" => a - b * (a / b).floor(),
                "**" => a.powf(b),
                "and" => f64::from(truth(a) && truth(b)),
                _ => f64::from(truth(a) || truth(b)),
            }
        }
        Py::Cmp(first, rest) => {
            let mut left = c(first)?;
            let mut all = true;
            for (op, _, r) in rest {
                let right = c(r)?;
                all &= match *op {
                    "<" => left < right,
                    ">" => left > right,
                    "==" => left == right,
                    "!=" => left != right,
                    "<=" => left <= right,
                    _ => left >= right,
                };
                left = right;
            }
            f64::from(all)
        }
        Py::Cond(k, a, b) => {
            if truth(c(k)?) {
                c(a)?
            } else {
                c(b)?
            }
        }
    })
}
