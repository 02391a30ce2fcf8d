//! The `.bsg` dialect of the project's expression language: its reserved
//! words and how its formulas read. A file of its own because the parser
//! reads formulas in it while the formula compiler builds on the parser's
//! syntax tree; here both import it from below.

use crate::lex::block_at;
use genform_core::expr::{Dialect, RawArgument, Wording};

/// Keywords, never rule names.
#[rustfmt::skip] // one long keyword would otherwise put each on its own line
pub(crate) const KEYWORDS: &[&str] = &[
    "grammar", "axiom", "limits", "box", "world", "allow_unknown_blocks", "group", "material", "support", "let",
    "when",
    "else", "weight", "split", "repeat", "round", "fill", "void", "skip", "reorient", "and", "or", "not",
];

/// The `.bsg` dialect of the expression language.
pub(crate) const DIALECT: Dialect<'static> = Dialect {
    hash_comments: true,
    word_logic: true,
    digit_separators: true,
    dotted_names: false,
    reserved: KEYWORDS,
    raw_argument: Some(RawArgument {
        calls: &["FULL", "NONEMPTY", "EMPTY", "COUNT"],
        noun: "block type",
        hint: "block types are SOLID, LIQUID, AIR, PASSABLE, a `group` or a block id",
        scan: block_end,
    }),
    wording: Wording {
        expression: "a formula",
        hint: "a formula is a number, a size like `X`, an observer like `FULL(SOLID)`, or a calculation of these",
        end: "the end of the file",
        quote_source: true,
    },
};

/// The end of the block type starting at `start`.
fn block_end(src: &str, start: usize) -> usize {
    block_at(src, start).end as usize
}
