# Quadratic Koch island (ABOP Fig. 1.7a). n = 3: 3803 modules, 2048
# segments, bounding box [-21, 85] x [-85, 21].
name: quadratic_koch_island
derivation: 3
angle: 90
heading: +x
axiom: F-F-F-F
production:
F -> F-F+F+FF-F-F+F
