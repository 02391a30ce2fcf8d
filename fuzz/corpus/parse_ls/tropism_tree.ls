# A tree bent by gravity (ABOP Fig. 2.8a): three branches per apex with
# divergence angles 94.74° and 132.63°, segments elongating and widths
# growing every step, tropism towards -y with elasticity 0.22.
name: tropism_tree
derivation: 6
view: 3d
tropism: 0, -1, 0
elasticity: 0.22
colors: #6b4423
define d1 = 94.74
define d2 = 132.63
define a = 18.95
define lr = 1.109
define vr = 1.732
axiom: !(1) F(200) /(45) A
production:
A -> !(vr) F(50) [&(a) F(50) A] /(d1) [&(a) F(50) A] /(d2) [&(a) F(50) A]
F(l) -> F(l * lr)
!(w) -> !(w * vr)
