"""The operators: ``genform.sample`` and ``genform.evolve``.

Both read their settings from ``context.scene.genform`` unless given as
operator properties (scripts and tests pass them). ``genform.evolve`` from
the panel runs the evolution on a worker thread and reports progress from a
window timer (the window manager's progress cursor and the panel's bar);
called from a script (``bpy.ops.genform.evolve()``, no UI) it runs to the
end in the calling thread.
"""

from __future__ import annotations

import threading

import bpy
from bpy.props import IntProperty, StringProperty

from . import build


def scene_algorithms(path: str) -> list[str]:
    """The algorithms the scene at ``path`` allows, its default first."""
    from . import scene_algorithms as names

    return names(path)


def _genform(op):
    """The genform module, or None after reporting how to install it."""
    try:
        import genform
    except ImportError as e:
        op.report({"ERROR"}, f"the genform Python package is not installed in Blender's Python ({e}); see docs/python.md")
        return None
    return genform


def place(context, model, name: str) -> list:
    """Adds `model` to the scene as the settings say (mesh or glTF, and
    a surface's typed edges as a curve object parented to it unless
    ``edges`` is off), selects what was made and makes the first object
    active."""
    settings = context.scene.genform
    for o in context.view_layer.objects:
        o.select_set(False)
    if settings.import_mode == "GLTF":
        objs = build.import_gltf(model)
        if len(objs) == 1:  # the merged node `model`
            objs[0].name = name
    else:
        objs = [build.build_object(model, name, context.collection, y_up=settings.y_up)]
    for o in objs:
        o["genform_summary"] = model.summary
        o.select_set(True)
    if objs and settings.edges:
        # glTF's importer turns +y up as y_up does.
        y_up = settings.y_up or settings.import_mode == "GLTF"
        edges = build.build_edges(model, f"{name}_edges", context.collection, y_up=y_up)
        if edges is not None:
            edges.parent = objs[0]
            edges.matrix_parent_inverse = objs[0].matrix_world.inverted()
            edges.select_set(True)
            objs.append(edges)
    if objs:
        context.view_layer.objects.active = objs[0]
    return objs


class GENFORM_OT_sample(bpy.types.Operator):
    """Sample a model from the grammar with the seed"""

    bl_idname = "genform.sample"
    bl_label = "Sample"
    bl_options = {"REGISTER", "UNDO"}

    grammar: StringProperty(name="Grammar", description="Grammar file; empty: the panel's", default="")
    seed: IntProperty(name="Seed", description="Random seed; -1: the panel's", default=-1, min=-1)

    def execute(self, context):
        genform = _genform(self)
        if genform is None:
            return {"CANCELLED"}
        settings = context.scene.genform
        path = bpy.path.abspath(self.grammar or settings.grammar_path)
        seed = settings.seed if self.seed < 0 else self.seed
        if not path:
            self.report({"ERROR"}, "choose a grammar file first")
            return {"CANCELLED"}
        try:
            grammar = genform.load(path)
            model = grammar.sample(seed=seed)
        except genform.GenformError as e:
            self.report({"ERROR"}, str(e))
            return {"CANCELLED"}
        place(context, model, f"{grammar.name}_seed{seed}")
        self.report({"INFO"}, model.summary)
        return {"FINISHED"}


class Cancelled(Exception):
    """Raised from the progress callback to stop a run (Esc)."""


# The panel's Population as each algorithm's setting (`evolve(**settings)`).
POPULATION_KEY = {
    "ga": "population",
    "ge": "population",
    "random": "population",
    "map-elites": "batch",
    "smc": "particles",
    "sosmc": "particles",
    "mh": "chains",
}


class Run:
    """One evolution on a worker thread: what the timer reads back."""

    def __init__(self, genform, scene_path: str, algorithm: str, seed: int, generations: int, population: int):
        self.genform = genform
        self.kwargs = dict(algorithm=algorithm, seed=seed, generations=generations)
        if population > 0:
            # What each optimizer calls its population (hybrid: none of its own).
            key = POPULATION_KEY.get(algorithm)
            if key:
                self.kwargs[key] = population
            if algorithm in ("ga", "ge", "random"):
                # A scene's elitism may not fit a smaller population: keep a fifth.
                self.kwargs["elitism"] = max(1, population // 5)
        self.scene_path = scene_path
        self.generations = generations
        self.generation = 0
        self.best = float("nan")
        self.cancel = False
        self.result = None
        self.error: BaseException | None = None
        self.thread: threading.Thread | None = None

    @property
    def fraction(self) -> float:
        return min(1.0, self.generation / max(1, self.generations))

    def _progress(self, row) -> None:
        # Runs on the evolving thread: plain attributes only, no bpy.
        # Rows come for generation 0 (the initial population) to `generations`.
        self.generation = int(row["generation"])
        self.best = float(row["best"])
        if self.cancel:
            raise Cancelled()

    def run(self) -> None:
        """Evolves to the end in this thread."""
        try:
            self.result = self.genform.evolve(self.scene_path, progress=self._progress, **self.kwargs)
        except BaseException as e:  # noqa: BLE001 - reported by the operator
            self.error = e

    def start(self) -> None:
        self.thread = threading.Thread(target=self.run, name="genform-evolve", daemon=True)
        self.thread.start()

    @property
    def done(self) -> bool:
        return self.thread is None or not self.thread.is_alive()


class GENFORM_OT_evolve(bpy.types.Operator):
    """Evolve models for the scene config and import the best (Esc stops)"""

    bl_idname = "genform.evolve"
    bl_label = "Evolve"

    scene_path: StringProperty(name="Scene", description="Scene config (.toml); empty: the panel's", default="")
    generations: IntProperty(name="Generations", description="-1: the panel's", default=-1, min=-1)
    population: IntProperty(name="Population", description="-1: the panel's; 0: the scene's", default=-1, min=-1)
    algorithm: StringProperty(name="Algorithm", description="ga, ge, map-elites, …; empty: the panel's", default="")

    _run: Run | None = None
    _timer = None

    def _new_run(self, context) -> Run | None:
        genform = _genform(self)
        if genform is None:
            return None
        s = context.scene.genform
        path = bpy.path.abspath(self.scene_path or s.scene_path)
        if not path:
            self.report({"ERROR"}, "choose a scene config (.toml) first")
            return None
        generations = s.generations if self.generations < 0 else self.generations
        population = s.population if self.population < 0 else self.population
        # The panel's choice when this scene allows it, else the scene's default.
        allowed = scene_algorithms(path)
        algorithm = self.algorithm or s.algorithm
        if algorithm not in allowed:
            if self.algorithm:
                self.report({"ERROR"}, f"{path} cannot be evolved with {algorithm}: use {', '.join(allowed)}")
                return None
            algorithm = allowed[0]
        return Run(genform, path, algorithm, s.seed, generations, population)

    def execute(self, context):
        run = self._new_run(context)
        if run is None:
            return {"CANCELLED"}
        run.run()
        return self._finish(context, run)

    def invoke(self, context, event):
        s = context.scene.genform
        if s.running:
            self.report({"WARNING"}, "an evolution is already running")
            return {"CANCELLED"}
        run = self._new_run(context)
        if run is None:
            return {"CANCELLED"}
        self._run = run
        s.running, s.progress, s.status = True, 0.0, "starting…"
        wm = context.window_manager
        wm.progress_begin(0.0, 1.0)
        self._timer = wm.event_timer_add(0.25, window=context.window)
        wm.modal_handler_add(self)
        run.start()
        return {"RUNNING_MODAL"}

    def modal(self, context, event):
        run, s = self._run, context.scene.genform
        if event.type == "ESC":
            run.cancel = True
            s.status = "stopping after this generation…"
        if event.type != "TIMER":
            return {"PASS_THROUGH"}
        s.progress = run.fraction
        if run.generation:
            s.status = f"generation {run.generation}/{run.generations}, best {run.best:.4g}"
        context.window_manager.progress_update(run.fraction)
        for area in context.screen.areas if context.screen else []:
            if area.type == "VIEW_3D":
                area.tag_redraw()
        if not run.done:
            return {"PASS_THROUGH"}
        wm = context.window_manager
        wm.event_timer_remove(self._timer)
        wm.progress_end()
        s.running = False
        return self._finish(context, run)

    def _finish(self, context, run: Run):
        s = context.scene.genform
        s.progress = run.fraction
        if isinstance(run.error, Cancelled):
            s.status = f"stopped at generation {run.generation}"
            self.report({"INFO"}, s.status)
            return {"CANCELLED"}
        if run.error is not None:
            s.status = "failed"
            self.report({"ERROR"}, str(run.error))
            return {"CANCELLED"}
        result = run.result
        if result.best is None:
            s.status = "no valid model found"
            self.report({"WARNING"}, s.status)
            return {"FINISHED"}
        name = f"best_{result.generations}gen_{result.best_fitness:.4g}"
        place(context, result.best, name)
        s.progress = 1.0
        s.status = f"best fitness {result.best_fitness:.4g} after {result.generations} generations"
        self.report({"INFO"}, s.status)
        return {"FINISHED"}


classes = (GENFORM_OT_sample, GENFORM_OT_evolve)
