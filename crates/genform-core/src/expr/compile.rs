//! Name resolution, constant folding and bytecode emission; the evaluator.

use super::parse::{Ast, BinOp, Node, UnOp};
use super::scope::Scope;
use super::suggest::did_you_mean;
use crate::diag::Diagnostic;
use crate::rng::{Draws, Rng, standard_normal, uniform_in};

/// Largest evaluation stack a program may need.
const STACK: usize = 64;

/// The stack of most programs: zeroing all of [`STACK`] would cost more
/// than evaluating a short formula.
const SHORT_STACK: usize = 8;

#[derive(Clone, Copy, Debug, PartialEq)]
enum Op {
    Const(f64),
    Load(u32),
    Un(UnOp),
    Bin(BinOp),
    /// Pops; jumps when false.
    JumpIfFalse(u32),
    Jump(u32),
    /// Replaces the top with 1 or 0.
    Truth,
    F1(F1),
    F2(F2),
    F3(F3),
    Rand(RandOp),
}

macro_rules! builtins {
    ($name:ident, $arity:literal, { $($s:literal => $v:ident),* $(,)? }) => {
        #[derive(Clone, Copy, Debug, PartialEq, Eq)]
        enum $name { $($v),* }
        impl $name {
            fn lookup(s: &str) -> Option<Self> {
                match s { $($s => Some($name::$v),)* _ => None }
            }
            const NAMES: &'static [&'static str] = &[$($s),*];
        }
    };
}

builtins!(F1, 1, {
    "sin" => Sin, "cos" => Cos, "tan" => Tan, "asin" => Asin, "acos" => Acos, "atan" => Atan,
    "sqrt" => Sqrt, "abs" => Abs, "floor" => Floor, "ceil" => Ceil, "round" => Round, "trunc" => Trunc,
    "fract" => Fract, "sign" => Sign, "exp" => Exp, "ln" => Ln, "log" => Log, "log2" => Log2,
    "log10" => Log10, "rad" => Rad, "deg" => Deg,
});
builtins!(F2, 2, { "atan2" => Atan2, "min" => Min, "max" => Max, "pow" => Pow, "mod" => Mod, "hypot" => Hypot, "step" => Step });
builtins!(F3, 3, { "clamp" => Clamp, "mix" => Mix, "lerp" => Lerp, "smoothstep" => Smoothstep, "smootherstep" => Smootherstep, "if" => If });
builtins!(RandOp, 2, { "uniform" => Uniform, "normal" => Normal, "rand" => Rand });

/// Whether `name` is one of the random-draw functions (`uniform`, `normal`,
/// `rand`).
pub(crate) fn is_random_function(name: &str) -> bool {
    RandOp::lookup(name).is_some()
}

impl F1 {
    fn apply(self, x: f64) -> f64 {
        match self {
            F1::Sin => x.sin(),
            F1::Cos => x.cos(),
            F1::Tan => x.tan(),
            F1::Asin => x.asin(),
            F1::Acos => x.acos(),
            F1::Atan => x.atan(),
            F1::Sqrt => x.sqrt(),
            F1::Abs => x.abs(),
            F1::Floor => x.floor(),
            F1::Ceil => x.ceil(),
            F1::Round => x.round(),
            F1::Trunc => x.trunc(),
            F1::Fract => x - x.floor(),
            F1::Sign => {
                if x > 0.0 {
                    1.0
                } else if x < 0.0 {
                    -1.0
                } else {
                    0.0
                }
            }
            F1::Exp => x.exp(),
            F1::Ln | F1::Log => x.ln(),
            F1::Log2 => x.log2(),
            F1::Log10 => x.log10(),
            F1::Rad => x.to_radians(),
            F1::Deg => x.to_degrees(),
        }
    }
}

impl F2 {
    fn apply(self, a: f64, b: f64) -> f64 {
        match self {
            F2::Atan2 => a.atan2(b),
            F2::Min => a.min(b),
            F2::Max => a.max(b),
            F2::Pow => a.powf(b),
            F2::Mod => a.rem_euclid(b),
            F2::Hypot => a.hypot(b),
            F2::Step => truth(b >= a),
        }
    }
}

/// Ken Perlin's smootherstep, `t³(t(6t − 15) + 10)` with `t` clamped to [0, 1].
pub fn smootherstep(a: f64, b: f64, x: f64) -> f64 {
    let t = if b == a { truth(x >= a) } else { ((x - a) / (b - a)).clamp(0.0, 1.0) };
    t * t * t * (t * (6.0 * t - 15.0) + 10.0)
}

impl F3 {
    fn apply(self, a: f64, b: f64, c: f64) -> f64 {
        match self {
            F3::Clamp => a.max(b).min(c),
            F3::Mix | F3::Lerp => a + (b - a) * c,
            F3::Smoothstep => {
                let t = if b == a { truth(c >= a) } else { ((c - a) / (b - a)).clamp(0.0, 1.0) };
                t * t * (3.0 - 2.0 * t)
            }
            F3::Smootherstep => smootherstep(a, b, c),
            F3::If => {
                if is_true(a) {
                    b
                } else {
                    c
                }
            }
        }
    }
}

#[inline]
fn truth(b: bool) -> f64 {
    if b { 1.0 } else { 0.0 }
}

#[inline]
fn is_true(v: f64) -> bool {
    v != 0.0 && !v.is_nan()
}

fn bin(op: BinOp, a: f64, b: f64) -> f64 {
    match op {
        BinOp::Add => a + b,
        BinOp::Sub => a - b,
        BinOp::Mul => a * b,
        BinOp::Div => a / b,
        BinOp::Rem => a % b,
        BinOp::Pow => a.powf(b),
        BinOp::Lt => truth(a < b),
        BinOp::Le => truth(a <= b),
        BinOp::Gt => truth(a > b),
        BinOp::Ge => truth(a >= b),
        BinOp::Eq => truth(a == b),
        BinOp::Ne => truth(a != b),
        // Logic is compiled to jumps; these serve constant folding.
        BinOp::And => truth(is_true(a) && is_true(b)),
        BinOp::Or => truth(is_true(a) || is_true(b)),
    }
}

/// A value a [`Trivial`] program reads.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Operand {
    /// A constant.
    Const(f64),
    /// Env slot `i` (NaN when the env is shorter, as in [`Program::eval`]).
    Load(u32),
}

/// The operation of a [`Trivial`] program.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Arith {
    /// `a + b`.
    Add,
    /// `a − b`.
    Sub,
    /// `a · b`.
    Mul,
    /// `a / b`.
    Div,
}

impl Arith {
    /// `a op b`: the one IEEE operation [`Program::eval`] performs for this
    /// operator, so fast paths that call it give bit-identical results.
    #[inline(always)]
    pub fn apply(self, a: f64, b: f64) -> f64 {
        match self {
            Arith::Add => a + b,
            Arith::Sub => a - b,
            Arith::Mul => a * b,
            Arith::Div => a / b,
        }
    }
}

impl Operand {
    /// The operand's value against `env`: the constant, or env slot `i`
    /// (NaN when the env is shorter, as in [`Program::eval`]).
    #[inline(always)]
    pub fn value(self, env: &[f64]) -> f64 {
        match self {
            Operand::Const(v) => v,
            Operand::Load(i) => env.get(i as usize).copied().unwrap_or(f64::NAN),
        }
    }
}

/// What a program computes when it is one value or one arithmetic
/// operation on two values (`2.5`, `size.x`, `sz / 2`, `sz * move`): most
/// operands of a grammar. Hot paths compute these directly, with the same
/// IEEE operation as [`Program::eval`], so results are bit-identical.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Trivial {
    /// The program yields this value.
    Value(Operand),
    /// The program yields `a op b`.
    Bin(Arith, Operand, Operand),
}

/// A compiled expression.
#[derive(Clone, Debug, PartialEq)]
pub struct Program {
    code: Vec<Op>,
    uses_rng: bool,
    /// The most values pending during an evaluation.
    depth: usize,
}

struct Compiler<'s> {
    scope: &'s dyn Scope,
    code: Vec<Op>,
    errors: Vec<Diagnostic>,
    uses_rng: bool,
}

/// Compiles an expression against the names of `scope`. Every unknown name,
/// unknown function and wrong argument count is reported.
pub fn compile(ast: &Ast, scope: &dyn Scope) -> Result<Program, Vec<Diagnostic>> {
    let mut c = Compiler { scope, code: Vec::new(), errors: Vec::new(), uses_rng: false };
    c.emit(ast);
    if !c.errors.is_empty() {
        return Err(c.errors);
    }
    let mut prog = Program { code: c.code, uses_rng: c.uses_rng, depth: 0 };
    prog.depth = prog.max_stack();
    if prog.depth > STACK {
        return Err(vec![
            Diagnostic::error(ast.span, "expression is too large to evaluate")
                .with_hint(format!("split it with intermediate variables (at most {STACK} pending values)")),
        ]);
    }
    Ok(prog)
}

impl Compiler<'_> {
    fn emit(&mut self, ast: &Ast) {
        // Fold constant sub-trees.
        if let Some(v) = self.fold(ast) {
            self.code.push(Op::Const(v));
            return;
        }
        match &ast.kind {
            Node::Num(v) => self.code.push(Op::Const(*v)),
            Node::Var(name) => self.load(name, ast),
            Node::Unary(op, a) => {
                self.emit(a);
                self.code.push(Op::Un(*op));
            }
            Node::Binary(BinOp::And, a, b) => {
                // a ? truth(b) : 0
                self.cond(
                    a,
                    |c| {
                        c.emit(b);
                        c.code.push(Op::Truth);
                    },
                    |c| c.code.push(Op::Const(0.0)),
                );
            }
            Node::Binary(BinOp::Or, a, b) => {
                self.cond(
                    a,
                    |c| c.code.push(Op::Const(1.0)),
                    |c| {
                        c.emit(b);
                        c.code.push(Op::Truth);
                    },
                );
            }
            Node::Binary(op, a, b) => {
                self.emit(a);
                self.emit(b);
                self.code.push(Op::Bin(*op));
            }
            Node::Cond(c, a, b) => self.cond(c, |s| s.emit(a), |s| s.emit(b)),
            Node::Call(name, name_span, args) => self.call(name, *name_span, args, ast),
        }
    }

    fn cond(&mut self, c: &Ast, then: impl FnOnce(&mut Self), els: impl FnOnce(&mut Self)) {
        self.emit(c);
        let jf = self.code.len();
        self.code.push(Op::JumpIfFalse(0));
        then(self);
        let j = self.code.len();
        self.code.push(Op::Jump(0));
        self.code[jf] = Op::JumpIfFalse(self.code.len() as u32);
        els(self);
        self.code[j] = Op::Jump(self.code.len() as u32);
    }

    fn load(&mut self, name: &str, ast: &Ast) {
        if let Some(v) = self.constant(name) {
            self.code.push(Op::Const(v));
            return;
        }
        match self.scope.variable(name) {
            Some(i) => self.code.push(Op::Load(i)),
            None => {
                let names = self.scope.names();
                let mut d = Diagnostic::error(ast.span, format!("unknown name `{name}`"));
                if let Some(s) = did_you_mean(name, names.iter().map(String::as_str)) {
                    d = d.with_hint(format!("did you mean `{s}`?"));
                } else if !names.is_empty() {
                    let mut shown: Vec<&str> = names.iter().map(String::as_str).take(12).collect();
                    shown.sort_unstable();
                    d = d.with_hint(format!("names available here: {}", shown.join(", ")));
                }
                self.errors.push(d);
            }
        }
    }

    fn call(&mut self, name: &str, name_span: crate::diag::Span, args: &[Ast], ast: &Ast) {
        let arity = |c: &mut Self, n: usize| -> bool {
            if args.len() != n {
                c.errors.push(Diagnostic::error(
                    ast.span,
                    format!("`{name}` takes {n} argument{}, found {}", if n == 1 { "" } else { "s" }, args.len()),
                ));
                return false;
            }
            for a in args {
                c.emit(a);
            }
            true
        };
        if let Some(f) = F1::lookup(name) {
            if arity(self, 1) {
                self.code.push(Op::F1(f));
            }
        } else if let Some(f) = F2::lookup(name) {
            if arity(self, 2) {
                self.code.push(Op::F2(f));
            }
        } else if let Some(f) = F3::lookup(name) {
            if arity(self, 3) {
                self.code.push(Op::F3(f));
            }
        } else if let Some(r) = RandOp::lookup(name) {
            let n = if r == RandOp::Rand { 0 } else { 2 };
            if arity(self, n) {
                self.uses_rng = true;
                self.code.push(Op::Rand(r));
            }
        } else if let Some(arg) = match args {
            [Ast { kind: Node::Var(arg), .. }] => Some(arg.as_str()),
            [] => Some(""),
            _ => None,
        } {
            // Host queries such as `has(slot)` or `inside()`.
            let key = format!("{name}({arg})");
            match self.scope.variable(&key) {
                Some(i) => self.code.push(Op::Load(i)),
                None => self.unknown_function(name, name_span),
            }
        } else {
            self.unknown_function(name, name_span);
        }
    }

    fn unknown_function(&mut self, name: &str, span: crate::diag::Span) {
        let all = F1::NAMES.iter().chain(F2::NAMES).chain(F3::NAMES).chain(RandOp::NAMES).copied();
        let mut d = Diagnostic::error(span, format!("unknown function `{name}`"));
        if let Some(s) = did_you_mean(name, all) {
            d = d.with_hint(format!("did you mean `{s}`?"));
        }
        self.errors.push(d);
    }

    /// The value of a sub-tree without names or random draws.
    fn fold(&self, ast: &Ast) -> Option<f64> {
        Some(match &ast.kind {
            Node::Num(v) => *v,
            Node::Var(n) => self.constant(n)?,
            Node::Unary(UnOp::Neg, a) => -self.fold(a)?,
            Node::Unary(UnOp::Not, a) => truth(!is_true(self.fold(a)?)),
            Node::Binary(op, a, b) => bin(*op, self.fold(a)?, self.fold(b)?),
            Node::Cond(c, a, b) => {
                if is_true(self.fold(c)?) {
                    self.fold(a)?
                } else {
                    self.fold(b)?
                }
            }
            Node::Call(name, _, args) => {
                let v: Option<Vec<f64>> = args.iter().map(|a| self.fold(a)).collect();
                let v = v?;
                match (v.as_slice(), F1::lookup(name), F2::lookup(name), F3::lookup(name)) {
                    ([x], Some(f), _, _) => f.apply(*x),
                    ([x, y], _, Some(f), _) => f.apply(*x, *y),
                    ([x, y, z], _, _, Some(f)) => f.apply(*x, *y, *z),
                    _ => return None,
                }
            }
        })
    }
}

impl Compiler<'_> {
    /// A name's constant value: the scope's own constants, then the
    /// built-in ones; `None` for variables (which shadow both).
    fn constant(&self, name: &str) -> Option<f64> {
        if self.scope.variable(name).is_some() {
            return None;
        }
        self.scope.constant(name).or_else(|| builtin_constant(name))
    }
}

pub(crate) fn builtin_constant(name: &str) -> Option<f64> {
    Some(match name {
        "pi" | "PI" => std::f64::consts::PI,
        "tau" => std::f64::consts::TAU,
        "e" => std::f64::consts::E,
        "true" => 1.0,
        "false" => 0.0,
        _ => return None,
    })
}

impl Program {
    /// Evaluates on `env`. Random functions draw from a fixed stream (seed
    /// 0); use [`Program::eval_rng`] when they should vary.
    pub fn eval(&self, env: &[f64]) -> f64 {
        if self.uses_rng {
            return self.eval_rng(env, &mut Rng::from_seed(0));
        }
        self.run::<Rng>(env, None)
    }

    /// Evaluates on `env`, drawing random values from `rng`.
    pub fn eval_rng(&self, env: &[f64], rng: &mut Rng) -> f64 {
        self.run(env, Some(rng))
    }

    /// Evaluates on `env`, taking random draws from `draws` (e.g. values
    /// stored in a genome). Draws per evaluation are at most
    /// [`Program::max_draws`].
    pub fn eval_draws(&self, env: &[f64], draws: &mut impl Draws) -> f64 {
        self.run(env, Some(draws))
    }

    /// The value when the expression is a constant.
    pub fn constant(&self) -> Option<f64> {
        match self.code.as_slice() {
            [Op::Const(v)] => Some(*v),
            _ => None,
        }
    }

    /// The program's computation when it is [`Trivial`], else `None`.
    pub fn trivial(&self) -> Option<Trivial> {
        let operand = |op: &Op| match *op {
            Op::Const(v) => Some(Operand::Const(v)),
            Op::Load(i) => Some(Operand::Load(i)),
            _ => None,
        };
        match self.code.as_slice() {
            [a] => Some(Trivial::Value(operand(a)?)),
            [a, b, Op::Bin(op)] => {
                let arith = match op {
                    BinOp::Add => Arith::Add,
                    BinOp::Sub => Arith::Sub,
                    BinOp::Mul => Arith::Mul,
                    BinOp::Div => Arith::Div,
                    _ => return None,
                };
                Some(Trivial::Bin(arith, operand(a)?, operand(b)?))
            }
            _ => None,
        }
    }

    /// Whether evaluation draws random numbers.
    pub fn uses_rng(&self) -> bool {
        self.uses_rng
    }

    /// Env indices the program reads.
    pub fn loads(&self) -> impl Iterator<Item = u32> + '_ {
        self.code.iter().filter_map(|op| match op {
            Op::Load(i) => Some(*i),
            _ => None,
        })
    }

    fn max_stack(&self) -> usize {
        // Straight-line over-approximation: count pushes minus pops ignoring
        // jumps, which is safe because both branches of a conditional are
        // balanced to one value each.
        let mut depth: isize = 0;
        let mut max: isize = 0;
        for op in &self.code {
            depth += match op {
                Op::Const(_) | Op::Load(_) => 1,
                Op::Un(_) | Op::Truth | Op::F1(_) | Op::Jump(_) => 0,
                Op::Bin(_) | Op::F2(_) | Op::JumpIfFalse(_) => -1,
                Op::F3(_) => -2,
                Op::Rand(RandOp::Rand) => 1,
                Op::Rand(_) => -1,
            };
            max = max.max(depth);
        }
        max.max(1) as usize
    }

    /// The most uniform draws one evaluation can take (`normal` takes two).
    pub fn max_draws(&self) -> usize {
        self.code
            .iter()
            .map(|op| match op {
                Op::Rand(RandOp::Normal) => 2,
                Op::Rand(_) => 1,
                _ => 0,
            })
            .sum()
    }

    fn run<D: Draws + ?Sized>(&self, env: &[f64], rng: Option<&mut D>) -> f64 {
        if self.depth <= SHORT_STACK {
            self.run_on::<SHORT_STACK, D>(env, rng)
        } else {
            self.run_on::<STACK, D>(env, rng)
        }
    }

    /// [`Program::run`] on a stack of `N` values (at least the program's
    /// depth).
    fn run_on<const N: usize, D: Draws + ?Sized>(&self, env: &[f64], mut rng: Option<&mut D>) -> f64 {
        let mut stack = [0.0f64; N];
        let mut sp = 0usize;
        let mut pc = 0usize;
        while pc < self.code.len() {
            match self.code[pc] {
                Op::Const(v) => {
                    stack[sp] = v;
                    sp += 1;
                }
                Op::Load(i) => {
                    stack[sp] = env.get(i as usize).copied().unwrap_or(f64::NAN);
                    sp += 1;
                }
                Op::Un(UnOp::Neg) => stack[sp - 1] = -stack[sp - 1],
                Op::Un(UnOp::Not) => stack[sp - 1] = truth(!is_true(stack[sp - 1])),
                Op::Truth => stack[sp - 1] = truth(is_true(stack[sp - 1])),
                Op::Bin(op) => {
                    sp -= 1;
                    stack[sp - 1] = bin(op, stack[sp - 1], stack[sp]);
                }
                Op::JumpIfFalse(t) => {
                    sp -= 1;
                    if !is_true(stack[sp]) {
                        pc = t as usize;
                        continue;
                    }
                }
                Op::Jump(t) => {
                    pc = t as usize;
                    continue;
                }
                Op::F1(f) => stack[sp - 1] = f.apply(stack[sp - 1]),
                Op::F2(f) => {
                    sp -= 1;
                    stack[sp - 1] = f.apply(stack[sp - 1], stack[sp]);
                }
                Op::F3(f) => {
                    sp -= 2;
                    stack[sp - 1] = f.apply(stack[sp - 1], stack[sp], stack[sp + 1]);
                }
                Op::Rand(r) => {
                    let rng = rng.as_deref_mut().expect("eval passes an rng for random programs");
                    match r {
                        RandOp::Rand => {
                            stack[sp] = rng.next_f64();
                            sp += 1;
                        }
                        RandOp::Uniform => {
                            sp -= 1;
                            stack[sp - 1] = uniform_in(rng, stack[sp - 1], stack[sp]);
                        }
                        RandOp::Normal => {
                            sp -= 1;
                            stack[sp - 1] += stack[sp] * standard_normal(rng);
                        }
                    }
                }
            }
            pc += 1;
        }
        stack[0]
    }
}
