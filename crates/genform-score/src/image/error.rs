//! Why an image target or scorer could not be built.

/// An invalid image size, camera or target picture. Each variant says what
/// was wrong and what to change.
#[derive(thiserror::Error, Debug, Clone, PartialEq)]
pub enum ImageError {
    /// Width or height is 0 or above [`crate::image::MAX_SIDE`].
    #[error("image size {width}×{height} is out of range: each side must be 1 to {max} pixels")]
    BadSize {
        /// Width asked for.
        width: u32,
        /// Height asked for.
        height: u32,
        /// The largest side accepted.
        max: u32,
    },
    /// The target picture and the scorer's rendering differ in size; render
    /// at the target's size (or resize the picture).
    #[error("the target image is {target_width}×{target_height} but the scorer renders {width}×{height}")]
    SizeMismatch {
        /// Target width.
        target_width: u32,
        /// Target height.
        target_height: u32,
        /// Rendering width.
        width: u32,
        /// Rendering height.
        height: u32,
    },
    /// A camera value is NaN or infinite, the field of view is outside
    /// (0°, 180°), or the clipping distances are not `0 < znear < zfar`.
    #[error("bad camera: {0}")]
    BadCamera(String),
    /// The PNG bytes could not be decoded.
    #[error("cannot decode the PNG target: {0}")]
    Png(String),
    /// The PFM bytes are malformed (header, size or data).
    #[error("cannot read the PFM target: {0}")]
    Pfm(String),
    /// A weight list does not have one value per pixel.
    #[error("the weight image has {got} values but {width}×{height} pixels")]
    WeightCount {
        /// Values given.
        got: usize,
        /// Width.
        width: u32,
        /// Height.
        height: u32,
    },
    /// A weight is NaN or infinite.
    #[error("the weight of pixel ({x}, {y}) is not finite")]
    NonFiniteWeight {
        /// Column, from the left.
        x: u32,
        /// Row, from the top.
        y: u32,
    },
}
