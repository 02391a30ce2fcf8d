#!/usr/bin/env bash
# GA against random search at an equal number of evaluations, on every
# shipped scene, over several seeds. Prints a Markdown table (the one in
# docs/evolve.md). Usage: scripts/ga-vs-random.sh [SEEDS] [OUT_DIR]
# Environment: SCENES="a b" limits the scenes (names without .toml);
# ARGS_<scene>="--generations 100" adds flags to that scene's GA runs (the
# random runs always get the GA's evaluation count).
set -euo pipefail
cd "$(dirname "$0")/.."
seeds=${1:-5}
out=${2:-target/ga-vs-random}
# BIN=path/to/genform skips the build.
if [ -z "${BIN:-}" ]; then
  CARGO_TARGET_DIR=${CARGO_TARGET_DIR:-target} cargo build --release -q -p genform-cli
fi
bin=${BIN:-${CARGO_TARGET_DIR:-target}/release/genform}
mkdir -p "$out"
echo "| scene | evaluations | GA best (mean ± sd) | random best (mean ± sd) | GA wins |"
echo "|---|---|---|---|---|"
for scene in examples/scenes/*.toml; do
  name=$(basename "$scene" .toml)
  if [ -n "${SCENES:-}" ] && [[ " $SCENES " != *" $name "* ]]; then continue; fi
  extra_var="ARGS_${name}"
  read -r -a extra <<< "${!extra_var:-}"
  ga=(); rnd=(); evals=0
  for seed in $(seq 1 "$seeds"); do
    "$bin" evolve "$scene" --seed "$seed" "${extra[@]}" --out "$out/$name-ga-$seed" -q 2>/dev/null
    evals=$(python3 -c "import json;print(json.load(open('$out/$name-ga-$seed/run.json'))['evaluations'])")
    "$bin" evolve "$scene" --seed "$seed" --algorithm random --evaluations "$evals" --out "$out/$name-rnd-$seed" -q 2>/dev/null
    ga+=("$(python3 -c "import json;print(json.load(open('$out/$name-ga-$seed/run.json'))['best_fitness'])")")
    rnd+=("$(python3 -c "import json;print(json.load(open('$out/$name-rnd-$seed/run.json'))['best_fitness'])")")
  done
  python3 - "$name" "$evals" "${ga[*]}" "${rnd[*]}" <<'PY'
import statistics as st, sys
name, evals, ga, rnd = sys.argv[1], sys.argv[2], list(map(float, sys.argv[3].split())), list(map(float, sys.argv[4].split()))
wins = sum(g > r for g, r in zip(ga, rnd))
f = lambda xs: f"{st.mean(xs):.4f} ± {st.stdev(xs) if len(xs) > 1 else 0:.4f}"
print(f"| {name} | {evals} | {f(ga)} | {f(rnd)} | {wins}/{len(ga)} |")
PY
done
