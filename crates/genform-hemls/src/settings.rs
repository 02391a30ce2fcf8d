//! Growth settings: Genr8's `genr8` command flags, with their documented
//! defaults, and the limits that stop runaway growth.

use glam::DVec3;

/// How a run grows: the `genr8` flags (`-n -s -sx -sy -sz -sl -sp -fc -fp
/// -ba -bl`) and genform's element limits.
#[derive(Clone, Debug, PartialEq)]
pub struct Settings {
    /// Derivation steps (`-n`, default 4).
    pub steps: u32,
    /// Scale per step along x, y, z (`-s` default 1.5, or `-sx -sy -sz`).
    pub scale: DVec3,
    /// Side of the seed polygon (`-sl`, default 1).
    pub start_length: f64,
    /// Centre of the seed (`-sp`, default origin).
    pub start_position: DVec3,
    /// Keep the centre at the start position (`-fc`).
    pub fixed_center: bool,
    /// Vertices of the outer boundary never move (`-fp`).
    pub fixed_perimeter: bool,
    /// Join cone in degrees (`-ba`, default 30) unless the grammar gives
    /// `BranchAngle`.
    pub branch_angle: f64,
    /// Largest join distance as a multiple of the characteristic length
    /// `start_length · s^k`; negative means no limit (`-bl`, default −1).
    pub branch_length: f64,
    /// Which join criteria apply beyond region, type, orientation and
    /// distance (`join` in the environment file).
    pub join: JoinTest,
    /// Element limits.
    pub limits: GrowthLimits,
}

impl Default for Settings {
    fn default() -> Self {
        Settings {
            steps: 4,
            scale: DVec3::splat(1.5),
            start_length: 1.0,
            start_position: DVec3::ZERO,
            fixed_center: false,
            fixed_perimeter: false,
            branch_angle: 30.0,
            branch_length: -1.0,
            join: JoinTest::default(),
            limits: GrowthLimits::default(),
        }
    }
}

/// How the join criteria on orientation and position are read (`join` in
/// the environment file). Every reading also requires the same region and
/// type and the join distance.
///
/// The paper says "the scalar product of their orientation must be less
/// than a given tolerance. The tolerance is given as an angle by the
/// BranchAngle keyword"; the help files call the angle "the cone used when
/// trying to match branches". genform first read this as anti-parallel
/// within β plus a cone test (`Cone`). Measured on 60 random `genr8.bnf`
/// rule sets grown 4 steps (docs/hemls.md), that lets 19 reach 4 faces;
/// the literal reading (`Scalar`) lets 35 do so, and Genr8's four
/// predefined grammars grow the same surfaces under every reading, so the
/// literal one is the default: joining is what gives evolved surfaces
/// internal structure.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum JoinTest {
    /// Anti-parallel within β (`d_p·d_q ≤ −cos β`) and each base in front
    /// of the other branch (`(q − p)·d_p > 0` and `(p − q)·d_q > 0`): the
    /// branches point towards each other but may be offset sideways.
    Facing,
    /// Anti-parallel within β and each base inside the other's cone of
    /// half-angle β (genform's first reading; the strictest).
    Cone,
    /// Anti-parallel within β, no test on the bases' positions.
    Paper,
    /// The paper's sentence read literally ("the scalar product of their
    /// orientation must be less than a given tolerance", the tolerance
    /// given as the angle β): `d_p·d_q < cos β`, the directions more than
    /// β apart, and each base in front of the other branch. With β = 90°
    /// (the paper's tile grammars) it equals `Facing`.
    #[default]
    Scalar,
}

impl JoinTest {
    /// Every test, in the order the environment file names them.
    pub const ALL: [JoinTest; 4] = [JoinTest::Facing, JoinTest::Cone, JoinTest::Paper, JoinTest::Scalar];

    /// The environment file's name for it (`join = "facing"`).
    pub fn name(self) -> &'static str {
        match self {
            JoinTest::Facing => "facing",
            JoinTest::Cone => "cone",
            JoinTest::Paper => "paper",
            JoinTest::Scalar => "scalar",
        }
    }

    /// Parses [`JoinTest::name`].
    pub fn from_name(name: &str) -> Option<JoinTest> {
        JoinTest::ALL.into_iter().find(|t| t.name() == name)
    }
}

/// Most elements a surface may reach; growth past one stops with
/// [`crate::GrowError::Limit`] naming it.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct GrowthLimits {
    /// Most vertices (default 2,000,000).
    pub max_vertices: usize,
    /// Most edges (default 4,000,000).
    pub max_edges: usize,
    /// Most bounded faces (default 2,000,000).
    pub max_faces: usize,
}

impl Default for GrowthLimits {
    fn default() -> Self {
        GrowthLimits { max_vertices: 2_000_000, max_edges: 4_000_000, max_faces: 2_000_000 }
    }
}
