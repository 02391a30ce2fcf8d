//! Polygon and mass scopes in the interpreter: `lot`, `extrude`, `comp(f)`,
//! `shape`, the roofs, and how `split` and `repeat` cut their geometry.
//!
//! A scope's geometry lives in the run's arena ([`Stacks::geoms`] and
//! [`Stacks::pts`]) in *unit* coordinates, like the built-in primitives: the
//! scope's frame × diag(size) places it, so `size`, `scale`, `rotate` and
//! `mirror` move and stretch it with the scope. A polygon lies in the
//! scope's xy plane (unit points `(x, y)`, z = 0), counter-clockwise seen
//! from +z, which is its outward side. A mass is the prism over a footprint
//! in the xz plane (unit points `(x, z)`, counter-clockwise seen from +y)
//! from y = −0.5 to +0.5.

use super::pieces::{Piece, PieceGeom};
use super::scope_geom::{Geom, GeomKind};
use super::*;
use crate::ast::CompKind;
use crate::geom::{self, RoofKind};
use crate::polygon::{area2, bbox};
use crate::program::{FACE_BACK, FACE_BOTTOM, FACE_FRONT, FACE_LEFT, FACE_RIGHT, FACE_TOP, PIECE_REST, PIECE_SHAPE};
use crate::scope::{LIFT, NO_GEOM};
use genform_core::scene::Mesh;
use glam::{DAffine3, DMat3, DVec2};

/// Points the geometry arena of one run may hold (32 MiB); a run that
/// needs more stops like one that places too many primitives.
const MAX_GEOM_POINTS: usize = 1 << 21;

/// The unit square, counter-clockwise in a polygon's xy plane.
pub(super) const SQUARE: [DVec2; 4] =
    [DVec2::new(-0.5, -0.5), DVec2::new(0.5, -0.5), DVec2::new(0.5, 0.5), DVec2::new(-0.5, 0.5)];
/// The unit square as a footprint (x, z), counter-clockwise seen from +y.
const FOOT_SQUARE: [DVec2; 4] =
    [DVec2::new(-0.5, 0.5), DVec2::new(0.5, 0.5), DVec2::new(0.5, -0.5), DVec2::new(-0.5, -0.5)];

/// Whether unit points are the whole unit square (so a box says the same).
fn is_unit_square(p: &[DVec2]) -> bool {
    p.len() == 4
        && FOOT_SQUARE.iter().all(|c| p.iter().any(|q| (*q - *c).abs().max_element() <= 1e-12))
        && (area2(p).abs() - 2.0).abs() <= 1e-9
}

impl<'g, M: Mode> Interp<'g, M> {
    pub(super) fn geom_of(&self, id: u32) -> Option<Geom> {
        (id != NO_GEOM).then(|| self.st.geoms[id as usize])
    }

    pub(super) fn points(&self, g: Geom) -> &[DVec2] {
        &self.st.pts[g.start as usize..(g.start + g.len) as usize]
    }

    /// Adds geometry (unit points) to the arena.
    fn add_geom(&mut self, kind: GeomKind, pts: &[DVec2]) -> Result<u32, Stop> {
        if self.st.pts.len() + pts.len() > MAX_GEOM_POINTS {
            return Err(self.mode.limit(LimitKind::Primitives, &self.limits));
        }
        let start = self.st.pts.len() as u32;
        self.st.pts.extend_from_slice(pts);
        self.st.geoms.push(Geom { kind, start, len: pts.len() as u32, reversed: false });
        Ok((self.st.geoms.len() - 1) as u32)
    }

    #[cold]
    pub(super) fn fail_at(&self, span: genform_core::Span, msg: String) -> Stop {
        let sym = &self.g.graph.symbols[self.top.sym as usize].name;
        let loc = self.g.file.location(span.start);
        ExpressError::Eval(format!("{loc}: rule `{sym}`: {msg}")).into()
    }

    /// The polygon a `splitArea` along `axis` divides: the scope's, in
    /// absolute units about the scope's centre, counter-clockwise.
    pub(super) fn area_polygon(&self, rule: &'g RuleCode, axis: u8, span: u32) -> Result<Vec<DVec2>, Stop> {
        match self.geom_of(self.cur.geom) {
            Some(g) if g.kind == GeomKind::Polygon && axis < 2 => Ok(self.absolute_foot(g)),
            _ => Err(self.fail_at(
                rule.spans[span as usize],
                "`splitArea` divides a polygon scope (a `lot`, a face from `comp(f)`) along x or y".to_string(),
            )),
        }
    }

    /// Notes at `span` that the run left something out (`msg` says what
    /// and why), placed as [`Self::fail_at`] places errors.
    pub(super) fn note_at(&mut self, span: genform_core::Span, msg: &str) {
        let sym = &self.g.graph.symbols[self.top.sym as usize].name;
        let loc = self.g.file.location(span.start);
        let text = format!("{loc}: rule `{sym}`: {msg}");
        self.mode.note(text);
    }

    /// `lot(w, d)` or `lot(x0, z0, …)`: a polygon scope in the current
    /// scope's xz plane through its centre (absolute units), its +z up
    /// along the current +y, its x along the current x.
    pub(super) fn lot(&mut self, rule: &'g RuleCode, args: u32, n: u32, span: u32) -> Result<(), Stop> {
        let at = rule.spans[span as usize];
        let mut v = Vec::with_capacity(n as usize);
        for k in 0..n {
            v.push(self.num(rule, args + k, "a lot size or coordinate")?);
        }
        let p: Vec<DVec2> = if n == 2 {
            let (w, d) = (v[0], v[1]);
            if !(w > 0.0 && d > 0.0) {
                return Err(self.fail_at(at, format!("`lot` needs a positive width and depth, found {w} and {d}")));
            }
            SQUARE.iter().map(|c| *c * DVec2::new(w, d)).collect()
        } else {
            // Written as (x, z); the polygon's y runs along −z.
            v.chunks(2).map(|c| DVec2::new(c[0], -c[1])).collect()
        };
        self.set_lot(p, Some(at))
    }

    /// Starts the run on a footprint's polygon `p` (as [`Self::set_lot`]),
    /// turned so that edge `street_edge` (from corner `i` to `i + 1` as
    /// given; negative: none) faces the scope's −y, its `front`.
    pub(super) fn start_on(&mut self, p: Vec<DVec2>, street_edge: f64) -> Result<(), Stop> {
        let n = p.len();
        if !(street_edge >= 0.0 && (street_edge as usize) < n) || n < 3 {
            return self.set_lot(p, None);
        }
        let k = street_edge as usize;
        let d = (p[(k + 1) % n] - p[k]).normalize_or_zero();
        // Outward: right of the edge on a counter-clockwise outline.
        let out = if area2(&p) > 0.0 { DVec2::new(d.y, -d.x) } else { DVec2::new(-d.y, d.x) };
        if out == DVec2::ZERO {
            return self.set_lot(p, None);
        }
        // Turn by the angle that takes `out` to −y.
        let a = -std::f64::consts::FRAC_PI_2 - out.y.atan2(out.x);
        let turn = DVec2::from_angle(a);
        let turned: Vec<DVec2> = p.iter().map(|&q| turn.rotate(q)).collect();
        self.set_lot_turned(turned, None, a)
    }

    /// Makes the scope the polygon `p` (points in the scope's xz plane
    /// relative to its centre, as `(x, −z)`), for `lot` at `at` or for a
    /// footprint the run starts on.
    pub(super) fn set_lot(&mut self, p: Vec<DVec2>, at: Option<genform_core::Span>) -> Result<(), Stop> {
        self.set_lot_turned(p, at, 0.0)
    }

    /// [`Self::set_lot`] for a polygon given turned by `a` (radians,
    /// counter-clockwise in the `(x, −z)` plane) from the scope's axes: the
    /// scope's x and y run along the turned axes.
    fn set_lot_turned(&mut self, mut p: Vec<DVec2>, at: Option<genform_core::Span>, a: f64) -> Result<(), Stop> {
        if !crate::footprint::is_valid_outline(&p) {
            let msg = "the lot's outline crosses itself, repeats a corner or has no area".to_string();
            return Err(match at {
                Some(at) => self.fail_at(at, msg),
                None => ExpressError::Eval(format!("the footprint: {msg}")).into(),
            });
        }
        let reversed = area2(&p) < 0.0;
        if reversed {
            p.reverse();
        }
        let (lo, hi) = bbox(&p).unwrap_or_default();
        let (c, size) = ((lo + hi) * 0.5, hi - lo);
        let unit: Vec<DVec2> = p.iter().map(|q| (*q - c) / size).collect();
        // The turned axes in the scope: x′ = (cos a, −sin a) and
        // y′ = (sin a, cos a) in `(x, −z)`, i.e. (cos a, 0, sin a) and
        // (sin a, 0, −cos a); the centre turned back likewise.
        // (Unturned, a = 0, these are x, −z and the centre itself.)
        let (sin, cos) = a.sin_cos();
        let back = DVec2::new(cos, -sin).rotate(c);
        let m = DMat3::from_cols(DVec3::new(cos, 0.0, sin), DVec3::new(sin, 0.0, -cos), DVec3::Y);
        let centre = DVec3::new(back.x, 0.0, -back.y);
        self.cur.frame *= DAffine3::from_mat3_translation(m, centre);
        self.cur.size = DVec3::new(size.x, size.y, 0.0);
        self.cur.geom = self.add_geom(GeomKind::Polygon, &unit)?;
        self.st.geoms[self.cur.geom as usize].reversed = reversed;
        Ok(())
    }

    /// `extrude(h)`: the prism over the polygon, `h` along its +z; the
    /// scope becomes the mass's box, its +y along the extrusion.
    pub(super) fn extrude(&mut self, rule: &'g RuleCode, e: u32) -> Result<(), Stop> {
        let at = rule.exprs[e as usize].span;
        let (g, h) = self.polygon_height(rule, e, at, "extrude", "an extrusion height")?;
        // (x, y) of the polygon → (x, z) of the footprint; a zero height
        // gives an empty mass.
        let foot: Vec<DVec2> =
            if h > 0.0 { self.points(g).iter().map(|q| DVec2::new(q.x, -q.y)).collect() } else { Vec::new() };
        let m = DMat3::from_cols(DVec3::X, DVec3::Z, DVec3::NEG_Y);
        self.cur.frame *= DAffine3::from_mat3_translation(m, DVec3::new(0.0, 0.0, 0.5 * h));
        self.cur.size = DVec3::new(self.cur.size.x, h, self.cur.size.y);
        self.cur.geom = self.add_geom(GeomKind::Mass, &foot)?;
        Ok(())
    }

    /// Counts one emission against the limit and checks the placement.
    pub(super) fn count_emission(&mut self) -> Result<Affine3A, Stop> {
        if self.emitted >= self.limits.max_primitives {
            return Err(self.mode.limit(LimitKind::Primitives, &self.limits));
        }
        self.emitted += 1;
        let t = self.cur.transform();
        if !t.is_finite() {
            return Err(self.placement_overflow());
        }
        if self.g.occlusion {
            self.st.placed.push(super::occlusion::Placed::of(&self.cur, self.top.gene));
        }
        Ok(t)
    }

    /// `shape;`: a box scope emits its box, a polygon scope its polygon, a
    /// mass its closed prism (a box when the footprint fills the scope).
    /// Everything made on the scope after it lies on what it emitted.
    pub(super) fn shape(&mut self, rule: &'g RuleCode) -> Result<(), Stop> {
        self.emit_shape(rule)?;
        self.cur.add_layer();
        Ok(())
    }

    /// The emission of [`Self::shape`]; a polygon on emitted surfaces is
    /// lifted off them along its normal.
    fn emit_shape(&mut self, rule: &'g RuleCode) -> Result<(), Stop> {
        let Some(g) = self.geom_of(self.cur.geom) else {
            return self.emit(rule, Prim::Box);
        };
        if g.len < 3 {
            return Ok(());
        }
        match g.kind {
            GeomKind::Polygon => {
                let (f, s) = (self.cur.frame, self.cur.size);
                let lift = f.transform_vector3(DVec3::Z).normalize_or_zero() * (LIFT * f64::from(self.cur.layer()));
                let pts: Vec<glam::Vec3> = self
                    .points(g)
                    .iter()
                    .map(|q| (f.transform_point3(DVec3::new(q.x * s.x, q.y * s.y, 0.0)) + lift).as_vec3())
                    .collect();
                self.count_emission()?;
                if !pts.iter().all(|p| p.is_finite()) {
                    return Err(self.placement_overflow());
                }
                self.mode.emit_polygon(self.g, pts, self.cur.tag());
            }
            GeomKind::Mass => {
                if is_unit_square(self.points(g)) {
                    return self.emit(rule, Prim::Box);
                }
                let mesh = geom::prism_mesh(self.points(g));
                let t = self.count_emission()?;
                self.mode.emit_mesh(self.g, t, mesh, self.cur.tag());
            }
        }
        Ok(())
    }

    /// `roof_*(angle, overhang, …)` on a polygon scope: a closed roof solid
    /// on the polygon, rising along its +z (see [`Op::Roof`] for the named
    /// arguments). Edge `i` of the scope's polygon runs from its corner `i`
    /// to `i + 1`; with `gables` the gable walls in the polygon's edges are
    /// emitted apart, with that tag.
    pub(super) fn roof(&mut self, rule: &'g RuleCode, op: Op) -> Result<(), Stop> {
        let Op::Roof { kind, ridge, ends, faces, args, n, span, gables } = op else { return Ok(()) };
        let kinds = [RoofKind::Gable, RoofKind::Hip, RoofKind::Pyramid, RoofKind::Shed, RoofKind::Ridge];
        let kind = kinds[kind as usize % kinds.len()];
        let angle = self.num(rule, args, "a roof angle")?;
        let overhang = self.num(rule, args + 1, "a roof overhang")?;
        let at = rule.spans[span as usize];
        let g = match self.geom_of(self.cur.geom) {
            Some(g) if g.kind == GeomKind::Polygon => g,
            _ => {
                return Err(self.fail_at(
                    at,
                    format!(
                        "`{}` needs a polygon scope: a `lot`, or a face from `comp(f)` (e.g. `comp(f) {{ top: {}(30) }}`)",
                        kind.name(),
                        kind.name()
                    ),
                ));
            }
        };
        let (mesh, walls) = if ridge == 0 && !ends && n == 0 && gables == u32::MAX && !faces {
            let mesh =
                geom::roof_mesh(&self.absolute_foot(g), kind, angle, overhang).map_err(|m| self.fail_at(at, m))?;
            (mesh, Mesh::default())
        } else {
            self.laid_roof(rule, op, g, kind, [angle, overhang])?
        };
        if mesh.triangles.is_empty() {
            self.note_at(at, &format!("`{}`: the polygon has no area here, so there is no roof", kind.name()));
        }
        if faces {
            // The walls flush with the façade apart from the rest of the
            // roof, so a gable face ends at the wall's corners.
            self.st.solid = Some((mesh, walls));
            return Ok(());
        }
        self.emit_on_polygon(mesh)?;
        if !walls.triangles.is_empty() {
            let tag = self.cur.tag();
            self.cur.set_tag(gables);
            let r = self.emit_on_polygon(walls);
            self.cur.set_tag(tag);
            r?;
        }
        Ok(())
    }

    /// The roof of [`Self::roof`] laid as its named arguments say (ridge
    /// edge, overhang per edge, gable ends, gable walls apart), and the
    /// gable walls; both empty on a polygon of fewer than 3 corners.
    fn laid_roof(
        &mut self,
        rule: &'g RuleCode,
        op: Op,
        g: Geom,
        kind: RoofKind,
        [angle, overhang]: [f64; 2],
    ) -> Result<(Mesh, Mesh), Stop> {
        let Op::Roof { ridge, ends, args, n, span, gables, .. } = op else { return Ok(Default::default()) };
        let at = rule.spans[span as usize];
        // The polygon counter-clockwise, and where each of the scope's
        // edges went.
        let s = self.cur.size;
        let mut foot: Vec<DVec2> = self.points(g).iter().map(|q| DVec2::new(q.x * s.x, q.y * s.y)).collect();
        let m = foot.len();
        if m < 3 {
            return Ok(Default::default());
        }
        let reversed = area2(&foot) < 0.0;
        if reversed {
            foot.reverse();
        }
        // Written edge → stored edge → edge of the counter-clockwise foot.
        let edge = |i: usize| {
            let i = g.stored_edge(i);
            if reversed { (2 * m - 2 - i) % m } else { i }
        };
        let mut per_edge = vec![overhang; m];
        if n > 0 {
            if n as usize != m {
                return Err(self.fail_at(
                    at,
                    format!("`{}`: the overhang list has {n} values, the polygon {m} edges", kind.name()),
                ));
            }
            for i in 0..m {
                per_edge[edge(i)] = self.num(rule, args + 4 + i as u32, "a roof overhang")?;
            }
        }
        let ridge_edge = match ridge {
            0 => None,
            crate::program::RIDGE_INDEX => {
                let v = self.num(rule, args + 2, "a ridge edge index")?;
                if v.fract() != 0.0 || v < 0.0 || v >= m as f64 {
                    return Err(self.fail_at(
                        at,
                        format!(
                            "`{}`: the ridge edge index must be a whole number from 0 to {}, found {v}",
                            kind.name(),
                            m - 1
                        ),
                    ));
                }
                Some(edge(v as usize))
            }
            side => (0..m).map(edge).find(|&j| super::pieces::edge_class(foot[(j + 1) % m] - foot[j]) == side),
        };
        if ridge != 0 && ridge_edge.is_none() {
            let name = ["front", "back", "left", "right"][(ridge.trailing_zeros() as usize).min(3)];
            return Err(self.fail_at(at, format!("`{}`: the polygon has no `{name}` edge for the ridge", kind.name())));
        }
        let ends = if ends { Some(self.num(rule, args + 3, "a gable-end overhang")?) } else { None };
        let Op::Roof { faces, .. } = op else { return Ok(Default::default()) };
        let apart = gables != u32::MAX || faces;
        let opts = geom::RoofOpts { overhang: per_edge, ridge: ridge_edge, ends, gables: apart };
        geom::roof_meshes(&foot, kind, angle, &opts).map_err(|m| self.fail_at(at, m))
    }

    /// `taper(h)` on a polygon scope: the pyramid over the polygon with its
    /// apex `h` above the polygon's centroid (CGA's `taper`), a closed
    /// solid emitted like a roof; `taper(h, s)` the frustum whose top is
    /// the polygon scaled by `s` about its centroid, `h` above it. On a concave polygon whose centroid does
    /// not see every edge the sides cross, as in CGA.
    pub(super) fn taper(&mut self, rule: &'g RuleCode, e: u32, span: u32, faces: bool) -> Result<(), Stop> {
        let at = rule.spans[span as usize];
        let (g, h) = self.polygon_height(rule, e, at, "taper", "a taper height")?;
        let top = self.num(rule, e + 1, "a taper's top scale")?;
        if !(0.0..=1.0).contains(&top) {
            return Err(self.fail_at(at, format!("a taper's top scale must lie from 0 to 1, found {top}")));
        }
        let mesh = if top == 0.0 {
            geom::pyramid_mesh(&self.absolute_foot(g), h)
        } else {
            geom::frustum_mesh(&self.absolute_foot(g), h, top)
        };
        if faces {
            self.st.solid = Some((mesh, Mesh::default()));
            return Ok(());
        }
        self.emit_on_polygon(mesh)
    }

    /// The polygon of a polygon scope and the height (≥ 0) expression `e`
    /// gives `op` there.
    fn polygon_height(
        &mut self,
        rule: &'g RuleCode,
        e: u32,
        at: genform_core::Span,
        op: &str,
        what: &str,
    ) -> Result<(Geom, f64), Stop> {
        let h = self.num(rule, e, what)?;
        let g = match self.geom_of(self.cur.geom) {
            Some(g) if g.kind == GeomKind::Polygon => g,
            _ => {
                return Err(
                    self.fail_at(at, format!("`{op}` needs a polygon scope: a `lot`, or a face from `comp(f)`"))
                );
            }
        };
        if h < 0.0 {
            return Err(self.fail_at(at, format!("{what} must be ≥ 0, found {h}")));
        }
        Ok((g, h))
    }

    /// The scope's polygon in absolute units, counter-clockwise.
    pub(super) fn absolute_foot(&self, g: Geom) -> Vec<DVec2> {
        let s = self.cur.size;
        let mut foot: Vec<DVec2> = self.points(g).iter().map(|q| DVec2::new(q.x * s.x, q.y * s.y)).collect();
        if area2(&foot) < 0.0 {
            foot.reverse();
        }
        foot
    }

    /// Emits a solid built on the scope's polygon (in the scope's frame,
    /// absolute units); nothing for an empty one.
    fn emit_on_polygon(&mut self, mesh: Mesh) -> Result<(), Stop> {
        if mesh.triangles.is_empty() {
            return Ok(());
        }
        self.count_emission()?;
        let t = self.cur.frame_transform();
        if !t.is_finite() {
            return Err(self.placement_overflow());
        }
        self.mode.emit_mesh(self.g, t, mesh, self.cur.tag());
        Ok(())
    }

    /// Cuts the scope's geometry to the piece just entered: the slab
    /// `centre ± len/2` along `axis` of a parent `parent` long. The piece's
    /// scope stays the whole slab; its geometry may come out empty.
    pub(super) fn cut_geom(&mut self, axis: u8, centre: f64, len: f64, parent: f64) -> Result<(), Stop> {
        let Some(g) = self.geom_of(self.cur.geom) else { return Ok(()) };
        let k = match (g.kind, axis) {
            (GeomKind::Polygon, 0) | (GeomKind::Mass, 0) => 0,
            (GeomKind::Polygon, 1) | (GeomKind::Mass, 2) => 1,
            // Along a polygon's normal or a mass's height: nothing to cut.
            _ => return Ok(()),
        };
        let pts: Vec<DVec2> = if len == 0.0 || parent == 0.0 || g.len < 3 {
            Vec::new()
        } else {
            let (a, b) = ((centre - 0.5 * len) / parent, (centre + 0.5 * len) / parent);
            let mut piece = geom::clip_slab(self.points(g), k, a.min(b), a.max(b));
            for q in &mut piece {
                q[k] = (q[k] * parent - centre) / len;
            }
            if piece.len() < 3 { Vec::new() } else { piece }
        };
        self.cur.geom = self.add_geom(g.kind, &pts)?;
        Ok(())
    }

    /// A component split (`comp(f)`, `comp(e)`, `offset`, `setback`,
    /// `shapeL/U/O`): lists its pieces with the arm each goes to (the first
    /// arm whose selectors take the piece's class) and opens the loop.
    pub(super) fn comp_begin(
        &mut self,
        rule: &'g RuleCode,
        kind: u8,
        args: u32,
        first: u32,
        n: u32,
        span: u32,
    ) -> Result<(), Stop> {
        let masks = &rule.comps[first as usize..(first + n) as usize];
        let kind = CompKind::ALL[kind as usize % CompKind::ALL.len()];
        let pieces = match kind {
            CompKind::Faces => self.faces(rule, span)?,
            CompKind::Solid => self.solid_pieces(),
            _ => {
                // An index selector may take a piece of any class.
                let by_index = masks.iter().any(|m| m.1 != 0);
                let taken = masks.iter().fold(if by_index { u8::MAX } else { 0 }, |a, m| a | m.0);
                self.pieces(rule, kind, args, taken, span)?
            }
        };
        // The first arm that names the piece's index or its class.
        let arm_of = |i: usize, class: u8| {
            let named = |m: &(u8, u64)| (i < 64 && m.1 & (1u64 << i) != 0) || m.0 & class != 0;
            masks.iter().position(named).map(|a| a as u32)
        };
        let start = self.st.faces.len();
        let square = if pieces.iter().any(|f| matches!(f.2, PieceGeom::Square)) {
            self.add_geom(GeomKind::Polygon, &SQUARE)?
        } else {
            NO_GEOM
        };
        for (i, (class, mut scope, pts)) in pieces.into_iter().enumerate() {
            let Some(arm) = arm_of(i, class) else { continue };
            scope.geom = match pts {
                PieceGeom::Polygon(p) => self.add_geom(GeomKind::Polygon, &p)?,
                PieceGeom::Square => square,
                PieceGeom::Line => NO_GEOM,
            };
            self.st.faces.push((arm, scope));
        }
        let base = self.top.env;
        let (index, count) = (self.st.env[base + ENV_INDEX], self.st.env[base + ENV_COUNT]);
        let nf = (self.st.faces.len() - start) as u32;
        self.st.loops.push(Loop::Comp { faces: start, n: nf, pos: 0, k: 0, index, count });
        Ok(())
    }

    /// `comp(f)`: the faces of the mass (a box scope counts as the mass of
    /// its box), each with its class and scope; a wall's polygon is the
    /// unit square (`None`), a cap's its footprint.
    fn faces(&mut self, rule: &'g RuleCode, span: u32) -> Result<Vec<Piece>, Stop> {
        let foot: Vec<DVec2> = match self.geom_of(self.cur.geom) {
            None => FOOT_SQUARE.to_vec(),
            Some(g) if g.kind == GeomKind::Mass => self.points(g).to_vec(),
            Some(_) => {
                return Err(self.fail_at(
                    rule.spans[span as usize],
                    "`comp(f)` needs a mass (after `extrude`) or a box scope, not a polygon".to_string(),
                ));
            }
        };
        let s = self.cur.size;
        let frame = self.cur.frame;
        let tagged = self.cur.tagged;
        let abs: Vec<DVec2> = foot.iter().map(|q| DVec2::new(q.x * s.x, q.y * s.z)).collect();
        let mut faces = Vec::new();
        if abs.len() >= 3 && s.y != 0.0 {
            for i in 0..abs.len() {
                let (a, b) = (abs[i], abs[(i + 1) % abs.len()]);
                let l = a.distance(b);
                if l == 0.0 {
                    continue;
                }
                let d = (b - a) / l;
                let nrm = DVec2::new(-d.y, d.x);
                let class = if nrm.y.abs() >= nrm.x.abs() {
                    if nrm.y > 0.0 { FACE_FRONT } else { FACE_BACK }
                } else if nrm.x > 0.0 {
                    FACE_RIGHT
                } else {
                    FACE_LEFT
                };
                let m = DMat3::from_cols(DVec3::new(d.x, 0.0, d.y), DVec3::Y, DVec3::new(nrm.x, 0.0, nrm.y));
                let mid = (a + b) * 0.5;
                let f = frame * DAffine3::from_mat3_translation(m, DVec3::new(mid.x, 0.0, mid.y));
                let scope = ScopeState { frame: f, size: DVec3::new(l, s.y, 0.0), tagged, geom: NO_GEOM };
                faces.push((class, scope, PieceGeom::Square));
            }
        }
        if abs.len() >= 3 {
            // Top: (x, −z), seen from above; bottom: (x, z) reversed.
            for (class, y, axes) in [
                (FACE_TOP, 0.5 * s.y, DMat3::from_cols(DVec3::X, DVec3::NEG_Z, DVec3::Y)),
                (FACE_BOTTOM, -0.5 * s.y, DMat3::from_cols(DVec3::X, DVec3::Z, DVec3::NEG_Y)),
            ] {
                let mut p: Vec<DVec2> = if class == FACE_TOP {
                    abs.iter().map(|q| DVec2::new(q.x, -q.y)).collect()
                } else {
                    abs.iter().rev().copied().collect()
                };
                let Some((lo, hi)) = bbox(&p) else { continue };
                let (c, size) = ((lo + hi) * 0.5, hi - lo);
                if size.x == 0.0 || size.y == 0.0 {
                    continue;
                }
                for q in &mut p {
                    *q = (*q - c) / size;
                }
                // The face centre in the mass's frame.
                let centre = axes * DVec3::new(c.x, c.y, 0.0) + DVec3::new(0.0, y, 0.0);
                let f = frame * DAffine3::from_mat3_translation(axes, centre);
                let scope = ScopeState { frame: f, size: DVec3::new(size.x, size.y, 0.0), tagged, geom: NO_GEOM };
                faces.push((class, scope, PieceGeom::Polygon(p)));
            }
        }
        Ok(faces)
    }

    /// The faces of the solid the roof or taper before the split built (in
    /// the polygon scope's frame, absolute units), each a polygon scope in
    /// its own plane: x along its eaves or base, y up it, z out of the
    /// solid (see [`crate::solid_faces`]). Classes: a slope by the side it
    /// faces (as `comp(e)` names the edges), a level top `top`, a vertical
    /// face in the polygon's edges (a gable wall flush with the façade)
    /// `side` ([`PIECE_REST`]), any other vertical face (a gable end out
    /// beyond the wall, the end of an overhanging eave) `verge`
    /// ([`PIECE_SHAPE`]), a face looking down `bottom`.
    fn solid_pieces(&mut self) -> Vec<Piece> {
        let Some((roof, walls)) = self.st.solid.take() else { return Vec::new() };
        let (frame, tagged) = (self.cur.frame, self.cur.tagged);
        let mut out = Vec::new();
        let walls = crate::solid_faces::planar_faces(&walls).into_iter().map(|f| (f, true));
        for (f, flush) in crate::solid_faces::planar_faces(&roof).into_iter().map(|f| (f, false)).chain(walls) {
            let n = f.normal;
            let (x, y) = crate::solid_faces::face_axes(n);
            let flat: Vec<DVec2> = f.outline.iter().map(|p| DVec2::new(p.dot(x), p.dot(y))).collect();
            let Some((lo, hi)) = bbox(&flat) else { continue };
            let (c, size) = ((lo + hi) * 0.5, hi - lo);
            if size.x <= 0.0 || size.y <= 0.0 {
                continue;
            }
            let class = if n.z < -1e-9 {
                FACE_BOTTOM
            } else if n.z.abs() <= 1e-9 {
                if flush { PIECE_REST } else { PIECE_SHAPE }
            } else if n.z >= 1.0 - 1e-12 {
                FACE_TOP
            } else {
                super::pieces::edge_class(DVec2::new(x.x, x.y))
            };
            let centre = x * c.x + y * c.y + n * n.dot(f.outline[0]);
            let f3 = frame * DAffine3::from_mat3_translation(DMat3::from_cols(x, y, n), centre);
            let scope = ScopeState { frame: f3, size: DVec3::new(size.x, size.y, 0.0), tagged, geom: NO_GEOM };
            out.push((class, scope, PieceGeom::Polygon(flat.iter().map(|q| (*q - c) / size).collect())));
        }
        out
    }

    /// The next face of `arm` at or after `from`.
    fn next_face(&self, faces: usize, n: u32, arm: u32, from: u32) -> Option<u32> {
        (from..n).find(|&j| self.st.faces[faces + j as usize].0 == arm)
    }

    fn enter_face(&mut self, faces: usize, n: u32, arm: u32, j: u32, k: u32) {
        let count = (0..n).filter(|&i| self.st.faces[faces + i as usize].0 == arm).count();
        if let Some(Loop::Comp { pos, k: kk, .. }) = self.st.loops.last_mut() {
            (*pos, *kk) = (j, k);
        }
        self.st.scopes.push(self.cur);
        self.cur = self.st.faces[faces + j as usize].1;
        let base = self.top.env;
        self.st.env[base + ENV_INDEX] = k as f64;
        self.st.env[base + ENV_COUNT] = count as f64;
    }

    /// Enters the first face of `arm`, or jumps past the arm.
    pub(super) fn comp_arm(&mut self, arm: u32, end: u32) {
        let Some(&Loop::Comp { faces, n, .. }) = self.st.loops.last() else { return };
        match self.next_face(faces, n, arm, 0) {
            Some(j) => self.enter_face(faces, n, arm, j, 0),
            None => self.top.pc = end as usize,
        }
    }

    /// Leaves the face; enters the next one of `arm` or goes on.
    pub(super) fn comp_next(&mut self, arm: u32, body: u32) {
        if let Some(s) = self.st.scopes.pop() {
            self.cur = s;
        }
        let Some(&Loop::Comp { faces, n, pos, k, .. }) = self.st.loops.last() else { return };
        if let Some(j) = self.next_face(faces, n, arm, pos + 1) {
            self.enter_face(faces, n, arm, j, k + 1);
            self.top.pc = body as usize;
        }
    }

    /// Closes the loop.
    pub(super) fn comp_end(&mut self) {
        if let Some(Loop::Comp { faces, index, count, .. }) = self.st.loops.pop() {
            self.st.faces.truncate(faces);
            self.restore_index(index, count);
        }
    }
}
