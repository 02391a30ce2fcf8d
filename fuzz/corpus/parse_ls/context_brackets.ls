# Brackets in contexts: the right context is an axial tree whose branches
# must close; the left context is a path to the root (ABOP §1.8).
axiom: A[B]C
production:
A > [B -> X          # Error: 5:5 `[` in the right context is never closed
A > B]C -> Y         # Error: 6:6 `]` in the right context closes no branch
A > [B]]C -> Z       # Error: 7:8 closes no branch
B[ < A -> W          # Error: 8:2 cannot be part of a left context
A > [B][C]D -> V
