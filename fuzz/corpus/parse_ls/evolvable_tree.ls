# A stochastic, parametric 3D tree made to be steered by evolution
# (examples/scenes/lsystem_tree_volume.toml). Each apex A(l, w) grows a
# segment and forks into three or two apices, or stops; branching angles
# and divergence are random draws. Every apex left at the end (stopped,
# pruned, or at the last step) is drawn as a foliage ball. As a generator,
# every rewrite of A is a gene (its production choice and its draws), and
# `growth: 0.9` lets optimizers prune an apex or regrow it.
name: evolvable_tree
derivation: 7
view: 3d
growth: 0.9
tropism: 0, -1, 0
elasticity: 0.04
colors: #6b4423 #3f7f2a
define r = 0.8
define shrink = 0.68
# The target volume's trunk starts at y = -0.79: move there first.
axiom: f(-0.79) !(0.3) F(1.2) A(1, 0.22)
production:
A(l, w) -(0.45)-> !(w) F(l) [ &(uniform(25, 50)) A(l*r, w*shrink) ] /(uniform(100, 140)) [ &(uniform(25, 50)) A(l*r, w*shrink) ] /(uniform(100, 140)) [ &(uniform(25, 50)) A(l*r, w*shrink) ]
A(l, w) -(0.4)-> !(w) F(l) /(uniform(60, 180)) [ &(uniform(20, 45)) A(l*r, w*shrink) ] A(l*r, w*shrink)
A(l, w) -(0.15)-> !(w) F(l * uniform(0.4, 1)) S
interpretation:
A(l, w) -> '(1) @O(0.3 + l * 0.4)
S -> '(1) @O(uniform(0.35, 0.6))
