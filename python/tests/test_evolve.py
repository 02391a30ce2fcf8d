"""genform.evolve, ask/tell determinism, built-in scorers as callables."""

from __future__ import annotations

import json
import math

import pytest

import genform
from conftest import SHIP_SCENE

# A small, fast version of the spaceship experiment.
SMALL = dict(population=16, elitism=4, initial_length=[10, 20])


def test_evolve_returns_stats_best_and_the_run_folder(tmp_path):
    seen = []
    r = genform.evolve(SHIP_SCENE, seed=1, generations=3, threads=2, out=tmp_path / "run", progress=seen.append, **SMALL)
    assert r.stopped_by == "generations" and r.generations == 3
    assert [s["generation"] for s in r.stats] == [0, 1, 2, 3]
    assert seen == r.stats
    assert r.stats[-1]["best"] == r.best_fitness
    assert all(b["best"] <= a["best"] for b, a in zip(r.stats, r.stats[1:]))
    assert r.evaluations == r.stats[-1]["total_evaluations"]
    scene = genform.load_scene(SHIP_SCENE)
    assert scene.fitness(r.best) == r.best_fitness
    names = ["stats.csv", "best-genome.json", "best.glb", "best.obj", "best.png", "run.json", "gallery.png"]
    for name in names + ["evolution.png", "best-model.png"]:
        assert (tmp_path / "run" / name).is_file(), name
    run = json.loads((tmp_path / "run" / "run.json").read_text())
    assert run["best_fitness"] == r.best_fitness and run["config"]["ga"]["population"] == 16
    assert json.loads((tmp_path / "run" / "best-genome.json").read_text()) == r.best.genome


def test_the_run_folder_has_what_the_cli_writes_for_image_scenes_and_map_elites(tmp_path):
    skyline = SHIP_SCENE.parent / "city_skyline.toml"
    genform.evolve(skyline, seed=1, generations=2, threads=2, out=tmp_path / "sky", population=12, elitism=2)
    assert (tmp_path / "sky" / "best-silhouette.png").read_bytes()[1:4] == b"PNG"
    genform.evolve(SHIP_SCENE, algorithm="map-elites", seed=1, evaluations=400, out=tmp_path / "me", initial=40, batch=40)
    assert (tmp_path / "me" / "archive.csv").read_text().count("\n") >= 2
    assert (tmp_path / "me" / "archive.png").is_file() and any((tmp_path / "me" / "elites").iterdir())


def test_same_seed_same_run_at_any_thread_count():
    a = genform.evolve(SHIP_SCENE, seed=4, generations=2, threads=1, **SMALL)
    b = genform.evolve(SHIP_SCENE, seed=4, generations=2, threads=2, **SMALL)
    strip = lambda rows: [{k: v for k, v in r.items() if "seconds" not in k} for r in rows]  # noqa: E731
    assert strip(a.stats) == strip(b.stats)
    assert a.best.genome == b.best.genome


def test_a_failing_progress_callable_stops_the_run():
    def progress(row):
        if row["generation"] == 1:
            raise RuntimeError("enough")

    with pytest.raises(RuntimeError, match="enough"):
        genform.evolve(SHIP_SCENE, seed=1, generations=50, progress=progress, **SMALL)


def test_settings_are_checked_like_the_scene_file():
    with pytest.raises(genform.GenformError, match="population"):
        genform.evolve(SHIP_SCENE, generations=1, populaton=3)
    with pytest.raises(genform.GenformError, match="unknown algorithm `gaa`"):
        genform.evolve(SHIP_SCENE, algorithm="gaa", generations=1)


def python_fitness(model):
    """A fitness of the user's own: tall models with few triangles."""
    b = model.bounds()
    if b is None:
        return -math.inf
    (lo, hi) = b
    return (hi[1] - lo[1]) - 0.001 * model.triangle_count()


def drive(opt, generations, fitness):
    asked = []
    while not (opt.is_initialized and opt.generation >= generations):
        batch = opt.ask()
        asked.append([m.genome_json() for m in batch])
        opt.tell([fitness(m) for m in reversed(batch)][::-1])
    return asked


def test_ask_tell_same_seed_same_scores_same_sequence():
    grammar = genform.load(SHIP_SCENE.parent / "../shape/spaceship.sg")
    runs = [drive(genform.Optimizer(grammar, "ga", seed=9, **SMALL), 3, python_fitness) for _ in range(2)]
    assert runs[0] == runs[1]
    other = drive(genform.Optimizer(grammar, "ga", seed=10, **SMALL), 3, python_fitness)
    assert other != runs[0]


def test_ask_is_stable_until_tell_and_tell_checks_the_count():
    opt = genform.Optimizer(SHIP_SCENE, "ga", seed=1, **SMALL)
    a, b = opt.ask(), opt.ask()
    assert [m.genome_json() for m in a] == [m.genome_json() for m in b] and len(a) == 16
    with pytest.raises(genform.GenformError, match="got 2 scores for the 16 models"):
        opt.tell([1.0, 2.0])
    stats = opt.tell([float(i) for i in range(16)])
    assert stats["generation"] == 0 and stats["max"] == 15.0 and opt.best_fitness == 15.0


def test_small_populations_keep_a_fifth_as_elites_and_breed_the_rest():
    grammar = genform.load(SHIP_SCENE.parent / "../shape/spaceship.sg")
    for population, children in [(20, 16), (40, 32), (10, 8)]:
        opt = genform.Optimizer(grammar, "ga", seed=1, population=population, initial_length=[10, 20])
        opt.tell([python_fitness(m) for m in opt.ask()])
        assert len(opt.ask()) == children, population
    with pytest.raises(genform.GenformError, match=r"elitism \(30\) must be smaller than the population \(20\)"):
        genform.Optimizer(grammar, "ga", population=20, elitism=30)


@pytest.mark.parametrize(
    "call",
    [
        lambda g: g.sample(seed=1, steps=-1),
        lambda g: g.sample(seed=-1),
        lambda g: g.sample(seed=1, max_genes=2**70),
        lambda g: g.sample(seed=1, every_step="yes"),
        lambda g: g.sample(seed=1).png(width=-5),
        lambda g: genform.Optimizer(g, "ga", seed=-3),
        lambda g: genform.Optimizer(g, "ga", generations=-1),
        lambda g: genform.evolve(SHIP_SCENE, generations=-1),
    ],
)
def test_bad_numbers_raise_genform_errors(call):
    grammar = genform.load(SHIP_SCENE.parent / "../shape/spaceship.sg")
    with pytest.raises(genform.GenformError, match="expected|`every_step`|must be a whole number"):
        call(grammar)


@pytest.mark.parametrize("algorithm", ["ga", "mh"])
def test_ask_tell_with_the_scene_scorer_equals_evolve(algorithm):
    settings = SMALL if algorithm == "ga" else dict(chains=3, initial_length=[10, 20])
    scene = genform.load_scene(SHIP_SCENE)
    direct = genform.evolve(scene, algorithm=algorithm, seed=2, generations=3, threads=2, **settings)
    opt = genform.Optimizer(scene, algorithm, seed=2, generations=3, **settings)
    while not (opt.is_initialized and opt.generation >= 3):
        batch = opt.ask()
        # The built-in scorer as a Python callable, mixed freely with other terms (here: none).
        opt.tell([scene(m) for m in batch])
    assert opt.best_fitness == direct.best_fitness
    assert opt.best.genome == direct.best.genome
    keys = ["generation", "max", "avg", "min", "invalid", "total_evaluations", "best"]
    assert [[s[k] for k in keys] for s in opt.stats] == [[s[k] for k in keys] for s in direct.stats]


def test_scene_scorers_are_callables():
    scene = genform.load_scene(SHIP_SCENE)
    m = scene.grammar.sample(seed=15)
    c = scene.counts(m)
    assert c["fitness"] == scene.fitness(m) == scene(m)
    assert c["target"] > 0 and c["good"] >= 0
    [(f, _, _)] = scene.score_genomes([m.genome_json()])
    assert f == scene(m)
    parts = scene.components(m)
    assert [p["name"] for p in parts] == ["good", "bad", "length"]
    assert abs(sum(p["value"] for p in parts) - f) < 1e-9
    assert all(p["value"] <= p["max"] + 1e-12 for p in parts) and parts[0]["max"] == parts[0]["weight"]
    no_genome = genform.load(SHIP_SCENE.parent / "../graph/koch.gg.yaml").sample(seed=1)
    with pytest.raises(genform.GenformError, match="no genome"):
        scene(no_genome)


def test_models_pickle_by_genome():
    import pickle

    m = genform.load(SHIP_SCENE.parent / "../shape/spaceship.sg").sample(seed=3)
    again = pickle.loads(pickle.dumps(m))
    assert again.genome == m.genome and again.mesh()[0].tolist() == m.mesh()[0].tolist()
    scene = pickle.loads(pickle.dumps(genform.load_scene(SHIP_SCENE)))
    assert scene.path == genform.load_scene(SHIP_SCENE).path


def _timeless(folder):
    """A run folder's files with the wall-clock fields left out: run.json
    without its seconds and rates, stats.csv without its time columns,
    fitness.svg (its x axis is time) by name only."""
    out = {}
    for p in sorted(folder.rglob("*")):
        if not p.is_file():
            continue
        name = str(p.relative_to(folder))
        if name == "run.json":
            run = json.loads(p.read_text())
            timed = ("seconds", "per_second", "us_per_eval", "threads")
            split = run.pop("eval_split", {})
            run["eval_split"] = {k: v for k, v in split.items() if k == "evaluations"}
            out[name] = {k: v for k, v in run.items() if not any(t in k for t in timed) and k not in ("scene",)}
        elif name == "stats.csv":
            rows = [line.split(",") for line in p.read_text().splitlines()]
            keep = [i for i, h in enumerate(rows[0]) if "seconds" not in h and "_us" not in h]
            out[name] = [[r[i] for i in keep] for r in rows]
        elif name == "fitness.svg":
            out[name] = "present"
        else:
            out[name] = p.read_bytes()
    return out


@pytest.mark.parametrize(
    "scene, flags, kwargs",
    [
        (SHIP_SCENE, ["--generations", "3", "--set", "ga.population=16", "--set", "ga.elitism=4"], dict(generations=3, population=16, elitism=4)),
        (SHIP_SCENE.parent / "genr8_canopy.toml", ["--evaluations", "600"], dict(evaluations=600)),
    ],
    ids=["tree", "codon"],
)
def test_the_cli_and_python_write_the_same_run_folder(cli, tmp_path, scene, flags, kwargs):
    if cli is None:
        pytest.skip("no genform binary built (cargo build -p genform-cli)")
    import subprocess

    subprocess.run([cli, "evolve", str(scene), "--seed", "5", "--threads", "2", "--out", str(tmp_path / "cli"), "-q", *flags], check=True)
    r = genform.evolve(scene, seed=5, threads=2, out=tmp_path / "py", **kwargs)
    a, b = _timeless(tmp_path / "cli"), _timeless(tmp_path / "py")
    assert sorted(a) == sorted(b)
    for name in a:
        assert a[name] == b[name], name
    assert r.best is not None and r.best.triangle_count() > 0


def test_codon_scenes_evolve_from_python(tmp_path):
    r = genform.evolve(SHIP_SCENE.parent / "genr8_canopy.toml", seed=1, evaluations=300, out=tmp_path / "run", population=20)
    assert r.stopped_by == "evaluations" and r.evaluations >= 300
    run = json.loads((tmp_path / "run" / "run.json").read_text())
    assert run["kind"] == "ge-gr8" and run["config"]["ge"]["population"] == 20 and run["best_fitness"] == r.best_fitness
    assert (tmp_path / "run" / "best.gr8").is_file() and r.best.grammar is None and r.best.bounds() is not None
