//! From syntax tree to [`BoxGrammar`]: names resolved, formulas compiled,
//! operations flattened into an arena, every problem reported.

use crate::derive::MAX_VOLUME;
use crate::formula::Formulas;
use crate::grammar::{
    AIR, Alternative, BoxGrammar, DeriveLimits, Guard, Material, Op, OpId, Paint, Rule, RuleId, Side, Site, Support,
};
use crate::known_blocks::{self, BlockCheck, Known};
use crate::observe::{BlockType, TypeTable};
use crate::syntax::{self, AltSyn, Ident, Item, OpSyn, RuleSyn, SiteValue};
use genform_core::diag::{Diagnostic, SourceFile, Span};
use genform_core::expr::did_you_mean;
use genform_core::{BlockState, Diagnostics};
use glam::IVec3;
use std::collections::HashMap;

/// Compiles a `.bsg` file. Returns the grammar and its warnings, or every
/// error found.
pub fn compile(file: &SourceFile) -> Result<(BoxGrammar, Diagnostics), Diagnostics> {
    let mut diags = Diagnostics::new(file.clone());
    let (items, errors) = syntax::parse(&file.text);
    if !errors.is_empty() {
        diags.items = errors;
        return Err(diags);
    }
    // The opt-out applies to the whole file, wherever it is written.
    let allow = items.iter().find_map(|i| if let Item::AllowUnknownBlocks(s) = i { Some(*s) } else { None });
    let mut c = Compiler {
        file,
        check: BlockCheck::new(allow),
        out: Vec::new(),
        types: TypeTable::new(),
        formulas: Formulas::for_file(file),
        rule_ids: HashMap::new(),
        rule_spans: Vec::new(),
        materials: HashMap::new(),
        material_list: Vec::new(),
        blocks: vec![BlockState::air()],
        block_ids: HashMap::new(),
        ops: Vec::new(),
        used: Vec::new(),
        supports: Vec::new(),
        site: None,
        site_span: None,
    };
    c.block_ids.insert(BlockState::air(), AIR);
    let grammar = c.run(&items);
    // Ids named by groups and observers, first use of each spelling.
    for (state, span) in std::mem::take(&mut c.types.named_ids) {
        c.check.check(&state, span, &mut c.out);
    }
    c.check.finish(&mut c.out);
    diags.items = c.out;
    match grammar {
        Some(g) if !diags.has_errors() => Ok((g, diags)),
        _ => Err(diags),
    }
}

struct Compiler<'f> {
    file: &'f SourceFile,
    /// Block ids against Minecraft's lists.
    check: BlockCheck,
    out: Vec<Diagnostic>,
    types: TypeTable,
    formulas: Formulas,
    rule_ids: HashMap<String, RuleId>,
    rule_spans: Vec<Span>,
    materials: HashMap<String, u32>,
    material_list: Vec<Material>,
    blocks: Vec<BlockState>,
    block_ids: HashMap<BlockState, u32>,
    ops: Vec<Op>,
    /// Rules each rule invokes, for reachability.
    used: Vec<Vec<RuleId>>,
    supports: Vec<Support>,
    site: Option<Site>,
    /// Where `site` was first declared, valid or not.
    site_span: Option<Span>,
}

const LIMIT_KEYS: &[&str] = &["applications", "backtracks", "depth"];

impl Compiler<'_> {
    fn line(&self, span: Span) -> u32 {
        self.file.line_col(span.start).0 as u32
    }

    fn run(&mut self, items: &[Item]) -> Option<BoxGrammar> {
        let mut name = String::new();
        let mut axiom: Option<&Ident> = None;
        let mut limits = DeriveLimits::default();
        let mut default_box: Option<(Option<(IVec3, IVec3)>, Span)> = None;
        let mut default_world: Option<(&String, Span)> = None;
        let mut allow_unknown: Option<Span> = None;
        let rules: Vec<&RuleSyn> =
            items.iter().filter_map(|i| if let Item::Rule(r) = i { Some(r) } else { None }).collect();
        for r in &rules {
            if let Some(&prev) = self.rule_ids.get(&r.name.name) {
                self.out.push(
                    Diagnostic::error(r.name.span, format!("rule `{}` is defined twice", r.name.name))
                        .with_label(self.rule_spans[prev as usize], "first defined here")
                        .with_hint("put all alternatives of a rule in one block"),
                );
                continue;
            }
            self.rule_ids.insert(r.name.name.clone(), self.rule_spans.len() as RuleId);
            self.rule_spans.push(r.name.span);
        }
        for item in items {
            match item {
                Item::Grammar(n, span) => {
                    if !name.is_empty() {
                        self.out.push(Diagnostic::error(*span, "the grammar is named twice"));
                    }
                    name = n.clone();
                }
                Item::Axiom(a) => {
                    if let Some(prev) = axiom {
                        self.out.push(
                            Diagnostic::error(a.span, "the axiom is given twice").with_label(prev.span, "first here"),
                        );
                    }
                    axiom = Some(a);
                }
                Item::Limits(list) => self.limits(list, &mut limits),
                Item::Box(corners, span) => {
                    if let Some((_, prev)) = default_box {
                        self.out
                            .push(Diagnostic::error(*span, "the box is given twice").with_label(prev, "first here"));
                    }
                    default_box = Some((self.default_box(corners, *span), *span));
                }
                Item::World(path, span) => {
                    if let Some((_, prev)) = default_world {
                        self.out
                            .push(Diagnostic::error(*span, "the world is given twice").with_label(prev, "first here"));
                    }
                    if path.trim().is_empty() {
                        self.out.push(
                            Diagnostic::error(*span, "the world's path is empty")
                                .with_hint("name a region file (r.X.Z.mca) or a folder of them"),
                        );
                    }
                    default_world = Some((path, *span));
                }
                Item::AllowUnknownBlocks(span) => {
                    if let Some(prev) = allow_unknown {
                        self.out.push(
                            Diagnostic::error(*span, "`allow_unknown_blocks` is given twice")
                                .with_label(prev, "first here"),
                        );
                    }
                    allow_unknown = Some(*span);
                }
                Item::Group(n, members) => {
                    if self.rule_ids.contains_key(&n.name) {
                        self.out.push(Diagnostic::error(n.span, format!("`{}` is already a rule", n.name)));
                    }
                    self.types.define_group(n, members, &mut self.out);
                }
                Item::Material(n, entries) => self.material(n, entries),
                Item::Support(side, members) => self.support(side, members),
                Item::Site(entries, span) => self.site(entries, *span),
                Item::Let(n, e) => self.formulas.define(n, e, &mut self.types, &mut self.out),
                Item::Rule(_) => {}
            }
        }
        // Rules compile in order of their ids (first definitions only).
        let mut compiled: Vec<Option<Rule>> = vec![None; self.rule_spans.len()];
        self.used = vec![Vec::new(); self.rule_spans.len()];
        for r in &rules {
            let id = self.rule_ids[&r.name.name];
            if self.rule_spans[id as usize] != r.name.span {
                continue;
            }
            compiled[id as usize] = Some(self.rule(id, r));
        }
        let Some(first) = rules.first() else {
            self.out.push(
                Diagnostic::error(Span::new(0, 0), "the grammar has no rules")
                    .with_hint("add a rule, e.g. `House { fill oak_planks }`"),
            );
            return None;
        };
        let axiom_id = match axiom {
            Some(a) => match self.rule_ids.get(&a.name) {
                Some(&id) => id,
                None => {
                    self.unknown_rule(a);
                    return None;
                }
            },
            None => self.rule_ids[&first.name.name],
        };
        self.warn_unreachable(axiom_id);
        let rules: Vec<Rule> = compiled.into_iter().collect::<Option<Vec<_>>>()?;
        let start = self.push(Op::Rule(axiom_id));
        Some(BoxGrammar {
            name,
            axiom: axiom_id,
            start,
            rules,
            ops: std::mem::take(&mut self.ops),
            blocks: std::mem::take(&mut self.blocks),
            materials: std::mem::take(&mut self.material_list),
            types: self.types.types.clone(),
            slots: self.formulas.slots.clone(),
            limits,
            default_box: default_box.and_then(|b| b.0),
            default_world: default_world.map(|w| w.0.clone()),
            supports: std::mem::take(&mut self.supports),
            site: self.site.take(),
        })
    }

    /// Checks the corners of `box …;`: six whole numbers making a box of at
    /// most [`MAX_VOLUME`] cells.
    fn default_box(&mut self, corners: &[(f64, Span)], span: Span) -> Option<(IVec3, IVec3)> {
        if corners.len() != 6 {
            self.out.push(
                Diagnostic::error(span, format!("a box has six corner coordinates, found {}", corners.len()))
                    .with_hint("write `box x0, y0, z0, x1, y1, z1;` (two opposite corners, inclusive)"),
            );
            return None;
        }
        let mut v = [0i32; 6];
        for (out, &(c, cs)) in v.iter_mut().zip(corners) {
            // Within ±2^30 so that sizes and `max + 1` stay in i32.
            if c.fract() != 0.0 || c.abs() > (1 << 30) as f64 {
                self.out
                    .push(Diagnostic::error(cs, "a corner coordinate must be a whole number (at most 2^30 in size)"));
                return None;
            }
            *out = c as i32;
        }
        let (a, b) = (IVec3::new(v[0], v[1], v[2]), IVec3::new(v[3], v[4], v[5]));
        let (min, max) = (a.min(b), a.max(b) + IVec3::ONE);
        let size = (max - min).as_i64vec3();
        // Up to 2^31 a side: the product needs 128 bits.
        let volume = size.x as u128 * size.y as u128 * size.z as u128;
        if volume > MAX_VOLUME as u128 {
            self.out.push(
                Diagnostic::error(
                    span,
                    format!(
                        "the box of {}×{}×{} = {volume} cells is larger than the {MAX_VOLUME} cells supported",
                        size.x, size.y, size.z
                    ),
                )
                .with_hint("the result and each observer table take 4 bytes a cell; choose a smaller box"),
            );
            return None;
        }
        Some((min, max))
    }

    fn limits(&mut self, list: &[(Ident, f64, Span)], limits: &mut DeriveLimits) {
        for (key, v, vs) in list {
            if !LIMIT_KEYS.contains(&key.name.as_str()) {
                let mut d = Diagnostic::error(key.span, format!("unknown limit `{}`", key.name));
                d = match did_you_mean(&key.name, LIMIT_KEYS.iter().copied()) {
                    Some(s) => d.with_hint(format!("did you mean `{s}`?")),
                    None => d.with_hint("limits are `applications`, `backtracks` and `depth`"),
                };
                self.out.push(d);
                continue;
            }
            if v.fract() != 0.0 || *v < 1.0 || *v > 1e15 {
                self.out.push(Diagnostic::error(*vs, format!("`{}` needs a whole number of at least 1", key.name)));
                continue;
            }
            match key.name.as_str() {
                "applications" => limits.applications = *v as u64,
                "backtracks" => limits.backtracks = *v as u64,
                _ => limits.depth = v.min(u32::MAX as f64) as u32,
            }
        }
    }

    fn material(&mut self, name: &Ident, entries: &[syntax::MixEntry]) {
        if self.materials.contains_key(&name.name) {
            self.out.push(Diagnostic::error(name.span, format!("material `{}` is defined twice", name.name)));
            return;
        }
        let mut m = Material { blocks: Vec::new(), weights: Vec::new() };
        for e in entries {
            if !(e.weight.is_finite() && e.weight > 0.0) {
                self.out.push(Diagnostic::error(
                    e.weight_span.unwrap_or(e.block.span),
                    "a mix weight must be a positive number",
                ));
                continue;
            }
            if self.materials.contains_key(&e.block.name) {
                self.out.push(
                    Diagnostic::error(e.block.span, "a material cannot contain another material")
                        .with_hint("list the blocks themselves"),
                );
                continue;
            }
            match BlockState::parse(&e.block.name) {
                Ok(b) => {
                    self.check.check(&b, e.block.span, &mut self.out);
                    m.blocks.push(self.block(b));
                    m.weights.push(e.weight);
                }
                Err(msg) => self.out.push(Diagnostic::error(e.block.span, msg)),
            }
        }
        self.materials.insert(name.name.clone(), self.material_list.len() as u32);
        self.material_list.push(m);
    }

    /// `support SIDE members;`: members are kinds, groups, block ids or
    /// materials (their blocks).
    fn support(&mut self, side: &Ident, members: &[Ident]) {
        let side = match side.name.as_str() {
            "above" => Side::Above,
            "below" => Side::Below,
            "rooted" => Side::Rooted,
            _ => Side::Beside,
        };
        let names: Vec<&str> = members.iter().map(|m| m.name.as_str()).collect();
        let mut ty = BlockType::empty(&names.join(", "));
        for m in members {
            if let Some(&i) = self.materials.get(&m.name) {
                let blocks = &self.material_list[i as usize].blocks;
                ty.states.extend(blocks.iter().map(|&b| self.blocks[b as usize].clone()));
                continue;
            }
            match self.types.resolve(m) {
                Ok(id) => ty.absorb(&self.types.types[id as usize]),
                Err(d) => self.out.push(d),
            }
        }
        self.supports.push(Support { side, ty });
    }

    /// `site foundation = B, yard = N;`: `foundation` is required, `yard`
    /// is 0 unless given.
    fn site(&mut self, entries: &[(Ident, SiteValue)], span: Span) {
        if let Some(prev) = self.site_span {
            self.out.push(Diagnostic::error(span, "the site is given twice").with_label(prev, "first here"));
            return;
        }
        self.site_span = Some(span);
        let (mut foundation, mut yard) = (None, 0);
        for (key, value) in entries {
            match (key.name.as_str(), value) {
                ("foundation", SiteValue::Block(b)) => foundation = self.paint(b),
                ("yard", SiteValue::Number(v, vs)) => {
                    if v.fract() != 0.0 || !(0.0..=64.0).contains(v) {
                        self.out.push(
                            Diagnostic::error(*vs, "`yard` needs a whole number of columns from 0 to 64")
                                .with_hint("`yard = 1` keeps one column around the building clear and paved"),
                        );
                    }
                    yard = v.clamp(0.0, 64.0) as i32;
                }
                ("foundation", SiteValue::Number(_, vs)) => self.out.push(
                    Diagnostic::error(*vs, "`foundation` needs a block or a material")
                        .with_hint("e.g. `site foundation = cobblestone, yard = 1;`"),
                ),
                ("yard", SiteValue::Block(b)) => self.out.push(
                    Diagnostic::error(b.span, "`yard` needs a whole number of columns")
                        .with_hint("e.g. `site foundation = cobblestone, yard = 1;`"),
                ),
                (other, _) => {
                    let d = Diagnostic::error(key.span, format!("unknown site setting `{other}`"));
                    self.out.push(match did_you_mean(other, ["foundation", "yard"]) {
                        Some(s) => d.with_hint(format!("did you mean `{s}`?")),
                        None => d.with_hint("a site takes `foundation = BLOCK` and `yard = N`"),
                    });
                }
            }
        }
        match foundation {
            Some(foundation) => self.site = Some(Site { foundation, yard }),
            None if !entries.iter().any(|(k, _)| k.name == "foundation") => self.out.push(
                Diagnostic::error(span, "the site has no foundation")
                    .with_hint("name what it is built of: `site foundation = cobblestone;`"),
            ),
            None => {}
        }
    }

    fn block(&mut self, b: BlockState) -> u32 {
        if let Some(&i) = self.block_ids.get(&b) {
            return i;
        }
        let i = self.blocks.len() as u32;
        self.block_ids.insert(b.clone(), i);
        self.blocks.push(b);
        i
    }

    fn push(&mut self, op: Op) -> OpId {
        self.ops.push(op);
        (self.ops.len() - 1) as OpId
    }

    fn rule(&mut self, id: RuleId, r: &RuleSyn) -> Rule {
        if r.alts.is_empty() {
            self.out.push(
                Diagnostic::error(r.name.span, format!("rule `{}` has no alternatives", r.name.name))
                    .with_hint("add one, e.g. `{ skip }`"),
            );
        }
        if r.alts.len() > u16::MAX as usize {
            self.out.push(Diagnostic::error(r.name.span, format!("rule `{}` has too many alternatives", r.name.name)));
        }
        let mut alternatives = Vec::new();
        let mut else_seen: Option<Span> = None;
        let mut always: Option<Span> = None;
        for a in &r.alts {
            if let Some(alt) = self.alternative(id, a, &mut else_seen, &mut always) {
                alternatives.push(alt);
            }
        }
        if let (Some(e), Some(a)) = (else_seen, always) {
            self.out.push(
                Diagnostic::warning(e, "this `else` is never used")
                    .with_label(a, "this alternative always applies")
                    .with_hint("`else` applies only when no other alternative's condition holds"),
            );
        }
        Rule { name: r.name.name.clone(), alternatives }
    }

    fn alternative(
        &mut self,
        id: RuleId,
        a: &AltSyn,
        else_seen: &mut Option<Span>,
        always: &mut Option<Span>,
    ) -> Option<Alternative> {
        let guard = match &a.guard {
            syntax::Guard::Always => {
                always.get_or_insert(a.span);
                Guard::Always
            }
            syntax::Guard::When(e) => {
                let f = self.formulas.compile(e, &mut self.types, &mut self.out);
                match f.as_ref().and_then(|f| f.constant) {
                    Some(v) if v != 0.0 && !v.is_nan() => {
                        always.get_or_insert(a.span);
                    }
                    Some(_) => self.out.push(Diagnostic::warning(e.span, "this condition is never true")),
                    None => {}
                }
                match f {
                    Some(f) => Guard::When(f),
                    None => {
                        // Still check the operation, for its own errors.
                        self.op(id, &a.op);
                        return None;
                    }
                }
            }
            syntax::Guard::Else => {
                if let Some(prev) = else_seen {
                    self.out.push(
                        Diagnostic::error(a.span, "a rule has at most one `else`").with_label(*prev, "first `else`"),
                    );
                }
                *else_seen = Some(a.span);
                if let Some((_, ws)) = a.weight {
                    self.out.push(Diagnostic::warning(ws, "the weight of `else` has no effect"));
                }
                Guard::Else
            }
        };
        let weight = match a.weight {
            Some((w, ws)) if !(w.is_finite() && w >= 0.0) => {
                self.out.push(Diagnostic::error(ws, "a weight must be a number of at least 0"));
                1.0
            }
            Some((w, _)) => w,
            None => 1.0,
        };
        let op = self.op(id, &a.op)?;
        Some(Alternative { guard, weight, op, line: self.line(a.span) })
    }

    fn op(&mut self, rule: RuleId, op: &OpSyn) -> Option<OpId> {
        let compiled = match op {
            OpSyn::Split { axis, sizes, repeat, round, children, span, children_span } => {
                let mut formulas = Vec::new();
                let mut ok = true;
                for s in sizes {
                    match self.formulas.compile(s, &mut self.types, &mut self.out) {
                        Some(f) => {
                            if f.constant.is_some_and(|v| v == 0.0 || !v.is_finite() || (v > 0.0 && v < 1.0)) {
                                self.out.push(
                                    Diagnostic::error(s.span, "this size makes an empty child")
                                        .with_hint("sizes are whole blocks (positive) or relative weights (negative)"),
                                );
                            }
                            formulas.push(f);
                        }
                        None => ok = false,
                    }
                }
                if sizes.is_empty() {
                    self.out.push(Diagnostic::error(*span, "a split needs at least one size"));
                } else if sizes.len() != children.len() {
                    self.out.push(
                        Diagnostic::error(
                            *children_span,
                            format!(
                                "{} size{} but {} child{}",
                                sizes.len(),
                                if sizes.len() == 1 { "" } else { "s" },
                                children.len(),
                                if children.len() == 1 { "" } else { "ren" }
                            ),
                        )
                        .with_label(*span, "this split")
                        .with_hint("give one child per size"),
                    );
                }
                let kids: Vec<Option<OpId>> = children.iter().map(|c| self.op(rule, c)).collect();
                let children: Vec<OpId> = kids.into_iter().collect::<Option<_>>()?;
                if !ok {
                    return None;
                }
                let constant = formulas.iter().map(|f| f.constant).collect::<Option<Vec<f64>>>();
                Op::Split { axis: *axis as u8, sizes: formulas, constant, repeat: *repeat, round: *round, children }
            }
            OpSyn::Fill(b) => Op::Fill(self.paint(b)?),
            OpSyn::Void => Op::Fill(Paint::Block(AIR)),
            OpSyn::Skip => Op::Skip,
            OpSyn::Reorient(perm, span, then) => {
                let mut seen = [false; 3];
                for &p in perm {
                    seen[p] = true;
                }
                if seen.contains(&false) {
                    self.out.push(
                        Diagnostic::error(*span, "`reorient` needs each of x, y and z exactly once")
                            .with_hint("e.g. `reorient(z, y, x)` swaps the local x and z axes"),
                    );
                }
                let then = self.op(rule, then)?;
                Op::Reorient([perm[0] as u8, perm[1] as u8, perm[2] as u8], then)
            }
            OpSyn::Call(name) => match self.rule_ids.get(&name.name) {
                Some(&target) => {
                    self.used[rule as usize].push(target);
                    Op::Rule(target)
                }
                None => {
                    self.unknown_rule(name);
                    return None;
                }
            },
        };
        Some(self.push(compiled))
    }

    fn paint(&mut self, b: &Ident) -> Option<Paint> {
        if let Some(&m) = self.materials.get(&b.name) {
            return Some(Paint::Material(m));
        }
        match BlockState::parse(&b.name) {
            Ok(state) => {
                // A near miss of a material is most likely a typo: an error
                // when the id is no block either, else a warning.
                if !b.name.contains([':', '['])
                    && let Some(s) = did_you_mean(&b.name, self.materials.keys().map(String::as_str))
                {
                    let hint = format!("did you mean the material `{s}`?");
                    if known_blocks::lookup(state.id()) == Known::Unknown && !self.check.allows_unknown() {
                        self.out.push(
                            Diagnostic::error(b.span, format!("`{}` is neither a material nor a known block", b.name))
                                .with_hint(hint),
                        );
                        return None;
                    }
                    self.out.push(
                        Diagnostic::warning(b.span, format!("`{}` is taken as the block `{state}`", b.name))
                            .with_hint(hint),
                    );
                }
                self.check.check(&state, b.span, &mut self.out);
                Some(Paint::Block(self.block(state)))
            }
            Err(msg) => {
                let mut d = Diagnostic::error(b.span, format!("`{}` is neither a material nor a block: {msg}", b.name));
                if let Some(s) = did_you_mean(&b.name, self.materials.keys().map(String::as_str)) {
                    d = d.with_hint(format!("did you mean the material `{s}`?"));
                }
                self.out.push(d);
                None
            }
        }
    }

    fn unknown_rule(&mut self, name: &Ident) {
        let mut d = Diagnostic::error(name.span, format!("unknown rule `{}`", name.name));
        if let Some(s) = did_you_mean(&name.name, self.rule_ids.keys().map(String::as_str)) {
            d = d.with_hint(format!("did you mean `{s}`?"));
        } else if self.materials.contains_key(&name.name) || BlockState::parse(&name.name).is_ok() {
            d = d.with_hint(format!("to paint the block or material write `fill {}`", name.name));
        }
        self.out.push(d);
    }

    fn warn_unreachable(&mut self, axiom: RuleId) {
        let mut seen = vec![false; self.rule_spans.len()];
        let mut stack = vec![axiom];
        while let Some(r) = stack.pop() {
            if std::mem::replace(&mut seen[r as usize], true) {
                continue;
            }
            stack.extend(self.used[r as usize].iter().copied());
        }
        let mut names: Vec<(&String, &RuleId)> = self.rule_ids.iter().collect();
        names.sort_by_key(|(_, id)| **id);
        for (name, &id) in names {
            if !seen[id as usize] {
                self.out.push(Diagnostic::warning(
                    self.rule_spans[id as usize],
                    format!("rule `{name}` is never used (not reachable from the axiom)"),
                ));
            }
        }
    }
}
