#!/usr/bin/env bash
# GA against random search on examples/scenes/building_roof.toml (issue 42):
# seeds 1–5, the GA with the scene's settings, random search with the GA's
# number of evaluations, one thread each. Prints the Markdown table of
# docs/shape-grammar.md ("Evolving a building envelope") and writes its
# pictures to docs/img/shape-roof-*.png (the target, and the best models of
# both algorithms for seed $PICTURED, default 3). Each run takes well under
# a second in a release build; the runs are seed-exact, so a rerun writes
# the same table and pictures.
#
#   scripts/building-roof.sh [GENFORM] [OUT_DIR]
#
# GENFORM is the genform binary (default: target/release/genform, built
# when missing); OUT_DIR keeps the run folders (default
# target/building-roof).
set -euo pipefail
root=$(cd "$(dirname "$0")/.." && pwd)
if [ $# -gt 0 ]; then
    genform=$(realpath -- "$1")
    cd "$root"
else
    cd "$root"
    genform=target/release/genform
    [ -x "$genform" ] || cargo build --release -p genform-cli
fi
out=${2:-target/building-roof}
pictured=${PICTURED:-3}
scene=examples/scenes/building_roof.toml
mkdir -p "$out"

# The roof kind of a run's best model: its OBJ names one object per roof,
# after the roof's tag (`o roof_pyramid#9c4a3c_1`); a flat roof adds none.
roof() { { grep -o '^o roof_[a-z]*' "$1/best.obj" || true; } | sed 's/^o roof_//' | paste -sd+ - | sed 's/^$/flat/'; }
field() { python3 -c "import json,sys; print(json.load(open(sys.argv[1]))[sys.argv[2]])" "$1/run.json" "$2"; }

rows=()
for seed in 1 2 3 4 5; do
    "$genform" evolve "$scene" --seed "$seed" --threads 1 --out "$out/ga-$seed" -q 2>/dev/null
    evals=$(field "$out/ga-$seed" evaluations)
    "$genform" evolve "$scene" --seed "$seed" --threads 1 --algorithm random --evaluations "$evals" \
        --out "$out/random-$seed" -q 2>/dev/null
    first=$(sed -n 2p "$out/ga-$seed/stats.csv" | cut -d, -f4)
    rows+=("$seed $evals $first $(field "$out/ga-$seed" best_fitness) $(roof "$out/ga-$seed") \
$(field "$out/random-$seed" best_fitness) $(roof "$out/random-$seed")")
done
printf '%s\n' "${rows[@]}" | python3 -c '
import statistics as st, sys
rows = [l.split() for l in sys.stdin if l.strip()]
print("| seed | evaluations | generation 0 best | GA best | GA roof | random best | random roof | GA − random |")
print("|---|---|---|---|---|---|---|---|")
for seed, n, first, ga, gr, rnd, rr in rows:
    print(f"| {seed} | {int(n):,} | {float(first):.4f} | {float(ga):.4f} | {gr} | {float(rnd):.4f} | {rr} | {float(ga) - float(rnd):+.4f} |")
col = lambda i: [float(r[i]) for r in rows]
first, ga, rnd = col(2), col(3), col(5)
pyr = lambda i: sum(r[i] == "pyramid" for r in rows)
print(f"| mean ± sd | | {st.mean(first):.4f} ± {st.stdev(first):.4f} | {st.mean(ga):.4f} ± {st.stdev(ga):.4f} | "
      f"{pyr(4)}/{len(rows)} pyramid | {st.mean(rnd):.4f} ± {st.stdev(rnd):.4f} | {pyr(6)}/{len(rows)} pyramid | "
      f"{st.mean(ga) - st.mean(rnd):+.4f} |")
'

img=docs/img
"$genform" derive examples/shape/roof_block.sg --genome examples/scenes/targets/pyramid_house.json \
    --out "$img/shape-roof-target.png" 2>/dev/null
for a in ga random; do
    cp "$out/$a-$pictured/best.png" "$img/shape-roof-$a.png"
    cp "$out/$a-$pictured/best-silhouette.png" "$img/shape-roof-$a-front.png"
done
