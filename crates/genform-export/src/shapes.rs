//! The distinct unit meshes of a scene's instances, tessellated once.

use genform_core::scene::{Mesh, Primitive, Scene, Tessellation, unit_mesh};
use std::borrow::Cow;
use std::collections::HashMap;

/// A hashable identity for a [`Primitive`] (`f32` parameters by bits, with
/// `-0.0` folded into `0.0`).
#[derive(Clone, Copy, PartialEq, Eq, Hash)]
enum Key {
    Box,
    Frustum(u32),
    Sphere,
    TaperedBox(u32),
    Mesh(u32),
}

fn key(p: Primitive) -> Key {
    let bits = |x: f32| (x + 0.0).to_bits();
    match p {
        Primitive::Box => Key::Box,
        Primitive::Frustum { top } => Key::Frustum(bits(top)),
        Primitive::Sphere => Key::Sphere,
        Primitive::TaperedBox { top } => Key::TaperedBox(bits(top)),
        Primitive::Mesh(id) => Key::Mesh(id),
    }
}

/// The distinct unit meshes in first-use order, and which one each instance
/// uses. Mesh assets are borrowed from the scene.
pub(crate) struct Shapes<'a> {
    /// Distinct unit meshes.
    pub meshes: Vec<Cow<'a, Mesh>>,
    /// For each instance, its index into `meshes`.
    pub of_instance: Vec<u32>,
}

impl<'a> Shapes<'a> {
    /// Tessellates the scene's distinct primitives.
    ///
    /// Panics if an instance names a missing mesh asset.
    pub fn new(scene: &'a Scene, tess: Tessellation) -> Shapes<'a> {
        let mut index: HashMap<Key, u32> = HashMap::new();
        let mut meshes = Vec::new();
        let of_instance = scene
            .instances
            .iter()
            .map(|inst| {
                *index.entry(key(inst.primitive)).or_insert_with(|| {
                    meshes.push(match inst.primitive {
                        Primitive::Mesh(id) => Cow::Borrowed(&*scene.meshes[id as usize]),
                        p => Cow::Owned(unit_mesh(p, tess)),
                    });
                    (meshes.len() - 1) as u32
                })
            })
            .collect();
        Shapes { meshes, of_instance }
    }

    /// The unit mesh of instance `i`.
    pub fn of(&self, i: usize) -> &Mesh {
        &self.meshes[self.of_instance[i] as usize]
    }
}

/// A display name for tag `tag` of `scene` usable in OBJ statements: no
/// whitespace, never empty.
pub(crate) fn tag_name(scene: &Scene, tag: u32) -> String {
    let raw = scene.tags.get(tag as usize).map(String::as_str).unwrap_or("");
    if raw.is_empty() {
        return format!("tag{tag}");
    }
    raw.chars().map(|c| if c.is_whitespace() || c.is_control() { '_' } else { c }).collect()
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::test_scenes;

    #[test]
    fn distinct_primitives_are_shared() {
        let s = test_scenes::mixed();
        let shapes = Shapes::new(&s, Tessellation::default());
        // 7 primitives, each placed twice, plus two more boxes.
        assert_eq!(shapes.meshes.len(), 7);
        assert_eq!(shapes.of_instance.len(), 16);
        assert_eq!(shapes.of_instance[0], shapes.of_instance[1]);
        assert_eq!(shapes.of_instance[14], 0);
        assert!(matches!(shapes.meshes[6], Cow::Borrowed(_)));
        assert_eq!(shapes.of(12).name, "tet");
    }

    #[test]
    fn tag_names_have_no_spaces() {
        let mut s = Scene::new();
        s.tag("roof tile");
        s.tag("");
        assert_eq!(tag_name(&s, 0), "roof_tile");
        assert_eq!(tag_name(&s, 1), "tag1");
        assert_eq!(tag_name(&s, 9), "tag9");
    }
}
