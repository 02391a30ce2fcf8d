# Bracketed right context (ABOP §1.8): `I > [L]` rewrites an internode
# whose lateral branch starts with a leaf L; branches that start otherwise
# are passed over, and `+ -` are ignored inside the branch too. Internodes
# under a leaf elongate by one F a step; those under a growing bud B do
# not. n = 8: 137 modules, 28 F, 16 branches.
name: branch_context
derivation: 8
angle: 30
heading: +y
ignore: + -
axiom: A
production:
A -> I[+L]I[-B]A
B -> IB
I > [L] -> FI
interpretation:
I -> F
L -> [+F]
