//! The scope: the oriented box that operations move, turn and resize.
//!
//! Kept in `f64` so long derivations do not drift; converted to `f32` only
//! when a primitive is placed. Every operation composes matrices exactly as
//! written here (no shortcuts for zero or unit components), so a scene is
//! bit-for-bit reproducible, signs of zeros included.

use glam::{Affine3A, DAffine3, DMat3, DVec3, Vec3A};

/// The scope: frame (rotation + position of the centre) and size.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) struct ScopeState {
    pub frame: DAffine3,
    pub size: DVec3,
    /// The tag (low 24 bits, [`ScopeState::tag`]) and the layer (high 8,
    /// [`ScopeState::layer`]) in one word: the scope is copied for every
    /// piece, and a separate byte made it 136 bytes instead of 128 (2–8 %
    /// on building derivations).
    pub tagged: u32,
    /// The scope's polygon or mass in the interpreter's geometry arena, or
    /// [`NO_GEOM`] for a plain box scope.
    pub geom: u32,
}

/// How many tags a grammar may have (they share a word with the layer).
pub(crate) const MAX_TAGS: usize = 1 << 24;

/// How far (model units, metres in buildings) a polygon emitted on an
/// emitted surface is lifted along its normal, per layer beneath it.
pub(crate) const LIFT: f64 = 0.005;

/// `ScopeState::geom` of a plain box scope.
pub(crate) const NO_GEOM: u32 = u32::MAX;

pub(crate) fn axis_vec(axis: u8) -> DVec3 {
    match axis {
        0 => DVec3::X,
        1 => DVec3::Y,
        _ => DVec3::Z,
    }
}

impl ScopeState {
    /// The unit scope at the origin (the axiom's scope).
    pub const UNIT: ScopeState = ScopeState { frame: DAffine3::IDENTITY, size: DVec3::ONE, tagged: 0, geom: NO_GEOM };

    /// The scope's tag.
    #[inline]
    pub fn tag(&self) -> u32 {
        self.tagged & 0x00FF_FFFF
    }

    /// Sets the tag, keeping the layer.
    #[inline]
    pub fn set_tag(&mut self, tag: u32) {
        self.tagged = (self.tagged & 0xFF00_0000) | (tag & 0x00FF_FFFF);
    }

    /// How many emitted surfaces lie under this scope: `shape` counts one
    /// up, and the scopes made after it (faces, pieces, splits) inherit
    /// the count, so a polygon emitted on a face of an emitted mass, or on
    /// an emitted polygon, is lifted off it ([`LIFT`] per layer) instead
    /// of z-fighting it.
    #[inline]
    pub fn layer(&self) -> u32 {
        self.tagged >> 24
    }

    /// Counts one more emitted surface under the scope (at most 255).
    #[inline]
    pub fn add_layer(&mut self) {
        if self.layer() < 255 {
            self.tagged += 1 << 24;
        }
    }

    /// Moves in the local frame (rotation only; size is not applied).
    #[inline]
    pub fn translate(&mut self, v: DVec3) {
        self.frame.translation += self.frame.matrix3 * v;
    }

    /// Rotates about a local axis (post-multiplication).
    pub fn rotate(&mut self, axis: u8, degrees: f64) {
        let r = match axis {
            0 => DMat3::from_rotation_x(degrees.to_radians()),
            1 => DMat3::from_rotation_y(degrees.to_radians()),
            _ => DMat3::from_rotation_z(degrees.to_radians()),
        };
        self.frame.matrix3 *= r;
    }

    /// Reflects across the local plane normal to `axis`.
    pub fn reflect(&mut self, axis: u8) {
        let mut d = DVec3::ONE;
        d[axis as usize] = -1.0;
        self.frame.matrix3 *= DMat3::from_diagonal(d);
    }

    /// Narrows the scope to the piece centred at `centre` (along `axis`,
    /// relative to the scope centre) of length `len`.
    pub fn piece(&mut self, axis: u8, centre: f64, len: f64) {
        self.translate(axis_vec(axis) * centre);
        self.size[axis as usize] = len;
    }

    /// Scope-local coordinates (sizes not applied) → world: the frame.
    pub fn frame_transform(&self) -> Affine3A {
        self.frame.as_affine3a()
    }

    /// Unit primitive → world: frame × diag(size).
    #[inline]
    pub fn transform(&self) -> Affine3A {
        let m = self.frame.matrix3 * DMat3::from_diagonal(self.size);
        // Component-wise `as f32` like `as_mat3`, but straight into the
        // SIMD columns (no detour through unaligned `Vec3`s).
        let col = |v: DVec3| Vec3A::new(v.x as f32, v.y as f32, v.z as f32);
        Affine3A::from_cols(col(m.x_axis), col(m.y_axis), col(m.z_axis), col(self.frame.translation))
    }
}
