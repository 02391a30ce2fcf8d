# A 3D bush with leaves (ABOP Fig. 1.25). Branches are frusta whose width
# shrinks with `!`; leaves are polygons traced by `f` moves inside `{ }`.
name: bush_3d
derivation: 7
angle: 22.5
view: 3d
width: 0.6
width_factor: 0.7
colors: #6b4423 #6b4423 #5d5a2a #3f7f2a #4f8a2b #5e9a33 #6aa83a #78b545
axiom: A
production:
A -> [&FL!A]/////'[&FL!A]///////'[&FL!A]
F -> S/////F
S -> FL
L -> ['''^^{-f+f+f-|-f+f+f}]
