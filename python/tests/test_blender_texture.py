"""A textured building in Blender: examples/shape/textured_house.sg saved
as a GLB by the wheel, imported by Blender's own glTF importer (under `bpy`,
Blender as a Python module) and rendered small with Cycles on the CPU.

The render must show the textures: brick-red pixels and the fine contrast
of mortar and tile joints, where the same render with the image nodes
unlinked (the materials' flat white base colour) shows neither.

Skipped, with the reason printed, where `bpy` cannot be imported (its
wheels exist for one CPython minor only).
"""

from __future__ import annotations

import atexit
import os
import shutil
import sys
import tempfile

import numpy as np
import pytest

if "BLENDER_USER_RESOURCES" not in os.environ:
    os.environ["BLENDER_USER_RESOURCES"] = tempfile.mkdtemp(prefix="genform-blender-")
    atexit.register(shutil.rmtree, os.environ["BLENDER_USER_RESOURCES"], ignore_errors=True)

try:
    import bpy
except ImportError as e:
    REASON = f"bpy (Blender as a Python module) cannot be imported ({e}) on CPython {sys.version_info[:2]}"
    print(f"test_blender_texture.py skipped: {REASON}")
    pytest.skip(REASON, allow_module_level=True)

import genform
from conftest import EXAMPLES, stage_render

HOUSE = EXAMPLES / "shape" / "textured_house.sg"


def render(path) -> np.ndarray:
    """Renders the current scene to `path`; its pixels as rows of RGB (0–1)."""
    bpy.context.scene.render.filepath = str(path)
    bpy.ops.render.render(write_still=True)
    img = bpy.data.images.load(str(path))
    try:
        w, h = img.size
        return np.array(img.pixels[:], dtype=np.float32).reshape(h, w, 4)[:, :, :3]
    finally:
        bpy.data.images.remove(img)


def looks(px: np.ndarray) -> tuple[float, float]:
    """(share of brick-red pixels, mean contrast between neighbouring pixels)."""
    r, g, b = px[..., 0], px[..., 1], px[..., 2]
    red = float(((r > 0.08) & (r > 1.6 * g) & (r > 1.6 * b)).mean())
    lum = px.mean(axis=2)
    contrast = float(np.abs(np.diff(lum, axis=0)).mean() + np.abs(np.diff(lum, axis=1)).mean())
    return red, contrast


def test_the_textured_house_renders_with_its_textures(tmp_path):
    for collection in (bpy.data.objects, bpy.data.meshes, bpy.data.materials, bpy.data.images, bpy.data.cameras, bpy.data.lights):
        for item in list(collection):
            collection.remove(item)
    glb = tmp_path / "house.glb"
    genform.load(HOUSE).sample(seed=0).save(glb)
    assert bpy.ops.import_scene.gltf(filepath=str(glb)) == {"FINISHED"}
    meshes = [o for o in bpy.data.objects if o.type == "MESH"]
    assert meshes and all(len(o.data.uv_layers) == 1 for o in meshes), "TEXCOORD_0 became a UV map"
    # The importer built image nodes from the embedded PNGs.
    images = {}
    for m in bpy.data.materials:
        for node in m.node_tree.nodes if m.node_tree else []:
            if node.type == "TEX_IMAGE" and node.image is not None:
                images[m.name.removesuffix(" (double-sided)")] = tuple(node.image.size)
    assert images == {"wall@brick": (128, 128), "roof@roof_tiles": (64, 64)}, images

    # Close enough that a brick course covers about two pixels.
    stage_render(np.array([o.matrix_world @ v.co for o in meshes for v in o.data.vertices]), (1.0, -1.3, 0.6), 160, 120)

    red, contrast = looks(render(tmp_path / "textured.png"))
    for m in bpy.data.materials:
        if m.node_tree:
            for link in list(m.node_tree.links):
                if link.from_node.type == "TEX_IMAGE":
                    m.node_tree.links.remove(link)
    flat_red, flat_contrast = looks(render(tmp_path / "flat.png"))
    print(f"textured: {red:.3f} red, contrast {contrast:.4f}; flat: {flat_red:.3f} red, contrast {flat_contrast:.4f}")
    assert red > 0.25 and flat_red < 0.01, (red, flat_red)
    assert contrast > 2.5 * flat_contrast, (contrast, flat_contrast)
