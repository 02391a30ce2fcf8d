"""Ray: a local two-CPU cluster gives the same run as one process."""

from __future__ import annotations

import pytest

import genform
from conftest import SHIP_SCENE

ray = pytest.importorskip("ray")

SMALL = dict(population=16, elitism=4, initial_length=[10, 20])


@pytest.fixture(scope="module")
def cluster():
    ray.init(num_cpus=2, include_dashboard=False, log_to_driver=False, configure_logging=False)
    yield
    ray.shutdown()


def test_ray_evolve_equals_the_single_process_run(cluster):
    direct = genform.evolve(SHIP_SCENE, seed=3, generations=3, threads=1, **SMALL)
    distributed = genform.ray.evolve(SHIP_SCENE, seed=3, generations=3, **SMALL)
    assert distributed.stopped_by == "generations" and distributed.generations == 3
    assert distributed.best_fitness == direct.best_fitness
    assert distributed.best.genome == direct.best.genome
    keys = ["generation", "best", "max", "avg", "min", "invalid", "total_evaluations"]
    assert [[s[k] for k in keys] for s in distributed.stats] == [[s[k] for k in keys] for s in direct.stats]


def test_ray_with_a_python_fitness_equals_local_ask_tell(cluster):
    def tall(model):
        lo, hi = model.bounds()
        return hi[1] - lo[1]

    distributed = genform.ray.evolve(SHIP_SCENE, seed=5, generations=2, fitness=tall, chunk=5, **SMALL)
    opt = genform.Optimizer(SHIP_SCENE, seed=5, generations=2, **SMALL)
    while not (opt.is_initialized and opt.generation >= 2):
        opt.tell([tall(m) for m in opt.ask()])
    assert distributed.best.genome == opt.best.genome
    assert distributed.best_fitness == opt.best_fitness
