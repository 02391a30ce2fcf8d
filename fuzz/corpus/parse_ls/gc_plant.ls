# A plant whose stems are generalized cylinders (L-Py's @Gc / @Ge): every
# branch is swept as one smooth tapering tube instead of a chain of frusta.
# The trunk's cylinder starts in the axiom; each lateral branch starts its
# own with `@Gc` and is closed by its `]`. Gravity bends the branches.
name: gc_plant
derivation: 8
view: 3d
width: 0.35
width_factor: 0.85
step: 1
tropism: 0, -1, 0
elasticity: 0.12
colors: #6b4423 #c62828
axiom: @Gc A
production:
A -> F /(137.5) [ &(45) @Gc !(0.6 * 0.35) B ] ! A
B -> F ^(8) ! B
interpretation:
A -> @Ge
B -> ;(1) @O(0.12)
