# Error: 1:1 no axiom
production:
F -> FF
