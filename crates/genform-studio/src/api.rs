//! What every endpoint shares: the JSON error answer ([`ApiError`]), the
//! size-limited JSON body ([`JsonBody`]), the numbered tables of samples,
//! runs and sessions, and the byte answers.

use axum::extract::{FromRequest, Request};
use axum::http::{HeaderValue, StatusCode, header};
use axum::response::{IntoResponse, Response};
use genform_app::{OverBudget, Refused, SourceErrors};
use serde::Serialize;
use serde::de::DeserializeOwned;

/// Largest request body (1 MiB); larger ones get 413.
pub const BODY_LIMIT: usize = 1 << 20;

/// Objects of one kind (samples, runs, breeding sessions) by number, with
/// the last number given out.
pub type Table<T> = std::sync::Mutex<(u64, std::collections::BTreeMap<u64, std::sync::Arc<T>>)>;

/// The next number after `last` that `taken` does not refuse (a folder an
/// earlier server left under that id), now the last one handed out.
pub fn claim_id(last: &mut u64, taken: impl Fn(u64) -> bool) -> u64 {
    let mut n = *last + 1;
    while taken(n) {
        n += 1;
    }
    *last = n;
    n
}

/// One diagnostic of a grammar or scene that did not compile.
#[derive(Clone, Debug, Serialize)]
pub struct Diag {
    /// The file (a root path where the file lies in a root).
    pub file: String,
    /// 1-based line.
    pub line: usize,
    /// 1-based column (characters).
    pub col: usize,
    /// What is wrong.
    pub message: String,
    /// How to fix it, if known.
    pub hint: Option<String>,
}

/// An error answer: `{"error": "...", "diagnostics": [...]}` with a 4xx/5xx status.
#[derive(Debug)]
pub struct ApiError {
    /// The HTTP status.
    pub status: StatusCode,
    /// The message.
    pub message: String,
    /// Compile diagnostics, if the error came from a grammar or scene file.
    pub diagnostics: Vec<Diag>,
}

impl ApiError {
    /// An error with `status` and `message`.
    pub fn new(status: StatusCode, message: impl Into<String>) -> Self {
        ApiError { status, message: message.into(), diagnostics: Vec::new() }
    }

    /// 400.
    pub fn bad_request(message: impl Into<String>) -> Self {
        Self::new(StatusCode::BAD_REQUEST, message)
    }

    /// 403.
    pub fn forbidden(message: impl Into<String>) -> Self {
        Self::new(StatusCode::FORBIDDEN, message)
    }

    /// 404.
    pub fn not_found(message: impl Into<String>) -> Self {
        Self::new(StatusCode::NOT_FOUND, message)
    }

    /// 409: the request does not fit the object's state.
    pub fn conflict(message: impl Into<String>) -> Self {
        Self::new(StatusCode::CONFLICT, message)
    }

    /// 500.
    pub fn internal(message: impl Into<String>) -> Self {
        Self::new(StatusCode::INTERNAL_SERVER_ERROR, message)
    }

    /// 503: the memory budget is held by other runs and sessions now.
    pub fn unavailable(message: impl Into<String>) -> Self {
        Self::new(StatusCode::SERVICE_UNAVAILABLE, message)
    }

    /// A failed CLI operation on user input (400): its error chain as one
    /// line, compile errors as diagnostics; 403 for a path outside the
    /// studio's folders ([`genform_app::Refused`]); 503 when it was refused because
    /// the memory budget is held by other runs and sessions
    /// ([`genform_app::OverBudget`]), so waiting may help. `shown` turns
    /// file names into what the client may see.
    pub fn from_anyhow(e: &anyhow::Error, shown: impl Fn(&str) -> String) -> Self {
        // A path outside the studio's folders, however it was named.
        if let Some(refused) =
            e.downcast_ref::<Refused>().or_else(|| e.chain().find_map(|c| c.downcast_ref::<Refused>()))
        {
            return Self::forbidden(refused.to_string());
        }
        if let Some(over) = e.chain().find_map(|c| c.downcast_ref::<OverBudget>())
            && over.asked <= over.budget
        {
            return Self::unavailable(e.chain().map(|c| c.to_string()).collect::<Vec<_>>().join(": "));
        }
        let mut diagnostics = Vec::new();
        let parts: Vec<String> = e
            .chain()
            .map(|cause| match cause.downcast_ref::<SourceErrors>() {
                Some(s) => {
                    let d = s.diagnostics();
                    for item in &d.items {
                        let (line, col) = item.span.map_or((0, 0), |sp| d.file.line_col(sp.start));
                        diagnostics.push(Diag {
                            file: shown(&d.file.name),
                            line,
                            col,
                            message: item.message.clone(),
                            hint: item.hints.first().cloned(),
                        });
                    }
                    s.summary().to_string()
                }
                None => cause.to_string(),
            })
            .collect();
        ApiError { status: StatusCode::BAD_REQUEST, message: parts.join(": "), diagnostics }
    }
}

impl IntoResponse for ApiError {
    fn into_response(self) -> Response {
        let body = serde_json::json!({ "error": self.message, "diagnostics": self.diagnostics });
        (self.status, axum::Json(body)).into_response()
    }
}

/// A JSON request body: over the size limit 413, not JSON or not the
/// expected shape 400, each with an [`ApiError`] body.
pub struct JsonBody<T>(pub T);

impl<S: Send + Sync, T: DeserializeOwned> FromRequest<S> for JsonBody<T> {
    type Rejection = ApiError;

    async fn from_request(req: Request, state: &S) -> Result<Self, ApiError> {
        let too_large = || {
            ApiError::new(
                StatusCode::PAYLOAD_TOO_LARGE,
                format!("the request body is larger than {} bytes", BODY_LIMIT),
            )
        };
        // A declared length over the limit is refused before anything is read;
        // other bodies are cut at the limit while they are read.
        let declared = req.headers().get(header::CONTENT_LENGTH).and_then(|v| v.to_str().ok()?.parse::<u64>().ok());
        if declared.is_some_and(|n| n > BODY_LIMIT as u64) {
            return Err(too_large());
        }
        let bytes = axum::body::Bytes::from_request(req, state).await.map_err(|r| {
            let status = r.status();
            if status == StatusCode::PAYLOAD_TOO_LARGE { too_large() } else { ApiError::new(status, r.body_text()) }
        })?;
        let bytes: &[u8] = if bytes.iter().all(u8::is_ascii_whitespace) { b"{}" } else { &bytes };
        serde_json::from_slice(bytes).map(JsonBody).map_err(|e| ApiError::bad_request(format!("bad JSON body: {e}")))
    }
}

/// `bytes` with `content_type`.
pub fn bytes_response(content_type: &str, bytes: Vec<u8>) -> Response {
    let mut r = bytes.into_response();
    if let Ok(v) = HeaderValue::from_str(content_type) {
        r.headers_mut().insert(header::CONTENT_TYPE, v);
    }
    r.headers_mut().insert(header::CACHE_CONTROL, HeaderValue::from_static("no-store"));
    r
}

/// Runs `f` on a blocking thread (CLI work: compiling, sampling, writing);
/// a panic becomes a 500.
pub async fn blocking<T: Send + 'static>(
    f: impl FnOnce() -> Result<T, ApiError> + Send + 'static,
) -> Result<T, ApiError> {
    tokio::task::spawn_blocking(f).await.map_err(|e| ApiError::internal(format!("internal error: {e}")))?
}
