# nproduce accumulates (and is the successor when no produce runs), a local
# variable carries a value between statements, a parameter can be
# reassigned, and a body that produces nothing leaves the module to the
# next production.
# Expect: F(3)[+F(2)]F(2)[+F(1)]D(1)
derivation: 2
axiom: A(3) C(1)
production:
A(x) : x > 1 -> {
  nproduce F(x)
  x = x - 1
  half = x / 2
  nproduce [+F(x)]
  if half >= 1: produce A(x)
  elif half > 100: produce Z
}
C(x) -> {
  if x > 5: produce Z
}
C(x) -> D(x)
