"""Shared fixtures: the repository's examples, the CLI binary when built."""

from __future__ import annotations

import os
import shutil
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[2]
EXAMPLES = ROOT / "examples"

# One small example per formalism (extension → file); test_formalisms checks
# that every row of genform.formalisms() has one.
SAMPLES = {
    ".sg": EXAMPLES / "shape" / "spaceship.sg",
    ".ls": EXAMPLES / "lsystem" / "koch_snowflake.ls",
    ".bsg": EXAMPLES / "boxsplit" / "house.bsg",
    ".gg.yaml": EXAMPLES / "graph" / "koch.gg.yaml",
    ".gr8": EXAMPLES / "hemls" / "tiles4.gr8",
}

SHIP_SCENE = EXAMPLES / "scenes" / "spaceship_volume.toml"


@pytest.fixture(scope="session")
def cli() -> str | None:
    """The `genform` binary: $GENFORM_BIN, target/{debug,release}/genform, or PATH."""
    candidates = [os.environ.get("GENFORM_BIN")]
    target = Path(os.environ.get("CARGO_TARGET_DIR", ROOT / "target"))
    candidates += [str(target / "debug" / "genform"), str(target / "release" / "genform"), shutil.which("genform")]
    for c in candidates:
        if c and Path(c).is_file() and os.access(c, os.X_OK):
            return c
    return None


def stage_render(points, offset, width: int, height: int) -> None:
    """Readies Blender's current scene for a small render of `points`
    (world positions, rows of xyz): a camera at the points' centre plus
    `offset` times their radius, looking at the centre, a sun, Cycles on the
    CPU at 4 samples without denoising (EEVEE where Cycles is missing),
    `width` × `height` PNG. Imports `bpy` itself: only Blender tests call it.
    """
    import bpy
    import numpy as np
    from mathutils import Vector

    scene = bpy.context.scene
    lo, hi = np.min(points, axis=0), np.max(points, axis=0)
    centre, radius = (lo + hi) / 2, float(np.linalg.norm(hi - lo)) / 2
    cam = bpy.data.objects.new("cam", bpy.data.cameras.new("cam"))
    scene.collection.objects.link(cam)
    cam.location = Vector(centre) + Vector(offset) * radius
    cam.rotation_euler = (Vector(centre) - cam.location).to_track_quat("-Z", "Y").to_euler()
    scene.camera = cam
    sun = bpy.data.objects.new("sun", bpy.data.lights.new("sun", "SUN"))
    sun.data.energy = 4.0
    sun.rotation_euler = (0.6, 0.2, 0.8)
    scene.collection.objects.link(sun)
    try:
        scene.render.engine = "CYCLES"
    except TypeError:
        # A bpy build without Cycles: its engines list names EEVEE's.
        engines = {e.identifier for e in bpy.types.RenderSettings.bl_rna.properties["engine"].enum_items}
        scene.render.engine = next(e for e in engines if e.startswith("BLENDER_EEVEE"))
    if scene.render.engine == "CYCLES":
        scene.cycles.device = "CPU"
        scene.cycles.samples = 4
        scene.cycles.use_denoising = False
    scene.render.resolution_x, scene.render.resolution_y, scene.render.resolution_percentage = width, height, 100
    scene.render.image_settings.file_format = "PNG"
