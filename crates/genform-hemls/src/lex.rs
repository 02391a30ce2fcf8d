//! Lines and tokens of a `.gr8` file.
//!
//! The format is line-oriented: every line is split on spaces and tabs
//! (several in a row are fine, a `\r` before the newline too), a word that
//! starts with `//` ends the line's content (a comment), and each remaining
//! word is classified on its own. Unknown words get a hint: the keyword they
//! are closest to, or the same text with spaces where tokens were glued.

use crate::grammar::{Age, Turn};
use genform_core::expr::did_you_mean;
use genform_core::{Diagnostic, Span};

/// Largest edge type (`EdgeN`) a file may name.
pub const MAX_EDGE_ID: u32 = 1_000_000;

/// A line with content: its 1-based number and its words (comments dropped).
#[derive(Clone, Debug)]
pub(crate) struct Line<'a> {
    /// 1-based line number.
    pub number: usize,
    /// The words before any comment; never empty.
    pub words: Vec<Word<'a>>,
}

impl Line<'_> {
    /// From the first word's start to the last word's end.
    pub fn span(&self) -> Span {
        let first = self.words.first().map(|w| w.span).unwrap_or_default();
        let last = self.words.last().map(|w| w.span).unwrap_or_default();
        first.to(last)
    }
}

/// A word of a line and where it is.
#[derive(Clone, Copy, Debug)]
pub(crate) struct Word<'a> {
    /// The text.
    pub text: &'a str,
    /// Its bytes in the file.
    pub span: Span,
}

/// The lines of `text` that have content, comments and blank lines dropped.
pub(crate) fn lines(text: &str) -> Vec<Line<'_>> {
    let is_space = |b: u8| matches!(b, b' ' | b'\t' | b'\r');
    let mut out = Vec::new();
    let mut start = 0;
    for (n, raw) in text.split('\n').enumerate() {
        let bytes = raw.as_bytes();
        let mut words = Vec::new();
        let mut i = 0;
        while i < bytes.len() {
            if is_space(bytes[i]) {
                i += 1;
                continue;
            }
            let s = i;
            while i < bytes.len() && !is_space(bytes[i]) {
                i += 1;
            }
            // Splitting only at ASCII bytes keeps `s..i` on char boundaries.
            let text = &raw[s..i];
            if text.starts_with("//") {
                break;
            }
            words.push(Word { text, span: Span::new(start + s, start + i) });
        }
        if !words.is_empty() {
            out.push(Line { number: n + 1, words });
        }
        start += raw.len() + 1;
    }
    out
}

/// What a word means.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) enum Tok {
    /// `EdgeN`, `EdgeN_i`, `EdgeN_i+1`, `EdgeN_i-1`.
    Edge(u32, Age),
    /// `+ - & ^ \ /`.
    Turn(Turn),
    /// `~`.
    Tilde,
    /// `[`.
    Open,
    /// `]`.
    Close,
    /// `->`.
    Arrow,
    /// `<`.
    Lt,
    /// `>`.
    Gt,
    /// `=`.
    Eq,
    /// `Angle`.
    Angle,
    /// `Sync`.
    Sync,
    /// `BranchAngle`.
    BranchAngle,
    /// `Weight`.
    Weight,
    /// `If`.
    If,
    /// `i` (the age variable of a condition).
    I,
    /// A number (possibly not finite: `inf`, `NaN`).
    Num(f64),
}

/// A classified word.
#[derive(Clone, Copy, Debug)]
pub(crate) struct Token<'a> {
    /// Its meaning.
    pub tok: Tok,
    /// Its text.
    pub text: &'a str,
    /// Where it is.
    pub span: Span,
}

/// Why a word is not a token.
#[derive(Clone, Copy, Debug, PartialEq)]
enum Bad {
    Unknown,
    /// `Edge` with no digits after it.
    NoNumber,
    /// The EA grammar's `EdgeX`, `EdgeY`, `EdgeZ`.
    Placeholder,
    /// More than [`MAX_EDGE_ID`].
    TooLarge,
    /// `EdgeN` followed by something other than an age form.
    Suffix,
}

/// Keywords, for "did you mean" hints.
const KEYWORDS: [&str; 5] = ["Angle", "Sync", "BranchAngle", "Weight", "If"];

fn classify(text: &str) -> Result<Tok, Bad> {
    if let Some(rest) = text.strip_prefix("Edge") {
        return edge(rest);
    }
    Ok(match text {
        "+" => Tok::Turn(Turn::Right),
        "-" => Tok::Turn(Turn::Left),
        "&" => Tok::Turn(Turn::PitchDown),
        "^" => Tok::Turn(Turn::PitchUp),
        "\\" => Tok::Turn(Turn::RollLeft),
        "/" => Tok::Turn(Turn::RollRight),
        "~" => Tok::Tilde,
        "[" => Tok::Open,
        "]" => Tok::Close,
        "->" => Tok::Arrow,
        "<" => Tok::Lt,
        ">" => Tok::Gt,
        "=" => Tok::Eq,
        "Angle" => Tok::Angle,
        "Sync" => Tok::Sync,
        "BranchAngle" => Tok::BranchAngle,
        "Weight" => Tok::Weight,
        "If" => Tok::If,
        "i" => Tok::I,
        _ => match text.parse::<f64>() {
            Ok(v) => Tok::Num(v),
            Err(_) => return Err(Bad::Unknown),
        },
    })
}

/// The part of an edge token after `Edge`.
fn edge(rest: &str) -> Result<Tok, Bad> {
    let digits = rest.bytes().take_while(u8::is_ascii_digit).count();
    if digits == 0 {
        return Err(if matches!(rest, "X" | "Y" | "Z") { Bad::Placeholder } else { Bad::NoNumber });
    }
    let (number, suffix) = rest.split_at(digits);
    let age = match suffix {
        "" => Age::Zero,
        "_i" => Age::Same,
        "_i+1" => Age::Plus1,
        "_i-1" => Age::Minus1,
        _ => return Err(Bad::Suffix),
    };
    let digits = number.trim_start_matches('0');
    // Seven significant digits at most: anything longer overflows before parsing.
    let kind = if digits.len() > 7 { None } else { Some(digits.parse::<u32>().unwrap_or(0)) };
    match kind {
        Some(k) if k <= MAX_EDGE_ID => Ok(Tok::Edge(k, age)),
        _ => Err(Bad::TooLarge),
    }
}

/// Classifies one word, or explains why it is not a token.
pub(crate) fn lex<'a>(word: &Word<'a>) -> Result<Token<'a>, Diagnostic> {
    let text = word.text;
    let span = word.span;
    match classify(text) {
        Ok(tok) => Ok(Token { tok, text, span }),
        Err(Bad::Unknown) => Err(unknown(text, span)),
        Err(Bad::Suffix) => {
            let d = Diagnostic::error(span, format!("unknown edge form `{text}`"));
            Err(match spaced(text) {
                Some(s) => d.with_hint(format!("separate tokens with spaces: `{s}`")),
                None => d.with_hint("timed edges are written `Edge3_i`, `Edge3_i+1` or `Edge3_i-1` (the age is `i`)"),
            })
        }
        Err(Bad::NoNumber) => {
            Err(Diagnostic::error(span, format!("`{text}`: an edge needs its type number after `Edge`"))
                .with_hint("write `Edge0`, `Edge1`, … with no space before the number"))
        }
        Err(Bad::Placeholder) => Err(Diagnostic::error(
            span,
            format!("`{text}` is a placeholder of Genr8's evolution grammar, not an edge type"),
        )
        .with_hint("the mapping replaces it by a number; write `Edge0`, `Edge1`, …")),
        Err(Bad::TooLarge) => {
            Err(Diagnostic::error(span, format!("the edge type in `{text}` is too large (at most {MAX_EDGE_ID})"))
                .with_hint("edge types are small integers naming kinds of edges: `Edge0`, `Edge1`, …"))
        }
    }
}

fn unknown(text: &str, span: Span) -> Diagnostic {
    let d = Diagnostic::error(span, format!("unknown token `{text}`"));
    match text {
        "=>" | "-->" | "→" => return d.with_hint("a rule's arrow is `->`"),
        "<=" | ">=" | "==" | "!=" => return d.with_hint("a condition compares with `<`, `>` or `=`: `If i < 3`"),
        _ => {}
    }
    if let Some(s) = spaced(text) {
        return d.with_hint(format!("separate tokens with spaces: `{s}`"));
    }
    if let Some(k) = KEYWORDS.iter().find(|k| k.eq_ignore_ascii_case(text)) {
        return d.with_hint(format!("did you mean `{k}`?"));
    }
    if text.get(..4).is_some_and(|p| p.eq_ignore_ascii_case("edge")) {
        let fixed = format!("Edge{}", &text[4..]);
        if classify(&fixed).is_ok() {
            return d.with_hint(format!("did you mean `{fixed}`?"));
        }
    }
    if let Some(k) = did_you_mean(text, KEYWORDS) {
        return d.with_hint(format!("did you mean `{k}`?"));
    }
    match text {
        "I" => d.with_hint("the age variable is a lower-case `i`: `If i < 3`"),
        _ => d.with_hint(
            "tokens are `EdgeN`, the turns `+ - & ^ \\ /`, `~`, `[ ]`, `->`, `<`, `>` and the keywords \
             `Angle`, `Sync`, `BranchAngle`, `Weight`, `If`",
        ),
    }
}

/// `text` with spaces between glued tokens (`Edge0+Edge1` → `Edge0 + Edge1`),
/// when that yields several valid tokens.
fn spaced(text: &str) -> Option<String> {
    const SYMBOLS: &str = "+-&^\\/~[]<>=";
    if text.len() > 60 {
        return None;
    }
    let mut pieces: Vec<String> = Vec::new();
    let mut cur = String::new();
    let mut chars = text.chars().peekable();
    while let Some(c) = chars.next() {
        if !SYMBOLS.contains(c) {
            cur.push(c);
            continue;
        }
        if (c == '+' || c == '-') && cur.ends_with("_i") && chars.peek() == Some(&'1') {
            // `Edge0_i+1` keeps its age form.
            cur.push(c);
            cur.push('1');
            chars.next();
            continue;
        }
        if !cur.is_empty() {
            pieces.push(std::mem::take(&mut cur));
        }
        if c == '-' && chars.peek() == Some(&'>') {
            chars.next();
            pieces.push("->".to_string());
        } else {
            pieces.push(c.to_string());
        }
    }
    if !cur.is_empty() {
        pieces.push(cur);
    }
    (pieces.len() > 1 && pieces.iter().all(|p| classify(p).is_ok())).then(|| pieces.join(" "))
}

/// Whether a line's first word names a parameter line (`Angle`, `Sync`,
/// `BranchAngle`), exactly or as a near miss (`angle`, `Synch`), so that a
/// misspelt parameter line is reported as such and not as a stray rule.
pub(crate) fn param_keyword(text: &str) -> Option<Tok> {
    const PARAMS: [(&str, Tok); 3] = [("Angle", Tok::Angle), ("Sync", Tok::Sync), ("BranchAngle", Tok::BranchAngle)];
    if let Some((_, t)) = PARAMS.iter().find(|(k, _)| k.eq_ignore_ascii_case(text)) {
        return Some(*t);
    }
    let near = did_you_mean(text, PARAMS.iter().map(|(k, _)| *k))?;
    PARAMS.iter().find(|(k, _)| *k == near).map(|(_, t)| *t)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn words(text: &str) -> Vec<Vec<&str>> {
        lines(text).iter().map(|l| l.words.iter().map(|w| w.text).collect()).collect()
    }

    #[test]
    fn lines_split_on_spaces_tabs_and_drop_comments() {
        let text = "// header\r\nEdge0  +\tEdge1 + Edge2\r\n\n   \nAngle 60 // trailing\n//x\n";
        assert_eq!(words(text), vec![vec!["Edge0", "+", "Edge1", "+", "Edge2"], vec!["Angle", "60"]]);
        let ls = lines(text);
        assert_eq!(ls[0].number, 2);
        assert_eq!(ls[1].number, 5);
        // Spans are byte offsets into the whole text.
        let w = ls[0].words[2];
        assert_eq!(&text[w.span.start as usize..w.span.end as usize], "Edge1");
    }

    #[test]
    fn edges_and_age_forms() {
        assert_eq!(classify("Edge12"), Ok(Tok::Edge(12, Age::Zero)));
        assert_eq!(classify("Edge3_i"), Ok(Tok::Edge(3, Age::Same)));
        assert_eq!(classify("Edge3_i+1"), Ok(Tok::Edge(3, Age::Plus1)));
        assert_eq!(classify("Edge3_i-1"), Ok(Tok::Edge(3, Age::Minus1)));
        assert_eq!(classify("Edge1000000"), Ok(Tok::Edge(1_000_000, Age::Zero)));
        assert_eq!(classify("Edge0001"), Ok(Tok::Edge(1, Age::Zero)));
        assert_eq!(classify("Edge1000001"), Err(Bad::TooLarge));
        assert_eq!(classify("Edge99999999999999999999999"), Err(Bad::TooLarge));
        assert_eq!(classify("Edge"), Err(Bad::NoNumber));
        assert_eq!(classify("Edge_i"), Err(Bad::NoNumber));
        assert_eq!(classify("EdgeX"), Err(Bad::Placeholder));
        assert_eq!(classify("Edge3_j"), Err(Bad::Suffix));
    }

    #[test]
    fn numbers_keywords_and_turns() {
        assert_eq!(classify("22.5"), Ok(Tok::Num(22.5)));
        assert_eq!(classify("-5"), Ok(Tok::Num(-5.0)));
        assert!(matches!(classify("inf"), Ok(Tok::Num(v)) if v.is_infinite()));
        assert!(matches!(classify("NaN"), Ok(Tok::Num(v)) if v.is_nan()));
        assert_eq!(classify("\\"), Ok(Tok::Turn(Turn::RollLeft)));
        assert_eq!(classify("BranchAngle"), Ok(Tok::BranchAngle));
        assert_eq!(classify("angle"), Err(Bad::Unknown));
    }

    fn hint(text: &str) -> String {
        let w = Word { text, span: Span::new(0, text.len()) };
        lex(&w).unwrap_err().hints.join("|")
    }

    #[test]
    fn unknown_tokens_get_the_nearest_keyword_or_spacing() {
        assert_eq!(hint("edge0"), "did you mean `Edge0`?");
        assert_eq!(hint("EDGE2_i+1"), "did you mean `Edge2_i+1`?");
        assert_eq!(hint("angle"), "did you mean `Angle`?");
        assert_eq!(hint("Wieght"), "did you mean `Weight`?");
        assert_eq!(hint("Edge0+Edge1"), "separate tokens with spaces: `Edge0 + Edge1`");
        assert_eq!(hint("[+Edge1_i+1]"), "separate tokens with spaces: `[ + Edge1_i+1 ]`");
        assert_eq!(hint("Edge0->Edge0"), "separate tokens with spaces: `Edge0 -> Edge0`");
        assert_eq!(hint("=>"), "a rule's arrow is `->`");
        assert!(hint("%%").contains("tokens are"));
    }

    #[test]
    fn parameter_lines_are_recognised_by_near_misses() {
        assert_eq!(param_keyword("Angle"), Some(Tok::Angle));
        assert_eq!(param_keyword("angle"), Some(Tok::Angle));
        assert_eq!(param_keyword("Synch"), Some(Tok::Sync));
        assert_eq!(param_keyword("branchangle"), Some(Tok::BranchAngle));
        assert_eq!(param_keyword("Edge0"), None);
        assert_eq!(param_keyword("~"), None);
    }
}
