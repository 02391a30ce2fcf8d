//! The fast voxelizer against the oracle, bit for bit.

use super::{oracle, voxelize};
use crate::grid::Grid;
use genform_core::scene::{Instance, Mesh, Primitive, Scene, Tessellation, unit_mesh};
use glam::{Affine3A, Mat3, Quat, Vec3};
use proptest::prelude::*;
use std::sync::Arc;

/// Fast and oracle agree on occupancy, overlap and `outside`.
fn check(grid: &Grid, scene: &Scene) {
    let fast = voxelize(grid, scene);
    let slow = oracle::voxelize(grid, scene);
    let diff = |a: &crate::VoxelSet, b: &crate::VoxelSet| {
        let mut d = Vec::new();
        a.for_each(|v| {
            if !b.contains(v) {
                d.push(v)
            }
        });
        d
    };
    assert!(
        fast.occupancy == slow.occupancy,
        "occupancy: fast-only {:?}, oracle-only {:?}",
        diff(&fast.occupancy, &slow.occupancy),
        diff(&slow.occupancy, &fast.occupancy)
    );
    assert!(fast.overlap == slow.overlap, "overlap differs");
    assert_eq!(fast.outside, slow.outside, "outside");
}

/// Small grids; one in four has a fine axis of 65–200 voxels, so that rows
/// span several words.
fn grid_strategy() -> impl Strategy<Value = Grid> {
    let dims = prop_oneof![
        3 => prop::array::uniform3(2u32..12),
        1 => (65u32..200, 2u32..8, 2u32..8).prop_map(|(a, b, c)| [a, b, c]),
    ];
    (prop::array::uniform3(-3.0f32..0.0), prop::array::uniform3(1.0f32..5.0), dims).prop_map(|(lo, ext, dims)| {
        let lo = Vec3::from_array(lo);
        Grid::new(lo, lo + Vec3::from_array(ext), dims).unwrap()
    })
}

/// Rotation × signed scale × optional shear; the translation is a fraction
/// of the grid's extent (from −0.1 to 1.1, so that shapes often stick out).
fn transform_strategy() -> impl Strategy<Value = (Mat3, Vec3)> {
    (
        prop::array::uniform3(-1.0f32..1.0),
        0.0f32..7.0,
        prop::array::uniform3(0.3f32..2.5),
        prop::array::uniform3(any::<bool>()),
        prop::option::of(prop::array::uniform3(-0.8f32..0.8)),
        prop::array::uniform3(-0.1f32..1.1),
    )
        .prop_map(|(axis, angle, scale, neg, shear, t)| {
            let axis = Vec3::from_array(axis).try_normalize().unwrap_or(Vec3::Y);
            let s = Vec3::from_array(std::array::from_fn(|i| if neg[i] { -scale[i] } else { scale[i] }));
            let shear = shear.map_or(Mat3::IDENTITY, |[a, b, c]| {
                Mat3::from_cols(Vec3::X, Vec3::new(a, 1.0, 0.0), Vec3::new(b, c, 1.0))
            });
            (Mat3::from_quat(Quat::from_axis_angle(axis, angle)) * shear * Mat3::from_diagonal(s), Vec3::from_array(t))
        })
}

/// A grid and `n` random items placed in it.
fn placed<T: std::fmt::Debug + Clone>(
    items: impl Strategy<Value = T>,
    n: std::ops::Range<usize>,
) -> impl Strategy<Value = (Grid, Vec<(Affine3A, T)>)> {
    (grid_strategy(), prop::collection::vec((transform_strategy(), items), n)).prop_map(|(grid, items)| {
        let ext = grid.max() - grid.min();
        let placed = items
            .into_iter()
            .map(|((m, t), item)| (Affine3A::from_mat3_translation(m, grid.min() + t * ext), item))
            .collect();
        (grid, placed)
    })
}

fn primitive_strategy() -> impl Strategy<Value = Primitive> {
    prop_oneof![
        Just(Primitive::Box),
        Just(Primitive::Sphere),
        (0.0f32..2.0).prop_map(|top| Primitive::Frustum { top }),
        (0.0f32..2.0).prop_map(|top| Primitive::TaperedBox { top }),
        Just(Primitive::Frustum { top: 0.0 }),
        Just(Primitive::TaperedBox { top: 0.0 }),
    ]
}

fn scene_of(items: impl IntoIterator<Item = (Affine3A, Primitive)>) -> Scene {
    let mut s = Scene::new();
    for (transform, primitive) in items {
        s.instances.push(Instance { transform, primitive, tag: 0 });
    }
    s
}

/// Axis-aligned, possibly mirrored or axis-swapped boxes with faces on
/// voxel centres and boundaries (grid voxels of size 0.5 over [0, n/2]).
/// With `exact`, sizes are powers of two and nothing is mirrored, so unit
/// coordinates are computed without rounding.
fn aligned_strategy(exact: bool) -> impl Strategy<Value = (Grid, Scene)> {
    let item = (prop::array::uniform3(1u32..6), prop::array::uniform3(0u32..1000), 0usize..6, any::<bool>());
    // One in four grids has rows of 130–200 voxels (several words).
    let dims = prop_oneof![
        3 => prop::array::uniform3(2u32..10),
        1 => (130u32..200, 2u32..6, 2u32..6).prop_map(|(a, b, c)| [a, b, c]),
    ];
    (dims, prop::collection::vec(item, 1..6)).prop_map(move |(dims, items)| {
        let max = Vec3::from_array(dims.map(|d| d as f32 * 0.5));
        let grid = Grid::new(Vec3::ZERO, max, dims).unwrap();
        let perms = [[0, 1, 2], [1, 0, 2], [2, 1, 0], [0, 2, 1], [1, 2, 0], [2, 0, 1]];
        let scene = scene_of(items.into_iter().map(move |(size, pos, perm, mirror)| {
            // Sizes and positions in quarter voxels: faces hit centres.
            let size = if exact { size.map(|v| 1 << (v % 4)) } else { size };
            let s = Vec3::from_array(size.map(|v| v as f32 * 0.25));
            let cols = perms[perm].map(|c| Vec3::AXES[c]);
            let mut m = Mat3::from_cols(cols[0], cols[1], cols[2]) * Mat3::from_diagonal(s);
            if mirror && !exact {
                m.x_axis = -m.x_axis;
            }
            // Anywhere from just before the grid to just past it, in quarter units.
            let at = Vec3::from_array(std::array::from_fn(|a| (pos[a] % (2 * dims[a] + 6)) as f32 * 0.25 - 0.5));
            (Affine3A::from_mat3_translation(m, at), Primitive::Box)
        }));
        (grid, scene)
    })
}

/// Axis-aligned boxes on any grid, the shapes of the separable-box path:
/// any axis permutation, any sign flips (mirrors), and extents either
/// arbitrary or with faces snapped to voxel centres and boundaries; sizes
/// from a sliver to three times the grid (so that some stick out of it on
/// both sides, like the spaceship's compounded segments).
fn separable_strategy() -> impl Strategy<Value = (Grid, Scene)> {
    let face = prop_oneof![
        // A face anywhere, mostly in the grid (in grid fractions) ...
        3 => (-0.2f32..1.2).prop_map(|f| (false, f)),
        // ... or far out of it,
        1 => (-1.2f32..2.2).prop_map(|f| (false, f)),
        // or on a voxel boundary or centre, in half voxels from the grid's min.
        2 => (-8i32..400).prop_map(|h| (true, h as f32)),
    ];
    let item = (prop::array::uniform3((face.clone(), face)), 0usize..6, prop::array::uniform3(any::<bool>()));
    (grid_strategy(), prop::collection::vec(item, 1..6)).prop_map(|(grid, items)| {
        let (lo, ext, vs) = (grid.min(), grid.max() - grid.min(), grid.voxel_size());
        let dims = grid.dims();
        let perms = [[0, 1, 2], [1, 0, 2], [2, 1, 0], [0, 2, 1], [1, 2, 0], [2, 0, 1]];
        let scene = scene_of(items.into_iter().map(|(faces, perm, flip)| {
            let at = |a: usize, (snapped, f): (bool, f32)| {
                let f = if snapped { f % (2 * dims[a] as i32 + 8) as f32 } else { f };
                lo[a] + if snapped { f * 0.5 * vs[a] } else { f * ext[a] }
            };
            let (mut min, mut max) = (Vec3::ZERO, Vec3::ZERO);
            for a in 0..3 {
                let (p, q) = (at(a, faces[a].0), at(a, faces[a].1));
                // Thin but never flat (a flat box holds nothing anyway).
                let q = if (q - p).abs() < 1e-3 * vs[a] { p + 0.37 * vs[a] } else { q };
                (min[a], max[a]) = (p.min(q), p.max(q));
            }
            // Unit axis c is world axis perms[perm][c], scaled by that extent.
            let axes = perms[perm];
            let cols: [Vec3; 3] = std::array::from_fn(|c| {
                let w = axes[c];
                let sign = if flip[c] { -1.0 } else { 1.0 };
                Vec3::AXES[w] * (sign * (max[w] - min[w]))
            });
            (
                Affine3A::from_mat3_translation(Mat3::from_cols(cols[0], cols[1], cols[2]), (min + max) * 0.5),
                Primitive::Box,
            )
        }));
        (grid, scene)
    })
}

/// Boxes rotated about one world axis by any angle (the city's buildings
/// turn about y), scaled and placed anywhere: the split-box path when that
/// axis crosses the rows, the general one when it runs along them.
fn axis_rotated_strategy() -> impl Strategy<Value = (Grid, Scene)> {
    let item = (0usize..3, 0.0f32..7.0, prop::array::uniform3(0.05f32..2.5), prop::array::uniform3(-0.1f32..1.1));
    (grid_strategy(), prop::collection::vec(item, 1..6)).prop_map(|(grid, items)| {
        let ext = grid.max() - grid.min();
        let scene = scene_of(items.into_iter().map(|(axis, angle, size, t)| {
            let at = grid.min() + Vec3::from_array(t) * ext;
            let r = Affine3A::from_axis_angle(Vec3::AXES[axis], angle);
            (Affine3A::from_translation(at) * r * Affine3A::from_scale(Vec3::from_array(size)), Primitive::Box)
        }));
        (grid, scene)
    })
}

/// How many instances of `scene` take the split-box path.
fn split_count(grid: &Grid, scene: &Scene) -> usize {
    let lat = crate::grid::Lattice::new(grid);
    let split = |inst| match super::prepare::prepare(&lat, scene, inst, &mut Vec::new()) {
        Some(super::prepare::Prepared { body: super::prepare::Body::Solid(s), .. }) => s.split.is_some(),
        _ => false,
    };
    scene.instances.iter().filter(|i| split(i)).count()
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(cases()))]

    #[test]
    fn axis_rotated_boxes_match_the_oracle((grid, scene) in axis_rotated_strategy()) {
        check(&grid, &scene);
    }

    #[test]
    fn primitives_match_the_oracle((grid, items) in placed(primitive_strategy(), 1..5)) {
        check(&grid, &scene_of(items));
    }

    #[test]
    fn aligned_boxes_match_the_oracle((grid, scene) in aligned_strategy(false)) {
        check(&grid, &scene);
    }

    #[test]
    fn separable_boxes_match_the_oracle((grid, scene) in separable_strategy()) {
        // Every box takes the separable path (else this tests nothing new).
        let lat = crate::grid::Lattice::new(&grid);
        for inst in &scene.instances {
            if let Some(p) = super::prepare::prepare(&lat, &scene, inst, &mut Vec::new()) {
                let super::prepare::Body::Solid(solid) = &p.body else { unreachable!() };
                prop_assert!(solid.separable.is_some(), "{:?}", inst.transform);
            }
        }
        check(&grid, &scene);
    }

    #[test]
    fn meshes_match_the_oracle((grid, items) in placed(0usize..6, 1..3)) {
        let mut scene = Scene::new();
        let tess = Tessellation { radial: 7, rings: 5 };
        let [trunk, leaf] = tree_assets();
        let meshes = [
            Arc::new(cube_mesh()),
            Arc::new(unit_mesh(Primitive::Sphere, tess)),
            Arc::new(unit_mesh(Primitive::Frustum { top: 0.4 }, tess)),
            Arc::new(open_strip()),
            Arc::new(trunk),
            Arc::new(leaf),
        ];
        for (transform, m) in items {
            let id = scene.mesh(&meshes[m]);
            scene.instances.push(Instance { transform, primitive: Primitive::Mesh(id), tag: 0 });
        }
        check(&grid, &scene);
    }

    #[test]
    fn aligned_meshes_match_the_oracle((grid, boxes) in aligned_strategy(true)) {
        let mut scene = boxes.clone();
        let cube = Arc::new(cube_mesh());
        let id = scene.mesh(&cube);
        for inst in &mut scene.instances {
            inst.primitive = Primitive::Mesh(id);
        }
        check(&grid, &scene);
        // Lattice-aligned cube meshes hold what the same boxes hold.
        prop_assert_eq!(voxelize(&grid, &scene).occupancy, voxelize(&grid, &boxes).occupancy);
    }
}

/// The reference's `cube.obj` (12 triangles spanning ±0.5).
pub(crate) fn cube_mesh() -> Mesh {
    Mesh::from_obj("cube", include_str!("../../tests/data/cube.obj")).unwrap()
}

/// The tree grammars' assets (`examples/shape/assets`): a 16-sided
/// frustum and a low-poly leaf.
pub(crate) fn tree_assets() -> [Mesh; 2] {
    [
        Mesh::from_obj("trunk", include_str!("../../tests/data/trunk.obj")).unwrap(),
        Mesh::from_obj("leaf", include_str!("../../tests/data/leaf_low_poly.obj")).unwrap(),
    ]
}

/// Trunks and leaves as the tree grammars place them (scaled, turned about
/// y, tilted about z, turned again), many overlapping, on a finer grid
/// than the proptests: long rows, many triangles per row line, slivers.
#[test]
fn tree_assets_match_the_oracle_on_a_fine_grid() {
    let mut rng = genform_core::Rng::stream(7, &[]);
    let [trunk, leaf] = tree_assets().map(Arc::new);
    for dims in [[48, 48, 48], [70, 33, 41]] {
        let grid = Grid::new(Vec3::splat(-2.5), Vec3::splat(2.5), dims).unwrap();
        let mut scene = Scene::new();
        let ids = [scene.mesh(&trunk), scene.mesh(&leaf)];
        for n in 0..24 {
            let mut u = || rng.next_f64() as f32;
            let size = Vec3::new(0.3 + u(), 0.5 + 2.0 * u(), 0.3 + u());
            let r = Quat::from_rotation_y(7.0 * u()) * Quat::from_rotation_z(1.5 * u()) * Quat::from_rotation_y(u());
            let at = Vec3::new(4.0 * u() - 2.0, 4.0 * u() - 2.0, 4.0 * u() - 2.0);
            let transform = Affine3A::from_scale_rotation_translation(size, r, at);
            scene.instances.push(Instance { transform, primitive: Primitive::Mesh(ids[n % 2]), tag: 0 });
        }
        check(&grid, &scene);
        let v = voxelize(&grid, &scene);
        assert!(v.occupancy.count() > 1000 && v.overlap.count() > 0 && v.outside > 0);
    }
}

/// Faces exactly on row centres (the tie rule decides every row, and the
/// per-instance slack of the row bounds must not lose one), beside trunks
/// and leaves shrunk to about a voxel (slivers a row or two wide): still
/// the oracle's result.
#[test]
fn narrow_triangles_on_row_centres_match_the_oracle() {
    let cube = Arc::new(cube_mesh());
    let [trunk, leaf] = tree_assets().map(Arc::new);
    let grid = Grid::new(Vec3::ZERO, Vec3::splat(8.0), [8, 8, 8]).unwrap();
    let mut scene = Scene::new();
    let ids = [scene.mesh(&cube), scene.mesh(&trunk), scene.mesh(&leaf)];
    let mut place = |id, size: Vec3, r: Quat, at: Vec3| {
        let transform = Affine3A::from_scale_rotation_translation(size, r, at);
        scene.instances.push(Instance { transform, primitive: Primitive::Mesh(id), tag: 0 });
    };
    // Faces on centres: one voxel (two rows per line) and two (three rows).
    place(ids[0], Vec3::ONE, Quat::IDENTITY, Vec3::splat(2.0));
    place(ids[0], Vec3::ONE, Quat::from_rotation_x(std::f32::consts::FRAC_PI_2), Vec3::new(5.0, 2.0, 6.0));
    place(ids[0], Vec3::splat(2.0), Quat::IDENTITY, Vec3::new(5.5, 5.5, 2.5));
    place(ids[0], Vec3::new(1.0, 2.0, 1.0), Quat::IDENTITY, Vec3::new(2.0, 5.5, 6.0));
    let mut rng = genform_core::Rng::stream(11, &[]);
    for n in 0..40 {
        let mut u = || rng.next_f64() as f32;
        let size = Vec3::new(0.4 + u(), 0.6 + 1.2 * u(), 0.4 + u());
        let r = Quat::from_rotation_y(7.0 * u()) * Quat::from_rotation_z(1.5 * u());
        let at = Vec3::new(1.0 + 6.0 * u(), 1.0 + 6.0 * u(), 1.0 + 6.0 * u());
        place(ids[1 + n % 2], size, r, at);
    }
    check(&grid, &scene);
    let v = voxelize(&grid, &scene);
    assert!(v.occupancy.count() >= 2 + 2 + 8 + 4, "{}", v.occupancy.count());
}

/// An open surface (parity is not a volume here, but both voxelizers must
/// still agree).
fn open_strip() -> Mesh {
    Mesh::from_obj("strip", "v -0.5 -0.5 0\nv 0.5 -0.5 0.2\nv 0.5 0.5 0\nv -0.5 0.5 -0.3\nf 1 2 3\nf 1 3 4\n").unwrap()
}

#[test]
fn degenerate_transforms_hold_nothing_and_do_not_panic() {
    let grid = Grid::new(Vec3::ZERO, Vec3::splat(4.0), [4; 3]).unwrap();
    let bad = [
        Affine3A::from_scale(Vec3::new(1.0, 0.0, 1.0)),
        Affine3A::from_translation(Vec3::splat(f32::NAN)),
        Affine3A::from_scale(Vec3::splat(f32::INFINITY)),
        Affine3A::from_scale(Vec3::splat(1e-30)),
    ];
    for t in bad {
        for p in [Primitive::Box, Primitive::Sphere, Primitive::Frustum { top: f32::NAN }, Primitive::Mesh(0)] {
            let mut scene = scene_of([(t, p)]);
            scene.meshes.push(Arc::new(cube_mesh()));
            let v = voxelize(&grid, &scene);
            assert_eq!((v.occupancy.count(), v.outside), (0, 0), "{t:?} {p:?}");
            check(&grid, &scene);
        }
    }
    // A missing mesh asset and a mesh with bad indices are skipped.
    let scene = scene_of([(Affine3A::IDENTITY, Primitive::Mesh(3))]);
    assert_eq!(voxelize(&grid, &scene).occupancy.count(), 0);
}

#[test]
fn huge_instances_estimate_outside() {
    let grid = Grid::new(Vec3::ZERO, Vec3::splat(4.0), [4; 3]).unwrap();
    // 2000³ unit voxels, all of the grid inside.
    let scene = scene_of([(Affine3A::from_scale(Vec3::splat(2000.0)), Primitive::Box)]);
    let v = voxelize(&grid, &scene);
    assert_eq!(v.occupancy.count(), 64);
    assert_eq!(v.outside, 8_000_000_000 - 64);
    check(&grid, &scene);
    let tall = scene_of([(Affine3A::from_scale(Vec3::new(1.0, 1e5, 1e5)), Primitive::Sphere)]);
    check(&grid, &tall);
    // A mesh reaching far outside along its rows (x; past the centre table).
    let stretch = Affine3A::from_scale_rotation_translation(Vec3::new(2e5, 1.3, 0.7), Quat::IDENTITY, Vec3::splat(0.6));
    let mut long = scene_of([(stretch, Primitive::Mesh(0))]);
    long.meshes.push(Arc::new(cube_mesh()));
    let v = voxelize(&grid, &long);
    assert_eq!((v.occupancy.count(), v.outside), (4, 199_996));
    check(&grid, &long);
}

#[test]
fn spans_are_exact_for_a_rotated_box_on_a_fine_grid() {
    // A larger case than the proptests: many rows, long spans.
    let grid = Grid::new(Vec3::splat(-2.0), Vec3::splat(2.0), [40, 30, 20]).unwrap();
    let t = Affine3A::from_scale_rotation_translation(
        Vec3::new(2.5, -1.0, 0.7),
        Quat::from_euler(glam::EulerRot::XYZ, 0.3, -0.7, 1.1),
        Vec3::new(0.3, -0.2, 0.1),
    );
    let scene = scene_of([(t, Primitive::Box), (t, Primitive::Sphere), (t, Primitive::Frustum { top: 0.3 })]);
    check(&grid, &scene);
    let v = voxelize(&grid, &scene);
    // Volume of the box is |det| = 1.75 units³ = 1750/ (0.1·0.1333·0.2) voxels.
    let want = 1.75 / grid.voxel_volume();
    let boxes = voxelize(&grid, &scene_of([(t, Primitive::Box)])).occupancy.count() as f64;
    assert!((boxes - want).abs() / want < 0.05, "{boxes} vs {want}");
    assert!(v.overlap.count() > 0);
}

/// The random scenes above do reach what they are meant to test: held
/// voxels, overlaps, voxels outside the grid, rows along every axis.
#[test]
fn strategies_reach_the_interesting_cases() {
    use proptest::strategy::ValueTree;
    let mut runner = proptest::test_runner::TestRunner::deterministic();
    let strategy = placed(primitive_strategy(), 1..5);
    let (mut held, mut over, mut out, mut axes) = (0, 0, 0, [0; 3]);
    for _ in 0..96 {
        let (grid, items) = strategy.new_tree(&mut runner).unwrap().current();
        let v = voxelize(&grid, &scene_of(items));
        held += usize::from(v.occupancy.count() > 0);
        over += usize::from(v.overlap.count() > 0);
        out += usize::from(v.outside > 0);
        axes[crate::grid::Lattice::new(&grid).axes[0]] += 1;
    }
    assert!(held > 70 && over > 15 && out > 40, "held {held}, overlap {over}, outside {out}");
    assert!(axes.iter().all(|&a| a > 15), "row axes {axes:?}");
}

/// Most axis-rotated boxes take the split path, and they hold voxels.
#[test]
fn axis_rotated_strategy_reaches_the_split_path() {
    use proptest::strategy::ValueTree;
    let mut runner = proptest::test_runner::TestRunner::deterministic();
    let strategy = axis_rotated_strategy();
    let (mut split, mut total, mut held) = (0, 0, 0);
    for _ in 0..96 {
        let (grid, scene) = strategy.new_tree(&mut runner).unwrap().current();
        split += split_count(&grid, &scene);
        total += scene.instances.len();
        held += usize::from(voxelize(&grid, &scene).occupancy.count() > 0);
    }
    assert!(split * 2 > total && held > 70, "split {split} of {total}, held {held}");
}

/// Cases per property: 256, or `PROPTEST_CASES` for longer hunts.
fn cases() -> u32 {
    std::env::var("PROPTEST_CASES").ok().and_then(|v| v.parse().ok()).unwrap_or(256)
}

/// The separable-box scenes often hold voxels, overlap and stick out of
/// the grid.
#[test]
fn separable_strategy_reaches_the_interesting_cases() {
    use proptest::strategy::ValueTree;
    let mut runner = proptest::test_runner::TestRunner::deterministic();
    let strategy = separable_strategy();
    let (mut held, mut over, mut out) = (0, 0, 0);
    for _ in 0..96 {
        let (grid, scene) = strategy.new_tree(&mut runner).unwrap().current();
        let v = voxelize(&grid, &scene);
        held += usize::from(v.occupancy.count() > 0);
        over += usize::from(v.overlap.count() > 0);
        out += usize::from(v.outside > 0);
    }
    assert!(held > 70 && over > 15 && out > 60, "held {held}, overlap {over}, outside {out}");
}

/// A block grid of `size` at `origin` with the block `f(x, y, z)` (local
/// coordinates; `None` leaves the cell unset).
fn block_grid(
    origin: glam::IVec3,
    size: glam::UVec3,
    f: impl Fn(i32, i32, i32) -> Option<&'static str>,
) -> genform_core::BlockGrid {
    let mut g = genform_core::BlockGrid::new(origin, size);
    for x in 0..size.x as i32 {
        for y in 0..size.y as i32 {
            for z in 0..size.z as i32 {
                if let Some(id) = f(x, y, z) {
                    g.set(origin + glam::IVec3::new(x, y, z), &genform_core::BlockState::new(id));
                }
            }
        }
    }
    g
}

/// Random block grids (unset, air, water and solid cells) near a random
/// grid, with a random box or sphere beside them.
fn blocks_strategy() -> impl Strategy<Value = (Grid, Scene)> {
    let ids = [None, Some("air"), Some("stone"), Some("stone"), Some("oak_planks"), Some("water")];
    let cells = prop::collection::vec(0usize..ids.len(), 1..=216);
    // Placed at a fraction of the grid (less a cell or two), so that most
    // structures reach into the grid and many stick out of it.
    let block = (prop::array::uniform3(-0.2f32..1.0), prop::array::uniform3(1u32..7), cells, 0u64..4);
    // Grids aligned with the cells too: voxels of 1/4, 1/2 or 1 cell, centres
    // on cell faces or not.
    let aligned = (prop::array::uniform3(0u32..3), prop::array::uniform3(-8i32..1), prop::array::uniform3(2u32..14))
        .prop_map(|(k, lo, dims)| {
            let size = Vec3::from_array(k.map(|k| 0.25 * (1 << k) as f32));
            let min = Vec3::from_array(lo.map(|l| l as f32 * 0.25));
            Grid::new(min, min + size * Vec3::from_array(dims.map(|d| d as f32)), dims).unwrap()
        });
    let grid = prop_oneof![grid_strategy(), aligned];
    (
        grid,
        prop::collection::vec(block, 1..4),
        prop::collection::vec((transform_strategy(), primitive_strategy()), 0..2),
    )
        .prop_map(move |(grid, blocks, items)| {
            let ext = grid.max() - grid.min();
            let mut scene = scene_of(
                items.into_iter().map(|((m, t), p)| (Affine3A::from_mat3_translation(m, grid.min() + t * ext), p)),
            );
            for (frac, size, cells, stride) in blocks {
                let size = glam::UVec3::from_array(size);
                let origin = (grid.min() + Vec3::from_array(frac) * ext).floor().as_ivec3() - glam::IVec3::ONE;
                let n = cells.len();
                let at = |x: i32, y: i32, z: i32| {
                    let i = ((y * size.z as i32 + z) * size.x as i32 + x) as u64;
                    ids[cells[((i * (stride + 1)) % n as u64) as usize]]
                };
                scene.blocks.push(block_grid(origin, size, at));
            }
            (grid, scene)
        })
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(cases()))]

    #[test]
    fn blocks_match_the_oracle((grid, scene) in blocks_strategy()) {
        check(&grid, &scene);
    }
}

/// Grids whose centres the cell faces hit (or not) with exact arithmetic.
fn exact_grids() -> Vec<Grid> {
    let g = |min: [f32; 3], size: [f32; 3], dims: [u32; 3]| {
        let min = Vec3::from_array(min);
        Grid::new(min, min + Vec3::from_array(size) * Vec3::from_array(dims.map(|d| d as f32)), dims).unwrap()
    };
    vec![
        g([0.0; 3], [1.0; 3], [8; 3]),
        g([-0.5; 3], [1.0; 3], [8; 3]),                      // centres on cell faces
        g([0.25, 0.0, -1.0], [0.5, 0.25, 1.0], [16, 40, 9]), // rows along y; ties along x
        g([-2.0, 1.0, 0.0], [2.0, 0.5, 0.25], [3, 12, 30]),  // voxels larger than cells along x
    ]
}

#[test]
fn blocks_voxelize_like_the_box_they_fill() {
    // Power-of-two extents: the box's unit coordinates are exact too.
    for grid in exact_grids() {
        for (origin, size) in [([1, 2, 0], [4, 2, 4]), ([-3, 0, 2], [8, 4, 2]), ([1, -1, -2], [2, 8, 16])] {
            let (o, s) = (glam::IVec3::from_array(origin), glam::UVec3::from_array(size));
            let mut blocks = Scene::new();
            blocks.blocks.push(block_grid(o, s, |_, _, _| Some("stone")));
            let centre = o.as_vec3() + s.as_vec3() * 0.5;
            let boxed = scene_of([(
                Affine3A::from_scale_rotation_translation(s.as_vec3(), Quat::IDENTITY, centre),
                Primitive::Box,
            )]);
            let (a, b) = (voxelize(&grid, &blocks), voxelize(&grid, &boxed));
            assert!(a.occupancy.count() > 0, "{grid:?} {origin:?}");
            assert_eq!(a, b, "{grid:?} {origin:?}");
            check(&grid, &blocks);
        }
    }
}

#[test]
fn neighbouring_blocks_share_no_voxel() {
    // Unit voxels centred on the integers: every centre on a cell face
    // belongs to exactly one of the cells sharing it.
    let grid = Grid::new(Vec3::splat(-0.5), Vec3::splat(7.5), [8; 3]).unwrap();
    let mut scene = Scene::new();
    let ids = ["stone", "dirt", "oak_planks", "glass"];
    scene.blocks.push(block_grid(glam::IVec3::ZERO, glam::UVec3::splat(4), |x, y, z| {
        Some(ids[((x + 2 * y + 3 * z) % 4) as usize])
    }));
    let v = voxelize(&grid, &scene);
    assert_eq!((v.occupancy.count(), v.overlap.count(), v.outside), (64, 0, 0));
    // Another grid over the same cells overlaps it; air and unset cells hold nothing.
    scene
        .blocks
        .push(block_grid(glam::IVec3::new(3, 0, 0), glam::UVec3::new(2, 1, 1), |x, _, _| (x == 0).then_some("stone")));
    scene.blocks.push(block_grid(glam::IVec3::new(0, 5, 0), glam::UVec3::splat(2), |_, _, _| Some("air")));
    let v = voxelize(&grid, &scene);
    assert_eq!((v.occupancy.count(), v.overlap.count(), v.outside), (64, 1, 0));
    check(&grid, &scene);
}

#[test]
fn blocks_outside_the_grid_count_as_outside() {
    let grid = Grid::new(Vec3::ZERO, Vec3::splat(4.0), [8; 3]).unwrap();
    let mut scene = Scene::new();
    // 6×1×1 cells from x = -1: 2 cells out (16 voxels of 1/8 each), 4 in.
    scene.blocks.push(block_grid(glam::IVec3::new(-1, 0, 0), glam::UVec3::new(6, 1, 1), |_, _, _| Some("stone")));
    // A far-away structure: all outside.
    scene.blocks.push(block_grid(glam::IVec3::new(1000, 0, 0), glam::UVec3::splat(2), |_, _, _| Some("stone")));
    let v = voxelize(&grid, &scene);
    assert_eq!(v.occupancy.count(), 4 * 8);
    assert_eq!(v.outside, 2 * 8 + 8 * 8);
    check(&grid, &scene);
}

/// The random block scenes often hold voxels, overlap and stick out.
#[test]
fn blocks_strategy_reaches_the_interesting_cases() {
    use proptest::strategy::ValueTree;
    let mut runner = proptest::test_runner::TestRunner::deterministic();
    let strategy = blocks_strategy();
    let (mut held, mut over, mut out) = (0, 0, 0);
    for _ in 0..96 {
        let (grid, mut scene) = strategy.new_tree(&mut runner).unwrap().current();
        scene.instances.clear();
        let v = voxelize(&grid, &scene);
        held += usize::from(v.occupancy.count() > 0);
        over += usize::from(v.overlap.count() > 0);
        out += usize::from(v.outside > 0);
    }
    assert!(held > 70 && over > 15 && out > 60, "held {held}, overlap {over}, outside {out}");
}
