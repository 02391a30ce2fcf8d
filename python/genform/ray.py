"""Evolution with each generation's batch scored as Ray tasks.

The optimizer stays on the driver (ask/tell, `genform.Optimizer`); each
batch is cut into chunks, one Ray task per chunk. A task either runs the
scene's Rust scorers (`Scene.score_genomes`, in parallel inside the worker)
or calls your Python `fitness` on the chunk's models. Since the optimizer
only sees the scores, in order, the result equals `genform.evolve` with the
same seed and settings. Workers load the scene and grammar by path, so on
a real cluster the files must be at the same path on every node (a shared
folder, or Ray's `runtime_env={"working_dir": ...}` with relative paths).
"""

from __future__ import annotations

import math
import os
import time
from typing import Any, Callable

import ray

import genform


@ray.remote
def _score_scene(scene: genform.Scene, genomes: list[str]) -> list[tuple[float, float, float]]:
    return scene.score_genomes(genomes)


@ray.remote
def _score_python(
    fitness: Callable[[genform.Model], Any], scene: genform.Scene, genomes: list[str]
) -> list[Any]:
    return [fitness(scene.derive(g)) for g in genomes]


def _chunks(items: list, n: int) -> list[list]:
    return [items[i : i + n] for i in range(0, len(items), n)]


def evolve(
    scene,
    algorithm: str = "ga",
    seed: int = 0,
    generations: int | None = None,
    evaluations: int | None = None,
    budget=None,
    fitness: Callable[[genform.Model], Any] | None = None,
    chunk: int | None = None,
    progress: Callable[[dict], Any] | None = None,
    **settings: Any,
) -> genform.RunResult:
    """Runs `algorithm` on `scene` with every batch scored by Ray tasks.

    `fitness`: a Python callable on models (default: the scene's own
    fitness, computed in Rust inside the workers). `chunk`: models per task
    (default: the batch split evenly over the cluster's CPUs). Stops like
    `genform.evolve` (generations, evaluations, budget; else the scene's
    `[run]`). Call `ray.init(...)` first to choose the cluster; without it
    Ray starts a local one.
    """
    scene = scene if isinstance(scene, genform.Scene) else genform.load_scene(os.fspath(scene))
    if generations is None and evaluations is None and budget is None:
        raise genform.GenformError("ray.evolve(): give generations, evaluations or budget")
    if isinstance(budget, str):
        budget = _seconds(budget)
    opt = genform.Optimizer(
        scene, algorithm, seed=seed, generations=generations, evaluations=evaluations, budget=budget, **settings
    )
    if not ray.is_initialized():
        ray.init()
    scene_ref = ray.put(scene)
    fitness_ref = ray.put(fitness) if fitness is not None else None
    cpus = max(1, int(ray.cluster_resources().get("CPU", 1)))
    start = time.monotonic()
    stopped_by = None
    while stopped_by is None:
        if opt.is_initialized and generations is not None and opt.generation >= generations:
            stopped_by = "generations"
        elif opt.is_initialized and evaluations is not None and opt.evaluations >= evaluations:
            stopped_by = "evaluations"
        elif budget is not None and time.monotonic() - start >= budget:
            stopped_by = "budget"
        if stopped_by:
            break
        # Genomes travel as JSON; the workers derive the models themselves.
        genomes = opt.ask_genomes()
        size = chunk or max(1, math.ceil(len(genomes) / cpus))
        if fitness_ref is None:
            futures = [_score_scene.remote(scene_ref, c) for c in _chunks(genomes, size)]
        else:
            futures = [_score_python.remote(fitness_ref, scene_ref, c) for c in _chunks(genomes, size)]
        scores = [s for part in ray.get(futures) for s in part]
        row = opt.tell(scores)
        if row is not None:
            row["seconds"] = time.monotonic() - start
            if progress is not None:
                progress(row)
    return genform.RunResult(
        opt.best,
        opt.best_fitness,
        opt.stats,
        None,
        opt.generation,
        opt.evaluations,
        stopped_by,
        time.monotonic() - start,
    )


def _seconds(text: str) -> float:
    units = {"ms": 0.001, "s": 1, "m": 60, "h": 3600}
    for unit in sorted(units, key=len, reverse=True):
        if text.endswith(unit):
            return float(text[: -len(unit)]) * units[unit]
    return float(text)
