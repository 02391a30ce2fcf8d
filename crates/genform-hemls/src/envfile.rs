//! The environment file (TOML): growth settings that mirror Genr8's `genr8`
//! flags, plus attractors, repellers, gravity and boundaries.
//!
//! ```toml
//! steps = 4                      # -n
//! scale = 1.5                    # -s, or [sx, sy, sz]
//! start_length = 1               # -sl
//! start_position = [0, 0, 0]     # -sp
//! fixed_center = false           # -fc
//! fixed_perimeter = false        # -fp
//! branch_angle = 30              # -ba (degrees, 0–90)
//! branch_length = -1             # -bl (negative: no limit)
//! join = "scalar"                # scalar (default), facing, cone or paper
//! gravity = { axis = "z", magnitude = -0.1 }   # -g z -0.1
//! min_distance = 0.001           # genform: smallest distance the charge law uses
//!
//! [[attractor]]                  # also [[repeller]]
//! position = [0, 0, 3]
//! strength = 1                   # c
//! exponent = 2                   # e
//!
//! [[boundary]]
//! sphere = { center = [0, 0, -2], radius = 1.5 }   # or box = { min, max },
//! behaviour = "slide"            # plane = { point, normal }, mesh = "file.obj"
//! keep = "outside"               # or "stop", "soft"; "inside"
//!
//! [limits]
//! max_vertices = 2000000
//! ```
//!
//! Every key is optional. Unknown keys, wrong types, non-finite numbers and
//! out-of-range values are errors with `file:line:col`; all of them are
//! reported at once. This module reads no files: [`EnvSpec::resolve`] gets
//! mesh boundaries from a loader the caller gives.

use crate::env::{Axis, Behaviour, Boundary, Charge, ChargeKind, Environment, Gravity, Keep};
use crate::settings::{GrowthLimits, Settings};
use genform_core::{Diagnostic, Diagnostics, Mesh, SourceFile, Span};
use glam::DVec3;
use toml::Spanned;
use toml::de::{DeTable, DeValue};

/// Most derivation steps an environment file may ask for.
pub const MAX_STEPS: u32 = 64;

/// Smallest `scale`: the growth shrinks by it every step.
pub const MIN_SCALE: f64 = 0.01;

/// Largest `scale`: it compounds every step (10 over 20 steps is 10²⁰).
pub const MAX_SCALE: f64 = 10.0;

/// A parsed environment file: settings, charges, gravity, and boundaries
/// whose meshes are not loaded yet.
#[derive(Clone, Debug, PartialEq)]
pub struct EnvSpec {
    /// Growth settings (the `genr8` flags and element limits).
    pub settings: Settings,
    /// Attractors then repellers, each in file order.
    pub charges: Vec<Charge>,
    /// Gravity, if any.
    pub gravity: Option<Gravity>,
    /// Boundaries in file order.
    pub boundaries: Vec<BoundarySpec>,
    /// The smallest distance the charge law uses
    /// ([`Environment::min_distance`]).
    pub min_distance: f64,
}

impl Default for EnvSpec {
    fn default() -> Self {
        EnvSpec {
            settings: Settings::default(),
            charges: Vec::new(),
            gravity: None,
            boundaries: Vec::new(),
            min_distance: Environment::MIN_DISTANCE,
        }
    }
}

/// One `[[boundary]]` of an environment file.
#[derive(Clone, Debug, PartialEq)]
pub struct BoundarySpec {
    /// The geometry (a mesh by path).
    pub shape: ShapeSpec,
    /// Slide (default), stop or soft.
    pub behaviour: Behaviour,
    /// Allowed side (default outside).
    pub keep: Keep,
}

/// The geometry of a [`BoundarySpec`].
#[derive(Clone, Debug, PartialEq)]
pub enum ShapeSpec {
    /// `sphere = { center, radius }`.
    Sphere {
        /// Centre.
        center: DVec3,
        /// Radius (positive).
        radius: f64,
    },
    /// `box = { min, max }`.
    Box {
        /// Lowest corner.
        min: DVec3,
        /// Highest corner (greater than `min` on every axis).
        max: DVec3,
    },
    /// `plane = { point, normal }`; the normal's side is the front.
    Plane {
        /// A point on the plane.
        point: DVec3,
        /// Normal (not zero; not normalised here).
        normal: DVec3,
    },
    /// `mesh = "path"`, as written (the caller resolves it).
    Mesh {
        /// The path as written in the file.
        path: String,
        /// Where the file names it (`file:line:col`), for the errors of
        /// reading it.
        at: String,
    },
}

impl EnvSpec {
    /// The mesh paths the boundaries name, in order.
    pub fn mesh_paths(&self) -> impl Iterator<Item = &str> {
        self.boundaries.iter().filter_map(|b| match &b.shape {
            ShapeSpec::Mesh { path, .. } => Some(path.as_str()),
            _ => None,
        })
    }

    /// Builds the environment; `load_mesh` gets each mesh path as written
    /// (the CLI resolves it relative to the environment file and reads it).
    /// Errors name the boundary and the path; a mesh's errors start at the
    /// position that names it.
    pub fn resolve(
        self,
        load_mesh: &mut dyn FnMut(&str) -> Result<Mesh, String>,
    ) -> Result<(Settings, Environment), String> {
        let mut env = Environment {
            charges: self.charges,
            gravity: self.gravity,
            boundaries: Vec::with_capacity(self.boundaries.len()),
            min_distance: self.min_distance,
        };
        for (i, b) in self.boundaries.into_iter().enumerate() {
            let boundary = match b.shape {
                ShapeSpec::Sphere { center, radius } => Boundary::sphere(center, radius),
                ShapeSpec::Box { min, max } => Boundary::cuboid(min, max),
                ShapeSpec::Plane { point, normal } => Boundary::plane(point, normal)
                    .ok_or_else(|| format!("boundary {}: the plane's normal is zero", i + 1))?,
                ShapeSpec::Mesh { path, at } => {
                    let mesh =
                        load_mesh(&path).map_err(|e| format!("{at}: boundary {} (mesh `{path}`): {e}", i + 1))?;
                    Boundary::mesh(&mesh).map_err(|e| format!("{at}: boundary {} (mesh `{path}`): {e}", i + 1))?
                }
            };
            env.boundaries.push(boundary.with_behaviour(b.behaviour).with_keep(b.keep));
        }
        Ok((self.settings, env))
    }
}

/// Parses an environment file. Every problem is reported, each at its
/// `line:col`.
pub fn parse_env(file: &SourceFile) -> Result<EnvSpec, Diagnostics> {
    let mut diags = Diagnostics::new(file.clone());
    let (root, errors) = DeTable::parse_recoverable(&file.text);
    if !errors.is_empty() {
        for e in errors {
            // Errors without a place (the parser's recursion limit) go at the file's start.
            let span = e.span().map_or(Span::new(0, 0), |r| Span::new(r.start, r.end));
            let message = format!("invalid TOML: {}", e.message().trim());
            diags.push(Diagnostic::error(span, message));
        }
        return Err(diags);
    }
    let mut r = Reader { errors: Vec::new(), file };
    let spec = r.document(root.get_ref());
    if r.errors.is_empty() {
        Ok(spec)
    } else {
        r.errors.sort_by_key(|d| d.span.map_or(0, |s| s.start));
        diags.items = r.errors;
        Err(diags)
    }
}

const TOP_KEYS: &[&str] = &[
    "steps",
    "scale",
    "start_length",
    "start_position",
    "fixed_center",
    "fixed_perimeter",
    "branch_angle",
    "branch_length",
    "join",
    "gravity",
    "min_distance",
    "attractor",
    "repeller",
    "boundary",
    "limits",
];
const CHARGE_KEYS: &[&str] = &["position", "strength", "exponent"];
const GRAVITY_KEYS: &[&str] = &["axis", "magnitude"];
const BOUNDARY_KEYS: &[&str] = &["sphere", "box", "plane", "mesh", "behaviour", "keep"];
const SHAPES: &[&str] = &["sphere", "box", "plane", "mesh"];
const LIMIT_KEYS: &[&str] = &["max_vertices", "max_edges", "max_faces"];

type Value<'i> = Spanned<DeValue<'i>>;

fn span_of<T>(v: &Spanned<T>) -> Span {
    let r = v.span();
    Span::new(r.start, r.end)
}

/// Walks the parsed document, collecting errors.
struct Reader<'f> {
    errors: Vec<Diagnostic>,
    /// The file read (positions of mesh paths, for the errors of reading them).
    file: &'f SourceFile,
}

impl Reader<'_> {
    fn error(&mut self, span: Span, message: impl Into<String>) -> &mut Diagnostic {
        self.errors.push(Diagnostic::error(span, message));
        self.errors.last_mut().expect("just pushed")
    }

    fn document(&mut self, root: &DeTable<'_>) -> EnvSpec {
        let mut spec = EnvSpec::default();
        self.check_keys(root, TOP_KEYS, "the environment file");
        let s = &mut spec.settings;
        if let Some(v) = root.get("steps")
            && let Some(n) = self.integer(v, "steps")
        {
            if (0..=MAX_STEPS as i64).contains(&n) {
                s.steps = n as u32;
            } else {
                self.error(span_of(v), format!("`steps` must be from 0 to {MAX_STEPS}, not {n}")).hints.push(
                    "growth is exponential (each step multiplies the elements by about 4); Genr8 advises at most about 4 steps".into(),
                );
            }
        }
        if let Some(v) = root.get("scale")
            && let Some(scale) = self.scale(v)
        {
            s.scale = scale;
        }
        if let Some(v) = root.get("start_length") {
            s.start_length = self.positive(v, "start_length").unwrap_or(s.start_length);
        }
        if let Some(v) = root.get("start_position") {
            s.start_position = self.vec3(v, "start_position").unwrap_or(s.start_position);
        }
        if let Some(v) = root.get("fixed_center") {
            s.fixed_center = self.boolean(v, "fixed_center").unwrap_or(s.fixed_center);
        }
        if let Some(v) = root.get("fixed_perimeter") {
            s.fixed_perimeter = self.boolean(v, "fixed_perimeter").unwrap_or(s.fixed_perimeter);
        }
        if let Some(v) = root.get("branch_angle")
            && let Some(a) = self.number(v, "branch_angle")
        {
            if (0.0..=90.0).contains(&a) {
                s.branch_angle = a;
            } else {
                self.error(span_of(v), format!("`branch_angle` must be from 0 to 90 degrees, not {a}"));
            }
        }
        if let Some(v) = root.get("branch_length") {
            s.branch_length = self.number(v, "branch_length").unwrap_or(s.branch_length);
        }
        if let Some(v) = root.get("join")
            && let Some(name) = self.string(v, "join")
        {
            match crate::settings::JoinTest::from_name(name) {
                Some(t) => s.join = t,
                None => {
                    let names: Vec<String> =
                        crate::settings::JoinTest::ALL.iter().map(|t| format!("\"{}\"", t.name())).collect();
                    let (last, rest) = names.split_last().expect("four readings");
                    let names = format!("{} or {last}", rest.join(", "));
                    self.error(span_of(v), format!("`join` must be {names}, not \"{name}\""));
                }
            }
        }
        if let Some(v) = root.get("limits") {
            self.limits(v, &mut s.limits);
        }
        if let Some(v) = root.get("min_distance") {
            spec.min_distance = self.positive(v, "min_distance").unwrap_or(spec.min_distance);
        }
        if let Some(v) = root.get("gravity") {
            spec.gravity = self.gravity(v);
        }
        for kind in [ChargeKind::Attractor, ChargeKind::Repeller] {
            if let Some(v) = root.get(kind.name()) {
                for t in self.tables(v, kind.name()) {
                    if let Some(c) = self.charge(t, kind) {
                        spec.charges.push(c);
                    }
                }
            }
        }
        if let Some(v) = root.get("boundary") {
            for t in self.tables(v, "boundary") {
                if let Some(b) = self.boundary(t) {
                    spec.boundaries.push(b);
                }
            }
        }
        spec
    }

    /// Reports every key of `table` not in `allowed`.
    fn check_keys(&mut self, table: &DeTable<'_>, allowed: &[&str], what: &str) {
        for key in table.keys() {
            let name: &str = key.get_ref();
            if allowed.contains(&name) {
                continue;
            }
            let d = self.error(span_of(key), format!("unknown key `{name}` in {what}"));
            match closest(name, allowed) {
                Some(near) => d.hints.push(format!("did you mean `{near}`?")),
                None => d.hints.push(format!("the keys here are: {}", allowed.join(", "))),
            }
        }
    }

    fn type_error(&mut self, v: &Value<'_>, key: &str, expected: &str) {
        self.error(span_of(v), format!("`{key}` must be {expected}, not {}", describe(v.get_ref())));
    }

    fn number(&mut self, v: &Value<'_>, key: &str) -> Option<f64> {
        let x = match v.get_ref() {
            DeValue::Integer(i) => i64::from_str_radix(i.as_str(), i.radix()).ok().map(|n| n as f64),
            DeValue::Float(f) => f.as_str().parse::<f64>().ok(),
            _ => {
                self.type_error(v, key, "a number");
                return None;
            }
        };
        match x {
            Some(x) if x.is_finite() => Some(x),
            _ => {
                self.error(span_of(v), format!("`{key}` must be a finite number"));
                None
            }
        }
    }

    fn positive(&mut self, v: &Value<'_>, key: &str) -> Option<f64> {
        let x = self.number(v, key)?;
        if x > 0.0 {
            Some(x)
        } else {
            self.error(span_of(v), format!("`{key}` must be positive, not {x}"));
            None
        }
    }

    fn integer(&mut self, v: &Value<'_>, key: &str) -> Option<i64> {
        match v.get_ref() {
            DeValue::Integer(i) => match i64::from_str_radix(i.as_str(), i.radix()) {
                Ok(n) => Some(n),
                Err(_) => {
                    self.error(span_of(v), format!("`{key}` is too large"));
                    None
                }
            },
            _ => {
                self.type_error(v, key, "a whole number");
                None
            }
        }
    }

    fn boolean(&mut self, v: &Value<'_>, key: &str) -> Option<bool> {
        match v.get_ref() {
            DeValue::Boolean(b) => Some(*b),
            _ => {
                self.type_error(v, key, "`true` or `false`");
                None
            }
        }
    }

    fn string<'v>(&mut self, v: &'v Value<'_>, key: &str) -> Option<&'v str> {
        match v.get_ref() {
            DeValue::String(s) => Some(s),
            _ => {
                self.type_error(v, key, "a string");
                None
            }
        }
    }

    fn table<'v, 'i>(&mut self, v: &'v Value<'i>, key: &str) -> Option<&'v DeTable<'i>> {
        match v.get_ref() {
            DeValue::Table(t) => Some(t),
            _ => {
                self.type_error(v, key, "a table");
                None
            }
        }
    }

    /// `[x, y, z]` of finite numbers.
    fn vec3(&mut self, v: &Value<'_>, key: &str) -> Option<DVec3> {
        let DeValue::Array(items) = v.get_ref() else {
            self.type_error(v, key, "an array of three numbers `[x, y, z]`");
            return None;
        };
        if items.len() != 3 {
            self.error(span_of(v), format!("`{key}` must have three numbers `[x, y, z]`, not {}", items.len()));
            return None;
        }
        let mut out = [0.0; 3];
        let mut ok = true;
        for (o, item) in out.iter_mut().zip(items.iter()) {
            match self.number(item, key) {
                Some(x) => *o = x,
                None => ok = false,
            }
        }
        ok.then(|| DVec3::from_array(out))
    }

    /// `scale = s` or `scale = [sx, sy, sz]`, all positive.
    fn scale(&mut self, v: &Value<'_>) -> Option<DVec3> {
        let s = match v.get_ref() {
            DeValue::Array(_) => self.vec3(v, "scale")?,
            DeValue::Integer(_) | DeValue::Float(_) => DVec3::splat(self.number(v, "scale")?),
            _ => {
                self.type_error(v, "scale", "a number or an array `[sx, sy, sz]`");
                return None;
            }
        };
        if s.min_element() >= MIN_SCALE && s.max_element() <= MAX_SCALE {
            Some(s)
        } else {
            self.error(
                span_of(v),
                format!(
                    "`scale` must lie from {MIN_SCALE} to {MAX_SCALE} (below 1 shrinks, above 1 grows; it compounds \
                     every step)"
                ),
            );
            None
        }
    }

    /// The tables of `[[name]]` (or `name = [{…}, …]`).
    fn tables<'v, 'i>(&mut self, v: &'v Value<'i>, key: &str) -> Vec<&'v Value<'i>> {
        match v.get_ref() {
            DeValue::Array(items) => {
                let mut out = Vec::new();
                for item in items.iter() {
                    if item.get_ref().is_table() {
                        out.push(item);
                    } else {
                        self.type_error(item, key, "a table");
                    }
                }
                out
            }
            _ => {
                self.type_error(v, key, &format!("an array of tables `[[{key}]]`"));
                Vec::new()
            }
        }
    }

    /// A required key of a table; the error points at the table.
    fn required<'v, 'i>(
        &mut self,
        table: &'v DeTable<'i>,
        at: &Value<'_>,
        key: &str,
        what: &str,
    ) -> Option<&'v Value<'i>> {
        let v = table.get(key);
        if v.is_none() {
            self.error(span_of(at), format!("{what} needs `{key}`"));
        }
        v
    }

    fn limits(&mut self, v: &Value<'_>, limits: &mut GrowthLimits) {
        let Some(t) = self.table(v, "limits") else { return };
        self.check_keys(t, LIMIT_KEYS, "`[limits]`");
        for (key, slot) in [
            ("max_vertices", &mut limits.max_vertices),
            ("max_edges", &mut limits.max_edges),
            ("max_faces", &mut limits.max_faces),
        ] {
            if let Some(x) = t.get(key)
                && let Some(n) = self.integer(x, key)
            {
                if n >= 1 {
                    *slot = n as usize;
                } else {
                    self.error(span_of(x), format!("`{key}` must be at least 1, not {n}"));
                }
            }
        }
    }

    fn gravity(&mut self, v: &Value<'_>) -> Option<Gravity> {
        let t = self.table(v, "gravity")?;
        self.check_keys(t, GRAVITY_KEYS, "`gravity`");
        let axis = self.required(t, v, "axis", "`gravity`").and_then(|a| {
            let name = self.string(a, "axis")?;
            match name {
                "x" => Some(Axis::X),
                "y" => Some(Axis::Y),
                "z" => Some(Axis::Z),
                _ => {
                    self.error(span_of(a), format!("`axis` must be \"x\", \"y\" or \"z\", not \"{name}\""));
                    None
                }
            }
        });
        let magnitude = self.required(t, v, "magnitude", "`gravity`").and_then(|m| self.number(m, "magnitude"));
        Some(Gravity { axis: axis?, magnitude: magnitude? })
    }

    fn charge(&mut self, v: &Value<'_>, kind: ChargeKind) -> Option<Charge> {
        let t = v.get_ref().as_table()?;
        let what = format!("`[[{}]]`", kind.name());
        self.check_keys(t, CHARGE_KEYS, &what);
        let position = self.required(t, v, "position", &what).and_then(|p| self.vec3(p, "position"));
        let strength = match t.get("strength") {
            Some(s) => self.number(s, "strength").and_then(|c| {
                if c >= 0.0 {
                    Some(c)
                } else {
                    let d = self.error(span_of(s), format!("`strength` must not be negative, not {c}"));
                    d.hints.push(match kind {
                        ChargeKind::Attractor => "to push vertices away, use `[[repeller]]`".into(),
                        ChargeKind::Repeller => "to pull vertices closer, use `[[attractor]]`".into(),
                    });
                    None
                }
            }),
            None => Some(Charge::DEFAULT_STRENGTH),
        };
        let exponent = match t.get("exponent") {
            Some(e) => self.number(e, "exponent"),
            None => Some(Charge::DEFAULT_EXPONENT),
        };
        Some(Charge { kind, position: position?, strength: strength?, exponent: exponent? })
    }

    fn boundary(&mut self, v: &Value<'_>) -> Option<BoundarySpec> {
        let t = v.get_ref().as_table()?;
        self.check_keys(t, BOUNDARY_KEYS, "`[[boundary]]`");
        let behaviour = match t.get("behaviour") {
            Some(b) => self.string(b, "behaviour").and_then(|name| match name {
                "slide" => Some(Behaviour::Slide),
                "stop" => Some(Behaviour::Stop),
                "soft" => Some(Behaviour::Soft),
                _ => {
                    self.error(
                        span_of(b),
                        format!("`behaviour` must be \"slide\", \"stop\" or \"soft\", not \"{name}\""),
                    );
                    None
                }
            }),
            None => Some(Behaviour::Slide),
        };
        let keep = match t.get("keep") {
            Some(k) => self.string(k, "keep").and_then(|name| match name {
                "outside" => Some(Keep::Outside),
                "inside" => Some(Keep::Inside),
                _ => {
                    let d = self.error(span_of(k), format!("`keep` must be \"outside\" or \"inside\", not \"{name}\""));
                    d.hints.push("\"outside\" makes an obstacle, \"inside\" an enclosure".into());
                    None
                }
            }),
            None => Some(Keep::Outside),
        };
        let mut shapes: Vec<_> = SHAPES.iter().filter_map(|&k| t.get_key_value(k)).collect();
        shapes.sort_by_key(|(k, _)| k.span().start);
        let shape = match shapes.as_slice() {
            [] => {
                self.error(span_of(v), "a `[[boundary]]` needs a shape: `sphere`, `box`, `plane` or `mesh`");
                None
            }
            [(key, value)] => self.shape(key.get_ref(), value),
            [(first, _), rest @ ..] => {
                for (key, _) in rest {
                    let d = self.error(
                        span_of(key),
                        format!(
                            "a `[[boundary]]` has one shape, but `{}` comes with `{}`",
                            key.get_ref(),
                            first.get_ref()
                        ),
                    );
                    d.hints.push("write one `[[boundary]]` table per shape".into());
                }
                None
            }
        };
        Some(BoundarySpec { shape: shape?, behaviour: behaviour?, keep: keep? })
    }

    fn shape(&mut self, key: &str, v: &Value<'_>) -> Option<ShapeSpec> {
        if key == "mesh" {
            let path = self.string(v, "mesh")?;
            if path.trim().is_empty() {
                self.error(span_of(v), "`mesh` must name an OBJ file");
                return None;
            }
            let at = self.file.location(span_of(v).start);
            return Some(ShapeSpec::Mesh { path: path.to_string(), at });
        }
        let t = self.table(v, key)?;
        let what = format!("`{key}`");
        let (a, b) = match key {
            "sphere" => ("center", "radius"),
            "box" => ("min", "max"),
            _ => ("point", "normal"),
        };
        self.check_keys(t, &[a, b], &what);
        let first = self.required(t, v, a, &what).and_then(|x| self.vec3(x, a));
        let second_value = self.required(t, v, b, &what);
        match key {
            "sphere" => {
                let radius = second_value.and_then(|r| {
                    let x = self.number(r, "radius")?;
                    if x > 0.0 {
                        Some(x)
                    } else {
                        self.error(span_of(r), format!("`radius` must be positive, not {x}"));
                        None
                    }
                });
                Some(ShapeSpec::Sphere { center: first?, radius: radius? })
            }
            "box" => {
                let sv = second_value?;
                let max = self.vec3(sv, "max")?;
                let min = first?;
                if !max.cmpgt(min).all() {
                    let d = self.error(span_of(sv), "`max` must be greater than `min` on every axis");
                    d.hints.push(format!("min is [{}, {}, {}]", min.x, min.y, min.z));
                    return None;
                }
                Some(ShapeSpec::Box { min, max })
            }
            _ => {
                let sv = second_value?;
                let normal = self.vec3(sv, "normal")?;
                if normal.length_squared() == 0.0 || !normal.length_squared().is_finite() {
                    self.error(span_of(sv), "`normal` must not be zero")
                        .hints
                        .push("the plane's normal points to the side that is kept (with keep = \"outside\")".into());
                    return None;
                }
                Some(ShapeSpec::Plane { point: first?, normal })
            }
        }
    }
}

/// A short description of a value's type for messages.
fn describe(v: &DeValue<'_>) -> &'static str {
    match v {
        DeValue::String(_) => "a string",
        DeValue::Integer(_) => "an integer",
        DeValue::Float(_) => "a number with a fraction",
        DeValue::Boolean(_) => "a boolean",
        DeValue::Datetime(_) => "a date",
        DeValue::Array(_) => "an array",
        DeValue::Table(_) => "a table",
    }
}

/// The allowed key closest to `name` (typos, `repellor`).
fn closest<'a>(name: &str, allowed: &[&'a str]) -> Option<&'a str> {
    genform_core::expr::did_you_mean(name, allowed.iter().copied())
}
