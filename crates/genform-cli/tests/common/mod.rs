//! Shared helpers of the end-to-end tests: run the real `genform` binary in
//! a folder and print everything it said when an expectation fails.
#![allow(dead_code)]

use std::path::{Path, PathBuf};
use std::process::{Command, Output};

pub fn root() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("../..").canonicalize().unwrap()
}

pub fn example(name: &str) -> PathBuf {
    root().join("examples/shape").join(name)
}

pub struct Run {
    pub out: Output,
}

impl Run {
    pub fn stdout(&self) -> String {
        String::from_utf8_lossy(&self.out.stdout).into_owned()
    }
    pub fn stderr(&self) -> String {
        String::from_utf8_lossy(&self.out.stderr).into_owned()
    }
    pub fn ok(self) -> Self {
        assert!(self.out.status.success(), "genform failed\nstdout:\n{}\nstderr:\n{}", self.stdout(), self.stderr());
        self
    }
    pub fn fails(self) -> Self {
        assert!(
            !self.out.status.success(),
            "genform should have failed\nstdout:\n{}\nstderr:\n{}",
            self.stdout(),
            self.stderr()
        );
        self
    }
}

pub fn genform(dir: &Path, args: &[&str]) -> Run {
    let out = Command::new(env!("CARGO_BIN_EXE_genform")).current_dir(dir).args(args).output().unwrap();
    Run { out }
}

pub fn s(p: &Path) -> &str {
    p.to_str().unwrap()
}
