#!/bin/sh
# The ShapeGenetics comparison on the reference implementation's own scale
# (issue #23; docs/comparison.md "On the reference's scale"): every run is
# scored as the reference's CPU volume evaluator counts
# (examples/scenes/spaceship_reference_cpu.toml, `form = "reference-cpu"`),
# 10 seeds each, and the tables beside the reference's own run are printed
# as Markdown. Run from the repository root after `cargo build --release`;
# about a minute. Fitness values do not depend on the machine.
set -e
G=${G:-target/release/genform}
S=examples/scenes/spaceship_reference_cpu.toml
OUT=${OUT:-reference-scale-out}
RUNS=${RUNS:-10}
sweep() { # name args…
  name=$1; shift
  $G sweep $S --runs $RUNS --quiet --out $OUT/$name "$@" > /dev/null
}
# The GA at 130 generations of 150 (15,750 evaluations: the elite keeps its
# fitness) and at the reference's evaluation count (19,650: it re-evaluates
# its elite every generation), default and thesis preset.
sweep ga-130 --generations 130 --set ga.preset=default,thesis
sweep ga-19650 --evaluations 19650 --set ga.preset=default,thesis
# MH (70 chains), SMC and SOSMC (500 particles) at the evaluation counts of
# the reference's runs (§3: ≈ 17,570 and ≈ 20,500).
sweep mh --algorithm mh --evaluations 17570 --set description=mh
sweep smc --algorithm smc --evaluations 20500 --set description=smc
sweep sosmc --algorithm sosmc --evaluations 20500 --set description=sosmc
python3 - "$OUT" <<'PY'
import csv, statistics, sys
out = sys.argv[1]
REF = {0: -3.52, 10: -1.60, 20: -0.80, 30: -0.15, 50: 0.07, 70: 0.32, 90: 0.39, 110: 0.41, 130: 0.41}

def runs(name):
    """{preset or variant: {run: [(generation, evaluations, best so far)]}}"""
    table = {}
    with open(f"{out}/{name}/sweep.csv") as f:
        for row in csv.DictReader(f):
            v = row.get("ga.preset") or row["variant"]
            table.setdefault(v, {}).setdefault(row["run"], []).append(
                (int(row["generation"]), int(row["evaluations"]), float(row["best_fitness"])))
    return table

def stats(values):
    q = statistics.quantiles(values, n=4, method="inclusive")
    return f"{statistics.median(values):.3f} ({q[0]:.3f} to {q[2]:.3f})"

def at(run, key, limit):
    """The best so far of `run` at the last row whose `key` (0: generation,
    1: evaluations) is at most `limit`."""
    rows = [r for r in run if r[key] <= limit]
    return (rows or run[:1])[-1][2]

# Rows: the reference's generations. By generation, ours and the reference's
# generation g; by evaluations, ours after the evaluations the reference had
# made by then (150 per generation, its elite re-evaluated).
for name, what, key, limit in [
    ("ga-130", "130 generations of 150 (15,750 evaluations)", 0, lambda g: g),
    ("ga-19650", "equal evaluations (the reference's 150 per generation, 19,650 in all)", 1, lambda g: 150 * (g + 1)),
]:
    t = runs(name)
    n = len(t["default"])
    print(f"\n#### GA, {what}: median (quartiles) of the best so far over {n} seeds\n")
    print("| reference generation | reference (1 run) | default GA | beats | thesis GA | beats |")
    print("|---|---|---|---|---|---|")
    for g, ref in REF.items():
        cells = []
        for preset in ["default", "thesis"]:
            vals = [at(r, key, limit(g)) for r in t[preset].values()]
            cells += [stats(vals), "yes" if statistics.median(vals) > ref else "no"]
        print(f"| {g} | {ref:.2f} | {cells[0]} | {cells[1]} | {cells[2]} | {cells[3]} |")
print("\n| algorithm | evaluations | reference (1 run, best ever) | genform, median (quartiles) | min – max |")
print("|---|---|---|---|---|")
for name, ref in [("mh", "−0.857"), ("smc", "−3.21"), ("sosmc", "−2.17")]:
    t = runs(name)
    finals = [r[-1] for v in t.values() for r in v.values()]
    vals = [b for _, _, b in finals]
    evals = statistics.median(e for _, e, _ in finals)
    print(f"| {name.upper()} | {evals:,.0f} | {ref} | {stats(vals)} | {min(vals):.3f} to {max(vals):.3f} |")
PY
