#!/usr/bin/env bash
# The strip of pictures at the top of README.md: one 800×600 PNG per
# formalism, each drawn by `genform sample` from a file under examples/ and
# written to docs/img/strip-<formalism>.png (shape, lsystem, boxsplit,
# graph, hemls). The seeds are fixed, so a rerun writes the same pictures.
#
#   scripts/readme-pictures.sh [GENFORM]
#
# GENFORM is the genform binary to use (default: target/release/genform,
# built with `cargo build --release` when it is missing). Run it from
# anywhere; paths are relative to the repository root.
set -euo pipefail
root=$(cd "$(dirname "$0")/.." && pwd)

if [ $# -gt 0 ]; then
    # A binary given as an argument is taken relative to the caller's folder.
    genform=$(realpath -- "$1")
    [ -x "$genform" ] || { echo "readme-pictures: $1 is not an executable" >&2; exit 1; }
    cd "$root"
else
    cd "$root"
    genform=target/release/genform
    [ -x "$genform" ] || cargo build --release -p genform-cli
fi

out=docs/img
mkdir -p "$out"

# Shape grammar: the thesis' spaceship; seed 15 is a full hull with wings
# and engines (most seeds give a few boxes).
"$genform" sample examples/shape/spaceship.sg --seed 15 --out "$out/strip-shape.png"
# L-system: the 3D bush with leaves (ABOP Figure 1.25), 7 steps.
"$genform" sample examples/lsystem/bush_3d.ls --out "$out/strip-lsystem.png"
# Box-split grammar: the castle in its declared 80×40×80 box.
"$genform" sample examples/boxsplit/castle.bsg --out "$out/strip-boxsplit.png"
# Graph grammar: a facade of windows and a door.
"$genform" sample examples/graph/facade.gg.yaml --out "$out/strip-graph.png"
# Genr8/HEMLS: a tiles4 surface that gravity drapes over a sphere, 4 steps
# (5 and more draw a grid too fine to read at the README's size).
"$genform" sample examples/hemls/tiles4.gr8 --env examples/hemls/drape_sphere.toml --steps 4 \
    --out "$out/strip-hemls.png"
