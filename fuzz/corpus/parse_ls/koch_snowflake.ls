# Koch snowflake (ABOP Fig. 1.7b): each edge of a triangle becomes four.
# n = 4: 1792 modules, 768 segments, bounding box x in [0, 81], y in
# [-23.383, 70.148].
name: koch_snowflake
derivation: 4
angle: 60
heading: +x
axiom: F++F++F
production:
F -> F-F++F-F
