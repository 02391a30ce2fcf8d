//! Operations (`translate`, `box`, …) and invocations of slots.

use super::*;

/// Most corners of a `lot` outline (its simplicity check is quadratic).
const MAX_LOT_CORNERS: usize = 1024;

impl SymbolCx<'_> {
    /// The single bare-name argument, if that is what `args` is.
    fn bare(args: &[Arg]) -> Option<&str> {
        match args {
            [Arg::Expr(e)] => e.bare.as_deref(),
            _ => None,
        }
    }

    pub(super) fn arity(&mut self, name: &str, span: Span, form: &str, found: usize) {
        let d = Diagnostic::error(span, format!("wrong number of arguments for `{name}`: found {found}"))
            .with_hint(format!("write `{form}`"));
        self.errors.push(d);
    }

    fn expr_args(&mut self, name: &str, args: &[Arg]) -> Option<Vec<u32>> {
        let mut out = Vec::new();
        for a in args {
            match a {
                Arg::Expr(e) => out.push(self.expr(e)),
                Arg::Str(_, span) => {
                    self.err(*span, format!("`{name}` takes numbers, not a string"));
                    return None;
                }
                Arg::Named { span, .. } => {
                    self.err(*span, format!("`{name}` takes no named arguments"));
                    return None;
                }
            }
        }
        Some(out)
    }

    pub(super) fn op(&mut self, target: &SymRef, args: Option<&[Arg]>) {
        let name = target.name.as_str();
        let span = target.span;
        let args = args.unwrap_or(&[]);
        match name {
            "translate" | "size" | "scale" => {
                let form = format!("{name}(x, y, z)");
                let first = self.exprs.len() as u32;
                if args.len() == 3 {
                    if self.expr_args(name, args).is_none() {
                        return;
                    }
                } else if args.len() == 1 {
                    let comps: Vec<String> = match Self::bare(args) {
                        Some(b) => ["x", "y", "z"]
                            .iter()
                            .map(|a| format!("{b}.{a}"))
                            .filter(|c| self.names.iter().any(|(n, _)| n == c))
                            .collect(),
                        None => Vec::new(),
                    };
                    if comps.len() == 3 {
                        let aspan = args[0].span();
                        for c in &comps {
                            self.component_expr(c, aspan);
                        }
                    } else if !comps.is_empty() {
                        let d = Diagnostic::error(
                            args[0].span(),
                            format!("`{name}` needs three values, this vector has {}", comps.len()),
                        )
                        .with_hint(format!("write `{form}`"));
                        self.errors.push(d);
                        return;
                    } else if name == "translate" {
                        self.arity(name, span, &form, 1);
                        return;
                    } else {
                        let Some(e) = self.expr_args(name, args) else { return };
                        let copy = self.exprs[e[0] as usize].clone();
                        self.exprs.push(copy.clone());
                        self.exprs.push(copy);
                    }
                } else {
                    let form = if name == "translate" { form } else { format!("{form}` or `{name}(s)") };
                    self.arity(name, span, &form, args.len());
                    return;
                }
                self.code.push(match name {
                    "translate" => Op::Translate(first),
                    "size" => Op::Size(first),
                    _ => Op::Scale(first),
                });
            }
            "rotate" => {
                if args.len() != 2 {
                    self.arity(name, span, "rotate(x|y|z, degrees)", args.len());
                    return;
                }
                let axis = match &args[0] {
                    Arg::Expr(e) => match e.bare.as_deref() {
                        Some("x") => 0,
                        Some("y") => 1,
                        Some("z") => 2,
                        _ => 3,
                    },
                    _ => 3,
                };
                if axis == 3 {
                    let d = Diagnostic::error(
                        args[0].span(),
                        "expected an axis `x`, `y` or `z` as the first argument of `rotate`",
                    )
                    .with_hint("write `rotate(y, 90)`; angles are in degrees");
                    self.errors.push(d);
                    return;
                }
                let Some(e) = self.expr_args(name, &args[1..]) else { return };
                self.code.push(Op::Rotate(axis, e[0]));
            }
            "tag" => match args {
                [Arg::Str(s, _)] => {
                    let t = self.g.intern_tag(s);
                    self.code.push(Op::Tag(t));
                }
                _ => {
                    let at = args.first().map_or(span, Arg::span);
                    let d = Diagnostic::error(at, "`tag` takes one quoted name").with_hint("write `tag(\"roof\")`");
                    self.errors.push(d);
                }
            },
            "color" => match args {
                [Arg::Str(c, _)] if is_hex_color(c) => {
                    let c = c.to_ascii_lowercase();
                    let k = match self.g.colors.iter().position(|x| *x == c) {
                        Some(k) => k,
                        None => {
                            self.g.colors.push(c);
                            self.g.colors.len() - 1
                        }
                    };
                    self.code.push(Op::Color(k as u32));
                }
                _ => {
                    let at = args.first().map_or(span, Arg::span);
                    let d = Diagnostic::error(at, "`color` takes one quoted colour `#rrggbb`")
                        .with_hint("write `color(\"#b5523b\")`: six hex digits, red, green, blue");
                    self.errors.push(d);
                }
            },
            "texture" => self.texture(span, args),
            "box" | "cylinder" | "cone" | "sphere" => {
                if !args.is_empty() {
                    self.arity(name, span, &format!("{name};"), args.len());
                    return;
                }
                self.emits = true;
                self.code.push(Op::Emit(match name {
                    "box" => Prim::Box,
                    "cylinder" => Prim::Cylinder,
                    "cone" => Prim::Cone,
                    _ => Prim::Sphere,
                }));
            }
            "frustum" | "taper_box" => {
                if args.len() != 1 {
                    self.arity(name, span, &format!("{name}(top_ratio)"), args.len());
                    return;
                }
                let Some(e) = self.expr_args(name, args) else { return };
                self.emits = true;
                self.code.push(Op::Emit(if name == "frustum" { Prim::Frustum(e[0]) } else { Prim::Taper(e[0]) }));
            }
            "lot" => {
                let n = args.len();
                if n != 2 && (n < 6 || !n.is_multiple_of(2)) {
                    self.arity(name, span, "lot(width, depth)` or `lot(x0, z0, x1, z1, x2, z2, …)", n);
                    return;
                }
                if n > 2 * MAX_LOT_CORNERS {
                    let d = Diagnostic::error(
                        span,
                        format!("a `lot` has at most {MAX_LOT_CORNERS} corners, found {}", n / 2),
                    )
                    .with_hint("split a large footprint into several lots");
                    self.errors.push(d);
                    return;
                }
                let Some(e) = self.expr_args(name, args) else { return };
                let at = self.span_index(span);
                self.code.push(Op::Lot { args: e[0], n: n as u32, span: at });
            }
            "extrude" => {
                if args.len() != 1 {
                    self.arity(name, span, "extrude(height)", args.len());
                    return;
                }
                let Some(e) = self.expr_args(name, args) else { return };
                self.code.push(Op::Extrude(e[0]));
            }
            "taper" => {
                if args.is_empty() || args.len() > 2 {
                    self.arity(name, span, "taper(height)` or `taper(height, top_scale)", args.len());
                    return;
                }
                let Some(e) = self.expr_args(name, args) else { return };
                if e.len() == 1 {
                    let zero = self.g.zero.clone();
                    self.exprs.push(Expr::new(zero, Vec::new(), span));
                }
                self.emits = true;
                let at = self.span_index(span);
                self.code.push(Op::Taper { height: e[0], span: at, faces: self.solid_faces });
            }
            "shape" => {
                if !args.is_empty() {
                    self.arity(name, span, "shape;", args.len());
                    return;
                }
                self.emits = true;
                let at = self.span_index(span);
                self.code.push(Op::Shape(at));
            }
            "roof_gable" | "roof_hip" | "roof_pyramid" | "roof_shed" | "roof_ridge" => self.roof(name, span, args),
            "mesh" | "insert" => {
                let Some(m) = Self::bare(args).map(str::to_string) else {
                    self.arity(name, span, &format!("{name}(name)"), args.len());
                    return;
                };
                match self.g.meshes.iter().position(|(n, _)| *n == m) {
                    Some(i) => {
                        let i = if name == "insert" { self.g.fitted_mesh(i) } else { i };
                        self.emits = true;
                        self.code.push(Op::Emit(Prim::Mesh(i as u32)));
                    }
                    None => {
                        let mut d = Diagnostic::error(args[0].span(), format!("unknown mesh `{m}`"));
                        d = match did_you_mean(&m, self.g.meshes.iter().map(|(n, _)| n.as_str())) {
                            Some(s) => d.with_hint(format!("did you mean `{s}`?")),
                            None => {
                                d.with_hint(format!("declare it at the top of the file: `mesh {m} = \"{m}.obj\";`"))
                            }
                        };
                        self.errors.push(d);
                    }
                }
            }
            _ => {}
        }
    }

    /// Compiles an invocation of local slot `local` at `site` (see
    /// [`Op::Invoke`]).
    pub(super) fn invoke(&mut self, local: usize, site: u32, target: &SymRef, args: Option<&[Arg]>) {
        let args = args.unwrap_or(&[]);
        let slot = &self.slots[local];
        let (graph, rule) = (slot.graph, slot.rule);
        let info = &self.g.rules[rule];
        if args.len() != info.n_args && (graph.is_some() || slot.implicit) {
            let want = info.n_args;
            let form = format!("{}({})", target.name, info.arg_names.join(", "));
            let d = Diagnostic::error(
                target.span,
                format!(
                    "wrong number of arguments for `{}`: rule `{}` takes {want}, found {}",
                    target.name,
                    info.name,
                    args.len()
                ),
            )
            .with_hint(if want == 0 {
                format!("write `{};`", target.name)
            } else {
                format!("write `{form}`")
            });
            self.errors.push(d);
            return;
        }
        let first = self.exprs.len() as u32;
        if self.expr_args(&target.name, args).is_none() {
            return;
        }
        if let Some(g) = graph {
            self.code.push(Op::Invoke { slot: g, args: first, nargs: args.len() as u32, site });
        }
    }
}

impl SymbolCx<'_> {
    /// `roof_*(angle, overhang, ridge = …, ends = …, overhang = […],
    /// gables = "tag")`: expressions angle, overhang, ridge edge index and
    /// gable-end overhang (zero when not given) from `args`, then the
    /// per-edge overhangs.
    fn roof(&mut self, name: &str, span: Span, args: &[Arg]) {
        let form = format!("{name}(angle)` or `{name}(angle, overhang)");
        let (pos, named): (Vec<&Arg>, Vec<&Arg>) = args.iter().partition(|a| !matches!(a, Arg::Named { .. }));
        if pos.is_empty() || pos.len() > 2 {
            self.arity(name, span, &form, pos.len());
            return;
        }
        let (mut ridge, mut ridge_e, mut ends, mut list, mut scalar, mut gables) =
            (0u8, None, None, None::<Vec<ExprSrc>>, None, u32::MAX);
        for a in &named {
            let Arg::Named { name: key, span: at, value, list: is_list } = a else { continue };
            let one = match (value.as_slice(), is_list) {
                ([Arg::Expr(e)], false) => Some(e),
                _ => None,
            };
            match key.as_str() {
                "ridge" if matches!(name, "roof_gable" | "roof_shed" | "roof_ridge") => match one {
                    Some(e) => match e.bare.as_deref().and_then(crate::program::edge_side) {
                        Some(side) => ridge = side,
                        None => {
                            ridge = crate::program::RIDGE_INDEX;
                            ridge_e = Some(e.clone());
                        }
                    },
                    None => self.err(*at, "`ridge` takes a side (`front`, `back`, `left`, `right`) or an edge index"),
                },
                "ends" if matches!(name, "roof_gable" | "roof_shed" | "roof_ridge") => match one {
                    Some(e) => ends = Some(e.clone()),
                    None => self.err(*at, "`ends` takes one number: the overhang at the gable ends"),
                },
                "overhang" => {
                    let exprs: Option<Vec<ExprSrc>> = value
                        .iter()
                        .map(|v| match v {
                            Arg::Expr(e) => Some(e.clone()),
                            _ => None,
                        })
                        .collect();
                    match (exprs, is_list) {
                        (Some(v), true) => list = Some(v),
                        (Some(v), false) if pos.len() == 1 => scalar = v.into_iter().next(),
                        (Some(_), false) => self.err(*at, "the overhang is given twice"),
                        (None, _) => {
                            self.err(*at, "`overhang` takes a number or a list `[d0, d1, …]` of numbers, one per edge")
                        }
                    }
                }
                "gables" => match value.as_slice() {
                    [Arg::Str(t, _)] if !is_list => gables = self.g.intern_tag(t),
                    _ => self.err(*at, "`gables` takes a quoted tag, e.g. `gables = \"wall\"`"),
                },
                _ => {
                    let d = Diagnostic::error(*at, format!("`{name}` takes no argument `{key}`")).with_hint(
                        if matches!(name, "roof_gable" | "roof_shed" | "roof_ridge") {
                            "its named arguments are `ridge`, `ends`, `overhang` and `gables`"
                        } else {
                            "its named arguments are `overhang` and `gables`"
                        },
                    );
                    self.errors.push(d);
                }
            }
        }
        if list.is_some() && pos.len() == 2 {
            self.err(span, "the overhang is given twice (as the second argument and as a list)");
        }
        let Some(e) = self.expr_args(name, &pos.iter().map(|a| (*a).clone()).collect::<Vec<_>>()) else { return };
        let zero = |c: &mut Self| {
            let z = c.g.zero.clone();
            c.exprs.push(Expr::new(z, Vec::new(), span));
        };
        match (pos.len(), &scalar) {
            (1, Some(x)) => {
                self.expr(x);
            }
            (1, None) => zero(self),
            _ => {}
        }
        for x in [&ridge_e, &ends] {
            match x {
                Some(x) => {
                    self.expr(x);
                }
                None => zero(self),
            }
        }
        let n = list.as_ref().map_or(0, Vec::len) as u32;
        for x in list.iter().flatten() {
            self.expr(x);
        }
        self.emits = true;
        let kind = match name {
            "roof_gable" => 0,
            "roof_hip" => 1,
            "roof_pyramid" => 2,
            "roof_shed" => 3,
            _ => 4,
        };
        let at = self.span_index(span);
        let faces = self.solid_faces;
        self.code.push(Op::Roof { kind, ridge, ends: ends.is_some(), faces, args: e[0], n, span: at, gables });
    }
}

/// `#rrggbb`: six hex digits after a hash.
impl SymbolCx<'_> {
    /// `texture("file.png")` or `texture("file.png", w, h)`: w and h, the
    /// size of one copy of the image in world units (1 by default), must
    /// be known when the grammar is compiled, since the texture belongs to
    /// the tag.
    fn texture(&mut self, span: Span, args: &[Arg]) {
        const FORM: &str =
            "write `texture(\"brick.png\")` or `texture(\"brick.png\", 2, 1)` (one copy of the image covers 2 × 1 m)";
        let Some(Arg::Str(path, pspan)) = args.first() else {
            let at = args.first().map_or(span, Arg::span);
            self.errors.push(Diagnostic::error(at, "`texture` takes a quoted PNG file first").with_hint(FORM));
            return;
        };
        let mut size = [1.0, 1.0];
        match &args[1..] {
            [] => {}
            [Arg::Expr(w), Arg::Expr(h)] => {
                for (k, (e, what)) in [(w, "a texture's width"), (h, "a texture's height")].into_iter().enumerate() {
                    match self.eval_const(e, what) {
                        Some(v) if v > 0.0 && v <= 1.0e6 => size[k] = v,
                        Some(v) => {
                            let d = Diagnostic::error(
                                e.span(),
                                format!("{what} must be above 0 (and at most 1e6), found {v}"),
                            )
                            .with_hint("the size is that of one copy of the image, in world units (metres)");
                            self.errors.push(d);
                            return;
                        }
                        None => return,
                    }
                }
            }
            rest => {
                let at = rest.first().map_or(span, Arg::span);
                let d = Diagnostic::error(at, "`texture` takes a file, then no size or a width and a height")
                    .with_hint(FORM);
                self.errors.push(d);
                return;
            }
        }
        if path.is_empty() {
            self.errors.push(Diagnostic::error(*pspan, "the texture file is empty").with_hint(FORM));
            return;
        }
        let k = match self.g.textures.iter().position(|t| t.path == *path && t.size == size) {
            Some(k) => k,
            None => {
                self.g.textures.push(TextureUse { path: path.clone(), span: *pspan, size });
                self.g.textures.len() - 1
            }
        };
        self.code.push(Op::Texture(k as u32));
    }
}

fn is_hex_color(c: &str) -> bool {
    c.len() == 7 && c.starts_with('#') && c[1..].bytes().all(|b| b.is_ascii_hexdigit())
}
