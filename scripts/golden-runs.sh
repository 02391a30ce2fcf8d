#!/usr/bin/env bash
# Runs every shipped example through a `genform` binary and keeps what it
# wrote and printed, so two binaries can be compared file by file: the
# check that a refactor changed no behaviour ("byte-identical").
#
#   scripts/golden-runs.sh BIN OUT        # e.g. /tmp/genform-old /tmp/old
#   scripts/golden-runs.sh --compare OLD NEW
#
# What it runs: `info` and `sample` (two seeds, .obj and .glb or the
# formalism's own format) of every grammar under examples/, `evolve` of
# every scene (3 generations, 1 and 2 threads, and more algorithms on one
# tree and one codon scene), `score` and `derive` of each run's best genome,
# `map`, and a set of refused inputs. Timing fields are blanked before the
# comparison: the seconds columns of stats.csv, the seconds keys of
# run.json, and the "fitness by time" panel of fitness.svg.
set -uo pipefail
cd "$(dirname "$0")/.."

normalize() {
    local dir=$1
    # The folder's own name, wherever it is printed.
    local abs
    abs=$(realpath "$dir")
    grep -rlF "$abs" "$dir" --include='*.log' --include='*.json' --include='*.md' | while IFS= read -r f; do
        sed -i "s#$abs#OUT#g" "$f"
    done
    find "$dir" -name stats.csv -print0 | while IFS= read -r -d '' f; do
        awk -F, 'BEGIN{OFS=","} NR>1{$3="";$8="";$9=""} {print}' "$f" >"$f.n" && mv "$f.n" "$f"
    done
    find "$dir" -name comparison.csv -print0 | while IFS= read -r -d '' f; do
        awk -F, 'BEGIN{OFS=","} NR>1{$4="";$5="";$6=""} {print}' "$f" >"$f.n" && mv "$f.n" "$f"
    done
    find "$dir" -name run.json -print0 | while IFS= read -r -d '' f; do
        python3 - "$f" <<'EOF'
import json, sys
p = sys.argv[1]
d = json.load(open(p))
for k in ["seconds", "evaluations_per_second", "eval_seconds", "reproduction_seconds", "eval_split"]:
    d.pop(k, None)
json.dump(d, open(p, "w"), indent=1, sort_keys=True)
EOF
    done
    find "$dir" -name fitness.svg -print0 | while IFS= read -r -d '' f; do
        python3 - "$f" <<'EOF'
import sys
p = sys.argv[1]
t = open(p).read()
i = t.find("fitness by time")
open(p, "w").write(t[:i] if i >= 0 else t)
EOF
    done
    # Timing in printed lines: "in 0.3 s (1234/s)", "(0.2 s)".
    find "$dir" -name '*.log' -print0 | while IFS= read -r -d '' f; do
        sed -E -i 's/[0-9]+\.[0-9]+ s\b/T s/g; s/\([0-9]+\/s\)/(R\/s)/g; s/[0-9]+ evals\/s/R evals\/s/g' "$f"
    done
}

if [[ "${1:-}" == "--compare" ]]; then
    old=$2 new=$3
    if diff -r -q "$old" "$new"; then
        echo "identical: $(find "$old" -type f | wc -l) files"
        exit 0
    fi
    exit 1
fi

bin=$(realpath "$1")
out=$2
rm -rf "$out"
mkdir -p "$out"
run() { # NAME ARGS...: runs the binary, keeping stdout+stderr and the exit status
    local name=$1
    shift
    (cd "$out" && "$bin" "$@" >"$name.log" 2>&1; echo "rc $?" >>"$name.log")
}
ex=$(realpath examples)

for g in "$ex"/shape/*.sg "$ex"/lsystem/*.ls "$ex"/graph/*.gg.yaml "$ex"/hemls/*.gr8 "$ex"/boxsplit/*.bsg; do
    base=$(basename "$g")
    run "info-$base" info "$g"
    for seed in 1 2; do
        case "$g" in
        *.bsg)
            run "sample-$base-$seed" sample "$g" --seed "$seed" --box 0,0,0,15,11,15 --out "sample-$base-$seed.schem" --trace "trace-$base-$seed.json"
            ;;
        *.gg.yaml)
            run "sample-$base-$seed" sample "$g" --seed "$seed" --out "sample-$base-$seed.svg"
            run "sample-$base-$seed-yaml" sample "$g" --seed "$seed" --out "sample-$base-$seed.yaml"
            ;;
        *.gr8)
            run "sample-$base-$seed" sample "$g" --seed "$seed" --steps 3 --out "sample-$base-$seed.obj"
            ;;
        *.ls)
            run "sample-$base-$seed" sample "$g" --seed "$seed" --out "sample-$base-$seed.obj" --string-out "string-$base-$seed.txt"
            ;;
        *)
            run "sample-$base-$seed" sample "$g" --seed "$seed" --out "sample-$base-$seed.glb" --genome-out "genome-$base-$seed.json"
            run "sample-$base-$seed-obj" sample "$g" --seed "$seed" --out "sample-$base-$seed.obj"
            ;;
        esac
    done
done
run sample-drape sample "$ex/hemls/tiles4.gr8" --env "$ex/hemls/drape_sphere.toml" --steps 4 --out drape.obj
run sample-rep sample "$ex/hemls/tiles4.gr8" --env "$ex/hemls/repellers.toml" --every-step --steps 3 --out rep.png
run sample-bridge sample "$ex/boxsplit/bridge.bsg" --world "$ex/terrain/prismarine-1.21.1/r.0.0.mca" --box 6,50,3,62,65,5 --out bridge.schem
run map-genr8 map "$ex/ge/genr8.bnf" --genr8 --genome 432,900,744,354,259,673,640,919,790,937,57,631,445
run map-json map "$ex/ge/arith.bnf" --genome 3,7,1,9,4 --json

for s in "$ex"/scenes/*.toml; do
    base=$(basename "$s" .toml)
    for t in 1 2; do
        run "evolve-$base-t$t" evolve "$s" --seed 1 --generations 3 --threads "$t" -q --out "evolve-$base-t$t"
    done
    d="$out/evolve-$base-t1"
    if [[ -f "$d/best-genome.json" ]]; then
        run "score-$base" score "$s" --genome "$d/best-genome.json"
        run "derive-$base" derive "$s" --genome "$d/best-genome.json" --out "derive-$base.obj"
    elif [[ -f "$d/best-codons.json" ]]; then
        run "score-$base" score "$s" --genome "$d/best-codons.json"
        run "derive-$base" derive "$s" --genome "$d/best-codons.json" --out "derive-$base.obj"
    fi
done
for alg in mh smc sosmc hybrid map-elites random; do
    run "evolve-ship-$alg" evolve "$ex/scenes/spaceship_volume.toml" --algorithm "$alg" --seed 2 --evaluations 600 -q --out "evolve-ship-$alg"
done
run evolve-canopy-random evolve "$ex/scenes/genr8_canopy.toml" --algorithm random --seed 2 --generations 3 -q --out evolve-canopy-random
run evolve-ship-set evolve "$ex/scenes/spaceship_volume.toml" --seed 3 --generations 2 --set ga.population=20 --set fitness.good=3 -q --out evolve-ship-set
run score-form score "$ex/scenes/spaceship_volume.toml" --genome "$out/evolve-spaceship_volume-t1/best-genome.json" --form reference-cpu
run sweep sweep "$ex/scenes/spaceship_volume.toml" --set ga.population=10,20 --runs 2 --generations 2 --threads 1 -q --out sweep

# Refused inputs: the messages must stay as they are (or get better on purpose).
bad="$out/bad"
mkdir -p "$bad"
scene() { # NAME TEXT: a scene file beside the examples' grammars
    printf '%s' "$2" >"$bad/$1.toml"
}
ship="grammar = \"$ex/shape/spaceship.sg\"\n[volume]\nmin = [-1.0, -1.0, -1.0]\nmax = [1.0, 1.0, 1.0]\nvoxels = [4, 4, 4]\n[[volume.target]]\nmesh = \"$ex/scenes/targets/spaceship_target.obj\"\n"
scene population0 "$(printf "${ship}[ga]\npopulation = 0\n[run]\ngenerations = 1\n")"
scene population1 "$(printf "${ship}[ga]\npopulation = 1\n[run]\ngenerations = 1\n")"
scene nanrate "$(printf "${ship}[ga]\nmutation_rate = nan\n[run]\ngenerations = 1\n")"
scene chains0 "$(printf "${ship}[mh]\nchains = 0\n[run]\ngenerations = 1\n")"
scene particles0 "$(printf "${ship}[smc]\nparticles = 0\n[run]\ngenerations = 1\n")"
scene tournament0 "$(printf "${ship}[ga]\nselection = { first = { tournament = 0 } }\n[run]\ngenerations = 1\n")"
scene limits0 "$(printf "${ship}[limits]\ngenes = 0\n[run]\ngenerations = 1\n")"
scene badvolume "$(printf "grammar = \"$ex/shape/spaceship.sg\"\n[volume]\nmin = [1.0, nan, -1.0]\nmax = [-1.0, 1.0, 1.0]\nvoxels = [4, 4, 4]\n[[volume.target]]\nmesh = \"x.obj\"\n[run]\ngenerations = 1\n")"
scene zeroweights "$(printf "grammar = \"$ex/ge/genr8.bnf\"\nphenotype = \"gr8\"\n[surface]\nsize = { target = 5, weight = 0 }\n[run]\ngenerations = 1\n")"
scene codonlimit "$(printf "grammar = \"$ex/ge/genr8.bnf\"\nphenotype = \"gr8\"\n[limits]\nvertices = 18446744073709551615\n[surface]\nsize = { target = 5 }\n[run]\ngenerations = 1\n")"
scene unknownkey "$(printf "${ship}[ga]\npopulaton = 5\n")"
for f in "$bad"/*.toml; do
    run "bad-$(basename "$f" .toml)" evolve "$f" -q --out "$bad/out"
done
normalize "$out"
echo "wrote $out ($(find "$out" -type f | wc -l) files)"
