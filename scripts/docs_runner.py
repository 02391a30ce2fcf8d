#!/usr/bin/env python3
"""Runs every command and Python block of the docs as written (scripts/test-docs).

Reads the fenced code blocks of README.md and docs/*.md:

* ```sh / bash / shell / console blocks: each line that calls `genform …`
  (or `cargo run --release -- …`, which runs the same binary) runs through
  bash, with `genform` on PATH being the debug binary `cargo test --workspace`
  built ($GENFORM_BIN, else $CARGO_TARGET_DIR/debug/genform). `$ ` prompts
  are dropped, `\\` continuations joined, trailing `# comments` left to bash,
  and a `for … do … done` loop around genform lines runs as one command.
  Other lines (pip, cargo, scripts/…, cd …) are not run; the repository
  paths they name must exist.
* ```python blocks run in the test environment's Python ($GENFORM_VENV, else
  $CARGO_TARGET_DIR/py-venv, which scripts/test-python made with the wheel).
  A block may use the imports of the Python blocks above it in the same
  file, as in one session; every other name it uses it must define itself.

Everything runs in a scratch folder laid out like the repository (a copy of
examples/, one per doc file), with HOME pointing into it: a Python block that
starts Ray alone first, then several at a time, those whose end is waited for
first (the other commands are niced). A command passes when it exits 0; a
long one (an evolution with many generations, a comparison, a sweep) that is
still running after the time limit without having printed an `error:` line
passes as "alive" and is stopped there; `genform serve` passes once it has
printed its URL. A command whose output a later command of the same file
reads (`--out run` then `--genome run/best-genome.json`) must run to its end.
A command meant to fail (the doc shows its error) is marked by a next line in
the block that starts with `error:`, by a trailing `# fails` comment, or by
`<!-- docs-runner: fails -->` just before the block; it passes when it exits
non-zero with an `error:` line. `<!-- docs-runner: skip REASON -->` just
before a block leaves it out. A Python block that fails only because it
imports a package the docs name as optional (prose like `pip install
pandas`) is counted as skipped, with a note.

Environment: GENFORM_DOCS_LIMIT (seconds a command may run, default 5),
GENFORM_DOCS_PY_LIMIT (Python blocks, default 40), GENFORM_DOCS_JOBS
(commands at a time, default 4), GENFORM_DOCS_KEEP=1 keeps the scratch
folder. Exit status 1 on any failure.
"""

from __future__ import annotations

import os
import re
import shlex
import shutil
import signal
import subprocess
import sys
import tempfile
import threading
import time
from dataclasses import dataclass, field
from pathlib import Path

REPO = Path(__file__).resolve().parent.parent
SHELL_LANGS = {"sh", "bash", "shell", "console", "zsh"}
OUTPUT_FLAGS = {"--out", "-o", "--genome-out", "--string-out", "--trace"}
# Repository folders whose paths a skipped line may name; such paths must exist.
CHECKED_ROOTS = {"scripts", "crates", "python", "examples", "docs", "fuzz", "tests"}
MARKER = re.compile(r"^\s*<!--\s*docs-runner:\s*(\w[\w-]*)\s*(.*?)\s*-->\s*$")
FENCE = re.compile(r"^(\s*)(`{3,}|~{3,})\s*([\w+-]*)")
GENFORM_CALL = re.compile(r"^(genform|cargo\s+run\s+--release\s+--)\s")
URL = re.compile(r"https?://[\w.\-]+:\d+/?")
RAY_IMPORT = re.compile(r"^\s*(import\s+ray\b|from\s+ray\b|import\s.*\bray\b)", re.M)
NO_MODULE = re.compile(r"ModuleNotFoundError: No module named '([\w.]+)'")


def env_number(name: str, default: float) -> float:
    try:
        return float(os.environ.get(name, default))
    except ValueError:
        sys.exit(f"docs: {name} must be a number")


LIMIT = env_number("GENFORM_DOCS_LIMIT", 5)
PY_LIMIT = env_number("GENFORM_DOCS_PY_LIMIT", 40)
NEEDED_LIMIT = 180.0  # a command whose output a later command reads must end
JOBS = int(env_number("GENFORM_DOCS_JOBS", 4))


@dataclass
class Block:
    file: str
    line: int  # line number of the opening fence
    lang: str
    body: list[str]
    marker: tuple[str, str] | None  # (kind, argument) of a docs-runner comment just before


@dataclass
class Item:
    """One thing to run (a genform line or loop, or a Python block) or one skipped line."""

    file: str
    line: int
    kind: str  # "cmd", "python" or "skip"
    text: str
    expect_fail: bool = False
    reason: str = ""  # why skipped
    outputs: list[str] = field(default_factory=list)
    redirects: list[str] = field(default_factory=list)  # files bash opens for writing
    inputs: list[str] = field(default_factory=list)
    needs: list["Item"] = field(default_factory=list)  # earlier items to wait for
    must_finish: bool = False
    serve: bool = False
    prelude: str = ""  # Python: the imports of the blocks above
    # results
    status: str = ""  # pass, alive, fail, skip
    note: str = ""
    seconds: float = 0.0
    tail: str = ""


def doc_files(args: list[str]) -> list[Path]:
    if args:  # scripts/test-docs docs/evolve.md …: only these
        return [Path(a).resolve() for a in args]
    return [REPO / "README.md"] + sorted((REPO / "docs").glob("*.md"))


def relative(path: Path) -> str:
    try:
        return str(path.relative_to(REPO))
    except ValueError:
        return str(path)


def parse_blocks(path: Path) -> tuple[list[Block], list[str]]:
    """The fenced blocks of a markdown file, and its prose lines (outside blocks)."""
    lines = path.read_text(encoding="utf-8").split("\n")
    rel = relative(path)
    blocks, prose = [], []
    i = 0
    while i < len(lines):
        m = FENCE.match(lines[i])
        if not m:
            prose.append(lines[i])
            i += 1
            continue
        indent, fence, lang = m.groups()
        end = i + 1
        close = re.compile(r"^\s*" + re.escape(fence[0]) + "{" + str(len(fence)) + r",}\s*$")
        while end < len(lines) and not close.match(lines[end]):
            end += 1
        body = [ln[len(indent):] if ln.startswith(indent) else ln.lstrip() for ln in lines[i + 1:end]]
        marker = None
        j = i - 1
        while j >= 0 and not lines[j].strip():
            j -= 1
        if j >= 0 and (mm := MARKER.match(lines[j])):
            marker = (mm.group(1), mm.group(2))
        blocks.append(Block(rel, i + 1, lang.lower(), body, marker))
        i = end + 1
    return blocks, prose


def optional_packages(prose: list[str]) -> set[str]:
    """Packages the docs' prose tells the reader to install themselves: `pip install pandas`."""
    names = set()
    # paragraph by paragraph: an inline `pip install\npandas` may span lines
    for para in re.split(r"\n\s*\n", "\n".join(prose)):
        for code in re.findall(r"`([^`]*)`", " ".join(para.split())):
            m = re.match(r"\s*pip install ([A-Za-z][\w.\-]*)(\s|$|&)", code)
            if m:
                names.add(m.group(1).lower().replace("-", "_"))
    return names


def strip_comment(line: str) -> tuple[str, str]:
    """(the command, its trailing comment) of a shell line; a `#` inside quotes stays."""
    quote = None
    for k, ch in enumerate(line):
        if quote:
            if ch == quote:
                quote = None
        elif ch in "'\"":
            quote = ch
        elif ch == "#" and (k == 0 or line[k - 1].isspace()):
            return line[:k].rstrip(), line[k + 1:].strip()
    return line.rstrip(), ""


def shell_items(block: Block) -> list[Item]:
    console = block.lang == "console"
    items: list[Item] = []
    lines = block.body
    i = 0
    while i < len(lines):
        raw = lines[i]
        start = i
        text = raw.strip()
        i += 1
        prompt = re.match(r"^[$%]\s+", text)
        if console and not prompt:
            continue  # output
        if prompt:
            text = text[prompt.end():]
        if not text or text.startswith("#") or re.match(r"(error|warning):", text):
            continue  # comments, and the output a block shows
        # `\` continuations
        while strip_comment(text)[0].endswith("\\") and i < len(lines):
            text = strip_comment(text)[0][:-1].rstrip() + " " + lines[i].strip()
            i += 1
        # a loop: up to the `done` that closes its `do`s
        if re.match(r"^(for|while)\s", text):
            depth = len(re.findall(r"\bdo\b", strip_comment(text)[0])) - len(re.findall(r"\bdone\b", text))
            while depth > 0 and i < len(lines):
                nxt = lines[i].strip()
                code = strip_comment(nxt)[0]
                depth += len(re.findall(r"\bdo\b", code)) - len(re.findall(r"\bdone\b", code))
                text += "\n" + nxt
                i += 1
        code, comment = strip_comment(text.split("\n")[0])
        body_code = "\n".join(strip_comment(t)[0] for t in text.split("\n"))
        next_line = lines[i].strip() if i < len(lines) else ""
        expect_fail = (
            next_line.startswith("error:")
            or re.match(r"fails\b", comment) is not None
            or (block.marker is not None and block.marker[0] == "fails")
        )
        is_loop = "\n" in text
        calls = [strip_comment(t)[0].strip() for t in text.split("\n")]
        if GENFORM_CALL.match(code) or (is_loop and any(GENFORM_CALL.match(c) for c in calls)):
            cargo = r"(^|\n)(\s*)cargo\s+run\s+--release\s+--\s"
            run = re.sub(cargo, r"\1\2genform ", text)
            body_code = re.sub(cargo, r"\1\2genform ", body_code)
            item = Item(block.file, block.line + 1 + start, "cmd", run, expect_fail=expect_fail)
            scan_paths(item, body_code)
            item.serve = re.search(r"(^|\s)genform\s+serve\b", body_code) is not None
            items.append(item)
        else:
            word = code.split()[0] if code.split() else code
            items.append(Item(block.file, block.line + 1 + start, "skip", text,
                              reason=f"not a genform command ({word})"))
    return items


def scan_paths(item: Item, code: str) -> None:
    """The files a command writes (its output flags and redirections) and the paths it names."""
    try:
        words = shlex.split(code.replace(";", " ; "))
    except ValueError:
        words = code.split()
    k = 0
    while k < len(words):
        w = words[k]
        if w in OUTPUT_FLAGS and k + 1 < len(words):
            item.outputs.append(norm(words[k + 1]))
            k += 2
            continue
        if w.startswith("--out="):
            item.outputs.append(norm(w.split("=", 1)[1]))
        elif w in (">", ">>") and k + 1 < len(words):
            item.outputs.append(words[k + 1])
            item.redirects.append(words[k + 1])
            k += 2
            continue
        elif "/" in w or "." in w:
            item.inputs.append(norm(w))
        k += 1


def norm(p: str) -> str:
    return os.path.normpath(p) if p and "$" not in p else p


def reads(later: Item, earlier: Item) -> bool:
    return any(i == o or i.startswith(o.rstrip("/") + "/") for o in earlier.outputs for i in later.inputs)


def python_items(block: Block, prelude: list[str]) -> Item:
    code = "\n".join(block.body)
    # an import that fails here is the earlier block's failure, not this one's
    guarded = [f"try:\n    {ln}\nexcept ImportError:\n    pass" for ln in prelude]
    return Item(block.file, block.line, "python", code, prelude="\n".join(guarded))


def imports_of(block: Block) -> list[str]:
    return [ln for ln in block.body if re.match(r"^(import|from)\s+[\w.]+", ln) and ";" not in ln]


def check_skipped_paths(item: Item) -> None:
    """A line that is not run still must not name a repository file that is not there."""
    try:
        words = shlex.split(strip_comment(item.text)[0])
    except ValueError:
        words = item.text.split()
    missing = []
    for w in words:
        w = w.rstrip(")")
        p = w[2:] if w.startswith("./") else w
        if any(ch in p for ch in "*?<>$[") or p.startswith(("/", "~", "../", "target")):
            continue
        if p.split("/")[0] in CHECKED_ROOTS and not (REPO / p).exists():
            missing.append(w)
    if missing:
        item.status, item.note = "fail", "not run, but names repository paths that do not exist: " + ", ".join(missing)


class Runner:
    def __init__(self, scratch: Path, binary: Path, python: Path | None):
        self.scratch = scratch
        self.python = python
        self.shim = scratch / "bin"
        self.shim.mkdir()
        (self.shim / "genform").symlink_to(binary)
        self.home = scratch / "home"
        self.home.mkdir()
        self.serve_lock = threading.Lock()
        self.roots: dict[str, Path] = {}
        self.root_lock = threading.Lock()
        self.optional: set[str] = set()

    def root(self, file: str) -> Path:
        """A folder laid out like the repository (a copy of examples/), one per doc file."""
        with self.root_lock:
            if file not in self.roots:
                r = self.scratch / re.sub(r"[^\w]+", "-", file)
                shutil.copytree(REPO / "examples", r / "examples", symlinks=True)
                self.roots[file] = r
            return self.roots[file]

    def env(self) -> dict[str, str]:
        env = dict(os.environ)
        env["PATH"] = f"{self.shim}{os.pathsep}{env.get('PATH', '')}"
        env["HOME"] = str(self.home)
        env["RAY_TMPDIR"] = str(self.scratch / "ray")
        env["MPLBACKEND"] = "Agg"
        env.pop("VIRTUAL_ENV", None)
        return env

    def run_all(self, items: list[Item], jobs: int) -> None:
        """Runs the items `jobs` at a time, each once the items it needs are done, in list order."""
        pending = list(items)
        cond = threading.Condition()

        def worker() -> None:
            while True:
                with cond:
                    while True:
                        ready = next((it for it in pending if all(d.done.is_set() for d in it.needs)), None)
                        if ready is not None or not pending:
                            break
                        cond.wait()
                    if ready is None:
                        return
                    pending.remove(ready)
                self.run(ready)
                with cond:
                    cond.notify_all()

        threads = [threading.Thread(target=worker) for _ in range(max(1, jobs))]
        for t in threads:
            t.start()
        for t in threads:
            t.join()

    def run(self, item: Item) -> None:
        try:
            if item.kind == "cmd":
                if any(d.must_finish and d.status != "pass" for d in item.needs if reads(item, d)):
                    item.status, item.note = "fail", "an earlier command it reads from did not finish"
                elif item.serve:
                    with self.serve_lock:
                        self.run_cmd(item)
                else:
                    self.run_cmd(item)
            else:
                self.run_python(item)
        except Exception as e:  # the runner's own trouble counts as a failure
            item.status, item.tail = "fail", f"runner: {e!r}"
        finally:
            item.done.set()  # type: ignore[attr-defined]

    def spawn(self, argv: list[str], cwd: Path, log: Path, limit: float, serve: bool):
        """Runs argv in its own process group; returns (exit code or None if stopped, seconds, output)."""
        start = time.monotonic()
        with open(log, "wb") as out:
            proc = subprocess.Popen(argv, cwd=cwd, env=self.env(), stdout=out, stderr=subprocess.STDOUT,
                                    stdin=subprocess.DEVNULL, start_new_session=True)
            code = None
            while True:
                try:
                    code = proc.wait(timeout=0.1)
                    break
                except subprocess.TimeoutExpired:
                    pass
                if time.monotonic() - start >= limit:
                    break
                if serve and URL.search(log.read_text(errors="replace")):
                    break
            if code is None:
                kill_group(proc)
        if not serve:
            self.reap(self.scratch / "ray", environ=False)  # a local Ray cluster a block started
        return code, time.monotonic() - start, log.read_text(errors="replace")

    def run_cmd(self, item: Item) -> None:
        root = self.root(item.file)
        for o in item.redirects:  # a redirection into a folder the reader has (~/.local/share/…)
            target = Path(o.replace("~", str(self.home), 1)) if o.startswith("~") else root / o
            if "$" not in o:
                target.parent.mkdir(parents=True, exist_ok=True)
        limit = NEEDED_LIMIT if item.must_finish else LIMIT
        log = self.scratch / f"log-{id(item)}.txt"
        # A command whose end nothing waits for yields the CPU to those that must end
        # (and a long one is stopped at the limit anyway).
        nice = [] if item.must_finish else ["nice", "-n", "10"]
        code, item.seconds, out = self.spawn(nice + ["bash", "-e", "-o", "pipefail", "-c", item.text], root, log,
                                             limit, item.serve)
        if item.serve and code is not None and "Address already in use" in out and "\n" not in item.text:
            # another program holds the port: that is this machine, not the doc
            again = strip_comment(item.text)[0] + " --port 0"
            code, item.seconds, out = self.spawn(["bash", "-c", again], root, log, limit, True)
            item.note = "its port was taken by another program, so it ran with --port 0: "
        errors = [ln for ln in out.splitlines() if ln.lstrip().startswith("error:")]
        item.tail = "\n".join(out.strip().splitlines()[-12:])
        if item.serve and code is None and URL.search(out):
            item.status, item.note = "pass", item.note + "printed " + URL.search(out).group(0)
        elif item.serve:
            item.status = "fail"
            item.note += "exited before printing its URL" if code is not None else "no URL within the limit"
        elif item.expect_fail:
            ok = code not in (None, 0) and errors
            item.status = "pass" if ok else "fail"
            item.note = "failed as the doc shows" if ok else "meant to fail with an `error:` line"
        elif code == 0:
            item.status = "pass"
        elif code is None and not errors:
            if item.must_finish:
                item.status, item.note = "fail", f"a later command reads its output, but it ran past {limit:.0f} s"
            else:
                item.status, item.note = "alive", f"still running after {limit:.0f} s, stopped"
        else:
            item.status = "fail"
            item.note = f"exit status {code}" if code is not None else "printed an error and kept running"

    def run_python(self, item: Item) -> None:
        if self.python is None:
            item.status, item.note = "fail", "no test environment (run scripts/test-python first)"
            return
        root = self.root(item.file)
        script = self.scratch / f"block-{Path(item.file).stem}-{item.line}.py"
        script.write_text((item.prelude + "\n" if item.prelude else "") + item.text + "\n", encoding="utf-8")
        log = self.scratch / f"log-{id(item)}.txt"
        code, item.seconds, out = self.spawn([str(self.python), str(script)], root, log, PY_LIMIT, False)
        item.tail = "\n".join(out.strip().splitlines()[-12:])
        missing = NO_MODULE.findall(out)
        if code == 0:
            item.status = "pass"
        elif code is None:
            item.status, item.note = "alive", f"still running after {PY_LIMIT:.0f} s, stopped"
        elif missing and missing[-1].split(".")[0].lower() in self.optional:
            item.status = "skip"
            item.note = f"needs {missing[-1]}, which the docs name as optional (not in the test environment)"
        else:
            item.status, item.note = "fail", f"exit status {code}"

    def reap(self, folder: Path, environ: bool) -> None:
        """Stops what a block left behind (Ray's local cluster): processes naming `folder`
        in their command line (or, with `environ`, in their environment)."""
        mark = str(folder).encode()
        me = os.getpid()
        for proc in Path("/proc").iterdir():
            if not proc.name.isdigit() or int(proc.name) == me:
                continue
            try:
                if mark in (proc / "cmdline").read_bytes() or (environ and mark in (proc / "environ").read_bytes()):
                    os.kill(int(proc.name), signal.SIGKILL)
            except (OSError, PermissionError):
                pass


def kill_group(proc: subprocess.Popen) -> None:
    try:
        os.killpg(proc.pid, signal.SIGTERM)
        try:
            proc.wait(timeout=2)
        except subprocess.TimeoutExpired:
            pass
        os.killpg(proc.pid, signal.SIGKILL)
    except ProcessLookupError:
        pass
    proc.wait()


def main() -> int:
    started = time.monotonic()
    target = Path(os.environ.get("CARGO_TARGET_DIR", REPO / "target"))
    if not target.is_absolute():
        target = REPO / target
    binary = Path(os.environ.get("GENFORM_BIN", target / "debug" / "genform")).resolve()
    if not binary.is_file():
        sys.exit(f"docs: no genform binary at {binary} (run `cargo build` or `cargo test --workspace` first)")
    venv = Path(os.environ.get("GENFORM_VENV", target / "py-venv")).resolve()
    python = venv / "bin" / "python"

    files = doc_files(sys.argv[1:])
    per_file: dict[str, dict] = {}
    items: list[Item] = []
    optional: set[str] = set()
    for path in files:
        blocks, prose = parse_blocks(path)
        optional |= optional_packages(prose)
        rel = relative(path)
        stats = per_file.setdefault(rel, {"blocks": len(blocks), "runnable": 0, "skipped_blocks": []})
        earlier_imports: list[str] = []
        for b in blocks:
            if b.lang not in SHELL_LANGS and b.lang != "python":
                continue
            if b.marker and b.marker[0] == "skip":
                stats["skipped_blocks"].append(f"line {b.line}: {b.marker[1] or 'marked skip'}")
                continue
            stats["runnable"] += 1
            if b.lang == "python":
                items.append(python_items(b, list(dict.fromkeys(earlier_imports))))
                earlier_imports += imports_of(b)
            else:
                items.extend(shell_items(b))

    # Order within a file: a command waits for the earlier ones whose output it reads
    # (those must run to their end) or whose output it overwrites.
    for k, it in enumerate(items):
        if it.kind != "cmd":
            continue
        for prev in items[:k]:
            if prev.kind != "cmd" or prev.file != it.file:
                continue
            if reads(it, prev):
                prev.must_finish = True
                it.needs.append(prev)
            elif set(it.outputs) & set(prev.outputs):
                it.needs.append(prev)
    for it in items:
        it.done = threading.Event()  # type: ignore[attr-defined]
        if it.kind == "skip":
            check_skipped_paths(it)
            if not it.status:
                it.status, it.note = "skip", it.reason

    scratch = Path(tempfile.mkdtemp(prefix="genform-docs-"))
    runner = Runner(scratch, binary, python if python.is_file() else None)
    runner.optional = optional
    todo = [it for it in items if it.kind != "skip"]
    # A block that starts a local Ray cluster runs alone, first: Ray gives its raylet 30 s
    # to come up, which two cores busy with other commands do not always give it.
    alone = [it for it in todo if it.kind == "python" and RAY_IMPORT.search(it.text)]
    todo = [it for it in todo if it not in alone]
    # Then what must run to its end (Python blocks, commands whose output a later
    # command reads), then the other commands in the docs' order.
    todo.sort(key=lambda it: 0 if it.kind == "python" or it.must_finish else 1)
    print(f"docs: {len(alone) + len(todo)} commands and Python blocks from {len(files)} files, {JOBS} at a time "
          f"(limit {LIMIT:.0f} s a command, {PY_LIMIT:.0f} s a Python block), in {scratch}", flush=True)
    try:
        runner.run_all(alone, 1)
        if alone:
            print(f"docs: {len(alone)} Python block(s) with Ray, alone, in {time.monotonic() - started:.0f} s",
                  flush=True)
        runner.run_all(todo, JOBS)
    finally:
        runner.reap(scratch, environ=True)  # nothing of ours runs any more
        if os.environ.get("GENFORM_DOCS_KEEP") != "1":
            shutil.rmtree(scratch, ignore_errors=True)

    failed = [it for it in items if it.status == "fail"]
    print(f"{'file':<26} {'blocks':>6} {'run':>4} {'items':>5} {'pass':>5} {'alive':>5} {'skip':>5} {'fail':>5}")
    totals = [0] * 7
    for rel, st in per_file.items():
        mine = [it for it in items if it.file == rel]
        row = [st["blocks"], st["runnable"], len([it for it in mine if it.kind != "skip"]),
               sum(it.status == "pass" for it in mine), sum(it.status == "alive" for it in mine),
               sum(it.status == "skip" for it in mine), sum(it.status == "fail" for it in mine)]
        totals = [a + b for a, b in zip(totals, row)]
        print(f"{rel:<26} " + " ".join(f"{v:>{w}}" for v, w in zip(row, (6, 4, 5, 5, 5, 5, 5))))
        for s in st["skipped_blocks"]:
            print(f"    block skipped at {s}")
    print(f"{'all':<26} " + " ".join(f"{v:>{w}}" for v, w in zip(totals, (6, 4, 5, 5, 5, 5, 5))))
    print("(blocks: fenced blocks; run: shell and Python blocks; items: genform lines, loops and Python"
          " blocks run; skip: lines that are not genform commands, or optional packages)")
    if os.environ.get("GENFORM_DOCS_VERBOSE") == "1":
        for it in items:
            first = it.text.split("\n")[0][:110]
            print(f"  {it.status:<5} {it.seconds:5.1f}s {it.file}:{it.line}: {first}  {it.note}")
    for it in items:
        if it.status == "skip":
            what = "Python block" if it.kind == "python" else strip_comment(it.text.split("\n")[0])[0][:70]
            print(f"skipped {it.file}:{it.line}: {what}: {it.note}")
    for it in failed:
        print(f"\nFAILED {it.file}:{it.line}: {it.note}\n  {it.text.strip()}")
        if it.tail:
            print("  | " + "\n  | ".join(it.tail.splitlines()))
    print(f"\ndocs: {len(failed)} failed, {totals[3]} passed, {totals[4]} alive at the limit, "
          f"{totals[5]} skipped, in {time.monotonic() - started:.0f} s")
    return 1 if failed else 0


if __name__ == "__main__":
    sys.exit(main())
