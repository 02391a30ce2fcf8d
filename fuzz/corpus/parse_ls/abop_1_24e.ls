# ABOP Fig. 1.24e: a bracketed plant, heading up. n = 7: 12863 modules, 4118 segments.
name: abop_1_24e
derivation: 7
angle: 25.7
axiom: X
production:
X -> F[+X][-X]FX
F -> FF
