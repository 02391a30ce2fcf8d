"""The Blender add-on (python/genform_blender) under `bpy`, Blender as a
Python module from PyPI: installed from a zip as a user would, then sample
and evolve through its operators.

`bpy` ships wheels for one CPython only (Blender 4.x/5.0: 3.11); where it
cannot be installed the whole file is skipped with the reason printed.
"""

from __future__ import annotations

import atexit
import json
import os
import shutil
import struct
import sys
import tempfile
import time
import zipfile
from pathlib import Path

import numpy as np
import pytest

# Blender's user folders (scripts, where the add-on is installed, config,
# extensions) in a throwaway folder rather than ~/.config/blender; Blender
# reads this when bpy is first imported.
if "BLENDER_USER_RESOURCES" not in os.environ:
    os.environ["BLENDER_USER_RESOURCES"] = tempfile.mkdtemp(prefix="genform-blender-")
    atexit.register(shutil.rmtree, os.environ["BLENDER_USER_RESOURCES"], ignore_errors=True)

try:
    import bpy
except ImportError as e:
    REASON = (
        f"bpy (Blender as a Python module) cannot be imported ({e}); `pip install bpy` has wheels for "
        f"CPython 3.11 only and this is {sys.version_info.major}.{sys.version_info.minor}"
    )
    print(f"test_blender.py skipped: {REASON}")
    pytest.skip(REASON, allow_module_level=True)

import addon_utils

import genform
from conftest import EXAMPLES, ROOT, SHIP_SCENE, stage_render

SHIP = EXAMPLES / "shape" / "spaceship.sg"
BUSH = EXAMPLES / "lsystem" / "bush_3d.ls"
# Seed 15 grows the 86-box ship of the README (past the 32-primitive threshold).
SHIP_SEED = 15


@pytest.fixture(scope="module")
def addon():
    """The add-on zipped, installed through Blender's preferences, enabled."""
    with tempfile.TemporaryDirectory() as tmp:
        archive = Path(tmp) / "genform_blender.zip"
        with zipfile.ZipFile(archive, "w") as z:
            for f in sorted((ROOT / "python" / "genform_blender").glob("*.py")):
                z.write(f, f"genform_blender/{f.name}")
        assert bpy.ops.preferences.addon_install(filepath=str(archive), overwrite=True) == {"FINISHED"}
    assert bpy.ops.preferences.addon_enable(module="genform_blender") == {"FINISHED"}
    yield sys.modules["genform_blender"]
    bpy.ops.preferences.addon_disable(module="genform_blender")


@pytest.fixture
def empty(addon):
    """An empty Blender scene with the panel's defaults, for each test."""
    for collection in (bpy.data.objects, bpy.data.meshes, bpy.data.materials):
        for item in list(collection):
            collection.remove(item)
    s = bpy.context.scene.genform
    s.import_mode, s.y_up, s.seed, s.status, s.progress = "MESH", True, 0, "", 0.0
    return addon


def test_addon_installs_from_a_zip_and_registers(addon):
    assert addon_utils.check("genform_blender") == (True, True)
    assert Path(addon.__file__).parent.parent == Path(bpy.utils.user_resource("SCRIPTS")) / "addons"
    assert addon.bl_info["blender"] <= bpy.app.version
    assert hasattr(bpy.types, "GENFORM_PT_panel") and hasattr(bpy.types.Scene, "genform")
    assert {"sample", "evolve"} <= set(dir(bpy.ops.genform))


def test_sampled_spaceship_is_the_wheels_mesh(empty):
    assert bpy.ops.genform.sample(grammar=str(SHIP), seed=SHIP_SEED) == {"FINISHED"}
    obj = bpy.context.view_layer.objects.active
    assert [o.name for o in bpy.data.objects] == [obj.name] and obj.type == "MESH"
    model = genform.load(SHIP).sample(seed=SHIP_SEED)
    verts, faces = model.mesh()
    assert len(faces) == 1032 and len(verts) == 8 * 86, "86 boxes"
    assert (len(obj.data.vertices), len(obj.data.polygons)) == (len(verts), len(faces))
    # The same points, turned y-up → z-up, and the same triangles.
    co = np.empty(3 * len(verts), dtype=np.float32)
    obj.data.vertices.foreach_get("co", co)
    turned = np.stack([verts[:, 0], -verts[:, 2], verts[:, 1]], axis=1)
    np.testing.assert_array_equal(co.reshape(-1, 3), turned)
    loops = np.empty(3 * len(faces), dtype=np.int32)
    obj.data.loops.foreach_get("vertex_index", loops)
    np.testing.assert_array_equal(loops.reshape(-1, 3), faces)
    # Materials: one per tag when the wheel names each face's tag.
    names = [m.name for m in obj.data.materials]
    if hasattr(model, "face_tags"):
        tags, tag_names = model.face_tags()
        assert sorted(names) == sorted({tag_names[t] for t in tags})
    else:
        assert names == ["genform"]
    assert obj["genform_summary"] == model.summary


def test_bush_is_one_object_with_the_default_granularity(empty):
    model = genform.load(BUSH).sample()
    _, faces = model.mesh()
    # Through the GLB (3,892 objects before granularity existed).
    bpy.context.scene.genform.import_mode = "GLTF"
    assert bpy.ops.genform.sample(grammar=str(BUSH), seed=0) == {"FINISHED"}
    objs = list(bpy.data.objects)
    assert [o.name for o in objs[:10]] == ["bush_3d_seed0"]
    assert sum(len(o.data.polygons) for o in objs) == len(faces)
    assert len(objs[0].data.materials) > 1, "a material per tag"
    # Straight from the arrays: one object too.
    bpy.context.scene.genform.import_mode = "MESH"
    assert bpy.ops.genform.sample(grammar=str(BUSH), seed=0) == {"FINISHED"}
    assert len(bpy.data.objects) == 2
    assert len(bpy.context.view_layer.objects.active.data.polygons) == len(faces)


def glb_materials(path) -> dict:
    """Material name → linear base colour (RGB) of a GLB file."""
    data = Path(path).read_bytes()
    (json_len,) = struct.unpack_from("<I", data, 12)
    materials = json.loads(data[20 : 20 + json_len])["materials"]
    return {m["name"].removesuffix(" (double-sided)"): m["pbrMetallicRoughness"]["baseColorFactor"][:3] for m in materials}


def test_tag_colours_match_the_glb_materials(empty, tmp_path):
    """The add-on takes genform's one tag palette and gives the GLB's colours."""
    path = tmp_path / "ship.glb"
    genform.load(SHIP).sample(seed=SHIP_SEED).save(path)
    materials = glb_materials(path)
    assert len(materials) >= 3
    srgb_to_linear = empty.build._srgb_to_linear
    for name, want in materials.items():
        got = [srgb_to_linear(c) for c in empty.build.tag_color(name)]
        assert np.allclose(got, want, atol=1e-4), name
    assert empty.build.tag_color("leaf#3a7d23") == pytest.approx((0x3A / 255, 0x7D / 255, 0x23 / 255))


def test_block_models_take_the_glbs_block_palette(empty, tmp_path):
    """Blocks come in the GLB's block colours (cobblestone grey, not a hashed hue)."""
    house = EXAMPLES / "boxsplit" / "house.bsg"
    path = tmp_path / "house.glb"
    genform.load(house).sample(seed=0).save(path)
    want = glb_materials(path)
    assert bpy.ops.genform.sample(grammar=str(house), seed=0) == {"FINISHED"}
    obj = bpy.context.view_layer.objects.active
    assert len(obj.data.materials) >= 2
    for mat in obj.data.materials:
        # The GLB names a block material by its id, without properties.
        glb = want[mat.name.split("[")[0]]
        base = empty.build.principled_bsdf(mat).inputs["Base Color"].default_value
        assert np.allclose(base[:3], glb, atol=1e-3), (mat.name, tuple(base), glb)
    cobble = genform.load(house).sample(seed=0)
    names = cobble.face_tags()[1]
    colours = dict(zip(names, cobble.tag_colors()))
    for name, (r, g, b) in colours.items():
        if name.startswith("minecraft:cobblestone"):
            assert max(r, g, b) - min(r, g, b) < 0.05, (name, r, g, b)


def test_the_spaceship_renders_in_colour(empty, tmp_path):
    """A tiny Cycles render (CPU, 4 samples) of the add-on's spaceship has at
    least 3 distinct clearly coloured (non-grey) pixel colours."""
    assert bpy.ops.genform.sample(grammar=str(SHIP), seed=SHIP_SEED) == {"FINISHED"}
    obj = bpy.context.view_layer.objects.active
    scene = bpy.context.scene
    stage_render([obj.matrix_world @ v.co for v in obj.data.vertices], (1.92, -2.56, 1.6), 96, 72)
    scene.render.filepath = str(tmp_path / "ship.png")
    bpy.ops.render.render(write_still=True)
    img = bpy.data.images.load(str(tmp_path / "ship.png"))
    px = np.array(img.pixels[:], dtype=np.float32).reshape(-1, 4)[:, :3]
    coloured = px[(px.max(axis=1) - px.min(axis=1)) > 0.12]
    distinct = {tuple(np.round(c * 4).astype(int)) for c in coloured}
    assert len(coloured) > 100 and len(distinct) >= 3, (scene.render.engine, len(coloured), distinct)


def test_evolve_imports_the_best_and_reports_progress(empty):
    result = bpy.ops.genform.evolve(scene_path=str(SHIP_SCENE), generations=2, population=12)
    assert result == {"FINISHED"}
    s = bpy.context.scene.genform
    assert s.progress == 1.0 and s.status.startswith("best fitness"), s.status
    best = bpy.context.view_layer.objects.active
    assert best.name.startswith("best_2gen_") and len(best.data.polygons) > 0


def test_a_run_on_a_thread_reports_progress_and_stops_on_request(empty):
    ops = empty.operators
    run = ops.Run(genform, str(SHIP_SCENE), "ga", 1, 3, 10)
    run.start()
    deadline = time.time() + 120
    while not run.done and time.time() < deadline:
        time.sleep(0.05)
    assert run.done and run.error is None, run.error
    assert (run.generation, run.fraction) == (3, 1.0)
    assert run.result.best is not None and run.result.generations == 3
    # Esc sets `cancel`: the run stops after the generation under way.
    stopped = ops.Run(genform, str(SHIP_SCENE), "ga", 1, 50, 10)
    stopped.cancel = True
    stopped.run()
    assert isinstance(stopped.error, ops.Cancelled) and stopped.generation == 0


def test_tiles4_imports_lying_flat_in_mesh_and_gltf_mode(empty):
    """HEMLS surfaces are +y up like every model, so Blender gets them flat."""
    tiles = EXAMPLES / "hemls" / "tiles4.gr8"
    for mode in ["MESH", "GLTF"]:
        for o in list(bpy.data.objects):
            bpy.data.objects.remove(o)
        bpy.context.scene.genform.import_mode = mode
        assert bpy.ops.genform.sample(grammar=str(tiles), seed=0) == {"FINISHED"}
        points = np.array(
            [o.matrix_world @ v.co for o in bpy.data.objects if o.type == "MESH" for v in o.data.vertices]
        )
        size = points.max(axis=0) - points.min(axis=0)
        assert size[0] > 1 and size[1] > 1 and size[2] < 1e-3, (mode, size)


def test_renders_get_the_tag_colours_through_the_principled_bsdf(empty):
    assert bpy.ops.genform.sample(grammar=str(SHIP), seed=SHIP_SEED) == {"FINISHED"}
    obj = bpy.context.view_layer.objects.active
    colours = set()
    for mat in obj.data.materials:
        bsdf = empty.build.principled_bsdf(mat)
        assert bsdf is not None, mat.name
        base = tuple(bsdf.inputs["Base Color"].default_value)
        assert base == pytest.approx(tuple(mat.diffuse_color)), mat.name
        assert bsdf.inputs["Roughness"].default_value == pytest.approx(0.8)
        colours.add(tuple(round(c, 3) for c in base[:3]))
    grey = {c for c in colours if max(c) - min(c) < 0.02}
    assert len(colours - grey) >= 3, colours


def test_graph_drawings_import_with_geometry(empty):
    """Koch (a graph grammar's drawing) comes in as flat ribbons, not an empty object."""
    koch = EXAMPLES / "graph" / "koch.gg.yaml"
    for mode in ["MESH", "GLTF"]:
        for o in list(bpy.data.objects):
            bpy.data.objects.remove(o)
        bpy.context.scene.genform.import_mode = mode
        assert bpy.ops.genform.sample(grammar=str(koch), seed=3) == {"FINISHED"}
        meshes = [o for o in bpy.data.objects if o.type == "MESH"]
        assert sum(len(o.data.polygons) for o in meshes) > 1000, mode
        points = np.array([o.matrix_world @ v.co for o in meshes for v in o.data.vertices])
        size = points.max(axis=0) - points.min(axis=0)
        # Drawn in genform's xy plane (+y up), so upright in Blender's xz.
        assert size[0] == pytest.approx(98.708, abs=0.05) and size[2] == pytest.approx(108.542, abs=0.05), (mode, size)
        assert size[1] < 1e-3, (mode, size)


def test_roof_planes_are_shaded_flat_at_their_ridges(empty):
    """A hip roof's planes meet at a crease: each plane keeps its own normal
    up to the ridge (split normals, as Blender's glTF importer gives), not
    a blotchy average over the shared vertices."""
    house = EXAMPLES / "shape" / "l_house.sg"  # hip roofs
    assert bpy.ops.genform.sample(grammar=str(house), seed=0) == {"FINISHED"}
    mesh = bpy.context.view_layer.objects.active.data
    n = len(mesh.polygons)
    face_normals = np.empty(3 * n, dtype=np.float32)
    mesh.polygons.foreach_get("normal", face_normals)
    face_normals = face_normals.reshape(-1, 3)
    corners = np.array([tuple(c.vector) for c in mesh.corner_normals], dtype=np.float32).reshape(-1, 3, 3)
    # Sloped faces (roof planes: neither walls nor flat): each corner's shading normal is the face's.
    sloped = np.flatnonzero((np.abs(face_normals[:, 2]) > 0.2) & (np.abs(face_normals[:, 2]) < 0.95))
    assert len(sloped) >= 4, "l_house has roofs"
    np.testing.assert_allclose(corners[sloped], np.repeat(face_normals[sloped, None, :], 3, axis=1), atol=1e-4)
    # So across a ridge (an edge of two sloped faces at a crease) the shading normals differ.
    edge_faces: dict = {}
    for f in sloped:
        for key in mesh.polygons[f].edge_keys:
            edge_faces.setdefault(key, []).append(f)
    ridges = [fs for fs in edge_faces.values() if len(fs) == 2 and face_normals[fs[0]] @ face_normals[fs[1]] < 0.95]
    assert ridges, "two roof planes meet at a ridge"
    for a, b in ridges:
        assert np.linalg.norm(corners[a, 0] - corners[b, 0]) > 0.1
    # Coplanar triangles of a wall stay one smooth plane (nothing marked sharp between them).
    sharp = mesh.attributes.get("sharp_edge")
    assert sharp is not None and 0 < sum(d.value for d in sharp.data) < len(mesh.edges)


def test_a_surfaces_typed_edges_come_as_coloured_tubes(empty, tmp_path):
    """Genr8/HEMLS surfaces bring their typed edges as a curve of thin
    tubes (loose edges would not render), a GLB-coloured material per type."""
    tiles = EXAMPLES / "hemls" / "tiles4.gr8"
    model = genform.load(tiles).sample(seed=0)
    points, edges, types, colours = model.surface_edges()
    assert points.shape[1] == 3 and edges.shape == (len(types), 2) and len(types) > 100
    assert set(colours) == set(types.tolist())
    model.save(tmp_path / "tiles.glb")
    glb = glb_materials(tmp_path / "tiles.glb")
    for mode in ["MESH", "GLTF"]:
        for o in list(bpy.data.objects):
            bpy.data.objects.remove(o)
        bpy.context.scene.genform.import_mode = mode
        assert bpy.ops.genform.sample(grammar=str(tiles), seed=0) == {"FINISHED"}
        curves = [o for o in bpy.data.objects if o.type == "CURVE"]
        assert len(curves) == 1, mode
        curve = curves[0]
        assert curve.parent is bpy.context.view_layer.objects.active and curve.select_get()
        assert curve.data.bevel_depth > 0 and len(curve.data.splines) == len(types)
        names = [m.name for m in curve.data.materials]
        assert sorted(names) == sorted(f"edge{k}" for k in set(types.tolist())), names
        for mat in curve.data.materials:
            base = empty.build.principled_bsdf(mat).inputs["Base Color"].default_value
            assert np.allclose(base[:3], glb[mat.name], atol=1e-3), (mat.name, tuple(base), glb[mat.name])
        # Real geometry (tubes), lying on the surface: flat like it.
        evaluated = curve.evaluated_get(bpy.context.evaluated_depsgraph_get())
        tubes = evaluated.to_mesh()
        assert len(tubes.polygons) > 4 * len(types), mode
        ends = np.array([curve.matrix_world @ p.co.xyz for s in curve.data.splines for p in s.points])
        surface = np.array([o.matrix_world @ v.co for o in bpy.data.objects if o.type == "MESH" for v in o.data.vertices])
        assert np.allclose(ends.min(axis=0), surface.min(axis=0), atol=1e-4), mode
        assert np.allclose(ends.max(axis=0), surface.max(axis=0), atol=1e-4), mode
        evaluated.to_mesh_clear()
    # Off in the panel: no curve.
    for o in list(bpy.data.objects):
        bpy.data.objects.remove(o)
    bpy.context.scene.genform.import_mode, bpy.context.scene.genform.edges = "MESH", False
    try:
        assert bpy.ops.genform.sample(grammar=str(tiles), seed=0) == {"FINISHED"}
        assert [o.type for o in bpy.data.objects] == ["MESH"]
    finally:
        bpy.context.scene.genform.edges = True


def test_the_panel_offers_the_scenes_algorithms_and_evolves_a_codon_scene(empty):
    """The algorithm list is the scene's (tree scenes: ga … map-elites,
    random; codon scenes: ge, random), its default chosen with the scene;
    a Genr8 codon scene evolves from the operator and its best comes in."""
    s = bpy.context.scene.genform
    canopy = EXAMPLES / "scenes" / "genr8_canopy.toml"
    items = lambda: [i[0] for i in empty._algorithm_items(s, bpy.context)]  # noqa: E731 - the enum's items
    s.scene_path = str(SHIP_SCENE)
    assert items() == ["ga", "mh", "smc", "sosmc", "hybrid", "map-elites", "random"] and s.algorithm == "ga"
    s.algorithm = "map-elites"
    s.scene_path = str(canopy)
    assert items() == ["ge", "random"] and s.algorithm == "ge"
    with pytest.raises(TypeError):
        s.algorithm = "ga"
    try:
        assert bpy.ops.genform.evolve(generations=2, population=12) == {"FINISHED"}
        assert s.status.startswith("best fitness"), s.status
        best = bpy.context.view_layer.objects.active
        assert best.name.startswith("best_2gen_") and len(best.data.polygons) > 0
        assert [o.parent for o in bpy.data.objects if o.type == "CURVE"] == [best], "its typed edges"
        # A tree algorithm named for a codon scene is refused, naming what it allows.
        with pytest.raises(RuntimeError, match="use ge, random"):
            bpy.ops.genform.evolve(generations=1, population=12, algorithm="ga")
    finally:
        s.scene_path = ""


@pytest.mark.parametrize("algorithm", ["map-elites", "smc", "mh"])
def test_the_panels_population_fits_every_tree_algorithm(empty, algorithm):
    """Population becomes each optimizer's own setting (batch, particles, chains)."""
    result = bpy.ops.genform.evolve(scene_path=str(SHIP_SCENE), generations=1, population=8, algorithm=algorithm)
    assert result == {"FINISHED"}
