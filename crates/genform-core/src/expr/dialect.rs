//! Dialects: how a host language writes the one expression language.
//!
//! Every front end parses its formulas with this module's parser. Most use
//! [`Dialect::STANDARD`]; a host whose own syntax already claims a character
//! the standard dialect uses (box-split's `#` comments and `//` integer
//! division) describes its variant here instead of keeping a parser of its
//! own, so precedence, nesting limits and spans stay one implementation.

/// A variant of the expression syntax. The compiled language — names,
/// functions, values — is the same in every dialect; a dialect changes only
/// how text is read and how parse errors are worded.
#[derive(Clone, Copy, Debug)]
pub struct Dialect<'a> {
    /// `#` starts a line comment, `a // b` is `floor(a / b)` and `a % b` is
    /// `mod(a, b)` (the remainder with the divisor's sign). Otherwise `//`
    /// and `/* */` are comments and `%` is the truncated remainder.
    pub hash_comments: bool,
    /// Word-logic precedence: `not`/`!` binds looser than comparisons
    /// (`not a < b` is `not (a < b)`), comparisons do not chain, a single
    /// `=` is reported as a mistaken `==`, and there is no `?:`.
    pub word_logic: bool,
    /// `_` may separate digits (`1_000`).
    pub digit_separators: bool,
    /// Names may contain dots (`size.x`).
    pub dotted_names: bool,
    /// Words that cannot be names (the host's keywords).
    pub reserved: &'a [&'a str],
    /// Calls whose one argument is host text, not an expression.
    pub raw_argument: Option<RawArgument<'a>>,
    /// How parse errors name things.
    pub wording: Wording<'a>,
}

/// Calls such as box-split's `FULL(minecraft:stone)` whose argument is
/// read by the host's scanner. The call parses as [`super::Node::Call`]
/// with one [`super::Node::Var`] argument holding the text as written.
#[derive(Clone, Copy, Debug)]
pub struct RawArgument<'a> {
    /// The functions that take a raw argument.
    pub calls: &'a [&'a str],
    /// What the argument is, for messages (`"block type"`).
    pub noun: &'a str,
    /// Hint for a missing argument.
    pub hint: &'a str,
    /// The end of the argument starting at byte `start` of the text
    /// (`start` when there is none).
    pub scan: fn(text: &str, start: usize) -> usize,
}

/// The words parse errors use.
#[derive(Clone, Copy, Debug)]
pub struct Wording<'a> {
    /// An expression, with its article (`"an expression"`, `"a formula"`).
    pub expression: &'a str,
    /// The hint after "expected an expression".
    pub hint: &'a str,
    /// The end of the text (`"end of input"`, `"the end of the file"`).
    pub end: &'a str,
    /// Name unexpected tokens by their text as written (`` `{` ``) rather
    /// than by kind (``number `2` ``, "an unexpected character").
    pub quote_source: bool,
}

impl Dialect<'static> {
    /// The expression syntax of every front end that does not say
    /// otherwise.
    pub const STANDARD: Dialect<'static> = Dialect {
        hash_comments: false,
        word_logic: false,
        digit_separators: false,
        dotted_names: true,
        reserved: &[],
        raw_argument: None,
        wording: Wording {
            expression: "an expression",
            hint: "an expression is a number, a name, a function call like `min(a, b)`, or a parenthesized formula",
            end: "end of input",
            quote_source: false,
        },
    };
}

impl Default for Dialect<'static> {
    fn default() -> Self {
        Dialect::STANDARD
    }
}

/// Skips whitespace and `#` line comments from byte `pos` (the trivia of a
/// [`Dialect::hash_comments`] dialect).
pub fn skip_hash_trivia(src: &str, mut pos: usize) -> usize {
    let b = src.as_bytes();
    loop {
        while pos < b.len() && b[pos].is_ascii_whitespace() {
            pos += 1;
        }
        if pos < b.len() && b[pos] == b'#' {
            while pos < b.len() && b[pos] != b'\n' {
                pos += 1;
            }
        } else {
            return pos;
        }
    }
}
