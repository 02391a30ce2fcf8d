#!/usr/bin/env python3
"""Runs every `.lpy` file of an L-Py checkout through `genform.lpy` and
writes a table: runs (derived and drawn) or why not.

    target/py-venv/bin/python scripts/lpy_survey.py LPY_ROOT [--out docs/lpy-python-survey.md]
        [--timeout 30] [--jobs 2]

LPY_ROOT is a work tree of openalea/lpy (the 313 files at commit 4a365a3).
Each file runs in its own process (cwd = its folder, random seeded with 1),
derived for its own derivation length and drawn to a genform model; a run
longer than --timeout seconds counts as too slow.
"""

from __future__ import annotations

import argparse
import collections
import concurrent.futures
import json
import os
import subprocess
import sys

RUNNER = r"""
import json, sys, time, traceback
sys.setrecursionlimit(10000)
path = sys.argv[1]
out = {"path": path}
try:
    from genform.lpy import Lsystem, LpyUnsupported, LpyError, PlantGLUnavailable
    t = time.perf_counter()
    l = Lsystem(path, seed=1)
    s = l.derive()
    out["derive_s"] = time.perf_counter() - t
    out["modules"] = len(s)
    out["steps"] = l.derivationLength
    t = time.perf_counter()
    m = l.model()
    out["draw_s"] = time.perf_counter() - t
    out["summary"] = m.summary
    out["status"] = "runs"
    rust = sys.argv[2] if len(sys.argv) > 2 else ""
    if rust:
        import os, subprocess, tempfile
        fd, txt = tempfile.mkstemp(suffix=".txt"); os.close(fd)
        fd, svg = tempfile.mkstemp(suffix=".svg"); os.close(fd)
        try:
            t = time.perf_counter()
            p = subprocess.run([rust, "sample", path, "--seed", "1", "--out", svg, "--string-out", txt],
                               capture_output=True, text=True, timeout=60)
            out["rust_s"] = time.perf_counter() - t
            if p.returncode == 0:
                from genform.lpy import CANONICAL, _parse_modules
                rs = open(txt).read().strip()
                def norm(text):
                    mods, _ = _parse_modules(text, 0, "\0", l._names)
                    res = []
                    for n, a in mods:
                        vals = []
                        for v in (a.split(",") if a else []):
                            v = {"True": "1", "False": "0"}.get(v.strip(), v)
                            try: vals.append(round(float(v), 6))
                            except ValueError: vals.append(v.strip())
                        res.append((CANONICAL.get(n, n), tuple(vals)))
                    return res
                out["rust"] = "same" if norm(rs) == norm(str(s)) else "differs"
                out["rust_exact"] = rs == str(s).strip()
            else:
                out["rust"] = "refused"
        except Exception as e:
            out["rust"] = "error " + type(e).__name__
        finally:
            os.unlink(txt); os.unlink(svg)
except BaseException as e:
    out["status"] = "fails"
    out["error"] = type(e).__name__
    out["message"] = str(e).splitlines()[0][:300] if str(e) else ""
    tb = traceback.extract_tb(e.__traceback__)
    out["where"] = next((f"{f.filename.rsplit('/', 1)[-1]}:{f.lineno}" for f in reversed(tb) if f.filename.endswith('.lpy')), "")
print(json.dumps(out))
"""


def reason(r: dict) -> str:
    """A short reason a file does not run, grouped for the table."""
    if r["status"] == "runs":
        return "runs"
    err, msg = r.get("error", ""), r.get("message", "")
    py2 = ("Missing parentheses in call to 'print'", "'xrange'", "name 'file'", "cannot import name 'clock'")
    if any(k in msg for k in py2):
        return "Python 2 code (print statement, xrange, file, time.clock; L-Py 3 refuses it too)"
    if err == "Timeout":
        return "slower than the time limit (deep derivations in Python)"
    if err == "PlantGLUnavailable":
        return "builds PlantGL geometry, scenes or viewers"
    if "openalea" in msg and err in ("ImportError", "ModuleNotFoundError"):
        return "imports OpenAlea packages other than PlantGL's curves (MTG, light, parameter sets)"
    if err in ("ImportError", "ModuleNotFoundError"):
        return "imports a package genform does not provide (" + msg.split("`")[1 if "`" in msg else 0].split("'")[-2 if "'" in msg else 0] + ")"
    if err == "LpyUnsupported":
        if "query" in msg:
            return "turtle queries (?P, ?H, …) in patterns"
        if "repetition" in msg or "alternative" in msg:
            return "pattern repetitions/alternatives (x(…), or)"
        if "alias" in msg:
            return "module aliases (module A = B)"
        return "L-Py construct not run: " + msg.split(": ", 2)[-1][:60]
    if err == "AssertionError":
        return "an assert of the file fails (multiscale matching, bracketed left contexts: not run)"
    if err == "GenformError":
        return "the drawing was refused by genform"
    if err == "LpyError":
        return "not read as L-Py: " + msg.split(": ", 2)[-1][:60]
    if err == "NameError":
        return "names L-Py or PlantGL provide that genform does not (" + msg[:50] + ")"
    if err == "AttributeError":
        return "L-Py/PlantGL object API genform does not provide (" + msg[:50] + ")"
    return f"{err}: {msg[:60]}"


def run_one(path: str, timeout: float, rust: str = "") -> dict:
    env = dict(os.environ)
    try:
        p = subprocess.run(
            [sys.executable, "-c", RUNNER, path] + ([rust] if rust else []),
            cwd=os.path.dirname(path),
            capture_output=True,
            text=True,
            timeout=timeout,
            env=env,
        )
    except subprocess.TimeoutExpired:
        return {"path": path, "status": "fails", "error": "Timeout", "message": f"over {timeout:g} s"}
    for line in reversed(p.stdout.splitlines()):
        if line.startswith("{"):
            return json.loads(line)
    return {"path": path, "status": "fails", "error": "Crash", "message": (p.stderr.strip().splitlines() or ["?"])[-1][:200]}


def main() -> int:
    ap = argparse.ArgumentParser()
    ap.add_argument("root")
    ap.add_argument("--out", default=None)
    ap.add_argument("--json", default=None)
    ap.add_argument("--timeout", type=float, default=30.0)
    ap.add_argument("--jobs", type=int, default=2)
    ap.add_argument("--rust", default="", help="a genform binary: compare with the Rust .lpy reader's --string-out")
    args = ap.parse_args()
    root = os.path.abspath(args.root)
    files = sorted(
        os.path.join(d, f) for d, _, fs in os.walk(root) for f in fs if f.endswith(".lpy") and "/.git/" not in d
    )
    with concurrent.futures.ThreadPoolExecutor(args.jobs) as ex:
        results = list(ex.map(lambda f: run_one(f, args.timeout, os.path.abspath(args.rust) if args.rust else ""), files))
    for r in results:
        r["path"] = os.path.relpath(r["path"], root)
        r["reason"] = reason(r)
    runs = [r for r in results if r["status"] == "runs"]
    by_reason = collections.Counter(r["reason"] for r in results if r["status"] != "runs")
    lines = [
        "# L-Py files through `genform.lpy` (survey)",
        "",
        "Written by `scripts/lpy_survey.py` (each file derived for its own",
        "derivation length with `random` seeded with 1, then drawn to a genform",
        f"model; {args.timeout:g} s per file).",
        "",
        f"**{len(runs)} of {len(results)} run** ({100 * len(runs) / max(1, len(results)):.0f} %).",
        "",
        "| why not | files |",
        "|---|---|",
    ]
    lines += [f"| {k} | {v} |" for k, v in by_reason.most_common()]
    both = [r for r in runs if r.get("rust") in ("same", "differs")]
    if both:
        same = sum(r["rust"] == "same" for r in both)
        exact = sum(bool(r.get("rust_exact")) for r in both)
        lines += [
            "",
            f"Of the {len(runs)} that run, {len(both)} also derive through the Rust `.lpy` reader "
            f"(`genform sample --string-out`, seed 1): {same} give the same string (parameters to 6 decimals), "
            f"{exact} of them character for character as L-Py prints it; "
            "the others draw random numbers (Python's `random` and genform's stream differ) or differ as listed.",
        ]
    lines += ["", "| file | result | modules | derive s | Rust reader |", "|---|---|---|---|---|"]
    for r in results:
        res = "runs" if r["status"] == "runs" else r["reason"] + (f" ({r['where']})" if r.get("where") else "")
        mods = r.get("modules", "")
        sec = f"{r['derive_s']:.2f}" if "derive_s" in r else ""
        lines.append(f"| `{r['path']}` | {res.replace('|', '/')} | {mods} | {sec} | {r.get('rust', '') + (' (exact)' if r.get('rust_exact') else '')} |")
    text = "\n".join(lines) + "\n"
    if args.out:
        with open(args.out, "w", encoding="utf-8") as f:
            f.write(text)
    else:
        sys.stdout.write(text)
    if args.json:
        with open(args.json, "w", encoding="utf-8") as f:
            json.dump(results, f, indent=1)
    print(f"{len(runs)}/{len(results)} run", file=sys.stderr)
    for k, v in by_reason.most_common():
        print(f"  {v:4d}  {k}", file=sys.stderr)
    return 0


if __name__ == "__main__":
    sys.exit(main())
