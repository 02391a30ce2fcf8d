"""genform: grammar-based procedural modeling and evolution.

A thin layer over the Rust library crates (the code the ``genform`` command
line runs): load grammars of every formalism, sample and derive models, get
their meshes as NumPy arrays, save them in every format the CLI writes, run
evolutions, or drive an optimizer by ask/tell with a fitness of your own.
See docs/python.md.
"""

from __future__ import annotations

import functools
import os

from ._genform import (
    Diagnostic,
    GenformError,
    Grammar,
    Model,
    Optimizer,
    RunResult,
    Scene,
    __version__,
    derive_with_limits,
    evolve,
    formalisms,
    load,
    load_scene,
    tag_color,
)

__all__ = [
    "Diagnostic",
    "GenformError",
    "Grammar",
    "Model",
    "Optimizer",
    "RunResult",
    "Scene",
    "__version__",
    "evolve",
    "formalisms",
    "load",
    "load_scene",
    "tag_color",
]

# GenformError always has a `diagnostics` list (empty unless a file failed to compile).
GenformError.diagnostics = []


@functools.lru_cache(maxsize=16)
def _cached_grammar(path: str) -> Grammar:
    return load(path)


@functools.lru_cache(maxsize=16)
def _cached_scene(path: str) -> Scene:
    """A scene loaded once per process (Ray workers unpickle scenes by path)."""
    return load_scene(path)


def _model_from_genome(path: str, genome: str, limits: tuple[int, int, int]) -> Model:
    """Unpickles a model: its grammar (loaded once per process) derives the genome again."""
    return derive_with_limits(_cached_grammar(os.fspath(path)), genome, limits)


def __getattr__(name: str):
    # `genform.ray` imports Ray only when used; `genform.lpy` is L-Py's files with Python.
    if name in ("ray", "lpy"):
        import importlib

        return importlib.import_module("." + name, __name__)
    raise AttributeError(f"module 'genform' has no attribute {name!r}")
