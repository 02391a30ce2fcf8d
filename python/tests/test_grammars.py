"""Every formalism loads and samples; meshes match the OBJ files; saving
writes every format; errors are exceptions with positions."""

from __future__ import annotations

import subprocess
from collections import Counter

import numpy as np
import pytest

import genform
from conftest import EXAMPLES, SAMPLES


def read_obj(path):
    """(vertices, triangles of the `f` elements, fan-split) of an OBJ file."""
    verts, faces = [], []
    for line in open(path):
        parts = line.split()
        if not parts:
            continue
        if parts[0] == "v":
            verts.append([float(x) for x in parts[1:4]])
        elif parts[0] == "f":
            idx = [int(p.split("/")[0]) - 1 for p in parts[1:]]
            faces.append(idx)
    return np.array(verts, dtype=np.float64).reshape(-1, 3), faces


def test_every_formalism_has_an_example_that_loads_and_samples():
    rows = genform.formalisms()
    assert {ext for r in rows for ext in r["extensions"]} >= set(SAMPLES)
    for ext, path in SAMPLES.items():
        g = genform.load(path)
        assert g.path.endswith(path.name)
        assert g.info().strip(), ext
        m = g.sample(seed=3)
        assert m.summary
        v, f = m.mesh()
        assert v.dtype == np.float32 and v.ndim == 2 and v.shape[1] == 3, ext
        assert f.dtype == np.uint32 and f.ndim == 2 and f.shape[1] == 3, ext
        assert f.size == 0 or f.max() < len(v), ext
        # The same seed gives the same model.
        v2, f2 = g.sample(seed=3).mesh()
        assert np.array_equal(v, v2) and np.array_equal(f, f2), ext


def canonical(tri):
    """A triangle as a tuple of points, rotated to start at its smallest (winding kept)."""
    i = tri.index(min(tri))
    return tri[i:] + tri[:i]


@pytest.mark.parametrize("ext", [".sg", ".ls", ".bsg", ".gr8", ".gg.yaml"])
def test_mesh_arrays_match_the_obj_file(tmp_path, ext):
    # koch_snowflake.ls draws lines only; bush_3d.ls has faces.
    path, options = SAMPLES[ext], {}
    if ext == ".ls":
        path, options = SAMPLES[ext].parent / "bush_3d.ls", {"steps": 2}
    m = genform.load(path).sample(seed=5, **options)
    v, f = m.mesh()
    assert 0 < len(f) and len(v) < 20000
    out = tmp_path / "m.obj"
    assert m.save(out)[0] == str(out)
    ov, ofaces = read_obj(out)
    # Same points, in any order: ours printed as the OBJ prints them (6 decimals).
    ours_pts = [tuple(float(f"{c:.6f}") for c in p) for p in v.tolist()]
    obj_pts = [tuple(p) for p in ov.tolist()]
    assert sorted(ours_pts) == sorted(obj_pts)
    ours = Counter(canonical(tuple(ours_pts[i] for i in t)) for t in f.tolist())
    theirs = Counter(canonical(tuple(obj_pts[i] for i in x)) for x in ofaces if len(x) == 3)
    # Every OBJ triangle is one of ours, as often; n-gons are split into at
    # most n - 2 (triangles of collinear corners are left out).
    assert not theirs - ours
    ngons = [x for x in ofaces if len(x) > 3]
    assert sum(theirs.values()) < len(f) <= sum(theirs.values()) + sum(len(x) - 2 for x in ngons) or not ngons


def test_sampled_models_equal_the_cli_sample(tmp_path, cli):
    if cli is None:
        pytest.skip("the genform binary is not built")
    for ext in [".sg", ".ls", ".gr8"]:
        path = SAMPLES[ext]
        m = genform.load(path).sample(seed=7)
        # Same names in two folders: an OBJ names its .mtl by name.
        (tmp_path / "py").mkdir(exist_ok=True)
        (tmp_path / "cli").mkdir(exist_ok=True)
        ours, theirs = tmp_path / "py" / f"m{ext}.obj", tmp_path / "cli" / f"m{ext}.obj"
        m.save(ours)
        args = [cli, "sample", str(path), "--seed", "7", "--out", str(theirs)]
        if m.genome is not None:
            args += ["--genome-out", str(tmp_path / "g.json")]
        subprocess.run(args, check=True, capture_output=True)
        assert ours.read_bytes() == theirs.read_bytes(), ext
        assert ours.with_suffix(".mtl").read_bytes() == theirs.with_suffix(".mtl").read_bytes(), ext
        v, _ = m.mesh()
        assert np.allclose(read_obj(theirs)[0], v, atol=1e-5)


def test_genomes_are_json_and_derive_the_same_model():
    import json

    g = genform.load(SAMPLES[".sg"])
    m = g.sample(seed=15)
    assert g.has_generator
    text = json.dumps(m.genome)
    again = g.derive(json.loads(text))
    assert np.array_equal(again.mesh()[0], m.mesh()[0])
    assert g.derive(m.genome_json()).genome == m.genome
    # Formalisms without a generator graph have no genome.
    assert genform.load(SAMPLES[".gg.yaml"]).sample(seed=1).genome is None


def test_save_writes_every_cli_format(tmp_path):
    m = genform.load(SAMPLES[".sg"]).sample(seed=2)
    for ext in ["obj", "glb", "ply", "stl", "png", "svg"]:
        out = tmp_path / f"m.{ext}"
        written = m.save(out)
        assert out.stat().st_size > 100, ext
        # An OBJ brings its material library, named relative in `mtllib`.
        assert written == ([str(out), str(tmp_path / "m.mtl")] if ext == "obj" else [str(out)]), ext
    assert "mtllib m.mtl" in (tmp_path / "m.obj").read_text()
    assert "newmtl" in (tmp_path / "m.mtl").read_text()
    png = m.png(64, 48)
    assert png[:8] == b"\x89PNG\r\n\x1a\n"
    assert m._repr_png_()[:4] == b"\x89PNG"
    # A formalism's own formats go through it: graph grammars write YAML.
    g = genform.load(SAMPLES[".gg.yaml"]).sample(seed=1)
    g.save(tmp_path / "g.yaml")
    assert "vertices" in (tmp_path / "g.yaml").read_text()
    with pytest.raises(genform.GenformError, match="use one of the extensions"):
        m.save(tmp_path / "m.dae")


def test_sample_options_follow_the_cli():
    ls = genform.load(SAMPLES[".ls"])
    short, long = ls.sample(seed=1, steps=2), ls.sample(seed=1, steps=3)
    assert len(short.mesh()[0]) < len(long.mesh()[0])
    with pytest.raises(genform.GenformError, match="--box applies to box-split grammars"):
        genform.load(SAMPLES[".sg"]).sample(seed=1, box="0,0,0,9,9,9")
    with pytest.raises(genform.GenformError, match="unknown option `colour`"):
        ls.sample(colour=1)


def test_sample_reads_other_footprints_as_the_cli_does(tmp_path, cli):
    """`footprints` is one of the options the table gives every door."""
    block = genform.load(EXAMPLES / "shape" / "city_block.sg")
    lots = tmp_path / "two.geojson"
    lots.write_text(
        '{"type": "FeatureCollection", "features": ['
        '{"type": "Feature", "geometry": {"type": "Polygon", "coordinates": [[[0, 0], [10, 0], [10, 8], [0, 8], [0, 0]]]}},'
        '{"type": "Feature", "geometry": {"type": "Polygon", "coordinates": [[[20, 0], [30, 0], [30, 4], [20, 4], [20, 0]]]}}]}'
    )
    own, two = block.sample(seed=3), block.sample(seed=3, footprints=str(lots))
    xs = two.mesh()[0][:, 0]
    assert 29.5 < xs.max() < 30.5 and -0.5 < xs.min() < 0.5, "the lots stand where the file puts them"
    assert own.triangle_count() != two.triangle_count()
    if cli is not None:
        (tmp_path / "py").mkdir()
        (tmp_path / "cli").mkdir()
        two.save(tmp_path / "py" / "b.obj")
        args = [cli, "sample", str(EXAMPLES / "shape" / "city_block.sg"), "--seed", "3"]
        args += ["--footprints", str(lots), "--out", str(tmp_path / "cli" / "b.obj")]
        subprocess.run(args, check=True, capture_output=True)
        assert (tmp_path / "py" / "b.obj").read_bytes() == (tmp_path / "cli" / "b.obj").read_bytes()


def test_compile_errors_carry_positions_and_hints(tmp_path):
    bad = tmp_path / "bad.sg"
    bad.write_text("Start {\n  boxx;\n}\n")
    with pytest.raises(genform.GenformError) as info:
        genform.load(bad)
    e = info.value
    assert "1 error in" in str(e)
    [d] = e.diagnostics
    assert (d.file, d.line, d.column, d.severity) == (str(bad), 2, 3, "error")
    assert "boxx" in d.message
    assert any("box" in h for h in d.hints)
    assert str(d).startswith(f"{bad}:2:3: error:")
    with pytest.raises(genform.GenformError, match="don't know the grammar format") as info:
        genform.load(tmp_path / "house.dae")
    assert info.value.diagnostics == []


def test_face_tags_name_the_tag_of_every_face():
    ship = genform.load(SAMPLES[".sg"]).sample(seed=15)
    _, faces = ship.mesh()
    tags, names = ship.face_tags()
    assert len(tags) == len(faces)
    used = {names[t] for t in tags}
    # The spaceship's boxes come from its body, top and wing rules.
    assert "Body" in used and len(used) >= 2, used
    # Box-split blocks are grouped by block state after the scene's tags.
    blocks = genform.load(SAMPLES[".bsg"]).sample(seed=1)
    btags, bnames = blocks.face_tags()
    assert len(btags) == len(blocks.mesh()[1])
    assert any(":" in bnames[t] for t in btags), bnames


def test_block_models_count_their_triangles_and_have_bounds():
    blocks = genform.load(SAMPLES[".bsg"]).sample(seed=1)
    v, f = blocks.mesh()
    assert len(f) > 0 and blocks.triangle_count() == len(f)
    lo, hi = blocks.bounds()
    assert np.allclose(lo, v.min(axis=0)) and np.allclose(hi, v.max(axis=0))
    assert all(h > l for l, h in zip(lo, hi))


def test_surfaces_are_y_up_in_mesh_bounds_and_every_file(tmp_path):
    tiles = genform.load(SAMPLES[".gr8"]).sample()
    v, _ = tiles.mesh()
    size = v.max(axis=0) - v.min(axis=0)
    assert size[0] > 1 and size[2] > 1 and size[1] < 1e-4, size
    lo, hi = tiles.bounds()
    assert np.allclose(lo, v.min(axis=0)) and np.allclose(hi, v.max(axis=0))
    ov, _ = read_obj(tiles.save(tmp_path / "t.obj")[0])
    assert np.allclose(ov.min(axis=0), v.min(axis=0), atol=1e-5) and np.allclose(ov.max(axis=0), v.max(axis=0), atol=1e-5)


def test_drawings_are_flat_ribbons_in_mesh_and_every_file(tmp_path):
    """Graph-grammar drawings and 2D L-systems have faces: strokes as ribbons."""
    for path in [SAMPLES[".gg.yaml"], SAMPLES[".ls"]]:
        m = genform.load(path).sample(seed=3)
        v, f = m.mesh()
        assert len(f) > 100 and m.triangle_count() == len(f), path.name
        # One stroke colour: every polygon on z = 0, facing the SVG's viewer.
        assert np.all(v[:, 2] == 0), path.name
        a, b, c = v[f[:, 0]], v[f[:, 1]], v[f[:, 2]]
        assert np.all(np.cross(b - a, c - a)[:, 2] > 0), path.name
        lo, hi = m.bounds()
        assert np.allclose(lo, v.min(axis=0)) and np.allclose(hi, v.max(axis=0))
        for ext in ["obj", "glb", "ply", "stl"]:
            out = tmp_path / f"d.{ext}"
            assert m.save(out)[0] == str(out) and out.stat().st_size > 1000, (path.name, ext)
        ov, faces = read_obj(tmp_path / "d.obj")
        assert len(faces) > 0 and np.allclose(ov.min(axis=0), lo, atol=1e-5)
    # The Koch graph: its extreme points widened by half the 0.6 stroke, up
    # to the caps' octagon (45° steps turned with each edge), which may fall
    # short of the round cap by 0.3 * (1 - cos 22.5°).
    lo, hi = genform.load(SAMPLES[".gg.yaml"]).sample(seed=3).bounds()
    tol = 0.01 + 0.3 * (1 - np.cos(np.pi / 8))
    assert np.allclose(lo, (-4.354, -30.3, 0), atol=tol) and np.allclose(hi, (94.354, 78.242, 0), atol=tol)


@pytest.mark.parametrize("name", ["l_house", "office_block", "infill"])
def test_building_grammars_sample_closed_roofs_and_polygons(name):
    # The polygon operations (shapeL/U, offset, setback, context) work
    # through Python unchanged: a model with triangles, the same per seed.
    from conftest import EXAMPLES

    g = genform.load(EXAMPLES / "shape" / f"{name}.sg")
    v, f = g.sample(seed=2).mesh()
    assert len(f) > 20 and np.isfinite(v).all(), name
    v2, f2 = g.sample(seed=2).mesh()
    assert np.array_equal(v, v2) and np.array_equal(f, f2), name


def test_a_model_is_never_saved_over_the_files_its_grammar_reads(tmp_path):
    import shutil

    shutil.copy(EXAMPLES / "shape" / "tree_v1.sg", tmp_path / "tree_v1.sg")
    shutil.copytree(EXAMPLES / "shape" / "assets", tmp_path / "assets")
    trunk = (tmp_path / "assets" / "trunk.obj").read_bytes()
    m = genform.load(tmp_path / "tree_v1.sg").sample(seed=1)
    with pytest.raises(genform.GenformError, match="would replace the mesh"):
        m.save(tmp_path / "assets" / ".." / "assets" / "trunk.obj")
    assert (tmp_path / "assets" / "trunk.obj").read_bytes() == trunk
    m.save(tmp_path / "tree.obj")


def test_every_ply_genform_writes_opens_in_trimesh(tmp_path):
    """An independent reader: trimesh opens every formalism's PLY as a
    mesh, and a Genr8 surface's typed edges travel beside it."""
    import trimesh

    for ext, path in SAMPLES.items():
        m = genform.load(path).sample(seed=1)
        out = tmp_path / f"m{ext.replace('.', '_')}.ply"
        m.save(out)
        mesh = trimesh.load(out, process=False)
        v, f = m.mesh()
        if len(f):
            assert isinstance(mesh, trimesh.Trimesh), ext
            assert len(mesh.faces) >= len(f) // 2, ext
        if ext == ".gr8":
            edges = mesh.metadata["_ply_raw"]["surface_edge"]["data"]
            assert len(edges) > 0 and set(edges.dtype.names) == {"vertex1", "vertex2", "type"}
            assert edges["vertex1"].max() < len(mesh.vertices)


def test_surface_edges_are_the_surfaces_typed_edges_on_the_mesh_points():
    """`Model.surface_edges()`: a Genr8 surface's typed edges over the same
    (+y up) points as `mesh()`, each type with its GLB colour; nothing for
    models without surfaces."""
    m = genform.load(SAMPLES[".gr8"]).sample(seed=0)
    points, edges, types, colours = m.surface_edges()
    assert points.dtype == np.float32 and edges.dtype == np.uint32 and types.dtype == np.int32
    assert points.shape[1] == 3 and edges.shape == (len(types), 2) and len(types) > 100
    assert edges.max() < len(points) and (edges[:, 0] != edges[:, 1]).all()
    # The surface's points are the mesh's (its only geometry), in order.
    v, _ = m.mesh()
    np.testing.assert_array_equal(points, v[: len(points)])
    assert set(colours) == set(types.tolist()) and all(t >= -1 for t in colours)
    assert all(len(c) == 3 and all(0 <= x <= 1 for x in c) for c in colours.values())
    assert len(set(colours.values())) == len(colours), "a colour per type"
    p, e, t, c = genform.load(SAMPLES[".sg"]).sample(seed=0).surface_edges()
    assert (p.shape, e.shape, t.shape, c) == ((0, 3), (0, 2), (0,), {})
