//! Turtle interpretation of successors, done once per grammar: every
//! successor becomes a [`Template`] in the edge's own frame, so rewriting an
//! edge is a handful of multiply-adds per new point.
//!
//! Frame conventions: heading H, left L = U × H, up U (the surface normal);
//! local coordinates are (H, L, U). `+`/`-` turn right/left about U (`+` is
//! clockwise seen from +U), `&`/`^` pitch the heading down/up about L,
//! `\`/`/` roll about H so that the left side goes down/up. The main line is
//! drawn with unit steps; then the similarity that maps the chain's
//! end-to-end vector onto (1, 0, 0) is applied (the minimal rotation, or a
//! half turn about U when the chain runs backwards), so the template's end
//! point is the old edge's end.

use crate::grammar::{EdgeSym, Item, Turn};
use glam::{DMat3, DQuat, DVec3};

/// One main-line edge of a successor.
#[derive(Clone, Copy, Debug)]
pub(crate) struct PieceT {
    pub sym: EdgeSym,
}

/// One branch of a successor in the aligned edge frame.
#[derive(Clone, Copy, Debug)]
pub(crate) struct BranchT {
    /// Chain vertex it starts at: 0 = the old start, k = the old end.
    pub at: u32,
    /// Unit direction in (H, L, U) of the old edge.
    pub dir: DVec3,
    /// +1: points to the left of the old edge, −1: to the right, 0: along
    /// it (never joins).
    pub side: i8,
    /// The branch's edge symbol.
    pub sym: EdgeSym,
}

/// A successor laid out in the frame of the edge it rewrites: the old edge
/// runs from (0,0,0) to (1,0,0).
#[derive(Clone, Debug)]
pub(crate) struct Template {
    /// Main-line edges in order (at least one).
    pub pieces: Vec<PieceT>,
    /// The k − 1 interior chain points.
    pub points: Vec<DVec3>,
    /// Branches in successor order.
    pub branches: Vec<BranchT>,
}

/// Smallest end-to-end length (in unit steps) a main line may have.
const MIN_SPAN: f64 = 1e-9;

fn turn_matrix(t: Turn, a: f64) -> DMat3 {
    match t {
        Turn::Right => DMat3::from_rotation_z(-a),
        Turn::Left => DMat3::from_rotation_z(a),
        Turn::PitchDown => DMat3::from_rotation_y(a),
        Turn::PitchUp => DMat3::from_rotation_y(-a),
        Turn::RollLeft => DMat3::from_rotation_x(-a),
        Turn::RollRight => DMat3::from_rotation_x(a),
    }
}

/// Lays out a successor's items with turn angle `angle_deg`. Errors (as a
/// sentence) when the main line draws no edge or ends where it starts.
pub(crate) fn compile(items: &[Item], angle_deg: f64) -> Result<Template, String> {
    let a = angle_deg.to_radians();
    let mut frame = DMat3::IDENTITY;
    let mut p = DVec3::ZERO;
    let mut pieces = Vec::new();
    let mut points = Vec::new();
    let mut branches = Vec::new();
    for item in items {
        match item {
            Item::Turn(t) => frame *= turn_matrix(*t, a),
            Item::Edge(sym) => {
                p += frame.x_axis;
                points.push(p);
                pieces.push(PieceT { sym: *sym });
            }
            Item::Branch(b) => {
                let mut f = frame;
                for t in &b.turns {
                    f *= turn_matrix(*t, a);
                }
                branches.push(BranchT { at: pieces.len() as u32, dir: f.x_axis, side: 0, sym: b.edge });
            }
        }
    }
    if pieces.is_empty() {
        return Err("its main line (outside brackets) draws no edge, so it cannot replace the old edge; \
                    put at least one EdgeN outside brackets"
            .into());
    }
    let span = p.length();
    if !span.is_finite() || span < MIN_SPAN {
        return Err("its main line ends where it starts (its turns bring it back to the start), \
                    so it cannot be stretched onto the old edge; the main line must end away from its start"
            .into());
    }
    let w = p / span;
    let rot = if w.y == 0.0 && w.z == 0.0 && w.x > 0.0 {
        DQuat::IDENTITY
    } else if w.x < -1.0 + 1e-12 {
        // Backwards chain: turn it half round about U, staying in the plane.
        DQuat::from_rotation_z(std::f64::consts::PI)
    } else {
        DQuat::from_rotation_arc(w, DVec3::X)
    };
    points.pop(); // the end point is the old end vertex
    for q in &mut points {
        *q = rot * *q / span;
    }
    for b in &mut branches {
        b.dir = (rot * b.dir).normalize();
        b.side = if b.dir.y > 1e-9 {
            1
        } else if b.dir.y < -1e-9 {
            -1
        } else {
            0
        };
    }
    Ok(Template { pieces, points, branches })
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::grammar::{Age, Branch};

    fn e(kind: u32) -> Item {
        Item::Edge(EdgeSym { kind, reversed: false, age: Age::Zero })
    }
    fn t(t: Turn) -> Item {
        Item::Turn(t)
    }
    fn br(turns: &[Turn], kind: u32) -> Item {
        Item::Branch(Branch { turns: turns.to_vec(), edge: EdgeSym { kind, reversed: false, age: Age::Zero } })
    }

    #[test]
    fn koch_bump_points_left_and_spans_three_steps() {
        use Turn::*;
        let k = compile(&[e(0), t(Left), e(0), t(Right), t(Right), e(0), t(Left), e(0)], 60.0).unwrap();
        assert_eq!(k.pieces.len(), 4);
        let want = [DVec3::new(1.0, 0.0, 0.0), DVec3::new(1.5, 3f64.sqrt() / 2.0, 0.0), DVec3::new(2.0, 0.0, 0.0)];
        for (p, w) in k.points.iter().zip(want) {
            assert!((*p - w / 3.0).length() < 1e-12, "{p} vs {}", w / 3.0);
        }
    }

    #[test]
    fn branches_turn_right_on_plus_and_get_their_side() {
        use Turn::*;
        let k = compile(&[e(0), br(&[Right], 1), br(&[Left], 1), br(&[], 2), e(0)], 90.0).unwrap();
        assert_eq!(k.points, vec![DVec3::new(0.5, 0.0, 0.0)]);
        let b = &k.branches;
        assert_eq!((b[0].at, b[0].side, b[1].side, b[2].side), (1, -1, 1, 0));
        assert!((b[0].dir - DVec3::new(0.0, -1.0, 0.0)).length() < 1e-12);
    }

    #[test]
    fn pitch_and_roll_follow_the_documented_axes() {
        use Turn::*;
        let k = compile(&[e(0), br(&[PitchDown], 0), br(&[RollLeft, Left], 0), e(0)], 90.0).unwrap();
        assert!((k.branches[0].dir - DVec3::new(0.0, 0.0, -1.0)).length() < 1e-12);
        // Rolling left turns L down to −U, so a left turn then heads down.
        assert!((k.branches[1].dir - DVec3::new(0.0, 0.0, -1.0)).length() < 1e-12);
    }

    #[test]
    fn chains_are_rotated_onto_the_edge() {
        use Turn::*;
        // Up-and-over: + E - E ends at (1+cos, −sin) after two steps.
        let k = compile(&[t(Right), e(0), t(Left), e(0)], 45.0).unwrap();
        let end = DVec3::new(1.0 + 0.5f64.sqrt(), -(0.5f64.sqrt()), 0.0);
        let first = DVec3::new(0.5f64.sqrt(), -(0.5f64.sqrt()), 0.0);
        let angle = -end.y.atan2(end.x);
        let want = DQuat::from_rotation_z(angle) * first / end.length();
        assert!((k.points[0] - want).length() < 1e-12);
        // A backwards chain stays in the plane.
        let k = compile(&[t(Right), t(Right), e(0), e(0), br(&[Right], 3)], 90.0).unwrap();
        assert!((k.points[0] - DVec3::new(0.5, 0.0, 0.0)).length() < 1e-12);
        assert!(k.branches[0].dir.z.abs() < 1e-12);
    }

    #[test]
    fn bad_main_lines_are_errors() {
        use Turn::*;
        assert!(compile(&[br(&[Right], 0)], 90.0).unwrap_err().contains("draws no edge"));
        let back = [e(0), t(Right), e(0), t(Right), e(0), t(Right), e(0)];
        assert!(compile(&back, 90.0).unwrap_err().contains("ends where it starts"));
    }
}
