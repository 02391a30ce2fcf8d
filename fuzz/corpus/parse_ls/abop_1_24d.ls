# ABOP Fig. 1.24d: a bracketed plant, heading up. n = 7: 13956 modules, 4118 segments.
name: abop_1_24d
derivation: 7
angle: 20
axiom: X
production:
X -> F[+X]F[-X]+X
F -> FF
