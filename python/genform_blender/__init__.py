"""genform for Blender: sample grammar models and evolve them from the 3D
view's sidebar (N panel, tab "genform").

A legacy add-on (``bl_info``), which Blender 4.2 and later, 5.0 included,
still install from a zip (Preferences > Add-ons > Install from Disk) and
which ``bpy`` from PyPI registers headless. It needs the ``genform``
Python package in Blender's Python; see docs/python.md.
"""

from __future__ import annotations

import os

import bpy
from bpy.props import BoolProperty, EnumProperty, FloatProperty, IntProperty, PointerProperty, StringProperty

from . import build, operators, panel

bl_info = {
    "name": "genform",
    "author": "genform",
    "version": (0, 1, 0),
    "blender": (4, 2, 0),
    "location": "View3D > Sidebar > genform",
    "description": "Grammar-based procedural models: sample a grammar, run an evolution, import the best",
    "category": "Add Mesh",
}

# Labels and descriptions of the optimizer table's names (genform evolve
# --algorithm); which of them a scene allows comes from the wheel.
ALGORITHMS = {
    "ga": ("GA", "Genetic algorithm"),
    "mh": ("MH", "Metropolis–Hastings"),
    "smc": ("SMC", "Sequential Monte Carlo"),
    "sosmc": ("SOSMC", "Stochastically ordered SMC"),
    "hybrid": ("Hybrid", "SMC then GA"),
    "map-elites": ("MAP-Elites", "Quality-diversity archive over two descriptors"),
    "ge": ("GE", "Grammatical evolution over codon genomes (codon scenes: .bnf, .bsg, .gg.yaml grammars)"),
    "random": ("Random", "Random search"),
}

_scene_algorithms_cache: dict = {}
# Blender keeps only pointers to the enum items' strings: they must outlive
# the callback, so the last lists returned are kept here.
_items_alive: dict = {}


def scene_algorithms(path: str) -> list[str]:
    """The algorithms that can evolve the scene config at ``path``, its
    default first (``genform.Scene.algorithms_for``: tree scenes ga … random,
    codon scenes ge, random); every name when the path or the wheel cannot
    say (no scene chosen yet, an older wheel)."""
    try:
        key = (path, os.path.getmtime(path))
    except OSError:
        return list(ALGORITHMS)
    if key not in _scene_algorithms_cache:
        try:
            import genform

            names = list(genform.Scene.algorithms_for(path))
        except Exception:  # noqa: BLE001 - no wheel, old wheel, broken scene: the evolve operator reports it
            names = list(ALGORITHMS)
        _scene_algorithms_cache[key] = names or list(ALGORITHMS)
    return _scene_algorithms_cache[key]


def _algorithm_items(self, context):
    path = bpy.path.abspath(self.scene_path) if self.scene_path else ""
    names = scene_algorithms(path)
    items = [(n, *ALGORITHMS.get(n, (n, n))) for n in names]
    _items_alive[path] = items
    return items


def _scene_changed(self, context):
    # The scene's default algorithm (its first) for a newly chosen scene.
    path = bpy.path.abspath(self.scene_path) if self.scene_path else ""
    self.algorithm = scene_algorithms(path)[0]


class GenformSettings(bpy.types.PropertyGroup):
    """The panel's settings, one set per Blender scene."""

    grammar_path: StringProperty(name="Grammar", subtype="FILE_PATH", description=".sg .ls .bsg .gg.yaml .gr8 file")
    seed: IntProperty(name="Seed", default=0, min=0, description="Random seed: the same seed gives the same model")
    import_mode: EnumProperty(
        name="Import",
        items=[
            ("MESH", "Mesh", "One object straight from Model.mesh(), one material per tag"),
            ("GLTF", "glTF", "The model's GLB through Blender's glTF importer (merged above 32 primitives)"),
        ],
        default="MESH",
    )
    y_up: BoolProperty(name="Y up", default=True, description="Turn genform's +y into Blender's +z (Mesh import)")
    edges: BoolProperty(
        name="Typed edges",
        default=True,
        description="A grown surface's typed edges as thin tubes in their type's colour (a curve object)",
    )
    scene_path: StringProperty(
        name="Scene", subtype="FILE_PATH", description="Evolution scene config (.toml)", update=_scene_changed
    )
    algorithm: EnumProperty(
        name="Algorithm",
        items=_algorithm_items,
        default=0,
        description="The optimizers that can evolve the scene (tree scenes: ga … random; codon scenes: ge, random)",
    )
    generations: IntProperty(name="Generations", default=20, min=1)
    population: IntProperty(
        name="Population", default=0, min=0, description="0: the scene config's; GA: elitism becomes a fifth of it"
    )
    running: BoolProperty(default=False, options={"SKIP_SAVE"})
    progress: FloatProperty(name="Progress", default=0.0, min=0.0, max=1.0, subtype="FACTOR", options={"SKIP_SAVE"})
    status: StringProperty(default="", options={"SKIP_SAVE"})


classes = (GenformSettings, *operators.classes, panel.GENFORM_PT_panel)


def register():
    for cls in classes:
        bpy.utils.register_class(cls)
    bpy.types.Scene.genform = PointerProperty(type=GenformSettings)


def unregister():
    del bpy.types.Scene.genform
    for cls in reversed(classes):
        bpy.utils.unregister_class(cls)


__all__ = ["bl_info", "build", "register", "unregister"]
