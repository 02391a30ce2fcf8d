"""A stand-in for the parts of PlantGL that L-Py files use for data.

L-Py files import ``openalea.plantgl.all`` for curves (the editor's
``NurbsCurve2D``, ``BezierCurve2D``, ``Polyline2D`` and
``QuantisedFunction``), vectors, colours and materials. genform runs such
files without PlantGL: this module gives those classes with the behaviour
production bodies read (a curve evaluated at u, a function evaluated at x,
vector arithmetic, a material's colour). Every other PlantGL class
(geometry, scenes, viewers, textures) raises :class:`PlantGLUnavailable`
when it is constructed, so a file that builds PlantGL objects stops with a
clear reason instead of drawing something else.
"""

from __future__ import annotations

import math


class PlantGLUnavailable(RuntimeError):
    """A PlantGL object genform does not provide was constructed."""


# ----------------------------------------------------------------- vectors


class _Vec:
    __slots__ = ("c",)
    N = 3

    def __init__(self, *args):
        if len(args) == 1 and not isinstance(args[0], (int, float)):
            args = tuple(args[0])
        c = [float(a) for a in args][: self.N]
        c += [0.0] * (self.N - len(c))
        self.c = c

    def _new(self, c):
        v = object.__new__(type(self))
        v.c = list(c)
        return v

    def __getitem__(self, i):
        return self.c[i]

    def __setitem__(self, i, v):
        self.c[i] = float(v)

    def __len__(self):
        return self.N

    def __iter__(self):
        return iter(self.c)

    def __add__(self, o):
        return self._new(a + b for a, b in zip(self.c, o))

    __radd__ = __add__

    def __sub__(self, o):
        return self._new(a - b for a, b in zip(self.c, o))

    def __rsub__(self, o):
        return self._new(b - a for a, b in zip(self.c, o))

    def __neg__(self):
        return self._new(-a for a in self.c)

    def __mul__(self, k):
        if isinstance(k, _Vec):
            return sum(a * b for a, b in zip(self.c, k.c))
        return self._new(a * k for a in self.c)

    __rmul__ = __mul__

    def __truediv__(self, k):
        return self._new(a / k for a in self.c)

    def __eq__(self, o):
        try:
            return len(o) == self.N and all(a == b for a, b in zip(self.c, o))
        except TypeError:
            return False

    def __hash__(self):
        return hash(tuple(self.c))

    def __abs__(self):
        return math.sqrt(sum(a * a for a in self.c))

    def __pow__(self, o):
        return cross(self, o)

    __xor__ = __pow__

    def __deepcopy__(self, memo):
        return self._new(self.c)

    def __repr__(self):
        return f"{type(self).__name__}({','.join(repr(a) for a in self.c)})"

    def normalize(self):
        n = abs(self)
        if n > 0:
            self.c = [a / n for a in self.c]
        return n

    def normed(self):
        n = abs(self)
        return self._new(a / n for a in self.c) if n > 0 else self._new(self.c)

    def __norm__(self):
        return abs(self)

    x = property(lambda s: s.c[0], lambda s, v: s.__setitem__(0, v))
    y = property(lambda s: s.c[1], lambda s, v: s.__setitem__(1, v))


class Vector2(_Vec):
    N = 2


class Vector3(_Vec):
    N = 3
    z = property(lambda s: s.c[2], lambda s, v: s.__setitem__(2, v))

    class Spherical:
        def __init__(self, radius, theta, phi):
            self.radius, self.theta, self.phi = radius, theta, phi

    class Cylindrical:
        def __init__(self, radius, theta, z):
            self.radius, self.theta, self.z = radius, theta, z

    def __init__(self, *args):
        if len(args) == 1 and isinstance(args[0], Vector3.Spherical):
            s = args[0]
            r, t, p = s.radius, s.theta, s.phi
            args = (r * math.cos(t) * math.sin(p), r * math.sin(t) * math.sin(p), r * math.cos(p))
        elif len(args) == 1 and isinstance(args[0], Vector3.Cylindrical):
            s = args[0]
            args = (s.radius * math.cos(s.theta), s.radius * math.sin(s.theta), s.z)
        elif len(args) == 2 and isinstance(args[0], Vector2):
            args = (args[0][0], args[0][1], args[1])
        super().__init__(*args)


Vector2.ORIGIN, Vector2.OX, Vector2.OY = Vector2(0, 0), Vector2(1, 0), Vector2(0, 1)
Vector3.ORIGIN, Vector3.OX, Vector3.OY, Vector3.OZ = Vector3(0, 0, 0), Vector3(1, 0, 0), Vector3(0, 1, 0), Vector3(0, 0, 1)


class Vector4(_Vec):
    N = 4
    z = property(lambda s: s.c[2], lambda s, v: s.__setitem__(2, v))
    w = property(lambda s: s.c[3], lambda s, v: s.__setitem__(3, v))

    def project(self):
        w = self.c[3] or 1.0
        return Vector3(self.c[0] / w, self.c[1] / w, self.c[2] / w)


def norm(v):
    return math.sqrt(sum(a * a for a in v))


def normSquared(v):
    return sum(a * a for a in v)


def dot(a, b):
    return sum(x * y for x, y in zip(a, b))


def cross(a, b):
    return Vector3(a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0])


def direction(v):
    n = norm(v)
    return type(v)(*[a / n for a in v]) if n > 0 and isinstance(v, _Vec) else Vector3(*[a / (n or 1) for a in v])


def angle(a, b, *axis):
    c = dot(a, b) / ((norm(a) * norm(b)) or 1.0)
    return math.acos(max(-1.0, min(1.0, c)))


# ------------------------------------------------------- arrays and colours


class _Array(list):
    def __init__(self, items=()):
        super().__init__(items)

    def getLength(self):
        return len(self)


class Point2Array(_Array):
    pass


class Point3Array(_Array):
    pass


class Point4Array(_Array):
    pass


class RealArray(_Array):
    pass


class Index(_Array):
    pass


class IndexArray(_Array):
    pass


class Color3:
    def __init__(self, r=0, g=0, b=0):
        if not isinstance(r, (int, float)):
            r, g, b = tuple(r)[:3]
        self.red, self.green, self.blue = int(r), int(g), int(b)

    def __iter__(self):
        return iter((self.red, self.green, self.blue))

    def __repr__(self):
        return f"Color3({self.red},{self.green},{self.blue})"


Color3.BLACK = Color3(0, 0, 0)
Color3.WHITE = Color3(255, 255, 255)
Color3.RED = Color3(255, 0, 0)
Color3.GREEN = Color3(0, 255, 0)
Color3.BLUE = Color3(0, 0, 255)


class Color4(Color3):
    def __init__(self, r=0, g=0, b=0, a=0):
        if not isinstance(r, (int, float)):
            r, g, b, a = (tuple(r) + (0,))[:4]
        super().__init__(r, g, b)
        self.alpha = int(a)


class Material:
    """A material: genform keeps its ambient colour times its diffuse factor."""

    DEFAULT_MATERIAL = None

    def __init__(self, *args, **kw):
        name = args[0] if args and isinstance(args[0], str) else kw.get("name", "")
        rest = [a for a in args if not isinstance(a, str)]
        ambient = kw.get("ambient", rest[0] if rest else Color3(80, 80, 80))
        diffuse = kw.get("diffuse", rest[1] if len(rest) > 1 else 2.0)
        if isinstance(ambient, tuple):
            ambient = Color3(*ambient)
        self.name = name
        self.ambient = ambient if isinstance(ambient, Color3) else Color3(80, 80, 80)
        self.diffuse = float(diffuse) if isinstance(diffuse, (int, float)) else 2.0
        self.transparency = float(kw.get("transparency", 0))

    def rgb(self):
        """The displayed colour (ambient × diffuse, clamped)."""
        d = self.diffuse
        return tuple(max(0, min(255, int(round(c * d)))) for c in self.ambient)


# ----------------------------------------------------------------- curves


class _Curve2D:
    """A curve of the editor: evaluated at u in [firstKnot, lastKnot]."""

    name = ""
    firstKnot = 0.0
    lastKnot = 1.0
    stride = 60

    def getPointAt(self, u):
        raise NotImplementedError

    def getTangentAt(self, u):
        h = 1e-4 * (self.lastKnot - self.firstKnot)
        a = self.getPointAt(max(self.firstKnot, u - h))
        b = self.getPointAt(min(self.lastKnot, u + h))
        return Vector2(b[0] - a[0], b[1] - a[1])

    def getNormalAt(self, u):
        t = self.getTangentAt(u)
        return Vector2(-t[1], t[0])

    def getLength(self, begin=None, end=None):
        a = self.firstKnot if begin is None else begin
        b = self.lastKnot if end is None else end
        n = 200
        pts = [self.getPointAt(a + (b - a) * k / n) for k in range(n + 1)]
        return sum(norm(pts[k + 1] - pts[k]) for k in range(n))

    def getArcLengthToUMapping(self):
        """The function from the arc length's fraction in [0, 1] to u."""
        a, b = self.firstKnot, self.lastKnot
        n = 200
        us = [a + (b - a) * k / n for k in range(n + 1)]
        pts = [self.getPointAt(u) for u in us]
        acc = [0.0]
        for k in range(n):
            acc.append(acc[-1] + norm(pts[k + 1] - pts[k]))
        total = acc[-1] or 1.0
        return QuantisedFunction([(s / total, u) for s, u in zip(acc, us)])

    def getUToArcLengthMapping(self):
        m = self.getArcLengthToUMapping()
        return QuantisedFunction([(y, x) for x, y in zip(m._x, m._y)])

    def __call__(self, u):
        return self.getPointAt(u)

    def deepcopy(self):
        import copy

        return copy.deepcopy(self)


class Polyline2D(_Curve2D):
    def __init__(self, pointList=(), *a, **kw):
        pts = kw.get("pointList", pointList)
        self.pointList = Point2Array([Vector2(p[0], p[1]) for p in pts])
        self.lastKnot = float(max(1, len(self.pointList) - 1))

    ctrlPointList = property(lambda s: s.pointList)

    @staticmethod
    def Circle(radius=1.0, slices=8):
        return Polyline2D(
            [(radius * math.cos(2 * math.pi * k / slices), radius * math.sin(2 * math.pi * k / slices)) for k in range(slices + 1)]
        )

    def getPointAt(self, u):
        pts = self.pointList
        if not pts:
            return Vector2(0, 0)
        u = max(0.0, min(self.lastKnot, float(u)))
        k = min(int(u), len(pts) - 2) if len(pts) > 1 else 0
        if len(pts) == 1:
            return Vector2(pts[0])
        t = u - k
        return pts[k] * (1 - t) + pts[k + 1] * t


class BezierCurve2D(_Curve2D):
    def __init__(self, ctrlPointList=(), stride=60, *a, **kw):
        pts = kw.get("ctrlPointList", ctrlPointList)
        self.ctrlPointList = Point3Array([Vector3(p[0], p[1], p[2] if len(p) > 2 else 1.0) for p in pts])
        self.stride = stride

    def getPointAt(self, u):
        pts = [Vector3(p) for p in self.ctrlPointList]
        u = max(0.0, min(1.0, float(u)))
        n = len(pts)
        while n > 1:
            pts = [pts[k] * (1 - u) + pts[k + 1] * u for k in range(n - 1)]
            n -= 1
        p = pts[0] if pts else Vector3(0, 0, 1)
        w = p[2] or 1.0
        return Vector2(p[0] / w, p[1] / w)


class NurbsCurve2D(_Curve2D):
    """A NURBS curve; control points (x, y, w) with w the weight; PlantGL's
    default degree 3 (less with fewer points) and clamped uniform knots."""

    def __init__(self, ctrlPointList=(), knotList=None, degree=3, stride=60, *a, **kw):
        pts = kw.get("ctrlPointList", ctrlPointList)
        self.ctrlPointList = Point3Array([Vector3(p[0], p[1], p[2] if len(p) > 2 else 1.0) for p in pts])
        n = len(self.ctrlPointList)
        self.degree = max(1, min(int(kw.get("degree", degree)), n - 1)) if n > 1 else 1
        knots = kw.get("knotList", knotList)
        if knots is None:
            p = self.degree
            inner = n - p - 1
            knots = [0.0] * (p + 1) + [k / (inner + 1) for k in range(1, inner + 1)] + [1.0] * (p + 1)
        self.knotList = RealArray(float(k) for k in knots)
        self.firstKnot = self.knotList[self.degree] if self.knotList else 0.0
        self.lastKnot = self.knotList[-self.degree - 1] if self.knotList else 1.0
        self.stride = stride

    def getPointAt(self, u):
        pts, p, U = self.ctrlPointList, self.degree, self.knotList
        n = len(pts)
        if n == 0:
            return Vector2(0, 0)
        if n == 1:
            return Vector2(pts[0][0], pts[0][1])
        u = max(self.firstKnot, min(self.lastKnot, float(u)))
        k = p
        while k < n - 1 and U[k + 1] <= u:
            k += 1
        # de Boor on homogeneous points (x·w, y·w, w).
        d = [Vector3(pts[j][0] * pts[j][2], pts[j][1] * pts[j][2], pts[j][2]) for j in range(k - p, k + 1)]
        for r in range(1, p + 1):
            for j in range(p, r - 1, -1):
                i = j + k - p
                den = U[i + p - r + 1] - U[i]
                a = (u - U[i]) / den if den else 0.0
                d[j] = d[j - 1] * (1 - a) + d[j] * a
        w = d[p][2] or 1.0
        return Vector2(d[p][0] / w, d[p][1] / w)


class QuantisedFunction:
    """A curve read as a function x ↦ y (the editor's functions)."""

    def __init__(self, curve, sampling=100, clamped=True):
        self.curve = curve
        self.clamped = clamped
        if isinstance(curve, (list, tuple)):
            pts = [Vector2(p[0], p[1]) for p in curve]
        else:
            n = max(2, int(sampling) * 4)
            a, b = curve.firstKnot, curve.lastKnot
            pts = [curve.getPointAt(a + (b - a) * k / n) for k in range(n + 1)]
        pts.sort(key=lambda p: p[0])
        self._x = [p[0] for p in pts]
        self._y = [p[1] for p in pts]
        self.firstx, self.lastx = self._x[0], self._x[-1]

    def __call__(self, x):
        xs, ys = self._x, self._y
        x = float(x)
        if x <= xs[0]:
            return ys[0]
        if x >= xs[-1]:
            return ys[-1]
        lo, hi = 0, len(xs) - 1
        while hi - lo > 1:
            mid = (lo + hi) // 2
            if xs[mid] <= x:
                lo = mid
            else:
                hi = mid
        span = xs[hi] - xs[lo]
        t = (x - xs[lo]) / span if span else 0.0
        return ys[lo] * (1 - t) + ys[hi] * t

    def getValue(self, x):
        return self(x)

    def findX(self, y, startingX=None):
        for k in range(len(self._y) - 1):
            a, b = self._y[k], self._y[k + 1]
            if (a - y) * (b - y) <= 0 and a != b:
                return self._x[k] + (y - a) / (b - a) * (self._x[k + 1] - self._x[k])
        return None


class Matrix3:
    """A 3×3 matrix (rows), for rotations of vectors."""

    def __init__(self, *rows):
        if len(rows) == 9:
            rows = (rows[0:3], rows[3:6], rows[6:9])
        self.m = [list(map(float, r)) for r in rows] if rows else [[1.0, 0, 0], [0, 1.0, 0], [0, 0, 1.0]]

    @staticmethod
    def axisRotation(axis, angle):
        x, y, z = direction(Vector3(*axis))
        c, s = math.cos(angle), math.sin(angle)
        t = 1 - c
        return Matrix3(
            (t * x * x + c, t * x * y - s * z, t * x * z + s * y),
            (t * x * y + s * z, t * y * y + c, t * y * z - s * x),
            (t * x * z - s * y, t * y * z + s * x, t * z * z + c),
        )

    @staticmethod
    def IDENTITY():
        return Matrix3()

    def __mul__(self, o):
        if isinstance(o, Matrix3):
            return Matrix3(*[[sum(self.m[i][k] * o.m[k][j] for k in range(3)) for j in range(3)] for i in range(3)])
        if isinstance(o, (int, float)):
            return Matrix3(*[[v * o for v in r] for r in self.m])
        return Vector3(*[sum(self.m[i][k] * o[k] for k in range(3)) for i in range(3)])

    def transpose(self):
        return Matrix3(*[[self.m[j][i] for j in range(3)] for i in range(3)])

    def getColumn(self, j):
        return Vector3(self.m[0][j], self.m[1][j], self.m[2][j])

    def getRow(self, i):
        return Vector3(*self.m[i])


Matrix3.IDENTITY = Matrix3()


def _unavailable(name):
    def make(*args, **kwargs):
        raise PlantGLUnavailable(f"PlantGL's {name} is not available in genform (it builds PlantGL geometry or a viewer)")

    make.__name__ = name
    return make


_UNAVAILABLE = """Cylinder Sphere Box Cone Frustum Disc Paraboloid Torus Text Font Shape Scene Viewer
Translated Scaled Oriented AxisRotated EulerRotated Transformed Group ExtrudedHull Extrusion Swung
TriangleSet QuadSet FaceSet PointSet PolylineSet Polyline NurbsCurve BezierCurve NurbsPatch BezierPatch
Point4Matrix Point3Matrix ImageTexture Texture2D Texture2DTransformation Tapered Revolution AmapSymbol
Sweep Curve2DArray Tesselator Discretizer BoundingBox Fit Camera Light ScreenProjector
ZBufferEngine Point3Grid Point2Grid Point4Grid PglTurtle Turtle Hull Line Polygon Triangle PGLViewer""".split()

for _n in _UNAVAILABLE:
    globals()[_n] = _unavailable(_n)

eStatic = eAnimatedScene = eAnimatedPrimitives = 0
pi = math.pi

__all__ = [n for n in globals() if not n.startswith("_") and n not in ("annotations", "math")]
