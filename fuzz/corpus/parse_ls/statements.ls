# Globals, hooks and production bodies: every mistake at its position.
global iteration = 1        # Error: 2:8 derivation step
global g = 1
global g = 2                # Error: 4:8 declared twice
global r = rand()           # Error: 5:12 must be a constant
axiom: A(1)
production:
A(x) -> {
  y = x + 1
  g = 2                     # Error: 10:3 cannot change in a production
  if y > z: produce B(y)    # Error: 11:10 unknown name `z`
  produce B [               # Error: 12:13 never closes
}
A(x) -(1)-> {               # Error: 14:1 cannot have a weight
  produce A(x)
}
EndEach:
g = g + 1
h = 2                       # Error: 19:1 unknown global `h`
iteration = 3               # Error: 20:1 cannot be assigned
