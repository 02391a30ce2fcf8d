"""Whole-process timings of genform against the Python L-system packages,
side by side in one run (see scripts/bench-peers.sh and docs/benchmarks.md).

Every command runs in a fresh process, round-robin (genform, peer, peer, …)
so that load from other work slows every side alike; the table gives
medians and each ratio against the fastest peer. Outputs are checked to be
the same string before anything is timed.
"""

import argparse
import os
import statistics
import subprocess
import sys
import tempfile
import time

HERE = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.dirname(os.path.dirname(HERE))
STRING_PEERS = ["LindenmayerSystem", "l_system_fractals", "lsys"]

# (label, system, steps, output): strings as ABOP sizes them, a drawing.
CASES = [
    ("ABOP 1.24e string, n = 12 (3.18 M modules)", "abop_1_24e", 12, "txt"),
    ("Koch snowflake string, n = 9 (1.84 M modules)", "koch_snowflake", 9, "txt"),
    ("ABOP 1.24e drawing to PNG, n = 7 (4,118 segments)", "abop_1_24e", 7, "png"),
]


def commands(genform, system, steps, kind, out):
    grammar = os.path.join(ROOT, "examples", "lsystem", system + ".ls")
    flag = "--string-out" if kind == "txt" else "--out"
    cmds = {"genform": [genform, "sample", grammar, "--steps", str(steps), flag, os.path.join(out, f"genform.{kind}")]}
    for peer in STRING_PEERS if kind == "txt" else ["lsys"]:
        script = os.path.join(HERE, "peer.py")
        cmds[peer] = [sys.executable, script, peer, system, str(steps), os.path.join(out, f"{peer}.{kind}")]
    return cmds


def run(cmd):
    start = time.perf_counter()
    subprocess.run(cmd, check=True, stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
    return time.perf_counter() - start


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--genform", required=True)
    ap.add_argument("--runs", type=int, default=7)
    args = ap.parse_args()
    print("| case | genform | fastest peer | ratio | all peers (median) |")
    print("|---|---|---|---|---|")
    with tempfile.TemporaryDirectory() as out:
        for label, system, steps, kind in CASES:
            cmds = commands(args.genform, system, steps, kind, out)
            times = {name: [] for name in cmds}
            for _ in range(args.runs):
                for name, cmd in cmds.items():
                    times[name].append(run(cmd))
            if kind == "txt":
                strings = {n: open(os.path.join(out, f"{n}.txt")).read().strip() for n in cmds}
                differ = [n for n, s in strings.items() if s != strings["genform"]]
                if differ:
                    sys.exit(f"{label}: {', '.join(differ)} derived a different string than genform")
            med = {n: statistics.median(t) * 1000 for n, t in times.items()}
            peers = {n: m for n, m in med.items() if n != "genform"}
            best = min(peers, key=peers.get)
            others = ", ".join(f"{n} {m:.0f} ms" for n, m in sorted(peers.items(), key=lambda kv: kv[1]))
            print(f"| {label} | {med['genform']:.1f} ms | {best} {peers[best]:.1f} ms "
                  f"| **{peers[best] / med['genform']:.1f}×** | {others} |")


if __name__ == "__main__":
    main()
