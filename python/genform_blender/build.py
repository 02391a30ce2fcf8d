"""Turning a genform model into Blender objects.

Two ways in:

- ``build_object`` (the default): one mesh object straight from
  ``Model.mesh()``, so its vertex and face counts are exactly the arrays'
  (triangles; lines contribute loose points). One material per tag when the
  model can say which tag each face has (``Model.face_tags()``), else one
  material for the whole model. Shaded as Blender's glTF importer shades:
  flat where faces meet at a crease (over ``SHARP_ANGLE``: a hip roof's
  ridges, a box's edges), smooth across gentler bends.
- ``import_gltf``: the model saved as GLB (its default granularity: one
  merged object above a few dozen primitives, one object per primitive
  below) and read by Blender's glTF importer; materials come from the GLB,
  vertices are split where flat-shaded normals differ.

- ``build_edges``: a surface's typed edges (Genr8/HEMLS growth,
  ``Model.surface_edges()``) as one curve object of thin tubes, a material
  per edge type in the GLB's ``edge<N>`` colours, so renders show them
  (Cycles does not render a mesh's loose edges).

Nothing here registers classes: the operators call these functions.
"""

from __future__ import annotations

import math
import os
import tempfile

import bpy
import numpy as np


# Faces meeting at a larger angle than this are shaded flat on either side
# of their edge (auto smooth by angle, as Blender's glTF importer gives).
SHARP_ANGLE = math.radians(30.0)


def tag_color(name: str) -> tuple[float, float, float]:
    """The display colour of a tag as sRGB in [0, 1]: the colour the GLB
    materials and the previews use, from the wheel's one palette
    (``genform.tag_color``, i.e. ``genform_export::tag_color``), not a copy."""
    import genform

    return tuple(genform.tag_color(name))


def tag_material(name: str, rgb: tuple[float, float, float] | None = None) -> bpy.types.Material:
    """The material of a tag or block state: reused by name when it exists
    (so edits a user made to it carry over to the next sample), else a new
    one in ``rgb`` (sRGB in [0, 1]; the tag palette's colour when not
    given), roughness 0.8 as in the GLB."""
    mat = bpy.data.materials.get(name)
    if mat is not None:
        return mat
    mat = bpy.data.materials.new(name)
    r, g, b = rgb if rgb is not None else tag_color(name)
    # Material.diffuse_color is linear; the viewport shows it converted.
    linear = (*(_srgb_to_linear(c) for c in (r, g, b)), 1.0)
    mat.diffuse_color = linear
    mat.roughness = 0.8
    mat.metallic = 0.0
    # Renders (Cycles, EEVEE) read the Principled BSDF, not diffuse_color.
    bsdf = principled_bsdf(mat)
    if bsdf is not None:
        bsdf.inputs["Base Color"].default_value = linear
        bsdf.inputs["Roughness"].default_value = 0.8
        bsdf.inputs["Metallic"].default_value = 0.0
    return mat


def principled_bsdf(mat: bpy.types.Material):
    """The material's Principled BSDF node (its node tree made when it has
    none), or None when Blender gives it no such node."""
    if mat.node_tree is None:
        try:
            mat.use_nodes = True  # deprecated in Blender 5 (node trees always there), needed before
        except (AttributeError, TypeError):
            pass
    tree = mat.node_tree
    if tree is None:
        return None
    return next((n for n in tree.nodes if n.type == "BSDF_PRINCIPLED"), None)


def _srgb_to_linear(c: float) -> float:
    return c / 12.92 if c <= 0.04045 else ((c + 0.055) / 1.055) ** 2.4


def face_tags(model, face_count: int) -> tuple[np.ndarray, list[str], list]:
    """(tag index per face of ``Model.mesh()``, tag names, their colours:
    sRGB in [0, 1] from ``Model.tag_colors()``, the GLB's tag and block
    palettes; None where the wheel cannot say); one unnamed group
    ``genform`` when the model cannot tell (older wheels without
    ``Model.face_tags``)."""
    if hasattr(model, "face_tags"):
        tags, names = model.face_tags()
        tags = np.asarray(tags, dtype=np.int32)
        if len(tags) == face_count:
            colors = list(model.tag_colors()) if hasattr(model, "tag_colors") else [None] * len(names)
            return tags, list(names), colors
    return np.zeros(face_count, dtype=np.int32), ["genform"], [None]


def build_object(model, name: str, collection=None, y_up: bool = True) -> bpy.types.Object:
    """One mesh object holding ``model.mesh()`` exactly: a vertex per row of
    the vertex array, a triangle per row of the face array, in their order.
    With ``y_up`` genform's +y becomes Blender's +z (a rotation, as Blender's
    glTF and OBJ importers do), so models stand upright."""
    verts, faces = model.mesh()
    verts = np.asarray(verts, dtype=np.float32).reshape(-1, 3)
    faces = np.asarray(faces, dtype=np.int32).reshape(-1, 3)
    if y_up:
        verts = np.stack([verts[:, 0], -verts[:, 2], verts[:, 1]], axis=1)
    tags, names, colors = face_tags(model, len(faces))
    # Only the tags in use become material slots, in order of first use.
    used, slot_of = [], {}
    for t in tags:
        if t not in slot_of:
            slot_of[t] = len(used)
            used.append(t)
    slots = np.array([slot_of[t] for t in tags], dtype=np.int32) if len(tags) else tags

    mesh = bpy.data.meshes.new(name)
    mesh.vertices.add(len(verts))
    mesh.vertices.foreach_set("co", np.ascontiguousarray(verts, dtype=np.float32).ravel())
    mesh.loops.add(3 * len(faces))
    mesh.loops.foreach_set("vertex_index", faces.ravel())
    mesh.polygons.add(len(faces))
    mesh.polygons.foreach_set("loop_start", np.arange(0, 3 * len(faces), 3, dtype=np.int32))
    mesh.polygons.foreach_set("material_index", slots)
    mesh.update(calc_edges=True)
    shade_by_angle(mesh)
    for t in used:
        mesh.materials.append(tag_material(names[t], colors[t]))

    obj = bpy.data.objects.new(name, mesh)
    (collection or bpy.context.scene.collection).objects.link(obj)
    return obj


def shade_by_angle(mesh: bpy.types.Mesh, angle: float = SHARP_ANGLE) -> None:
    """Smooth shading with split normals at creases: edges whose faces meet
    at more than ``angle`` are marked sharp (Blender 4.1+:
    ``Mesh.set_sharp_from_angle``; before it, auto smooth). A mesh built
    from arrays is otherwise smooth over every shared vertex, which washes
    out a roof's ridges and a box's edges."""
    if hasattr(mesh, "set_sharp_from_angle"):
        mesh.set_sharp_from_angle(angle=angle)
        return
    mesh.polygons.foreach_set("use_smooth", np.ones(len(mesh.polygons), dtype=bool))
    if hasattr(mesh, "use_auto_smooth"):  # Blender < 4.1
        mesh.use_auto_smooth = True
        mesh.auto_smooth_angle = angle
    else:
        mesh.polygons.foreach_set("use_smooth", np.zeros(len(mesh.polygons), dtype=bool))


def edge_material(kind: int, rgb: tuple[float, float, float]) -> bpy.types.Material:
    """The material of surface edges of type ``kind`` (-1: untyped), named
    as the GLB names it (``edge<N>``, ``edge_untyped``)."""
    return tag_material("edge_untyped" if kind < 0 else f"edge{kind}", rgb)


def surface_edges(model):
    """``Model.surface_edges()``: (positions, edges, types, colours), or
    None when the model has no typed edges or the wheel cannot say."""
    if not hasattr(model, "surface_edges"):
        return None
    points, edges, types, colors = model.surface_edges()
    if len(edges) == 0:
        return None
    return (
        np.asarray(points, dtype=np.float32).reshape(-1, 3),
        np.asarray(edges, dtype=np.int64).reshape(-1, 2),
        np.asarray(types, dtype=np.int32),
        dict(colors),
    )


def build_edges(model, name: str, collection=None, y_up: bool = True, radius: float | None = None):
    """A surface's typed edges as one curve object: a two-point poly spline
    per edge, beveled into a tube (``radius``; default: 6% of the median
    edge length), a material per edge type in the GLB's colours. None when
    the model has no surface edges."""
    got = surface_edges(model)
    if got is None:
        return None
    points, edges, types, colors = got
    if y_up:
        points = np.stack([points[:, 0], -points[:, 2], points[:, 1]], axis=1)
    ends = points[edges]  # (M, 2, 3)
    lengths = np.linalg.norm(ends[:, 1] - ends[:, 0], axis=1)
    if radius is None:
        positive = lengths[lengths > 0]
        radius = 0.06 * float(np.median(positive)) if len(positive) else 0.01
    kinds = sorted(set(types.tolist()), key=lambda k: (k < 0, k))  # untyped last, as the GLB
    slot = {k: i for i, k in enumerate(kinds)}

    curve = bpy.data.curves.new(name, type="CURVE")
    curve.dimensions = "3D"
    curve.bevel_depth = radius
    curve.bevel_resolution = 2
    curve.use_fill_caps = True
    for k in kinds:
        curve.materials.append(edge_material(k, colors.get(k, (0.44, 0.44, 0.44))))
    for (a, b), k in zip(ends, types.tolist()):
        spline = curve.splines.new("POLY")
        spline.points.add(1)  # a new spline has one point
        spline.points.foreach_set("co", [*a, 1.0, *b, 1.0])
        spline.material_index = slot[k]
    obj = bpy.data.objects.new(name, curve)
    obj["genform_edge_types"] = [int(k) for k in kinds]
    (collection or bpy.context.scene.collection).objects.link(obj)
    return obj


def import_gltf(model, collection=None) -> list[bpy.types.Object]:
    """The model saved as GLB and read by Blender's glTF importer; returns
    the objects it made (linked into ``collection`` too when given)."""
    before = set(bpy.data.objects)
    with tempfile.TemporaryDirectory(prefix="genform-") as tmp:
        path = os.path.join(tmp, "model.glb")
        model.save(path)
        bpy.ops.import_scene.gltf(filepath=path)
    made = [o for o in bpy.data.objects if o not in before]
    if collection is not None:
        for o in made:
            if collection not in o.users_collection:
                collection.objects.link(o)
    return made
