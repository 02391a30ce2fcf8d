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
            limits: GrowthLimits::default(),
        }
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
