#!/usr/bin/env python3
"""Extracts the block ids of one Minecraft Java version from the npm package
`minecraft-data` into crates/genform-boxsplit/data/blocks-<version>.txt
(one id per line, without namespace, sorted).

Usage: scripts/minecraft-blocks.py PACKAGE_DIR VERSION...
  PACKAGE_DIR  the unpacked package (`npm pack minecraft-data && tar xzf minecraft-data-*.tgz`
               gives ./package)
  VERSION      a pc version, e.g. 1.21.1 1.19.4
"""
import json
import pathlib
import sys


def main() -> int:
    if len(sys.argv) < 3:
        print(__doc__, file=sys.stderr)
        return 2
    data = pathlib.Path(sys.argv[1]) / "minecraft-data" / "data"
    paths = json.loads((data / "dataPaths.json").read_text())["pc"]
    out_dir = pathlib.Path(__file__).resolve().parent.parent / "crates" / "genform-boxsplit" / "data"
    for version in sys.argv[2:]:
        if version not in paths or "blocks" not in paths[version]:
            print(f"minecraft-data has no block list for pc {version}", file=sys.stderr)
            return 1
        blocks = json.loads((data / paths[version]["blocks"] / "blocks.json").read_text())
        names = sorted({b["name"] for b in blocks})
        out = out_dir / f"blocks-{version}.txt"
        out.write_text("".join(n + "\n" for n in names))
        print(f"{out}: {len(names)} ids (from {paths[version]['blocks']})")
    return 0


if __name__ == "__main__":
    sys.exit(main())
