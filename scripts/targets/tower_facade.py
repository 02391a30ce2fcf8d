#!/usr/bin/env python3
"""Draws examples/scenes/targets/tower_facade.png: the front silhouette of a
three-step tower with a pyramid roof (base 20 wide, 9 high, 14 deep; a
middle block 14 × 12 × 10; a top block 8 × 8 × 6; a roof 3 high), seen
through the camera of examples/scenes/building_facade.toml (genform's orbit
camera: eye = look_at + radius·(cos θ cos φ, sin θ, cos θ sin φ), vertical
field of view 60°, 800 × 600). Dark = the target. Pure Python (zlib)."""
import math, struct, zlib, sys

W, H, FOV = 800, 600, 60.0
PHI, THETA, RADIUS, LOOK = math.pi / 2, 0.0, 40.0, (0.0, 16.0, 0.0)

def sub(a, b): return tuple(x - y for x, y in zip(a, b))
def dot(a, b): return sum(x * y for x, y in zip(a, b))
def cross(a, b): return (a[1]*b[2]-a[2]*b[1], a[2]*b[0]-a[0]*b[2], a[0]*b[1]-a[1]*b[0])
def norm(a):
    l = math.sqrt(dot(a, a)); return tuple(x / l for x in a)

eye = (LOOK[0] + RADIUS*math.cos(THETA)*math.cos(PHI), LOOK[1] + RADIUS*math.sin(THETA), LOOK[2] + RADIUS*math.cos(THETA)*math.sin(PHI))
f = norm(sub(LOOK, eye)); r = norm(cross(f, (0, 1, 0))); u = cross(r, f)
t = math.tan(math.radians(FOV) / 2)

def project(p):
    d = sub(p, eye); z = dot(d, f)
    return ((dot(d, r) / z / (t * W / H) + 1) / 2 * W, (1 - dot(d, u) / z / t) / 2 * H)

def hull(pts):
    pts = sorted(set(pts))
    def half(ps):
        out = []
        for p in ps:
            while len(out) >= 2 and (out[-1][0]-out[-2][0])*(p[1]-out[-2][1]) - (out[-1][1]-out[-2][1])*(p[0]-out[-2][0]) <= 0:
                out.pop()
            out.append(p)
        return out
    lo, hi = half(pts), half(pts[::-1])
    return lo[:-1] + hi[:-1]

def box(w, y0, y1, d):
    return [(sx*w/2, y, sz*d/2) for sx in (-1, 1) for y in (y0, y1) for sz in (-1, 1)]

solids = [box(20, 0, 9, 14), box(14, 9, 21, 10), box(8, 21, 29, 6),
          [(sx*4, 29, sz*3) for sx in (-1, 1) for sz in (-1, 1)] + [(0, 32, 0)]]
polys = [hull([project(p) for p in s]) for s in solids]

def inside(x, y, poly):
    n = len(poly); sign = 0
    for i in range(n):
        (ax, ay), (bx, by) = poly[i], poly[(i+1) % n]
        c = (bx-ax)*(y-ay) - (by-ay)*(x-ax)
        if c != 0:
            if sign == 0: sign = 1 if c > 0 else -1
            elif (c > 0) != (sign > 0): return False
    return True

rows = []
for py in range(H):
    row = bytearray([0])
    for px in range(W):
        dark = any(inside(px + 0.5, py + 0.5, p) for p in polys)
        row += bytes([0 if dark else 255])
    rows.append(bytes(row))
def chunk(k, data): return struct.pack('>I', len(data)) + k + data + struct.pack('>I', zlib.crc32(k + data) & 0xffffffff)
png = b'\x89PNG\r\n\x1a\n' + chunk(b'IHDR', struct.pack('>IIBBBBB', W, H, 8, 0, 0, 0, 0)) \
    + chunk(b'IDAT', zlib.compress(b''.join(rows), 9)) + chunk(b'IEND', b'')
open(sys.argv[1] if len(sys.argv) > 1 else 'tower_facade.png', 'wb').write(png)
