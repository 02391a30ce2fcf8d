# The parametric Koch construction (ABOP §1.10.1): each segment splits at
# ratio p into a bump. n = 5: 2388 modules, 1024 segments whose lengths sum
# to (1 + 2h)^5 = 25.8559959446.
name: koch_parametric
derivation: 5
angle: 86
heading: +x
define p = 0.3
define q = 1 - p
define h = sqrt(p * q)
axiom: F(1)
production:
F(x) -> F(x*p) + F(x*h) - - F(x*h) + F(x*q)
