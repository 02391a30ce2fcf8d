# A stochastic plant (ABOP Fig. 1.27): each segment becomes one of three
# branchings, so every seed gives another plant. E[#F] = 3.66^n.
name: stochastic_plant
derivation: 5
angle: 25.7
axiom: F
production:
F -(0.33)-> F[+F]F[-F]F
F -(0.33)-> F[+F]F
F -(0.34)-> F[-F]F
