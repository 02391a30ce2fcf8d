"""The Blender 4.2+ extension package (scripts/blender-extension): built
from the wheel under test, its layout and manifest checked, and, under
`bpy`, installed through Blender's own extension installer (offline: the
package brings its wheel)."""

from __future__ import annotations

import os
import subprocess
import sys
import tomllib
import zipfile
from pathlib import Path

import pytest

from conftest import ROOT


@pytest.fixture(scope="module")
def package(tmp_path_factory) -> Path:
    """The extension zip, built from the wheel scripts/test-python made
    ($GENFORM_WHEELS names its folder)."""
    wheels = sorted(Path(os.environ.get("GENFORM_WHEELS", "/nonexistent")).glob("genform-*.whl"))
    if not wheels:
        pytest.skip("no genform wheel: run through scripts/test-python (it sets GENFORM_WHEELS)")
    out = tmp_path_factory.mktemp("ext") / "genform-blender.zip"
    script = ROOT / "scripts" / "blender-extension"
    subprocess.run([sys.executable, str(script), str(wheels[0]), str(out)], check=True, capture_output=True)
    return out


def test_the_package_holds_the_addon_its_manifest_and_the_wheel(package):
    z = zipfile.ZipFile(package)
    names = set(z.namelist())
    addon = {f.name for f in (ROOT / "python" / "genform_blender").glob("*.py")}
    assert addon <= names and "__init__.py" in names
    m = tomllib.loads(z.read("blender_manifest.toml").decode())
    # What Blender's manifest schema 1.0.0 requires, as its validator checks.
    for key in ["schema_version", "id", "version", "name", "tagline", "maintainer", "type", "blender_version_min", "license"]:
        assert key in m, key
    assert m["type"] == "add-on" and m["id"].isidentifier()
    assert len(m["tagline"]) <= 64 and m["tagline"][-1] not in ".!?"
    assert tuple(int(x) for x in m["blender_version_min"].split(".")) >= (4, 2, 0)
    assert all(lic.startswith("SPDX:") for lic in m["license"])
    assert all(not text.endswith(".") for text in m["permissions"].values())
    # The wheel is there, listed relative, and holds the extension module.
    assert len(m["wheels"]) == 1 and m["wheels"][0].startswith("./wheels/genform-")
    wheel = m["wheels"][0][2:]
    assert wheel in names
    assert m["platforms"] and all("-" in p for p in m["platforms"])
    import io

    inner = zipfile.ZipFile(io.BytesIO(z.read(wheel))).namelist()
    assert any(n.startswith("genform/_genform") for n in inner), inner[:10]
    assert m["version"] == wheel.split("-")[1]


def test_blender_installs_the_package_offline(package):
    bpy = pytest.importorskip("bpy", reason="bpy (Blender as a Python module) is not installed")
    if not hasattr(bpy.ops.extensions, "package_install_files"):
        pytest.skip("this bpy has no extension installer (Blender < 4.2)")
    try:
        result = bpy.ops.extensions.package_install_files(
            filepath=str(package), repo="user_default", enable_on_install=True
        )
    except RuntimeError as e:
        pytest.skip(f"bpy's extension installer refused to run headless: {e}")
    assert result == {"FINISHED"}
    import addon_utils

    assert addon_utils.check("bl_ext.user_default.genform") == (True, True)
    module = sys.modules["bl_ext.user_default.genform"]
    assert module.build.tag_color("leaf#3a7d23") == pytest.approx((0x3A / 255, 0x7D / 255, 0x23 / 255))
    bpy.ops.preferences.addon_disable(module="bl_ext.user_default.genform")
