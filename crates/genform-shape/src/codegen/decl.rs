//! Declarations of a symbol: parameters with their distributions, declared
//! and implicit slots, and the hidden parameters of `alt`s.

use super::*;

impl SymbolCx<'_> {
    fn value(&mut self, v: &Value, dim: usize, what: &str) -> Option<Vec<f64>> {
        match v {
            Value::Scalar(e) => self.eval_const(e, what).map(|x| vec![x; dim]),
            Value::Vector(items, span) => {
                if items.len() != dim {
                    self.err(*span, format!("expected {dim} components for {what}, found {}", items.len()));
                    return None;
                }
                let vals: Vec<Option<f64>> = items.iter().map(|e| self.eval_const(e, what)).collect();
                vals.into_iter().collect()
            }
        }
    }

    pub(super) fn param(&mut self, p: &ParamDecl) {
        if !self.declare_ok(&p.name, p.span, "parameter") {
            return;
        }
        let mut dim = p.dim;
        let vector_lens =
            p.args.iter().map(|a| &a.value).chain(p.bounds.iter().flat_map(|(a, b)| [a, b])).filter_map(|v| match v {
                Value::Vector(items, span) => Some((items.len(), *span)),
                Value::Scalar(_) => None,
            });
        for (n, span) in vector_lens {
            match dim {
                None if (1..=3).contains(&n) => dim = Some(n),
                Some(d) if d == n => {}
                _ => {
                    let want = dim.map_or("1 to 3".to_string(), |d| d.to_string());
                    self.err(span, format!("parameter `{}` has {want} components, this vector has {n}", p.name));
                    return;
                }
            }
        }
        let dim = dim.unwrap_or(1);
        let nargs = p.args.len();
        let arity = |cx: &mut Self, n: usize, form: &str| -> bool {
            if nargs != n {
                cx.err(
                    p.args_span,
                    format!("`{}` takes {n} argument{}, found {nargs}", p.dist, if n == 1 { "" } else { "s" }),
                );
                if let Some(d) = cx.errors.last_mut() {
                    d.hints.push(format!("write `{form}`"));
                }
                return false;
            }
            if let Some(a) = p.args.iter().find(|a| a.weight.is_some()) {
                let span = a.value.span();
                cx.err(span, format!("only `choice` values have weights (`value: weight`), not `{}`", p.dist));
                return false;
            }
            true
        };
        if p.bounds.is_some() && p.dist != "normal" {
            self.err(p.dist_span, format!("`in [lo, hi]` bounds apply to `normal` only, not `{}`", p.dist));
        }
        let comps: Option<Vec<Distribution>> = match p.dist.as_str() {
            "uniform" => {
                if !arity(self, 2, "uniform(min, max)") {
                    return;
                }
                let lo = self.value(&p.args[0].value, dim, "the minimum");
                let hi = self.value(&p.args[1].value, dim, "the maximum");
                let (Some(lo), Some(hi)) = (lo, hi) else { return };
                Some(lo.iter().zip(&hi).map(|(a, b)| Distribution::Uniform { min: *a, max: *b }).collect())
            }
            "normal" => {
                if !arity(self, 2, "normal(mean, sd) in [lo, hi]") {
                    return;
                }
                let mean = self.value(&p.args[0].value, dim, "the mean");
                let sd = self.value(&p.args[1].value, dim, "the standard deviation");
                let (lo, hi) = match &p.bounds {
                    Some((lo, hi)) => (self.value(lo, dim, "the lower bound"), self.value(hi, dim, "the upper bound")),
                    None => (Some(vec![f64::NEG_INFINITY; dim]), Some(vec![f64::INFINITY; dim])),
                };
                let (Some(mean), Some(sd), Some(lo), Some(hi)) = (mean, sd, lo, hi) else { return };
                Some(
                    (0..dim)
                        .map(|i| Distribution::Normal { mean: mean[i], sd: sd[i], min: lo[i], max: hi[i] })
                        .collect(),
                )
            }
            "int" => {
                if !arity(self, 2, "int(min, max)") {
                    return;
                }
                let lo = self.value(&p.args[0].value, dim, "the minimum");
                let hi = self.value(&p.args[1].value, dim, "the maximum");
                let (Some(lo), Some(hi)) = (lo, hi) else { return };
                if let Some(v) = lo.iter().chain(&hi).find(|v| v.fract() != 0.0 || v.abs() > 9.0e15) {
                    self.err(p.args_span, format!("`int` bounds must be integers, found {v}"));
                    return;
                }
                Some(
                    lo.iter()
                        .zip(&hi)
                        .map(|(a, b)| Distribution::IntRange { min: *a as i64, max: *b as i64 })
                        .collect(),
                )
            }
            "choice" => {
                if p.args.is_empty() {
                    self.err(p.args_span, "`choice` needs at least one value")
                }
                let mut values = Vec::new();
                let mut weights = Vec::new();
                for a in &p.args {
                    let v = self.value(&a.value, 1, "a choice value").map(|v| v[0]);
                    let w = match &a.weight {
                        Some(w) => self.eval_const(w, "a choice weight"),
                        None => Some(1.0),
                    };
                    if let (Some(v), Some(w)) = (v, w) {
                        values.push(v);
                        weights.push(w);
                    }
                }
                (values.len() == p.args.len() && !values.is_empty())
                    .then(|| vec![Distribution::Choice { values, weights }; dim])
            }
            other => {
                let mut d = Diagnostic::error(p.dist_span, format!("unknown distribution `{other}`"));
                d = match did_you_mean(other, DISTRIBUTIONS.iter().copied()) {
                    Some(s) => d.with_hint(format!("did you mean `{s}`?")),
                    None => d.with_hint("distributions are `uniform`, `normal`, `int` and `choice`"),
                };
                self.errors.push(d);
                return;
            }
        };
        let Some(comps) = comps else { return };
        const AXES: [&str; 3] = ["x", "y", "z"];
        for (i, c) in comps.iter().enumerate() {
            if let Err(msg) = c.check() {
                let which = if dim > 1 { format!(" (component {})", AXES[i]) } else { String::new() };
                let msg =
                    msg.replace("range is empty", "range is invalid").replace("bounds are empty", "bounds are invalid");
                let d = Diagnostic::error(p.args_span, format!("parameter `{}`{which}: {msg}", p.name))
                    .with_hint("give the smaller bound first; a standard deviation cannot be negative");
                self.errors.push(d);
                return;
            }
        }
        if dim == 1 {
            self.new_env(Some(&p.name), 0.0);
        } else {
            for a in &AXES[..dim] {
                self.new_env(Some(&format!("{}.{a}", p.name)), 0.0);
            }
        }
        self.params.push(ParamSpec { name: p.name.clone(), components: comps });
    }

    /// Resolves a rule reference: `Ok(Some((rule, symbol)))`, `Ok(None)`
    /// when the template index is outside the range, `Err` when reported.
    fn resolve(&mut self, r: &SymRef) -> Result<(usize, Option<u32>), ()> {
        let Some(ri) = self.g.rule(&r.name) else {
            let mut d = Diagnostic::error(r.span, format!("unknown rule `{}`", r.name));
            let rules: Vec<&str> = self.g.rules.iter().map(|x| x.name.as_str()).collect();
            d = match did_you_mean(&r.name, rules) {
                Some(s) => d.with_hint(format!("did you mean `{s}`?")),
                None => d.with_hint(format!("define it as `{} {{ ... }}`", r.name)),
            };
            self.errors.push(d);
            return Err(());
        };
        let info = &self.g.rules[ri];
        match (info.range, &r.index) {
            (None, None) => Ok((ri, Some(info.first))),
            (None, Some(_)) => {
                let msg = format!("`{}` is not a template rule, so it takes no `<index>`", r.name);
                self.err(r.span, msg);
                Err(())
            }
            (Some((lo, _)), None) => {
                let d = Diagnostic::error(r.span, format!("`{}` is a template rule and needs an index", r.name))
                    .with_hint(format!("write `{}<{lo}>` or `{}<i + 1>`", r.name, r.name));
                self.errors.push(d);
                Err(())
            }
            (Some((lo, hi)), Some(e)) => {
                let first = info.first;
                let v = self.eval_const(e, "a template index").ok_or(())?;
                if v.fract() != 0.0 {
                    self.err(e.span(), format!("a template index must be an integer, found {v}"));
                    return Err(());
                }
                if v < lo as f64 || v >= hi as f64 {
                    return Ok((ri, None));
                }
                Ok((ri, Some(first + (v as i64 - lo) as u32)))
            }
        }
    }

    pub(super) fn slot(&mut self, sd: &SlotDecl) {
        if self.slots.iter().any(|s| s.name == sd.name) {
            self.err(sd.span, format!("slot `{}` is declared twice in rule `{}`", sd.name, self.rule.name));
            return;
        }
        let target = self.resolve(&sd.target);
        let prob = match &sd.prob {
            Some(e) => {
                let p = self.eval_const(e, "a slot probability");
                match p {
                    Some(p) if !(0.0..=1.0).contains(&p) => {
                        let d =
                            Diagnostic::error(e.span(), format!("a slot probability must lie in [0, 1], found {p}"))
                                .with_hint("it is the chance that each link of the slot holds a child");
                        self.errors.push(d);
                        None
                    }
                    p => p,
                }
            }
            None => Some(1.0),
        };
        let count = match &sd.count {
            Some(e) => match self.eval_const(e, "a slot count") {
                Some(n) if n.fract() != 0.0 || !(1.0..=MAX_SLOT_COUNT).contains(&n) => {
                    self.err(
                        e.span(),
                        format!("a slot count must be an integer from 1 to {MAX_SLOT_COUNT}, found {n}"),
                    );
                    None
                }
                n => n,
            },
            None => Some(1.0),
        };
        let (Ok((rule, target)), Some(prob), Some(count)) = (target, prob, count) else {
            // Keep the name so uses of it do not cascade into more errors.
            self.slots.push(LocalSlot { name: sd.name.clone(), graph: None, has_env: 0, rule: 0, implicit: false });
            return;
        };
        let graph = target.map(|t| {
            self.graph_slots.push(SlotSpec { name: sd.name.clone(), target: t, prob, max_count: count as u32 });
            (self.graph_slots.len() - 1) as u32
        });
        self.slots.push(LocalSlot { name: sd.name.clone(), graph, has_env: 0, rule, implicit: false });
    }

    /// Finds `alt`s (hidden parameters) and invocations of rules (implicit
    /// slots) anywhere in the body, in source order, and classifies calls.
    pub(super) fn prepass(&mut self, body: &[Stmt], top: bool) {
        for s in body {
            match s {
                Stmt::Param(p) if !top => {
                    self.err(p.span, "`param` must be declared at the top level of a rule body");
                }
                Stmt::Slot(sd) if !top => {
                    self.err(sd.span, "`slot` must be declared at the top level of a rule body");
                }
                Stmt::Param(_) | Stmt::Slot(_) | Stmt::Let { .. } => {}
                Stmt::If { then, els, .. } => {
                    self.prepass(then, false);
                    self.prepass(els, false);
                }
                Stmt::Alt { span, arms } => {
                    let mut weights = Vec::new();
                    for (w, _) in arms {
                        match self.eval_const(w, "an alternative's weight") {
                            Some(v) if v < 0.0 => {
                                self.err(w.span(), format!("an alternative's weight must be ≥ 0, found {v}"))
                            }
                            Some(v) => weights.push(v),
                            None => {}
                        }
                    }
                    if weights.len() == arms.len() && weights.iter().all(|w| *w == 0.0) {
                        self.err(*span, "at least one alternative needs a weight above 0");
                    }
                    let name = format!("alt#{}", self.alt_envs.len());
                    let env = self.new_env(None, 0.0);
                    self.alt_envs.push(env);
                    let values = (0..arms.len()).map(|i| i as f64).collect();
                    if weights.len() != arms.len() {
                        weights = vec![1.0; arms.len()];
                    }
                    let weights = if weights.iter().all(|w| *w == 0.0) { vec![1.0; arms.len()] } else { weights };
                    self.params.push(ParamSpec { name, components: vec![Distribution::Choice { values, weights }] });
                    for (_, arm) in arms {
                        self.prepass(arm, false);
                    }
                }
                Stmt::Mirror { body, .. } | Stmt::Repeat { body, .. } | Stmt::Scoped(body) => {
                    self.prepass(body, false);
                }
                Stmt::Comp { arms, .. } => {
                    for a in arms {
                        self.prepass(&a.body, false);
                    }
                }
                Stmt::Split { pieces, .. } => {
                    for p in pieces {
                        self.prepass(&p.body, false);
                    }
                }
                Stmt::Call { target, .. } => {
                    let kind = self.classify(target);
                    self.calls.push((target.span.start, kind));
                }
            }
        }
    }

    fn classify(&mut self, target: &SymRef) -> CallKind {
        if target.index.is_none() {
            if OPS.contains(&target.name.as_str()) {
                return CallKind::Op;
            }
            if let Some(i) = self.slots.iter().position(|s| s.name == target.name && !s.implicit) {
                return CallKind::Slot(i, COUNTED);
            }
        }
        if self.g.rule(&target.name).is_none() {
            let mut d = Diagnostic::error(target.span, format!("unknown operation or rule `{}`", target.name));
            let cands: Vec<String> = OPS
                .iter()
                .map(|s| s.to_string())
                .chain(self.slots.iter().filter(|s| !s.implicit).map(|s| s.name.clone()))
                .chain(self.g.rules.iter().map(|r| r.name.clone()))
                .collect();
            d = match did_you_mean(&target.name, cands.iter().map(String::as_str)) {
                Some(s) => d.with_hint(format!("did you mean `{s}`?")),
                None => d.with_hint("a statement is an operation (`box`, `translate`, …), a slot or a rule name"),
            };
            self.errors.push(d);
            return CallKind::Bad;
        }
        let Ok((rule, sym)) = self.resolve(target) else { return CallKind::Bad };
        let name = match (&self.g.rules[rule].range, sym) {
            (None, _) => target.name.clone(),
            (Some(_), Some(s)) => instance_name(&target.name, (s - self.g.rules[rule].first) as i64 + self.lo(rule)),
            (Some(_), None) => format!("{}<out of range>", target.name),
        };
        // Each place an implicit slot is invoked owns the next link (past
        // the most links, the places share the last one).
        if let Some(i) = self.slots.iter().position(|s| s.name == name && s.implicit) {
            let mut site = 0;
            if let Some(gi) = self.slots[i].graph {
                let s = &mut self.graph_slots[gi as usize];
                s.max_count = s.max_count.saturating_add(1).min(MAX_SLOT_COUNT as u32);
                site = s.max_count - 1;
            }
            return CallKind::Slot(i, site);
        }
        let graph = sym.map(|t| {
            self.graph_slots.push(SlotSpec { name: name.clone(), target: t, prob: 1.0, max_count: 1 });
            (self.graph_slots.len() - 1) as u32
        });
        self.slots.push(LocalSlot { name, graph, has_env: 0, rule, implicit: true });
        CallKind::Slot(self.slots.len() - 1, 0)
    }

    fn lo(&self, rule: usize) -> i64 {
        self.g.rules[rule].range.map_or(0, |r| r.0)
    }
}
