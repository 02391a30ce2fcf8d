# Context-sensitive signal propagation (ABOP Fig. 1.31a, Hogeweg and
# Hesper): states 0 and 1 pass along the branches; turns and segments are
# ignored when matching contexts. n = 30: 6910 modules, 2501 segments.
name: hogeweg
derivation: 30
angle: 22.5
ignore: + - F
axiom: F1F1F1
production:
0 < 0 > 0 -> 0
0 < 0 > 1 -> 1[+F1F1]
0 < 1 > 0 -> 1
0 < 1 > 1 -> 1
1 < 0 > 0 -> 0
1 < 0 > 1 -> 1F1
1 < 1 > 0 -> 0
1 < 1 > 1 -> 0
+ -> -
- -> +
