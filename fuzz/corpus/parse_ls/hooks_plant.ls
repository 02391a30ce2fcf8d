# Global variables and L-Py's hooks: the internode length is a global that
# the EndEach hook shrinks after every step, so the segments each step adds
# are shorter than the last (L-Py: `def EndEach(): global len; len *= 0.6`).
# `iteration` (L-Py's getIterationNb()) picks each step's colour.
name: hooks_plant
derivation: 6
angle: 22.5
colors: #6b4423 #4e7d2a #2e7d32 #66bb6a
global len = 10
axiom: X
production:
X -> '(min(iteration, 3)) F(len) [+X] [-X] F(len) X
Start:
len = 10
EndEach:
len = len * 0.6
