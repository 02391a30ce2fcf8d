# A row of trees (ABOP Fig. 1.39 after Mandelbrot): the parametric Koch
# construction with delays, so later segments start their own bumps
# later.
name: row_of_trees
derivation: 10
angle: 86
heading: +x
define c = 1
define p = 0.3
define q = c - p
define h = (p * q) ^ 0.5
axiom: F(1, 0)
production:
F(x, t) : t == 0 -> F(x*p, 2) + F(x*h, 1) - - F(x*h, 1) + F(x*q, 0)
F(x, t) : t > 0 -> F(x, t - 1)
