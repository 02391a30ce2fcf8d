define p = 1
define p = 2             # Warning: 2:8 defined again
axiom: F
production:
F -> FF
G(x) -> G                # Warning: 6:1 never applies
