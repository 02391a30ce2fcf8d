"""The notebook-style example runs end to end."""

from __future__ import annotations

import runpy

from conftest import ROOT


def test_notebook_example_runs(tmp_path, monkeypatch):
    monkeypatch.setenv("GENFORM_NOTEBOOK_OUT", str(tmp_path))
    runpy.run_path(str(ROOT / "examples" / "python" / "notebook.py"), run_name="__main__")
    for name in ["ship.glb", "ship.png", "ship-run/run.json", "ship-run/best.obj", "own-fitness.obj"]:
        assert (tmp_path / name).is_file(), name
