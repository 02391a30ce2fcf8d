//! The compile driver: header items, rule table, template expansion, symbol
//! compilation, the axiom, reachability warnings.

use crate::assets::AssetResolver;
use crate::ast::*;
use crate::codegen::{ConstScope, Globals, KEYWORDS, OPS, RuleInfo, SymbolCx, eval_const, instance_name, reserved};
use crate::grammar::ShapeGrammar;
use crate::parser::{is_header_word, parse_file};
use genform_core::expr::did_you_mean;
use genform_core::{Diagnostic, Diagnostics, GeneratorGraph, Limits, Mesh, Severity, SourceFile, Span};
use std::sync::Arc;

/// Most instances one template rule may expand to.
const MAX_INSTANCES: i64 = 1024;
/// Most symbols a grammar may have after expansion.
const MAX_SYMBOLS: usize = 16_384;

/// See [`crate::compile`].
pub(crate) fn compile(
    file: &SourceFile,
    assets: &dyn AssetResolver,
) -> Result<(ShapeGrammar, Diagnostics), Diagnostics> {
    let (items, mut errors) = parse_file(&file.text);
    let mut warnings: Vec<Diagnostic> = Vec::new();
    let zero = genform_core::expr::parse("0")
        .ok()
        .and_then(|a| genform_core::expr::compile(&a, &genform_core::expr::Names(&[])).ok());
    let Some(zero) = zero else {
        errors.push(Diagnostic::error(Span::default(), "the expression compiler is unavailable"));
        return Err(finish(file, errors, warnings));
    };
    let mut g = Globals {
        consts: Vec::new(),
        rules: Vec::new(),
        meshes: Vec::new(),
        tags: Vec::new(),
        tags_given: Vec::new(),
        query_tags: Vec::new(),
        colors: Vec::new(),
        textures: Vec::new(),
        textured: Vec::new(),
        zero,
    };

    let mut name: Option<String> = None;
    let mut axiom: Option<SymRef> = None;
    let mut limit_items = Vec::new();
    let mut rules: Vec<Rule> = Vec::new();
    let mut footprints = Vec::new();
    let mut footprints_at = None;
    let mut footprint_props = Vec::new();
    let mut footprint_origin = None;
    let mut context: Option<(Mesh, Span)> = None;
    for item in items {
        match item {
            Item::Grammar(n, span) => {
                if name.is_some() {
                    errors.push(Diagnostic::error(span, "the grammar name is given twice"));
                }
                name.get_or_insert(n);
            }
            Item::Axiom(r) => {
                if axiom.is_some() {
                    errors.push(Diagnostic::error(r.span, "the axiom is given twice"));
                } else {
                    axiom = Some(r);
                }
            }
            Item::Limits(v) => limit_items.extend(v),
            Item::Const(n, span, e) => {
                if let Some(why) = reserved(&n) {
                    errors.push(Diagnostic::error(span, format!("`{n}` is {why} and cannot name a constant")));
                    continue;
                }
                if g.consts.iter().any(|(c, _)| *c == n) {
                    errors.push(Diagnostic::error(span, format!("constant `{n}` is defined twice")));
                    continue;
                }
                let scope = ConstScope { consts: &g.consts, template: None };
                let v = eval_const(&e, &scope, "a constant", &mut errors);
                g.consts.push((n, v.unwrap_or(0.0)));
            }
            Item::Mesh(n, span, path, pspan) => {
                if g.meshes.iter().any(|(m, _)| *m == n) {
                    errors.push(Diagnostic::error(span, format!("mesh `{n}` is defined twice")));
                    continue;
                }
                let mesh = match assets.load_mesh(&path) {
                    Ok(m) => m,
                    Err(msg) => {
                        errors.push(
                            Diagnostic::error(pspan, format!("cannot load mesh `{n}` from \"{path}\": {msg}"))
                                .with_hint("mesh paths are relative to the grammar file"),
                        );
                        Mesh::default()
                    }
                };
                g.meshes.push((n, Arc::new(mesh)));
            }
            Item::Footprints(path, pspan) => {
                if !footprints.is_empty() || footprints_at.is_some() {
                    errors.push(Diagnostic::error(pspan, "`footprints` is given twice"));
                    continue;
                }
                footprints_at = Some(pspan);
                match assets.load_footprint_set(&path) {
                    Ok(set) if set.lots.is_empty() && set.skipped.is_empty() => errors.push(
                        Diagnostic::error(pspan, format!("\"{path}\" holds no footprint"))
                            .with_hint(
                                "a GeoJSON file or GeoPackage layer (`lots.gpkg#LAYER`) of Polygon or MultiPolygon features, or an OBJ file of faces facing up (+y)",
                            ),
                    ),
                    Ok(set) => {
                        let mut skipped = set.skipped;
                        for lot in &set.lots {
                            match crate::footprint::outline(&lot.corners) {
                                Ok(outline) => {
                                    footprints.push(outline);
                                    footprint_props.push(lot.props);
                                }
                                Err(why) => skipped.push(format!("{} {why}", lot.label)),
                            }
                        }
                        if footprints.is_empty() {
                            let first = skipped.first().cloned().unwrap_or_default();
                            errors.push(Diagnostic::error(
                                pspan,
                                format!("\"{path}\" holds no usable footprint ({} skipped; {first})", skipped.len()),
                            ));
                        } else {
                            for why in skipped {
                                warnings.push(Diagnostic::warning(
                                    pspan,
                                    format!("footprints \"{path}\": {why}; the lot is skipped"),
                                ));
                            }
                        }
                        footprint_origin = set.origin;
                    }
                    Err(msg) => errors.push(
                        Diagnostic::error(pspan, format!("cannot load footprints from \"{path}\": {msg}"))
                            .with_hint("footprint paths are relative to the grammar file"),
                    ),
                }
            }
            Item::Context(path, pspan) => {
                if context.is_some() {
                    errors.push(Diagnostic::error(pspan, "`context` is given twice"));
                    continue;
                }
                match assets.load_mesh(&path) {
                    Ok(m) => context = Some((m, pspan)),
                    Err(msg) => errors.push(
                        Diagnostic::error(pspan, format!("cannot load the context mesh \"{path}\": {msg}"))
                            .with_hint("context paths are relative to the grammar file"),
                    ),
                }
            }
            Item::Rule(r) => rules.push(r),
        }
    }

    let (limits, limits_at) = limits(&limit_items, &g, &mut errors);

    // The rule table: names, template ranges, symbol ids.
    let mut kept: Vec<(Rule, Option<(i64, i64)>)> = Vec::new();
    let mut symbols = 0usize;
    for r in rules {
        if OPS.contains(&r.name.as_str()) || KEYWORDS.contains(&r.name.as_str()) || is_header_word(&r.name) {
            errors.push(Diagnostic::error(r.span, format!("`{}` is a built-in word and cannot name a rule", r.name)));
            continue;
        }
        if let Some((first, _)) = kept.iter().find(|(k, _)| k.name == r.name) {
            errors.push(
                Diagnostic::error(r.span, format!("rule `{}` is defined twice", r.name))
                    .with_label(first.span, "first defined here"),
            );
            continue;
        }
        // An invalid range still names the rule (with no instances), so
        // references to it do not cascade into more errors.
        let range = r.template.as_ref().map(|t| template_range(t, &g, &mut errors).unwrap_or((0, 0)));
        let n = range.map_or(1, |(lo, hi)| (hi - lo) as usize);
        if symbols + n > MAX_SYMBOLS {
            errors.push(Diagnostic::error(r.span, format!("the grammar expands to more than {MAX_SYMBOLS} symbols")));
            continue;
        }
        g.rules.push(RuleInfo {
            name: r.name.clone(),
            range,
            first: symbols as u32,
            n_args: r.args.len(),
            arg_names: r.args.iter().map(|(a, _)| a.clone()).collect(),
        });
        symbols += n;
        kept.push((r, range));
    }

    // Symbols.
    let mut specs = Vec::with_capacity(symbols);
    let mut codes = Vec::with_capacity(symbols);
    for (r, range) in &kept {
        let indices: Vec<Option<i64>> = match range {
            None => vec![None],
            Some((lo, hi)) => (*lo..*hi).map(Some).collect(),
        };
        for index in indices {
            let (spec, code) = SymbolCx::new(&mut g, r, index, &mut errors).compile();
            specs.push(spec);
            codes.push(code);
        }
    }

    // The axiom.
    let root = match &axiom {
        Some(a) => resolve_axiom(a, &g, &mut errors),
        None => match kept.first() {
            Some((r, _)) => {
                if !r.args.is_empty() {
                    errors.push(Diagnostic::error(
                        r.span,
                        format!("the axiom `{}` (the first rule) cannot take arguments", r.name),
                    ));
                }
                Some(0)
            }
            None => {
                if errors.is_empty() {
                    errors.push(
                        Diagnostic::error(Span::default(), "the grammar has no rules")
                            .with_hint("add a rule, e.g. `Start { box; }`"),
                    );
                }
                None
            }
        },
    };

    // The context's parts are occluders tagged `context`.
    let context: Arc<[crate::interp::occlusion::Placed]> = match context {
        Some((m, _)) => {
            let tag = g.intern_tag("context");
            crate::interp::occlusion::Placed::context(&m, tag).into()
        }
        None => Arc::new([]),
    };
    g.check_query_tags(&mut errors);
    let textures = load_textures(&g.textures, assets, &mut errors);
    let stem = std::path::Path::new(&*file.name).file_stem().map(|s| s.to_string_lossy().into_owned());
    let name = name.or(stem).unwrap_or_else(|| "grammar".into());
    let graph = GeneratorGraph { name: name.clone(), symbols: specs, root: root.unwrap_or(0) };
    if errors.is_empty()
        && let Err(msgs) = graph.check()
    {
        errors.extend(msgs.into_iter().map(|m| Diagnostic::error(Span::default(), m)));
    }
    if !errors.is_empty() {
        return Err(finish(file, errors, warnings));
    }

    // Rules no derivation can reach.
    let mut seen = vec![false; graph.symbols.len()];
    let mut stack = vec![graph.root as usize];
    seen[graph.root as usize] = true;
    while let Some(s) = stack.pop() {
        for slot in &graph.symbols[s].slots {
            let t = slot.target as usize;
            if !seen[t] && slot.prob > 0.0 {
                seen[t] = true;
                stack.push(t);
            }
        }
    }
    for ((r, _), info) in kept.iter().zip(&g.rules) {
        let n = info.range.map_or(1, |(lo, hi)| (hi - lo) as usize);
        let first = info.first as usize;
        if !seen[first..first + n].iter().any(|s| *s) {
            let root_name = &graph.symbols[graph.root as usize].name;
            warnings.push(
                Diagnostic::warning(r.span, format!("rule `{}` is unreachable from the axiom `{root_name}`", r.name))
                    .with_hint("no slot or invocation with a probability above 0 leads to it"),
            );
        }
    }

    let occlusion = codes.iter().any(|r| r.exprs.iter().any(|e| !e.queries.is_empty()));
    let texture_names: Vec<String> = textures.iter().map(|t| t.name.clone()).collect();
    g.textured_tags(&texture_names);
    let color_tags = g.color_tags();
    let base_tags = if occlusion { g.base_tags() } else { Vec::new() };
    let (texture_tags, tag_textures) = g.texture_tables(textures.len());
    if g.tags.len() > crate::scope::MAX_TAGS {
        // Tags share a word with the scope's layer (`ScopeState::tagged`).
        let n = g.tags.len();
        errors.push(
            Diagnostic::error(Span::default(), format!("the grammar makes {n} tags (with its colours and textures)"))
                .with_hint(format!("at most {} tags are possible; use fewer tags or colours", crate::scope::MAX_TAGS)),
        );
        return Err(finish(file, errors, warnings));
    }
    let meshes = g.meshes.into_iter().map(|(_, m)| m).collect();
    let check = crate::genome_check::GenomeCheck::new(&graph);
    let grammar = ShapeGrammar {
        name,
        graph,
        rules: codes,
        meshes,
        tags: g.tags,
        limits,
        file: file.clone(),
        check,
        occlusion,
        footprints,
        footprint_props,
        footprint_origin,
        context,
        start_lot: None,
        start_props: Default::default(),
        limits_at,
        color_tags,
        base_tags,
        textures,
        texture_tags,
        tag_textures,
    };
    Ok((grammar, finish(file, Vec::new(), warnings)))
}

/// Reads the images of `texture(…)` through `assets`, each named by its
/// file stem (letters, digits, `_` and `-`; numbered when two files share
/// one); a file that cannot be read or is no PNG is an error at its path.
fn load_textures(
    uses: &[crate::codegen::TextureUse],
    assets: &dyn AssetResolver,
    errors: &mut Vec<Diagnostic>,
) -> Vec<Arc<genform_core::scene::Texture>> {
    let mut out: Vec<Arc<genform_core::scene::Texture>> = Vec::new();
    for u in uses {
        let stem = std::path::Path::new(&u.path).file_stem().map(|s| s.to_string_lossy().into_owned());
        let stem: String = stem
            .unwrap_or_default()
            .chars()
            .map(|c| if c.is_ascii_alphanumeric() || c == '-' { c } else { '_' })
            .collect();
        let stem = if stem.is_empty() { "texture".to_string() } else { stem };
        let mut name = stem.clone();
        let mut n = 1;
        while out.iter().any(|t| t.name == name) {
            n += 1;
            name = format!("{stem}{n}");
        }
        let size = u.size.map(|v| v as f32);
        let loaded =
            assets.load_texture(&u.path).and_then(|bytes| genform_core::scene::Texture::from_png(&name, bytes, size));
        match loaded {
            Ok(t) => out.push(Arc::new(t)),
            Err(msg) => {
                errors.push(
                    Diagnostic::error(u.span, format!("cannot load the texture \"{}\": {msg}", u.path))
                        .with_hint("texture paths are relative to the grammar file; textures are PNG images"),
                );
                // A stand-in keeps the indices of later textures.
                out.push(Arc::new(genform_core::scene::Texture {
                    name,
                    png: Vec::new(),
                    pixels: [1, 1],
                    size: [1.0, 1.0],
                }));
            }
        }
    }
    out
}

/// Sorts by position, drops duplicates (template instances report the same
/// problem once per instance) and wraps.
fn finish(file: &SourceFile, errors: Vec<Diagnostic>, warnings: Vec<Diagnostic>) -> Diagnostics {
    let mut items: Vec<Diagnostic> = Vec::new();
    for d in errors.into_iter().chain(warnings) {
        if !items.iter().any(|x| x.span == d.span && x.message == d.message && x.severity == d.severity) {
            items.push(d);
        }
    }
    items.sort_by_key(|d| (d.span.map_or(0, |s| s.start), d.severity != Severity::Error));
    let mut out = Diagnostics::new(file.clone());
    out.items = items;
    out
}

/// The limits of the `limits` items, and where each value is written
/// (genes, depth, primitives).
fn limits(items: &[(String, Span, ExprSrc)], g: &Globals, errors: &mut Vec<Diagnostic>) -> (Limits, [Option<Span>; 3]) {
    let mut l = Limits::default();
    let mut at = [None; 3];
    for (k, span, e) in items {
        let (field, slot) = match k.as_str() {
            "genes" => (&mut l.max_genes, 0),
            "depth" => (&mut l.max_depth, 1),
            "primitives" => (&mut l.max_primitives, 2),
            other => {
                let mut d = Diagnostic::error(*span, format!("unknown limit `{other}`"));
                d = match did_you_mean(other, ["genes", "depth", "primitives"]) {
                    Some(s) => d.with_hint(format!("did you mean `{s}`?")),
                    None => d.with_hint("limits are `genes`, `depth` and `primitives`"),
                };
                errors.push(d);
                continue;
            }
        };
        let scope = ConstScope { consts: &g.consts, template: None };
        if let Some(v) = eval_const(e, &scope, "a limit", errors) {
            if v.fract() != 0.0 || !(1.0..=1.0e12).contains(&v) {
                errors.push(Diagnostic::error(e.span(), format!("a limit must be a positive integer, found {v}")));
            } else {
                *field = v as usize;
                at[slot] = Some(e.span());
            }
        }
    }
    (l, at)
}

fn template_range(t: &Template, g: &Globals, errors: &mut Vec<Diagnostic>) -> Option<(i64, i64)> {
    let mut bound = |b: &Bound| -> Option<i64> {
        let (v, span) = match b {
            Bound::Int(v, s) => (*v, *s),
            Bound::Const(c, s) => match g.consts.iter().rev().find(|(n, _)| n == c) {
                Some((_, v)) => (*v, *s),
                None => {
                    errors.push(
                        Diagnostic::error(*s, format!("unknown constant `{c}` in a template range"))
                            .with_hint("template bounds are integers or `const` names"),
                    );
                    return None;
                }
            },
        };
        if v.fract() != 0.0 || v.abs() > 1.0e9 {
            errors.push(Diagnostic::error(span, format!("a template bound must be an integer, found {v}")));
            return None;
        }
        Some(v as i64)
    };
    let lo = bound(&t.lo);
    let hi = bound(&t.hi);
    let (lo, hi) = (lo?, hi?);
    if hi <= lo {
        errors.push(
            Diagnostic::error(t.var_span, format!("the template range {lo}..{hi} is empty"))
                .with_hint("the end is exclusive: `0..8` gives the indices 0 to 7"),
        );
        return None;
    }
    if hi - lo > MAX_INSTANCES {
        errors.push(Diagnostic::error(
            t.var_span,
            format!("the template range {lo}..{hi} has more than {MAX_INSTANCES} indices"),
        ));
        return None;
    }
    Some((lo, hi))
}

fn resolve_axiom(a: &SymRef, g: &Globals, errors: &mut Vec<Diagnostic>) -> Option<u32> {
    let Some(info) = g.rules.iter().find(|r| r.name == a.name) else {
        let mut d = Diagnostic::error(a.span, format!("unknown rule `{}` as the axiom", a.name));
        if let Some(s) = did_you_mean(&a.name, g.rules.iter().map(|r| r.name.as_str())) {
            d = d.with_hint(format!("did you mean `{s}`?"));
        }
        errors.push(d);
        return None;
    };
    if info.n_args > 0 {
        errors.push(Diagnostic::error(
            a.span,
            format!("the axiom `{}` cannot take arguments (nothing invokes it)", a.name),
        ));
    }
    match (info.range, &a.index) {
        (None, None) => Some(info.first),
        (None, Some(_)) => {
            errors.push(Diagnostic::error(a.span, format!("`{}` is not a template rule", a.name)));
            None
        }
        (Some((lo, _)), None) => {
            errors.push(
                Diagnostic::error(a.span, format!("`{}` is a template rule and needs an index", a.name))
                    .with_hint(format!("write `axiom {}<{lo}>;`", a.name)),
            );
            None
        }
        (Some((lo, hi)), Some(e)) => {
            let scope = ConstScope { consts: &g.consts, template: None };
            let v = eval_const(e, &scope, "the axiom's index", errors)?;
            if v.fract() != 0.0 || v < lo as f64 || v >= hi as f64 {
                errors.push(Diagnostic::error(
                    e.span(),
                    format!("the axiom's index {v} is outside {lo}..{hi} (`{}`)", instance_name(&a.name, lo)),
                ));
                return None;
            }
            Some(info.first + (v as i64 - lo) as u32)
        }
    }
}
