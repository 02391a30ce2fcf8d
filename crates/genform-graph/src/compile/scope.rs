//! Names visible in a production's formulas, and the env slots they get.
//!
//! `A.x`, `A.y`, `A.degree`, `A.generation` and `A.attr` for a mother
//! vertex `A`; `e.attr` and `e.generation` for a mother edge `e`; `A` and
//! named vectors as vectors (`v.x`, `v.y` their components); variables;
//! globals. Slots are handed out on first use, so a match loads only what
//! the production's formulas read.

use crate::mother::Load;
use crate::names::Interner;
use genform_core::expr::Scope;
use genform_core::expr::vec2::VecScope;
use std::cell::RefCell;
use std::collections::HashMap;

/// What fills an env slot.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) enum Owner {
    /// Global formula `i` (per run).
    Global(usize),
    /// A variable evaluated once per run.
    RunVar,
    /// A variable drawn per application (after matching).
    AppVar,
    Vertex(usize, Load),
    Edge(usize, Load),
    /// Named pair vector `i`, x then y.
    Pair(usize),
}

/// A global: a constant folded into formulas, or a per-run formula.
#[derive(Clone, Debug)]
pub(crate) enum GlobalInfo {
    Const(f64),
    Formula(usize),
}

#[derive(Clone, Debug)]
pub(crate) enum VecDef {
    Point(usize),
    Pair(usize),
}

#[derive(Default)]
pub(crate) struct Slots {
    pub(crate) by_name: HashMap<String, u32>,
    pub(crate) owners: Vec<Owner>,
}

impl Slots {
    pub(crate) fn alloc(&mut self, name: &str, owner: Owner) -> u32 {
        let slot = self.owners.len() as u32;
        self.owners.push(owner);
        self.by_name.insert(name.to_string(), slot);
        slot
    }
}

pub(crate) struct ProdScope<'a> {
    pub(crate) globals: &'a [(String, GlobalInfo)],
    pub(crate) attrs: &'a Interner,
    /// Mother vertex and edge names.
    pub(crate) vertices: Vec<String>,
    pub(crate) edges: Vec<String>,
    pub(crate) vectors: Vec<(String, VecDef)>,
    /// Pair vectors' ends (mother vertex indices).
    pub(crate) pairs: Vec<(usize, usize)>,
    /// Variables now visible: name, slot.
    pub(crate) vars: Vec<(String, u32)>,
    pub(crate) slots: RefCell<Slots>,
}

impl ProdScope<'_> {
    fn vertex(&self, name: &str) -> Option<usize> {
        self.vertices.iter().position(|v| v == name)
    }

    fn edge(&self, name: &str) -> Option<usize> {
        self.edges.iter().position(|e| e == name)
    }

    fn vector_def(&self, name: &str) -> Option<&VecDef> {
        self.vectors.iter().find(|(n, _)| n == name).map(|(_, d)| d)
    }

    /// Declares a variable; returns its slot.
    pub(crate) fn declare(&mut self, name: &str, per_run: bool) -> u32 {
        let slot = self
            .slots
            .get_mut()
            .alloc(&format!("\0var {}", self.vars.len()), if per_run { Owner::RunVar } else { Owner::AppVar });
        self.vars.push((name.to_string(), slot));
        slot
    }

    /// What a name would resolve to, allocating its slot.
    fn resolve(&self, name: &str) -> Option<u32> {
        if let Some((_, slot)) = self.vars.iter().rev().find(|(n, _)| n == name) {
            return Some(*slot);
        }
        if let Some(&slot) = self.slots.borrow().by_name.get(name) {
            return Some(slot);
        }
        let owner = match name.split_once('.') {
            None => match self.globals.iter().find(|(n, _)| n == name)?.1 {
                GlobalInfo::Formula(i) => Owner::Global(i),
                GlobalInfo::Const(_) => return None,
            },
            Some((base, field)) => {
                if let Some(v) = self.vertex(base) {
                    let load = match field {
                        "x" => Load::X,
                        "y" => Load::Y,
                        "degree" => Load::Degree,
                        "generation" => Load::Generation,
                        a => Load::Attr(self.attrs.get(a).filter(|&id| id != 0)?),
                    };
                    Owner::Vertex(v, load)
                } else if let Some(e) = self.edge(base) {
                    let load = match field {
                        "generation" => Load::Generation,
                        a => Load::Attr(self.attrs.get(a).filter(|&id| id != 0)?),
                    };
                    Owner::Edge(e, load)
                } else {
                    match (self.vector_def(base)?, field) {
                        (VecDef::Point(v), "x" | "y") => {
                            return self.resolve(&format!("{}.{field}", self.vertices[*v]));
                        }
                        (VecDef::Pair(i), "x" | "y") => {
                            let i = *i;
                            let mut slots = self.slots.borrow_mut();
                            let x = slots.alloc(&format!("{base}.x"), Owner::Pair(i));
                            let y = slots.alloc(&format!("{base}.y"), Owner::Pair(i));
                            return Some(if field == "x" { x } else { y });
                        }
                        _ => return None,
                    }
                }
            }
        };
        Some(self.slots.borrow_mut().alloc(name, owner))
    }
}

impl Scope for ProdScope<'_> {
    fn variable(&self, name: &str) -> Option<u32> {
        self.resolve(name)
    }

    fn constant(&self, name: &str) -> Option<f64> {
        match self.globals.iter().find(|(n, _)| n == name)?.1 {
            GlobalInfo::Const(v) => Some(v),
            GlobalInfo::Formula(_) => None,
        }
    }

    fn names(&self) -> Vec<String> {
        let attrs: Vec<&str> = self.attrs.all().skip(1).collect();
        let mut out: Vec<String> = Vec::new();
        out.extend(self.vars.iter().map(|(n, _)| n.clone()));
        out.extend(self.globals.iter().map(|(n, _)| n.clone()));
        out.extend(self.vectors.iter().flat_map(|(n, _)| [n.clone(), format!("{n}.x"), format!("{n}.y")]));
        for v in &self.vertices {
            out.push(v.clone());
            for f in ["x", "y", "degree", "generation"].into_iter().chain(attrs.iter().copied()) {
                out.push(format!("{v}.{f}"));
            }
        }
        for e in &self.edges {
            for f in ["generation"].into_iter().chain(attrs.iter().copied()) {
                out.push(format!("{e}.{f}"));
            }
        }
        out
    }
}

impl VecScope for ProdScope<'_> {
    fn vector(&self, name: &str) -> Option<[String; 2]> {
        if self.vertex(name).is_some() || self.vector_def(name).is_some() {
            Some([format!("{name}.x"), format!("{name}.y")])
        } else {
            None
        }
    }
}

/// The scope of global formulas: the globals before them.
pub(crate) struct GlobalScope<'a> {
    pub(crate) before: &'a [(String, GlobalInfo)],
}

impl Scope for GlobalScope<'_> {
    fn variable(&self, name: &str) -> Option<u32> {
        match self.before.iter().find(|(n, _)| n == name)?.1 {
            GlobalInfo::Formula(i) => Some(i as u32),
            GlobalInfo::Const(_) => None,
        }
    }

    fn constant(&self, name: &str) -> Option<f64> {
        match self.before.iter().find(|(n, _)| n == name)?.1 {
            GlobalInfo::Const(v) => Some(v),
            GlobalInfo::Formula(_) => None,
        }
    }

    fn names(&self) -> Vec<String> {
        self.before.iter().map(|(n, _)| n.clone()).collect()
    }
}

impl VecScope for GlobalScope<'_> {
    fn vector(&self, _name: &str) -> Option<[String; 2]> {
        None
    }
}
