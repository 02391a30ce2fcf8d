//! The component splits of a polygon scope other than `comp(f)`:
//! `comp(e)` (its edges), `offset(d)` (inset or grown polygon and the border
//! between), `setback(d)` (strips along selected edges and the remainder)
//! and `shapeL/U/O` (CGA's L, U and O footprints on a rectangular polygon).
//!
//! Every piece is a new scope in the polygon's plane. Pieces along an edge
//! (border, setback strips, edges) turn their scope so that x runs along the
//! edge and y inwards; the others keep the polygon's axes. An edge's class
//! is its outward normal in the polygon's plane: −y `front` (a lot's street
//! side, world +z), +y `back`, +x `right`, −x `left`.

use super::scope_geom::GeomKind;
use super::*;
use crate::ast::CompKind;
use crate::geom::{self, clip};
use crate::polygon::{area2, bbox};
use crate::program::{FACE_BACK, FACE_FRONT, FACE_LEFT, FACE_RIGHT, PIECE_REST, PIECE_SHAPE, SIDE};
use crate::scope::NO_GEOM;
use crate::skeleton;
use glam::{DAffine3, DMat3, DVec2};

/// A piece's geometry: the unit square (a wall of `comp(f)`), a polygon in
/// unit coordinates, or none (an edge: a scope of no height or depth).
pub(super) enum PieceGeom {
    Square,
    Polygon(Vec<DVec2>),
    Line,
}

/// A piece of a component split: its class (selector bits), scope and
/// geometry.
pub(super) type Piece = (u8, ScopeState, PieceGeom);

/// The class of an edge running along `d` (counter-clockwise polygon).
pub(super) fn edge_class(d: DVec2) -> u8 {
    let out = DVec2::new(d.y, -d.x);
    if out.y.abs() >= out.x.abs() {
        if out.y < 0.0 { FACE_FRONT } else { FACE_BACK }
    } else if out.x > 0.0 {
        FACE_RIGHT
    } else {
        FACE_LEFT
    }
}

/// A rectangle far around the box `[lo, hi]`, which half-planes cut into
/// the convex band of an edge.
fn enclosing(lo: DVec2, hi: DVec2) -> Vec<DVec2> {
    let big = 4.0 * (hi - lo).length() + 1.0;
    rect(lo - DVec2::splat(big), hi + DVec2::splat(big))
}

/// A rectangle `[lo, hi]` counter-clockwise.
fn rect(lo: DVec2, hi: DVec2) -> Vec<DVec2> {
    vec![lo, DVec2::new(hi.x, lo.y), hi, DVec2::new(lo.x, hi.y)]
}

impl<'g, M: Mode> Interp<'g, M> {
    /// The current scope's frame turned in its xy plane so that x runs
    /// along the unit direction `x`, moved to `at` (scope units).
    fn frame_along(&self, x: DVec2, at: DVec2) -> DAffine3 {
        let y = x.perp();
        let m = DMat3::from_cols(DVec3::new(x.x, x.y, 0.0), DVec3::new(y.x, y.y, 0.0), DVec3::Z);
        self.cur.frame * DAffine3::from_mat3_translation(m, DVec3::new(at.x, at.y, 0.0))
    }

    /// A scope in the plane of the current polygon scope holding `abs`
    /// (absolute points relative to the scope's centre), its x along the
    /// unit direction `x`; `None` for a piece with no area.
    fn piece(&self, class: u8, abs: &[DVec2], x: DVec2) -> Option<Piece> {
        if abs.len() < 3 || area2(abs).abs() <= 1e-12 * bbox(abs).map_or(0.0, |(lo, hi)| (hi - lo).length_squared()) {
            return None;
        }
        let y = x.perp();
        let local: Vec<DVec2> = abs.iter().map(|p| DVec2::new(p.dot(x), p.dot(y))).collect();
        let (lo, hi) = bbox(&local)?;
        let (c, size) = ((lo + hi) * 0.5, hi - lo);
        if size.x <= 0.0 || size.y <= 0.0 {
            return None;
        }
        let unit = local.iter().map(|q| (*q - c) / size).collect();
        let frame = self.frame_along(x, x * c.x + y * c.y);
        let scope = ScopeState { frame, size: DVec3::new(size.x, size.y, 0.0), tagged: self.cur.tagged, geom: NO_GEOM };
        Some((class, scope, PieceGeom::Polygon(unit)))
    }

    /// `setback(d, edges = [d0, d1, …])`: the distance of each of
    /// `corners`' edges (the scope's polygon cleaned of straight corners),
    /// read from the `n` expressions after the fixed arguments, where edge
    /// `j` of the list runs from the polygon's corner `j` to `j + 1` as
    /// written; `None` without a list.
    fn edge_distances(
        &mut self,
        rule: &'g RuleCode,
        args: u32,
        n: f64,
        g: super::scope_geom::Geom,
        at: genform_core::Span,
        corners: &[DVec2],
    ) -> Result<Option<Vec<f64>>, Stop> {
        if n <= 0.0 {
            return Ok(None);
        }
        let s = self.cur.size;
        let orig: Vec<DVec2> = self.points(g).iter().map(|q| DVec2::new(q.x * s.x, q.y * s.y)).collect();
        if n as usize != orig.len() {
            return Err(self
                .fail_at(at, format!("`setback`: `edges` lists {n} distances, the polygon has {} edges", orig.len())));
        }
        let mut d = vec![0.0; orig.len()];
        for j in 0..orig.len() {
            let x = self.num(rule, args + 6 + j as u32, "an edge's setback distance")?;
            if x.is_nan() || x < 0.0 {
                return Err(self.fail_at(at, format!("`setback`: the distance must be ≥ 0, found {x}")));
            }
            d[g.stored_edge(j)] = x;
        }
        // Each cleaned edge takes the distance of the written edge its
        // middle lies on.
        let k = corners.len();
        Ok(Some(
            (0..k)
                .map(|i| {
                    let mid = (corners[i] + corners[(i + 1) % k]) * 0.5;
                    let on = |j: usize| {
                        let (a, b) = (orig[j], orig[(j + 1) % orig.len()]);
                        let e = b - a;
                        let t = ((mid - a).dot(e) / e.length_squared().max(f64::MIN_POSITIVE)).clamp(0.0, 1.0);
                        (a + e * t).distance(mid)
                    };
                    let j = (0..orig.len()).min_by(|&a, &b| on(a).total_cmp(&on(b))).unwrap_or(0);
                    d[j]
                })
                .collect(),
        ))
    }

    /// The pieces of `comp(e)`, `offset`, `setback` and `shapeL/U/O` on the
    /// current polygon scope; `taken` is every class some arm selects.
    pub(super) fn pieces(
        &mut self,
        rule: &'g RuleCode,
        kind: CompKind,
        args: u32,
        taken: u8,
        span: u32,
    ) -> Result<Vec<Piece>, Stop> {
        let at = rule.spans[span as usize];
        let name = kind.name().0;
        let mut v = Vec::with_capacity(kind.name().1);
        for k in 0..kind.name().1 as u32 {
            v.push(self.num(rule, args + k, "a distance or width")?);
        }
        let g = match self.geom_of(self.cur.geom) {
            Some(g) if g.kind == GeomKind::Polygon => g,
            _ => {
                return Err(self.fail_at(
                    at,
                    format!("`{name}` needs a polygon scope: a `lot`, or a face from `comp(f)` (e.g. `comp(f) {{ top: … }}`)"),
                ));
            }
        };
        if g.len < 3 {
            return Ok(Vec::new());
        }
        let foot = self.absolute_foot(g);
        let (lo, hi) = bbox(&foot).unwrap_or_default();
        let eps = 1e-9 * (hi - lo).length();
        let corners = skeleton::clean(&foot, eps);
        let k = corners.len();
        if k < 3 {
            return Ok(Vec::new());
        }
        let dirs: Vec<DVec2> = (0..k).map(|i| (corners[(i + 1) % k] - corners[i]).normalize()).collect();
        let mut out = Vec::new();
        match kind {
            CompKind::Faces | CompKind::Solid => unreachable!("comp(f) and a solid's faces have their own pieces"),
            CompKind::Edges => {
                for i in 0..k {
                    let (a, b, d) = (corners[i], corners[(i + 1) % k], dirs[i]);
                    let frame = self.frame_along(d, (a + b) * 0.5);
                    let size = DVec3::new(a.distance(b), 0.0, 0.0);
                    out.push((
                        edge_class(d),
                        ScopeState { frame, size, tagged: self.cur.tagged, geom: NO_GEOM },
                        PieceGeom::Line,
                    ));
                }
            }
            CompKind::Vertices => {
                // Each corner, its x along the edge leaving it, classed by
                // the way it points (its outward bisector).
                for i in 0..k {
                    let (din, dout) = (dirs[(i + k - 1) % k], dirs[i]);
                    let bisector = DVec2::new(din.y, -din.x) + DVec2::new(dout.y, -dout.x);
                    let bisector = if bisector.length_squared() > 1e-24 { bisector } else { din };
                    let frame = self.frame_along(dout, corners[i]);
                    out.push((
                        edge_class(bisector.perp()),
                        ScopeState { frame, size: DVec3::ZERO, tagged: self.cur.tagged, geom: NO_GEOM },
                        PieceGeom::Line,
                    ));
                }
            }
            CompKind::Offset => {
                let d = v[0];
                if d < 0.0 {
                    let fail = |m: String| self.fail_at(at, format!("`offset`: {m}"));
                    let inset = skeleton::skeleton(&corners, Some(-d)).map_err(fail)?;
                    // The border bands: each edge's skeleton face up to the inset.
                    let faces = if taken & SIDE != 0 {
                        skeleton::skeleton(&corners, None).map_err(fail)?.faces
                    } else {
                        Vec::new()
                    };
                    for f in &inset.fronts {
                        out.extend(self.piece(PIECE_REST, f, DVec2::X));
                    }
                    if inset.fronts.is_empty() && taken & PIECE_REST != 0 {
                        self.note_at(
                            at,
                            &format!(
                                "`offset({d})` leaves nothing inside this polygon (an inset of {} reaches past its \
                                 middle), so `inside` gets no piece",
                                -d
                            ),
                        );
                    }
                    // `corners` is already clean, so the skeleton's edges are its edges.
                    for ((face, a), dir) in faces.iter().zip(&corners).zip(&dirs) {
                        let n = dir.perp();
                        let band = clip(face, n, n.dot(*a) - d);
                        out.extend(self.piece(edge_class(*dir), &band, *dir));
                    }
                } else {
                    out.extend(self.piece(PIECE_REST, &corners, DVec2::X));
                    if d > 0.0 && taken & SIDE != 0 {
                        let grown = geom::offset_miter(&corners, d);
                        let quads: Option<Vec<[DVec2; 4]>> = (grown.len() == k && geom::is_simple(&grown))
                            .then(|| {
                                (0..k)
                                    .map(|i| [corners[i], grown[i], grown[(i + 1) % k], corners[(i + 1) % k]])
                                    .collect()
                            })
                            .filter(|q: &Vec<[DVec2; 4]>| q.iter().all(|b| area2(b) > 0.0 && geom::is_simple(b)));
                        match quads {
                            Some(quads) => {
                                for (i, band) in quads.iter().enumerate() {
                                    out.extend(self.piece(edge_class(dirs[i]), band, dirs[i]));
                                }
                            }
                            // Mitred corners would make the outline cross
                            // itself or the bands fold over (a notch
                            // narrower than 2d): grow by the outside
                            // wavefront, which closes the notch, and cut
                            // each edge's band from the grown outline.
                            None => {
                                let grown = skeleton::grow(&corners, &vec![d; k])
                                    .ok()
                                    .flatten()
                                    .filter(|f| f.len() >= 3 && geom::is_simple(f))
                                    .ok_or_else(|| {
                                        self.fail_at(
                                            at,
                                            format!("`offset({d})`: the grown outline could not be laid out"),
                                        )
                                    })?;
                                let (glo, ghi) = bbox(&grown).unwrap_or((lo, hi));
                                let around = enclosing(glo, ghi);
                                let line = |i: usize| (dirs[i].perp(), dirs[i].perp().dot(corners[i]));
                                let bands: Vec<Vec<DVec2>> = (0..k)
                                    .map(|i| {
                                        // Up to d outside the edge's line and d
                                        // past its ends (a corner's square goes
                                        // to the earlier edge; in a closed
                                        // notch the walls' bands overlap, and
                                        // the earlier takes it).
                                        let (n, c) = line(i);
                                        let (u, a, b) = (dirs[i], corners[i], corners[(i + 1) % k]);
                                        let band = clip(&clip(&around, -n, d - c), n, c);
                                        clip(&clip(&band, -u, d - u.dot(a)), u, u.dot(b) + d)
                                    })
                                    .collect();
                                let (strips, _) = crate::setback::cut(&grown, &bands, Some(&corners));
                                for (i, pieces) in strips.into_iter().enumerate() {
                                    for p in pieces {
                                        out.extend(self.piece(edge_class(dirs[i]), &p, dirs[i]));
                                    }
                                }
                            }
                        }
                    }
                }
            }
            CompKind::Setback => {
                if let Some(d) = v.iter().find(|d| d.is_nan() || **d < 0.0) {
                    return Err(self.fail_at(at, format!("`setback`: the distance must be ≥ 0, found {d}")));
                }
                let per_edge = self.edge_distances(rule, args, v[5], g, at, &corners)?;
                // Each edge's distance: from `edges = […]`, or by its side
                // (all `v[0]` unless named).
                let dist = |i: usize| match (&per_edge, edge_class(dirs[i])) {
                    (Some(d), _) => d[i],
                    (None, FACE_FRONT) => v[1],
                    (None, FACE_BACK) => v[2],
                    (None, FACE_LEFT) => v[3],
                    (None, _) => v[4],
                };
                // The selected edges, one per line (collinear edges share a strip).
                let line = |i: usize| (dirs[i].perp(), dirs[i].perp().dot(corners[i]));
                let mut sel: Vec<usize> = Vec::new();
                for (i, dir) in dirs.iter().enumerate() {
                    let (n, c) = line(i);
                    let same = |j: &usize| {
                        let (m, e) = line(*j);
                        m.distance(n) <= 1e-9 && (e - c).abs() <= eps
                    };
                    if edge_class(*dir) & taken != 0 && !sel.iter().any(same) {
                        sel.push(i);
                    }
                }
                if !geom::is_convex(&corners) {
                    // Each strip in its edge's convex band: up to the depth,
                    // not past a reflex corner at either end, cut from an
                    // adjacent selected edge's strip as below.
                    let around = enclosing(lo, hi);
                    let turn = |a: usize, b: usize| dirs[a].perp_dot(dirs[b]);
                    let bands: Vec<Vec<DVec2>> = sel
                        .iter()
                        .map(|&i| {
                            let (n, c) = line(i);
                            let d = dist(i);
                            let (prev, next) = ((i + k - 1) % k, (i + 1) % k);
                            let mut band = clip(&clip(&around, n, c + d), -n, -c);
                            if turn(prev, i) < 0.0 {
                                band = clip(&band, -dirs[i], -dirs[i].dot(corners[i]));
                            }
                            if turn(i, next) < 0.0 {
                                band = clip(&band, dirs[i], dirs[i].dot(corners[next]));
                            }
                            for j in [prev, next] {
                                let dj = dist(j);
                                if j == i || !sel.contains(&j) || dj == 0.0 {
                                    continue;
                                }
                                let (m, e) = line(j);
                                band = if dj == d {
                                    clip(&band, n - m, c - e)
                                } else {
                                    clip(&band, n * dj - m * d, c * dj - e * d)
                                };
                            }
                            band
                        })
                        .collect();
                    let (strips, rest) = crate::setback::cut(&corners, &bands, None);
                    for (&i, pieces) in sel.iter().zip(strips) {
                        for p in pieces {
                            out.extend(self.piece(edge_class(dirs[i]), &p, dirs[i]));
                        }
                    }
                    for p in rest {
                        out.extend(self.piece(PIECE_REST, &p, DVec2::X));
                    }
                    return Ok(out);
                }
                for (si, &i) in sel.iter().enumerate() {
                    let (n, c) = line(i);
                    let d = dist(i);
                    // Inside the band, and nearer this edge's line than any
                    // other selected one's, in units of each band's depth
                    // (the corner between two strips is cut along the line
                    // from the polygon's corner to the remainder's; the
                    // bisector when the depths agree; ties go to the
                    // earlier edge).
                    let mut strip = clip(&corners, n, c + d);
                    for (sj, &j) in sel.iter().enumerate() {
                        if sj == si || strip.is_empty() {
                            continue;
                        }
                        let (m, e) = line(j);
                        let bias = if sj < si { -eps } else { eps };
                        let dj = dist(j);
                        // Equal depths cut along the bisector; a neighbour
                        // with no strip (depth 0) leaves this one whole.
                        strip = if dj == d {
                            clip(&strip, n - m, c - e + bias)
                        } else {
                            clip(&strip, n * dj - m * d, c * dj - e * d + bias * d.max(dj))
                        };
                    }
                    out.extend(self.piece(edge_class(dirs[i]), &strip, dirs[i]));
                }
                let mut rest = corners.clone();
                for &i in &sel {
                    let (n, c) = line(i);
                    rest = clip(&rest, -n, -(c + dist(i)));
                }
                out.extend(self.piece(PIECE_REST, &rest, DVec2::X));
            }
            CompKind::ShapeL | CompKind::ShapeU | CompKind::ShapeO => {
                if let Some(w) = v.iter().find(|w| **w < 0.0) {
                    return Err(self.fail_at(at, format!("`{name}`: the widths must be ≥ 0, found {w}")));
                }
                let box_area = (hi - lo).x * (hi - lo).y;
                if (area2(&foot) / 2.0 - box_area).abs() > 1e-9 * box_area {
                    return Err(self.fail_at(
                        at,
                        format!(
                            "`{name}` needs a rectangular polygon (a `lot(w, d)` or a wall); this one does not fill its box \
                             (use `setback` on other outlines)"
                        ),
                    ));
                }
                let (w, dp) = (hi.x - lo.x, hi.y - lo.y);
                // Inner corner of the remainder, each width clamped to the rectangle.
                let front = v[0].min(dp);
                let y0 = lo.y + front;
                let (x0, x1, y1) = match kind {
                    CompKind::ShapeL => (lo.x + v[1].min(w), hi.x, hi.y),
                    CompKind::ShapeU => (lo.x + v[1].min(w), (hi.x - v[2]).max(lo.x + v[1].min(w)), hi.y),
                    _ => ((lo.x + v[3]).min(hi.x), (hi.x - v[1]).max((lo.x + v[3]).min(hi.x)), (hi.y - v[2]).max(y0)),
                };
                let rest_empty = x1 - x0 <= eps || y1 - y0 <= eps;
                let shape: Vec<Vec<DVec2>> = if rest_empty {
                    vec![rect(lo, hi)]
                } else {
                    match kind {
                        CompKind::ShapeL => vec![vec![
                            lo,
                            DVec2::new(hi.x, lo.y),
                            DVec2::new(hi.x, y0),
                            DVec2::new(x0, y0),
                            DVec2::new(x0, hi.y),
                            DVec2::new(lo.x, hi.y),
                        ]],
                        CompKind::ShapeU => vec![vec![
                            lo,
                            DVec2::new(hi.x, lo.y),
                            hi,
                            DVec2::new(x1, hi.y),
                            DVec2::new(x1, y0),
                            DVec2::new(x0, y0),
                            DVec2::new(x0, hi.y),
                            DVec2::new(lo.x, hi.y),
                        ]],
                        // A ring is no simple polygon: four bands, front and
                        // back across the whole width.
                        _ => vec![
                            rect(lo, DVec2::new(hi.x, y0)),
                            rect(DVec2::new(x1, y0), DVec2::new(hi.x, y1)),
                            rect(DVec2::new(lo.x, y1), hi),
                            rect(DVec2::new(lo.x, y0), DVec2::new(x0, y1)),
                        ],
                    }
                };
                for p in &shape {
                    out.extend(self.piece(PIECE_SHAPE, &skeleton::clean(p, eps), DVec2::X));
                }
                if !rest_empty {
                    out.extend(self.piece(PIECE_REST, &rect(DVec2::new(x0, y0), DVec2::new(x1, y1)), DVec2::X));
                }
            }
        }
        Ok(out)
    }
}
