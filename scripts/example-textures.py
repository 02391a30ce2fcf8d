#!/usr/bin/env python3
"""Writes the example textures of examples/shape/textured_house.sg:
examples/shape/assets/brick.png (running-bond brick, 128 x 128 pixels,
four courses of 0.3 m bricks per 0.6 m: the grammar lays one copy over
1.2 x 1.2 m) and examples/shape/assets/roof_tiles.png (rows of clay tiles
shaded towards their lower edge, 64 x 64 pixels over 0.8 x 0.8 m).

Standard library only (zlib for the PNG); the same bytes every run.
"""

import struct
import zlib
from pathlib import Path


def png(width, height, pixel):
    """An 8-bit RGB PNG of pixel(x, y) -> (r, g, b)."""
    rows = b"".join(b"\0" + bytes(c for x in range(width) for c in pixel(x, y)) for y in range(height))

    def chunk(kind, data):
        return struct.pack(">I", len(data)) + kind + data + struct.pack(">I", zlib.crc32(kind + data))

    header = struct.pack(">IIBBBBB", width, height, 8, 2, 0, 0, 0)
    return b"\x89PNG\r\n\x1a\n" + chunk(b"IHDR", header) + chunk(b"IDAT", zlib.compress(rows, 9)) + chunk(b"IEND", b"")


def shade(k):
    """A small deterministic variation per brick or tile, -1 to 1."""
    h = (k * 2654435761) & 0xFFFFFFFF
    h ^= h >> 15
    return ((h * 2246822519) & 0xFFFF) / 32767.5 - 1.0


def brick(x, y):
    course, row_y = divmod(y, 16)
    offset = 16 if course % 2 else 0
    column, row_x = divmod(x + offset, 32)
    if row_y < 2 or row_x < 2:
        return (206, 200, 188)  # mortar
    s = shade(course * 31 + column % 4)
    return (int(160 + 25 * s), int(62 + 12 * s), int(44 + 8 * s))


def tile(x, y):
    row, row_y = divmod(y, 16)
    offset = 8 if row % 2 else 0
    column, row_x = divmod(x + offset, 16)
    if row_x == 0:
        return (60, 32, 26)  # the joint between tiles
    s = shade(row * 7 + column % 4)
    dark = row_y / 15  # darker towards the lower edge of each row
    return (int((150 + 15 * s) * (1 - 0.45 * dark)), int((70 + 8 * s) * (1 - 0.45 * dark)), int((52 + 6 * s) * (1 - 0.45 * dark)))


assets = Path(__file__).resolve().parent.parent / "examples" / "shape" / "assets"
(assets / "brick.png").write_bytes(png(128, 128, brick))
(assets / "roof_tiles.png").write_bytes(png(64, 64, tile))
