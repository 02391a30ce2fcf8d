"""Measures what Ray adds per generation (docs/benchmarks.md).

Runs the spaceship scene for GENERATIONS generations four ways: genform.evolve
in one process, ask/tell in one process with the scene's Rust scorer, and
genform.ray.evolve on a local cluster with the Rust scorer and with a
do-nothing Python fitness. Prints seconds per generation of each; Ray's
overhead per generation is the difference to the one-process ask/tell run.

    python examples/python/ray_overhead.py [CPUS] [GENERATIONS] [POPULATION]
"""

import sys
import time
from pathlib import Path

import ray

import genform

ROOT = Path(__file__).resolve().parents[2]
SCENE = ROOT / "examples/scenes/spaceship_volume.toml"
cpus = int(sys.argv[1]) if len(sys.argv) > 1 else 2
generations = int(sys.argv[2]) if len(sys.argv) > 2 else 20
population = int(sys.argv[3]) if len(sys.argv) > 3 else 150
settings = dict(population=population, elitism=population // 5)


def timed(label, fn):
    t = time.perf_counter()
    r = fn()
    per = (time.perf_counter() - t) / (generations + 1)
    print(f"{label:<38} {per * 1000:8.1f} ms/generation  best {r.best_fitness:.4f}")
    return per, r


def ask_tell():
    scene = genform.load_scene(SCENE)
    opt = genform.Optimizer(scene, "ga", seed=1, generations=generations, **settings)
    while not (opt.is_initialized and opt.generation >= generations):
        opt.tell([s[0] for s in scene.score_genomes(opt.ask_genomes())])
    return genform.RunResult(opt.best, opt.best_fitness, opt.stats, None, opt.generation, opt.evaluations, "", 0.0)


def zero(model):
    return 0.0


print(f"{population} individuals, {generations + 1} generations, Ray with {cpus} CPUs")
local, a = timed("genform.evolve (threads=%d)" % cpus, lambda: genform.evolve(SCENE, seed=1, generations=generations, threads=cpus, **settings))
at, b = timed("ask/tell, Rust scorer, one process", ask_tell)
ray.init(num_cpus=cpus, include_dashboard=False, log_to_driver=False)
genform.ray.evolve(SCENE, seed=1, generations=1, **settings)  # warm the workers
rr, c = timed("ray.evolve, Rust scorer", lambda: genform.ray.evolve(SCENE, seed=1, generations=generations, **settings))
rp, _ = timed("ray.evolve, Python fitness returning 0", lambda: genform.ray.evolve(SCENE, seed=1, generations=generations, fitness=zero, **settings))
assert a.best_fitness == b.best_fitness == c.best_fitness
print(f"Ray overhead per generation (Rust scorer): {(rr - at) * 1000:.1f} ms; with pickled models: {rp * 1000:.1f} ms")
