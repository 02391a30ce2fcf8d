# ABOP Fig. 1.24a: a bracketed plant, heading up. n = 5: 7811 modules, 3125 segments.
name: abop_1_24a
derivation: 5
angle: 25.7
axiom: F
production:
F -> F[+F]F[-F]F
