"""One Python L-system package doing one job, for scripts/bench-peers.sh.

usage: peer.py PACKAGE SYSTEM STEPS OUT

PACKAGE is LindenmayerSystem, l_system_fractals or lsys; SYSTEM is
abop_1_24e or koch_snowflake (the same axioms, productions and angles as
examples/lsystem/*.ls). OUT ending in .txt gets the derived string, OUT
ending in .png a drawing (lsys only: the one package here that computes
turtle coordinates without a window), through matplotlib as its docs show.
Each package is used as its README shows; nothing here speeds it up.
"""

import sys

SYSTEMS = {
    # axiom, productions (applied in parallel), turning angle in degrees
    "abop_1_24e": ("X", {"X": "F[+X][-X]FX", "F": "FF"}, 25.7),
    "koch_snowflake": ("F++F++F", {"F": "F-F++F-F"}, 60.0),
}


def derive(package, axiom, rules, steps):
    if package == "LindenmayerSystem":
        from LindenmayerSystem.LSystem import LSystem

        return LSystem(list(rules), ["+", "-", "[", "]"], axiom, rules, steps).system[-1]
    if package == "l_system_fractals":
        from l_system_fractals.constants import DRAW_FORWARD
        from l_system_fractals.l_system import LSystem

        # Its rules are applied one after the other (str.replace): correct
        # here because no successor of a later rule's symbol is rewritten by
        # an earlier one in these two systems (F before X).
        ordered = sorted(rules.items(), key=lambda kv: kv[0] != "F")
        return LSystem(steps, axiom, ordered, [(s, DRAW_FORWARD) for s in rules], [], 0, 1, 1, 90).string
    if package == "lsys":
        from lsys import Lsys

        return Lsys(axiom=axiom, rule=rules, depth=steps).string
    raise SystemExit(f"unknown package {package}")


def draw(axiom, rules, steps, angle, out):
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    from lsys import Lsys, viz

    # lsys turns right on `+`; ABOP turns left: swap them.
    system = Lsys(axiom=axiom, rule=rules, depth=steps, a0=90, da=angle, right="-", left="+", ignore="X")
    fig, ax = plt.subplots()
    ax.add_collection(viz.construct_line_collection(system.coords, color="k", lw=0.5))
    ax.autoscale()
    ax.set_aspect("equal")
    ax.axis("off")
    fig.savefig(out)


def main():
    package, name, steps, out = sys.argv[1], sys.argv[2], int(sys.argv[3]), sys.argv[4]
    axiom, rules, angle = SYSTEMS[name]
    if out.endswith(".png"):
        draw(axiom, rules, steps, angle, out)
    else:
        with open(out, "w") as f:
            f.write(derive(package, axiom, rules, steps))


main()
