//! Reading L-Py (`.lpy`) files: pure L-systems and a small Python subset.
//!
//! An L-Py file is a Python module with an L-system section. genform reads
//! the header words (`Axiom:`, `derivation length:`, `maximum depth:`,
//! `production:`, `decomposition:`, `interpretation:`/`homomorphism:`,
//! `endlsystem`, `group N:`/`endgroup`, `ignore:`/`consider:`), `module`
//! declarations, productions with `-->` (or `->`) or with an indented
//! Python body (`if`/`elif`/`else`, assignments, `produce`, `nproduce`,
//! `produce *`), module-level constants, `from math import …`, `import
//! random`, small `def` functions of expressions, `random()`, `uniform`,
//! `gauss`, `randint`, `getIterationNb()`, the hooks `Start`, `StartEach`,
//! `EndEach` and `End` assigning globals, `useGroup`, and L-Py's
//! `context().turtle.setAngleIncrement(a)`. Everything else that is
//! Python (loops, the lstring, PlantGL objects, other imports, calls) is
//! an error at its `file:line:col` naming the construct.
//!
//! The file is translated into the `.ls` language ([`translate`]) and
//! compiled by the `.ls` compiler, so derivation, the turtle and every
//! export work unchanged; a source map takes every diagnostic back to the
//! `.lpy` text. Python expressions are read into a tree first
//! (`pyexpr.rs`), so Python's precedence and operators (`**`, `//`, `%`,
//! `a if c else b`, chained comparisons) keep their meaning; random draws
//! map onto the `.ls` random functions, which draw from the derivation's
//! one stream.
//!
//! Files: `text.rs` (logical lines, the output with its source map),
//! `pyexpr.rs` (Python expressions), `block.rs` (indented statement
//! blocks), `translate.rs` (the file), `names.rs` (L-Py's module names).
//!
//! **Turtle.** PlantGL's turtle starts with heading H = (0, 0, 1), left
//! L = (0, −1, 0) and up U = (1, 0, 0) in L-Py's z-up world, turns by 60°
//! and steps by 1. genform's world is y-up; the axis change
//! (x, y, z) ↦ (y, z, x) (a rotation, [`to_genform_axes`]) takes L-Py's
//! up +z to genform's +y and its frame to H = +y, L = −x, U = +z, which is
//! genform's `heading: +y` frame, and L-Py's default camera (from +x, with
//! +y to the right) to the SVG's xy plane. PlantGL's widths are radii:
//! `width_unit: 2` turns them into genform's diameters (initial radius
//! 0.1). Long predefined names (`SetColor`, `SetWidth`, `Sphere`, `Left`,
//! …) are one module each and draw as their one-character aliases.

mod block;
mod names;
mod pyexpr;
mod pytypes;
mod text;
mod translate;

use crate::alphabet::{Command, PyKinds, PyParams};
use crate::compile::LSystem;
use crate::surface::SurfaceAssets;
use genform_core::{Diagnostic, Diagnostics, SourceFile};
use names::{DRAWS_AS, canonical};
pub use text::Translation;

pub use crate::axes::{to_genform_axes, to_lpy_axes};

/// Translates an L-Py file into `.ls` text, or says why it cannot.
pub fn translate(src: &str) -> Result<Translation, Vec<Diagnostic>> {
    translate::translate(src)
}

/// Compiles an L-Py file (the subset above) into an [`LSystem`].
pub fn compile_lpy(file: &SourceFile) -> Result<(LSystem, Diagnostics), Diagnostics> {
    compile_lpy_with_assets(file, &crate::surface::NoSurfaceAssets)
}

/// [`compile_lpy`], loading surface meshes through `assets`.
pub fn compile_lpy_with_assets(
    file: &SourceFile,
    assets: &dyn SurfaceAssets,
) -> Result<(LSystem, Diagnostics), Diagnostics> {
    let mut diags = Diagnostics::new(file.clone());
    // An error at the end of the file (`x =`) points at the end, not past it.
    let len = file.text.len() as u32;
    let in_file = |mut d: Diagnostic| {
        if let Some(span) = d.span.as_mut() {
            span.end = span.end.min(len);
            span.start = span.start.min(span.end);
        }
        d
    };
    let t = match translate(&file.text) {
        Ok(t) => t,
        Err(errors) => {
            for e in errors {
                diags.push(in_file(e));
            }
            return Err(diags);
        }
    };
    let ls = SourceFile::new(format!("{} (as .ls)", file.name), t.text.clone());
    let map = |d: Diagnostics, diags: &mut Diagnostics| {
        for item in d.items {
            diags.push(in_file(t.map_diagnostic(item)));
        }
    };
    match crate::entry::compile_with_assets(&ls, assets) {
        Ok((mut system, warnings)) => {
            for w in t.warnings.iter().cloned() {
                diags.push(in_file(w));
            }
            map(warnings, &mut diags);
            let stem = std::path::Path::new(&*file.name).file_stem().map(|s| s.to_string_lossy().into_owned());
            system.settings.name = stem.unwrap_or_default();
            system.settings.lpy = true;
            for sym in &mut system.alphabet.symbols {
                let typed = t.params.iter().find(|(n, a, _)| *n == sym.name && *a == sym.arity as usize);
                let mut python = typed.map(|(_, _, p)| p.clone()).unwrap_or_default();
                if crate::turtle::query::Query::of(&sym.name).is_some() {
                    // The turtle fills a query's x, y, z with floats, from the
                    // axiom on.
                    let xyz = if sym.arity == 3 { 0b111 } else { 0 };
                    python = PyParams { steps: vec![PyKinds { floats: xyz, bools: 0 }] };
                }
                sym.python = Some(python);
                if let Some((_, short)) = DRAWS_AS.iter().find(|(n, _)| *n == sym.name) {
                    sym.command = Command::of(short);
                }
                if let Some((_, target)) = t.aliases.iter().find(|(n, _)| *n == sym.name) {
                    let target = canonical(target);
                    let short = DRAWS_AS.iter().find(|(n, _)| *n == target).map_or(target, |(_, a)| a);
                    sym.command = Command::of(short);
                }
            }
            if t.empty_axiom {
                system.axiom.syms.clear();
                system.axiom.params.clear();
            }
            Ok((system, diags))
        }
        Err(errors) => {
            map(errors, &mut diags);
            Err(diags)
        }
    }
}
