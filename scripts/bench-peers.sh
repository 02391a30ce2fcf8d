#!/usr/bin/env bash
# Whole-process comparison with the Python L-system packages (issue #28):
# installs LindenmayerSystem, l-system-fractals and lsys into a virtual
# environment, builds genform, and prints each comparison as a ratio
# (medians of interleaved runs, outputs checked equal first).
#   scripts/bench-peers.sh [--runs N]
set -euo pipefail
root=$(cd "$(dirname "$0")/.." && pwd)
venv=${PEERS_VENV:-$root/target/peers-venv}
[ -x "$venv/bin/python" ] || python3 -m venv "$venv"
"$venv/bin/python" -m pip install --quiet --disable-pip-version-check \
    LindenmayerSystem==1.0.0 l-system-fractals==0.0.6 lsys==0.2.0 matplotlib
cargo build --release --quiet -p genform-cli
"$venv/bin/python" "$root/scripts/peers/bench.py" --genform "$root/target/release/genform" "$@"
