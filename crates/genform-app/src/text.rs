//! Reading the text files users write (grammars, environments, scenes) and
//! turning their diagnostics into one error, so every such file fails the
//! same way: a position for bad bytes, ariadne's reports for bad content.

use anyhow::Result;
use genform_core::{Diagnostics, SourceFile};
use std::fmt;
use std::path::Path;

/// Reads the text file `path`, a `what` (e.g. "grammar") the user gave.
/// A file that cannot be read says "cannot read {what} {path}"; one that is
/// not UTF-8 says `FILE:LINE:COL: not valid UTF-8 (byte 0xNN at byte offset K)`.
pub fn read_text(path: &Path, what: &str) -> Result<String> {
    let bytes = crate::gate::read_bytes(path, what)?;
    String::from_utf8(bytes).map_err(|e| {
        let at = e.utf8_error().valid_up_to();
        anyhow::anyhow!("{}:{}", path.display(), invalid_utf8(e.as_bytes(), at))
    })
}

/// Reads and compiles a grammar file with `compile`: warnings go to the
/// door's [`crate::notes`] sink, errors become one error with every
/// diagnostic rendered.
pub(crate) fn compile_file<T>(
    path: &Path,
    compile: impl FnOnce(&SourceFile) -> Result<(T, Diagnostics), Diagnostics>,
) -> Result<T> {
    let text = read_text(path, "grammar")?;
    let file = SourceFile::new(path.display().to_string(), text);
    crate::gate::take_refusal();
    let color = crate::notes::colour();
    match compile(&file) {
        Ok((value, warnings)) => {
            if !warnings.items.is_empty() {
                crate::notes::warn(&warnings.render(color));
            }
            Ok(value)
        }
        Err(errors) => {
            let e = anyhow::Error::new(SourceErrors::new(&errors, color));
            // An asset outside a confined process's folders refuses the grammar.
            Err(match crate::gate::take_refusal() {
                Some(why) => e.context(crate::gate::Refused(why)),
                None => e,
            })
        }
    }
}

/// `LINE:COL: not valid UTF-8 (byte 0xNN at byte offset K)` for the first
/// bad byte at `at`; the column counts characters, like diagnostics do.
fn invalid_utf8(bytes: &[u8], at: usize) -> String {
    let before = &bytes[..at];
    let line_start = before.iter().rposition(|&b| b == b'\n').map_or(0, |i| i + 1);
    let line = before.iter().filter(|&&b| b == b'\n').count() + 1;
    // Everything before the first bad byte is valid, so this never loses characters.
    let col = String::from_utf8_lossy(&before[line_start..]).chars().count() + 1;
    format!("{line}:{col}: not valid UTF-8 (byte {:#04x} at byte offset {at})", bytes[at])
}

/// The errors found in one source file: every diagnostic rendered (with
/// ariadne's own `Error:` headers) and the summary "N errors in FILE".
/// Its `Display` shows both, so nothing is lost wherever it is formatted;
/// the binary prints it with [`report`], which prefixes only the summary.
#[derive(Debug)]
pub struct SourceErrors {
    rendered: String,
    summary: String,
    diagnostics: Diagnostics,
}

impl SourceErrors {
    /// Renders `diagnostics` (with colour when `color`).
    pub fn new(diagnostics: &Diagnostics, color: bool) -> Self {
        let n = diagnostics.error_count();
        let summary = format!("{n} error{} in {}", if n == 1 { "" } else { "s" }, diagnostics.file.name);
        SourceErrors { rendered: diagnostics.render(color), summary, diagnostics: diagnostics.clone() }
    }

    /// The diagnostics themselves, for callers that show them their own way
    /// (the Python package's exceptions carry file, line, column, hints).
    pub fn diagnostics(&self) -> &Diagnostics {
        &self.diagnostics
    }

    /// The diagnostics as ariadne reports, one after another.
    pub fn rendered(&self) -> &str {
        &self.rendered
    }

    /// "N errors in FILE".
    pub fn summary(&self) -> &str {
        &self.summary
    }
}

impl fmt::Display for SourceErrors {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "{}{}", self.rendered, self.summary)
    }
}

impl std::error::Error for SourceErrors {}

/// What the binary prints for a failed command: the rendered diagnostics of
/// any [`SourceErrors`] in the chain as they are, then one `error: ` line
/// with the chain (as `{e:#}` shows it, the diagnostics replaced by their
/// summary). So each diagnostic carries exactly one `Error:` header, as
/// warnings carry one `Warning:` header.
pub fn report(e: &anyhow::Error) -> String {
    let mut rendered = String::new();
    let parts: Vec<String> = e
        .chain()
        .map(|cause| match cause.downcast_ref::<SourceErrors>() {
            Some(s) => {
                rendered.push_str(&s.rendered);
                s.summary.clone()
            }
            None => cause.to_string(),
        })
        .collect();
    format!("{rendered}error: {}\n", parts.join(": "))
}

#[cfg(test)]
mod tests {
    use super::*;
    use genform_core::{Diagnostic, Span};

    #[test]
    fn invalid_utf8_names_line_column_and_byte() {
        // 'é' is two bytes but one column; the bad byte is the 3rd character of line 2.
        assert_eq!(invalid_utf8(b"a\n\xc3\xa9b\xff;", 5), "2:3: not valid UTF-8 (byte 0xff at byte offset 5)");
        assert_eq!(invalid_utf8(b"\x80", 0), "1:1: not valid UTF-8 (byte 0x80 at byte offset 0)");
    }

    #[test]
    fn read_text_reports_the_file_and_position() {
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join("g.sg");
        std::fs::write(&path, b"Start {\n  box\xfe;\n}\n").unwrap();
        let msg = format!("{:#}", read_text(&path, "grammar").unwrap_err());
        assert_eq!(msg, format!("{}:2:6: not valid UTF-8 (byte 0xfe at byte offset 13)", path.display()));
        let missing = format!("{:#}", read_text(&dir.path().join("no.sg"), "grammar").unwrap_err());
        assert!(missing.starts_with("cannot read grammar "), "{missing}");
        std::fs::write(&path, "Start { box; }\n").unwrap();
        assert_eq!(read_text(&path, "grammar").unwrap(), "Start { box; }\n");
    }

    #[test]
    fn report_gives_each_diagnostic_one_error_prefix() {
        let mut d = Diagnostics::new(SourceFile::new("x.sg", "Start { boxx; }\n"));
        d.push(Diagnostic::error(Span::new(8, 12), "unknown operation `boxx`"));
        let e = anyhow::Error::new(SourceErrors::new(&d, false)).context("cannot load the scene's grammar");
        let out = report(&e);
        assert_eq!(out.matches("Error:").count(), 1, "{out}");
        assert!(!out.contains("error: Error"), "{out}");
        assert!(out.contains("unknown operation `boxx` (x.sg:1:9)"), "{out}");
        assert!(out.ends_with("error: cannot load the scene's grammar: 1 error in x.sg\n"), "{out}");
        // Formatted anywhere else, the error still carries every diagnostic.
        assert!(format!("{e:#}").contains("unknown operation `boxx`"));
    }
}
