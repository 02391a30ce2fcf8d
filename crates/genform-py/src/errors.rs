//! genform's errors as Python exceptions: [`GenformError`] with the whole
//! error chain as its message and, for files that failed to compile, a
//! `diagnostics` list of [`Diagnostic`]s (file, line, column, hints).

use genform_app::SourceErrors;
use genform_core::Severity;
use pyo3::exceptions::PyException;
use pyo3::prelude::*;
use pyo3::types::PyList;

pyo3::create_exception!(genform, GenformError, PyException, "Every error genform raises.");

/// One located message of a grammar or scene file.
#[pyclass(module = "genform", frozen, get_all)]
#[derive(Clone, Debug)]
pub struct Diagnostic {
    /// The file's name as given.
    pub file: String,
    /// 1-based line; 0 without a position.
    pub line: usize,
    /// 1-based column in characters; 0 without a position.
    pub column: usize,
    /// "error", "warning" or "note".
    pub severity: String,
    /// The message.
    pub message: String,
    /// How to fix it, if genform knows.
    pub hints: Vec<String>,
}

#[pymethods]
impl Diagnostic {
    fn __str__(&self) -> String {
        let mut s = if self.line > 0 {
            format!("{}:{}:{}: {}: {}", self.file, self.line, self.column, self.severity, self.message)
        } else {
            format!("{}: {}: {}", self.file, self.severity, self.message)
        };
        for h in &self.hints {
            s.push_str(&format!("\n  hint: {h}"));
        }
        s
    }

    fn __repr__(&self) -> String {
        format!("Diagnostic({:?})", self.__str__())
    }
}

/// The diagnostics of every [`SourceErrors`] in `e`'s chain.
fn diagnostics(e: &anyhow::Error) -> Vec<Diagnostic> {
    let mut out = Vec::new();
    for cause in e.chain() {
        let Some(errors) = cause.downcast_ref::<SourceErrors>() else { continue };
        let d = errors.diagnostics();
        for item in &d.items {
            let (line, column) = item.span.map_or((0, 0), |s| d.file.line_col(s.start));
            let severity = match item.severity {
                Severity::Error => "error",
                Severity::Warning => "warning",
                Severity::Note => "note",
            };
            out.push(Diagnostic {
                file: d.file.name.to_string(),
                line,
                column,
                severity: severity.to_string(),
                message: item.message.clone(),
                hints: item.hints.clone(),
            });
        }
    }
    out
}

/// `e` as a [`GenformError`]: the chain joined by ": " (compile errors as
/// their summary), then one line per diagnostic; `.diagnostics` holds them.
pub fn to_py(e: anyhow::Error) -> PyErr {
    let found = diagnostics(&e);
    let chain: Vec<String> = e
        .chain()
        .map(|c| match c.downcast_ref::<SourceErrors>() {
            Some(s) => s.summary().to_string(),
            None => c.to_string(),
        })
        .collect();
    let mut message = chain.join(": ");
    for d in &found {
        message.push('\n');
        message.push_str(&d.__str__());
    }
    Python::attach(|py| {
        let err = GenformError::new_err(message);
        let list = found.into_iter().map(|d| Py::new(py, d)).collect::<PyResult<Vec<_>>>();
        if let Ok(list) = list.and_then(|l| PyList::new(py, l)) {
            let _ = err.value(py).setattr("diagnostics", list);
        }
        err
    })
}

/// `anyhow` results as Python results.
pub trait OrRaise<T> {
    /// The value, or the error as a [`GenformError`].
    fn or_raise(self) -> PyResult<T>;
}

impl<T> OrRaise<T> for anyhow::Result<T> {
    fn or_raise(self) -> PyResult<T> {
        self.map_err(to_py)
    }
}

/// A [`GenformError`] with `message` and no diagnostics.
pub fn error(message: impl Into<String>) -> PyErr {
    to_py(anyhow::anyhow!(message.into()))
}

/// A whole-number argument (`seed`, `generations`, `width`, …): a value
/// that is no int, is negative or is too large raises [`GenformError`]
/// naming the range, not Python's `OverflowError` or `TypeError`.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct Whole<T>(pub T);

/// `obj`'s `repr`, for messages.
fn shown(obj: &Bound<'_, PyAny>) -> String {
    obj.repr().map(|r| r.to_string()).unwrap_or_else(|_| "that value".to_string())
}

macro_rules! whole {
    ($($t:ty),*) => {$(
        impl<'a, 'py> FromPyObject<'a, 'py> for Whole<$t> {
            type Error = PyErr;

            fn extract(obj: pyo3::Borrowed<'a, 'py, PyAny>) -> PyResult<Self> {
                obj.extract::<$t>().map(Whole).map_err(|_| {
                    error(format!("expected a whole number from 0 to {}, got {}", <$t>::MAX, shown(&obj)))
                })
            }
        }
    )*};
}
whole!(u8, u32, u64, usize);
