//! Behaviour descriptors: named measures of a model that MAP-Elites
//! spreads its archive over and galleries tell individuals apart by. Like
//! the scorers they read only a Scene (and the genome's length).

use genform_core::scene::{Primitive, Scene};
use glam::Vec3;

/// A behaviour descriptor of a model: what MAP-Elites spreads its archive
/// over and what the gallery tells individuals apart by. Sizes are along
/// the scene's axes (+y is up in previews).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Descriptor {
    /// Genes of the genome.
    Length,
    /// Bounding box: longest side over shortest side (≥ 1; the shortest
    /// side counts as at least 1 % of the longest, so flat models give 100,
    /// not infinity).
    Aspect,
    /// Bounding box along x.
    Width,
    /// Bounding box along y (up).
    Height,
    /// Bounding box along z.
    Depth,
    /// Instanced primitives, polylines and polygons of the scene.
    Primitives,
}

impl Descriptor {
    /// Every descriptor with its name in scene files.
    pub const ALL: [(&'static str, Descriptor); 6] = [
        ("length", Descriptor::Length),
        ("aspect", Descriptor::Aspect),
        ("width", Descriptor::Width),
        ("height", Descriptor::Height),
        ("depth", Descriptor::Depth),
        ("primitives", Descriptor::Primitives),
    ];

    /// The descriptor called `name`.
    pub fn from_name(name: &str) -> Option<Self> {
        Self::ALL.iter().find(|(n, _)| *n == name).map(|(_, d)| *d)
    }

    /// Its name in scene files.
    pub fn name(self) -> &'static str {
        Self::ALL.iter().find(|(_, d)| *d == self).map_or("", |(n, _)| n)
    }

    /// Its value for a genome of `genome_len` genes expressed as `scene`;
    /// NaN for a size of an empty scene.
    pub fn value(self, genome_len: usize, scene: &Scene) -> f64 {
        let size = || extent(scene).unwrap_or([f32::NAN; 3]).map(f64::from);
        match self {
            Descriptor::Length => genome_len as f64,
            Descriptor::Aspect => {
                let s = size();
                let longest = s[0].max(s[1]).max(s[2]);
                longest / s[0].min(s[1]).min(s[2]).max(0.01 * longest)
            }
            Descriptor::Width => size()[0],
            Descriptor::Height => size()[1],
            Descriptor::Depth => size()[2],
            Descriptor::Primitives => (scene.instances.len() + scene.polylines.len() + scene.polygons.len()) as f64,
        }
    }

    /// The range binned when a scene gives none: `length` the GA's length
    /// bounds `[min_length, max_length]`; `aspect` [1, 6]; a size from 0
    /// to the `[volume]` grid's side along its axis (`box_size`, else 10);
    /// `primitives` [0, max_length].
    pub fn default_range(self, lengths: [usize; 2], box_size: Option<[f64; 3]>) -> [f64; 2] {
        let side = |axis: usize| [0.0, box_size.map_or(10.0, |b| b[axis])];
        match self {
            Descriptor::Length => [lengths[0] as f64, lengths[1] as f64],
            Descriptor::Aspect => [1.0, 6.0],
            Descriptor::Width => side(0),
            Descriptor::Height => side(1),
            Descriptor::Depth => side(2),
            Descriptor::Primitives => [0.0, lengths[1] as f64],
        }
    }
}

/// Sides of the axis-aligned bounding box of the scene's geometry, or
/// `None` for an empty scene. Each instance counts with its primitive's
/// local box (the unit cube for built-in primitives, the mesh's box for a
/// mesh) carried to world space: exact for boxes, slightly generous for
/// rotated curved ones, and a few operations per instance instead of
/// tessellating — MAP-Elites measures every evaluated model.
fn extent(scene: &Scene) -> Option<[f32; 3]> {
    let (mut lo, mut hi) = (Vec3::INFINITY, Vec3::NEG_INFINITY);
    for inst in &scene.instances {
        let (a, b) = match inst.primitive {
            Primitive::Mesh(id) => {
                let mesh = &scene.meshes[id as usize];
                let Some(&first) = mesh.positions.first() else { continue };
                mesh.positions.iter().fold((first, first), |(a, b), p| (a.min(*p), b.max(*p)))
            }
            Primitive::Frustum { top } | Primitive::TaperedBox { top } => {
                let r = 0.5 * top.max(1.0);
                (Vec3::new(-r, -0.5, -r), Vec3::new(r, 0.5, r))
            }
            Primitive::Box | Primitive::Sphere => (Vec3::splat(-0.5), Vec3::splat(0.5)),
        };
        let m = inst.transform.matrix3;
        let centre = inst.transform.transform_point3((a + b) * 0.5);
        let half = (b - a) * 0.5;
        let reach = Vec3::from(m.x_axis.abs() * half.x + m.y_axis.abs() * half.y + m.z_axis.abs() * half.z);
        lo = lo.min(centre - reach);
        hi = hi.max(centre + reach);
    }
    let points = scene.polylines.points().iter().chain(scene.polygons.iter().flat_map(|p| &p.points));
    for p in points.chain(scene.surfaces.iter().flat_map(|s| &s.positions)) {
        lo = lo.min(*p);
        hi = hi.max(*p);
    }
    (lo.x <= hi.x).then(|| (hi - lo).to_array())
}

#[cfg(test)]
mod tests {
    use super::*;
    use genform_core::Instance;

    fn boxes(corners: &[[f32; 3]]) -> Scene {
        let mut scene = Scene::new();
        for &c in corners {
            let transform = glam::Affine3A::from_translation(c.into());
            scene.instances.push(Instance { transform, primitive: Primitive::Box, tag: 0 });
        }
        scene
    }

    #[test]
    fn descriptors_measure_the_bounding_box() {
        // Two unit boxes 4 apart along z: a 1 × 1 × 5 box.
        let scene = boxes(&[[0.0, 0.0, 0.0], [0.0, 0.0, 4.0]]);
        let v = |d: Descriptor| d.value(0, &scene);
        assert_eq!((v(Descriptor::Width), v(Descriptor::Height), v(Descriptor::Depth)), (1.0, 1.0, 5.0));
        assert_eq!(v(Descriptor::Aspect), 5.0);
        assert_eq!(v(Descriptor::Primitives), 2.0);
        assert_eq!(v(Descriptor::Length), 0.0);
        assert!(Descriptor::Width.value(0, &Scene::new()).is_nan());
        for (name, d) in Descriptor::ALL {
            assert_eq!(Descriptor::from_name(name), Some(d));
            assert_eq!(d.name(), name);
        }
        assert_eq!(Descriptor::from_name("lenght"), None);
    }
}
