"""The sidebar panel (3D view, N, tab "genform")."""

from __future__ import annotations

import bpy


class GENFORM_PT_panel(bpy.types.Panel):
    """Sample a grammar; evolve for a scene and import the best."""

    bl_label = "genform"
    bl_idname = "GENFORM_PT_panel"
    bl_space_type = "VIEW_3D"
    bl_region_type = "UI"
    bl_category = "genform"

    def draw(self, context):
        s = context.scene.genform
        layout = self.layout

        box = layout.box()
        box.label(text="Sample", icon="MESH_DATA")
        box.prop(s, "grammar_path")
        row = box.row(align=True)
        row.prop(s, "seed")
        row.prop(s, "import_mode", text="")
        row = box.row(align=True)
        if s.import_mode == "MESH":
            row.prop(s, "y_up")
        row.prop(s, "edges")
        box.operator("genform.sample", icon="PLAY")

        box = layout.box()
        box.label(text="Evolve", icon="MOD_PARTICLES")
        box.prop(s, "scene_path")
        box.prop(s, "algorithm")
        row = box.row(align=True)
        row.prop(s, "generations")
        row.prop(s, "population")
        col = box.column()
        col.enabled = not s.running
        col.operator("genform.evolve", icon="EXPERIMENTAL")
        if s.running or s.status:
            if hasattr(box, "progress"):  # UILayout.progress: Blender 4.0+
                box.progress(factor=s.progress, type="BAR", text=s.status or "")
            else:
                box.prop(s, "progress", slider=True)
                box.label(text=s.status)
