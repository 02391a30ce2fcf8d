# ABOP Fig. 1.24c: a bracketed plant, heading up. n = 4: 11116 modules, 4096 segments.
name: abop_1_24c
derivation: 4
angle: 22.5
axiom: F
production:
F -> FF-[-F+F+F]+[+F-F-F]
