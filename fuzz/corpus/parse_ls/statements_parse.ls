# Statement syntax: every mistake at its position (parse errors).
axiom: A
production:
A -> {
  if 1 > 0 produce B        # Error: 5:12 expected `:`
  B C                       # Error: 6:3 expected a statement
  else produce C            # Error: 7:3 expected `else: statement`
}
EndEach:
produce A                   # Error: 10:1 belongs in a production body
else: A = 0                 # Error: 11:1 follows no `if`
surface = "x.obj"           # Error: 12:1 expected `surface name
