//! The studio page's files, embedded at build time (see `build.rs`), and
//! the content type of each file name.

include!(concat!(env!("OUT_DIR"), "/studio_assets.rs"));

/// The embedded file at `path` (relative to `studio/`, `/`-separated).
pub fn get(path: &str) -> Option<&'static [u8]> {
    ASSETS.iter().find(|(p, _)| *p == path).map(|(_, bytes)| *bytes)
}

/// What `/` shows when the page was not built in: where it should be.
pub const PLACEHOLDER: &str = "<!doctype html><meta charset=utf-8><title>genform studio</title>\
<p>The studio page is not in this build (crates/genform-studio/studio/index.html). The API is at <code>/api/</code>.";

/// The content type of a file, by its name's ending.
pub fn content_type(name: &str) -> &'static str {
    let ext = name.rsplit_once('.').map(|(_, e)| e.to_ascii_lowercase()).unwrap_or_default();
    match ext.as_str() {
        "html" | "htm" => "text/html; charset=utf-8",
        "js" | "mjs" => "text/javascript; charset=utf-8",
        "css" => "text/css; charset=utf-8",
        "json" | "map" => "application/json",
        "svg" => "image/svg+xml",
        "png" => "image/png",
        "jpg" | "jpeg" => "image/jpeg",
        "gif" => "image/gif",
        "ico" => "image/x-icon",
        "webp" => "image/webp",
        "wasm" => "application/wasm",
        "woff2" => "font/woff2",
        "woff" => "font/woff",
        "glb" => "model/gltf-binary",
        "gltf" => "model/gltf+json",
        "txt" | "md" | "csv" | "obj" | "sg" | "ls" | "bsg" | "gr8" | "bnf" | "yaml" | "yml" | "toml" => {
            "text/plain; charset=utf-8"
        }
        "" if name.ends_with("LICENSE") => "text/plain; charset=utf-8",
        _ => "application/octet-stream",
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn content_types_follow_the_ending() {
        assert_eq!(content_type("index.html"), "text/html; charset=utf-8");
        assert_eq!(content_type("vendor/three/three.module.JS"), "text/javascript; charset=utf-8");
        assert_eq!(content_type("best.glb"), "model/gltf-binary");
        assert_eq!(content_type("stats.csv"), "text/plain; charset=utf-8");
        assert_eq!(content_type("x.schem"), "application/octet-stream");
    }

    #[test]
    fn the_table_has_relative_slash_paths() {
        for (p, _) in ASSETS {
            assert!(!p.starts_with('/') && !p.contains('\\') && !p.split('/').any(|c| c == ".."), "{p}");
        }
    }
}
