//! Which module parameters of an `.lpy` file hold Python floats or
//! booleans.
//!
//! genform's modules carry `f64` parameters; L-Py's carry Python objects,
//! and L-Py prints a float as `A(6.0)`, an int as `A(6)` and a boolean as
//! `A(True)`. The translation records every module it writes into the
//! derived string (the axiom, productions and decomposition, not the
//! interpretation) with its argument expressions and the names they see;
//! [`Facts::solve`] types every parameter slot (module, arity, position)
//! step by step: step 0 is the axiom; each step joins what the
//! productions write, reading their predecessors' slots as the step before
//! left them, with the modules no rule always rewrites and what
//! decomposition writes, until the types settle (beyond 16 steps, the
//! fixed point over all writers). Python's rules: `/`, float
//! literals, `math` functions and `random()` give floats; `+ - * // %`
//! give a float when one side is; `floor`, `int`, `round(x)`, `randint`
//! and `getIterationNb()` give ints; comparisons and `not` give booleans.
//! A slot prints as a float or a boolean only when every writer gives one;
//! anything unknown (a string, a name the reader does not type) or mixed
//! leaves the slot as before: whole values print as ints.

use super::pyexpr::{MATH, MAX_DEPTH, Names, Py, substitute};
use crate::alphabet::{PyKinds, PyParams};
use crate::turtle::query::Query;
use std::collections::HashMap;

/// Steps typed one by one before the types must have settled.
const MAX_STEPS: usize = 16;

/// The type of a Python value, as far as printing goes.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum Ty {
    /// Nothing written yet (the bottom of the fixed point).
    Unset,
    Int,
    Float,
    Bool,
    /// Mixed or unknown.
    Any,
}

impl Ty {
    fn join(self, other: Ty) -> Ty {
        match (self, other) {
            (Ty::Unset, t) | (t, Ty::Unset) => t,
            (a, b) if a == b => a,
            _ => Ty::Any,
        }
    }

    /// The type in arithmetic: `True + 1` is an int.
    fn number(self) -> Ty {
        if self == Ty::Bool { Ty::Int } else { self }
    }
}

/// A parameter slot: module name, arity, position.
pub(super) type Slot = (String, usize, usize);

/// The names a production's expressions see besides the module-level ones.
#[derive(Debug, Default)]
pub(super) struct Scope {
    /// Predecessor parameters and their slots.
    pub params: Vec<(String, Slot)>,
    /// The body's assignments (`x += 1` as `x + 1`).
    pub locals: Vec<(String, Py)>,
    /// A decomposition rule (not a production).
    pub decomposition: bool,
}

/// A module written into the string, with its arguments.
#[derive(Debug)]
struct Use {
    name: String,
    args: Vec<Py>,
    /// The production's scope; `None` at module level (the axiom).
    scope: Option<usize>,
}

/// What the translation records for typing.
#[derive(Debug, Default)]
pub(super) struct Facts {
    /// Every assignment of a module-level name: constants, the editor's
    /// scalars, the globals hooks and bodies assign.
    pub consts: Vec<(String, Py)>,
    scopes: Vec<Scope>,
    uses: Vec<Use>,
    /// Modules a production rewrites wherever they stand (an arrow rule
    /// of group 0 whose predecessor is the module alone): after a step,
    /// none of the axiom's is left.
    rewritten: Vec<(String, usize)>,
}

impl Facts {
    /// Adds a production's scope; its id for [`Facts::write`].
    pub fn scope(&mut self, scope: Scope) -> usize {
        self.scopes.push(scope);
        self.scopes.len() - 1
    }

    /// Records the module `name(args…)` written into the string.
    pub fn write(&mut self, name: &str, args: Vec<Py>, scope: Option<usize>) {
        self.uses.push(Use { name: name.to_string(), args, scope });
    }

    /// Records that a production rewrites every `name` of `arity`.
    pub fn always_rewritten(&mut self, name: &str, arity: usize) {
        self.rewritten.push((name.to_string(), arity));
    }

    /// The float and boolean parameters of every (module name, arity)
    /// written with parameters, step by step.
    pub fn solve(&self, names: &Names) -> Vec<(String, usize, PyParams)> {
        let (no_slots, no_locals) = (HashMap::new(), HashMap::new());
        let consts = assigned(&self.consts, |known, e| {
            Typer { names, slots: &no_slots, params: &[], locals: &no_locals, consts: known }.ty(e, 0)
        });
        let production = |u: &Use| u.scope.and_then(|s| self.scopes.get(s)).is_some_and(|s| !s.decomposition);
        let decomposition = |u: &Use| u.scope.and_then(|s| self.scopes.get(s)).is_some_and(|s| s.decomposition);
        // Step 0 is the axiom; every step then rewrites the modules that
        // were there, keeps the others unless a rule always rewrites them,
        // and decomposes.
        let decompose = |slots: &mut HashMap<Slot, Ty>| {
            while self.join_uses(names, &consts, slots, decomposition) {}
        };
        let mut first = HashMap::new();
        self.join_uses(names, &consts, &mut first, |u| u.scope.is_none());
        let mut steps = vec![first];
        let stable = loop {
            let prev = steps.last().expect("step 0");
            let mut next: HashMap<Slot, Ty> = prev
                .iter()
                .filter(|((n, a, _), _)| !self.rewritten.iter().any(|(rn, ra)| rn == n && ra == a))
                .map(|(k, t)| (k.clone(), *t))
                .collect();
            self.join_uses_with(names, &consts, prev, &mut next, production);
            decompose(&mut next);
            if next == *prev {
                break true;
            }
            if steps.len() > MAX_STEPS {
                break false;
            }
            steps.push(next);
        };
        if !stable {
            // No settling: every later step as one, the fixed point over all
            // writers (every step's types are in it).
            let mut all = steps[0].clone();
            while self.join_uses(names, &consts, &mut all, |_| true) {}
            steps.push(all);
        }
        let mut keys: Vec<&Slot> = steps.iter().flat_map(HashMap::keys).collect();
        keys.sort();
        keys.dedup();
        let mut out: Vec<(String, usize, PyParams)> = Vec::new();
        for slot in keys {
            let (name, arity, i) = slot;
            if out.last().is_none_or(|(n, a, _)| n != name || a != arity) {
                out.push((name.clone(), *arity, PyParams { steps: vec![PyKinds::default(); steps.len()] }));
            }
            let p = &mut out.last_mut().expect("pushed").2;
            let bit = if *i < 64 { 1u64 << i } else { 0 };
            for (kinds, map) in p.steps.iter_mut().zip(&steps) {
                match map.get(slot) {
                    Some(Ty::Float) => kinds.floats |= bit,
                    Some(Ty::Bool) => kinds.bools |= bit,
                    _ => {}
                }
            }
        }
        out
    }

    /// Joins the types the uses `keep` accepts write into `slots`, reading
    /// predecessors from `slots` itself; whether any slot changed.
    fn join_uses(
        &self,
        names: &Names,
        consts: &HashMap<String, Ty>,
        slots: &mut HashMap<Slot, Ty>,
        keep: impl Fn(&Use) -> bool,
    ) -> bool {
        let read = slots.clone();
        self.join_uses_with(names, consts, &read, slots, keep)
    }

    /// Joins the types the uses `keep` accepts write into `slots`, reading
    /// predecessors from `read`; whether any slot changed.
    fn join_uses_with(
        &self,
        names: &Names,
        consts: &HashMap<String, Ty>,
        read: &HashMap<Slot, Ty>,
        slots: &mut HashMap<Slot, Ty>,
        keep: impl Fn(&Use) -> bool,
    ) -> bool {
        let none = HashMap::new();
        let mut locals: HashMap<usize, HashMap<String, Ty>> = HashMap::new();
        let mut changed = false;
        for u in self.uses.iter().filter(|u| keep(u)) {
            let (params, local) = match u.scope.and_then(|id| Some((id, self.scopes.get(id)?))) {
                Some((id, scope)) => {
                    let local = locals.entry(id).or_insert_with(|| {
                        assigned(&scope.locals, |known, e| {
                            Typer { names, slots: read, params: &scope.params, locals: known, consts }.ty(e, 0)
                        })
                    });
                    (&scope.params[..], &*local)
                }
                None => (&[][..], &none),
            };
            let typer = Typer { names, slots: read, params, locals: local, consts };
            for (i, a) in u.args.iter().enumerate() {
                let t = typer.ty(a, 0);
                let slot = (u.name.clone(), u.args.len(), i);
                let old = slots.get(&slot).copied().unwrap_or(Ty::Unset);
                let new = old.join(t);
                if new != old {
                    slots.insert(slot, new);
                    changed = true;
                }
            }
        }
        changed
    }
}

/// The types of the names `assigns` assigns, to a fixed point: each the
/// join of what is assigned to it, where a name read in an assignment
/// (its own, `x = x + 1`, included) is what is known of it so far.
fn assigned(assigns: &[(String, Py)], ty: impl Fn(&HashMap<String, Ty>, &Py) -> Ty) -> HashMap<String, Ty> {
    let mut types: HashMap<String, Ty> = assigns.iter().map(|(n, _)| (n.clone(), Ty::Unset)).collect();
    // Names only rise (join), each at most three times.
    loop {
        let known = types.clone();
        let mut changed = false;
        for (n, e) in assigns {
            let t = ty(&known, e);
            if let Some(old) = types.get_mut(n) {
                let new = old.join(t);
                changed |= new != *old;
                *old = new;
            }
        }
        if !changed {
            return types;
        }
    }
}

/// Types expressions in one scope against the slots known so far.
struct Typer<'a> {
    names: &'a Names,
    slots: &'a HashMap<Slot, Ty>,
    /// The predecessor's parameters (none at module level).
    params: &'a [(String, Slot)],
    /// The body's assigned names, as typed so far.
    locals: &'a HashMap<String, Ty>,
    /// The module-level names, as typed so far.
    consts: &'a HashMap<String, Ty>,
}

impl Typer<'_> {
    fn ty(&self, e: &Py, depth: usize) -> Ty {
        if depth > MAX_DEPTH {
            return Ty::Any;
        }
        match e {
            Py::Num(n, _) => {
                if n.contains(['.', 'e', 'E']) && !n.starts_with("0x") {
                    Ty::Float
                } else {
                    Ty::Int
                }
            }
            Py::Name(n, _) => self.name(n),
            Py::Neg(_, x) => self.ty(x, depth + 1).number(),
            Py::Not(..) | Py::Cmp(..) => Ty::Bool,
            Py::Cond(_, a, b) => self.ty(a, depth + 1).join(self.ty(b, depth + 1)),
            Py::Bin(op, _, a, b) => {
                let (ta, tb) = (self.ty(a, depth + 1), self.ty(b, depth + 1));
                match *op {
                    "and" | "or" => ta.join(tb),
                    "/" => Ty::Float,
                    "**" => power(ta, tb, matches!(**b, Py::Num(..))),
                    _ => arithmetic(ta, tb),
                }
            }
            Py::Call(name, _, args) => self.call(name, args, depth),
        }
    }

    fn name(&self, n: &str) -> Ty {
        match n {
            "True" | "False" => return Ty::Bool,
            "pi" | "e" | "math.pi" | "math.e" => return Ty::Float,
            _ => {}
        }
        let local = self.locals.get(n).copied();
        if let Some((_, slot)) = self.params.iter().find(|(k, _)| k == n) {
            // The turtle fills a query's x, y, z with floats. A parameter
            // may keep its value past a conditional assignment.
            let query = Query::of(&slot.0).is_some() && slot.1 == 3;
            let read = if query { Ty::Float } else { self.slots.get(slot).copied().unwrap_or(Ty::Unset) };
            return local.unwrap_or(Ty::Unset).join(read);
        }
        local.or_else(|| self.consts.get(n).copied()).unwrap_or(Ty::Any)
    }

    fn call(&self, name: &str, args: &[Py], depth: usize) -> Ty {
        let (module, f) = self.names.module_of(name);
        if module.is_empty()
            && let Some(func) = self.names.funcs.iter().find(|func| func.name == name)
        {
            return match &func.body {
                Ok(body) if args.len() == func.params.len() => {
                    self.ty(&substitute(body, &func.params, args), depth + 1)
                }
                _ => Ty::Any,
            };
        }
        let arg = |this: &Self, i: usize| args.get(i).map_or(Ty::Any, |a| this.ty(a, depth + 1));
        match (module, f) {
            ("", "getIterationNb" | "getGroup" | "int" | "len") | ("random" | "", "randint") => Ty::Int,
            ("math" | "", "floor" | "ceil" | "trunc") => Ty::Int,
            ("random" | "", "random" | "uniform" | "gauss" | "normalvariate") => Ty::Float,
            ("", "float") => Ty::Float,
            ("", "round") if args.len() == 1 => Ty::Int,
            ("", "round" | "abs") => arg(self, 0).number(),
            ("", "bool") => Ty::Bool,
            ("", "min" | "max") => (0..args.len()).fold(Ty::Unset, |t, i| t.join(arg(self, i))),
            ("", "pow") => power(arg(self, 0), arg(self, 1), false),
            ("", "fmod") | ("math", "fmod") => Ty::Float,
            ("math" | "", _) if MATH.iter().any(|(p, _)| *p == f) => Ty::Float,
            _ => Ty::Any,
        }
    }
}

/// `a ** b`: a float when either side is; ints give an int only for a
/// literal power (a negative one is written `-n`, a float).
fn power(a: Ty, b: Ty, literal: bool) -> Ty {
    match (a.number(), b.number()) {
        (Ty::Unset, _) | (_, Ty::Unset) => Ty::Unset,
        (Ty::Float, _) | (_, Ty::Float) => Ty::Float,
        (Ty::Int, Ty::Int) if literal => Ty::Int,
        _ => Ty::Any,
    }
}

/// `+ - * // %`: a float when either side is, an int when both are.
fn arithmetic(a: Ty, b: Ty) -> Ty {
    match (a.number(), b.number()) {
        (Ty::Unset, _) | (_, Ty::Unset) => Ty::Unset,
        (Ty::Float, _) | (_, Ty::Float) => Ty::Float,
        (Ty::Int, Ty::Int) => Ty::Int,
        _ => Ty::Any,
    }
}
