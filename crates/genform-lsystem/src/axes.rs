//! L-Py's z-up axes and genform's y-up axes (see [`crate::lpy`]).

use glam::DVec3;

/// An L-Py vector (x, y, z) in genform's axes: (y, z, x). L-Py's up +z
/// becomes genform's up +y.
pub fn to_genform_axes(v: DVec3) -> DVec3 {
    DVec3::new(v.y, v.z, v.x)
}

/// A genform vector in L-Py's axes (the inverse of [`to_genform_axes`]).
pub fn to_lpy_axes(v: DVec3) -> DVec3 {
    DVec3::new(v.z, v.x, v.y)
}
