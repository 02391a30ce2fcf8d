"""L-Py files with real Python: ``genform.lpy``.

``Lsystem(path)`` reads a whole ``.lpy`` file of L-Py (openalea/lpy) the way
L-Py's own parser does and runs it with CPython: module-level Python, the
hooks ``Start``/``StartEach``/``EndEach``/``End``, production bodies with
``produce``/``nproduce``, ``Stop()``, ``useGroup()``, ``getIterationNb()``,
``forward()``/``backward()``, the ``lstring`` passed to hooks, and the init
block (``__initialiseContext__``) that sets the editor's scalars, curves and
materials. PlantGL is not needed for curves, vectors and materials (see
``genform._lpy_pgl``); files that build PlantGL geometry stop with
``PlantGLUnavailable``.

The derivation follows L-Py: each step tries, at each module from left to
right (right to left after ``backward()``), the rules of the active group
and then those of group 0 in file order; a rule whose body returns without
``produce`` does not apply and the next one is tried. Contexts are matched
in the axial tree (``<`` and ``>`` skip branches, ``ignore:``/``consider:``
filter), ``<<`` and ``>>`` match against the string already produced in
this step. Decomposition and interpretation rules re-apply up to their
``maximum depth``; interpretation rules change only the drawing.

The derived string is drawn by genform's turtle (``Lsystem.model()``), with
PlantGL's start frame, default angle and widths (as the Rust ``.lpy``
reader does), so ``model.save("plant.glb")`` writes every genform format.
"""

from __future__ import annotations

import builtins
import inspect
import math
import os
import random as _random
import re
import tempfile
import time
import types

from . import _genform as _native
from . import _lpy_pgl

__all__ = [
    "Lsystem",
    "Lstring",
    "Module",
    "LpyError",
    "LpyUnsupported",
    "PlantGLUnavailable",
]

PlantGLUnavailable = _lpy_pgl.PlantGLUnavailable


class LpyError(Exception):
    """A `.lpy` file that cannot be read: the message names file:line."""


class LpyUnsupported(LpyError):
    """A construct of L-Py that genform's Python path does not run."""


# --------------------------------------------------------------- module names

# L-Py's predefined module names (src/cpp/predefinedmodules.cpp), every
# spelling; L-Py reads a module name as the longest known name, else one
# character.
PREDEFINED = """[ SB ] EB =] F f nF ?P GetPos ?H GetHead ?U GetUp ?L GetLeft ?R GetRight ?F GetFrame
@Gc StartGC @Ge EndGC { BP } EP . PP @M MoveTo MoveRel LineTo OLineTo Pinpoint LineRel OLineRel
PinpointRel @R SetHead EulerAngles + Left - Right ^ Up & Down / RollL \\ RollR iRollL iRollR
| TurnAround @v RollToVert @h RollToHorizontal @O Sphere @B Box @b Quad @o Circle @L Label
_ IncWidth ! DecWidth SetWidth ; IncColor , DecColor SetColor InterpolateColors TextureBaseColor
InterpolateTextureBaseColors @Dd DivScale @Di MultScale @D SetScale surface ~ @g PglShape Frame
Arrow @Ts Elasticity @Tp Tropism SetContour SectionResolution SetGuide EndGuide Sweep
PositionOnGuide TextureScale TextureUScale TextureVScale TextureVCoeff TextureTranslation
TextureRotation TextureTransformation LeftReflection UpReflection HeadingReflection
@2D StartScreenProjection @3D EndScreenProjection % Cut * ?I GetIterator $ GetModule
X MouseIns""".split()

# Spellings of one module class: L-Py keeps the first as the name.
_SAME = [
    ("[", "SB"), ("]", "EB"), ("?P", "GetPos"), ("?H", "GetHead"), ("?U", "GetUp"), ("?L", "GetLeft"),
    ("?R", "GetRight"), ("?F", "GetFrame"), ("@Gc", "StartGC"), ("@Ge", "EndGC"), ("{", "BP"),
    ("}", "EP"), (".", "PP"), ("@M", "MoveTo"), ("@R", "SetHead"), ("+", "Left"), ("-", "Right"),
    ("^", "Up"), ("&", "Down"), ("/", "RollL"), ("\\", "RollR"), ("|", "TurnAround"),
    ("@v", "RollToVert"), ("@h", "RollToHorizontal"), ("@O", "Sphere"), ("@B", "Box"), ("@b", "Quad"),
    ("@o", "Circle"), ("@L", "Label"), ("_", "IncWidth"), ("!", "DecWidth"), (";", "IncColor"),
    (",", "DecColor"), ("@Dd", "DivScale"), ("@Di", "MultScale"), ("@D", "SetScale"), ("~", "surface"),
    ("@g", "PglShape"), ("@Ts", "Elasticity"), ("@Tp", "Tropism"), ("@2D", "StartScreenProjection"),
    ("@3D", "EndScreenProjection"), ("%", "Cut"), ("*", "any"), ("?I", "GetIterator"), ("$", "GetModule"),
    ("TextureVScale", "TextureVCoeff"),
]
CANONICAL = {alias: name for name, alias in _SAME}

# Modules matched as patterns but that genform's path does not run.
_PATTERN_ONLY = {"x", "repexp", "all", "or", "||", "?I", "GetIterator", "=]"}
_QUERIES = {"?P", "?H", "?U", "?L", "?R", "?F"}

# Which engine rewrites: the scan and the matching in Rust (the default),
# or `python`, the reference engine (`Lsystem._step_py`).
_RUST_ENGINE = os.environ.get("GENFORM_LPY_ENGINE", "rust").strip().lower() != "python"


class Module:
    """One module of an lstring: a name and its parameters (any Python
    objects), as L-Py's ``ParamModule``."""

    __slots__ = ("name", "args")

    def __init__(self, name, *args):
        if isinstance(name, Module):
            name, args = name.name, tuple(name.args) + args
        # The slots' own setters: `__setattr__` below is Python code, and
        # a derivation makes a module per produced symbol.
        _SET_NAME(self, CANONICAL.get(name, name))
        _SET_ARGS(self, list(args[0]) if len(args) == 1 and isinstance(args[0], _ArgList) else list(args))

    def __len__(self):
        return len(self.args)

    def __getitem__(self, i):
        return self.args[i]

    def __setitem__(self, i, v):
        self.args[i] = v

    def __iter__(self):
        return iter(self.args)

    def __getattr__(self, attr):
        names = _PARAM_NAMES.get(object.__getattribute__(self, "name"))
        if names and attr in names:
            i = names.index(attr)
            args = object.__getattribute__(self, "args")
            if i < len(args):
                return args[i]
        raise AttributeError(attr)

    def __setattr__(self, attr, value):
        if attr in Module.__slots__:
            object.__setattr__(self, attr, value)
            return
        names = _PARAM_NAMES.get(self.name)
        if names and attr in names:
            self.args[names.index(attr)] = value
            return
        raise AttributeError(attr)

    def argSize(self):
        return len(self.args)

    def hasParameter(self, name):
        names = _PARAM_NAMES.get(self.name)
        return bool(names and name in names)

    def getParameter(self, name):
        return getattr(self, name)

    def __eq__(self, other):
        if isinstance(other, Module):
            return self.name == other.name and self.args == other.args
        if isinstance(other, str):
            return str(self) == other or (not self.args and self.name == CANONICAL.get(other, other))
        return NotImplemented

    def __ne__(self, other):
        r = self.__eq__(other)
        return r if r is NotImplemented else not r

    def __hash__(self):
        return hash(self.name)

    def __str__(self):
        if not self.args:
            return self.name
        if self.name == "~" and isinstance(self.args[0], str) and len(self.args[0]) == 1:
            # A surface prints as written: `~l(2)`.
            rest = self.args[1:]
            return "~" + self.args[0] + ("(" + ",".join(_fmt(a) for a in rest) + ")" if rest else "")
        return self.name + "(" + ",".join(_fmt(a) for a in self.args) + ")"

    __repr__ = __str__

    def copy(self):
        return Module(self.name, *self.args)


ParamModule = Module
_SET_NAME = Module.name.__set__
_SET_ARGS = Module.args.__set__
_NEW = object.__new__


def _new_module(name, args):
    """``Module(name, *args)`` for a plain name and a tuple of parameters,
    without the call's checks (the successor of every rewrite is built
    this way)."""
    m = _NEW(Module)
    _SET_NAME(m, CANONICAL.get(name, name))
    _SET_ARGS(m, list(args[0]) if len(args) == 1 and type(args[0]) is _ArgList else list(args))
    return m


class _ArgList(list):
    """Parameters handed over whole (``PackedArgs``)."""


def PackedArgs(args):
    return _ArgList(args)


# Declared parameter names per module (``module A(x, y)``), for ``m.x``.
_PARAM_NAMES: dict[str, list[str]] = {}


def _fmt(v):
    if isinstance(v, bool):
        return str(v)
    if isinstance(v, float):
        return repr(v)
    if isinstance(v, (int, str)):
        return repr(v) if isinstance(v, str) else str(v)
    return str(v)


class Lstring:
    """A string of modules (L-Py's ``Lstring``/``AxialTree``)."""

    def __init__(self, items=None):
        if items is None:
            self._m = []
        elif isinstance(items, Lstring):
            self._m = [m.copy() for m in items._m]
        elif isinstance(items, str):
            self._m = _parse_lstring_value(items)
        else:
            self._m = [_as_module(x) for x in items]

    @classmethod
    def _wrap(cls, mods):
        s = cls.__new__(cls)
        s._m = mods
        return s

    def __len__(self):
        return len(self._m)

    def __iter__(self):
        return iter(self._m)

    def __getitem__(self, i):
        if isinstance(i, slice):
            return Lstring._wrap(self._m[i])
        return self._m[i]

    def __setitem__(self, i, v):
        self._m[i] = _as_module(v)

    def __delitem__(self, i):
        del self._m[i]

    def __str__(self):
        return "".join(str(m) for m in self._m)

    def __repr__(self):
        return f"Lstring({str(self)!r})"

    def __eq__(self, other):
        if isinstance(other, str):
            return str(self) == other or self._m == Lstring(other)._m
        if isinstance(other, Lstring):
            return self._m == other._m
        return NotImplemented

    def __add__(self, other):
        return Lstring._wrap(self._m + Lstring(other)._m if not isinstance(other, Lstring) else self._m + other._m)

    def __iadd__(self, other):
        self._m.extend(Lstring(other)._m if not isinstance(other, Lstring) else other._m)
        return self

    def append(self, m):
        self._m.append(_as_module(m))

    def insertAt(self, i, m):
        self._m[i:i] = Lstring(m)._m if isinstance(m, (str, Lstring, list)) else [_as_module(m)]

    def clear(self):
        self._m.clear()

    def empty(self):
        return not self._m

    def count(self, name):
        return sum(1 for m in self._m if m.name == name)

    def wellBracketed(self):
        depth = 0
        for m in self._m:
            depth += (m.name == "[") - (m.name == "]")
            if depth < 0:
                return False
        return depth == 0

    def endBracket(self, i):
        return _end_bracket(self._m, i)

    def parent(self, i):
        return _parent(self._m, i)

    def children(self, i):
        return _children(self._m, i)

    def complex(self, i):
        return None


AxialTree = Lstring


class ParameterSet:
    """L-Py's attribute bag (``openalea.lpy.parameterset``)."""

    def __init__(self, **kwd):
        self.__dict__.update(kwd)

    def hasattr(self, name):
        return hasattr(self, name)

    def get(self, name, default=None):
        return getattr(self, name, default)

    def set(self, **kwd):
        self.__dict__.update(kwd)

    def setdefault(self, **kwd):
        for k, v in kwd.items():
            if not hasattr(self, k):
                setattr(self, k, v)

    def parameter_names(self):
        return list(self.__dict__)

    def copy(self, deep=True):
        import copy

        return copy.deepcopy(self) if deep else copy.copy(self)

    def __getitem__(self, name):
        return getattr(self, name)

    def __setitem__(self, name, value):
        setattr(self, name, value)

    def __eq__(self, other):
        return isinstance(other, ParameterSet) and self.__dict__ == other.__dict__

    def __repr__(self):
        return "ParameterSet(" + ",".join(f"{k}={v!r}" for k, v in self.__dict__.items()) + ")"


def _as_module(x):
    if isinstance(x, Module):
        return x
    if isinstance(x, str):
        mods = _parse_lstring_value(x)
        if len(mods) != 1:
            raise LpyError(f"{x!r} is not one module")
        return mods[0]
    if isinstance(x, (tuple, list)) and x and isinstance(x[0], str):
        return Module(x[0], *x[1:])
    raise LpyError(f"{x!r} is not a module")


def _end_bracket(mods, i):
    depth = 0
    for j in range(i + 1, len(mods)):
        n = mods[j].name
        if n == "[":
            depth += 1
        elif n == "]":
            if depth == 0:
                return j
            depth -= 1
    return len(mods)


def _parent(mods, i):
    j = i - 1
    while j >= 0:
        n = mods[j].name
        if n == "]":
            j = _begin_bracket(mods, j) - 1
            continue
        if n == "[":
            j -= 1
            continue
        return j
    return None


def _begin_bracket(mods, j):
    depth = 0
    for k in range(j - 1, -1, -1):
        n = mods[k].name
        if n == "]":
            depth += 1
        elif n == "[":
            if depth == 0:
                return k
            depth -= 1
    return 0


def _children(mods, i):
    out = []
    j = i + 1
    while j < len(mods):
        n = mods[j].name
        if n == "[":
            k = j + 1
            if k < len(mods) and mods[k].name not in ("[", "]"):
                out.append(k)
            j = _end_bracket(mods, j) + 1
            continue
        if n == "]":
            break
        out.append(j)
        break
    return out


# -------------------------------------------------------------- lstring text


class _Names:
    """Module names known to a file: predefined and declared; the longest
    match wins, else one character."""

    def __init__(self):
        self.names = set(PREDEFINED)
        self.longest = max(len(n) for n in self.names)

    def declare(self, name):
        self.names.add(name)
        self.longest = max(self.longest, len(name))

    def read(self, text, i):
        for w in range(min(self.longest, len(text) - i), 0, -1):
            if text[i : i + w] in self.names:
                return text[i : i + w]
        return text[i]


_DEFAULT_NAMES = _Names()


def _skip_string(text, i):
    """Index after the string literal starting at text[i]."""
    q = text[i]
    if text.startswith(q * 3, i):
        end = text.find(q * 3, i + 3)
        return len(text) if end < 0 else end + 3
    j = i + 1
    while j < len(text) and text[j] != q and text[j] != "\n":
        j += 2 if text[j] == "\\" else 1
    return j + 1


def _parse_modules(text, i, delim, names, lineno=0):
    """L-Py's ``parselstring``: modules from text[i] up to `delim` (a
    character at top level) or the end. Returns ([(name, args text or
    None)], end index). A `$name` (GetModule) gives ('$', 'name')."""
    out = []
    n = len(text)
    while i < n and text[i] != delim:
        c = text[i]
        if c == "#":
            k = i + 1
            while k < n and text[k] in " \t":
                k += 1
            if k < n and text[k] == "(":
                # L-Py refuses cpfg's `#` module: `#` starts a comment.
                raise LpyError(f"line {lineno}: found `#(` in an lstring: `#` starts a comment in L-Py; use `_` instead")
            while i < n and text[i] != "\n" and text[i] != delim:
                i += 1
            continue
        if c in " \t\r\n":
            i += 1
            continue
        if c in "()":
            raise LpyError(f"line {lineno}: found a module named {c!r}")
        name = names.read(text, i)
        i += len(name)
        while i < n and text[i] in " \t":
            i += 1
        if name in ("$", "GetModule") and i < n and text[i] != "(":
            j = i
            while j < n and (text[j].isalnum() or text[j] == "_"):
                j += 1
            out.append(("$", text[i:j]))
            i = j
            continue
        args = None
        if name in ("~", "surface") and i < n and text[i] != "(" and text[i] not in " \t\n" and text[i] != delim:
            # `~l(2)`: the surface's name is a one-letter first argument.
            sname = text[i]
            i += 1
            args = repr(sname)
            if i < n and text[i] == "(":
                j = _close_paren(text, i, lineno)
                inner = text[i + 1 : j].strip()
                if inner:
                    args += "," + inner
                i = j + 1
            out.append((name, args))
            continue
        if i < n and text[i] == "(":
            j = _close_paren(text, i, lineno)
            args = text[i + 1 : j]
            i = j + 1
        out.append((name, args))
    return out, i


def _close_paren(text, i, lineno):
    depth = 0
    j = i
    n = len(text)
    while j < n:
        c = text[j]
        if c in "'\"":
            j = _skip_string(text, j)
            continue
        if c == "#":
            while j < n and text[j] != "\n":
                j += 1
            continue
        if c == "(":
            depth += 1
        elif c == ")":
            depth -= 1
            if depth == 0:
                return j
        j += 1
    raise LpyError(f"line {lineno}: unclosed parenthesis in an lstring")


def _split_args(text):
    """Top-level comma-separated pieces of an argument list."""
    out, depth, start, i = [], 0, 0, 0
    while i < len(text):
        c = text[i]
        if c in "'\"":
            i = _skip_string(text, i)
            continue
        if c in "([{":
            depth += 1
        elif c in ")]}":
            depth -= 1
        elif c == "," and depth == 0:
            out.append(text[start:i])
            start = i + 1
        i += 1
    last = text[start:]
    if last.strip() or out:
        out.append(last)
    return [a.strip() for a in out]


def _lstring_py(mods):
    """Python source of a list of modules (successor, axiom): items
    ``('name', (args,))`` and variables holding modules (``$m``)."""
    items = []
    for name, args in mods:
        if name == "$":
            items.append(args)
        elif name == "None" or (name in ("*", "any") and not (args or "").strip()):
            # `produce *` and a bare `produce` give an empty successor.
            continue
        elif args is None or not args.strip():
            items.append(f"({name!r},())")
        else:
            pieces = []
            for a in _split_args(args):
                if a.startswith("*") and not a.startswith("**"):
                    pieces.append(a)
                else:
                    pieces.append(a)
            items.append(f"({name!r},({','.join(pieces)},))")
    return "[" + ",".join(items) + "]"


def _parse_lstring_value(text, namespace=None, names=None):
    """An lstring from text, parameters evaluated as Python."""
    mods, _ = _parse_modules(text, 0, "\0", names or _DEFAULT_NAMES)
    src = _lstring_py(mods)
    items = eval(src, dict(namespace or {}))
    return [_item_module(x) for x in items]


def _item_module(x):
    if type(x) is Module or isinstance(x, Module):
        return x
    name, args = x
    if args and name in _NEW_NAMES:
        return Module(args[0], *args[1:])
    if type(name) is str:
        return _new_module(name, args)
    return Module(name, *args)


_NEW_NAMES = frozenset(("*", "any", "new", "newmodule"))


# ------------------------------------------------------------------ patterns


class _Pat:
    """One module of a rule's pattern."""

    __slots__ = ("name", "kinds", "values", "star", "checks")

    def __init__(self, name, args_text, lineno):
        self.name = CANONICAL.get(name, name)
        self.kinds = []  # per argument: 'var' or 'const'
        self.values = []  # variable name or constant value
        self.star = None  # name of a `*args` argument
        self.checks = {}  # argument index: (operator, expression source) of `x == v`, `n in 'AB'`
        if self.name in _PATTERN_ONLY:
            raise LpyUnsupported(f"line {lineno}: the pattern module {name!r} (repetition or alternative) is not run by genform")
        if self.name == "$":
            raise LpyUnsupported(f"line {lineno}: `$` in a pattern is not run by genform")
        if args_text is None:
            return
        for a in _split_args(args_text):
            if a.startswith("**"):
                raise LpyUnsupported(f"line {lineno}: keyword patterns `**{a[2:]}` are not run by genform")
            if a.startswith("*"):
                self.star = a[1:].strip()
                continue
            if self.star is not None:
                raise LpyError(f"line {lineno}: an argument after `*{self.star}`")
            if re.fullmatch(r"[A-Za-z_]\w*", a) and a not in ("True", "False", "None"):
                self.kinds.append("var")
                self.values.append(a)
                continue
            c = re.fullmatch(r"([A-Za-z_]\w*)\s*(==|!=|<=|>=|<|>|\bnot\s+in\b|\bin\b)\s*(.+)", a, re.S)
            if c:
                # A value constraint: the module matches when it holds.
                self.kinds.append("var")
                self.values.append(c.group(1))
                self.checks[len(self.kinds) - 1] = "__v " + re.sub(r"\s+", " ", c.group(2)) + " (" + c.group(3) + ")"
            else:
                try:
                    v = eval(a, {})
                except Exception:
                    raise LpyUnsupported(f"line {lineno}: the pattern argument {a!r} is not run by genform") from None
                self.kinds.append("const")
                self.values.append(v)

    def variables(self):
        vs = [v for k, v in zip(self.kinds, self.values) if k == "var"]
        if self.name in ("*", "any") and not self.kinds and self.star is None:
            return vs
        if self.star is not None:
            vs.append(self.star)
        return vs

    def match(self, m, out):
        """Binds the module's parameters into `out`; False if it does not match."""
        args = m.args
        if self.name == "*":
            if not self.kinds and self.star is None:
                return True
            # `*(n, x, y)`: the first variable is the name.
            vals = [m.name] + args
        else:
            if m.name != self.name:
                return False
            vals = args
        k = len(self.kinds)
        if self.star is None:
            if len(vals) != k:
                return False
        elif len(vals) < k:
            return False
        for j in range(k):
            if self.kinds[j] == "var":
                if self.checks and j in self.checks and not self.checks[j](vals[j]):
                    return False
                out.append(vals[j])
            elif vals[j] != self.values[j]:
                return False
        if self.star is not None:
            out.append(list(vals[k:]))
        return True


def _patterns(text, names, lineno):
    mods, _ = _parse_modules(text, 0, "\0", names, lineno)
    return [_Pat(n, a, lineno) for n, a in mods]


class _Filter:
    """``ignore:`` (skipped names) or ``consider:`` (only these names)."""

    def __init__(self, kind, names):
        self.kind = kind
        self.names = set(CANONICAL.get(n, n) for n in names)

    def skips(self, name):
        if name in ("[", "]"):
            return False
        return (name in self.names) if self.kind == "ignore" else (name not in self.names)


class _Rule:
    __slots__ = ("kind", "group", "left", "nleft", "pred", "nright", "right", "filter", "func", "lineno", "header")


# ------------------------------------------------------------- the translator

_KEYWORD_LINE = re.compile(
    r"(production|decomposition|interpretation|homomorphism)\s*:|endlsystem\b|endgroup\b|group\s+(\S+)\s*:|"
    r"maximum\s+depth\s*:|derivation\s+length\s*:|consider\s*:|ignore\s*:|def\s"
)


def _word_at(text, i, word):
    if not text.startswith(word, i):
        return False
    before = text[i - 1] if i > 0 else " "
    j = i + len(word)
    after = text[j] if j < len(text) else " "
    return not (before.isalnum() or before in "_.") and not (after.isalnum() or after == "_")


def _transform_python(text, names, first_line):
    """L-Py's keywords in Python code: ``produce X`` → a return of the
    successor, ``nproduce X`` → a call adding it, ``makestring(X)`` → an
    Lstring; strings and comments are left alone."""
    out = []
    i, last, n = 0, 0, len(text)
    while i < n:
        c = text[i]
        if c == "#":
            while i < n and text[i] != "\n":
                i += 1
            continue
        if c in "'\"":
            i = _skip_string(text, i)
            continue
        ctx = next((w for w in ("InLeftContext", "InRightContext") if c == "I" and _word_at(text, i, w)), None)
        if ctx:
            j = i + len(ctx)
            while j < n and text[j] in " \t":
                j += 1
            if j < n and text[j] == "(":
                # The pattern is L-Py syntax, not Python: handed over as text.
                lineno = first_line + text.count("\n", 0, i)
                close = _close_paren(text, j, lineno)
                pieces = _split_args(text[j + 1 : close])
                pattern, params = (pieces[0], "None") if len(pieces) == 1 else (",".join(pieces[:-1]), pieces[-1])
                out.append(text[last:i])
                out.append(f"__in_context__({ctx == 'InLeftContext'}, {pattern!r}, {params})")
                i = last = close + 1
                continue
        for word, head in (("nproduce", "__nproduce__"), ("produce", "return __produce__"), ("makestring", "__makestring__")):
            if c == word[0] and _word_at(text, i, word):
                out.append(text[last:i])
                j = i + len(word)
                while j < n and text[j] in " \t":
                    j += 1
                delim = "\n"
                if j < n and text[j] == "(":
                    delim = ")"
                    j += 1
                lineno = first_line + text.count("\n", 0, i)
                mods, j = _parse_modules(text, j, delim, names, lineno)
                consumed = text[i:j]
                if delim == ")" and j < n:
                    j += 1
                out.append(f"{head}({_lstring_py(mods)}" + "\n" * consumed.count("\n") + ")")
                i = last = j
                break
        else:
            i += 1
    out.append(text[last:])
    return "".join(out)


class _Parsed:
    def __init__(self):
        self.main = []  # lines of module-level Python (same numbering as the file)
        self.init = ""  # the init block's code
        self.init_line = 0
        self.rules = []  # (kind, group, header, definition, lineno, filter)
        self.axiom_function = False


def _parse(text, names):
    text = text.replace("\r\n", "\n").replace("\r", "\n")
    p = _Parsed()
    tag = text.find("###### INITIALISATION ######")
    if tag >= 0:
        p.init_line = text.count("\n", 0, tag) + 1
        p.init = "\n" * (p.init_line - 1) + text[tag:]
        text = text[:tag]
    lines = text.split("\n")
    main = ["" for _ in lines]
    mode = -1
    group = 0
    filt = None
    i = 0
    n = len(lines)
    while i < n:
        line = lines[i]
        stripped = line.strip()
        col0 = bool(line) and line[0] not in " \t"
        lineno = i + 1
        if mode == -1:
            if _opens_triple(line):
                # A multi-line string: its lines are Python, whatever they say.
                main[i] = line
                quote = _opens_triple(line)
                i += 1
                while i < n and quote not in lines[i]:
                    main[i] = lines[i]
                    i += 1
                if i < n:
                    main[i] = lines[i]
                    i += 1
                continue
            m = re.match(r"(Axiom|axiom)\s*:", line) if col0 else None
            if m:
                rest = line[m.end() :]
                mods, _ = _parse_modules(rest, 0, "\n", names, lineno)
                if not mods and i + 1 < n and lines[i + 1][:1] in (" ", "\t"):
                    main[i] = "def __axiom__():"
                    p.axiom_function = True
                else:
                    main[i] = "__axiom__ = " + _lstring_py(mods)
                i += 1
                continue
            m = re.match(r"derivation\s+length\s*:", line) if col0 else None
            if m:
                main[i] = "__derivation_length__ = " + line[m.end() :].split("#")[0].strip()
                i += 1
                continue
            m = re.match(r"(\s*)(module|undeclare)\s", line)
            if m and not re.match(r"\s*module\s*=", line):
                if m.group(2) == "module":
                    _declare(line[m.end() :], names, lineno)
                i += 1
                continue
            m = re.match(r"(production|decomposition|interpretation|homomorphism)\s*:", line) if col0 else None
            if m:
                mode = {"production": 0, "decomposition": 1}.get(m.group(1), 2)
                i += 1
                continue
            m = re.match(r"(ignore|consider)\s*:", line) if col0 else None
            if m:
                filt = _filter(m.group(1), line[m.end() :], names, lineno)
                i += 1
                continue
            if col0 and re.match(r"endlsystem\b", line):
                i += 1
                continue
            if col0 and re.match(r"(extern|group|endgroup)\b", line):
                raise LpyUnsupported(f"line {lineno}: `{stripped.split()[0]}` outside the rules is not run by genform")
            main[i] = line
            i += 1
            continue
        # Rule sections.
        if not stripped:
            i += 1
            continue
        if col0 and stripped.startswith("#"):
            i += 1
            continue
        if col0:
            m = _KEYWORD_LINE.match(line)
            if m:
                word = m.group(0)
                if word.startswith("def"):
                    mode = -1
                    continue
                if word.startswith("endlsystem"):
                    mode = -1
                elif word.startswith("endgroup"):
                    group = 0
                elif word.startswith("group"):
                    try:
                        group = int(m.group(2))
                    except ValueError:
                        raise LpyError(f"line {lineno}: invalid group {m.group(2)!r}") from None
                elif m.group(1):
                    mode = {"production": 0, "decomposition": 1}.get(m.group(1), 2)
                elif word.startswith("maximum"):
                    var = "__decomposition_max_depth__" if mode == 1 else "__homomorphism_max_depth__"
                    main[i] = f"{var} = " + line[m.end() :].split("#")[0].strip()
                elif word.startswith("derivation"):
                    main[i] = "__derivation_length__ = " + line[m.end() :].split("#")[0].strip()
                elif word.startswith("consider") or word.startswith("ignore"):
                    kind = "consider" if word.startswith("consider") else "ignore"
                    rest = line[m.end() :]
                    filt = _filter(kind, rest, names, lineno) if rest.split("#")[0].strip() else None
                i += 1
                continue
            # A rule: this line and the indented (or blank) ones after it.
            j = i + 1
            while j < n:
                nxt = lines[j]
                if nxt.strip() == "":
                    k = j
                    while k < n and lines[k].strip() == "":
                        k += 1
                    if k < n and lines[k][:1] in (" ", "\t"):
                        j = k
                        continue
                    break
                if nxt[:1] in (" ", "\t"):
                    j += 1
                    continue
                break
            rule_text = "\n".join(lines[i:j])
            p.rules.append((mode, group, rule_text, lineno, filt))
            i = j
            continue
        raise LpyError(f"line {lineno}: unexpected indent in the rules")
    p.main = main
    return p


def _opens_triple(line):
    """The triple quote a line opens and leaves open, if any."""
    i, n = 0, len(line)
    while i < n:
        c = line[i]
        if c == "#":
            return None
        if c in "'\"":
            q = c * 3
            if line.startswith(q, i):
                end = line.find(q, i + 3)
                if end < 0:
                    return q
                i = end + 3
                continue
            i = _skip_string(line, i)
            continue
        i += 1
    return None


def _declare(text, names, lineno):
    """``module A, B(x, y) : scale = 2``, ``module A = F``."""
    body = text.split("#")[0]
    body = re.split(r"\)\s*:|^\s*[^(:]*:", body)[0] if ":" in body else body
    for piece in _split_args(body):
        piece = piece.strip()
        if not piece:
            continue
        if "=" in piece and "(" not in piece.split("=")[0]:
            raise LpyUnsupported(f"line {lineno}: the module alias `{piece}` is not run by genform")
        m = re.match(r"([^\s(]+)\s*(?:\((.*)\))?", piece)
        if not m:
            raise LpyError(f"line {lineno}: invalid module declaration {piece!r}")
        name = m.group(1).rstrip(")")
        names.declare(name)
        if m.group(2):
            _PARAM_NAMES[name] = [a.strip() for a in m.group(2).split(",") if a.strip()]


def _filter(kind, text, names, lineno):
    mods, _ = _parse_modules(text.split("#")[0], 0, "\n", names, lineno)
    return _Filter(kind, [n for n, _ in mods])


def _split_rule(rule_text, lineno):
    """(header, definition, is_arrow): L-Py cuts at the first `:` or `-->`."""
    i = 0
    n = len(rule_text)
    while i < n:
        c = rule_text[i]
        if c == ":":
            return rule_text[:i], rule_text[i + 1 :], False
        if c == "-" and rule_text.startswith("-->", i) and (i == 0 or rule_text[i - 1] != "-"):
            return rule_text[:i], rule_text[i + 3 :], True
        if c == "-" and rule_text.startswith("-static->", i):
            return rule_text[:i], rule_text[i + 9 :], True
        if c == "(":
            i = _close_paren(rule_text, i, lineno) + 1
            continue
        i += 1
    raise LpyError(f"line {lineno}: a rule without `:` or `-->`: {rule_text.splitlines()[0]!r}")


def _split_header(header, lineno):
    """(left, new left, predecessor, new right, right) texts."""
    parts = {"cg": "", "ncg": "", "pred": "", "ncd": "", "cd": ""}
    # Split at top-level < << > >> (outside parentheses).
    tokens, buf, i, n = [], "", 0, len(header)
    while i < n:
        c = header[i]
        if c == "(":
            j = _close_paren(header, i, lineno)
            buf += header[i : j + 1]
            i = j + 1
            continue
        if c in "<>":
            op = header[i : i + 2] if header[i : i + 2] in ("<<", ">>") else c
            tokens.append(buf)
            tokens.append(op)
            buf = ""
            i += len(op)
            continue
        buf += c
        i += 1
    tokens.append(buf)
    segs = tokens[0::2]
    ops = tokens[1::2]
    if not ops:
        parts["pred"] = segs[0]
    else:
        # Everything before the last left operator is context; after the
        # first right operator too.
        k = 0
        while k < len(ops) and ops[k] in ("<", "<<"):
            parts["cg" if ops[k] == "<" else "ncg"] = segs[k]
            k += 1
        parts["pred"] = segs[k]
        while k < len(ops):
            if ops[k] not in (">", ">>"):
                raise LpyError(f"line {lineno}: ill-formed rule header {header.strip()!r}")
            parts["cd" if ops[k] == ">" else "ncd"] = segs[k + 1]
            k += 1
    if not parts["pred"].strip():
        raise LpyError(f"line {lineno}: no predecessor in {header.strip()!r}")
    return parts


# ------------------------------------------------------------- the L-system


class _Context:
    """What ``__initialiseContext__(context)`` and ``context()`` see."""

    def __init__(self, lsys):
        self._lsys = lsys
        self.turtle = _Turtle(lsys)
        self.options = _Options()
        self.animation_timestep = 0.1

    def __setitem__(self, k, v):
        self._lsys._ns[k] = v

    def __getitem__(self, k):
        return self._lsys._ns[k]

    def __contains__(self, k):
        return k in self._lsys._ns

    def __getattr__(self, name):
        return _Anything(name)

    def getIterationNb(self):
        return self._lsys._iteration

    def getGroup(self):
        return self._lsys._group

    def useGroup(self, g):
        self._lsys._group = int(g)

    def globals(self):
        return self._lsys._ns

    def locals(self):
        return self._lsys._ns


class _Anything:
    """Accepts any call or attribute (GUI and display settings)."""

    def __init__(self, name=""):
        self._name = name

    def __call__(self, *a, **k):
        return None

    def __getattr__(self, name):
        return _Anything(name)


class _Options(_Anything):
    def setSelection(self, name, value):
        return None


class _Turtle(_Anything):
    def __init__(self, lsys):
        super().__init__("turtle")
        self._lsys = lsys

    def setMaterial(self, i, material):
        if isinstance(material, _lpy_pgl.Material):
            self._lsys.materials[int(i)] = material.rgb()

    def setColorAt(self, i, *rgb):
        self._lsys.materials[int(i)] = tuple(int(c) for c in rgb[:3])

    def setAngleIncrement(self, a):
        self._lsys.angle = float(a)

    def setWidthIncrement(self, w):
        return None

    def setDefaultStep(self, s):
        self._lsys.step = float(s)


def _importer(real_import):
    """``__import__`` of a file's namespace: ``openalea.plantgl.*`` is the
    stand-in, ``openalea.lpy`` this module."""

    def imp(name, globals=None, locals=None, fromlist=(), level=0):
        if name == "openalea" or name.startswith("openalea."):
            top = types.ModuleType("openalea")
            pgl = _pgl_module()
            plantgl = types.ModuleType("openalea.plantgl")
            plantgl.all = pgl
            plantgl.math = pgl
            plantgl.scenegraph = pgl
            top.plantgl = plantgl
            lpymod = _lpy_module()
            top.lpy = lpymod
            if name.startswith("openalea.plantgl.light") or name.startswith("openalea.mtg") or name.startswith(
                "openalea.plantgl.gui"
            ):
                raise PlantGLUnavailable(f"`{name}` is not available in genform (a PlantGL or OpenAlea package)")
            mod = {
                "openalea": top,
                "openalea.plantgl": plantgl,
                "openalea.plantgl.all": pgl,
                "openalea.plantgl.math": pgl,
                "openalea.plantgl.scenegraph": pgl,
                "openalea.lpy": lpymod,
                "openalea.lpy.__lpyfuture__": lpymod,
                "openalea.lpy.parameterset": lpymod,
            }.get(name)
            if mod is None:
                raise ImportError(f"`{name}` is not available in genform")
            return mod if fromlist else top
        return real_import(name, globals, locals, fromlist, level)

    return imp


_PGL = None


def _pgl_module():
    global _PGL
    if _PGL is None:
        _PGL = types.ModuleType("openalea.plantgl.all")
        for k in _lpy_pgl.__all__:
            setattr(_PGL, k, getattr(_lpy_pgl, k))
    return _PGL


def _lpy_module():
    m = types.ModuleType("openalea.lpy")
    names = ["Lsystem", "Lstring", "AxialTree", "Module", "ParamModule", "PackedArgs", "ParameterSet"]
    for k in names:
        setattr(m, k, globals()[k])
    m.__all__ = names
    m.__lpyfuture__ = m
    return m


class Lsystem:
    """An L-Py L-system, as ``openalea.lpy.Lsystem``: ``Lsystem(path)``,
    ``axiom``, ``derivationLength``, ``derive``/``iterate``, ``model()``.

    `parameters` (a dict) overrides names of the file as L-Py's
    ``Lsystem(path, parameters)`` does. `seed` seeds Python's ``random``
    before the file runs and before each derivation from step 0, so the
    same seed gives the same string (``seed=None`` leaves ``random`` alone,
    as L-Py does)."""

    def __init__(self, path=None, parameters=None, seed=0):
        self.filename = os.fspath(path) if path is not None else ""
        self.materials: dict[int, tuple[int, int, int]] = {}
        self.angle = 60.0
        self.step = 1.0
        self._group = 0
        self._iteration = 0
        self._forward = True
        self._stop = False
        self._nprod: list = []
        self._rules: list[_Rule] = []
        # (kind, group, forward) → (active rules, their genform._genform.LpyRules).
        self._native_rules: dict = {}
        self._queries = False
        self._ctx_cache: dict = {}
        #: The longest string a derivation may make (as `.ls`'s max_modules).
        self.max_modules = 5_000_000
        self._ns: dict = {}
        self.lstring = None
        self._seed = seed
        if path is not None:
            with open(self.filename, encoding="utf-8", errors="replace") as f:
                self.setCode(f.read(), parameters)

    # -- reading

    def setCode(self, code, parameters=None):
        """Reads an L-Py file's text (``Lsystem.setCode``)."""
        fname = self.filename or "<lpy>"
        names = _Names()
        try:
            parsed = _parse(code, names)
        except LpyError as e:
            raise type(e)(f"{fname}: {e}") from None
        self._names = names
        ns = self._namespace()
        if parameters:
            ns.update(parameters)
        if self._seed is not None:
            _random.seed(self._seed)
        if parsed.init:
            self._exec(parsed.init, fname)
            init = ns.get("__initialiseContext__")
            if callable(init):
                init(self._context)
            if parameters:
                ns.update(parameters)
        main = "\n".join(parsed.main)
        try:
            main = _transform_python(main, names, 1)
        except LpyError as e:
            raise type(e)(f"{fname}: {e}") from None
        self._exec(main, fname)
        rules = []
        counters = {}
        for kind, group, text, lineno, filt in parsed.rules:
            try:
                rules.append(self._rule(kind, group, text, lineno, filt, counters, fname))
            except LpyError as e:
                raise type(e)(f"{fname}: {e}") from None
        self._rules = rules
        self._native_rules = {}
        # L-Py fills the turtle queries (?P, ?H, …) before each step whose
        # rules read them.
        self._queries = any(
            p.name in _QUERIES for r in rules if r.kind == 0 for p in r.left + r.nleft + r.pred + r.nright + r.right
        )
        self.derivationLength = int(ns.get("__derivation_length__", 1))
        self.decompositionMaxDepth = int(ns.get("__decomposition_max_depth__", 1))
        self.homomorphismMaxDepth = int(ns.get("__homomorphism_max_depth__", 1))
        ax = ns.get("__axiom__", [])
        if parsed.axiom_function and callable(ax):
            self._nprod = []
            res = ax()
            ax = self._collect(res)
        self.axiom = self._to_lstring(ax)
        self.lstring = self.axiom

    set = setCode

    def _namespace(self):
        ns = {}
        b = dict(vars(builtins))
        b["__import__"] = _importer(builtins.__import__)
        ns["__builtins__"] = b
        ns["__name__"] = "__lpy__"
        for k in _lpy_pgl.__all__:
            ns[k] = getattr(_lpy_pgl, k)
        self._context = _Context(self)
        lsys = self

        def Stop():
            lsys._stop = True

        def useGroup(g):
            lsys._group = int(g)

        def getGroup():
            return lsys._group

        def getIterationNb():
            return lsys._iteration

        def forward():
            lsys._forward = True

        def backward():
            lsys._forward = False

        def isForward():
            return lsys._forward

        def nproduce_fn(*items):
            for x in items:
                lsys._nprod.extend(lsys._to_lstring(x)._m)

        ns.update(
            {
                "Stop": Stop,
                "useGroup": useGroup,
                "getGroup": getGroup,
                "getIterationNb": getIterationNb,
                "forward": forward,
                "backward": backward,
                "isForward": isForward,
                "context": lambda: lsys._context,
                "execContext": lambda: lsys._context,
                "enable_string_discard": lambda *a: None,
                "setSelectionAlwaysRequired": lambda *a: None,
                "setSelectionRequired": lambda *a: None,
                "isSelectionAlwaysRequired": lambda: False,
                "Lstring": Lstring,
                "AxialTree": AxialTree,
                "Module": Module,
                "ParamModule": ParamModule,
                "PackedArgs": PackedArgs,
                "ParameterSet": ParameterSet,
                "ModuleClass": _ModuleClass,
                "Lsystem": Lsystem,
                "__produce__": self._produce,
                "__in_context__": self._in_context,
                "inLeftContext": lambda pattern, params=None: self._in_context(True, pattern, params),
                "inRightContext": lambda pattern, params=None: self._in_context(False, pattern, params),
                "__nproduce__": self._nproduce,
                "__makestring__": lambda items: Lstring._wrap([_item_module(x) for x in items]),
                "pproduce": nproduce_fn,
                "frameDisplay": lambda *a: None,
                "isAnimationEnabled": lambda: False,
                "requestSelection": lambda *a: None,
                "getSelection": lambda: [],
                "enableEarlyReturn": lambda *a: None,
                "setTurtle": lambda *a: None,
                "EnableModuleScale": lambda *a: None,
                "__lpy_code_version__": 1.1,
            }
        )
        self._ns = ns
        return ns

    def _exec(self, code, fname):
        try:
            compiled = compile(code, fname, "exec")
        except SyntaxError as e:
            raise LpyError(f"{fname}:{e.lineno}: Python syntax error: {e.msg}") from None
        exec(compiled, self._ns)

    def _rule(self, kind, group, text, lineno, filt, counters, fname):
        header, definition, arrow = _split_rule(text, lineno)
        parts = _split_header(header, lineno)
        r = _Rule()
        r.kind = kind
        r.group = group
        r.lineno = lineno
        r.header = header.strip()
        r.filter = filt
        pats = {k: (_patterns(v, self._names, lineno) if v.strip() else []) for k, v in parts.items()}
        r.left, r.nleft, r.pred, r.nright, r.right = (pats[k] for k in ("cg", "ncg", "pred", "ncd", "cd"))
        for ps in pats.values():
            for p in ps:
                for j, src in list(p.checks.items()):
                    try:
                        p.checks[j] = eval(compile("lambda __v: " + src, fname, "eval"), self._ns)
                    except SyntaxError:
                        raise LpyError(f"line {lineno}: invalid constraint in a pattern: {src[4:]!r}") from None
        if not r.pred:
            raise LpyError(f"line {lineno}: no predecessor in {header.strip()!r}")
        formals = []
        for k in ("cg", "ncg", "pred", "ncd", "cd"):
            for p in pats[k]:
                formals.extend(p.variables())
        if len(set(formals)) != len(formals):
            raise LpyError(f"line {lineno}: a parameter is named twice in {header.strip()!r}")
        prefix = "pdh"[kind]
        idx = counters.get((kind, group), 0)
        counters[(kind, group)] = idx + 1
        fname_py = f"__{prefix}_{group}_{idx}_" + re.sub(r"[^A-Za-z]", "_", re.sub(r"\s", "", header))
        if arrow:
            body = _transform_python("produce " + definition, self._names, lineno)
        else:
            body = _transform_python(definition, self._names, lineno)
        code_lines = [ln for ln in body.split("\n") if ln.strip() and not ln.strip().startswith("#")]
        if not code_lines:
            body = " pass"
        src = "\n" * (lineno - 1) + f"def {fname_py}({','.join(formals)}):" + body + "\n"
        try:
            code = compile(src, fname, "exec")
        except SyntaxError as e:
            raise LpyError(f"line {e.lineno}: Python syntax error in a rule: {e.msg}") from None
        exec(code, self._ns)
        r.func = self._ns[fname_py]
        return r

    # -- produce

    def _produce(self, items):
        res = [_item_module(x) for x in items]
        if self._nprod:
            res = self._nprod + res
            self._nprod = []
        return _Produced(res)

    def _nproduce(self, items):
        self._nprod.extend(_item_module(x) for x in items)

    def _collect(self, res):
        """A body's result: its successor, None when the rule does not apply."""
        nprod, self._nprod = self._nprod, []
        if res is None:
            return nprod if nprod else None
        if isinstance(res, _Produced):
            return nprod + res.mods if nprod else res.mods
        return nprod + self._to_lstring(res)._m

    def _to_lstring(self, x):
        if isinstance(x, Lstring):
            return x
        if isinstance(x, _Produced):
            return Lstring._wrap(x.mods)
        if isinstance(x, str):
            return Lstring._wrap(_parse_lstring_value(x, self._ns, self._names))
        if isinstance(x, Module):
            return Lstring._wrap([x])
        return Lstring._wrap([_item_module(i) if isinstance(i, tuple) else _as_module(i) for i in x])

    # -- hooks

    def _hook(self, name, lstring, with_lstring=True):
        f = self._ns.get(name)
        if not callable(f):
            return lstring
        try:
            nparams = len(inspect.signature(f).parameters)
        except (TypeError, ValueError):
            nparams = 0
        self._nprod = []
        if nparams == 0 or not with_lstring:
            res = f()
        elif nparams == 1:
            res = f(lstring)
        else:
            res = f(lstring, _NoScene())
        self._nprod = []
        if isinstance(res, (Lstring, _Produced)) or (isinstance(res, list) and res and isinstance(res[0], Module)):
            return self._to_lstring(res)
        return lstring

    # -- derivation

    def _active(self, kind):
        """The rules a step of `kind` tries: the active group's, then group
        0's, file order in each."""
        forward = self._forward
        active = [r for r in self._rules if r.kind == kind and r.group == self._group]
        if self._group != 0:
            if not any(r.group == self._group for r in self._rules):
                active = []
            active += [r for r in self._rules if r.kind == kind and r.group == 0]
        return [r for r in active if (not r.nleft or forward) and (not r.nright or not forward)]

    def _ruleset(self, kind):
        """`_active(kind)` by the name of the predecessor's first module."""
        by_name = {}
        for r in self._active(kind):
            by_name.setdefault(r.pred[0].name, []).append(r)
        return by_name

    def _step(self, mods, kind):
        """One parallel rewriting step; returns (new modules, matched).
        The scan and the matching run in Rust (`genform._genform.lpy_step`),
        calling back into Python for bodies, value checks and constants;
        `GENFORM_LPY_ENGINE=python` runs `_step_py`, the reference."""
        if not _RUST_ENGINE:
            return self._step_py(mods, kind)
        key = (kind, self._group, self._forward)
        entry = self._native_rules.get(key)
        if entry is None:
            # Built once per kind, group and direction: the rules do not
            # change between steps (`setCode` empties the cache).
            active = self._active(kind)
            native = None
            if active:
                native = _native.LpyRules(
                    [(self._rules.index(r), r.left, r.nleft, r.pred, r.nright, r.right, r.filter) for r in active]
                )
            entry = self._native_rules[key] = (active, native)
        active, native = entry
        if native is None:
            return mods, False

        def apply(ri, args, start, end):
            return self._fire(active[ri], mods, start, end, args)

        return _native.lpy_step(native, mods, self._forward, apply)

    def _step_py(self, mods, kind):
        """One parallel rewriting step in Python: the reference engine."""
        rules = self._ruleset(kind)
        if not rules:
            return mods, False
        star = rules.get("*", [])
        forward = self._forward
        n = len(mods)
        matched = False
        # Forward: `out` is the produced string; backward: it is the
        # produced string reversed (turned round at the end).
        out = []
        i = 0 if forward else n - 1
        while 0 <= i < n:
            m = mods[i]
            if forward and m.name == "%":
                i = _end_bracket(mods, i)
                continue
            cands = rules.get(m.name, ())
            if star:
                cands = sorted(list(cands) + star, key=self._rules.index) if cands else star
            done = self._rewrite_at(cands, mods, i, out, forward) if cands else None
            if done is None:
                out.append(m)
                i += 1 if forward else -1
                continue
            res, i = done
            out.extend(res if forward else reversed(res))
            matched = True
        if not forward:
            out.reverse()
        return out, matched

    def _rewrite_at(self, cands, mods, i, out, forward):
        """The successor of the first of `cands` that matches at module `i`
        and produces, and where the scan goes on; None when none does."""
        for r in cands:
            args = []
            # Going backward the predecessor ends at `i`.
            start = i if forward else i - len(r.pred) + 1
            if not self._match(r, mods, start, out, forward, args):
                continue
            end = start + len(r.pred)
            after = end if forward else start - 1
            res = self._fire(r, mods, start, end, args)
            if res is not None:
                return res, after
        return None

    def _in_context(self, left, pattern, params=None):
        """L-Py's ``InLeftContext(pattern, params)``: whether `pattern`
        matches in the context of the module being rewritten; its
        variables go into the dict `params`."""
        cur = getattr(self, "_cur", None)
        if cur is None:
            raise LpyError("InLeftContext/InRightContext outside a production body")
        mods, start, end, filt = cur
        key = (pattern,)
        pats = self._ctx_cache.get(key)
        if pats is None:
            pats = self._ctx_cache[key] = _patterns(pattern, self._names, 0)
        vals = []
        if left:
            where = []
            ok = _left_match(mods, start - 1, pats, filt, vals, where)
            if ok:
                # The next call looks further left (`while InLeftContext(B)` counts them).
                self._cur = (mods, where[0], end, filt)
        else:
            after = _right_match(mods, end, pats, filt, vals)
            ok = after is not None
            if ok:
                self._cur = (mods, start, after, filt)
        if ok and params is not None:
            names = [v for p in pats for v in p.variables()]
            params.update(zip(names, vals))
        return bool(ok)

    def _fire(self, r, mods, start, end, args):
        """Rule r's body on the predecessor `mods[start:end]` (where
        InLeftContext/InRightContext look from) and its arguments."""
        self._cur = (mods, start, end, r.filter)
        return self._apply(r, args)

    def _apply(self, r, args):
        self._nprod = []
        try:
            res = r.func(*args)
        except (PlantGLUnavailable, LpyError):
            raise
        except Exception as e:
            e.add_note(f"in the rule `{r.header}` ({self.filename}:{r.lineno})") if hasattr(e, "add_note") else None
            raise
        return self._collect(res)

    def _match(self, r, mods, start, out, forward, args):
        """Whether rule r matches with its predecessor from `mods[start]`,
        binding parameters in string order (L-Py's): left context, a new
        left context (`<<`, forward), predecessor, a new right context
        (`>>`, backward), right context. `out` is the string produced so
        far: to the left going forward; reversed, to the right, going
        backward."""
        k = len(r.pred)
        if start < 0 or start + k > len(mods):
            return False
        pred_args = []
        for j, p in enumerate(r.pred):
            if not p.match(mods[start + j], pred_args):
                return False
        left_args = []
        if r.left and not _left_match(mods, start - 1, r.left, r.filter, left_args):
            return False
        new_args = []
        if forward:
            if r.nleft and not _left_match(out, len(out) - 1, r.nleft, r.filter, new_args):
                return False
        elif r.nright and _right_match(out[::-1], 0, r.nright, r.filter, new_args) is None:
            return False
        right_args = []
        if r.right and _right_match(mods, start + k, r.right, r.filter, right_args) is None:
            return False
        args.extend(left_args)
        if forward:
            args.extend(new_args)
        args.extend(pred_args)
        if not forward:
            args.extend(new_args)
        args.extend(right_args)
        return True

    def _checked(self, mods):
        # The `.ls` kernel's limit: a runaway file stops with an error
        # instead of exhausting memory.
        if len(mods) > self.max_modules:
            raise LpyError(
                f"{self.filename}: the string has more than {self.max_modules} modules at step "
                f"{self._iteration}; raise Lsystem.max_modules or derive fewer steps"
            )
        return mods

    def _recursive(self, mods, kind, depth):
        matched_any = False
        for _ in range(max(0, depth)):
            mods, matched = self._step(mods, kind)
            self._checked(mods)
            if not matched:
                break
            matched_any = True
        return mods, matched_any

    def derive(self, *args, **kwargs):
        """``derive()``, ``derive(n)``, ``derive(lstring, n)``,
        ``derive(lstring, start, n)``: the string after the steps."""
        lstring, start, n = None, 0, None
        if len(args) == 1:
            if isinstance(args[0], (Lstring, str, list)):
                lstring = args[0]
            else:
                n = args[0]
        elif len(args) == 2:
            lstring, n = args
        elif len(args) == 3:
            lstring, start, n = args
        n = kwargs.get("n", kwargs.get("nbsteps", n))
        start = kwargs.get("start", start)
        if n is None:
            n = self.derivationLength - start
        s = self.axiom if lstring is None else self._to_lstring(lstring)
        result = self._derive(s, int(start), int(n))
        self.lstring = result
        return result

    iterate = derive

    def _derive(self, s, start, steps):
        mods = [m.copy() for m in s]
        self._stop = False
        if start == 0 and self._seed is not None:
            # Same seed, same string: Python's `random` (which the file's
            # `random()`, `uniform`, … draw from) restarts with each derivation.
            _random.seed(self._seed)
        if start == 0:
            self._iteration = 0
            self._forward = True
            mods = self._hook("Start", Lstring._wrap(mods))._m
        has_rules = bool(self._rules)
        if not has_rules or not mods:
            # L-Py returns at once (and calls End if this was the last step).
            if start + steps == self.derivationLength:
                self._iteration = self.derivationLength
                mods = self._hook("End", Lstring._wrap(mods))._m
            return Lstring._wrap(mods)
        matching = True
        i = 0
        while matching and i < steps:
            self._iteration = start + i
            mods = self._hook("StartEach", Lstring._wrap(mods))._m
            matching = False
            if any(r.kind == 0 for r in self._rules):
                if self._queries:
                    _fill_queries(mods, self.angle, self.step)
                mods, matching = self._step(mods, 0)
                self._checked(mods)
            if any(r.kind == 1 for r in self._rules):
                mods, dec = self._recursive(mods, 1, self.decompositionMaxDepth)
                matching = matching or dec
            mods = self._hook("EndEach", Lstring._wrap(mods))._m
            i += 1
            if self._stop:
                break
        if start + i == self.derivationLength and not self._stop:
            mods = self._hook("End", Lstring._wrap(mods))._m
        return Lstring._wrap(mods)

    def interpret(self, lstring=None):
        """The string the turtle draws: interpretation rules applied."""
        s = self.lstring if lstring is None else self._to_lstring(lstring)
        mods = list(s)
        if any(r.kind == 2 for r in self._rules):
            mods, _ = self._recursive(mods, 2, self.homomorphismMaxDepth)
        return Lstring._wrap(mods)

    homomorphism = interpret

    def context(self):
        return self._context

    def __getattr__(self, name):
        ns = self.__dict__.get("_ns")
        if ns is not None and name in ns:
            return ns[name]
        raise AttributeError(name)

    # -- drawing

    def ls_text(self, lstring=None):
        """The drawing as genform `.ls` text: PlantGL's frame and defaults,
        the interpreted string's turtle modules with numeric parameters."""
        s = self.interpret(lstring)
        body = _turtle_text(s)
        colors = ""
        if self.materials:
            top = max(self.materials)
            table = [self.materials.get(k, (128, 128, 128)) for k in range(top + 1)]
            colors = "colors: " + " ".join("#%02x%02x%02x" % c for c in table) + "\n"
        name = os.path.splitext(os.path.basename(self.filename))[0] or "lpy"
        return (
            f"name: {re.sub(r'[^A-Za-z0-9_.-]', '_', name)}\nderivation: 0\n"
            f"angle: {self.angle!r}\nstep: {self.step!r}\nheading: +y\nview: 3d\nwidth: 0.1\nwidth_unit: 2\n"
            f"{colors}axiom: {body or 'f(0)'}\n"
        )

    def model(self, lstring=None):
        """The derived string drawn by genform's turtle: a ``genform.Model``
        (``.save("x.glb")``, ``.png()``, ``.mesh()``)."""
        from . import load

        text = self.ls_text(lstring)
        fd, path = tempfile.mkstemp(suffix=".ls", prefix="lpy-")
        try:
            with os.fdopen(fd, "w", encoding="utf-8") as f:
                f.write(text)
            return load(path).sample(seed=0)
        finally:
            os.unlink(path)

    def plot(self, path, lstring=None):
        """Draws the string into `path` (any genform format)."""
        return self.model(lstring).save(path)


class _NoScene:
    """The PlantGL scene L-Py hands to ``EndEach(lstring, scene)``: genform
    draws no PlantGL scene, so any use of it stops the run."""

    def _refuse(self, *a, **k):
        raise PlantGLUnavailable("the PlantGL scene handed to EndEach/End is not available in genform")

    __len__ = __iter__ = __getitem__ = _refuse

    def __getattr__(self, name):
        self._refuse()

    def __bool__(self):
        return True


class _Produced:
    __slots__ = ("mods",)

    def __init__(self, mods):
        self.mods = mods


class _ModuleClass:
    def __init__(self, name):
        self.name = name

    @staticmethod
    def get(name):
        return _ModuleClass(name)

    def __eq__(self, other):
        return getattr(other, "name", other) == self.name

    def __hash__(self):
        return hash(self.name)


def _left_match(mods, j, pats, filt, out, where=None):
    """Left context: pattern modules from the last backwards, skipping
    finished branches (`[…]` behind) and branch starts (to the parent)."""
    per = []
    for p in reversed(pats):
        while j >= 0:
            name = mods[j].name
            if name == "]" and p.name != "]":
                j = _begin_bracket(mods, j) - 1
                continue
            if name == "[" and p.name != "[":
                j -= 1
                continue
            if filt is not None and filt.skips(name):
                j -= 1
                continue
            break
        if j < 0:
            return False
        b = []
        if not p.match(mods[j], b):
            return False
        per.append(b)
        j -= 1
    for b in reversed(per):
        out.extend(b)
    if where is not None:
        where.append(j + 1)
    return True


def _right_match(mods, j, pats, filt, out):
    """Right context: lateral branches are skipped unless the pattern
    enters them with `[`; `]` in the pattern skips to the branch's end."""
    n = len(mods)
    for p in pats:
        if p.name == "]":
            j = _end_bracket_from(mods, j)
            if j >= n:
                return None
            j += 1
            continue
        while j < n:
            name = mods[j].name
            if name == "[" and p.name != "[":
                j = _end_bracket(mods, j) + 1
                continue
            if name == "]":
                return None
            if filt is not None and filt.skips(name):
                j += 1
                continue
            break
        if j >= n:
            return None
        if not p.match(mods[j], out):
            return None
        j += 1
    return j


def _end_bracket_from(mods, j):
    """Index of the `]` closing the branch that position j is in."""
    depth = 0
    while j < len(mods):
        n = mods[j].name
        if n == "[":
            depth += 1
        elif n == "]":
            if depth == 0:
                return j
            depth -= 1
        j += 1
    return len(mods)


# ------------------------------------------------------------ turtle queries


def _rotate(a, b, deg):
    """(a, b) turned by `deg` degrees in their plane, a towards b."""
    r = math.radians(deg)
    c, s = math.cos(r), math.sin(r)
    return (
        [a[k] * c + b[k] * s for k in range(3)],
        [b[k] * c - a[k] * s for k in range(3)],
    )


def _fill_queries(mods, angle, step):
    """PlantGL's turtle, in L-Py's axes, run over the string to fill the
    parameters of ?P ?H ?U ?L ?R ?F (position and frame where they stand)."""
    V = _lpy_pgl.Vector3
    pos, h, l, u = [0.0, 0.0, 0.0], [0.0, 0.0, 1.0], [0.0, -1.0, 0.0], [1.0, 0.0, 0.0]
    stack = []
    for m in mods:
        name, args = m.name, m.args
        a = args[0] if args and _num(args[0]) else None
        if name in ("F", "f"):
            d = step if a is None else a
            pos = [pos[k] + h[k] * d for k in range(3)]
        elif name == "nF" and a is not None:
            pos = [pos[k] + h[k] * a for k in range(3)]
        elif name in ("+", "-"):
            h, l = _rotate(h, l, (angle if a is None else a) * (1 if name == "+" else -1))
        elif name in ("^", "&"):
            h, u = _rotate(h, u, (angle if a is None else a) * (1 if name == "^" else -1))
        elif name in ("/", "\\"):
            l, u = _rotate(l, u, (angle if a is None else a) * (1 if name == "/" else -1))
        elif name == "|":
            h, l = [-x for x in h], [-x for x in l]
        elif name == "[":
            stack.append((pos, h, l, u))
        elif name == "]" and stack:
            pos, h, l, u = stack.pop()
        elif name == "@M" and len(args) >= 3 and all(_num(x) for x in args[:3]):
            pos = [float(x) for x in args[:3]]
        elif name in _QUERIES:
            vec = {"?P": pos, "?H": h, "?U": u, "?L": l, "?R": [-x for x in l]}.get(name)
            if name == "?F":
                m.args = [V(*pos), V(*h), V(*u), V(*l)][: max(len(args), 4) if args else 4]
            elif len(args) == 3:
                m.args = list(vec)
            else:
                m.args = [V(*vec)]


# --------------------------------------------------------------- the drawing

# L-Py names with the genform turtle command they draw as.
_DRAW = {
    "F": "F", "f": "f", "+": "+", "-": "-", "^": "^", "&": "&", "/": "/", "\\": "\\", "|": "|",
    "[": "[", "]": "]", "!": "!", "_": "_", ";": ";", ",": ",", "SetWidth": "!", "SetColor": ",",
    "@O": "@O", "@Gc": "@Gc", "@Ge": "@Ge", "{": "{", "}": "}", ".": ".", "@D": "@D", "@Di": "@Di",
    "@Dd": "@Dd", "@R": "@R", "@v": "$", "@h": "$",
}


def _num(v):
    return isinstance(v, (int, float)) and not isinstance(v, bool) and math.isfinite(v)


def _turtle_text(s):
    """The `.ls` axiom of an interpreted string: modules genform draws,
    with their numeric parameters (others are left out)."""
    out = []
    mods = list(s)
    i = 0
    while i < len(mods):
        m = mods[i]
        i += 1
        name = m.name
        if name == "%":
            # PlantGL's turtle skips the rest of the branch after a cut.
            i = _end_bracket(mods, i - 1)
            continue
        if name == "nF" and len(m.args) >= 2 and _num(m.args[0]) and _num(m.args[1]) and m.args[1] > 0:
            count = min(10000, int(round(m.args[0] / m.args[1])))
            out.append(f"F({m.args[1]!r})" * count)
            continue
        g = _DRAW.get(name)
        if g is None:
            if name == "~" and m.args and m.args[0] == "l":
                sc = m.args[1] if len(m.args) > 1 and _num(m.args[1]) else 1
                out.append(f"~l({float(sc)!r})")
            continue
        args = m.args
        if name == "SetColor" and len(args) != 1:
            args = []
        if name == "@R":
            if len(args) >= 6 and all(_num(a) for a in args[:6]):
                h, u = args[:3], args[3:6]
                args = [h[1], h[2], h[0], u[1], u[2], u[0]]
            elif len(args) >= 2 and all(isinstance(a, (list, tuple, _lpy_pgl._Vec)) and len(a) >= 3 for a in args[:2]):
                h, u = args[0], args[1]
                args = [h[1], h[2], h[0], u[1], u[2], u[0]]
            else:
                continue
        nums = []
        for a in args:
            if not _num(a):
                break
            nums.append(float(a))
        if name in ("F", "f") and len(nums) > 1:
            nums = nums[:1]
        out.append(g + ("(" + ",".join(repr(v) for v in nums) + ")" if nums else ""))
    return "".join(out)


def run(path, steps=None, seed=None):
    """Reads and derives a file: (Lsystem, final lstring, seconds)."""
    t = time.perf_counter()
    lsys = Lsystem(path, seed=seed)
    s = lsys.derive() if steps is None else lsys.derive(steps)
    return lsys, s, time.perf_counter() - t
