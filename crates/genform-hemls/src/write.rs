//! Canonical `.gr8` text for the compiled grammar: [`Hemls`] (and each of its
//! parts) implements [`Display`](fmt::Display), and the text of a valid
//! system compiles back to an equal value (rule spans aside).
//!
//! The canonical form: tokens separated by one space; the axiom's sides
//! joined by ` + `; `~` directly before the edge it reverses; branches as
//! sibling groups `[ turns edge ]`; `Weight w` only where `w ≠ 1`; the
//! condition after the first successor; then `Angle`, `Sync`,
//! `BranchAngle`. Numbers use Rust's shortest round-trip form. No comments
//! (the name is the file's, not part of the text).

use crate::grammar::{
    Age, AxiomSide, Branch, Cmp, Condition, EdgeSym, Hemls, Item, Predecessor, Rule, Successor, Turn,
};
use std::fmt;

impl fmt::Display for Turn {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(match self {
            Turn::Right => "+",
            Turn::Left => "-",
            Turn::PitchDown => "&",
            Turn::PitchUp => "^",
            Turn::RollLeft => "\\",
            Turn::RollRight => "/",
        })
    }
}

impl fmt::Display for EdgeSym {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        if self.reversed {
            f.write_str("~ ")?;
        }
        let age = match self.age {
            Age::Zero => "",
            Age::Same => "_i",
            Age::Plus1 => "_i+1",
            Age::Minus1 => "_i-1",
        };
        write!(f, "Edge{}{age}", self.kind)
    }
}

impl fmt::Display for Branch {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str("[ ")?;
        for t in &self.turns {
            write!(f, "{t} ")?;
        }
        write!(f, "{} ]", self.edge)
    }
}

impl fmt::Display for Item {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Item::Turn(t) => t.fmt(f),
            Item::Edge(e) => e.fmt(f),
            Item::Branch(b) => b.fmt(f),
        }
    }
}

/// The items only; the weight belongs to the rule line.
impl fmt::Display for Successor {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        for (k, item) in self.items.iter().enumerate() {
            if k > 0 {
                f.write_str(" ")?;
            }
            item.fmt(f)?;
        }
        Ok(())
    }
}

impl fmt::Display for Predecessor {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        if let Some(l) = self.left {
            write!(f, "Edge{l} < ")?;
        }
        write!(f, "Edge{}{}", self.kind, if self.timed { "_i" } else { "" })?;
        if let Some(r) = self.right {
            write!(f, " > Edge{r}")?;
        }
        Ok(())
    }
}

impl fmt::Display for Condition {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        let op = match self.cmp {
            Cmp::Less => "<",
            Cmp::Equal => "=",
            Cmp::Greater => ">",
        };
        write!(f, "If i {op} {}", self.value)
    }
}

/// One rule line, without the newline.
impl fmt::Display for Rule {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        self.pred.fmt(f)?;
        for (k, s) in self.successors.iter().enumerate() {
            write!(f, " -> {s}")?;
            if s.weight != 1.0 {
                write!(f, " Weight {}", s.weight)?;
            }
            if k == 0
                && let Some(c) = &self.condition
            {
                write!(f, " {c}")?;
            }
        }
        Ok(())
    }
}

impl fmt::Display for AxiomSide {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "{}Edge{}", if self.reversed { "~ " } else { "" }, self.kind)
    }
}

/// The whole file, one line each for the axiom, every rule, `Angle` and,
/// when set, `Sync` and `BranchAngle`.
impl fmt::Display for Hemls {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        for (k, side) in self.axiom.iter().enumerate() {
            if k > 0 {
                f.write_str(" + ")?;
            }
            side.fmt(f)?;
        }
        f.write_str("\n")?;
        for rule in &self.rules {
            writeln!(f, "{rule}")?;
        }
        writeln!(f, "Angle {}", self.angle)?;
        if self.sync {
            writeln!(f, "Sync")?;
        }
        if let Some(b) = self.branch_angle {
            writeln!(f, "BranchAngle {b}")?;
        }
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use crate::syntax::parse_str;

    #[test]
    fn writes_canonical_text_with_sibling_branches() {
        let text = "// tiles\nEdge0  + ~ Edge1 + Edge2\nEdge0 -> Edge0 [ [ [ [ + Edge2 ] + + Edge1 ] - Edge1 ] - - Edge2 ] Edge0\n\
                    Edge1 < Edge0_i > Edge2 -> ~ Edge1_i+1 & Edge2_i-1 ^ Weight 2.5 If i > 3 -> Edge0_i\n\
                    Sync\nAngle 60\nBranchAngle 22.5\n";
        let h = parse_str("t.gr8", text).unwrap();
        let written = h.to_string();
        assert_eq!(
            written,
            "Edge0 + ~ Edge1 + Edge2\n\
             Edge0 -> Edge0 [ + Edge2 ] [ + + Edge1 ] [ - Edge1 ] [ - - Edge2 ] Edge0\n\
             Edge1 < Edge0_i > Edge2 -> ~ Edge1_i+1 & Edge2_i-1 ^ Weight 2.5 If i > 3 -> Edge0_i\n\
             Angle 60\nSync\nBranchAngle 22.5\n"
        );
        let unspanned = |mut h: crate::Hemls| {
            h.rules.iter_mut().for_each(|r| r.span = Default::default());
            h
        };
        assert_eq!(unspanned(parse_str("t.gr8", &written).unwrap()), unspanned(h));
    }
}
