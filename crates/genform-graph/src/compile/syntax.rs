//! The YAML tree read into the grammar's parts, with spans; every shape
//! problem (a wrong type, an unknown key) is collected, none stops the
//! reading.

use crate::yaml::{Key, Node, Positions, Val};
use genform_core::diag::{Diagnostic, Span};
use genform_core::expr::did_you_mean;

/// A name or literal text with its span.
#[derive(Clone, Debug)]
pub(crate) struct Text {
    pub(crate) s: String,
    pub(crate) span: Span,
}

/// A string value: a formula or template, with where each of its bytes
/// was written in the file.
#[derive(Clone, Debug)]
pub(crate) struct Formula {
    pub(crate) s: String,
    pub(crate) pos: Positions,
    pub(crate) span: Span,
}

/// A value as written: a number (booleans are 1 and 0) or a string.
#[derive(Clone, Debug)]
pub(crate) enum Written {
    Num(f64, Span),
    Str(Formula),
}

impl Written {
    pub(crate) fn span(&self) -> Span {
        match self {
            Written::Num(_, s) => *s,
            Written::Str(f) => f.content_span(),
        }
    }
}

impl Formula {
    /// The formula's text (inside any quotes).
    pub(crate) fn content_span(&self) -> Span {
        self.pos.span(Span::new(0, self.s.len()))
    }
}

/// A vertex or an edge as written, in any part of the file; which keys
/// are allowed where is checked when compiling.
#[derive(Clone, Debug, Default)]
pub(crate) struct Element {
    pub(crate) name: Option<Text>,
    /// The element's map (or its key for a vertex).
    pub(crate) span: Span,
    pub(crate) label: Option<Formula>,
    pub(crate) when: Option<Formula>,
    pub(crate) wildcard: Option<(bool, Span)>,
    pub(crate) at: Option<([f64; 2], Span)>,
    pub(crate) keep: Option<Text>,
    pub(crate) pos: Option<Formula>,
    pub(crate) x: Option<Written>,
    pub(crate) y: Option<Written>,
    pub(crate) from: Option<Text>,
    pub(crate) to: Option<Text>,
    pub(crate) directed: Option<(bool, Span)>,
    pub(crate) attrs: Vec<(Text, Written)>,
}

impl Element {
    /// The element's name: its own, or `From-To` for an unnamed edge.
    pub(crate) fn name(&self) -> String {
        match (&self.name, &self.from, &self.to) {
            (Some(n), _, _) => n.s.clone(),
            (None, Some(f), Some(t)) => format!("{}-{}", f.s, t.s),
            _ => String::new(),
        }
    }

    /// Where to point at the element's name.
    pub(crate) fn name_span(&self) -> Span {
        self.name.as_ref().map_or(self.span, |n| n.span)
    }
}

#[derive(Clone, Debug, Default)]
pub(crate) struct GraphSyn {
    pub(crate) vertices: Vec<Element>,
    pub(crate) edges: Vec<Element>,
}

#[derive(Clone, Debug)]
pub(crate) struct Variable {
    pub(crate) name: Text,
    pub(crate) value: Written,
    pub(crate) per_run: bool,
}

#[derive(Clone, Debug)]
pub(crate) struct OptionSyn {
    pub(crate) weight: Option<(f64, Span)>,
    pub(crate) vars: Vec<Variable>,
    pub(crate) graph: GraphSyn,
}

#[derive(Clone, Debug)]
pub(crate) enum VectorSyn {
    Point(Text),
    Pair(Text, Text),
}

#[derive(Clone, Debug)]
pub(crate) struct ProductionSyn {
    pub(crate) name: Text,
    pub(crate) priority: i64,
    pub(crate) oldest: bool,
    pub(crate) spatial: bool,
    pub(crate) mother: GraphSyn,
    pub(crate) vectors: Vec<(Text, VectorSyn)>,
    pub(crate) vars: Vec<Variable>,
    pub(crate) when: Vec<Formula>,
    pub(crate) options: Vec<OptionSyn>,
}

#[derive(Clone, Debug, Default)]
pub(crate) struct FileSyn {
    pub(crate) name: Option<Text>,
    pub(crate) steps: Option<(usize, Span)>,
    /// `time_limit:` in seconds.
    pub(crate) time_limit: Option<f64>,
    pub(crate) limits: Vec<(i64, Span, usize)>,
    pub(crate) globals: Vec<(Text, Written)>,
    pub(crate) host: GraphSyn,
    pub(crate) productions: Vec<ProductionSyn>,
}

/// Reads nodes, collecting errors.
pub(crate) struct Reader<'t> {
    pub(crate) text: &'t str,
    pub(crate) errors: Vec<Diagnostic>,
}

const TOP_KEYS: &[&str] = &["name", "steps", "time_limit", "priority_limits", "globals", "host", "productions"];
const PRODUCTION_KEYS: &[&str] =
    &["name", "priority", "match", "spatial", "mother", "vectors", "variables", "when", "daughters", "daughter"];
const OPTION_KEYS: &[&str] = &["weight", "variables", "vertices", "edges"];
const GRAPH_KEYS: &[&str] = &["vertices", "edges"];

impl<'t> Reader<'t> {
    fn error(&mut self, span: Span, msg: impl Into<String>) -> &mut Diagnostic {
        self.errors.push(Diagnostic::error(span, msg));
        self.errors.last_mut().expect("just pushed")
    }

    fn wrong(&mut self, node: &Node, want: &str, context: &str) {
        self.error(node.span, format!("{context} must be {want}, found {}", node.value.kind()));
    }

    fn unknown_key(&mut self, key: &Key, known: &[&str], context: &str) {
        let d = self.error(key.span, format!("unknown key `{}` in {context}", key.name));
        let hint = match did_you_mean(&key.name, known.iter().copied()) {
            Some(s) => format!("did you mean `{s}`?"),
            None => format!("known keys: {}", known.join(", ")),
        };
        d.hints.push(hint);
    }

    /// The entries of a map node (an empty map for `~`).
    fn map<'n>(&mut self, node: &'n Node, context: &str) -> &'n [(Key, Node)] {
        match &node.value {
            Val::Map(m) => m,
            Val::Null => &[],
            _ => {
                self.wrong(node, "a map (`key: value` lines)", context);
                &[]
            }
        }
    }

    fn seq<'n>(&mut self, node: &'n Node, context: &str) -> &'n [Node] {
        match &node.value {
            Val::Seq(s) => s,
            Val::Null => &[],
            _ => {
                self.wrong(node, "a list (`- item` lines)", context);
                &[]
            }
        }
    }

    fn number(&mut self, node: &Node, context: &str) -> Option<f64> {
        match node.value {
            Val::Num(v) => Some(v),
            _ => {
                self.wrong(node, "a number", context);
                None
            }
        }
    }

    fn count(&mut self, node: &Node, context: &str) -> Option<usize> {
        let v = self.number(node, context)?;
        if v >= 0.0 && v.fract() == 0.0 && v <= 1e15 {
            Some(v as usize)
        } else {
            self.error(node.span, format!("{context} must be a whole number ≥ 0"));
            None
        }
    }

    fn integer(&mut self, node: &Node, context: &str) -> Option<i64> {
        let v = self.number(node, context)?;
        if v.fract() == 0.0 && v.abs() <= 1e15 {
            Some(v as i64)
        } else {
            self.error(node.span, format!("{context} must be a whole number"));
            None
        }
    }

    fn boolean(&mut self, node: &Node, context: &str) -> Option<bool> {
        match node.value {
            Val::Bool(b) => Some(b),
            _ => {
                self.wrong(node, "`true` or `false`", context);
                None
            }
        }
    }

    /// Text: a string, or a number written as text (`label: 1`).
    fn text(&mut self, node: &Node, context: &str) -> Option<Text> {
        match &node.value {
            Val::Str(s) => Some(Text { s: s.clone(), span: node.span }),
            Val::Num(v) => Some(Text { s: crate::write::number(*v), span: node.span }),
            Val::Bool(b) => Some(Text { s: b.to_string(), span: node.span }),
            _ => {
                self.wrong(node, "text", context);
                None
            }
        }
    }

    fn formula(&mut self, node: &Node, context: &str) -> Option<Formula> {
        match &node.value {
            Val::Str(s) => {
                let pos = Positions::of(self.text, node.span.start as usize, s);
                Some(Formula { s: s.clone(), pos, span: node.span })
            }
            Val::Num(v) => {
                let s = crate::write::number(*v);
                let pos = Positions::verbatim(node.span.start as usize, s.len());
                Some(Formula { s, pos, span: node.span })
            }
            _ => {
                self.wrong(node, "a formula in quotes", context);
                None
            }
        }
    }

    fn written(&mut self, node: &Node, context: &str) -> Option<Written> {
        match &node.value {
            Val::Num(v) => Some(Written::Num(*v, node.span)),
            Val::Bool(b) => Some(Written::Num(f64::from(u8::from(*b)), node.span)),
            Val::Str(_) => self.formula(node, context).map(Written::Str),
            _ => {
                self.wrong(node, "a number or text", context);
                None
            }
        }
    }

    fn name(&mut self, key: &Key, what: &str) -> Text {
        if !is_identifier(&key.name) {
            self.error(key.span, format!("`{}` is not a valid {what} name", key.name))
                .hints
                .push("names start with a letter or `_` and hold letters, digits and `_`".into());
        }
        Text { s: key.name.clone(), span: key.span }
    }

    /// The whole file.
    pub(crate) fn file(&mut self, root: &Node) -> FileSyn {
        let mut f = FileSyn::default();
        let mut host = None;
        for (k, v) in self.map(root, "the file") {
            match k.name.as_str() {
                "name" => f.name = self.text(v, "`name`"),
                "steps" => f.steps = self.count(v, "`steps`").map(|n| (n, v.span)),
                "time_limit" => {
                    f.time_limit = self.number(v, "`time_limit`").and_then(|t| {
                        if t > 0.0 && t <= crate::derive::MAX_TIME_LIMIT_SECS {
                            Some(t)
                        } else {
                            self.error(
                                v.span,
                                format!(
                                    "`time_limit` must be a number of seconds above 0 and at most {}",
                                    crate::derive::MAX_TIME_LIMIT_SECS
                                ),
                            );
                            None
                        }
                    })
                }
                "priority_limits" => {
                    for (pk, pv) in self.map(v, "`priority_limits`") {
                        let p = pk.name.trim().parse::<i64>();
                        let n = self.count(pv, "a priority limit");
                        match (p, n) {
                            (Ok(p), Some(n)) => f.limits.push((p, pk.span, n)),
                            (Err(_), _) => {
                                self.error(pk.span, format!("`{}` is not a priority (a whole number)", pk.name));
                            }
                            _ => {}
                        }
                    }
                }
                "globals" => {
                    for (gk, gv) in self.map(v, "`globals`") {
                        let name = self.name(gk, "global");
                        if let Some(w) = self.written(gv, "a global") {
                            f.globals.push((name, w));
                        }
                    }
                }
                "host" => host = Some(v),
                "productions" => {
                    for p in self.seq(v, "`productions`") {
                        if let Some(p) = self.production(p) {
                            f.productions.push(p);
                        }
                    }
                }
                _ => self.unknown_key(k, TOP_KEYS, "the file"),
            }
        }
        match host {
            Some(h) => f.host = self.graph(h, "the host", GRAPH_KEYS),
            None => {
                self.error(Span::new(0, 0), "the grammar has no host graph")
                    .hints
                    .push("add `host:` with `vertices:` (and `edges:`), the graph the derivation starts from".into());
            }
        }
        f
    }

    fn graph(&mut self, node: &Node, context: &str, keys: &[&str]) -> GraphSyn {
        let mut g = GraphSyn::default();
        for (k, v) in self.map(node, context) {
            match k.name.as_str() {
                "vertices" => {
                    for (vk, vv) in self.map(v, "`vertices`") {
                        let name = self.name(vk, "vertex");
                        let mut e = self.element(vv, &format!("vertex `{}`", vk.name));
                        e.span = vk.span;
                        e.name = Some(name);
                        g.vertices.push(e);
                    }
                }
                "edges" => {
                    for ev in self.seq(v, "`edges`") {
                        let e = match &ev.value {
                            // `[a, b]`: an undirected edge without label.
                            Val::Seq(ends) => {
                                let mut e = Element { span: ev.span, ..Element::default() };
                                if let [a, b] = ends.as_slice() {
                                    e.from = self.text(a, "an edge end");
                                    e.to = self.text(b, "an edge end");
                                } else {
                                    self.error(ev.span, "an edge written as a list needs exactly two vertex names")
                                        .hints
                                        .push("write `[a, b]` or `{from: a, to: b, …}`".into());
                                }
                                e
                            }
                            _ => self.element(ev, "an edge"),
                        };
                        g.edges.push(e);
                    }
                }
                _ if keys.contains(&k.name.as_str()) => {}
                _ => self.unknown_key(k, keys, context),
            }
        }
        g
    }

    fn element(&mut self, node: &Node, context: &str) -> Element {
        let mut e = Element { span: node.span, ..Element::default() };
        for (k, v) in self.map(node, context) {
            match k.name.as_str() {
                "name" => e.name = self.text(v, "`name`"),
                "label" => e.label = self.formula(v, "`label`"),
                "when" => e.when = self.formula(v, "`when`"),
                "wildcard" => e.wildcard = self.boolean(v, "`wildcard`").map(|b| (b, v.span)),
                "keep" => e.keep = self.text(v, "`keep`"),
                "pos" => e.pos = self.formula(v, "`pos`"),
                "x" => e.x = self.written(v, "`x`"),
                "y" => e.y = self.written(v, "`y`"),
                "from" => e.from = self.text(v, "`from`"),
                "to" => e.to = self.text(v, "`to`"),
                "directed" => e.directed = self.boolean(v, "`directed`").map(|b| (b, v.span)),
                "at" => {
                    let pair = match &v.value {
                        Val::Seq(xs) if xs.len() == 2 => match (&xs[0].value, &xs[1].value) {
                            (Val::Num(x), Val::Num(y)) => Some([*x, *y]),
                            _ => None,
                        },
                        _ => None,
                    };
                    match pair {
                        Some(p) => e.at = Some((p, v.span)),
                        None => {
                            self.error(v.span, "`at` must be a point `[x, y]` of two numbers")
                                .hints
                                .push("`at` is where the vertex is drawn in the production's own layout".into());
                        }
                    }
                }
                _ => {
                    let name = self.name(k, "attribute");
                    if matches!(k.name.as_str(), "degree" | "generation") {
                        self.error(k.span, format!("`{}` is computed, not an attribute", k.name))
                            .hints
                            .push(format!("read it in formulas as `Name.{}`; pick another attribute name", k.name));
                    }
                    if let Some(w) = self.written(v, &format!("attribute `{}`", k.name)) {
                        e.attrs.push((name, w));
                    }
                }
            }
        }
        e
    }

    fn variables(&mut self, node: &Node) -> Vec<Variable> {
        let mut out = Vec::new();
        for (k, v) in self.map(node, "`variables`") {
            let name = self.name(k, "variable");
            let (value, per_run) = match &v.value {
                Val::Map(m) => {
                    let (mut value, mut per_run) = (None, false);
                    for (vk, vv) in m {
                        match vk.name.as_str() {
                            "value" => value = self.written(vv, "`value`"),
                            "per" => match &vv.value {
                                Val::Str(s) if s == "run" => per_run = true,
                                Val::Str(s) if s == "application" => per_run = false,
                                _ => {
                                    self.error(vv.span, "`per` must be `run` or `application`");
                                }
                            },
                            _ => self.unknown_key(vk, &["value", "per"], "a variable"),
                        }
                    }
                    if value.is_none() {
                        self.error(v.span, format!("variable `{}` has no `value`", k.name));
                    }
                    (value, per_run)
                }
                _ => (self.written(v, "a variable"), false),
            };
            if let Some(value) = value {
                out.push(Variable { name, value, per_run });
            }
        }
        out
    }

    fn production(&mut self, node: &Node) -> Option<ProductionSyn> {
        let entries = self.map(node, "a production");
        let mut name = None;
        let mut p = ProductionSyn {
            name: Text { s: String::new(), span: node.span },
            priority: 0,
            oldest: false,
            spatial: false,
            mother: GraphSyn::default(),
            vectors: Vec::new(),
            vars: Vec::new(),
            when: Vec::new(),
            options: Vec::new(),
        };
        let mut mother = false;
        for (k, v) in entries {
            match k.name.as_str() {
                "name" => name = self.text(v, "`name`"),
                "priority" => p.priority = self.integer(v, "`priority`").unwrap_or(0),
                "match" => match &v.value {
                    Val::Str(s) if s == "oldest" => p.oldest = true,
                    Val::Str(s) if s == "random" => p.oldest = false,
                    _ => {
                        self.error(v.span, "`match` must be `random` or `oldest`");
                    }
                },
                "spatial" => p.spatial = self.boolean(v, "`spatial`").unwrap_or(false),
                "mother" => {
                    mother = true;
                    p.mother = self.graph(v, "the mother graph", GRAPH_KEYS);
                }
                "vectors" => {
                    for (vk, vv) in self.map(v, "`vectors`") {
                        let vname = self.name(vk, "vector");
                        let def = match &vv.value {
                            Val::Seq(ends) if ends.len() == 2 => {
                                match (self.text(&ends[0], "a vector end"), self.text(&ends[1], "a vector end")) {
                                    (Some(a), Some(b)) => Some(VectorSyn::Pair(a, b)),
                                    _ => None,
                                }
                            }
                            Val::Str(_) => self.text(vv, "a vector").map(VectorSyn::Point),
                            _ => {
                                self.error(
                                    vv.span,
                                    "a vector is a vertex `A` (its position) or a pair `[A, B]` (B − A)",
                                );
                                None
                            }
                        };
                        if let Some(d) = def {
                            p.vectors.push((vname, d));
                        }
                    }
                }
                "variables" => p.vars = self.variables(v),
                "when" => match &v.value {
                    Val::Seq(items) => {
                        for i in items {
                            if let Some(f) = self.formula(i, "a condition") {
                                p.when.push(f);
                            }
                        }
                    }
                    _ => p.when.extend(self.formula(v, "`when`")),
                },
                "daughters" => {
                    for o in self.seq(v, "`daughters`") {
                        let o = self.option(o);
                        p.options.push(o);
                    }
                }
                "daughter" => {
                    let o = self.option(v);
                    p.options.push(o);
                }
                _ => self.unknown_key(k, PRODUCTION_KEYS, "a production"),
            }
        }
        match name {
            Some(n) => p.name = n,
            None => {
                self.error(node.span, "a production needs a `name`");
            }
        }
        if !mother {
            self.error(p.name.span, format!("production `{}` has no `mother` graph", p.name.s))
                .hints
                .push("the mother graph is the pattern the production replaces".into());
        }
        if p.options.is_empty() {
            self.error(p.name.span, format!("production `{}` has no daughter", p.name.s))
                .hints
                .push("add `daughter:` (or `daughters:`, a list of weighted options): what replaces the match".into());
        }
        Some(p)
    }

    fn option(&mut self, node: &Node) -> OptionSyn {
        let mut o = OptionSyn { weight: None, vars: Vec::new(), graph: GraphSyn::default() };
        for (k, v) in self.map(node, "a daughter") {
            match k.name.as_str() {
                "weight" => o.weight = self.number(v, "`weight`").map(|w| (w, v.span)),
                "variables" => o.vars = self.variables(v),
                "vertices" | "edges" => {}
                _ => self.unknown_key(k, OPTION_KEYS, "a daughter"),
            }
        }
        o.graph = self.graph(node, "a daughter", OPTION_KEYS);
        o
    }
}

/// `[A-Za-z_][A-Za-z0-9_]*`.
pub(crate) fn is_identifier(s: &str) -> bool {
    let mut c = s.chars();
    c.next().is_some_and(|f| f.is_ascii_alphabetic() || f == '_') && c.all(|x| x.is_ascii_alphanumeric() || x == '_')
}
