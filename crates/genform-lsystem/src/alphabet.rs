//! Module symbols: a name with a parameter count, and what the turtle does
//! with it.

/// Index of a symbol in an [`Alphabet`].
pub type Sym = u16;

/// What the turtle does for a module (ABOP p. 19 and L-Py's turtle).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Command {
    /// `F`: move forward drawing a segment.
    Draw,
    /// `f` and `G`: move forward without drawing.
    Move,
    /// `+`: turn left about U.
    Left,
    /// `-`: turn right about U.
    Right,
    /// `&`: pitch down about L.
    Down,
    /// `^`: pitch up about L.
    Up,
    /// `\`: roll left about H.
    RollLeft,
    /// `/`: roll right about H.
    RollRight,
    /// `|`: turn around.
    TurnAround,
    /// `$`: roll so that L is horizontal.
    RollHorizontal,
    /// `[`: push the turtle state.
    Push,
    /// `]`: pop the turtle state.
    Pop,
    /// `!`: set (with a parameter) or decrease the width.
    Width,
    /// `_` (L-Py's IncWidth): set (with a parameter) or increase the width.
    WidthUp,
    /// `'` and `;`: set (with a parameter) or increment the colour index.
    Color,
    /// `,` (L-Py's DecColor): set (with a parameter) or decrement the
    /// colour index.
    ColorDown,
    /// `@R(hx, hy, hz, ux, uy, uz)` (L-Py's SetHead): set the heading and up
    /// vectors.
    SetHead,
    /// `@D(s)` (L-Py's SetScale): set the turtle's scale.
    SetScale,
    /// `@Di(f)` (L-Py's MultScale): multiply the scale.
    MultScale,
    /// `@Dd(f)` (L-Py's DivScale): divide the scale.
    DivScale,
    /// `{`: start a polygon.
    PolygonStart,
    /// `.`: record a polygon vertex.
    PolygonVertex,
    /// `}`: close the polygon.
    PolygonEnd,
    /// `@O`: a sphere of the given radius (default: half the width).
    Sphere,
    /// `@Gc` (L-Py's StartGC): start a generalized cylinder; the `F`s that
    /// follow on the branch are swept into one mesh.
    CylinderStart,
    /// `@Ge` (L-Py's EndGC): end the generalized cylinder.
    CylinderEnd,
    /// `%`: cut the rest of the branch (during derivation).
    Cut,
    /// No drawing meaning.
    None,
}

impl Command {
    /// The command of a module name.
    pub fn of(name: &str) -> Command {
        match name {
            "F" => Command::Draw,
            "f" | "G" => Command::Move,
            "+" => Command::Left,
            "-" => Command::Right,
            "&" => Command::Down,
            "^" => Command::Up,
            "\\" => Command::RollLeft,
            "/" => Command::RollRight,
            "|" => Command::TurnAround,
            "$" => Command::RollHorizontal,
            "[" => Command::Push,
            "]" => Command::Pop,
            "!" => Command::Width,
            "_" => Command::WidthUp,
            "'" | ";" => Command::Color,
            "," => Command::ColorDown,
            "@R" => Command::SetHead,
            "@D" => Command::SetScale,
            "@Di" => Command::MultScale,
            "@Dd" => Command::DivScale,
            "{" => Command::PolygonStart,
            "." => Command::PolygonVertex,
            "}" => Command::PolygonEnd,
            "%" => Command::Cut,
            "@O" => Command::Sphere,
            "@Gc" => Command::CylinderStart,
            "@Ge" => Command::CylinderEnd,
            _ => Command::None,
        }
    }
}

/// What a turtle-looking module genform does not draw means in L-Py/cpfg,
/// or `None` when the name is not such a command (a plain symbol, or one
/// the turtle implements). Used to warn instead of staying silent.
pub fn unsupported(name: &str) -> Option<&'static str> {
    Some(match name {
        "~" => "predefined surface",
        "@M" => "move to a position",
        "@v" => "roll to vertical",
        "@B" => "box",
        "@b" => "quad",
        "@o" => "circle",
        "@L" => "text label",
        "@g" => "PlantGL shape",
        "@Ts" => "elasticity",
        "@Tp" => "tropism",
        "@2D" => "screen projection",
        "@3D" => "world projection",
        "?R" => "right-vector query",
        "?F" => "frame query",
        "?I" => "iterator query",
        _ if name.starts_with('@') && Command::of(name) == Command::None => "turtle command",
        _ => return None,
    })
}

/// One symbol.
#[derive(Clone, Debug, PartialEq)]
pub struct SymbolInfo {
    /// The module name.
    pub name: String,
    /// Number of parameters.
    pub arity: u8,
    /// The turtle command.
    pub command: Command,
    /// For a module of an L-Py file, how its parameters print as Python
    /// prints them (`None`: genform's plain numbers).
    pub python: Option<PyParams>,
}

/// Which parameters of a module hold Python floats and which booleans, so
/// a derived string prints as L-Py prints it: `A(6.0)` and `B(True)`
/// where genform's numbers are `6` and `1`. Any other parameter prints as
/// a Python int when whole.
#[derive(Clone, Debug, Default, PartialEq, Eq)]
pub struct PyParams {
    /// After 0, 1, … steps; the last entry holds for every later step.
    pub steps: Vec<PyKinds>,
}

impl PyParams {
    /// The kinds after `steps` steps.
    pub fn at(&self, steps: usize) -> PyKinds {
        self.steps.get(steps).or(self.steps.last()).copied().unwrap_or_default()
    }
}

/// Parameters that always hold floats or booleans (bit `i`: parameter
/// `i`, the first 64).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct PyKinds {
    /// Always floats.
    pub floats: u64,
    /// Always booleans.
    pub bools: u64,
}

/// Every (name, parameter count) pair a grammar uses.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Alphabet {
    /// The symbols, indexed by [`Sym`].
    pub symbols: Vec<SymbolInfo>,
}

impl Alphabet {
    /// The most symbols an alphabet holds.
    pub const MAX: usize = u16::MAX as usize;

    /// The symbol of `name` with `arity` parameters, if used.
    pub fn find(&self, name: &str, arity: usize) -> Option<Sym> {
        self.symbols.iter().position(|s| s.name == name && s.arity as usize == arity).map(|i| i as Sym)
    }

    /// The symbol of `name` with `arity` parameters, added on first use;
    /// `None` when the alphabet is full or the arity exceeds 255.
    pub fn intern(&mut self, name: &str, arity: usize) -> Option<Sym> {
        if let Some(s) = self.find(name, arity) {
            return Some(s);
        }
        if self.symbols.len() >= Self::MAX || arity > u8::MAX as usize {
            return None;
        }
        self.symbols.push(SymbolInfo {
            name: name.to_string(),
            arity: arity as u8,
            command: Command::of(name),
            python: None,
        });
        Some((self.symbols.len() - 1) as Sym)
    }

    /// Parameter count of `s`.
    #[inline]
    pub fn arity(&self, s: Sym) -> usize {
        self.symbols[s as usize].arity as usize
    }

    /// The turtle command of `s`.
    #[inline]
    pub fn command(&self, s: Sym) -> Command {
        self.symbols[s as usize].command
    }

    /// Every symbol whose name is `name`, any arity.
    pub fn named<'a>(&'a self, name: &'a str) -> impl Iterator<Item = Sym> + 'a {
        self.symbols.iter().enumerate().filter(move |(_, s)| s.name == name).map(|(i, _)| i as Sym)
    }
}
