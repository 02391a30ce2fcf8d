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
