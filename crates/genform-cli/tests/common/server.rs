//! A running `genform serve` driven over HTTP (ureq, and raw sockets where
//! a client would clean up the path), for the studio's end-to-end tests.

use super::{root, s};
use serde_json::Value;
use std::io::{BufRead, BufReader, Read, Write};
use std::net::TcpStream;
use std::path::Path;
use std::process::{Child, Command, Stdio};
use std::sync::mpsc;
use std::time::{Duration, Instant};

/// A running `genform serve`, killed when dropped.
pub struct Server {
    pub child: Child,
    pub url: String,
    /// What the server says on stderr, once it ends (a lock: tests share
    /// the server between threads).
    pub stderr: std::sync::Mutex<mpsc::Receiver<String>>,
    pub agent: ureq::Agent,
}

impl Drop for Server {
    fn drop(&mut self) {
        let _ = self.child.kill();
        let _ = self.child.wait();
    }
}

/// An HTTP answer.
pub struct Answer {
    pub status: u16,
    pub content_type: String,
    pub body: Vec<u8>,
}

impl Answer {
    pub fn json(&self) -> Value {
        serde_json::from_slice(&self.body)
            .unwrap_or_else(|e| panic!("not JSON ({e}): {}", String::from_utf8_lossy(&self.body)))
    }

    pub fn ok(self) -> Self {
        assert!(self.status < 300, "status {}: {}", self.status, String::from_utf8_lossy(&self.body));
        self
    }
}

impl Server {
    /// `genform serve ARGS --port 0 --out out --examples <repo>/examples` in `dir`.
    pub fn start(dir: &Path, args: &[&str]) -> Server {
        let examples = root().join("examples");
        let mut child = Command::new(env!("CARGO_BIN_EXE_genform"))
            .current_dir(dir)
            .arg("serve")
            .args(args)
            .args(["--port", "0", "--out", "out", "--examples", s(&examples)])
            .stdout(Stdio::piped())
            .stderr(Stdio::piped())
            .spawn()
            .unwrap();
        let mut line = String::new();
        BufReader::new(child.stdout.take().unwrap()).read_line(&mut line).unwrap();
        let url = line.trim().strip_prefix("genform studio: ").unwrap_or_else(|| panic!("first line: {line:?}"));
        let (tx, stderr) = mpsc::channel();
        let mut err = child.stderr.take().unwrap();
        std::thread::spawn(move || {
            let mut text = String::new();
            let _ = err.read_to_string(&mut text);
            let _ = tx.send(text);
        });
        let config = ureq::Agent::config_builder()
            .http_status_as_error(false)
            .timeout_global(Some(Duration::from_secs(120)))
            .build();
        Server { child, url: url.trim_end_matches('/').to_string(), stderr: stderr.into(), agent: config.into() }
    }

    pub fn answer(mut r: ureq::http::Response<ureq::Body>) -> Answer {
        let status = r.status().as_u16();
        let content_type =
            r.headers().get("content-type").and_then(|v| v.to_str().ok()).unwrap_or_default().to_string();
        let body = r.body_mut().with_config().limit(64 << 20).read_to_vec().unwrap();
        Answer { status, content_type, body }
    }

    pub fn get(&self, path: &str) -> Answer {
        // A pooled keep-alive connection the server closed just as it is
        // reused fails at once ("Peer disconnected"); browsers retry such
        // idempotent requests, and so does this client, on a fresh one.
        let mut tries = 0;
        loop {
            match self.agent.get(format!("{}{path}", self.url)).call() {
                Ok(r) => return Self::answer(r),
                Err(e) if tries < 3 && matches!(e, ureq::Error::Io(_)) => tries += 1,
                Err(e) => panic!("GET {path}: {e}"),
            }
        }
    }

    pub fn post(&self, path: &str, body: &Value) -> Answer {
        self.post_raw(path, &body.to_string())
    }

    pub fn post_raw(&self, path: &str, body: &str) -> Answer {
        let r = self
            .agent
            .post(format!("{}{path}", self.url))
            .header("content-type", "application/json")
            .send(body)
            .unwrap();
        Self::answer(r)
    }

    /// The status of `GET target` sent as is (no client-side path cleaning).
    pub fn raw_status(&self, target: &str) -> u16 {
        let addr = self.url.trim_start_matches("http://");
        let mut stream = TcpStream::connect(addr).unwrap();
        write!(stream, "GET {target} HTTP/1.1\r\nHost: {addr}\r\nConnection: close\r\n\r\n").unwrap();
        let mut text = String::new();
        stream.read_to_string(&mut text).unwrap();
        let status = text.split_whitespace().nth(1).unwrap_or_default();
        status.parse().unwrap_or_else(|_| panic!("no status in {text:?}"))
    }

    /// `method target` with `headers` (each `Name: value`) and `body`, sent
    /// as is: the status and the text of the answer.
    pub fn raw(&self, method: &str, target: &str, headers: &[&str], body: &str) -> (u16, String) {
        let addr = self.url.trim_start_matches("http://");
        let mut stream = TcpStream::connect(addr).unwrap();
        let mut head = format!("{method} {target} HTTP/1.1\r\nConnection: close\r\n");
        if !headers.iter().any(|h| h.to_ascii_lowercase().starts_with("host:")) {
            head.push_str(&format!("Host: {addr}\r\n"));
        }
        for h in headers {
            head.push_str(&format!("{h}\r\n"));
        }
        write!(stream, "{head}Content-Length: {}\r\n\r\n{body}", body.len()).unwrap();
        let mut text = String::new();
        stream.read_to_string(&mut text).unwrap();
        let status = text.split_whitespace().nth(1).and_then(|s| s.parse().ok()).unwrap_or(0);
        (status, text)
    }

    /// Sends only the head of a POST declaring a `length`-byte body; the
    /// status and the text of the answer.
    pub fn raw_post_head(&self, path: &str, length: usize) -> (u16, String) {
        let addr = self.url.trim_start_matches("http://");
        let mut stream = TcpStream::connect(addr).unwrap();
        write!(
            stream,
            "POST {path} HTTP/1.1\r\nHost: {addr}\r\nContent-Type: application/json\r\nContent-Length: {length}\r\n\r\n{{"
        )
        .unwrap();
        stream.set_read_timeout(Some(Duration::from_secs(30))).unwrap();
        let mut bytes = Vec::new();
        let _ = stream.read_to_end(&mut bytes);
        let text = String::from_utf8_lossy(&bytes).into_owned();
        let status = text.split_whitespace().nth(1).and_then(|s| s.parse().ok()).unwrap_or(0);
        (status, text)
    }

    /// Polls run `id` until `done` holds for its snapshot (at most a minute).
    pub fn wait_run(&self, id: &str, what: &str, done: impl Fn(&Value) -> bool) -> Value {
        let start = Instant::now();
        loop {
            let snap = self.get(&format!("/api/runs/{id}")).ok().json();
            if done(&snap) {
                return snap;
            }
            assert!(start.elapsed() < Duration::from_secs(60), "run {id} never {what}: {snap:#}");
            std::thread::sleep(Duration::from_millis(50));
        }
    }

    /// Everything the server said on stderr (ends it).
    pub fn stderr(mut self) -> String {
        let _ = self.child.kill();
        let stderr = self.stderr.lock().unwrap_or_else(|e| e.into_inner());
        stderr.recv_timeout(Duration::from_secs(10)).unwrap_or_default()
    }
}
