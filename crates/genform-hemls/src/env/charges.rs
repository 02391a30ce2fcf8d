//! Point charges (attractors, repellers) and gravity: the displacement part
//! of the environment.

use glam::DVec3;

/// Whether a charge pulls or pushes.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum ChargeKind {
    /// Pulls vertices towards its position.
    Attractor,
    /// Pushes vertices away from its position.
    Repeller,
}

impl ChargeKind {
    /// `attractor` or `repeller` (the env-file table name and guide tag).
    pub fn name(self) -> &'static str {
        match self {
            ChargeKind::Attractor => "attractor",
            ChargeKind::Repeller => "repeller",
        }
    }
}

/// An attractor or repeller: a vertex at distance `d` is displaced by
/// `strength / d^exponent` each step, towards (attractor) or away from
/// (repeller) `position`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Charge {
    /// Attractor or repeller.
    pub kind: ChargeKind,
    /// Where the charge sits.
    pub position: DVec3,
    /// The constant `c` of the law (default 1; not negative).
    pub strength: f64,
    /// The exponent `e` of the law (default 2, inverse square).
    pub exponent: f64,
}

impl Charge {
    /// Default strength `c`.
    pub const DEFAULT_STRENGTH: f64 = 1.0;
    /// Default exponent `e` (the paper's inverse square).
    pub const DEFAULT_EXPONENT: f64 = 2.0;

    /// An attractor at `position` with `c = 1`, `e = 2`.
    pub fn attractor(position: DVec3) -> Self {
        Charge {
            kind: ChargeKind::Attractor,
            position,
            strength: Self::DEFAULT_STRENGTH,
            exponent: Self::DEFAULT_EXPONENT,
        }
    }

    /// A repeller at `position` with `c = 1`, `e = 2`.
    pub fn repeller(position: DVec3) -> Self {
        Charge { kind: ChargeKind::Repeller, ..Self::attractor(position) }
    }

    /// The same charge with strength `c`.
    pub fn with_strength(mut self, strength: f64) -> Self {
        self.strength = strength;
        self
    }

    /// The same charge with exponent `e`.
    pub fn with_exponent(mut self, exponent: f64) -> Self {
        self.exponent = exponent;
        self
    }

    /// The displacement of a vertex at `p` in one step.
    ///
    /// The law is singular at the charge, so the distance is clamped below
    /// at `min_distance` before the power is taken: the magnitude is at most
    /// `c / min_distance^e`. Two decisions keep it well behaved:
    /// - an attractor never moves a vertex past (or onto the far side of)
    ///   its own position: the magnitude is capped at the distance `d`;
    /// - a vertex exactly on the charge (d = 0, direction undefined) is
    ///   not displaced by it.
    pub fn displacement(&self, p: DVec3, min_distance: f64) -> DVec3 {
        let to_charge = self.position - p;
        let d = to_charge.length();
        if d == 0.0 || !d.is_finite() {
            return DVec3::ZERO;
        }
        let magnitude = self.strength / power(d.max(min_distance), self.exponent);
        match self.kind {
            ChargeKind::Attractor => to_charge * (magnitude.min(d) / d),
            ChargeKind::Repeller => to_charge * (-magnitude / d),
        }
    }
}

/// `r^e`. The usual exponents (1, 2, 3) are multiplied out: `powf` is
/// the largest single cost of a growth step in an environment with charges.
fn power(r: f64, e: f64) -> f64 {
    if e == 2.0 {
        r * r
    } else if e == 1.0 {
        r
    } else if e == 3.0 {
        r * r * r
    } else {
        r.powf(e)
    }
}

/// A principal axis.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum Axis {
    /// The x axis.
    X,
    /// The y axis.
    Y,
    /// The z axis.
    Z,
}

impl Axis {
    /// The unit vector along the axis.
    pub fn unit(self) -> DVec3 {
        match self {
            Axis::X => DVec3::X,
            Axis::Y => DVec3::Y,
            Axis::Z => DVec3::Z,
        }
    }

    /// `x`, `y` or `z`.
    pub fn name(self) -> &'static str {
        match self {
            Axis::X => "x",
            Axis::Y => "y",
            Axis::Z => "z",
        }
    }
}

/// Uniform gravity (`-g axis magnitude`): every vertex moves by `magnitude`
/// along `axis` each step; the sign of the magnitude gives the direction
/// (`z -0.1` moves down by 0.1).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Gravity {
    /// Which axis.
    pub axis: Axis,
    /// Signed displacement per step along the axis.
    pub magnitude: f64,
}

impl Gravity {
    /// Gravity of `magnitude` along `axis`.
    pub fn new(axis: Axis, magnitude: f64) -> Self {
        Gravity { axis, magnitude }
    }

    /// The displacement every vertex receives each step.
    pub fn vector(&self) -> DVec3 {
        self.axis.unit() * self.magnitude
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn inverse_square_law_at_distance_two() {
        let p = DVec3::new(1.0, 2.0, 3.0);
        let q = p + DVec3::new(0.0, 2.0, 0.0);
        let a = Charge::attractor(q).displacement(p, 1e-3);
        assert!((a - DVec3::new(0.0, 0.25, 0.0)).length() < 1e-15, "{a}");
        let r = Charge::repeller(q).displacement(p, 1e-3);
        assert!((r - DVec3::new(0.0, -0.25, 0.0)).length() < 1e-15, "{r}");
        let cubic = Charge::attractor(q).with_strength(4.0).with_exponent(3.0).displacement(p, 1e-3);
        assert!((cubic.y - 0.5).abs() < 1e-15, "{cubic}");
    }

    #[test]
    fn attractor_never_overshoots_and_clamp_bounds_repellers() {
        let q = DVec3::new(0.0, 0.0, 1.0);
        for d in [1e-12, 1e-6, 0.01, 0.5, 0.999] {
            let p = q - DVec3::Z * d;
            let m = Charge::attractor(q).displacement(p, 1e-3);
            assert!(m.z > 0.0 && p.z + m.z <= q.z, "d {d}: {m}");
            let r = Charge::repeller(q).displacement(p, 1e-3);
            assert!(r.is_finite() && r.z < 0.0 && -r.z <= 1e6 * (1.0 + 1e-12), "d {d}: {r}");
        }
        assert_eq!(Charge::repeller(q).displacement(q, 1e-3), DVec3::ZERO);
        assert_eq!(Charge::attractor(q).displacement(q, 1e-3), DVec3::ZERO);
    }

    #[test]
    fn multiplied_out_powers_match_powf() {
        for r in [1e-3, 0.37, 1.0, 2.0, 7.5, 1e6] {
            for e in [1.0, 2.0, 3.0, 0.5, 2.5, 4.0] {
                let want = f64::powf(r, e);
                assert!((power(r, e) - want).abs() <= 4.0 * f64::EPSILON * want, "{r}^{e}");
            }
        }
    }

    #[test]
    fn gravity_sign_gives_direction() {
        assert_eq!(Gravity::new(Axis::Z, -0.1).vector(), DVec3::new(0.0, 0.0, -0.1));
        assert_eq!(Gravity::new(Axis::X, 2.0).vector(), DVec3::new(2.0, 0.0, 0.0));
    }
}
