# ABOP Fig. 1.30 (p. 43), its four conditional productions written as two
# bodies with if/else. The figure's fifth string:
# Expect: CB(0)B(8)A(1.1428571428571428,0)
derivation: 5
axiom: B(2)A(4,4)
production:
A(x, y) -> {
  if y <= 3: produce A(x * 2, x + y)
  else: produce B(x) A(x / y, 0)
}
B(x) -> {
  if x < 1: produce C
  else: produce B(x - 1)
}
