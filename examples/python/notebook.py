# %% [markdown]
# # genform from Python
#
# A notebook-style tour (cells marked `# %%`: open it in Jupyter with
# jupytext, VS Code or PyCharm, or run it as a script from the repository
# root: `python examples/python/notebook.py`). It writes into `notebook-out/`
# (or the folder in $GENFORM_NOTEBOOK_OUT).

# %%
import os
from pathlib import Path

import numpy as np

import genform

ROOT = Path(__file__).resolve().parents[2]
OUT = Path(os.environ.get("GENFORM_NOTEBOOK_OUT", "notebook-out"))
OUT.mkdir(parents=True, exist_ok=True)
print("formalisms:", [f["name"] for f in genform.formalisms()])

# %% [markdown]
# ## Load a grammar and draw models
# Any formalism loads by extension. In Jupyter a model shows itself as a
# picture (`_repr_png_`).

# %%
ship = genform.load(ROOT / "examples/shape/spaceship.sg")
print(ship.info().splitlines()[0])
model = ship.sample(seed=15)
print(model.summary)
vertices, faces = model.mesh()  # NumPy arrays, ready for trimesh, pyvista, ...
print("mesh:", vertices.shape, faces.shape, "extent", np.ptp(vertices, axis=0))
model.save(OUT / "ship.glb")
(OUT / "ship.png").write_bytes(model.png(320, 240))

# %% [markdown]
# Genomes are plain JSON data: save them, edit them, derive the same model again.

# %%
again = ship.derive(model.genome)
assert np.array_equal(again.mesh()[0], vertices)

# %% [markdown]
# ## Evolve against a scene
# `progress` sees every generation; `stats` is a list of dicts
# (`pandas.DataFrame(result.stats)`); `out` gets the CLI's run folder.

# %%
result = genform.evolve(
    ROOT / "examples/scenes/spaceship_volume.toml",
    seed=1,
    generations=5,
    population=30,
    elitism=6,
    out=OUT / "ship-run",
    progress=lambda row: print(f"gen {row['generation']}: best {row['best']:.4f}"),
)
print(result, "→", result.out)

# %% [markdown]
# ## Your own fitness: ask/tell
# Mix the scene's built-in scorer (a Python callable) with a term of your own.

# %%
scene = genform.load_scene(ROOT / "examples/scenes/spaceship_volume.toml")


def fitness(m: genform.Model) -> float:
    lo, hi = m.bounds() or ((0, 0, 0), (0, 0, 0))
    return scene(m) + 0.01 * (hi[2] - lo[2])  # fill the volume, and be long


opt = genform.Optimizer(scene, "ga", seed=2, population=30, elitism=6)
for _ in range(4):
    batch = opt.ask()
    opt.tell([fitness(m) for m in batch])
print("ask/tell best", round(opt.best_fitness, 4), "after", opt.evaluations, "evaluations")
opt.best.save(OUT / "own-fitness.obj")
