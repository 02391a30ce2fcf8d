//! Turtle strokes stored flat: every polyline's points in one array.
//!
//! A plant drawing has tens of thousands of short polylines (a new one at
//! every branch); one `Vec` per line made a million-segment drawing spend
//! about a third of its time allocating, growing and freeing point lists.

use super::mesh::TagId;
use glam::Vec3;

/// One polyline, borrowed from [`Polylines`]: an open line through points.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Polyline<'a> {
    /// The points, in order.
    pub points: &'a [Vec3],
    /// Stroke width in scene units.
    pub width: f32,
    /// Semantic tag.
    pub tag: TagId,
}

/// Where a line's points end in the shared array, and its style.
#[derive(Clone, Copy, Debug, PartialEq)]
struct Line {
    end: usize,
    width: f32,
    tag: TagId,
}

/// The polylines of a scene, in emission order.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Polylines {
    points: Vec<Vec3>,
    lines: Vec<Line>,
}

impl Polylines {
    /// Number of polylines.
    pub fn len(&self) -> usize {
        self.lines.len()
    }

    /// Whether there is no polyline.
    pub fn is_empty(&self) -> bool {
        self.lines.is_empty()
    }

    /// Removes every polyline, keeping the allocations.
    pub fn clear(&mut self) {
        self.points.clear();
        self.lines.clear();
    }

    /// Appends a polyline (its points are copied).
    #[inline]
    pub fn push(&mut self, line: Polyline<'_>) {
        self.points.extend_from_slice(line.points);
        self.lines.push(Line { end: self.points.len(), width: line.width, tag: line.tag });
    }

    /// Appends a point to the last polyline; does nothing when there is none.
    #[inline]
    pub fn extend_last(&mut self, p: Vec3) {
        if let Some(last) = self.lines.last_mut() {
            self.points.push(p);
            last.end = self.points.len();
        }
    }

    /// Polyline `k`.
    #[inline]
    pub fn get(&self, k: usize) -> Option<Polyline<'_>> {
        let line = self.lines.get(k)?;
        let start = if k == 0 { 0 } else { self.lines[k - 1].end };
        Some(Polyline { points: &self.points[start..line.end], width: line.width, tag: line.tag })
    }

    /// The last polyline.
    #[inline]
    pub fn last(&self) -> Option<Polyline<'_>> {
        self.get(self.lines.len().checked_sub(1)?)
    }

    /// The points of polyline `k`, to edit in place.
    pub fn points_mut(&mut self, k: usize) -> &mut [Vec3] {
        let start = if k == 0 { 0 } else { self.lines[k - 1].end };
        &mut self.points[start..self.lines[k].end]
    }

    /// Every point of every polyline, line after line.
    pub fn points(&self) -> &[Vec3] {
        &self.points
    }

    /// Number of segments (points minus one per line, over all lines).
    pub fn segments(&self) -> usize {
        self.iter().map(|l| l.points.len().saturating_sub(1)).sum()
    }

    /// The polylines in order.
    pub fn iter(&self) -> Iter<'_> {
        Iter { points: &self.points, lines: self.lines.iter(), start: 0 }
    }
}

impl<'a> IntoIterator for &'a Polylines {
    type Item = Polyline<'a>;
    type IntoIter = Iter<'a>;
    fn into_iter(self) -> Iter<'a> {
        self.iter()
    }
}

/// The polylines of a [`Polylines`], in order.
#[derive(Clone, Debug)]
pub struct Iter<'a> {
    points: &'a [Vec3],
    lines: std::slice::Iter<'a, Line>,
    start: usize,
}

impl<'a> Iterator for Iter<'a> {
    type Item = Polyline<'a>;

    #[inline]
    fn next(&mut self) -> Option<Polyline<'a>> {
        let line = self.lines.next()?;
        let points = &self.points[self.start..line.end];
        self.start = line.end;
        Some(Polyline { points, width: line.width, tag: line.tag })
    }

    fn size_hint(&self) -> (usize, Option<usize>) {
        self.lines.size_hint()
    }
}

impl ExactSizeIterator for Iter<'_> {}

#[cfg(test)]
mod tests {
    use super::*;

    fn pts(xs: &[f32]) -> Vec<Vec3> {
        xs.iter().map(|&x| Vec3::new(x, 0.0, 0.0)).collect()
    }

    #[test]
    fn lines_keep_their_own_points_and_style() {
        let mut ls = Polylines::default();
        assert!(ls.last().is_none());
        ls.extend_last(Vec3::ONE);
        assert!(ls.points().is_empty(), "no line to extend");
        ls.push(Polyline { points: &pts(&[0.0, 1.0]), width: 0.5, tag: 1 });
        ls.push(Polyline { points: &pts(&[5.0]), width: 2.0, tag: 3 });
        ls.extend_last(Vec3::new(6.0, 0.0, 0.0));
        ls.push(Polyline { points: &[], width: 0.0, tag: 0 });
        assert_eq!(ls.len(), 3);
        let got: Vec<_> = ls.iter().map(|l| (l.points.to_vec(), l.width, l.tag)).collect();
        assert_eq!(got, [(pts(&[0.0, 1.0]), 0.5, 1), (pts(&[5.0, 6.0]), 2.0, 3), (vec![], 0.0, 0)]);
        assert_eq!(ls.get(1).unwrap().points, &pts(&[5.0, 6.0])[..]);
        assert_eq!(ls.last().unwrap().points.len(), 0);
        assert_eq!(ls.segments(), 2);
        ls.points_mut(1)[0].y = 7.0;
        assert_eq!(ls.points()[2], Vec3::new(5.0, 7.0, 0.0));
        assert_eq!(ls.iter().len(), 3);
        ls.clear();
        assert!(ls.is_empty() && ls.points().is_empty());
    }
}
