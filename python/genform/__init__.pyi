"""Type stubs for genform: grammar-based procedural modeling and evolution.

The package is a thin layer over the Rust library crates (the same code the
``genform`` command line runs); see docs/python.md.
"""

from __future__ import annotations

import os
from typing import Any, Callable, Mapping, Sequence, Union

import numpy as np
import numpy.typing as npt

from . import lpy as lpy
from . import ray as ray

__version__: str

PathLike = Union[str, "os.PathLike[str]"]
#: What ``Optimizer.tell`` takes per model: a fitness, or a fitness and the
#: two behaviour descriptors MAP-Elites bins by.
Score = Union[float, tuple[float, float, float]]

class Diagnostic:
    """One located message of a grammar or scene file."""

    file: str
    line: int  # 1-based; 0 when the message has no position
    column: int  # 1-based, in characters; 0 when the message has no position
    severity: str  # "error", "warning" or "note"
    message: str
    hints: list[str]
    def __str__(self) -> str: ...  # "FILE:LINE:COL: error: MESSAGE"

class GenformError(Exception):
    """Every error genform raises: the message of the whole error chain and,
    for files that failed to compile, their diagnostics."""

    diagnostics: list[Diagnostic]

def formalisms() -> list[dict[str, Any]]:
    """The formalisms genform loads: ``{"name", "extensions"}`` per row."""

def tag_color(name: str) -> tuple[float, float, float]:
    """A tag's display colour as sRGB in [0, 1] (the GLB's and the previews'
    palette: a trailing `#rrggbb` wins, else a hash of the name)."""

def load(path: PathLike) -> Grammar:
    """Compiles a grammar file; its formalism follows the extension
    (.sg .ls .bsg .gg.yaml .gr8). Raises GenformError with diagnostics."""

def load_scene(path: PathLike) -> Scene:
    """Loads an evolution scene (a TOML scene config) with its grammar and
    targets."""

class Grammar:
    """A compiled grammar of any formalism."""

    path: str
    name: str
    formalism: str  # e.g. "shape grammar", "L-system"
    has_generator: bool  # whether genomes (derive, evolve, ask/tell) apply
    def info(self) -> str:
        """What `genform info` prints."""
    def sample(self, seed: int = 0, **options: Any) -> Model:
        """Draws one model. Options are `genform sample`'s flags without the
        dashes (steps, max_modules, max_genes, max_depth, max_primitives,
        footprints, box, world, env, smooth, every_step, ...); a flag another formalism
        owns raises GenformError. Grammars with a generator graph give a
        model with a genome; the same seed gives the same model as the CLI."""
    def derive(self, genome: Mapping[str, Any] | str) -> Model:
        """Expresses a genome (the dict of ``Model.genome`` or its JSON
        text, as `genform sample --genome-out` writes it)."""

class Model:
    """One derived model."""

    genome: dict[str, Any] | None  # JSON-able; None for formalisms without genomes
    summary: str
    def genome_json(self) -> str | None: ...
    def mesh(self) -> tuple[npt.NDArray[np.float32], npt.NDArray[np.uint32]]:
        """(vertices (N, 3) float32, faces (M, 3) uint32, counter-clockwise
        seen from outside): the points and faces of the OBJ file
        `save("x.obj")` writes (n-gons split into triangles; the order may
        differ). Lines have no faces; their points are among the vertices."""
    def face_tags(self) -> tuple[npt.NDArray[np.uint32], list[str]]:
        """(index into the names per face of `mesh()`, in its order; the names:
        the scene's tags, then one per block state), e.g. for one material per tag."""
    def tag_colors(self) -> list[tuple[float, float, float]]:
        """The display colour (sRGB in [0, 1]) of each name of `face_tags()`:
        the GLB materials' colours, block states in the block palette."""
    def surface_edges(
        self,
    ) -> tuple[
        npt.NDArray[np.float32],
        npt.NDArray[np.uint32],
        npt.NDArray[np.int32],
        dict[int, tuple[float, float, float]],
    ]:
        """A grown surface's typed edges (Genr8/HEMLS): (points (N, 3)
        float32, +y up as in `mesh()`, every surface's one after the other;
        edges (M, 2) uint32 into them; their types (M,) int32, -1 untyped;
        {type: colour (sRGB in [0, 1])} for the types in use: the GLB's
        `edge<N>` materials' colours). Empty without surfaces."""
    def triangle_count(self) -> int: ...
    def bounds(self) -> tuple[tuple[float, float, float], tuple[float, float, float]] | None: ...
    def save(self, path: PathLike) -> list[str]:
        """Writes the model in the format the extension names (every format
        `genform sample --out` writes: .obj .glb .ply .stl .png .svg and the
        formalism's own); returns the files written."""
    def png(self, width: int = 512, height: int = 512) -> bytes:
        """A shaded preview as PNG bytes."""
    def _repr_png_(self) -> bytes: ...

class Scene:
    """An evolution scene: a grammar, targets and fitness settings. The
    built-in scorers are callables: ``scene.fitness(model)``."""

    path: str
    grammar: Grammar
    algorithms: list[str]  # the algorithms that can evolve it, its default first
    @staticmethod
    def algorithms_for(path: PathLike) -> list[str]:
        """The `evolve()` algorithms that can evolve the scene config at
        `path`, tree or codon scene (which `load_scene` does not open), its
        default first: ga, mh, smc, sosmc, hybrid, map-elites, random for
        tree scenes; ge, random for codon scenes."""
    def fitness(self, model: Model) -> float:
        """The scene's fitness of a model (NaN: invalid)."""
    def counts(self, model: Model) -> dict[str, float]:
        """The voxel/pixel counts behind the fitness (good, bad, overlap,
        outside, target) and `fitness`."""
    def components(self, model: Model) -> list[dict[str, Any]]:
        """The named parts of the fitness, one dict each: `name`, `value`
        (what it adds), `weight`, `max` (the most it can add), `measure`
        and, for criteria, `target`."""
    def derive(self, genome: Mapping[str, Any] | str) -> Model:
        """Expresses a genome under the scene's limits."""
    def score_genomes(self, genomes: Sequence[str]) -> list[tuple[float, float, float]]:
        """(fitness, descriptor 0, descriptor 1) for genome JSON texts, in
        parallel: what Ray workers run."""
    def __call__(self, model: Model) -> float: ...

class RunResult:
    """What `evolve` returns."""

    best: Model | None
    best_fitness: float
    stats: list[dict[str, Any]]  # one dict per generation (pandas.DataFrame(stats))
    out: str | None  # the run folder, as `genform evolve --out` writes it
    generations: int
    evaluations: int
    stopped_by: str  # "generations", "budget", "evaluations" or "interrupted"
    seconds: float

def evolve(
    scene: PathLike | Scene,
    algorithm: str | None = None,
    seed: int = 0,
    budget: str | float | None = None,
    generations: int | None = None,
    evaluations: int | None = None,
    threads: int | None = None,
    out: PathLike | None = None,
    progress: Callable[[dict[str, Any]], Any] | None = None,
    **settings: Any,
) -> RunResult:
    """Runs an optimizer on a scene (tree or codon scene) through the same
    run loop as `genform evolve`, writing the same run folder when `out` is
    given. `algorithm`: ga for tree scenes, ge for codon scenes by default.
    `**settings`: scene settings, `population=20` (the algorithm's table) or
    `ga={...}`, `surface={...}` (any table), applied like `--set`. Ctrl-C stops
    it after the current generation (stopped_by == "interrupted"); an
    exception raised by `progress` stops it and propagates."""

class Optimizer:
    """Ask/tell over any algorithm, for a fitness computed elsewhere (Python,
    Ray workers). Same seed and same scores give the same sequence."""

    algorithm: str
    generation: int
    evaluations: int
    best: Model | None
    best_fitness: float
    best_genome_json: str | None
    is_initialized: bool  # whether generation 0 is complete
    stats: list[dict[str, Any]]
    def __init__(
        self,
        target: Grammar | Scene | PathLike,
        algorithm: str = "ga",
        seed: int = 0,
        generations: int | None = None,
        evaluations: int | None = None,
        budget: str | float | None = None,
        **settings: Any,
    ) -> None:
        """`target`: a grammar or scene (a path loads either; a scene brings
        its settings and limits). `settings`: keys of the algorithm's section
        of a scene config (population=…, elitism=…) or whole sections
        (ga={…}, mh={…}). `generations`/`evaluations`/`budget`: the stop
        rules the caller will use (only the hybrid plans with them)."""
    def ask(self) -> list[Model]:
        """The models to score next (the same list until `tell`)."""
    def ask_genomes(self) -> list[str]:
        """The genomes of `ask` as JSON texts, without deriving the models
        (for scorers that derive them elsewhere: `Scene.score_genomes`,
        `Scene.derive`, Ray workers)."""
    def tell(self, scores: Sequence[Score]) -> dict[str, Any] | None:
        """Scores for the models of `ask`, in order; returns the
        generation's statistics when it completed, None when the algorithm
        needs another batch for it."""
