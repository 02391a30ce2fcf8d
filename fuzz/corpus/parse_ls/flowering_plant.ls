# A flowering plant (ABOP Fig. 1.26): internodes, leaves as polygons and
# five-wedge flowers on pedicels. Multi-letter modules are declared first.
name: flowering_plant
derivation: 5
angle: 18
view: 3d
width: 0.15
colors: #4f7a28 #3a7d23 #f2f2f2 #e8c547
module: plant internode flower leaf seg pedicel wedge
axiom: plant
production:
plant -> internode + [ plant + flower ] - - / / [ - - leaf ] internode [ + + leaf ] - [ plant flower ] + + plant flower
internode -> F seg [ / / & & leaf ] [ / / ^ ^ leaf ] F seg
seg -> seg F seg
leaf -> [ '(1) { + f - f f - f + | + f - f f - f } ]
flower -> [ & & & pedicel '(2) / wedge / / / / wedge / / / / wedge / / / / wedge / / / / wedge ]
pedicel -> F F
wedge -> [ '(3) ^ F ] [ '(2) { & & & & - f + f | - f + f } ]
