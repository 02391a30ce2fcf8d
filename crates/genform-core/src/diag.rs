//! The one diagnostics type: errors and warnings with spans and hints.
//!
//! Front ends collect every problem they find into [`Diagnostics`] instead
//! of stopping at the first, then render them all at once. Each diagnostic
//! names `file:line:col`, says what was expected, and may carry hints.

use std::fmt;
use std::sync::Arc;

/// A byte range in one source file.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, Default)]
pub struct Span {
    /// First byte.
    pub start: u32,
    /// One past the last byte (equal to `start` for a point).
    pub end: u32,
}

impl Span {
    /// The span `start..end`.
    pub fn new(start: usize, end: usize) -> Self {
        Span { start: start as u32, end: end.max(start) as u32 }
    }

    /// The smallest span covering both.
    pub fn to(self, other: Span) -> Span {
        Span { start: self.start.min(other.start), end: self.end.max(other.end) }
    }

    /// This span moved right by `offset` bytes (for sub-parsers of embedded text).
    pub fn shift(self, offset: usize) -> Span {
        Span { start: self.start + offset as u32, end: self.end + offset as u32 }
    }
}

/// How serious a diagnostic is.
#[derive(Clone, Copy, Debug, PartialEq, Eq, PartialOrd, Ord, Hash)]
pub enum Severity {
    /// Additional information.
    Note,
    /// Suspicious but accepted input.
    Warning,
    /// Input that cannot be used.
    Error,
}

impl fmt::Display for Severity {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(match self {
            Severity::Note => "note",
            Severity::Warning => "warning",
            Severity::Error => "error",
        })
    }
}

/// One problem found in a source file.
#[derive(Clone, Debug, PartialEq)]
pub struct Diagnostic {
    /// Error, warning or note.
    pub severity: Severity,
    /// What is wrong, e.g. "expected `)` after the arguments of `translate`".
    pub message: String,
    /// Where; `None` for problems of the whole file.
    pub span: Option<Span>,
    /// Secondary locations with a short explanation each.
    pub labels: Vec<(Span, String)>,
    /// Suggestions on how to fix it.
    pub hints: Vec<String>,
}

impl Diagnostic {
    /// An error at `span`.
    pub fn error(span: Span, message: impl Into<String>) -> Self {
        Diagnostic {
            severity: Severity::Error,
            message: message.into(),
            span: Some(span),
            labels: Vec::new(),
            hints: Vec::new(),
        }
    }

    /// A warning at `span`.
    pub fn warning(span: Span, message: impl Into<String>) -> Self {
        Diagnostic { severity: Severity::Warning, ..Diagnostic::error(span, message) }
    }

    /// Adds a hint.
    pub fn with_hint(mut self, hint: impl Into<String>) -> Self {
        self.hints.push(hint.into());
        self
    }

    /// Adds a secondary labelled location.
    pub fn with_label(mut self, span: Span, text: impl Into<String>) -> Self {
        self.labels.push((span, text.into()));
        self
    }

    /// Moves every span right by `offset` bytes.
    pub fn shifted(mut self, offset: usize) -> Self {
        self.span = self.span.map(|s| s.shift(offset));
        for (s, _) in &mut self.labels {
            *s = s.shift(offset);
        }
        self
    }
}

/// A named source text, shared cheaply.
#[derive(Clone, Debug)]
pub struct SourceFile {
    /// The name shown in messages (usually the path as the user gave it).
    pub name: Arc<str>,
    /// The full text.
    pub text: Arc<str>,
    line_starts: Arc<[u32]>,
}

impl SourceFile {
    /// Wraps a text under a display name.
    pub fn new(name: impl Into<Arc<str>>, text: impl Into<Arc<str>>) -> Self {
        let text: Arc<str> = text.into();
        let mut starts = vec![0u32];
        starts.extend(text.match_indices('\n').map(|(i, _)| i as u32 + 1));
        SourceFile { name: name.into(), text, line_starts: starts.into() }
    }

    /// 1-based line and column (in characters) of a byte offset.
    pub fn line_col(&self, offset: u32) -> (usize, usize) {
        let offset = offset.min(self.text.len() as u32);
        let line = match self.line_starts.binary_search(&offset) {
            Ok(i) => i,
            Err(i) => i - 1,
        };
        let start = self.line_starts[line] as usize;
        let mut end = offset as usize;
        while !self.text.is_char_boundary(end) {
            end -= 1;
        }
        (line + 1, self.text[start..end].chars().count() + 1)
    }

    /// `name:line:col` of a byte offset.
    pub fn location(&self, offset: u32) -> String {
        let (l, c) = self.line_col(offset);
        format!("{}:{}:{}", self.name, l, c)
    }
}

/// All diagnostics of one source file.
#[derive(Clone, Debug)]
pub struct Diagnostics {
    /// The file they refer to.
    pub file: SourceFile,
    /// In the order found.
    pub items: Vec<Diagnostic>,
}

impl Diagnostics {
    /// An empty set for `file`.
    pub fn new(file: SourceFile) -> Self {
        Diagnostics { file, items: Vec::new() }
    }

    /// Adds one.
    pub fn push(&mut self, d: Diagnostic) {
        self.items.push(d);
    }

    /// Whether any item is an error.
    pub fn has_errors(&self) -> bool {
        self.items.iter().any(|d| d.severity == Severity::Error)
    }

    /// Number of errors.
    pub fn error_count(&self) -> usize {
        self.items.iter().filter(|d| d.severity == Severity::Error).count()
    }

    /// One line per diagnostic: `file:line:col: severity: message`, each hint
    /// on its own `  hint: ` line. Stable and compact; used by fixture tests.
    pub fn short(&self) -> String {
        let mut out = String::new();
        for d in &self.items {
            let loc = match d.span {
                Some(s) => self.file.location(s.start),
                None => self.file.name.to_string(),
            };
            out.push_str(&format!("{loc}: {}: {}\n", d.severity, d.message));
            for h in &d.hints {
                out.push_str(&format!("  hint: {h}\n"));
            }
        }
        out
    }

    /// A full report with source excerpts (ariadne), for people.
    pub fn render(&self, color: bool) -> String {
        use ariadne::{Config, Label, Report, ReportKind, Source};
        let name: &str = &self.file.name;
        let mut cache = (name, Source::from(&*self.file.text));
        let mut out = Vec::new();
        for d in &self.items {
            let kind = match d.severity {
                Severity::Error => ReportKind::Error,
                Severity::Warning => ReportKind::Warning,
                Severity::Note => ReportKind::Advice,
            };
            let span = d.span.unwrap_or_default();
            let range = char_range(&self.file.text, span);
            let loc = self.file.location(span.start);
            let mut report = Report::build(kind, (name, range.clone()))
                .with_config(Config::default().with_color(color))
                .with_message(format!("{} ({loc})", d.message));
            if d.span.is_some() {
                report = report.with_label(Label::new((name, range)).with_message("here"));
            }
            for (s, text) in &d.labels {
                report = report.with_label(Label::new((name, char_range(&self.file.text, *s))).with_message(text));
            }
            for h in &d.hints {
                report = report.with_help(h);
            }
            let _ = report.finish().write(&mut cache, &mut out);
        }
        String::from_utf8_lossy(&out).into_owned()
    }
}

/// ariadne counts characters, not bytes.
fn char_range(text: &str, span: Span) -> std::ops::Range<usize> {
    let clamp = |mut b: usize| {
        b = b.min(text.len());
        while !text.is_char_boundary(b) {
            b -= 1;
        }
        text[..b].chars().count()
    };
    clamp(span.start as usize)..clamp(span.end as usize)
}

impl fmt::Display for Diagnostics {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(&self.short())
    }
}

impl std::error::Error for Diagnostics {}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn line_col_counts_characters() {
        let f = SourceFile::new("a.sg", "ab\ncäd\n\nx");
        assert_eq!(f.line_col(0), (1, 1));
        assert_eq!(f.line_col(3), (2, 1));
        // 'd' is at byte 6 (ä is two bytes) and column 3.
        assert_eq!(f.line_col(6), (2, 3));
        assert_eq!(f.line_col(9), (4, 1));
        assert_eq!(f.location(9), "a.sg:4:1");
    }

    #[test]
    fn short_and_render_name_the_location_and_hint() {
        let f = SourceFile::new("x.sg", "rule A {\n  boxx;\n}\n");
        let mut d = Diagnostics::new(f);
        d.push(Diagnostic::error(Span::new(11, 15), "unknown operation `boxx`").with_hint("did you mean `box`?"));
        assert!(d.has_errors());
        assert_eq!(d.short(), "x.sg:2:3: error: unknown operation `boxx`\n  hint: did you mean `box`?\n");
        let r = d.render(false);
        assert!(r.contains("x.sg:2:3"), "{r}");
        assert!(r.contains("did you mean"), "{r}");
    }
}
