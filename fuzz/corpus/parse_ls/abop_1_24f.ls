# ABOP Fig. 1.24f: a bracketed plant, heading up. n = 5: 6263 modules, 1488 segments.
name: abop_1_24f
derivation: 5
angle: 22.5
axiom: X
production:
X -> F-[[X]+X]+F[+FX]-X
F -> FF
