//! Tables kept per id (per label, per attribute list, per daughter
//! element) that grow on first use.

/// Entry `i` of `v`, which grows (with default entries) to hold it: the
/// tables kept per label, per attribute list or per daughter element.
pub(crate) fn grown<T: Default>(v: &mut Vec<T>, i: usize) -> &mut T {
    if v.len() <= i {
        v.resize_with(i + 1, T::default);
    }
    &mut v[i]
}
