# ABOP Fig. 1.24b: a bracketed plant, heading up. n = 5: 9373 modules, 3125 segments.
name: abop_1_24b
derivation: 5
angle: 20
axiom: F
production:
F -> F[+F]F[-F][F]
