# EndEach computes Fibonacci numbers in globals; the production records
# them. F(1..5) = 1 1 2 3 5 (the counts ABOP §1.2 gives for A -> B, B -> AB).
# Expect: X(0,1,1)X(1,1,2)X(2,2,3)X(3,3,5)X(4,5,8)A
# Expect-state: 5, 8, 13
derivation: 5
global a = 1
global b = 1
axiom: A
production:
A -> X(iteration, a, b) A
EndEach:
b = a + b
a = b - a
