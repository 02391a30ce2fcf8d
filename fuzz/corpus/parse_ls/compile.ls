derivation: 2.5    # Error: 1:13 whole number of steps
view: 4d           # Error: 2:7 unknown view
heading: up        # Error: 3:10 unknown heading
colors: red        # Error: 4:9 is not a colour
growth: 2          # Error: 5:9 is a probability
define k = rand()  # Error: 6:12 must be a constant
axiom: A(1)
production:
A(x) : y > 1 -> B        # Error: 9:8 unknown name `y`
A(x) -> B(x, sqr(x))     # Error: 10:14 unknown function `sqr`
A(x, x) -> B             # Error: 11:6 named twice
A [ < B -> C             # Error: 12:1 brackets cannot be part of a context
decomposition:
A < B -> C               # Error: 14:1 context-free
