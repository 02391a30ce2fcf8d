angel: 60          # Error: 1:1 unknown setting `angel`
axiom: F(1         # Error: 2:9 never closed
production:
F => FF            # Error: 4:1 expected a production
A(x+1) -> B        # Error: 5:3 a predecessor's parameters are names
A B -> C           # Error: 6:1 the strict predecessor must be one module
A -> B(x +)        # Error: 7:11 expected an expression
maxdepth: 3        # Error: 8:1 `maxdepth:` belongs in
define = 2         # Error: 9:1 expected a name after `define`
