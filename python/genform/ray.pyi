from __future__ import annotations

from typing import Any, Callable

from . import Model, PathLike, RunResult, Scene

def evolve(
    scene: PathLike | Scene,
    algorithm: str = "ga",
    seed: int = 0,
    generations: int | None = None,
    evaluations: int | None = None,
    budget: str | float | None = None,
    fitness: Callable[[Model], float] | None = None,
    chunk: int | None = None,
    progress: Callable[[dict[str, Any]], Any] | None = None,
    **settings: Any,
) -> RunResult:
    """Evolution with each generation's batch scored as Ray tasks (the
    scene's Rust scorers, or `fitness` on models); the optimizer stays on
    the driver, so the result equals `genform.evolve` with the same seed."""
