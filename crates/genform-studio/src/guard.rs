//! What a web page elsewhere must not make the studio do.
//!
//! A browser lets any page send requests to `http://127.0.0.1:PORT`: simple
//! cross-site POSTs (`Content-Type: text/plain`, no preflight) and, after a
//! DNS rebinding, requests whose `Host` is the attacker's name but that reach
//! this server. So every request passes [`guard`]:
//!
//! - its `Host` must name this server: `localhost`, an IP address literal
//!   (never what a rebound name looks like), or the `--host` value;
//! - a request that changes state (any method but GET, HEAD and OPTIONS)
//!   must not come from another origin: an `Origin` header, when present,
//!   must be this server's own `http://HOST`, `Sec-Fetch-Site` must not be
//!   `cross-site`/`same-site`, and a body must be declared
//!   `application/json` (a type that a cross-site page can only send after
//!   a CORS preflight, which this server never grants: it sends no CORS
//!   headers at all).
//!
//! Clients other than browsers (curl, scripts, the tests) send no `Origin`
//! and are served as before. Error answers name files by their root paths,
//! never by the server's absolute paths: [`scrub`] replaces what handlers
//! let through.

use super::api::ApiError;
use super::state::{Allowed, App, Shared};
use axum::body::Body;
use axum::extract::{Request, State};
use axum::http::{HeaderMap, Method, StatusCode, header};
use axum::middleware::Next;
use axum::response::{IntoResponse, Response};

/// Largest error body [`guard`] rewrites (error answers are small JSON).
const SCRUB_LIMIT: usize = 1 << 20;

/// The middleware: refuses foreign hosts and cross-origin state changes,
/// and scrubs server paths out of error answers.
pub async fn guard(State(app): State<Shared>, request: Request, next: Next) -> Response {
    if let Err(e) = check(&app.allowed, request.method(), request.headers()) {
        return e.into_response();
    }
    let response = next.run(request).await;
    if response.status().is_client_error() || response.status().is_server_error() {
        scrub_response(&app, response).await
    } else {
        response
    }
}

/// Why a request with `method` and `headers` must be refused, if it must.
pub fn check(allowed: &Allowed, method: &Method, headers: &HeaderMap) -> Result<(), ApiError> {
    let host = headers.get(header::HOST).and_then(|h| h.to_str().ok()).unwrap_or_default();
    if !host_allowed(allowed, host) {
        return Err(ApiError::new(
            StatusCode::MISDIRECTED_REQUEST,
            format!("this server answers only to requests for localhost or its address, not `{host}`"),
        ));
    }
    if matches!(*method, Method::GET | Method::HEAD | Method::OPTIONS) {
        return Ok(());
    }
    let forbidden = |why: &str| Err(ApiError::forbidden(format!("refused a {method} {why}")));
    if let Some(origin) = headers.get(header::ORIGIN) {
        let origin = origin.to_str().unwrap_or_default();
        if !origin.eq_ignore_ascii_case(&format!("http://{host}")) {
            return forbidden(&format!("from another page (`{origin}`): the studio takes changes only from itself"));
        }
    }
    if let Some(site) = headers.get("sec-fetch-site").and_then(|v| v.to_str().ok())
        && (site.eq_ignore_ascii_case("cross-site") || site.eq_ignore_ascii_case("same-site"))
    {
        return forbidden("from another site");
    }
    let declared_body =
        headers.get(header::CONTENT_LENGTH).and_then(|v| v.to_str().ok()?.parse::<u64>().ok()).is_some_and(|n| n > 0)
            || headers.contains_key(header::TRANSFER_ENCODING);
    let json = headers
        .get(header::CONTENT_TYPE)
        .and_then(|v| v.to_str().ok())
        .and_then(|v| v.split(';').next())
        .is_some_and(|t| t.trim().eq_ignore_ascii_case("application/json"));
    if declared_body && !json {
        return Err(ApiError::new(
            StatusCode::UNSUPPORTED_MEDIA_TYPE,
            "request bodies must be sent as `Content-Type: application/json`",
        ));
    }
    Ok(())
}

/// Whether `host` (a `Host` header: name or address, then `:port`) names
/// this server.
fn host_allowed(allowed: &Allowed, host: &str) -> bool {
    let name = match host.strip_prefix('[') {
        // An IPv6 literal: `[::1]:8150`.
        Some(rest) => return rest.split(']').next().is_some_and(|a| a.parse::<std::net::Ipv6Addr>().is_ok()),
        None => host.rsplit_once(':').map_or(host, |(name, _)| name),
    };
    let name = name.to_ascii_lowercase();
    name == "localhost" || name.parse::<std::net::Ipv4Addr>().is_ok() || allowed.host.as_deref() == Some(&name)
}

/// `message` with every root folder's absolute path replaced by its root
/// name, and the server's working folder by `.`.
pub fn scrub(app: &App, message: &str) -> String {
    let mut out = message.to_string();
    let mut dirs: Vec<(String, String)> =
        app.roots.list().iter().map(|r| (r.dir.display().to_string(), r.name.to_string())).collect();
    if let Ok(cwd) = std::env::current_dir().and_then(|d| d.canonicalize()) {
        dirs.push((cwd.display().to_string(), ".".to_string()));
    }
    // Longest first, so a root inside the working folder keeps its name.
    dirs.sort_by_key(|(d, _)| std::cmp::Reverse(d.len()));
    for (dir, name) in dirs {
        if dir.len() > 1 {
            out = replace_folder(&out, &dir, &name);
        }
    }
    out
}

/// `text` with the folder path `dir` replaced by `name` wherever it is a
/// whole path or a path's start (`/srv/out` in `/srv/out/r1`, not in
/// `/srv/outside`).
fn replace_folder(text: &str, dir: &str, name: &str) -> String {
    let mut out = String::with_capacity(text.len());
    let mut rest = text;
    while let Some(i) = rest.find(dir) {
        let after = &rest[i + dir.len()..];
        let whole = !after.starts_with(|c: char| c.is_alphanumeric() || matches!(c, '.' | '-' | '_'));
        out.push_str(&rest[..i]);
        out.push_str(if whole { name } else { dir });
        rest = after;
    }
    out.push_str(rest);
    out
}

async fn scrub_response(app: &App, response: Response) -> Response {
    let (parts, body) = response.into_parts();
    match axum::body::to_bytes(body, SCRUB_LIMIT).await {
        Ok(bytes) => {
            let text = String::from_utf8_lossy(&bytes);
            let mut parts = parts;
            parts.headers.remove(header::CONTENT_LENGTH);
            Response::from_parts(parts, Body::from(scrub(app, &text)))
        }
        Err(_) => ApiError::internal("internal error").into_response(),
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use axum::http::HeaderValue;

    fn headers(pairs: &[(&'static str, &str)]) -> HeaderMap {
        let mut h = HeaderMap::new();
        for (k, v) in pairs {
            h.insert(*k, HeaderValue::from_str(v).unwrap());
        }
        h
    }

    #[test]
    fn hosts_are_loopback_names_or_addresses_only() {
        let a = Allowed::default();
        for ok in ["127.0.0.1:8150", "localhost:8150", "LOCALHOST", "[::1]:8150", "192.168.1.4:80"] {
            assert!(host_allowed(&a, ok), "{ok}");
        }
        for bad in ["evil.example", "evil.example:8150", "", "localhost.evil.example:8150", "[evil]:1"] {
            assert!(!host_allowed(&a, bad), "{bad}");
        }
        let named = Allowed { host: Some("studio.lan".into()) };
        assert!(host_allowed(&named, "studio.lan:8150"));
        assert!(!host_allowed(&named, "evil.example:8150"));
    }

    #[test]
    fn cross_origin_state_changes_are_refused() {
        let a = Allowed::default();
        let own = [("host", "127.0.0.1:8150"), ("origin", "http://127.0.0.1:8150")];
        let json = [("content-type", "application/json"), ("content-length", "2")];
        assert!(check(&a, &Method::POST, &headers(&[own[0], own[1], json[0], json[1]])).is_ok());
        assert!(check(&a, &Method::POST, &headers(&[own[0], json[0], json[1]])).is_ok(), "no Origin: not a browser");
        let evil = headers(&[own[0], ("origin", "http://evil.example"), json[0], json[1]]);
        assert_eq!(check(&a, &Method::POST, &evil).unwrap_err().status, StatusCode::FORBIDDEN);
        assert!(check(&a, &Method::GET, &evil).is_ok(), "reading is not a state change");
        let text = headers(&[own[0], ("content-type", "text/plain"), ("content-length", "20")]);
        assert_eq!(check(&a, &Method::POST, &text).unwrap_err().status, StatusCode::UNSUPPORTED_MEDIA_TYPE);
        let site = headers(&[own[0], ("sec-fetch-site", "cross-site"), json[0], json[1]]);
        assert_eq!(check(&a, &Method::POST, &site).unwrap_err().status, StatusCode::FORBIDDEN);
        let rebound = headers(&[("host", "evil.example:8150")]);
        assert_eq!(check(&a, &Method::GET, &rebound).unwrap_err().status, StatusCode::MISDIRECTED_REQUEST);
        assert!(check(&a, &Method::POST, &headers(&[own[0], ("content-length", "0")])).is_ok(), "empty bodies");
    }
}
