"""genform for Blender: sample grammar models and evolve them from the 3D
view's sidebar (N panel, tab "genform").

A legacy add-on (``bl_info``), which Blender 4.2 and later, 5.0 included,
still install from a zip (Preferences > Add-ons > Install from Disk) and
which ``bpy`` from PyPI registers headless. It needs the ``genform``
Python package in Blender's Python; see docs/python.md.
"""

from __future__ import annotations

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

ALGORITHMS = [
    ("ga", "GA", "Genetic algorithm"),
    ("mh", "MH", "Metropolis–Hastings"),
    ("smc", "SMC", "Sequential Monte Carlo"),
    ("sosmc", "SOSMC", "Stochastically ordered SMC"),
    ("hybrid", "Hybrid", "SMC then GA"),
    ("random", "Random", "Random search"),
]


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
    scene_path: StringProperty(name="Scene", subtype="FILE_PATH", description="Evolution scene config (.toml)")
    algorithm: EnumProperty(name="Algorithm", items=ALGORITHMS, default="ga")
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
