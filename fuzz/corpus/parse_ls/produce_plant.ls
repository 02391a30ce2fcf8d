# One production per module, with L-Py's `produce` in its body: the apex
# computes its internode length once, emits it with `nproduce`, and then
# either flowers, forks, or grows on, by `if`/`elif`/`else`. Without bodies
# this takes three productions that repeat the length formula.
name: produce_plant
derivation: 8
angle: 28
colors: #3e5f1f #c62828
axiom: A(0)
production:
A(t) -> {
  len = 1.2 * 0.85 ^ t
  nproduce F(len)
  if t >= 6: produce K
  elif t % 2 == 0: produce [+A(t + 1)] [-A(t + 1)] A(t + 1)
  else: produce +(4) A(t + 1)
}
interpretation:
K -> [ '(1) { . +(72) f(0.2) +(72) f(0.2) +(72) f(0.2) +(72) f(0.2) } ]
