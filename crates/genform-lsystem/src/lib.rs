//! L-systems (`.ls`): the classic rewriting systems of *The Algorithmic
//! Beauty of Plants* and L-Py, with a 2D/3D turtle, and an L-system as a
//! genform [`Generator`](genform_core::Generator) for evolutionary control.
//!
//! - [`compile`] reads a `.ls` file (every error at once, with positions).
//! - [`LSystem::derive`] rewrites the axiom in parallel steps:
//!   deterministic, stochastic (weighted groups), parametric with
//!   conditions, context-sensitive with bracket-aware contexts and
//!   `ignore`/`consider` sets, decomposition rules, cut `%`, production
//!   bodies with L-Py's `produce`/`nproduce`, global variables changed by
//!   Start/StartEach/EndEach/End hooks, and query modules `?P ?H ?U ?L`
//!   filled from the turtle after each step.
//! - [`LSystem::interpret`] runs the turtle, with interpretation rules,
//!   into a [`Scene`](genform_core::Scene): polylines in 2D, frusta in 3D,
//!   polygons, generalized cylinders, and `~` surfaces (a built-in
//!   Bézier-patch leaf, or meshes loaded with [`compile_with_assets`]).
//! - [`LsGenerator`] makes each module rewrite a gene (production choice and
//!   random draws) with the successor's rewritable modules as its child
//!   slots, so the optimizers can steer a context-free stochastic or
//!   parametric L-system; ranged constants (`define a = 30 in [0, 90]`,
//!   `define n = 3 in 1..5`, an L-Py file's editor scalars) are genes of
//!   its root ([`LSystem::with_constants`]).
//!
//! The language is documented in `docs/lsystem.md`.
//!
//! ```
//! use genform_core::{Rng, SourceFile};
//! let file = SourceFile::new("koch.ls", "derivation: 2\nangle: 60\nheading: +x\naxiom: F++F++F\nproduction:\nF -> F-F++F-F\n");
//! let (system, _warnings) = genform_lsystem::compile(&file).unwrap();
//! let s = system.derive(system.settings.derivation, &mut Rng::from_seed(1)).unwrap();
//! assert_eq!(s.len(), 112);
//! ```

mod alphabet;
mod arg;
mod axes;
mod body;
mod compile;
mod context;
mod derive;
mod entry;
mod generator;
pub mod lpy;
mod ranged;
mod recompile;
mod rules;
mod settings;
mod string;
mod surface;
mod syntax;
mod turtle;

#[cfg(test)]
mod tests;

pub use alphabet::{Alphabet, Command, PyKinds, PyParams, Sym, SymbolInfo};
pub use compile::LSystem;
pub use derive::DeriveError;
pub use entry::{compile, compile_with_assets};
pub use generator::{GeneratorError, LsGenerator};
pub use lpy::{compile_lpy, compile_lpy_with_assets};
pub use ranged::RangedConstant;
pub use settings::{Heading, Settings, View};
pub use string::ModuleString;
pub use surface::{NoSurfaceAssets, SurfaceAssets};
pub use turtle::{TurtleEnd, TurtleError};
