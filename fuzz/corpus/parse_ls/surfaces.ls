# Predefined surfaces: `~l` is built in; other names must be declared.
surface petal = "petal.obj"   # Error: 2:17 cannot load surface `petal`
axiom: A
production:
A -> F ~l(2) ~lf(1) A         # Error: 5:14 unknown surface `lf`
A -> ~leaf ~lf                # Error: 6:6 unknown surface `leaf`
