# Leaves from genform's built-in predefined surface `~l` (cpfg/L-Py `~`): a
# bicubic Bézier-patch leaf placed at the turtle, its blade along the
# heading, its face towards the up vector, scaled by the parameter. The
# apex A leaves one leaf and one side shoot B per step; every B step adds a
# pair of leaves.
name: leafy_plant
derivation: 6
view: 3d
angle: 30
width: 0.1
colors: #6b4423 #3a7d23
axiom: A
production:
A -> F [ &(50) ;(1) ~l(1.4) ] /(137.5) [ &(40) !(0.06) B ] /(137.5) A
B -> F(0.7) [ +(60) &(20) ;(1) ~l(0.9) ] [ -(60) &(20) ;(1) ~l(0.9) ] B
