# Environmental sensitivity with a query module (cpfg/L-Py `?P`; the
# "synthetic topiary" of Prusinkiewicz, James & Měch 1994): after each step
# the turtle fills every ?P(x, y, z) with its position, so an apex can see
# where it is. Apices that left the disc of radius 6 around (0, 7) stop
# and flower; the others fork. The crown takes the disc's shape.
name: topiary
derivation: 12
angle: 24
colors: #5d4037 #c62828
define r = 6
define cy = 7
axiom: F(1.5) A ?P(0, 0, 0)
production:
A > ?P(x, y, z) : x * x + (y - cy) ^ 2 > r * r -> K
A -> F(0.9) [ +A ?P(0, 0, 0) ] -(12) A
interpretation:
K -> [ '(1) @O(0.15) ]
