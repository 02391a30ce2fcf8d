//! The names an expression can refer to: the [`Scope`] trait [`compile`]
//! resolves names against, and [`Names`], a scope from a list of names.
//!
//! [`compile`]: super::compile()

/// Names visible to an expression, mapped to indices of the `env` slice
/// passed to [`Program::eval`](super::Program::eval).
pub trait Scope {
    /// The env index of variable `name` (names may contain dots, e.g.
    /// `size.x`; a call `f(x)` of a non-builtin function `f` with one bare
    /// identifier argument is looked up as the variable `"f(x)"`, and a call
    /// `f()` without arguments as `"f()"`).
    fn variable(&self, name: &str) -> Option<u32>;
    /// The value of a named constant (folded at compile time); variables
    /// shadow constants, constants shadow the built-in `pi`, `e`, ….
    fn constant(&self, _name: &str) -> Option<f64> {
        None
    }
    /// Known names, for "did you mean" hints.
    fn names(&self) -> Vec<String> {
        Vec::new()
    }
}

/// A scope from a list of names: name `i` is env index `i`.
#[derive(Clone, Copy, Debug)]
pub struct Names<'a>(pub &'a [&'a str]);

impl Scope for Names<'_> {
    fn variable(&self, name: &str) -> Option<u32> {
        self.0.iter().position(|n| *n == name).map(|i| i as u32)
    }
    fn names(&self) -> Vec<String> {
        self.0.iter().map(|s| s.to_string()).collect()
    }
}
